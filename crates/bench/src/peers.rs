//! The peers, run in the same process on the same data: fast-surface-nets meshing the very array our
//! meshing step takes (its meshing step alone), and fidget meshing the same polynomial, written as a
//! fidget expression, at the same resolution (its whole pipeline: it evaluates as it meshes).

use bezsolid_bench::{Clock, Row, bench_solid, sampled, time};
use bezsolid_core::model::SolidSpec;
use fast_surface_nets::ndshape::RuntimeShape;
use fast_surface_nets::{SurfaceNetsBuffer, surface_nets};
use fidget::context::Tree;
use fidget::mesh::{Octree, Settings};

pub(crate) fn run(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let sizes: &[usize] = if quick { &[20] } else { &[20, 64, 128, 256] };
    let mut rows = Vec::new();
    for &n in sizes {
        // The same samples as our meshing step; fast-surface-nets wants inside negative, in f32.
        let (grid, values) = sampled(n + 2);
        let sdf: Vec<f32> = values.iter().map(|&v| -v as f32).collect();
        let dims = grid.dims.map(|d| d as u32);
        let shape = RuntimeShape::<u32, 3>::new(dims);
        let mut buffer = SurfaceNetsBuffer::default();
        let (ms, runs, ()) = time(clock, budget, || {
            surface_nets(&sdf, &shape, [0; 3], dims.map(|d| d - 1), &mut buffer);
        });
        rows.push(Row {
            case: "meshing step alone (sampled array)".into(),
            who: "fast-surface-nets 0.2.1".into(),
            n,
            ms,
            runs,
            extra: (buffer.indices.len() / 3) as f64,
            note: String::new(),
        });
    }
    rows.extend(polygonize_peer(clock, quick));
    rows.extend(tree_peer(clock, quick));
    rows
}

/// fidget meshing the benchmark's polynomial over its box at 2^depth cells per axis (64, 128 and
/// 256: only powers of two compare; 256 takes seconds).
pub(crate) fn polygonize_peer(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let to_unit_cube = nalgebra::Matrix4::new_translation(&nalgebra::Vector3::repeat(0.5f32))
        * nalgebra::Matrix4::new_scaling(0.5f32);
    let depths: &[u8] = if quick { &[7] } else { &[6, 7, 8] };
    fidget_rows(
        clock,
        budget,
        "polygonize",
        -bernstein_tree(),
        to_unit_cube,
        depths,
    )
}

/// fidget meshing the benchmark's tree of 20 solids ([`bezsolid_bench::tree`]), built from the
/// same formulas (DESIGN §5), at 2^depth cells along the longest side of the tree's bounds.
pub(crate) fn tree_peer(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let file = bezsolid_bench::tree::bench_tree();
    let Some((lo, hi)) = bezsolid_bench::tree::tree().bounds() else {
        return Vec::new();
    };
    let centre = nalgebra::Vector3::from_fn(|i, _| ((lo[i] + hi[i]) / 2.0) as f32);
    let half = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max) as f32 / 2.0;
    let to_model =
        nalgebra::Matrix4::new_translation(&centre) * nalgebra::Matrix4::new_scaling(half);
    let depths: &[u8] = if quick { &[6] } else { &[7, 8] };
    fidget_rows(
        clock,
        budget,
        "tree of 20 solids: polygonize",
        -fidget_tree(&file.solid),
        to_model,
        depths,
    )
}

/// fidget meshing `tree` (inside where it is negative) at each of `depths` (2^depth cells along
/// the side of the cube `to_model` maps fidget's `[-1, 1]³` onto), JIT, one thread.
fn fidget_rows(
    clock: &mut dyn Clock,
    budget: f64,
    case: &str,
    tree: Tree,
    to_model: nalgebra::Matrix4<f32>,
    depths: &[u8],
) -> Vec<Row> {
    let shape: fidget::jit::JitShape = fidget::shape::Shape::from(tree);
    let Ok(bound) = shape.try_into() else {
        eprintln!("bezsolid-bench: fidget refused the shape of {case:?}");
        return Vec::new();
    };
    let mut rows = Vec::new();
    for &depth in depths {
        let settings = Settings {
            depth,
            world_to_model: to_model,
            threads: None,
            ..Default::default()
        };
        let (ms, runs, triangles) = time(clock, budget, || {
            Octree::build(&bound, &settings)
                .map(|o| o.walk_dual().triangles.len())
                .unwrap_or(0)
        });
        rows.push(Row {
            case: case.into(),
            who: "fidget 0.5.1 (JIT, 1 thread; adaptive dual contouring)".into(),
            n: 1 << depth,
            ms,
            runs,
            extra: triangles as f64,
            note: String::new(),
        });
    }
    rows
}

