//! Triangular Bézier patches `T(u, v, w) = Σ_{i+j+k=n} P_ijk · n!/(i! j! k!) · uⁱ vʲ wᵏ` of any
//! degree 1 to [`MAX_DEGREE`], over barycentric coordinates `(u, v, w)` with `u + v + w = 1`.
//!
//! The domain triangle has the corners `A = (1, 0, 0)`, `B = (0, 1, 0)` and `C = (0, 0, 1)`; the
//! control point `P_n00` sits at `A`, `P_0n0` at `B` and `P_00n` at `C`.
//!
//! Barycentric points are passed as a [`DVec3`] `(u, v, w)`. Every evaluation is the polynomial
//! above, so a point whose coordinates do not sum to 1 gives the value of that polynomial, which is
//! not a point of the patch: callers pass `u + v + w = 1` (coordinates may be negative, which
//! extrapolates outside the triangle).
//!
//! Where a Cartesian parameter pair is more convenient, the patch is read over the unit triangle
//! `s, t ≥ 0, s + t ≤ 1` with `u = 1 − s − t`, `v = s`, `w = t` ([`TriangularPatch::eval_st`],
//! [`TriangularPatch::ds`], [`TriangularPatch::dt`]).
//!
//! ```
//! use bezsolid_core::triangular::TriangularPatch;
//! use glam::DVec3;
//!
//! // Linear precision: P_ijk = (i, j, k)/n reproduces the barycentric point itself.
//! let n = 3;
//! let patch = TriangularPatch::from_fn(n, |i, j, k| {
//!     DVec3::new(i as f64, j as f64, k as f64) / n as f64
//! })
//! .unwrap();
//! let b = DVec3::new(0.2, 0.3, 0.5);
//! assert!((patch.eval(b) - b).abs().max_element() < 1e-12);
//! ```

use alloc::vec;
use alloc::vec::Vec;

use glam::{DVec2, DVec3, DVec4};

use crate::BezierCurve;
use crate::bernstein::{MAX_DEGREE, binomial};
use crate::tensor::{ControlPoint, PatchError};

/// The number of control points of a triangular net of degree `n`: `(n + 1)(n + 2)/2`.
#[must_use]
pub const fn point_count(degree: usize) -> usize {
    (degree + 1) * (degree + 2) / 2
}

/// The storage index of `P_ijk` (`k = n − i − j`) in a net of degree `n`: `i·(2n + 3 − i)/2 + j`.
///
/// Points are stored lexicographically by `i` ascending, then `j` ascending: row `i` holds the
/// `n − i + 1` points `P_(i, 0, n−i) … P_(i, n−i, 0)`. The result is meaningful only for `i + j ≤ n`
/// (see [`TriangularPatch::index`] for a checked version).
#[must_use]
pub const fn net_index(degree: usize, i: usize, j: usize) -> usize {
    i * (2 * degree + 3 - i) / 2 + j
}

/// The most control points of a net of degree at most [`MAX_DEGREE`].
const NET_MAX: usize = point_count(MAX_DEGREE);

/// A triangular Bézier patch of degree `n`, `1 ≤ n ≤ MAX_DEGREE`, with `(n + 1)(n + 2)/2` control
/// points `P_ijk`, `i + j + k = n`.
///
/// Storage order: lexicographic by `i` ascending, then `j` ascending (so `k` descends within a row):
/// `P_ijk` is at index [`net_index`]`(n, i, j) = i·(2n + 3 − i)/2 + j`. For `n = 2` the order is
/// `P_002, P_011, P_020, P_101, P_110, P_200`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangularPatch<P> {
    degree: usize,
    points: Vec<P>,
}

