//! One suite for every inverse path against the pure-clipping reference.

use alloc::vec::Vec;

use glam::{DVec3, DVec4};

use super::atlas::{AtlasBudget, Share};
use super::*;
use crate::tensor::{Patch, Volume};
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// A regular grid over the unit box with every point moved by up to `amp` per coordinate and
/// random ξ.
pub(crate) fn warped_patch(rng: &mut Rng, degree: [usize; 2], amp: f64) -> Patch<DVec3> {
    let [n, m] = degree;
    Patch::from_fn(degree, |[i, j]| {
        DVec3::new(
            i as f64 / n as f64 + rng.range(-amp, amp),
            j as f64 / m as f64 + rng.range(-amp, amp),
            rng.range(-1.0, 1.0),
        )
    })
    .unwrap()
}

pub(crate) fn warped_volume(rng: &mut Rng, degree: [usize; 3], amp: f64) -> Volume<DVec4> {
    let [n, m, l] = degree;
    Volume::from_fn(degree, |[i, j, k]| {
        DVec4::new(
            i as f64 / n as f64 + rng.range(-amp, amp),
            j as f64 / m as f64 + rng.range(-amp, amp),
            k as f64 / l as f64 + rng.range(-amp, amp),
            rng.range(-1.0, 1.0),
        )
    })
    .unwrap()
}

fn dist<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    max_abs_diff(a, b)
}

fn random_u<const D: usize>(rng: &mut Rng) -> [f64; D] {
    core::array::from_fn(|_| rng.range(0.0, 1.0))
}

#[test]
fn every_method_inverts_mild_warps_to_1e_10() {
    let mut rng = Rng::new(11);
    let mut certified = 0;
    for trial in 0..12 {
        let net = warped_patch(&mut rng, [3, 3], 0.08);
        let map = InverseMap::new(&net);
        certified += usize::from(map.injective());
        for _ in 0..40 {
            let u0: [f64; 2] = random_u(&mut rng);
            let p = net.forward(u0).x;
            for method in Method::ALL {
                let roots = map.preimages(&net, p, method, 1e-12, &mut QueryStats::default());
                assert!(!roots.is_empty(), "trial {trial} {method:?}");
                for r in &roots {
                    assert!(dist(net.forward(*r).x, p) < 1e-10, "{method:?}");
                }
                assert!(roots.iter().any(|r| dist(*r, u0) < 1e-8), "{method:?}");
            }
        }
    }
    // Mild warps are the common case the fast path exists for: most are certified.
    assert!(certified >= 9, "only {certified} of 12 certified");
    let mut rng = Rng::new(12);
    for _ in 0..4 {
        let net = warped_volume(&mut rng, [4, 4, 4], 0.05);
        let map = InverseMap::new(&net);
        assert!(map.injective());
        for _ in 0..20 {
            let u0: [f64; 3] = random_u(&mut rng);
            let p = net.forward(u0).x;
            for method in Method::ALL {
                let roots = map.preimages(&net, p, method, 1e-12, &mut QueryStats::default());
                assert_eq!(roots.len(), 1, "{method:?}");
                assert!(dist(net.forward(roots[0]).x, p) < 1e-10);
                assert!(dist(roots[0], u0) < 1e-8);
            }
        }
    }
}

/// Every distinct root that Newton finds from a dense grid of starts.
fn dense_roots<const D: usize, F: Forward<D>>(
    map: &InverseMap<D>,
    net: &F,
    p: [f64; D],
    k: usize,
) -> Vec<[f64; D]> {
    let mut roots: Vec<[f64; D]> = Vec::new();
    for index in 0..k.pow(D as u32) {
        let idx = multi_index([k; D], index);
        let start = core::array::from_fn(|a| (idx[a] as f64 + 0.5) / k as f64);
        if let Some(u) = newton::newton(
            net,
            p,
            start,
            map.scale,
            40,
            newton::Until::Root,
            &mut QueryStats::default(),
        ) && inside_closed(u, 0.0)
            && roots.iter().all(|r| dist(*r, u) > 1e-6)
        {
            roots.push(u);
        }
    }
    roots
}

