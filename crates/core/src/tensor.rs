//! Tensor-product Bézier patches `S(u, v) = Σ_i Σ_j P_ij B_i^n(u) B_j^m(v)` and volumes
//! `S(u, v, w) = Σ_i Σ_j Σ_k P_ijk B_i^n(u) B_j^m(v) B_k^l(w)`.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use core::ops::{Add, Mul, Sub};

use glam::{DVec2, DVec3, DVec4};

use crate::bernstein::{MAX_DEGREE, basis, basis_array};

/// What a control point must do: be added, scaled by `f64`, and copied. Implemented for `f64` and the
/// glam `f64` vectors, so one patch type serves scalar fields, `(x, y, ξ)` points and `(x, y, z, ξ)`.
pub trait ControlPoint:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self> + PartialEq + fmt::Debug
{
    /// The additive identity.
    const ZERO: Self;
}

impl ControlPoint for f64 {
    const ZERO: Self = 0.0;
}
impl ControlPoint for DVec2 {
    const ZERO: Self = DVec2::ZERO;
}
impl ControlPoint for DVec3 {
    const ZERO: Self = DVec3::ZERO;
}
impl ControlPoint for DVec4 {
    const ZERO: Self = DVec4::ZERO;
}

/// Why a patch could not be built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PatchError {
    /// A degree is 0 or above [`MAX_DEGREE`].
    Degree {
        /// The degree given.
        degree: usize,
    },
    /// The number of control points is not `(n + 1)(m + 1)`.
    PointCount {
        /// `(n + 1)(m + 1)`.
        expected: usize,
        /// The number given.
        got: usize,
    },
}

impl fmt::Display for PatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Degree { degree } => {
                write!(f, "degree {degree} is outside 1..={MAX_DEGREE}")
            }
            Self::PointCount { expected, got } => {
                write!(f, "expected {expected} control points, got {got}")
            }
        }
    }
}

impl core::error::Error for PatchError {}

/// A tensor-product Bézier patch of degree `(n, m)`, `1 ≤ n, m ≤ MAX_DEGREE`.
///
/// Control points are stored row by row: `P_ij` at index `i·(m + 1) + j` (`i` along `u`, `j` along
/// `v`), the order of the model file (DESIGN §5).
#[derive(Clone, Debug, PartialEq)]
pub struct Patch<P> {
    degree: (usize, usize),
    points: Vec<P>,
}

impl<P: ControlPoint> Patch<P> {
    /// A patch from its degree and `(n + 1)(m + 1)` control points.
    ///
    /// # Errors
    ///
    /// [`PatchError`] when a degree is out of range or the point count does not match.
    pub fn try_new(degree: (usize, usize), points: Vec<P>) -> Result<Self, PatchError> {
        check_net(&[degree.0, degree.1], points.len())?;
        Ok(Self { degree, points })
    }

    /// A patch whose control point `P_ij` is `point(i, j)`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when a degree is out of range.
    pub fn from_fn(
        degree: (usize, usize),
        mut point: impl FnMut(usize, usize) -> P,
    ) -> Result<Self, PatchError> {
        check_degrees(&[degree.0, degree.1])?;
        let mut points = Vec::with_capacity((degree.0 + 1) * (degree.1 + 1));
        for i in 0..=degree.0 {
            for j in 0..=degree.1 {
                points.push(point(i, j));
            }
        }
        Self::try_new(degree, points)
    }

    /// The degree `(n, m)`.
    #[must_use]
    pub fn degree(&self) -> (usize, usize) {
        self.degree
    }