impl<P: ControlPoint> TriangularPatch<P> {
    /// A patch from its degree and `(n + 1)(n + 2)/2` control points in the storage order of
    /// [`TriangularPatch`] (by `i`, then `j`).
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when `degree` is 0 or above [`MAX_DEGREE`], [`PatchError::PointCount`]
    /// when the number of points is not `(n + 1)(n + 2)/2`.
    pub fn try_new(degree: usize, points: Vec<P>) -> Result<Self, PatchError> {
        check_degree(degree)?;
        let expected = point_count(degree);
        if points.len() != expected {
            return Err(PatchError::PointCount {
                expected,
                got: points.len(),
            });
        }
        Ok(Self { degree, points })
    }

    /// A patch whose control point `P_ijk` is `point(i, j, k)`, called in storage order.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when `degree` is 0 or above [`MAX_DEGREE`].
    pub fn from_fn(
        degree: usize,
        mut point: impl FnMut(usize, usize, usize) -> P,
    ) -> Result<Self, PatchError> {
        check_degree(degree)?;
        let points = triples(degree).map(|(i, j, k)| point(i, j, k)).collect();
        Self::try_new(degree, points)
    }

    /// The degree `n`.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The control points in storage order (`P_ijk` at [`net_index`]`(n, i, j)`).
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The storage index of `P_ijk`, `k = n − i − j`; `None` when `i + j > n`.
    #[must_use]
    pub fn index(&self, i: usize, j: usize) -> Option<usize> {
        (i + j <= self.degree).then(|| net_index(self.degree, i, j))
    }

