//! Tensor-product Bézier patches `S(u, v) = Σ_i Σ_j P_ij B_i^n(u) B_j^m(v)` and volumes
//! `S(u, v, w) = Σ_i Σ_j Σ_k P_ijk B_i^n(u) B_j^m(v) B_k^l(w)`.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use core::ops::{Add, Mul, Sub};

use glam::{DVec2, DVec3, DVec4};

use crate::bernstein::{MAX_DEGREE, basis, basis_and_derivative_into, basis_array};

/// What a control point must do: be added, scaled by `f64`, and copied. Implemented for `f64` and the
/// glam `f64` vectors, so one patch type serves scalar fields, `(x, y, ξ)` points and `(x, y, z, ξ)`.
pub trait ControlPoint:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self> + PartialEq + fmt::Debug
{
    /// The additive identity.
    const ZERO: Self;
    /// The componentwise minimum.
    #[must_use]
    fn min_components(self, other: Self) -> Self;
    /// The componentwise maximum.
    #[must_use]
    fn max_components(self, other: Self) -> Self;
}

impl ControlPoint for f64 {
    const ZERO: Self = 0.0;
    fn min_components(self, other: Self) -> Self {
        self.min(other)
    }
    fn max_components(self, other: Self) -> Self {
        self.max(other)
    }
}

macro_rules! glam_control_point {
    ($($t:ty),*) => {$(
        impl ControlPoint for $t {
            const ZERO: Self = <$t>::ZERO;
            fn min_components(self, other: Self) -> Self {
                self.min(other)
            }
            fn max_components(self, other: Self) -> Self {
                self.max(other)
            }
        }
    )*};
}
glam_control_point!(DVec2, DVec3, DVec4);

/// One of the parameters of a patch (`U`, `V`) or a volume (`U`, `V`, `W`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The first parameter, `u` (index `i`).
    U,
    /// The second parameter, `v` (index `j`).
    V,
    /// The third parameter, `w` (index `k`); volumes only.
    W,
}

/// The two axes other than `axis` (0, 1 or 2), in increasing order.
pub(crate) const fn other_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

impl Axis {
    pub(crate) fn index(self) -> usize {
        match self {
            Self::U => 0,
            Self::V => 1,
            Self::W => 2,
        }
    }
}

/// The componentwise box `(min, max)` of a set of points; `(ZERO, ZERO)` for none.
pub(crate) fn bounds_of<P: ControlPoint>(points: &[P]) -> (P, P) {
    let first = points.first().copied().unwrap_or(P::ZERO);
    points.iter().fold((first, first), |(lo, hi), &p| {
        (lo.min_components(p), hi.max_components(p))
    })
}