    /// The control points, row by row (`P_ij` at `i·(m + 1) + j`).
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// `P_ij`.
    ///
    /// # Panics
    ///
    /// If `i > n` or `j > m`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> P {
        self.points[self.index(i, j)]
    }

    /// Mutable access to `P_ij`.
    ///
    /// # Panics
    ///
    /// If `i > n` or `j > m`.
    pub fn point_mut(&mut self, i: usize, j: usize) -> &mut P {
        let k = self.index(i, j);
        &mut self.points[k]
    }

    fn index(&self, i: usize, j: usize) -> usize {
        assert!(
            i <= self.degree.0 && j <= self.degree.1,
            "P_{i}{j} outside degree {:?}",
            self.degree
        );
        i * (self.degree.1 + 1) + j
    }

    /// `S(u, v)` in basis form: `Σ_i B_i^n(u) Σ_j P_ij B_j^m(v)`.
    #[must_use]
    pub fn eval(&self, u: f64, v: f64) -> P {
        let (n, m) = self.degree;
        let bu = basis_array(n, u);
        let bv = basis_array(m, v);
        let mut sum = P::ZERO;
        for (i, row) in self.points.chunks_exact(m + 1).enumerate() {
            let mut r = P::ZERO;
            for (p, &b) in row.iter().zip(&bv) {
                r = r + *p * b;
            }
            sum = sum + r * bu[i];
        }
        sum
    }

    /// `S(u, v)` by de Casteljau: repeated linear interpolation, first along `v` in every row, then
    /// along `u`. Slower than [`Patch::eval`]; the reference it is tested against.
    #[must_use]
    pub fn eval_de_casteljau(&self, u: f64, v: f64) -> P {
        let (n, m) = self.degree;
        let mut rows = [P::ZERO; MAX_DEGREE + 1];
        let mut tmp = [P::ZERO; MAX_DEGREE + 1];
        for (i, row) in self.points.chunks_exact(m + 1).enumerate() {
            tmp[..=m].copy_from_slice(row);
            rows[i] = de_casteljau(&mut tmp[..=m], v);
        }
        de_casteljau(&mut rows[..=n], u)
    }

    /// `S` at every `(us[a], vs[b])`, returned row-major by `b` (index `b·us.len() + a`, so rows run
    /// along `u`, which is `x` in the view).
    ///
    /// Axis at a time: the control net is first contracted along `v` for every `vs[b]` (giving `n + 1`
    /// points per `b`), then along `u`: `O((m + 1)(n + 1)·|vs| + (n + 1)·|us|·|vs|)` instead of
    /// `(n + 1)(m + 1)` multiply-adds per grid point.
    #[must_use]
    pub fn eval_grid(&self, us: &[f64], vs: &[f64]) -> Vec<P> {
        let (n, m) = self.degree;
        // Basis values along u, one row of n + 1 per us[a].
        let mut bu = vec![0.0; us.len() * (n + 1)];
        for (a, &u) in us.iter().enumerate() {
            basis(n, u, &mut bu[a * (n + 1)..(a + 1) * (n + 1)]);
        }
        let mut out = Vec::with_capacity(us.len() * vs.len());
        let mut bv = [0.0; MAX_DEGREE + 1];
        let mut column = [P::ZERO; MAX_DEGREE + 1];
        for &v in vs {
            basis(m, v, &mut bv);
            for (i, row) in self.points.chunks_exact(m + 1).enumerate() {
                let mut r = P::ZERO;
                for (p, &b) in row.iter().zip(&bv) {
                    r = r + *p * b;
                }
                column[i] = r;
            }
            for weights in bu.chunks_exact(n + 1) {
                let mut s = P::ZERO;
                for (c, &w) in column.iter().zip(weights) {
                    s = s + *c * w;
                }
                out.push(s);
            }
        }
        out
    }
}

/// A tensor-product Bézier volume of degree `(n, m, l)`, each from 1 to [`MAX_DEGREE`].
///
/// Control points are stored with `k` fastest: `P_ijk` at `(i·(m + 1) + j)·(l + 1) + k`, the order of
/// the model file (DESIGN §5).
#[derive(Clone, Debug, PartialEq)]
pub struct Volume<P> {
    degree: (usize, usize, usize),
    points: Vec<P>,
}

