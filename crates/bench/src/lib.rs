//! The benchmark cases of bezsolid, shared by the native runner (`src/main.rs`) and the wasm build
//! that `cargo xtask bench` runs in node. Each case is timed by the caller's clock, repeated until it
//! has run for a while, and reported as the median of its runs.

pub mod esc;
pub mod hyperfun;
pub mod inverse;
pub mod plasm;
pub mod tree;

use bezsolid_core::mesh::{LinearRoots, Mesh, SampleGrid, polygonize};
use bezsolid_core::{Axis, Solid3, Volume};
use glam::DVec3;
use serde::Serialize;

/// One measured case.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// What was measured, e.g. `grid evaluation`.
    pub case: String,
    /// Who did it: `bezsolid` or a peer's name.
    pub who: String,
    /// The resolution (samples or cells per axis).
    pub n: usize,
    /// The median time of one run in milliseconds.
    pub ms: f64,
    /// Runs timed.
    pub runs: usize,
    /// A case-specific figure: points per second for evaluation, triangles for meshing.
    pub extra: f64,
    /// Anything else worth a line (iteration histograms).
    pub note: String,
}

/// A clock in milliseconds (monotonic; its zero does not matter).
pub trait Clock {
    /// Now, in milliseconds.
    fn now_ms(&mut self) -> f64;
}

/// Times `f`: at least 3 runs and until `budget_ms` has passed (at most 50 runs); the median.
pub fn time<T>(clock: &mut dyn Clock, budget_ms: f64, mut f: impl FnMut() -> T) -> (f64, usize, T) {
    let mut times = Vec::new();
    let start = clock.now_ms();
    let mut last;
    loop {
        let t0 = clock.now_ms();
        last = f();
        times.push(clock.now_ms() - t0);
        if times.len() >= 50 || (times.len() >= 3 && clock.now_ms() - start > budget_ms) {
            break;
        }
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], times.len(), last)
}

/// The benchmark's solid: a degree-(4, 4, 4) volume over `[0, 1]³` whose `S_ξ` is a ball (the degree-2
/// ball, elevated) with ripples added to its control values, so no axis or term is special.
#[must_use]
pub fn bench_solid() -> Solid3 {
    let c = [0.25, -0.25, 0.25];
    let ball = Solid3::regular([2, 2, 2], DVec3::ZERO, DVec3::ONE, |[i, j, k]| {
        0.16 - c[i] - c[j] - c[k]
    })
    .unwrap_or_else(|_| unreachable!("a valid net"));
    let mut xi = ball.xi_net();
    for axis in [Axis::U, Axis::V, Axis::W] {
        for _ in 0..2 {
            xi = xi
                .elevate(axis)
                .unwrap_or_else(|_| unreachable!("degree 4 is allowed"));
        }
    }
    let [n, m, l] = xi.degree();
    let pts = xi.points().to_vec();
    let rippled = Volume::from_fn([n, m, l], |[i, j, k]| {
        let s = pts[(i * (m + 1) + j) * (l + 1) + k];
        let ripple = 0.03 * (((i * 7 + j * 3 + k * 5) % 5) as f64 - 2.0) / 2.0;
        DVec3::new(
            i as f64 / n as f64,
            j as f64 / m as f64,
            k as f64 / l as f64,
        )
        .extend(s + ripple)
    })
    .unwrap_or_else(|_| unreachable!("a valid net"));
    Solid3::try_from_net(rippled).unwrap_or_else(|_| unreachable!("a regular grid"))
}

/// `n` sample coordinates spread over `[0, 1]`.
#[must_use]
pub fn samples(n: usize) -> Vec<f64> {
    (0..n).map(|a| a as f64 / (n - 1) as f64).collect()
}

/// The sampled field of [`bench_solid`] at `n³` samples over the box, as the meshers take it.
#[must_use]
pub fn sampled(n: usize) -> (SampleGrid, Vec<f64>) {
    let solid = bench_solid();
    let grid = solid
        .mesh_grid(n - 2)
        .unwrap_or_else(|_| unreachable!("n is small"));
    let axis = |k: usize| -> Vec<f64> {
        (0..grid.dims[k])
            .map(|a| grid.origin[k] + grid.step[k] * a as f64)
            .collect()
    };
    let values = solid.f_grid([&axis(0), &axis(1), &axis(2)]);
    (grid, values)
}

/// Our cases: grid evaluation of the scalar volume and of the clipped `f`, polygonization end to end,
/// and the meshing step alone on a sampled array.
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let mut rows = eval_suite(clock, quick);
    rows.extend(inverse::suite(clock, quick));
    rows.extend(esc::suite(clock, quick));
    rows.extend(plasm::suite(clock, quick));
    rows.extend(hyperfun::suite(clock, quick));
    rows.extend(tree::suite(clock, quick));
    rows.extend(mesh_suite(clock, quick));
    rows
}

/// Grid evaluation of the scalar volume and of the clipped `f`.
pub fn eval_suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let solid = bench_solid();
    let xi = solid.xi_net();
    let mut rows = Vec::new();
    let eval_sizes: &[usize] = if quick { &[32] } else { &[64, 128, 256] };
    for &n in eval_sizes {
        let t = samples(n);
        let (ms, runs, out) = time(clock, budget, || xi.eval_grid([&t, &t, &t]));
        let points = (n * n * n) as f64;
        rows.push(Row {
            case: "grid evaluation S_xi, degree (4,4,4)".into(),
            who: "bezsolid".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: String::new(),
        });
        assert_eq!(out.len(), n * n * n);
        let (ms, runs, _) = time(clock, budget, || solid.f_grid([&t, &t, &t]));
        rows.push(Row {
            case: "grid evaluation f = S_xi & F_s".into(),
            who: "bezsolid".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: String::new(),
        });
    }
    rows
}

