//! The space-mapping cases: random points through the inverse map by each method, a warped 16 ×
//! 16-point patch contoured, and a warped volume polygonized; and nets that fold over themselves
//! everywhere (their control points shuffled), through the atlas.

use bezsolid_core::contour::{forward_contour, sampled_contour};
use bezsolid_core::inverse::{InverseMap, Method, QueryStats};
use bezsolid_core::{INVERSE_ACCURACY, Patch, Solid2, Solid3, Volume};
use glam::{DVec3, DVec4};

use crate::{Clock, Row, bench_solid, time};

/// A smooth warp of the unit square (or cube) that keeps the map injective: every point moves by at
/// most `a` along each axis, with derivatives well below 1.
fn warp(p: DVec3, a: f64) -> DVec3 {
    use std::f64::consts::PI;
    DVec3::new(
        p.x + a * (PI * p.x).sin() * (2.0 * PI * p.y).sin(),
        p.y + a * (PI * p.y).sin() * (2.0 * PI * (p.x + p.z)).cos(),
        p.z + a * (PI * p.z).sin() * (2.0 * PI * p.x).sin(),
    )
}

/// A patch with `points` control points per axis over the warped unit square; ξ a blob.
#[must_use]
pub fn warped_patch(points: usize) -> Solid2 {
    let d = points - 1;
    let patch = Patch::from_fn([d, d], |[i, j]| {
        let (x, y) = (i as f64 / d as f64, j as f64 / d as f64);
        let w = warp(DVec3::new(x, y, 0.0), 0.06);
        let xi = 0.12 - (x - 0.5).powi(2) - (y - 0.45).powi(2) + 0.05 * (7.0 * x).sin();
        DVec3::new(w.x, w.y, xi)
    })
    .unwrap_or_else(|_| unreachable!("a valid degree"));
    Solid2::try_from_net(patch).unwrap_or_else(|_| unreachable!("finite values"))
}

/// The benchmark volume ([`bench_solid`]) with its control points warped in space.
#[must_use]
pub fn warped_volume() -> Solid3 {
    let base = bench_solid();
    let v = base.net();
    let [n, m, l] = v.degree();
    let volume = Volume::from_fn([n, m, l], |[i, j, k]| {
        let p = v[[i, j, k]];
        let w = warp(p.truncate(), 0.05);
        DVec4::new(w.x, w.y, w.z, p.w)
    })
    .unwrap_or_else(|_| unreachable!("a valid degree"));
    Solid3::try_from_net(volume).unwrap_or_else(|_| unreachable!("finite values"))
}

/// xorshift64*: the same points natively and in wasm.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Work per query: clipping passes, Newton steps, fallbacks.
#[derive(Default)]
struct Histogram {
    passes: [u64; 6],
    total_passes: u64,
    newton: u64,
    fallbacks: u64,
    exhausted: u64,
    queries: u64,
    preimages: u64,
}

impl Histogram {
    fn add(&mut self, s: &QueryStats, preimages: usize) {
        let bucket = match s.clip.passes {
            0 => 0,
            1..=2 => 1,
            3..=4 => 2,
            5..=8 => 3,
            9..=32 => 4,
            _ => 5,
        };
        self.passes[bucket] += 1;
        self.total_passes += u64::from(s.clip.passes);
        self.newton += u64::from(s.newton_steps);
        self.fallbacks += u64::from(s.fallback);
        self.exhausted += u64::from(s.exhausted);
        self.queries += 1;
        self.preimages += preimages as u64;
    }

    fn note(&self) -> String {
        let q = self.queries.max(1) as f64;
        let pct = |c: u64| 100.0 * c as f64 / q;
        format!(
            "clipping passes per query: mean {:.2}; 0: {:.1}%, 1–2: {:.1}%, 3–4: {:.1}%, 5–8: {:.1}%, \
             9–32: {:.1}%, >32: {:.1}%; Newton steps per query {:.2}; fallbacks {:.2}%; out of \
             their work budget {:.2}%; preimages per query {:.3}",
            self.total_passes as f64 / q,
            pct(self.passes[0]),
            pct(self.passes[1]),
            pct(self.passes[2]),
            pct(self.passes[3]),
            pct(self.passes[4]),
            pct(self.passes[5]),
            self.newton as f64 / q,
            pct(self.fallbacks),
            pct(self.exhausted),
            self.preimages as f64 / q,
        )
    }
}