#[test]
fn clipping_finds_every_root_of_folded_nets() {
    let mut rng = Rng::new(21);
    let mut folds = 0;
    for _ in 0..16 {
        let net = warped_patch(&mut rng, [3, 3], 0.45);
        let map = InverseMap::new(&net);
        for _ in 0..12 {
            let p = net.forward(random_u(&mut rng)).x;
            let mut stats = QueryStats::default();
            let roots = map.preimages(&net, p, Method::Clipping, 1e-12, &mut stats);
            assert!(!stats.clip.capped);
            for r in &roots {
                assert!(dist(net.forward(*r).x, p) < 1e-10);
            }
            let dense = dense_roots(&map, &net, p, 24);
            folds += usize::from(dense.len() > 1);
            for d in &dense {
                assert!(
                    roots.iter().any(|r| dist(*r, *d) < 1e-7),
                    "{d:?} not in {roots:?}"
                );
            }
        }
    }
    assert!(folds > 10, "the nets should fold: {folds}");
    let mut rng = Rng::new(22);
    for _ in 0..3 {
        let net = warped_volume(&mut rng, [3, 3, 3], 0.3);
        let map = InverseMap::new(&net);
        for _ in 0..6 {
            let p = net.forward(random_u(&mut rng)).x;
            let roots = map.preimages(&net, p, Method::Clipping, 1e-12, &mut QueryStats::default());
            for d in &dense_roots(&map, &net, p, 8) {
                assert!(roots.iter().any(|r| dist(*r, *d) < 1e-7));
            }
        }
    }
}

/// `f` by every method equals the reference at random points of and around the image.
fn methods_agree<const D: usize, F: Forward<D>>(net: &F, rng: &mut Rng) {
    let map = InverseMap::new(net);
    let (lo, hi) = bounds(&net.spatial());
    for _ in 0..60 {
        let p: [f64; D] = core::array::from_fn(|c| {
            let pad = 0.1 * (hi[c] - lo[c]);
            rng.range(lo[c] - pad, hi[c] + pad)
        });
        let reference = map.f(net, p, Method::Clipping, 1e-12, &mut QueryStats::default());
        for method in [Method::Hybrid, Method::Fast] {
            let got = map.f(net, p, method, 1e-12, &mut QueryStats::default());
            assert_eq!(
                got.preimages,
                reference.preimages,
                "{method:?} at {p:?}: {got:?} vs {reference:?}, injective {}",
                map.injective()
            );
            assert!((got.f - reference.f).abs() < 1e-9, "{method:?} at {p:?}");
        }
    }
}

#[test]
fn every_path_agrees_with_clipping() {
    let mut rng = Rng::new(31);
    for amp in [0.05, 0.15, 0.45] {
        for _ in 0..4 {
            methods_agree(&warped_patch(&mut rng, [3, 3], amp), &mut rng);
        }
        methods_agree(&warped_volume(&mut rng, [3, 3, 3], amp * 0.7), &mut rng);
    }
}