    /// `P_ijk`; `None` unless `i + j + k = n`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize, k: usize) -> Option<P> {
        if i + j + k != self.degree {
            return None;
        }
        self.index(i, j)
            .and_then(|idx| self.points.get(idx).copied())
    }

    /// The corner control point, which the patch interpolates: corner 0 is `P_n00` at `A = (1, 0, 0)`,
    /// corner 1 is `P_0n0` at `B = (0, 1, 0)`, corner 2 is `P_00n` at `C = (0, 0, 1)`; `None` for any
    /// other `corner`.
    #[must_use]
    pub fn corner(&self, corner: usize) -> Option<P> {
        let n = self.degree;
        match corner {
            0 => self.point(n, 0, 0),
            1 => self.point(0, n, 0),
            2 => self.point(0, 0, n),
            _ => None,
        }
    }

    /// The boundary curve `edge` as a Bézier curve of degree `n`; `None` for `edge > 2`.
    ///
    /// Edge `e` runs from corner `e` to corner `(e + 1) mod 3`: `curve(t) = T((1 − t)·corner_e +
    /// t·corner_(e+1))`. So edge 0 is `w = 0` from `A` to `B` (points `P_(n−l, l, 0)`), edge 1 is
    /// `u = 0` from `B` to `C` (points `P_(0, n−l, l)`) and edge 2 is `v = 0` from `C` to `A` (points
    /// `P_(l, 0, n−l)`), `l = 0 … n`.
    #[must_use]
    pub fn edge(&self, edge: usize) -> Option<BezierCurve<P>> {
        let n = self.degree;
        let points: Option<Vec<P>> = (0..=n)
            .map(|l| match edge {
                0 => self.point(n - l, l, 0),
                1 => self.point(0, n - l, l),
                2 => self.point(l, 0, n - l),
                _ => None,
            })
            .collect();
        BezierCurve::try_new(points?).ok()
    }

    /// `T(u, v, w)` in basis form: `Σ P_ijk · C(n, i)·C(n − i, j) · uⁱ vʲ wᵏ`, with the powers
    /// tabulated once and the trinomial coefficients in `f64` (exact for every degree up to
    /// [`MAX_DEGREE`]). Expects `u + v + w = 1`.
    #[must_use]
    pub fn eval(&self, bary: DVec3) -> P {
        eval_net(self.degree, &self.points, bary)
    }

    /// `T(u, v, w)` by the triangular de Casteljau algorithm: `n` levels of
    /// `P^r_ijk = u P^(r−1)_(i+1,j,k) + v P^(r−1)_(i,j+1,k) + w P^(r−1)_(i,j,k+1)`. Slower than
    /// [`TriangularPatch::eval`]; the reference it is tested against. Expects `u + v + w = 1`.
    #[must_use]
    pub fn eval_de_casteljau(&self, bary: DVec3) -> P {
        let n = self.degree;
        let mut work = [P::ZERO; NET_MAX];
        let net = &mut work[..self.points.len()];
        net.copy_from_slice(&self.points);
        for m in (1..=n).rev() {
            casteljau_step(net, m, bary);
        }
        net[0]
    }

    /// `T(s, t) = T(1 − s − t, s, t)`: the patch over the unit triangle `s, t ≥ 0`, `s + t ≤ 1`.
    #[must_use]
    pub fn eval_st(&self, s: f64, t: f64) -> P {
        self.eval(st_to_bary(s, t))
    }

    /// The directional derivative `D_d T(b) = n Σ_{|I|=n−1} (d_u P_(I+e1) + d_v P_(I+e2) +
    /// d_w P_(I+e3)) B_I^(n−1)(b)` along the barycentric direction `dir = (d_u, d_v, d_w)`, whose
    /// components sum to 0 (the difference of two barycentric points). Computed by `n − 1`
    /// de Casteljau levels at `bary` and one at `dir` (the blossom `n·T[b, …, b, d]`).
    #[must_use]
    pub fn directional_derivative(&self, bary: DVec3, dir: DVec3) -> P {
        let n = self.degree;
        let mut work = [P::ZERO; NET_MAX];
        let net = &mut work[..self.points.len()];
        net.copy_from_slice(&self.points);
        for m in (2..=n).rev() {
            casteljau_step(net, m, bary);
        }
        casteljau_step(net, 1, dir);
        net[0] * n as f64
    }

    /// The directional derivative along `dir` (components summing to 0) as a patch of degree
    /// `n − 1`, with control points `n (d_u P_(I+e1) + d_v P_(I+e2) + d_w P_(I+e3))`; `None` for
    /// `n = 1`, whose derivative is the constant [`TriangularPatch::directional_derivative`] (at any
    /// point).
    #[must_use]
    pub fn derivative_patch(&self, dir: DVec3) -> Option<Self> {
        let n = self.degree;
        if n < 2 {
            return None;
        }
        let mut net = self.points.clone();
        casteljau_step(&mut net, n, dir);
        net.truncate(point_count(n - 1));
        for p in &mut net {
            *p = *p * n as f64;
        }
        Some(Self {
            degree: n - 1,
            points: net,
        })
    }

    /// `∂T/∂s` at `(s, t)` over the unit triangle (`u = 1 − s − t`, `v = s`, `w = t`): the
    /// directional derivative along `(−1, 1, 0)`.
    #[must_use]
    pub fn ds(&self, s: f64, t: f64) -> P {
        self.directional_derivative(st_to_bary(s, t), DVec3::new(-1.0, 1.0, 0.0))
    }

    /// `∂T/∂t` at `(s, t)` over the unit triangle (`u = 1 − s − t`, `v = s`, `w = t`): the
    /// directional derivative along `(−1, 0, 1)`.
    #[must_use]
    pub fn dt(&self, s: f64, t: f64) -> P {
        self.directional_derivative(st_to_bary(s, t), DVec3::new(-1.0, 0.0, 1.0))
    }

    /// De Casteljau subdivision at the barycentric point `p` (`u + v + w = 1`, meant to be inside the
    /// triangle) into the three sub-patches over the triangles `[(p, B, C), (A, p, C), (A, B, p)]`,
    /// `A, B, C` the corners `e1, e2, e3`.
    ///
    /// Each sub-patch is parametrised by its own barycentric coordinates in that vertex order:
    /// sub-patch `0` at `(a, b, c)` equals `T(a·p + b·B + c·C)`, sub-patch `1` equals
    /// `T(a·A + b·p + c·C)`, sub-patch `2` equals `T(a·A + b·B + c·p)`. In other words, sub-patch
    /// `e` is the original with corner `e` replaced by `p`. Its control points are the blossom values
    /// `T[p^i, B^j, C^k]` (and so on), read off the de Casteljau levels at `p`. For `p` on an edge one
    /// sub-triangle is degenerate (its patch is still correct, just flat in one direction).
    #[must_use]
    pub fn subdivide(&self, p: DVec3) -> [Self; 3] {
        let n = self.degree;
        let count = self.points.len();
        let mut subs = [
            vec![P::ZERO; count],
            vec![P::ZERO; count],
            vec![P::ZERO; count],
        ];
        let mut work = [P::ZERO; NET_MAX];
        let net = &mut work[..count];
        net.copy_from_slice(&self.points);
        for l in 0..=n {
            // `net[..point_count(m)]` holds the level-l net T[p^l, ·] of degree m = n − l.
            let m = n - l;
            for a in 0..=m {
                // Sub-patch 0 (p, B, C): P_(l, a, m−a) = level-l point (0, a, m − a).
                subs[0][net_index(n, l, a)] = net[net_index(m, 0, a)];
                // Sub-patch 1 (A, p, C): P_(a, l, m−a) = level-l point (a, 0, m − a).
                subs[1][net_index(n, a, l)] = net[net_index(m, a, 0)];
                // Sub-patch 2 (A, B, p): P_(a, m−a, l) = level-l point (a, m − a, 0).
                subs[2][net_index(n, a, m - a)] = net[net_index(m, a, m - a)];
            }
            if m > 0 {
                casteljau_step(net, m, p);
            }
        }
        subs.map(|points| Self { degree: n, points })
    }

    /// Degree elevation by one: the same patch with degree `n + 1` and control points
    /// `Q_I = (i P_(I−e1) + j P_(I−e2) + k P_(I−e3)) / (n + 1)`, `I = (i, j, k)`, `|I| = n + 1`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when the patch already has degree [`MAX_DEGREE`].
    pub fn elevate(&self) -> Result<Self, PatchError> {
        let n = self.degree;
        check_degree(n + 1)?;
        let n1 = (n + 1) as f64;
        let p = |i: usize, j: usize| self.points[net_index(n, i, j)];
        // Each weight divided separately, so the corners (weight (n + 1)/(n + 1) = 1) stay exact.
        let points = triples(n + 1)
            .map(|(i, j, k)| {
                let mut q = P::ZERO;
                if i > 0 {
                    q = q + p(i - 1, j) * (i as f64 / n1);
                }
                if j > 0 {
                    q = q + p(i, j - 1) * (j as f64 / n1);
                }
                if k > 0 {
                    q = q + p(i, j) * (k as f64 / n1);
                }
                q
            })
            .collect();
        Ok(Self {
            degree: n + 1,
            points,
        })
    }
}