/// Each of `methods` over the same random points of the image (`p = S(u)`, `u` uniform): one
/// timed pass.
fn points_case<const D: usize, F: bezsolid_core::inverse::Forward<D>>(
    clock: &mut dyn Clock,
    case: &str,
    (net, map): (&F, &InverseMap<D>),
    count: usize,
    methods: &[Method],
) -> Vec<Row> {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let points: Vec<[f64; D]> = (0..count)
        .map(|_| net.forward(core::array::from_fn(|_| rng.unit())).x)
        .collect();
    let names = [
        (
            Method::Clipping,
            "bezsolid: Bézier clipping over the whole domain",
        ),
        (
            Method::Hybrid,
            "bezsolid: the paper's hybrid (spline guess, clipping in a box, then whole domain)",
        ),
        (
            Method::Fast,
            "bezsolid: fast path (seed table + Newton, verified; hybrid fallback)",
        ),
    ];
    let mut rows = Vec::new();
    for (method, who) in names.into_iter().filter(|(m, _)| methods.contains(m)) {
        let mut hist = Histogram::default();
        let t0 = clock.now_ms();
        let mut checksum = 0.0;
        for p in &points {
            let mut stats = QueryStats::default();
            let v = map.f(net, *p, method, INVERSE_ACCURACY, &mut stats);
            checksum += v.f;
            hist.add(&stats, v.preimages);
        }
        let ms = clock.now_ms() - t0;
        assert!(checksum.is_finite());
        rows.push(Row {
            case: case.into(),
            who: who.into(),
            n: count,
            ms,
            runs: 1,
            extra: count as f64 / (ms / 1000.0),
            note: hist.note(),
        });
    }
    rows
}

/// The regular grid over the unit box with the positions of its control points shuffled among them
/// (and ξ random): a net that folds over itself everywhere, the worst a user can drag into being.
#[must_use]
pub fn shuffled_patch(degree: [usize; 2], seed: u64) -> Solid2 {
    let [n, m] = degree;
    let mut rng = Rng(seed);
    let mut spots: Vec<(f64, f64)> = (0..=n)
        .flat_map(|i| (0..=m).map(move |j| (i as f64 / n as f64, j as f64 / m as f64)))
        .collect();
    for k in (1..spots.len()).rev() {
        spots.swap(k, ((rng.unit() * (k + 1) as f64) as usize).min(k));
    }
    let patch = Patch::from_fn(degree, |[i, j]| {
        let (x, y) = spots[i * (m + 1) + j];
        DVec3::new(x, y, rng.unit() * 2.0 - 1.0)
    })
    .unwrap_or_else(|_| unreachable!("a valid degree"));
    Solid2::try_from_net(patch).unwrap_or_else(|_| unreachable!("finite values"))
}

/// [`shuffled_patch`] for volumes.
#[must_use]
pub fn shuffled_volume(degree: [usize; 3], seed: u64) -> Solid3 {
    let [n, m, l] = degree;
    let mut rng = Rng(seed);
    let mut spots: Vec<[f64; 3]> = Vec::new();
    for i in 0..=n {
        for j in 0..=m {
            for k in 0..=l {
                spots.push([
                    i as f64 / n as f64,
                    j as f64 / m as f64,
                    k as f64 / l as f64,
                ]);
            }
        }
    }
    for k in (1..spots.len()).rev() {
        spots.swap(k, ((rng.unit() * (k + 1) as f64) as usize).min(k));
    }
    let volume = Volume::from_fn(degree, |[i, j, k]| {
        let [x, y, z] = spots[(i * (m + 1) + j) * (l + 1) + k];
        DVec4::new(x, y, z, rng.unit() * 2.0 - 1.0)
    })
    .unwrap_or_else(|_| unreachable!("a valid degree"));
    Solid3::try_from_net(volume).unwrap_or_else(|_| unreachable!("finite values"))
}