#[test]
fn f_is_continuous_across_the_domain_boundary() {
    let mut rng = Rng::new(41);
    for _ in 0..6 {
        let net = warped_patch(&mut rng, [3, 3], 0.1);
        let map = InverseMap::new(&net);
        for _ in 0..10 {
            // A point on a boundary edge and the outward normal of the image there.
            let t = rng.range(0.05, 0.95);
            let edge = rng.int(0, 3);
            let (u, tangent_axis) = match edge {
                0 => ([0.0, t], 1),
                1 => ([1.0, t], 1),
                2 => ([t, 0.0], 0),
                _ => ([t, 1.0], 0),
            };
            let e = net.forward(u);
            let tan = e.jac[tangent_axis];
            let mut normal = [tan[1], -tan[0]];
            // Orient it away from the image: towards decreasing inside parameter.
            let inward = if edge == 0 || edge == 2 { 1.0 } else { -1.0 };
            let other = 1 - tangent_axis;
            let d = e.jac[other];
            if (normal[0] * d[0] + normal[1] * d[1]) * inward > 0.0 {
                normal = [-normal[0], -normal[1]];
            }
            let len = (normal[0] * normal[0] + normal[1] * normal[1]).sqrt();
            let mut prev: Option<f64> = None;
            for k in -3i32..=3 {
                let h = 1e-7 * f64::from(k) / len;
                let p = [e.x[0] + h * normal[0], e.x[1] + h * normal[1]];
                let f = map
                    .f(&net, p, Method::Clipping, 1e-12, &mut QueryStats::default())
                    .f;
                if let Some(q) = prev {
                    assert!((f - q).abs() < 1e-5, "jump {q} → {f} at edge {edge}");
                }
                prev = Some(f);
            }
        }
    }
}

#[test]
fn a_regular_grid_inverts_to_its_scaling() {
    let mut rng = Rng::new(51);
    let net = warped_patch(&mut rng, [4, 2], 0.0);
    let map = InverseMap::new(&net);
    assert!(map.injective());
    for _ in 0..50 {
        let p: [f64; 2] = random_u(&mut rng);
        for method in Method::ALL {
            let roots = map.preimages(&net, p, method, 1e-12, &mut QueryStats::default());
            assert_eq!(roots.len(), 1);
            assert!(dist(roots[0], p) < 1e-13);
        }
    }
}

#[test]
fn degenerate_nets_give_defined_values() {
    let mut rng = Rng::new(61);
    let same = Patch::from_fn([3, 3], |[_, _]| DVec3::new(0.5, 0.5, 0.3)).unwrap();
    let collapsed = Patch::from_fn([3, 3], |[i, j]| {
        let x = i as f64 / 3.0;
        let y = j as f64 / 3.0;
        // The edge u = 0 collapsed to one point.
        if i == 0 {
            DVec3::new(0.0, 0.5, 1.0)
        } else {
            DVec3::new(x, y, 1.0 - x)
        }
    })
    .unwrap();
    let inside_out = Patch::from_fn([3, 3], |[i, j]| {
        DVec3::new(1.0 - i as f64 / 3.0, j as f64 / 3.0, 0.5)
    })
    .unwrap();
    let line = Patch::from_fn([2, 2], |[i, j]| DVec3::new(i as f64 + j as f64, 0.0, 0.2)).unwrap();
    for net in [same, collapsed, inside_out, line] {
        let map = InverseMap::new(&net);
        let mut points: Vec<[f64; 2]> = (0..30).map(|_| random_u(&mut rng)).collect();
        points.extend([[0.5, 0.5], [0.0, 0.5], [1.0, 0.0], [0.25, 0.0]]);
        for p in points {
            for method in Method::ALL {
                let mut stats = QueryStats::default();
                let v = map.f(&net, p, method, 1e-12, &mut stats);
                assert!(v.f.is_finite(), "{p:?} {method:?}");
                if method == Method::Fast && !map.injective() {
                    // Through the atlas: within the query's work budget (and its slack).
                    let slack = (48 * 4 + 80) * 16 * 2 + 13 * 16;
                    assert!(
                        stats.work <= AtlasBudget::query_work(0, 0, Share::WHOLE, 9) + slack,
                        "{stats:?}"
                    );
                } else {
                    assert!(stats.clip.passes <= ClipLimits::default().max_passes * 2);
                }
            }
        }
    }
    let same = Volume::from_fn([2, 2, 2], |[_, _, _]| DVec4::new(1.0, 1.0, 1.0, 0.5)).unwrap();
    let map = InverseMap::new(&same);
    for p in [[1.0, 1.0, 1.0], [0.0, 0.3, 0.2]] {
        assert!(
            map.f(&same, p, Method::Fast, 1e-12, &mut QueryStats::default())
                .f
                .is_finite()
        );
    }
}

