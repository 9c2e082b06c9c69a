//! Bézier clipping for `D` polynomial equations in `D` unknowns in tensor-product Bernstein form
//! (Nishita, Sederberg, Kakimoto 1990; in `D` dimensions this is the projected-polyhedron method of
//! Sherbrooke and Patrikalakis).
//!
//! Every equation `g_e(u) = Σ c_e,I B_I(u)` over the current parameter box is projected onto each
//! axis `a`: the points `(i/n_a, c_e,I)` lie in a convex hull that contains the graph of `g_e` along
//! `u_a`, so the zeros of `g_e` lie where that hull meets the axis. Intersecting the intervals of all
//! equations clips the box; when a pass removes less than a fifth of the box, it is split in half.
//! Every root in the box is found, to a parameter accuracy, within caps on the work.

use alloc::vec;
use alloc::vec::Vec;

/// A pass that keeps more than this fraction of the box splits it instead.
const SPLIT_RATIO: f64 = 0.8;

/// A tensor-product Bernstein polynomial map `R^D → R^D` over a box of its parameters: `dims[a]`
/// coefficients along axis `a`, stored with the last axis fastest (the model file's order).
///
/// `E` is the number of components (equations); clipping uses `E = D`, the injectivity certificate
/// also splits boundary curves (`D = 1`, `E = 2`) and faces (`D = 2`, `E = 3`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bernstein<const D: usize, const E: usize> {
    pub(crate) dims: [usize; D],
    pub(crate) coefs: Vec<[f64; E]>,
}

impl<const D: usize, const E: usize> Bernstein<D, E> {
    fn stride(&self, axis: usize) -> usize {
        self.dims[axis + 1..].iter().product()
    }

    /// The same polynomial minus the constant `p`: the system `S(u) − p = 0`.
    pub(crate) fn minus(&self, p: [f64; E]) -> Self {
        Self {
            dims: self.dims,
            coefs: self
                .coefs
                .iter()
                .map(|c| core::array::from_fn(|e| c[e] - p[e]))
                .collect(),
        }
    }

    /// Restrict axis `axis` to the sub-interval `[t0, t1]` of `[0, 1]` (two de Casteljau steps per line).
    pub(crate) fn restrict(&mut self, axis: usize, t0: f64, t1: f64, line: &mut Vec<[f64; E]>) {
        let n = self.dims[axis];
        let stride = self.stride(axis);
        let outer = self.coefs.len() / (n * stride);
        for o in 0..outer {
            for s in 0..stride {
                let base = o * n * stride + s;
                line.clear();
                line.extend((0..n).map(|i| self.coefs[base + i * stride]));
                restrict_line(line, t0, t1);
                for (i, c) in line.iter().enumerate() {
                    self.coefs[base + i * stride] = *c;
                }
            }
        }
    }

    /// The split halves `[0, 1/2]` and `[1/2, 1]` along `axis`.
    pub(crate) fn halves(&self, axis: usize, line: &mut Vec<[f64; E]>) -> (Self, Self) {
        let mut left = self.clone();
        let mut right = self.clone();
        left.restrict(axis, 0.0, 0.5, line);
        right.restrict(axis, 0.5, 1.0, line);
        (left, right)
    }