/// Nets that fold over themselves everywhere: points through the atlas against whole-domain
/// clipping, a contour and a mesh, each within its budget.
fn folded(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let mut rows = Vec::new();
    let patch = shuffled_patch([6, 6], 0x2545_F491_4F6C_DD1D);
    let map = patch
        .inverse()
        .unwrap_or_else(|| unreachable!("a shuffled net"));
    let count = if quick { 300 } else { 5_000 };
    map.plan(count);
    let case = "inverse map: random points of a patch that folds over itself (shuffled 6×6 net)";
    rows.extend(points_case(
        clock,
        case,
        (patch.net(), map),
        count,
        &[Method::Clipping, Method::Fast],
    ));
    // The worst net there is: degree 16 on every axis, 4,913 points shuffled. Whole-domain
    // clipping takes seconds a point there.
    let volume = shuffled_volume([16, 16, 16], 0xBF58_476D_1CE4_E5B9);
    let map = volume
        .inverse()
        .unwrap_or_else(|| unreachable!("a shuffled net"));
    let count = if quick { 500 } else { 20_000 };
    map.plan(count);
    rows.extend(points_case(
        clock,
        "inverse map: random points of a volume that folds over itself (shuffled degree-16 net)",
        (volume.net(), map),
        count,
        &[Method::Fast],
    ));
    for r in rows.iter_mut().filter(|r| r.who.contains("fast path")) {
        r.who = "bezsolid: the atlas (pieces certified or clipped, Newton on the net)".into();
    }
    let res = if quick { 64 } else { 256 };
    for (degree, seed) in [(6, 0x9E37_79B9_7F4A_7C15u64), (16, 0xD1B5_4A32_D192_ED03)] {
        let (ms, runs, lines) = time(clock, budget, || {
            // A fresh net each run: the atlas is part of the cost.
            sampled_contour(&shuffled_patch([degree, degree], seed), res, 1e-9)
        });
        rows.push(Row {
            case: "contour of a patch that folds over itself (shuffled net)".into(),
            who: format!("bezsolid: the atlas at every sample, {degree}×{degree} degree"),
            n: res,
            ms,
            runs,
            extra: lines.iter().map(|l| l.points.len()).sum::<usize>() as f64,
            note: String::new(),
        });
    }
    let res = if quick { 16 } else { 64 };
    let (ms, runs, mesh) = time(clock, budget, || {
        shuffled_volume([6, 6, 1], 0x94D0_49BB_1331_11EB)
            .polygonize(res, 1e-9)
            .unwrap_or_else(|_| unreachable!("valid arguments"))
    });
    rows.push(Row {
        case: "polygonize a volume that folds over itself (shuffled (6,6,1) net)".into(),
        who: "bezsolid: the atlas at every sample".into(),
        n: res,
        ms,
        runs,
        extra: mesh.triangle_count() as f64,
        note: String::new(),
    });
    rows
}

/// The space-mapping cases.
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let mut rows = Vec::new();
    let patch = warped_patch(4);
    let map = patch
        .inverse()
        .unwrap_or_else(|| unreachable!("a warped net"));
    let count = if quick { 5_000 } else { 1_000_000 };
    rows.extend(points_case(
        clock,
        "inverse map: random points in a warped bicubic patch",
        (patch.net(), map),
        count,
        &Method::ALL,
    ));
    let volume = warped_volume();
    let map = volume
        .inverse()
        .unwrap_or_else(|| unreachable!("a warped net"));
    let count = if quick { 1_000 } else { 1_000_000 };
    rows.extend(points_case(
        clock,
        "inverse map: random points in a warped degree-(4,4,4) volume",
        (volume.net(), map),
        count,
        &Method::ALL,
    ));

    // What a space-mapping edit costs before anything is drawn: the spline fit, the injectivity
    // certificate and the seed table.
    let build = "build the inverse map after an edit (spline, certificate, seed table)";
    let small = warped_patch(4);
    let big = warped_patch(16);
    for (n, net) in [(4, small.net()), (16, big.net())] {
        let (ms, runs, map) = time(clock, budget, || InverseMap::new(net));
        rows.push(Row {
            case: build.into(),
            who: format!("bezsolid: patch, {n}×{n} points"),
            n,
            ms,
            runs,
            extra: f64::from(u8::from(map.injective())),
            note: String::new(),
        });
    }
    let (ms, runs, map) = time(clock, budget, || InverseMap::new(volume.net()));
    rows.push(Row {
        case: build.into(),
        who: "bezsolid: volume, 5×5×5 points".into(),
        n: 5,
        ms,
        runs,
        extra: f64::from(u8::from(map.injective())),
        note: String::new(),
    });

    let res = if quick { 128 } else { 512 };
    let (ms, runs, lines) = time(clock, budget, || {
        forward_contour(&big, res, 1e-9).unwrap_or_else(|| unreachable!("certified injective"))
    });
    let contour = "contour of a warped 16×16-point patch";
    rows.push(Row {
        case: contour.into(),
        who: "bezsolid: forward-mapped (parameter-space contour, vertices mapped)".into(),
        n: res,
        ms,
        runs,
        extra: lines.iter().map(|l| l.points.len()).sum::<usize>() as f64,
        note: String::new(),
    });
    let (ms, runs, lines) = time(clock, budget, || sampled_contour(&big, res, 1e-9));
    rows.push(Row {
        case: contour.into(),
        who: "bezsolid: inverse path (seeded Newton at every sample)".into(),
        n: res,
        ms,
        runs,
        extra: lines.iter().map(|l| l.points.len()).sum::<usize>() as f64,
        note: String::new(),
    });

    let sizes: &[usize] = if quick { &[20] } else { &[64, 128] };
    for &n in sizes {
        let (ms, runs, mesh) = time(clock, budget, || {
            volume
                .polygonize(n, 1e-9)
                .unwrap_or_else(|_| unreachable!("valid arguments"))
        });
        rows.push(Row {
            case: "polygonize a warped volume (space mapping)".into(),
            who: "bezsolid: forward-mapped (parameter-space mesh, vertices mapped)".into(),
            n,
            ms,
            runs,
            extra: mesh.triangle_count() as f64,
            note: String::new(),
        });
    }
    rows.extend(folded(clock, quick));
    rows
}