/// Mean distance from the spline guess to the true preimage over random points of random warps.
fn guess_error<const D: usize, F: Forward<D>>(
    nets: &[F],
    fit: GuessFit,
    kernel: Option<Kernel>,
    rng: &mut Rng,
) -> f64 {
    let mut sum = 0.0;
    let mut count = 0;
    for net in nets {
        let mut map = InverseMap::with_guess(net, fit);
        if let Some(kernel) = kernel {
            let (sites, values) = match fit {
                GuessFit::ControlPoints => control_sites(&map.tensor),
                GuessFit::ForwardSamples => forward_sites(net, 5),
            };
            map.guess = Spline::fit(kernel, &sites, &values);
        }
        for _ in 0..200 {
            let u: [f64; D] = random_u(rng);
            let g = map.guess(net.forward(u).x);
            sum += dist(g, u);
            count += 1;
        }
    }
    sum / f64::from(count)
}

#[test]
fn the_default_guess_is_the_better_one_by_measurement() {
    let mut rng = Rng::new(71);
    let patches: Vec<_> = (0..8)
        .map(|_| warped_patch(&mut rng, [3, 3], 0.12))
        .collect();
    let control = guess_error(&patches, GuessFit::ControlPoints, None, &mut rng);
    let forward = guess_error(&patches, GuessFit::ForwardSamples, None, &mut rng);
    std::println!("2D guess error: control points {control:.2e}, forward samples {forward:.2e}");
    assert!(forward < control);
    let volumes: Vec<_> = (0..4)
        .map(|_| warped_volume(&mut rng, [4, 4, 4], 0.08))
        .collect();
    let fit = GuessFit::ForwardSamples;
    let linear = guess_error(&volumes, fit, Some(Kernel::Linear), &mut rng);
    let cubic = guess_error(&volumes, fit, Some(Kernel::Cubic), &mut rng);
    std::println!("3D guess error: φ = r {linear:.2e}, φ = r³ {cubic:.2e}");
    assert!(cubic < linear);
}

/// The fold of `x(u) = 3u − 2.5u²` (degree (2, 1), `y = v`): at `x = 0.9` the two preimages meet in a
/// double root at `u = 0.6`; at `u = 0.5` a simple root sits on the seam of the first split. Each is
/// one root, found without hitting the caps.
#[test]
fn tangential_and_seam_roots_are_single() {
    let xs = [0.0, 1.5, 0.5];
    let net = Patch::from_fn([2, 1], |[i, j]| DVec3::new(xs[i], j as f64, 0.5)).unwrap();
    let map = InverseMap::new(&net);
    assert!(!map.injective());
    for p in [[0.9, 0.5], [0.9, 0.0], [0.9, 1.0]] {
        let mut stats = QueryStats::default();
        let roots = map.preimages(&net, p, Method::Clipping, 1e-12, &mut stats);
        assert!(!stats.clip.capped, "{p:?}: {stats:?}");
        // One root, found to about the square root of the accuracy (a double root).
        assert_eq!(roots.len(), 1, "{p:?}: {roots:?}");
        assert!((roots[0][0] - 0.6).abs() < 1e-5 && (roots[0][1] - p[1]).abs() < 1e-9);
    }
    // x(0.5) = x(0.7) = 0.875: two simple roots, the first on the seam u = 0.5, each once.
    let mut stats = QueryStats::default();
    let roots = map.preimages(&net, [0.875, 0.5], Method::Clipping, 1e-12, &mut stats);
    assert!(!stats.clip.capped);
    assert_eq!(roots.len(), 2, "{roots:?}");
    for u in [0.5, 0.7] {
        assert!(
            roots
                .iter()
                .any(|r| (r[0] - u).abs() < 1e-12 && (r[1] - 0.5).abs() < 1e-12)
        );
    }
}