impl<P: ControlPoint> Volume<P> {
    /// A volume from its degree and `(n + 1)(m + 1)(l + 1)` control points.
    ///
    /// # Errors
    ///
    /// [`PatchError`] when a degree is out of range or the point count does not match.
    pub fn try_new(degree: (usize, usize, usize), points: Vec<P>) -> Result<Self, PatchError> {
        check_net(&[degree.0, degree.1, degree.2], points.len())?;
        Ok(Self { degree, points })
    }

    /// A volume whose control point `P_ijk` is `point(i, j, k)`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when a degree is out of range.
    pub fn from_fn(
        degree: (usize, usize, usize),
        mut point: impl FnMut(usize, usize, usize) -> P,
    ) -> Result<Self, PatchError> {
        check_degrees(&[degree.0, degree.1, degree.2])?;
        let mut points = Vec::with_capacity((degree.0 + 1) * (degree.1 + 1) * (degree.2 + 1));
        for i in 0..=degree.0 {
            for j in 0..=degree.1 {
                for k in 0..=degree.2 {
                    points.push(point(i, j, k));
                }
            }
        }
        Self::try_new(degree, points)
    }

    /// The degree `(n, m, l)`.
    #[must_use]
    pub fn degree(&self) -> (usize, usize, usize) {
        self.degree
    }

    /// The control points (`P_ijk` at `(i·(m + 1) + j)·(l + 1) + k`).
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// `P_ijk`.
    ///
    /// # Panics
    ///
    /// If an index is above its degree.
    #[must_use]
    pub fn point(&self, i: usize, j: usize, k: usize) -> P {
        let (n, m, l) = self.degree;
        assert!(
            i <= n && j <= m && k <= l,
            "P_{i}{j}{k} outside degree {:?}",
            self.degree
        );
        self.points[(i * (m + 1) + j) * (l + 1) + k]
    }

    /// `S(u, v, w)` in basis form, contracting `w`, then `v`, then `u`.
    #[must_use]
    pub fn eval(&self, u: f64, v: f64, w: f64) -> P {
        let (n, m, l) = self.degree;
        let bu = basis_array(n, u);
        let bv = basis_array(m, v);
        let bw = basis_array(l, w);
        let mut sum = P::ZERO;
        for (i, slab) in self.points.chunks_exact((m + 1) * (l + 1)).enumerate() {
            let mut s = P::ZERO;
            for (j, row) in slab.chunks_exact(l + 1).enumerate() {
                let mut r = P::ZERO;
                for (p, &b) in row.iter().zip(&bw) {
                    r = r + *p * b;
                }
                s = s + r * bv[j];
            }
            sum = sum + s * bu[i];
        }
        sum
    }

    /// `S` at every `(us[a], vs[b], ws[c])`, returned with `a` fastest (index
    /// `(c·|vs| + b)·|us| + a`), one axis at a time: the net is contracted along `w` for each `ws[c]`,
    /// then along `v`, then along `u`, so a grid point costs about `n + 1` multiply-adds plus shares
    /// of the earlier contractions, not `(n + 1)(m + 1)(l + 1)`.
    #[must_use]
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], ws: &[f64]) -> Vec<P> {
        let (n, m, l) = self.degree;
        let table = |deg: usize, ts: &[f64]| {
            let mut out = vec![0.0; ts.len() * (deg + 1)];
            for (a, &t) in ts.iter().enumerate() {
                basis(deg, t, &mut out[a * (deg + 1)..(a + 1) * (deg + 1)]);
            }
            out
        };
        let (bu, bv, bw) = (table(n, us), table(m, vs), table(l, ws));
        let mut out = Vec::with_capacity(us.len() * vs.len() * ws.len());
        let mut plane = vec![P::ZERO; (n + 1) * (m + 1)];
        let mut column = [P::ZERO; MAX_DEGREE + 1];
        for wc in bw.chunks_exact(l + 1) {
            for (slot, row) in plane.iter_mut().zip(self.points.chunks_exact(l + 1)) {
                *slot = row
                    .iter()
                    .zip(wc)
                    .fold(P::ZERO, |acc, (p, &b)| acc + *p * b);
            }
            for vc in bv.chunks_exact(m + 1) {
                for (i, row) in plane.chunks_exact(m + 1).enumerate() {
                    column[i] = row
                        .iter()
                        .zip(vc)
                        .fold(P::ZERO, |acc, (p, &b)| acc + *p * b);
                }
                for uc in bu.chunks_exact(n + 1) {
                    out.push(
                        column
                            .iter()
                            .zip(uc)
                            .fold(P::ZERO, |acc, (p, &b)| acc + *p * b),
                    );
                }
            }
        }
        out
    }
}