/// Polygonizing the benchmark's solid: the adaptive mesher (what `Solid3::polygonize` does) at
/// each size up to 512, the uniform grid it is checked against (the plain path, every sample
/// evaluated and every cube marched), and the meshing step alone on a sampled array.
pub fn mesh_suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let solid = bench_solid();
    let mut rows = Vec::new();
    let mesh_sizes: &[usize] = if quick {
        &[20, 128]
    } else {
        &[20, 64, 128, 256, 512]
    };
    for &n in mesh_sizes {
        let (ms, runs, (mesh, stats)) = time(clock, budget, || {
            solid
                .polygonize_with_stats(n, 1e-9)
                .ok()
                .flatten()
                .unwrap_or_else(|| unreachable!("valid arguments, no space mapping"))
        });
        rows.push(Row {
            case: "polygonize".into(),
            who: ADAPTIVE.into(),
            n,
            ms,
            runs,
            extra: mesh.triangle_count() as f64,
            note: format!(
                "{:.1} % of {} cells skipped by the Bernstein bounds; {} blocks, {} samples evaluated",
                100.0 * stats.skipped as f64 / stats.cells.max(1) as f64,
                stats.cells,
                stats.blocks,
                stats.evaluated
            ),
        });
        if n > 256 {
            continue;
        }
        let (ms, runs, mesh) = time(clock, budget, || {
            solid
                .polygonize_uniform(n, 1e-9)
                .unwrap_or_else(|_| unreachable!("valid arguments"))
        });
        rows.push(Row {
            case: "polygonize".into(),
            who: UNIFORM.into(),
            n,
            ms,
            runs,
            extra: mesh.triangle_count() as f64,
            note: String::new(),
        });
        let (grid, values) = sampled(n + 2);
        let (ms, runs, mesh) = time(clock, budget, || -> Mesh {
            polygonize(&grid, &values, &mut LinearRoots)
        });
        rows.push(Row {
            case: "meshing step alone (sampled array)".into(),
            who: "bezsolid".into(),
            n,
            ms,
            runs,
            extra: mesh.triangle_count() as f64,
            note: String::new(),
        });
    }
    rows
}

/// Who the adaptive mesher's rows are by.
pub const ADAPTIVE: &str =
    "bezsolid (adaptive: Bernstein bounds; vertices on f = 0 within 1e-9; normals from ∇f)";
/// Who the uniform grid's rows are by.
pub const UNIFORM: &str = "bezsolid (uniform grid, the plain path)";

/// The wasm entry point `cargo xtask bench` calls from node.
#[cfg(target_arch = "wasm32")]
pub mod wasm {
    use super::{Clock, suite};
    use wasm_bindgen::prelude::*;

    struct Performance(js_sys::Function, JsValue);

    impl super::Clock for Performance {
        fn now_ms(&mut self) -> f64 {
            self.0
                .call0(&self.1)
                .ok()
                .and_then(|v| v.as_f64())
                .unwrap_or(0.0)
        }
    }

    /// Runs the suite with `performance.now()` and returns its rows as JSON.
    #[wasm_bindgen]
    pub fn run(quick: bool) -> String {
        with_clock(|clock| suite(clock, quick))
    }

    /// Share `index` of `count` of the benchmark solid's drawn surface at `n` cells, as a page's
    /// worker makes it (the mesh of its blocks, then six `f32` a vertex, three vertices a
    /// triangle); its triangles. `crates/bench/workers.js` times it on worker threads.
    #[wasm_bindgen]
    #[must_use]
    pub fn surface_share(n: usize, index: usize, count: usize) -> usize {
        let Some(share) = bezsolid_core::mesh::Share::new(index, count) else {
            return 0;
        };
        let Ok(piece) = super::bench_solid().polygonize_share(n, 1e-9, share) else {
            return 0;
        };
        let mesh = &piece.mesh;
        let mut floats: Vec<f32> = Vec::with_capacity(mesh.triangles.len() * 18);
        for t in &mesh.triangles {
            for &i in t {
                floats.extend(mesh.positions[i as usize].as_vec3().to_array());
                floats.extend(mesh.normals[i as usize].as_vec3().to_array());
            }
        }
        floats.len() / 18
    }

    /// Only grid evaluation (`cargo xtask bench` runs it in a module built without SIMD too).
    #[wasm_bindgen]
    pub fn run_eval(quick: bool) -> String {
        with_clock(|clock| super::eval_suite(clock, quick))
    }

    /// Only grid evaluation and meshing (for working on them).
    #[wasm_bindgen]
    pub fn run_mesh(quick: bool) -> String {
        with_clock(|clock| {
            let mut rows = super::eval_suite(clock, quick);
            rows.extend(super::mesh_suite(clock, quick));
            rows
        })
    }

    fn with_clock(f: impl FnOnce(&mut dyn Clock) -> Vec<super::Row>) -> String {
        let perf =
            js_sys::Reflect::get(&js_sys::global(), &"performance".into()).unwrap_or(JsValue::NULL);
        let now = js_sys::Reflect::get(&perf, &"now".into())
            .ok()
            .and_then(|f| f.dyn_into::<js_sys::Function>().ok());
        let Some(now) = now else {
            return "[]".into();
        };
        let mut clock: Box<dyn Clock> = Box::new(Performance(now, perf));
        serde_json::to_string(&f(clock.as_mut())).unwrap_or_default()
    }
}