    /// The interval of `[0, 1]` along `axis` where the convex hulls of every equation's control
    /// points, each widened by its `band` up and down, meet zero; `None` when some hull misses it
    /// (no point of the box is within the bands of a root).
    fn clip_interval(&self, axis: usize, band: [f64; E]) -> Option<(f64, f64)> {
        let n = self.dims[axis];
        let stride = self.stride(axis);
        let outer = self.coefs.len() / (n * stride);
        let mut lo = [[f64::INFINITY; E]; crate::bernstein::MAX_DEGREE + 1];
        let mut hi = [[f64::NEG_INFINITY; E]; crate::bernstein::MAX_DEGREE + 1];
        // Walked in storage order, slab by slab: no division per coefficient.
        for o in 0..outer {
            for i in 0..n {
                let base = (o * n + i) * stride;
                for c in &self.coefs[base..base + stride] {
                    for e in 0..E {
                        lo[i][e] = lo[i][e].min(c[e]);
                        hi[i][e] = hi[i][e].max(c[e]);
                    }
                }
            }
        }
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for e in 0..E {
            let column = |i: usize| (lo[i][e] - band[e], hi[i][e] + band[e]);
            let (a, b) = hull_zero_interval(n, column)?;
            t0 = t0.max(a);
            t1 = t1.min(b);
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }

    /// The largest coefficient magnitude.
    fn max_abs(&self) -> f64 {
        self.coefs
            .iter()
            .flat_map(|c| c.iter())
            .fold(0.0f64, |m, c| m.max(c.abs()))
    }
}

/// de Casteljau restriction of one Bernstein line to `[t0, t1]`.
fn restrict_line<const E: usize>(v: &mut [[f64; E]], t0: f64, t1: f64) {
    let n = v.len() - 1;
    let mix = |a: [f64; E], b: [f64; E], t: f64| -> [f64; E] {
        core::array::from_fn(|e| a[e] + (b[e] - a[e]) * t)
    };
    if t0 > 0.0 {
        // The right part of the split at t0: v[i] ← b_i^{n−i}.
        for r in 1..=n {
            for i in 0..=n - r {
                v[i] = mix(v[i], v[i + 1], t0);
            }
        }
    }
    let s = if t0 > 0.0 { (t1 - t0) / (1.0 - t0) } else { t1 };
    if s < 1.0 {
        // The left part of the split at s: v[i] ← b_0^i.
        for r in 1..=n {
            for i in (r..=n).rev() {
                v[i] = mix(v[i - 1], v[i], s);
            }
        }
    }
}

/// Where the convex hull of the points `(i/(n−1), y)`, `y ∈ column(i)`, meets `y = 0`: the hull of
/// the crossings of every pair of points with opposite signs, and of every point on zero.
fn hull_zero_interval(n: usize, column: impl Fn(usize) -> (f64, f64)) -> Option<(f64, f64)> {
    let deg = (n - 1) as f64;
    let (mut t0, mut t1) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut add = |t: f64| {
        t0 = t0.min(t);
        t1 = t1.max(t);
    };
    for a in 0..n {
        let (la, ha) = column(a);
        let ta = a as f64 / deg;
        if la <= 0.0 && ha >= 0.0 {
            add(ta);
        }
        for b in a + 1..n {
            let (lb, hb) = column(b);
            let tb = b as f64 / deg;
            for ya in [la, ha] {
                for yb in [lb, hb] {
                    if (ya < 0.0 && yb > 0.0) || (ya > 0.0 && yb < 0.0) {
                        add(ta + (tb - ta) * ya / (ya - yb));
                    }
                }
            }
        }
    }
    (t0 <= t1).then_some((t0.max(0.0), t1.min(1.0)))
}

/// Limits and results of one clipping run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipLimits {
    /// Stop refining a box once every side is below this (parameter units).
    pub accuracy: f64,
    /// The most clipping passes (one pass clips every axis once) before giving up on the rest.
    pub max_passes: u32,
}

impl Default for ClipLimits {
    fn default() -> Self {
        Self {
            accuracy: 1e-12,
            max_passes: 4096,
        }
    }
}

/// What one clipping run did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipStats {
    /// Clipping passes made.
    pub passes: u32,
    /// Boxes split in half.
    pub splits: u32,
    /// Whether the pass cap stopped the search before every box was resolved.
    pub capped: bool,
}