macro_rules! impl_bounds {
    ($($v:ty),*) => {$(
        impl TriangularPatch<$v> {
            /// The axis-aligned bounding box `(min, max)` of the control net. By the convex hull
            /// property it bounds the patch over its triangle (`u, v, w ≥ 0`).
            #[must_use]
            pub fn bounds(&self) -> ($v, $v) {
                self.points.iter().fold(
                    (<$v>::INFINITY, <$v>::NEG_INFINITY),
                    |(lo, hi), &p| (lo.min(p), hi.max(p)),
                )
            }
        }
    )*};
}

impl_bounds!(DVec2, DVec3, DVec4);

/// `1 ≤ degree ≤ MAX_DEGREE`.
fn check_degree(degree: usize) -> Result<(), PatchError> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(PatchError::Degree { degree });
    }
    Ok(())
}

/// `(1 − s − t, s, t)`.
fn st_to_bary(s: f64, t: f64) -> DVec3 {
    DVec3::new(1.0 - s - t, s, t)
}

/// Every `(i, j, k)` with `i + j + k = n`, in storage order (by `i`, then `j`).
fn triples(n: usize) -> impl Iterator<Item = (usize, usize, usize)> {
    (0..=n).flat_map(move |i| (0..=n - i).map(move |j| (i, j, n - i - j)))
}