/// Far from the origin rounding in `S(u)` is larger than the net's extent suggests: the fast path
/// still converges and verifies instead of falling back.
#[test]
fn far_from_the_origin_the_fast_path_still_converges() {
    let mut rng = Rng::new(101);
    let near = warped_patch(&mut rng, [3, 3], 0.05);
    let far = Patch::from_fn([3, 3], |[i, j]| {
        let p = near[[i, j]];
        DVec3::new(p.x + 1e5, p.y - 3e5, p.z)
    })
    .unwrap();
    let map = InverseMap::new(&far);
    assert!(map.injective());
    let mut fallbacks = 0;
    for _ in 0..100 {
        let u: [f64; 2] = random_u(&mut rng);
        let p = far.forward(u).x;
        let mut stats = QueryStats::default();
        let v = map.f(&far, p, Method::Fast, 1e-12, &mut stats);
        fallbacks += usize::from(stats.fallback);
        assert_eq!(v.preimages, 1);
        assert!(dist(v.u, u) < 1e-9);
    }
    assert_eq!(fallbacks, 0);
}

/// The regular grid over the unit box with the control points' positions shuffled among them (ξ
/// random): a net that folds over itself everywhere, the worst a user can drag into being.
pub(crate) fn shuffled_patch(rng: &mut Rng, degree: [usize; 2]) -> Patch<DVec3> {
    let [n, m] = degree;
    let mut spots: Vec<(f64, f64)> = (0..=n)
        .flat_map(|i| (0..=m).map(move |j| (i as f64 / n as f64, j as f64 / m as f64)))
        .collect();
    for k in (1..spots.len()).rev() {
        spots.swap(k, rng.int(0, k));
    }
    Patch::from_fn(degree, |[i, j]| {
        let (x, y) = spots[i * (m + 1) + j];
        DVec3::new(x, y, rng.range(-1.0, 1.0))
    })
    .unwrap()
}

/// [`shuffled_patch`] for volumes.
pub(crate) fn shuffled_volume(rng: &mut Rng, degree: [usize; 3]) -> Volume<DVec4> {
    let [n, m, l] = degree;
    let mut spots: Vec<[f64; 3]> = (0..(n + 1) * (m + 1) * (l + 1))
        .map(|index| {
            let idx = multi_index([n + 1, m + 1, l + 1], index);
            [
                idx[0] as f64 / n as f64,
                idx[1] as f64 / m as f64,
                idx[2] as f64 / l as f64,
            ]
        })
        .collect();
    for k in (1..spots.len()).rev() {
        spots.swap(k, rng.int(0, k));
    }
    Volume::from_fn(degree, |[i, j, k]| {
        let [x, y, z] = spots[(i * (m + 1) + j) * (l + 1) + k];
        DVec4::new(x, y, z, rng.range(-1.0, 1.0))
    })
    .unwrap()
}

/// The ratio of the smallest to the largest singular value bound of `J` at `u`: small near a fold.
fn conditioning<const D: usize, F: Forward<D>>(net: &F, u: [f64; D]) -> f64 {
    let e = net.forward(u);
    let size = e.jac.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let mut inv = 0.0;
    for c in 0..D {
        let mut unit = [0.0; D];
        unit[c] = 1.0;
        match solve_jac(&e.jac, unit) {
            Some(x) => inv += x.iter().map(|v| v * v).sum::<f64>(),
            None => return 0.0,
        }
    }
    1.0 / (size * inv.sqrt())
}