/// The centres of the boxes, at most `accuracy` wide, that may hold a root of `system = 0` inside
/// the parameter box `[lo, hi]` (a subset of the unit box the coefficients are given over).
///
/// `system` is the polynomial over the *unit* box; it is restricted to `[lo, hi]` first. Several
/// centres may belong to one root (at a seam between split boxes, or a tangential root); the caller
/// polishes and merges them. A box whose coefficients are all within rounding of zero (the map is
/// constant there) is reported as a root without further splitting.
pub(crate) fn clip_roots<const D: usize>(
    system: &Bernstein<D, D>,
    lo: [f64; D],
    hi: [f64; D],
    limits: ClipLimits,
    stats: &mut ClipStats,
) -> Vec<[f64; D]> {
    let noise = system.max_abs().max(f64::MIN_POSITIVE) * 1e-14;
    search(system, lo, hi, [0.0; D], [noise; D], false, limits, stats)
}

/// Seeds for the roots of a system known only to within `band` per equation (an approximation of
/// the true system, the true one within `band[e]` of equation `e` everywhere on the unit box): the
/// centres of the boxes, at most `accuracy` wide, where every equation's hull comes within its band
/// of zero. No true root is lost: the true system is zero only where the approximation is within
/// the bands. When the pass cap stops the search, the boxes still open are given as seeds too, so
/// that the work is bounded and no region is dropped unseen.
pub(crate) fn clip_seeds<const D: usize>(
    system: &Bernstein<D, D>,
    band: [f64; D],
    limits: ClipLimits,
    stats: &mut ClipStats,
) -> Vec<[f64; D]> {
    search(system, [0.0; D], [1.0; D], band, band, true, limits, stats)
}

/// The clipping search over `[lo, hi]`: hulls widened by `band`, a box whose coefficients are all
/// within `flat` of zero taken as a root, open boxes kept as seeds at the pass cap if `keep_open`.
#[allow(clippy::too_many_arguments)]
fn search<const D: usize>(
    system: &Bernstein<D, D>,
    lo: [f64; D],
    hi: [f64; D],
    band: [f64; D],
    flat: [f64; D],
    keep_open: bool,
    limits: ClipLimits,
    stats: &mut ClipStats,
) -> Vec<[f64; D]> {
    let mut line = Vec::with_capacity(crate::bernstein::MAX_DEGREE + 1);
    let mut start = system.clone();
    for a in 0..D {
        if lo[a] > 0.0 || hi[a] < 1.0 {
            start.restrict(a, lo[a], hi[a], &mut line);
        }
    }
    let within_band = |t: &Bernstein<D, D>| {
        t.coefs
            .iter()
            .all(|c| (0..D).all(|e| c[e].abs() <= flat[e]))
    };
    let mut roots = Vec::new();
    let mut stack = vec![(start, lo, hi)];
    'boxes: while let Some((mut t, mut lo, mut hi)) = stack.pop() {
        loop {
            if stats.passes >= limits.max_passes {
                stats.capped = true;
                if keep_open {
                    roots.push(centre(lo, hi));
                    roots.extend(stack.iter().map(|(_, lo, hi)| centre(*lo, *hi)));
                }
                break 'boxes;
            }
            stats.passes += 1;
            if within_band(&t) {
                roots.push(centre(lo, hi));
                continue 'boxes;
            }
            let before: [f64; D] = core::array::from_fn(|a| hi[a] - lo[a]);
            for a in 0..D {
                let Some((s0, s1)) = t.clip_interval(a, band) else {
                    continue 'boxes;
                };
                // A margin against rounding in the hull: never lose a root on the interval's end.
                let margin = 1e-9;
                let (s0, s1) = ((s0 - margin).max(0.0), (s1 + margin).min(1.0));
                if s0 > 0.0 || s1 < 1.0 {
                    t.restrict(a, s0, s1, &mut line);
                    let w = hi[a] - lo[a];
                    let (n0, n1) = (lo[a] + w * s0, lo[a] + w * s1);
                    lo[a] = n0;
                    hi[a] = n1;
                }
            }
            let width: [f64; D] = core::array::from_fn(|a| hi[a] - lo[a]);
            if width.iter().all(|&w| w <= limits.accuracy) {
                roots.push(centre(lo, hi));
                continue 'boxes;
            }
            let kept = (0..D)
                .map(|a| {
                    if before[a] > 0.0 {
                        width[a] / before[a]
                    } else {
                        0.0
                    }
                })
                .fold(0.0f64, f64::max);
            if kept > SPLIT_RATIO {
                let axis = (0..D)
                    .max_by(|&a, &b| width[a].total_cmp(&width[b]))
                    .unwrap_or(0);
                stats.splits += 1;
                let (left, right) = t.halves(axis, &mut line);
                let mid = 0.5 * (lo[axis] + hi[axis]);
                let (mut hi_l, mut lo_r) = (hi, lo);
                hi_l[axis] = mid;
                lo_r[axis] = mid;
                stack.push((right, lo_r, hi));
                stack.push((left, lo, hi_l));
                continue 'boxes;
            }
        }
    }
    roots
}