/// Why a patch could not be built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PatchError {
    /// The parameter asked for does not exist (`W` of a patch).
    Axis {
        /// The parameter asked for.
        axis: Axis,
    },
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
            Self::Axis { axis } => write!(f, "a patch has no parameter {axis:?}"),
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

    /// `S(u, v)` with its partial derivatives `(S, ∂S/∂u, ∂S/∂v)`.
    #[must_use]
    pub fn eval_with_partials(&self, u: f64, v: f64) -> (P, P, P) {
        let (n, m) = self.degree;
        let [mut bu, mut du, mut bv, mut dv] = [[0.0; MAX_DEGREE + 1]; 4];
        basis_and_derivative_into(n, u, &mut bu, &mut du);
        basis_and_derivative_into(m, v, &mut bv, &mut dv);
        let (mut s, mut su, mut sv) = (P::ZERO, P::ZERO, P::ZERO);
        for (i, row) in self.points.chunks_exact(m + 1).enumerate() {
            let (mut r, mut rv) = (P::ZERO, P::ZERO);
            for (j, p) in row.iter().enumerate() {
                r = r + *p * bv[j];
                rv = rv + *p * dv[j];
            }
            s = s + r * bu[i];
            su = su + r * du[i];
            sv = sv + rv * bu[i];
        }
        (s, su, sv)
    }

    /// de Casteljau split along `axis` at `t`: the halves over `[0, t]` and `[t, 1]` of that parameter,
    /// each of the same degree, reproducing the patch on their parts.
    ///
    /// # Errors
    ///
    /// [`PatchError::Axis`] for [`Axis::W`].
    pub fn split(&self, axis: Axis, t: f64) -> Result<(Self, Self), PatchError> {
        let a = self.axis(axis)?;
        let dims = [self.degree.0 + 1, self.degree.1 + 1];
        let (left, right) = split_net(&self.points, &dims, a, t);
        Ok((
            Self {
                degree: self.degree,
                points: left,
            },
            Self {
                degree: self.degree,
                points: right,
            },
        ))
    }

    /// Degree elevation by one along `axis`: the same patch with one more row of control points.
    ///
    /// # Errors
    ///
    /// [`PatchError::Axis`] for [`Axis::W`]; [`PatchError::Degree`] when that degree is already
    /// [`MAX_DEGREE`].
    pub fn elevate(&self, axis: Axis) -> Result<Self, PatchError> {
        let a = self.axis(axis)?;
        let mut degrees = [self.degree.0, self.degree.1];
        let points = elevate_net(&self.points, &degrees, a)?;
        degrees[a] += 1;
        Ok(Self {
            degree: (degrees[0], degrees[1]),
            points,
        })
    }

    /// The componentwise box of the control points, which holds the whole patch over `[0, 1]²`
    /// (convex hull property).
    #[must_use]
    pub fn bounds(&self) -> (P, P) {
        bounds_of(&self.points)
    }

    fn axis(&self, axis: Axis) -> Result<usize, PatchError> {
        match axis {
            Axis::W => Err(PatchError::Axis { axis }),
            _ => Ok(axis.index()),
        }
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
        self.points[self.index(i, j, k)]
    }

    /// Mutable access to `P_ijk`.
    ///
    /// # Panics
    ///
    /// If an index is above its degree.
    pub fn point_mut(&mut self, i: usize, j: usize, k: usize) -> &mut P {
        let at = self.index(i, j, k);
        &mut self.points[at]
    }

    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        let (n, m, l) = self.degree;
        assert!(
            i <= n && j <= m && k <= l,
            "P_{i}{j}{k} outside degree {:?}",
            self.degree
        );
        (i * (m + 1) + j) * (l + 1) + k
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

    /// `S(u, v, w)` with its gradient `[∂S/∂u, ∂S/∂v, ∂S/∂w]`.
    #[must_use]
    pub fn eval_with_gradient(&self, u: f64, v: f64, w: f64) -> (P, [P; 3]) {
        let (n, m, l) = self.degree;
        let [mut bu, mut du, mut bv, mut dv, mut bw, mut dw] = [[0.0; MAX_DEGREE + 1]; 6];
        basis_and_derivative_into(n, u, &mut bu, &mut du);
        basis_and_derivative_into(m, v, &mut bv, &mut dv);
        basis_and_derivative_into(l, w, &mut bw, &mut dw);
        let (mut s, mut su, mut sv, mut sw) = (P::ZERO, P::ZERO, P::ZERO, P::ZERO);
        for (i, slab) in self.points.chunks_exact((m + 1) * (l + 1)).enumerate() {
            let (mut t, mut tv, mut tw) = (P::ZERO, P::ZERO, P::ZERO);
            for (j, row) in slab.chunks_exact(l + 1).enumerate() {
                let (mut r, mut rw) = (P::ZERO, P::ZERO);
                for (k, p) in row.iter().enumerate() {
                    r = r + *p * bw[k];
                    rw = rw + *p * dw[k];
                }
                t = t + r * bv[j];
                tv = tv + r * dv[j];
                tw = tw + rw * bv[j];
            }
            s = s + t * bu[i];
            su = su + t * du[i];
            sv = sv + tv * bu[i];
            sw = sw + tw * bu[i];
        }
        (s, [su, sv, sw])
    }

    /// de Casteljau split along `axis` at `t`: the halves over `[0, t]` and `[t, 1]` of that parameter.
    #[must_use]
    pub fn split(&self, axis: Axis, t: f64) -> (Self, Self) {
        let (n, m, l) = self.degree;
        let (left, right) = split_net(&self.points, &[n + 1, m + 1, l + 1], axis.index(), t);
        (
            Self {
                degree: self.degree,
                points: left,
            },
            Self {
                degree: self.degree,
                points: right,
            },
        )
    }

    /// Degree elevation by one along `axis`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when that degree is already [`MAX_DEGREE`].
    pub fn elevate(&self, axis: Axis) -> Result<Self, PatchError> {
        let mut degrees = [self.degree.0, self.degree.1, self.degree.2];
        let points = elevate_net(&self.points, &degrees, axis.index())?;
        degrees[axis.index()] += 1;
        Ok(Self {
            degree: (degrees[0], degrees[1], degrees[2]),
            points,
        })
    }

    /// The componentwise box of the control points, which holds the whole volume over `[0, 1]³`.
    #[must_use]
    pub fn bounds(&self) -> (P, P) {
        bounds_of(&self.points)
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

/// Applies `f` to every line of a net along `axis` (`dims` are the point counts per axis, the last
/// fastest), where `f` maps a line of `dims[axis]` points to one of `out_len`; returns the new net.
fn map_lines<P: ControlPoint>(
    points: &[P],
    dims: &[usize],
    axis: usize,
    out_len: usize,
    mut f: impl FnMut(&[P], &mut [P]),
) -> Vec<P> {
    let inner: usize = dims[axis + 1..].iter().product();
    let outer: usize = dims[..axis].iter().product();
    let len = dims[axis];
    let mut out = vec![P::ZERO; outer * out_len * inner];
    let mut line = [P::ZERO; MAX_DEGREE + 2];
    let mut mapped = [P::ZERO; MAX_DEGREE + 2];
    for o in 0..outer {
        for c in 0..inner {
            for (a, slot) in line[..len].iter_mut().enumerate() {
                *slot = points[(o * len + a) * inner + c];
            }
            f(&line[..len], &mut mapped[..out_len]);
            for (a, &p) in mapped[..out_len].iter().enumerate() {
                out[(o * out_len + a) * inner + c] = p;
            }
        }
    }
    out
}

/// The two halves of a net split at `t` along `axis`.
fn split_net<P: ControlPoint>(
    points: &[P],
    dims: &[usize],
    axis: usize,
    t: f64,
) -> (Vec<P>, Vec<P>) {
    let len = dims[axis];
    let half = |left: bool| {
        map_lines(points, dims, axis, len, |line, out| {
            // The triangle of de Casteljau: its left edge is the left half, its right edge the right.
            let mut tri = [P::ZERO; MAX_DEGREE + 2];
            tri[..len].copy_from_slice(line);
            for k in 0..len {
                if left {
                    out[k] = tri[0];
                } else {
                    out[len - 1 - k] = tri[len - 1 - k];
                }
                for i in 0..len - 1 - k {
                    tri[i] = tri[i] * (1.0 - t) + tri[i + 1] * t;
                }
            }
        })
    };
    (half(true), half(false))
}

/// A net elevated by one degree along `axis`: `Q_i = (i/(n+1))·P_(i−1) + (1 − i/(n+1))·P_i`.
fn elevate_net<P: ControlPoint>(
    points: &[P],
    degrees: &[usize],
    axis: usize,
) -> Result<Vec<P>, PatchError> {
    let n = degrees[axis];
    if n >= MAX_DEGREE {
        return Err(PatchError::Degree { degree: n + 1 });
    }
    let dims: Vec<usize> = degrees.iter().map(|d| d + 1).collect();
    Ok(map_lines(points, &dims, axis, n + 2, |line, out| {
        out[0] = line[0];
        out[n + 1] = line[n];
        for i in 1..=n {
            let a = i as f64 / (n + 1) as f64;
            out[i] = line[i - 1] * a + line[i] * (1.0 - a);
        }
    }))
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

    fn close3(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol * (1.0 + a.abs().max_element())
    }

    fn close4(a: DVec4, b: DVec4, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol * (1.0 + a.abs().max_element())
    }

    #[test]
    fn patch_partials_match_finite_differences() {
        let mut rng = Rng::new(21);
        let h = 1e-6;
        for _ in 0..60 {
            let patch = random_patch(&mut rng, 8);
            let (u, v) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (s, su, sv) = patch.eval_with_partials(u, v);
            assert!(close3(s, patch.eval(u, v), 1e-12));
            let fu = (patch.eval(u + h, v) - patch.eval(u - h, v)) / (2.0 * h);
            let fv = (patch.eval(u, v + h) - patch.eval(u, v - h)) / (2.0 * h);
            assert!(close3(su, fu, 1e-5), "{su} vs {fu}");
            assert!(close3(sv, fv, 1e-5), "{sv} vs {fv}");
        }
    }

    #[test]
    fn volume_gradient_matches_finite_differences() {
        let mut rng = Rng::new(22);
        let h = 1e-6;
        for _ in 0..40 {
            let vol = random_volume(&mut rng, 6);
            let p = [
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            ];
            let (s, grad) = vol.eval_with_gradient(p[0], p[1], p[2]);
            assert!(close4(s, vol.eval(p[0], p[1], p[2]), 1e-12));
            for (axis, g) in grad.iter().enumerate() {
                let (mut up, mut down) = (p, p);
                up[axis] += h;
                down[axis] -= h;
                let fd = (vol.eval(up[0], up[1], up[2]) - vol.eval(down[0], down[1], down[2]))
                    / (2.0 * h);
                assert!(close4(*g, fd, 1e-5), "axis {axis}: {g} vs {fd}");
            }
        }
    }

    #[test]
    fn patch_split_halves_reproduce_the_patch() {
        let mut rng = Rng::new(23);
        for _ in 0..40 {
            let patch = random_patch(&mut rng, 8);
            let t = rng.range(0.05, 0.95);
            for axis in [Axis::U, Axis::V] {
                let (left, right) = patch.split(axis, t).unwrap();
                for _ in 0..10 {
                    let (a, b) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
                    // (a, b) in a half is (t·a, b) or (t + (1 − t)·a, b) in the whole, along `axis`.
                    let whole = |x: f64| match axis {
                        Axis::U => patch.eval(x, b),
                        _ => patch.eval(b, x),
                    };
                    let (l, r) = match axis {
                        Axis::U => (left.eval(a, b), right.eval(a, b)),
                        _ => (left.eval(b, a), right.eval(b, a)),
                    };
                    assert!(close3(l, whole(t * a), 1e-10));
                    assert!(close3(r, whole(t + (1.0 - t) * a), 1e-10));
                }
            }
        }
        assert_eq!(
            random_patch(&mut rng, 3).split(Axis::W, 0.5),
            Err(PatchError::Axis { axis: Axis::W })
        );
    }

    #[test]
    fn volume_split_halves_reproduce_the_volume() {
        let mut rng = Rng::new(24);
        for _ in 0..20 {
            let vol = random_volume(&mut rng, 5);
            let t = rng.range(0.05, 0.95);
            for (axis, ix) in [(Axis::U, 0), (Axis::V, 1), (Axis::W, 2)] {
                let (left, right) = vol.split(axis, t);
                for _ in 0..5 {
                    let p = [
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                    ];
                    let (mut pl, mut pr) = (p, p);
                    pl[ix] = t * p[ix];
                    pr[ix] = t + (1.0 - t) * p[ix];
                    let at = |v: &Volume<DVec4>, q: [f64; 3]| v.eval(q[0], q[1], q[2]);
                    assert!(close4(at(&left, p), at(&vol, pl), 1e-10));
                    assert!(close4(at(&right, p), at(&vol, pr), 1e-10));
                }
            }
        }
    }

    #[test]
    fn elevation_preserves_every_point() {
        let mut rng = Rng::new(25);
        for _ in 0..40 {
            let patch = random_patch(&mut rng, 8);
            let vol = random_volume(&mut rng, 5);
            for axis in [Axis::U, Axis::V] {
                let up = patch.elevate(axis).unwrap();
                let (n, m) = patch.degree();
                let expect = if axis == Axis::U {
                    (n + 1, m)
                } else {
                    (n, m + 1)
                };
                assert_eq!(up.degree(), expect);
                for _ in 0..10 {
                    let (u, v) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                    assert!(close3(up.eval(u, v), patch.eval(u, v), 1e-10));
                }
            }
            for axis in [Axis::U, Axis::V, Axis::W] {
                let up = vol.elevate(axis).unwrap();
                for _ in 0..5 {
                    let p = [
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                    ];
                    assert!(close4(
                        up.eval(p[0], p[1], p[2]),
                        vol.eval(p[0], p[1], p[2]),
                        1e-10
                    ));
                }
            }
        }
        let top = Patch::from_fn((MAX_DEGREE, 1), |_, _| 0.0).unwrap();
        assert_eq!(
            top.elevate(Axis::U),
            Err(PatchError::Degree {
                degree: MAX_DEGREE + 1
            })
        );
        assert!(top.elevate(Axis::V).is_ok());
    }

    #[test]
    fn bounds_hold_the_patch_and_the_volume() {
        let mut rng = Rng::new(26);
        for _ in 0..30 {
            let patch = random_patch(&mut rng, 8);
            let vol = random_volume(&mut rng, 5);
            let (lo, hi) = patch.bounds();
            let (vlo, vhi) = vol.bounds();
            for _ in 0..20 {
                let (u, v, w) = (
                    rng.range(0.0, 1.0),
                    rng.range(0.0, 1.0),
                    rng.range(0.0, 1.0),
                );
                let p = patch.eval(u, v);
                assert!(p.cmpge(lo - 1e-12).all() && p.cmple(hi + 1e-12).all());
                let q = vol.eval(u, v, w);
                assert!(q.cmpge(vlo - 1e-12).all() && q.cmple(vhi + 1e-12).all());
            }
            // The box is exactly the control points' extent, component by component.
            for axis in 0..3 {
                let coords = patch.points().iter().map(|p| p[axis]);
                let min = coords.clone().fold(f64::INFINITY, f64::min);
                let max = coords.fold(f64::NEG_INFINITY, f64::max);
                assert_eq!((lo[axis], hi[axis]), (min, max));
            }
        }
    }
}