/// The atlas path against whole-domain clipping: every preimage it gives is one, and it misses
/// none that clipping finds away from folds (where the Jacobian is well conditioned); the few it
/// may miss sit where two preimages merge, and `f` jumps there anyway.
fn atlas_agrees_with_clipping<const D: usize, F: Forward<D>>(
    net: &F,
    rng: &mut Rng,
    queries: usize,
) -> (usize, usize) {
    let map = InverseMap::new(net);
    assert!(!map.injective());
    let (lo, hi) = bounds(&net.spatial());
    let (mut found, mut near_folds) = (0, 0);
    for q in 0..queries {
        // Points of the image (from parameters) and points of its bounds, alternately.
        let p: [f64; D] = if q % 2 == 0 {
            net.forward(random_u(rng)).x
        } else {
            core::array::from_fn(|c| rng.range(lo[c], hi[c]))
        };
        let mut stats = QueryStats::default();
        let fast = map.preimages(net, p, Method::Fast, 1e-12, &mut stats);
        assert!(!stats.exhausted, "{stats:?}");
        let reference = map.preimages(net, p, Method::Clipping, 1e-12, &mut QueryStats::default());
        for r in &fast {
            assert!(inside_closed(*r, 0.0));
            assert!(
                dist(net.forward(*r).x, p) < 1e-9,
                "{r:?} is no preimage of {p:?}"
            );
        }
        for r in &reference {
            if fast.iter().any(|f| dist(*f, *r) < 1e-7) {
                found += 1;
            } else if conditioning(net, *r) < 1e-2 {
                near_folds += 1;
            } else {
                panic!(
                    "{r:?} (conditioning {}) missed at {p:?}: {fast:?} ({stats:?})",
                    conditioning(net, *r)
                );
            }
        }
    }
    (found, near_folds)
}

#[test]
fn the_atlas_finds_the_preimages_of_nets_that_fold_everywhere() {
    let mut rng = Rng::new(111);
    let (mut found, mut near_folds) = (0, 0);
    for degree in [[3, 3], [6, 6], [9, 4]] {
        for _ in 0..3 {
            let net = shuffled_patch(&mut rng, degree);
            let (f, n) = atlas_agrees_with_clipping(&net, &mut rng, 150);
            found += f;
            near_folds += n;
        }
    }
    for _ in 0..2 {
        let net = shuffled_volume(&mut rng, [2, 2, 2]);
        let (f, n) = atlas_agrees_with_clipping(&net, &mut rng, 60);
        found += f;
        near_folds += n;
        let net = warped_volume(&mut rng, [3, 3, 3], 0.3);
        let (f, n) = atlas_agrees_with_clipping(&net, &mut rng, 60);
        found += f;
        near_folds += n;
    }
    std::println!("atlas: {found} preimages found, {near_folds} near folds missed");
    assert!(
        found > 500 && near_folds * 100 < found,
        "{found} {near_folds}"
    );
}

#[test]
fn queries_through_the_atlas_are_bounded_however_the_net_folds() {
    let mut rng = Rng::new(112);
    for (degree, planned) in [([16, 16], 1 << 20), ([16, 16], 0), ([6, 6], 1 << 22)] {
        let net = shuffled_patch(&mut rng, degree);
        let points = (degree[0] + 1) * (degree[1] + 1);
        let map = InverseMap::new(&net);
        map.plan(planned);
        let (pieces, _) = map.atlas_pieces();
        assert_eq!(
            pieces,
            AtlasBudget::for_queries(2, points, planned, Share::WHOLE).max_pieces
        );
        // The largest a query may spend: before the plan's work is spent.
        let cap = AtlasBudget::query_work(planned, 0, Share::WHOLE, points);
        let mut most = QueryStats::default();
        for _ in 0..200 {
            let p = net.forward(random_u(&mut rng)).x;
            let mut stats = QueryStats::default();
            let v = map.f(&net, p, Method::Fast, 1e-12, &mut stats);
            assert!(v.f.is_finite());
            assert_eq!(v.exhausted, stats.exhausted);
            if stats.work > most.work {
                most = stats;
            }
        }
        std::println!("{degree:?}, {planned} planned: the most work of one query: {most:?}");
        // The budget is checked before each piece and each solve: past it by at most one piece's
        // seeds (48 passes at four units a coefficient and 8 × 10 Newton steps on a 4 × 4
        // approximation) and one solve (13
        // evaluations of the net).
        let slack = (48 * 4 + 80) * 16 * 2 + 13 * points as u64;
        assert!(most.work <= cap + slack, "{} > {cap} + {slack}", most.work);
    }
}