/// Every degree in `1..=MAX_DEGREE`; checked before anything is sized by the degrees.
fn check_degrees(degrees: &[usize]) -> Result<(), PatchError> {
    match degrees.iter().find(|&&d| d == 0 || d > MAX_DEGREE) {
        Some(&degree) => Err(PatchError::Degree { degree }),
        None => Ok(()),
    }
}

/// Valid degrees and `Π (d + 1)` control points, for a net of any dimension.
fn check_net(degrees: &[usize], got: usize) -> Result<(), PatchError> {
    check_degrees(degrees)?;
    let expected = degrees.iter().map(|d| d + 1).product();
    if got != expected {
        return Err(PatchError::PointCount { expected, got });
    }
    Ok(())
}

/// de Casteljau's algorithm on a scratch slice of control points (overwritten).
fn de_casteljau<P: ControlPoint>(pts: &mut [P], t: f64) -> P {
    let n = pts.len();
    for k in 1..n {
        for i in 0..n - k {
            pts[i] = pts[i] * (1.0 - t) + pts[i + 1] * t;
        }
    }
    pts[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bernstein::bernstein;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn random_patch(rng: &mut Rng, max_degree: usize) -> Patch<DVec3> {
        let degree = (rng.int(1, max_degree), rng.int(1, max_degree));
        Patch::from_fn(degree, |_, _| {
            DVec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            )
        })
        .unwrap()
    }

    /// The definition, written out: `Σ_i Σ_j P_ij C(n,i) uⁱ(1−u)ⁿ⁻ⁱ C(m,j) vʲ(1−v)ᵐ⁻ʲ`.
    fn direct(patch: &Patch<DVec3>, u: f64, v: f64) -> DVec3 {
        let (n, m) = patch.degree();
        let mut s = DVec3::ZERO;
        for i in 0..=n {
            for j in 0..=m {
                s += patch.point(i, j) * bernstein(n, i, u) * bernstein(m, j, v);
            }
        }
        s
    }

    #[test]
    fn patch_eval_equals_direct_formula() {
        let mut rng = Rng::new(10);
        for _ in 0..200 {
            let patch = random_patch(&mut rng, MAX_DEGREE);
            let (u, v) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let a = patch.eval(u, v);
            let b = direct(&patch, u, v);
            assert!((a - b).abs().max_element() < 1e-11, "{a} vs {b}");
        }
    }

    #[test]
    fn patch_basis_form_equals_de_casteljau() {
        let mut rng = Rng::new(11);
        for _ in 0..200 {
            let patch = random_patch(&mut rng, MAX_DEGREE);
            let (u, v) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
            let a = patch.eval(u, v);
            let b = patch.eval_de_casteljau(u, v);
            assert!((a - b).abs().max_element() < 1e-10, "{a} vs {b}");
        }
    }

    #[test]
    fn patch_interpolates_corners() {
        let mut rng = Rng::new(12);
        let patch = random_patch(&mut rng, 6);
        let (n, m) = patch.degree();
        assert_eq!(patch.eval(0.0, 0.0), patch.point(0, 0));
        assert!(
            (patch.eval(1.0, 1.0) - patch.point(n, m))
                .abs()
                .max_element()
                < 1e-14
        );
        assert!(
            (patch.eval(1.0, 0.0) - patch.point(n, 0))
                .abs()
                .max_element()
                < 1e-14
        );
    }

    #[test]
    fn patch_grid_equals_pointwise() {
        let mut rng = Rng::new(13);
        for _ in 0..20 {
            let patch = random_patch(&mut rng, 8);
            let us: Vec<f64> = (0..7).map(|_| rng.range(-0.1, 1.1)).collect();
            let vs: Vec<f64> = (0..5).map(|_| rng.range(-0.1, 1.1)).collect();
            let grid = patch.eval_grid(&us, &vs);
            for (b, &v) in vs.iter().enumerate() {
                for (a, &u) in us.iter().enumerate() {
                    let d = grid[b * us.len() + a] - patch.eval(u, v);
                    assert!(d.abs().max_element() < 1e-12);
                }
            }
        }
    }

    fn random_volume(rng: &mut Rng, max_degree: usize) -> Volume<DVec4> {
        let degree = (
            rng.int(1, max_degree),
            rng.int(1, max_degree),
            rng.int(1, max_degree),
        );
        Volume::from_fn(degree, |_, _, _| {
            DVec4::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            )
        })
        .unwrap()
    }

    #[test]
    fn volume_eval_equals_direct_formula() {
        let mut rng = Rng::new(14);
        for _ in 0..100 {
            let vol = random_volume(&mut rng, 8);
            let (n, m, l) = vol.degree();
            let (u, v, w) = (
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            );
            let mut direct = DVec4::ZERO;
            for i in 0..=n {
                for j in 0..=m {
                    for k in 0..=l {
                        direct += vol.point(i, j, k)
                            * bernstein(n, i, u)
                            * bernstein(m, j, v)
                            * bernstein(l, k, w);
                    }
                }
            }
            assert!((vol.eval(u, v, w) - direct).abs().max_element() < 1e-11);
        }
    }

    #[test]
    fn volume_grid_equals_pointwise() {
        let mut rng = Rng::new(15);
        for _ in 0..10 {
            let vol = random_volume(&mut rng, 6);
            let us: Vec<f64> = (0..4).map(|_| rng.range(-0.1, 1.1)).collect();
            let vs: Vec<f64> = (0..3).map(|_| rng.range(-0.1, 1.1)).collect();
            let ws: Vec<f64> = (0..5).map(|_| rng.range(-0.1, 1.1)).collect();
            let grid = vol.eval_grid(&us, &vs, &ws);
            for (c, &w) in ws.iter().enumerate() {
                for (b, &v) in vs.iter().enumerate() {
                    for (a, &u) in us.iter().enumerate() {
                        let d = grid[(c * vs.len() + b) * us.len() + a] - vol.eval(u, v, w);
                        assert!(d.abs().max_element() < 1e-12);
                    }
                }
            }
        }
    }

    #[test]
    fn volume_rejects_bad_input() {
        assert_eq!(
            Volume::try_new((1, 1, 1), alloc::vec![0.0; 7]),
            Err(PatchError::PointCount {
                expected: 8,
                got: 7
            })
        );
        assert_eq!(
            Volume::<f64>::from_fn((1, 1, 17), |_, _, _| 0.0),
            Err(PatchError::Degree { degree: 17 })
        );
    }

    #[test]
    fn patch_rejects_bad_input() {
        assert_eq!(
            Patch::try_new((2, 2), alloc::vec![0.0; 8]),
            Err(PatchError::PointCount {
                expected: 9,
                got: 8
            })
        );
        assert_eq!(
            Patch::try_new((0, 2), alloc::vec![0.0; 3]),
            Err(PatchError::Degree { degree: 0 })
        );
        assert_eq!(
            Patch::<f64>::from_fn((17, 1), |_, _| 0.0),
            Err(PatchError::Degree { degree: 17 })
        );
        assert_eq!(
            Patch::<f64>::from_fn((usize::MAX, 1), |_, _| 0.0),
            Err(PatchError::Degree { degree: usize::MAX })
        );
    }
}