/// `[1, x, x², …, xⁿ]` (entries past `n` are 0).
fn powers(n: usize, x: f64) -> [f64; MAX_DEGREE + 1] {
    let mut out = [0.0; MAX_DEGREE + 1];
    let mut p = 1.0;
    for slot in out.iter_mut().take(n + 1) {
        *slot = p;
        p *= x;
    }
    out
}

/// The basis form on a net of degree `n ≤ MAX_DEGREE` (0 allowed) in storage order.
fn eval_net<P: ControlPoint>(n: usize, points: &[P], bary: DVec3) -> P {
    let pu = powers(n, bary.x);
    let pv = powers(n, bary.y);
    let pw = powers(n, bary.z);
    triples(n)
        .zip(points)
        .fold(P::ZERO, |acc, ((i, j, k), &p)| {
            let b = binomial(n, i) * binomial(n - i, j) * pu[i] * pv[j] * pw[k];
            acc + p * b
        })
}

/// One triangular de Casteljau level, in place: the net of degree `m ≥ 1` in
/// `net[..point_count(m)]` becomes the net of degree `m − 1` in `net[..point_count(m − 1)]` with
/// `Q_ijk = b_u P_(i+1,j,k) + b_v P_(i,j+1,k) + b_w P_(i,j,k+1)`.
///
/// In place is safe: the target index `net_index(m − 1, i, j) = net_index(m, i, j) − i` is below
/// every source of this and all later targets, so no source is overwritten before it is read.
fn casteljau_step<P: ControlPoint>(net: &mut [P], m: usize, b: DVec3) {
    let mut target = 0;
    let mut source = 0; // net_index(m, i, j)
    for i in 0..m {
        let row = m - i + 1; // points in row i of the degree-m net
        for _ in 0..m - i {
            net[target] = net[source + row] * b.x + net[source + 1] * b.y + net[source] * b.z;
            target += 1;
            source += 1;
        }
        source += 1; // skip P_(i, m−i, 0), which has no (i, j + 1) neighbour
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use crate::testutil::{Rng, assert_close};

    fn random_point(rng: &mut Rng) -> DVec3 {
        DVec3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        )
    }

    fn random_patch(rng: &mut Rng, max_degree: usize) -> TriangularPatch<DVec3> {
        let n = rng.int(1, max_degree);
        TriangularPatch::from_fn(n, |_, _, _| random_point(rng)).unwrap()
    }

    /// A uniform point of the triangle (`u, v, w ≥ 0`, sum 1).
    fn random_bary(rng: &mut Rng) -> DVec3 {
        let (mut s, mut t) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        if s + t > 1.0 {
            (s, t) = (1.0 - s, 1.0 - t);
        }
        st_to_bary(s, t)
    }

    /// A point strictly inside the triangle, away from the edges.
    fn random_interior(rng: &mut Rng) -> DVec3 {
        let b = random_bary(rng);
        b * 0.8 + DVec3::splat(0.2 / 3.0)
    }

    /// A barycentric direction (components sum to 0).
    fn random_dir(rng: &mut Rng) -> DVec3 {
        let (a, b) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        DVec3::new(a, b, -a - b)
    }

    #[test]
    fn triangular_storage_order_and_accessors() {
        for n in 1..=MAX_DEGREE {
            let patch =
                TriangularPatch::from_fn(n, |i, j, k| DVec3::new(i as f64, j as f64, k as f64))
                    .unwrap();
            assert_eq!(patch.degree(), n);
            assert_eq!(patch.points().len(), point_count(n));
            for (idx, (i, j, k)) in triples(n).enumerate() {
                assert_eq!(patch.index(i, j), Some(idx));
                assert_eq!(net_index(n, i, j), idx);
                assert_eq!(
                    patch.point(i, j, k),
                    Some(DVec3::new(i as f64, j as f64, k as f64))
                );
            }
            assert_eq!(patch.index(n, 1), None);
            assert_eq!(patch.point(n, 0, 1), None);
            assert_eq!(patch.point(0, 0, n.saturating_sub(1)), None);
            assert_eq!(patch.corner(0), Some(DVec3::new(n as f64, 0.0, 0.0)));
            assert_eq!(patch.corner(1), Some(DVec3::new(0.0, n as f64, 0.0)));
            assert_eq!(patch.corner(2), Some(DVec3::new(0.0, 0.0, n as f64)));
            assert_eq!(patch.corner(3), None);
            assert!(patch.edge(3).is_none());
        }
        let two = TriangularPatch::from_fn(2, |i, j, k| (100 * i + 10 * j + k) as f64).unwrap();
        assert_eq!(two.points(), &[2.0, 11.0, 20.0, 101.0, 110.0, 200.0]);
    }

    #[test]
    fn triangular_rejects_bad_input() {
        assert_eq!(
            TriangularPatch::<f64>::try_new(0, vec![1.0]),
            Err(PatchError::Degree { degree: 0 })
        );
        assert_eq!(
            TriangularPatch::<f64>::try_new(MAX_DEGREE + 1, vec![0.0; point_count(MAX_DEGREE + 1)]),
            Err(PatchError::Degree {
                degree: MAX_DEGREE + 1
            })
        );
        assert_eq!(
            TriangularPatch::<f64>::from_fn(0, |_, _, _| 0.0),
            Err(PatchError::Degree { degree: 0 })
        );
        assert_eq!(
            TriangularPatch::<f64>::from_fn(17, |_, _, _| 0.0),
            Err(PatchError::Degree { degree: 17 })
        );
        assert_eq!(
            TriangularPatch::<f64>::try_new(2, vec![0.0; 5]),
            Err(PatchError::PointCount {
                expected: 6,
                got: 5
            })
        );
        assert_eq!(
            TriangularPatch::<f64>::try_new(3, vec![0.0; 11]),
            Err(PatchError::PointCount {
                expected: 10,
                got: 11
            })
        );
        assert!(TriangularPatch::<f64>::try_new(MAX_DEGREE, vec![0.0; NET_MAX]).is_ok());
    }

    #[test]
    fn triangular_linear_precision() {
        // P_ijk = (i, j, k)/n reproduces the identity, at every degree.
        let mut rng = Rng::new(700);
        for n in 1..=MAX_DEGREE {
            let patch = TriangularPatch::from_fn(n, |i, j, k| {
                DVec3::new(i as f64, j as f64, k as f64) / n as f64
            })
            .unwrap();
            for _ in 0..20 {
                let b = random_bary(&mut rng);
                assert_close!(patch.eval(b), b, 1e-12, "n = {n}");
                assert_close!(patch.eval_de_casteljau(b), b, 1e-12, "n = {n}");
                let d = random_dir(&mut rng);
                assert_close!(patch.directional_derivative(b, d), d, 1e-12, "n = {n}");
            }
        }
    }

    #[test]
    fn triangular_basis_form_equals_de_casteljau() {
        let mut rng = Rng::new(701);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            for _ in 0..20 {
                let b = random_bary(&mut rng);
                let (x, y) = (patch.eval(b), patch.eval_de_casteljau(b));
                assert_close!(x, y, 1e-12, "{x} vs {y}");
            }
            // Slightly outside the triangle: still the same polynomial.
            for _ in 0..5 {
                let (s, t) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                let b = st_to_bary(s, t);
                assert_close!(patch.eval(b), patch.eval_de_casteljau(b), 1e-10);
            }
        }
        // The highest degree too.
        let mut rng = Rng::new(702);
        let patch = TriangularPatch::from_fn(MAX_DEGREE, |_, _, _| random_point(&mut rng)).unwrap();
        for _ in 0..20 {
            let b = random_bary(&mut rng);
            assert_close!(patch.eval(b), patch.eval_de_casteljau(b), 1e-11);
        }
    }

    #[test]
    fn triangular_corners_interpolate_control_points() {
        let mut rng = Rng::new(703);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            for (c, b) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                let corner = patch.corner(c).unwrap();
                assert_close!(patch.eval(b), corner, 1e-14);
                assert_close!(patch.eval_de_casteljau(b), corner, 1e-14);
            }
        }
    }

    #[test]
    fn triangular_edges_are_the_boundary_curves() {
        let mut rng = Rng::new(704);
        let corners = [DVec3::X, DVec3::Y, DVec3::Z];
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            for e in 0..3 {
                let curve = patch.edge(e).unwrap();
                assert_eq!(curve.degree(), patch.degree());
                assert_eq!(curve.points()[0], patch.corner(e).unwrap());
                assert_eq!(
                    curve.points()[patch.degree()],
                    patch.corner((e + 1) % 3).unwrap()
                );
                for _ in 0..10 {
                    let t = rng.range(0.0, 1.0);
                    let b = corners[e] * (1.0 - t) + corners[(e + 1) % 3] * t;
                    assert_close!(curve.eval(t), patch.eval(b), 1e-12);
                }
            }
        }
    }

    #[test]
    fn triangular_directional_derivative_matches_finite_differences() {
        let mut rng = Rng::new(705);
        let h = 1e-6;
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            for _ in 0..10 {
                let b = random_bary(&mut rng);
                let d = random_dir(&mut rng);
                let fd = (patch.eval(b + d * h) - patch.eval(b - d * h)) / (2.0 * h);
                let dd = patch.directional_derivative(b, d);
                assert_close!(fd, dd, 1e-5, "{fd} vs {dd}");
            }
        }
    }

    #[test]
    fn triangular_st_partials_match_finite_differences() {
        let mut rng = Rng::new(706);
        let h = 1e-6;
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            for _ in 0..10 {
                let b = random_bary(&mut rng);
                let (s, t) = (b.y, b.z);
                assert_close!(patch.eval_st(s, t), patch.eval(b), 1e-15);
                let fs = (patch.eval_st(s + h, t) - patch.eval_st(s - h, t)) / (2.0 * h);
                let ft = (patch.eval_st(s, t + h) - patch.eval_st(s, t - h)) / (2.0 * h);
                assert_close!(fs, patch.ds(s, t), 1e-5);
                assert_close!(ft, patch.dt(s, t), 1e-5);
            }
        }
    }

    #[test]
    fn triangular_derivative_patch_equals_directional_derivative() {
        let mut rng = Rng::new(707);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            let d = random_dir(&mut rng);
            let Some(dp) = patch.derivative_patch(d) else {
                assert_eq!(patch.degree(), 1);
                // A linear patch has a constant derivative.
                let c = patch.directional_derivative(random_bary(&mut rng), d);
                for _ in 0..5 {
                    let b = random_bary(&mut rng);
                    assert_close!(patch.directional_derivative(b, d), c, 1e-13);
                }
                continue;
            };
            assert_eq!(dp.degree(), patch.degree() - 1);
            for _ in 0..10 {
                let b = random_bary(&mut rng);
                let (x, y) = (dp.eval(b), patch.directional_derivative(b, d));
                assert_close!(x, y, 1e-12, "{x} vs {y}");
            }
        }
    }

    #[test]
    fn triangular_subdivision_reproduces_the_patch() {
        let mut rng = Rng::new(708);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            let p = random_interior(&mut rng);
            let subs = patch.subdivide(p);
            // Vertices of the sub-triangles, in the documented order.
            let tris = [
                [p, DVec3::Y, DVec3::Z],
                [DVec3::X, p, DVec3::Z],
                [DVec3::X, DVec3::Y, p],
            ];
            for (sub, tri) in subs.iter().zip(&tris) {
                assert_eq!(sub.degree(), patch.degree());
                for _ in 0..10 {
                    let x = random_bary(&mut rng);
                    let mapped = tri[0] * x.x + tri[1] * x.y + tri[2] * x.z;
                    let (a, b) = (sub.eval(x), patch.eval(mapped));
                    assert_close!(a, b, 1e-11, "{a} vs {b}");
                }
            }
            // The split point is a corner of every sub-patch.
            let tp = patch.eval(p);
            assert_close!(subs[0].corner(0).unwrap(), tp, 1e-12);
            assert_close!(subs[1].corner(1).unwrap(), tp, 1e-12);
            assert_close!(subs[2].corner(2).unwrap(), tp, 1e-12);
        }
    }

    #[test]
    fn triangular_elevation_preserves_every_point() {
        let mut rng = Rng::new(709);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            let e = patch.elevate().unwrap();
            assert_eq!(e.degree(), patch.degree() + 1);
            assert_eq!(e.points().len(), point_count(patch.degree() + 1));
            for c in 0..3 {
                assert_eq!(e.corner(c), patch.corner(c));
            }
            for _ in 0..10 {
                let b = random_bary(&mut rng);
                assert_close!(e.eval(b), patch.eval(b), 1e-12);
            }
        }
        let top = TriangularPatch::from_fn(MAX_DEGREE, |_, _, _| 1.0).unwrap();
        assert_eq!(
            top.elevate(),
            Err(PatchError::Degree {
                degree: MAX_DEGREE + 1
            })
        );
    }

    #[test]
    fn triangular_bounds_contain_the_patch() {
        let mut rng = Rng::new(710);
        for _ in 0..50 {
            let patch = random_patch(&mut rng, 8);
            let (lo, hi) = patch.bounds();
            assert!(lo.cmple(hi).all());
            for p in patch.points() {
                assert!(lo.cmple(*p).all() && p.cmple(hi).all());
            }
            for _ in 0..20 {
                let x = patch.eval(random_bary(&mut rng));
                let eps = DVec3::splat(1e-12);
                assert!(
                    (lo - eps).cmple(x).all() && x.cmple(hi + eps).all(),
                    "{x} outside"
                );
            }
        }
        let flat =
            TriangularPatch::from_fn(2, |i, j, _| DVec2::new(i as f64, -(j as f64))).unwrap();
        assert_eq!(flat.bounds(), (DVec2::new(0.0, -2.0), DVec2::new(2.0, 0.0)));
    }

    #[test]
    fn triangular_scalar_and_dvec4_points() {
        // The generic code serves every control point type.
        let mut rng = Rng::new(711);
        let scalar = TriangularPatch::from_fn(4, |_, _, _| rng.range(-1.0, 1.0)).unwrap();
        let quad =
            TriangularPatch::from_fn(3, |i, j, k| DVec4::new(i as f64, j as f64, k as f64, 1.0))
                .unwrap();
        for _ in 0..20 {
            let b = random_bary(&mut rng);
            assert!((scalar.eval(b) - scalar.eval_de_casteljau(b)).abs() < 1e-13);
            assert!((quad.eval(b) - (b * 3.0).extend(1.0)).abs().max_element() < 1e-12);
        }
        let (lo, hi) = quad.bounds();
        assert_eq!(lo, DVec4::new(0.0, 0.0, 0.0, 1.0));
        assert_eq!(hi, DVec4::new(3.0, 3.0, 3.0, 1.0));
    }
}