/// A node of the tree as a fidget expression, from DESIGN §5's formulas (the kinds the benchmark's
/// tree has: unions, blended unions, regular volumes, spheres, boxes, tori).
fn fidget_tree(spec: &SolidSpec) -> Tree {
    let c = |v: f64| Tree::constant(v as f32);
    let and = |a: Tree, b: Tree| a.clone() + b.clone() - (a.square() + b.square()).sqrt();
    let or = |a: Tree, b: Tree| a.clone() + b.clone() + (a.square() + b.square()).sqrt();
    let xyz = [Tree::x(), Tree::y(), Tree::z()];
    match spec {
        SolidSpec::Union { of } => of
            .iter()
            .map(fidget_tree)
            .reduce(or)
            .unwrap_or_else(|| c(-1.0)),
        SolidSpec::BlendUnion { of, a0, a1, a2 } => {
            let (f1, f2) = (fidget_tree(&of[0]), fidget_tree(&of[1]));
            let den = c(1.0) + (f1.clone() / c(*a1)).square() + (f2.clone() / c(*a2)).square();
            or(f1, f2) + c(*a0) / den
        }
        SolidSpec::Sphere { center, radius } => {
            let d = (0..3)
                .map(|i| (xyz[i].clone() - c(center[i])).square())
                .reduce(|a, b| a + b)
                .unwrap_or_else(|| c(0.0));
            c(radius * radius) - d
        }
        SolidSpec::Box { min, max } => (0..3)
            .map(|i| (xyz[i].clone() - c(min[i])) * (c(max[i]) - xyz[i].clone()))
            .reduce(and)
            .unwrap_or_else(|| c(-1.0)),
        SolidSpec::Torus {
            center,
            axis,
            major,
            minor,
        } => {
            let k = axis.index();
            let across = (0..3)
                .filter(|&i| i != k)
                .map(|i| (xyz[i].clone() - c(center[i])).square())
                .reduce(|a, b| a + b)
                .unwrap_or_else(|| c(0.0));
            c(minor * minor)
                - (across.sqrt() - c(*major)).square()
                - (xyz[k].clone() - c(center[k])).square()
        }
        SolidSpec::Volume { degree, points } => {
            let [n, m, l] = *degree;
            let lo: [f64; 3] =
                core::array::from_fn(|i| points.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min));
            let hi: [f64; 3] = core::array::from_fn(|i| {
                points
                    .iter()
                    .map(|p| p[i])
                    .fold(f64::NEG_INFINITY, f64::max)
            });
            let t: Vec<Tree> = (0..3)
                .map(|i| (xyz[i].clone() - c(lo[i])) / c(hi[i] - lo[i]))
                .collect();
            let basis = |axis: &Tree, degree: usize| -> Vec<Tree> {
                let rest = c(1.0) - axis.clone();
                (0..=degree)
                    .map(|i| {
                        c(bezsolid_core::bernstein::binomial(degree, i))
                            * (axis.clone().pow(i as i64) * rest.clone().pow((degree - i) as i64))
                    })
                    .collect()
            };
            let (bu, bv, bw) = (basis(&t[0], n), basis(&t[1], m), basis(&t[2], l));
            let sum = |terms: Vec<Tree>| {
                terms
                    .into_iter()
                    .reduce(|a, b| a + b)
                    .unwrap_or_else(|| c(0.0))
            };
            let mut outer = Vec::new();
            for (i, bu_i) in bu.iter().enumerate() {
                let mut middle = Vec::new();
                for (j, bv_j) in bv.iter().enumerate() {
                    let inner: Vec<Tree> = bw
                        .iter()
                        .enumerate()
                        .map(|(k, bw_k)| {
                            c(points[(i * (m + 1) + j) * (l + 1) + k][3]) * bw_k.clone()
                        })
                        .collect();
                    middle.push(bv_j.clone() * sum(inner));
                }
                outer.push(bu_i.clone() * sum(middle));
            }
            let strips = t
                .iter()
                .map(|ti| ti.clone() * (c(1.0) - ti.clone()))
                .reduce(and)
                .unwrap_or_else(|| c(1.0));
            and(sum(outer), strips)
        }
        _ => c(-1.0),
    }
}

/// `S_ξ` of the benchmark solid as a fidget tree: `Σ_i Bu_i (Σ_j Bv_j (Σ_k c_ijk Bw_k))` over
/// `[0, 1]³` (the solid's box), each basis polynomial built once per axis. The clipping is left out:
/// inside the box it does not move the zero set, and fidget only meshes the box.
fn bernstein_tree() -> Tree {
    let xi = bench_solid().xi_net();
    let [n, m, l] = xi.degree();
    let basis = |axis: Tree, degree: usize| -> Vec<Tree> {
        let rest = 1.0f32 - axis.clone();
        (0..=degree)
            .map(|i| {
                let c = bezsolid_core::bernstein::binomial(degree, i) as f32;
                c * (axis.clone().pow(i as i64) * rest.clone().pow((degree - i) as i64))
            })
            .collect()
    };
    let (bu, bv, bw) = (
        basis(Tree::x(), n),
        basis(Tree::y(), m),
        basis(Tree::z(), l),
    );
    let sum = |terms: Vec<Tree>| {
        terms
            .into_iter()
            .reduce(|a, b| a + b)
            .unwrap_or_else(|| Tree::constant(0.0))
    };
    let pts = xi.points();
    let mut outer = Vec::new();
    for (i, bu_i) in bu.iter().enumerate() {
        let mut middle = Vec::new();
        for (j, bv_j) in bv.iter().enumerate() {
            let inner: Vec<Tree> = bw
                .iter()
                .enumerate()
                .map(|(k, bw_k)| pts[(i * (m + 1) + j) * (l + 1) + k] as f32 * bw_k.clone())
                .collect();
            middle.push(bv_j.clone() * sum(inner));
        }
        outer.push(bu_i.clone() * sum(middle));
    }
    sum(outer)
}