fn centre<const D: usize>(lo: [f64; D], hi: [f64; D]) -> [f64; D] {
    core::array::from_fn(|a| 0.5 * (lo[a] + hi[a]))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn restriction_reproduces_the_line() {
        // B(t) = (1−t)^2·1 + 2t(1−t)·(−2) + t^2·3 restricted to [0.2, 0.7].
        let eval = |c: &[[f64; 1]], t: f64| {
            let n = c.len() - 1;
            (0..=n)
                .map(|i| c[i][0] * crate::bernstein::bernstein(n, i, t))
                .sum::<f64>()
        };
        let orig = [[1.0], [-2.0], [3.0]];
        let mut line = orig;
        restrict_line(&mut line, 0.2, 0.7);
        for s in [0.0, 0.3, 0.5, 1.0] {
            let t = 0.2 + 0.5 * s;
            assert!((eval(&line, s) - eval(&orig, t)).abs() < 1e-14);
        }
    }

    #[test]
    fn a_circle_and_a_line_meet_twice() {
        // (u − 0.5)² + (v − 0.5)² − 0.09 = 0 and u − v = 0 in Bernstein form, degree (2, 2).
        let f = |u: f64, v: f64| [(u - 0.5).powi(2) + (v - 0.5).powi(2) - 0.09, u - v];
        // Bernstein coefficients by blossoming: the blossom of (u − 0.5)² at (s1, s2) is
        // (s1 − 0.5)(s2 − 0.5), that of u is (s1 + s2)/2, at (0,0), (0,1), (1,1) for i = 0, 1, 2.
        let coef = |i: usize, j: usize| {
            let pts = [0.0, 0.0, 1.0, 1.0];
            let (u1, u2) = (pts[i], pts[i + 1]);
            let (v1, v2) = (pts[j], pts[j + 1]);
            [
                (u1 - 0.5) * (u2 - 0.5) + (v1 - 0.5) * (v2 - 0.5) - 0.09,
                0.5 * (u1 + u2) - 0.5 * (v1 + v2),
            ]
        };
        let coefs = (0..3)
            .flat_map(|i| (0..3).map(move |j| coef(i, j)))
            .collect();
        let t = Bernstein {
            dims: [3, 3],
            coefs,
        };
        let mut stats = ClipStats::default();
        let roots = clip_roots(&t, [0.0; 2], [1.0; 2], ClipLimits::default(), &mut stats);
        assert!(!stats.capped);
        let r = 0.3 / 2f64.sqrt();
        for want in [0.5 - r, 0.5 + r] {
            assert!(
                roots
                    .iter()
                    .any(|p| (p[0] - want).abs() < 1e-10 && (p[1] - want).abs() < 1e-10),
                "{roots:?}"
            );
        }
        for p in &roots {
            let g = f(p[0], p[1]);
            assert!(g[0].abs() < 1e-10 && g[1].abs() < 1e-10);
        }
    }
}
