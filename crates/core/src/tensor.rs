//! Tensor-product Bézier nets of any dimension `D`: `S(t) = Σ_I P_I B_I(t)` with
//! `B_I(t) = Π_a B_{i_a}^{n_a}(t_a)`: patches `S(u, v)` (`D = 2`), volumes `S(u, v, w)` (`D = 3`).
//!
//! One type, [`Tensor`], serves every dimension; [`Patch`] and [`Volume`] name its two common ones.
//! Every operation contracts or maps the net one axis at a time, the last axis fastest in storage
//! (the model file's order, DESIGN §5).

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use core::ops::{Add, Index, IndexMut, Mul, Sub};

use glam::{DVec2, DVec3, DVec4};

use crate::bernstein::{MAX_DEGREE, basis, basis_and_derivative_into};

/// What a control point must do: be added, scaled by `f64`, and copied. Implemented for `f64` and the
/// glam `f64` vectors, so one net type serves scalar fields, `(x, y, ξ)` points and `(x, y, z, ξ)`.
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

    /// Appends `Σ_i coeffs[i] · rows[i · stride + k]` for every `k < count` to `out`, each summed
    /// from zero in the order of `i`: a line of a net weighed against the basis rows of `count`
    /// samples stored transposed (one row per coefficient, `stride` values apart). What
    /// [`Tensor::eval_grid`] spends its time in; `f64` sums neighbouring samples in SIMD lanes, to
    /// the same bits.
    ///
    /// # Panics
    /// Where `rows` holds fewer than `(coeffs.len() − 1) · stride + count` values.
    fn weigh(coeffs: &[Self], rows: &[f64], stride: usize, count: usize, out: &mut Vec<Self>) {
        out.extend((0..count).map(|k| {
            coeffs
                .iter()
                .enumerate()
                .fold(Self::ZERO, |acc, (i, &c)| acc + c * rows[i * stride + k])
        }));
    }
}

impl ControlPoint for f64 {
    const ZERO: Self = 0.0;
    fn min_components(self, other: Self) -> Self {
        self.min(other)
    }
    fn max_components(self, other: Self) -> Self {
        self.max(other)
    }
    fn weigh(coeffs: &[Self], rows: &[f64], stride: usize, count: usize, out: &mut Vec<Self>) {
        crate::lanes::weigh(coeffs, rows, stride, count, out);
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

/// One of the parameters of a net: `U`, `V` of a patch, and `W` of a volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The first parameter, `u` (index `i`).
    U,
    /// The second parameter, `v` (index `j`).
    V,
    /// The third parameter, `w` (index `k`); volumes only.
    W,
}

impl Axis {
    /// The three axes in order.
    pub const ALL: [Self; 3] = [Self::U, Self::V, Self::W];

    /// The axis's number: 0 for `U`, 1 for `V`, 2 for `W` (the position of its index in `P_ijk`).
    #[must_use]
    pub const fn index(self) -> usize {
        match self {
            Self::U => 0,
            Self::V => 1,
            Self::W => 2,
        }
    }

    /// The axis of a number, `None` past 2.
    #[must_use]
    pub const fn from_index(index: usize) -> Option<Self> {
        match index {
            0 => Some(Self::U),
            1 => Some(Self::V),
            2 => Some(Self::W),
            _ => None,
        }
    }

    /// The two other axes of a volume, in increasing order: the parameters of a slice across this
    /// one.
    #[must_use]
    pub const fn others(self) -> (Self, Self) {
        match self {
            Self::U => (Self::V, Self::W),
            Self::V => (Self::U, Self::W),
            Self::W => (Self::U, Self::V),
        }
    }

    /// The volume index `[i, j, k]` of point `[p, q]` of the slice with `index` along this axis
    /// (`p`, `q` along the two [other](Axis::others) axes in order).
    #[must_use]
    pub const fn embed(self, index: usize, [p, q]: [usize; 2]) -> [usize; 3] {
        match self {
            Self::U => [index, p, q],
            Self::V => [p, index, q],
            Self::W => [p, q, index],
        }
    }
}

/// The two axes other than `axis` (0, 1 or 2), in increasing order.
pub(crate) const fn other_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The componentwise box `(min, max)` of a set of points; `(ZERO, ZERO)` for none.
pub(crate) fn bounds_of<P: ControlPoint>(points: &[P]) -> (P, P) {
    let first = points.first().copied().unwrap_or(P::ZERO);
    points.iter().fold((first, first), |(lo, hi), &p| {
        (lo.min_components(p), hi.max_components(p))
    })
}

/// The multi-index `[i, j, …]` of the `flat`-th point of a net with `dims` points per axis (the last
/// axis fastest).
pub(crate) fn multi_index<const D: usize>(dims: [usize; D], mut flat: usize) -> [usize; D] {
    let mut out = [0; D];
    for a in (0..D).rev() {
        out[a] = flat % dims[a];
        flat /= dims[a];
    }
    out
}

/// Why a net could not be built, split or elevated.
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
    /// The number of control points is not `Π (n_a + 1)`.
    PointCount {
        /// `Π (n_a + 1)`.
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

/// A tensor-product Bézier net over `D` parameters, of degree `n_a` along axis `a`,
/// `1 ≤ n_a ≤ MAX_DEGREE`.
///
/// Control points are stored with the last index fastest: `P_ij` of a patch at `i·(m + 1) + j`,
/// `P_ijk` of a volume at `(i·(m + 1) + j)·(l + 1) + k`, the order of the model file (DESIGN §5).
/// Indexing with `[i, j, …]` panics past the net, as a slice does; [`Tensor::get`] says `None`
/// instead, for indices that come from input.
#[derive(Clone, Debug, PartialEq)]
pub struct Tensor<P, const D: usize> {
    degree: [usize; D],
    points: Vec<P>,
}

/// A tensor-product Bézier patch `S(u, v) = Σ_i Σ_j P_ij B_i^n(u) B_j^m(v)`.
pub type Patch<P> = Tensor<P, 2>;

/// A tensor-product Bézier volume `S(u, v, w) = Σ_i Σ_j Σ_k P_ijk B_i^n(u) B_j^m(v) B_k^l(w)`.
pub type Volume<P> = Tensor<P, 3>;

impl<P: ControlPoint, const D: usize> Tensor<P, D> {
    /// A net from its degree and `Π (n_a + 1)` control points.
    ///
    /// # Errors
    ///
    /// [`PatchError`] when a degree is out of range or the point count does not match.
    pub fn try_new(degree: [usize; D], points: Vec<P>) -> Result<Self, PatchError> {
        check_net(&degree, points.len())?;
        Ok(Self { degree, points })
    }

    /// A net whose control point `P_I` is `point(I)`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when a degree is out of range.
    pub fn from_fn(
        degree: [usize; D],
        mut point: impl FnMut([usize; D]) -> P,
    ) -> Result<Self, PatchError> {
        check_degrees(&degree)?;
        let dims = degree.map(|d| d + 1);
        let count = dims.iter().product();
        let points = (0..count).map(|k| point(multi_index(dims, k))).collect();
        Self::try_new(degree, points)
    }

    /// The degree along each axis.
    #[must_use]
    pub fn degree(&self) -> [usize; D] {
        self.degree
    }

    /// The number of control points along each axis, `n_a + 1`.
    #[must_use]
    pub fn dims(&self) -> [usize; D] {
        self.degree.map(|d| d + 1)
    }

    /// The control points in storage order (the last index fastest).
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The position in [`Tensor::points`] of `P_I`, `None` past the net.
    #[must_use]
    pub fn flat_index(&self, index: [usize; D]) -> Option<usize> {
        let mut flat = 0;
        for (&i, &n) in index.iter().zip(&self.degree) {
            if i > n {
                return None;
            }
            flat = flat * (n + 1) + i;
        }
        Some(flat)
    }

    /// The multi-index of the `flat`-th control point, `None` past the net.
    #[must_use]
    pub fn multi_index(&self, flat: usize) -> Option<[usize; D]> {
        (flat < self.points.len()).then(|| multi_index(self.dims(), flat))
    }

    /// `P_I`, `None` past the net.
    #[must_use]
    pub fn get(&self, index: [usize; D]) -> Option<P> {
        self.flat_index(index).map(|k| self.points[k])
    }

    /// Mutable access to `P_I`, `None` past the net.
    pub fn get_mut(&mut self, index: [usize; D]) -> Option<&mut P> {
        self.flat_index(index).map(|k| &mut self.points[k])
    }

    /// The net of the same degree with every control point mapped by `f` (the ξ part of a solid's
    /// net, a projection, a change of coordinates).
    #[must_use]
    pub fn map<Q: ControlPoint>(&self, f: impl FnMut(P) -> Q) -> Tensor<Q, D> {
        Tensor {
            degree: self.degree,
            points: self.points.iter().copied().map(f).collect(),
        }
    }

    /// `S(t)` in basis form, contracting the last axis first.
    #[must_use]
    pub fn eval(&self, t: [f64; D]) -> P {
        let mut bases = [[0.0; MAX_DEGREE + 1]; D];
        for a in 0..D {
            basis(self.degree[a], t[a], &mut bases[a]);
        }
        contract(&self.points, &self.dims(), &bases)
    }

    /// `S(t)` by de Casteljau: repeated linear interpolation along the last axis in every line, then
    /// along the one before. Slower than [`Tensor::eval`]; the reference it is tested against.
    #[must_use]
    pub fn eval_de_casteljau(&self, t: [f64; D]) -> P {
        casteljau(&self.points, &self.dims(), &t)
    }

    /// `S` at every point of the grid `ts[0] × ts[1] × …`, the first axis fastest: a patch's grid
    /// point `(us[a], vs[b])` at `b·|us| + a` (rows run along `u`, which is `x` in the view), a
    /// volume's `(us[a], vs[b], ws[c])` at `(c·|vs| + b)·|us| + a`.
    ///
    /// One axis at a time: the net is contracted along the last axis for each of its samples, then
    /// along the one before, so a grid point costs about `n_0 + 1` multiply-adds plus shares of the
    /// earlier contractions, not `Π (n_a + 1)`.
    #[must_use]
    pub fn eval_grid(&self, ts: [&[f64]; D]) -> Vec<P> {
        let dims = self.dims();
        // The first axis's rows transposed, a row per basis function: its samples are summed side
        // by side (`ControlPoint::weigh`).
        let tables: [Vec<f64>; D] = core::array::from_fn(|a| {
            let n = self.degree[a];
            let mut table = vec![0.0; ts[a].len() * (n + 1)];
            for (row, &t) in table.chunks_exact_mut(n + 1).zip(ts[a]) {
                basis(n, t, row);
            }
            if a == 0 {
                crate::lanes::transpose(&table, n + 1)
            } else {
                table
            }
        });
        // One scratch net per contraction: after the last axis, after the last two, …
        let mut scratch: Vec<Vec<P>> = (1..D)
            .map(|k| vec![P::ZERO; dims[..D - k].iter().product()])
            .collect();
        let mut out = Vec::with_capacity(ts.iter().map(|t| t.len()).product());
        grid(&self.points, &dims, &tables, &mut scratch, &mut out);
        out
    }

    /// `S(t)` with its gradient `[∂S/∂t_0, ∂S/∂t_1, …]`.
    #[must_use]
    pub fn eval_with_gradient(&self, t: [f64; D]) -> (P, [P; D]) {
        // Patches and volumes, the hot path of every Newton step, have kernels whose sums stay in
        // registers; other dimensions contract slab by slab.
        let at = |a: usize| {
            (
                self.degree.get(a).copied().unwrap_or(0),
                t.get(a).copied().unwrap_or(0.0),
            )
        };
        match D {
            2 => {
                let ([n, m], [u, v]) = ([at(0).0, at(1).0], [at(0).1, at(1).1]);
                let (s, su, sv) = partials2(&self.points, [n, m], [u, v]);
                (s, core::array::from_fn(|a| if a == 0 { su } else { sv }))
            }
            3 => {
                let degree = [at(0).0, at(1).0, at(2).0];
                let (s, g) = partials3(&self.points, degree, [at(0).1, at(1).1, at(2).1]);
                (s, core::array::from_fn(|a| g[a % 3]))
            }
            _ => {
                let mut bases = [[0.0; MAX_DEGREE + 1]; D];
                let mut derivs = [[0.0; MAX_DEGREE + 1]; D];
                for a in 0..D {
                    basis_and_derivative_into(self.degree[a], t[a], &mut bases[a], &mut derivs[a]);
                }
                contract_with_gradient(&self.points, &self.dims(), &bases, &derivs)
            }
        }
    }

    /// de Casteljau split along `axis` at `t`: the halves over `[0, t]` and `[t, 1]` of that parameter,
    /// each of the same degree, reproducing the net on their parts.
    ///
    /// # Errors
    ///
    /// [`PatchError::Axis`] for an axis the net does not have ([`Axis::W`] of a patch).
    pub fn split(&self, axis: Axis, t: f64) -> Result<(Self, Self), PatchError> {
        let a = self.axis(axis)?;
        let (left, right) = split_net(&self.points, &self.dims(), a, t);
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

    /// Degree elevation by one along `axis`: the same map with one more layer of control points.
    ///
    /// # Errors
    ///
    /// [`PatchError::Axis`] for an axis the net does not have; [`PatchError::Degree`] when that
    /// degree is already [`MAX_DEGREE`].
    pub fn elevate(&self, axis: Axis) -> Result<Self, PatchError> {
        let a = self.axis(axis)?;
        let points = elevate_net(&self.points, &self.degree, a)?;
        let mut degree = self.degree;
        degree[a] += 1;
        Ok(Self { degree, points })
    }

    /// The componentwise box of the control points, which holds the whole net's image over the unit
    /// box of its parameters (convex hull property).
    #[must_use]
    pub fn bounds(&self) -> (P, P) {
        bounds_of(&self.points)
    }

    fn axis(&self, axis: Axis) -> Result<usize, PatchError> {
        let a = axis.index();
        if a < D {
            Ok(a)
        } else {
            Err(PatchError::Axis { axis })
        }
    }
}

impl<P: ControlPoint> Volume<P> {
    /// The control points whose index along `axis` is `index`, as a patch over the two other axes
    /// in increasing order (`P_index,j,k` as `Q_jk` across `U`); `None` past the net.
    #[must_use]
    pub fn slice(&self, axis: Axis, index: usize) -> Option<Patch<P>> {
        let a = axis.index();
        if index > self.degree[a] {
            return None;
        }
        let (p, q) = other_axes(a);
        let degree = [self.degree[p], self.degree[q]];
        Patch::from_fn(degree, |pq| self[axis.embed(index, pq)]).ok()
    }

    /// Writes `slice` into the control points whose index along `axis` is `index` (the inverse of
    /// [`Volume::slice`]).
    ///
    /// # Errors
    ///
    /// [`PatchError::Axis`] for a slice past the net, [`PatchError::PointCount`] when the slice's
    /// degree is not that of the two other axes; the volume is unchanged then.
    pub fn set_slice(
        &mut self,
        axis: Axis,
        index: usize,
        slice: &Patch<P>,
    ) -> Result<(), PatchError> {
        let a = axis.index();
        if index > self.degree[a] {
            return Err(PatchError::Axis { axis });
        }
        let (p, q) = other_axes(a);
        if slice.degree != [self.degree[p], self.degree[q]] {
            return Err(PatchError::PointCount {
                expected: (self.degree[p] + 1) * (self.degree[q] + 1),
                got: slice.points.len(),
            });
        }
        for (flat, &point) in slice.points.iter().enumerate() {
            self[axis.embed(index, multi_index(slice.dims(), flat))] = point;
        }
        Ok(())
    }
}

impl<P: ControlPoint, const D: usize> Index<[usize; D]> for Tensor<P, D> {
    type Output = P;

    /// `P_I`.
    ///
    /// # Panics
    ///
    /// If an index is above its degree (see [`Tensor::get`]).
    fn index(&self, index: [usize; D]) -> &P {
        match self.flat_index(index) {
            Some(k) => &self.points[k],
            None => panic!("P_{index:?} outside degree {:?}", self.degree),
        }
    }
}

impl<P: ControlPoint, const D: usize> IndexMut<[usize; D]> for Tensor<P, D> {
    fn index_mut(&mut self, index: [usize; D]) -> &mut P {
        match self.flat_index(index) {
            Some(k) => &mut self.points[k],
            None => panic!("P_{index:?} outside degree {:?}", self.degree),
        }
    }
}

/// A row of basis values, one per control point along an axis.
type Row = [f64; MAX_DEGREE + 1];

/// `Σ_i p_i b_i` over one line of a net.
#[inline(always)]
fn dot<P: ControlPoint>(line: &[P], b: &[f64]) -> P {
    line.iter()
        .zip(b)
        .fold(P::ZERO, |acc, (p, &w)| acc + *p * w)
}

/// `Σ_I P_I Π_a b_a[i_a]` over a net with `dims` points per axis and one basis row per axis,
/// contracting the last axis first. The last two axes are one loop; more recurse slab by slab.
#[inline(always)]
fn contract<P: ControlPoint>(points: &[P], dims: &[usize], bases: &[Row]) -> P {
    match (dims, bases) {
        ([_, m], [bu, bv]) => {
            let mut sum = P::ZERO;
            for (row, &w) in points.chunks_exact(*m).zip(bu) {
                sum = sum + dot(row, bv) * w;
            }
            sum
        }
        ([_, inner @ ..], [b, rest @ ..]) if !inner.is_empty() => {
            let slab = inner.iter().product();
            points
                .chunks_exact(slab)
                .zip(b)
                .fold(P::ZERO, |acc, (s, &w)| acc + contract(s, inner, rest) * w)
        }
        (_, [b, ..]) => dot(points, b),
        _ => points.first().copied().unwrap_or(P::ZERO),
    }
}

/// [`contract`] with the partial derivatives along each axis, from the basis rows `b` and their
/// derivatives `d`: `g[a]` is the derivative along this net's axis `a` (the rest are zero).
#[inline]
fn contract_with_gradient<P: ControlPoint, const D: usize>(
    points: &[P],
    dims: &[usize],
    b: &[Row],
    d: &[Row],
) -> (P, [P; D]) {
    let mut g = [P::ZERO; D];
    let mut s = P::ZERO;
    match (dims, b, d) {
        ([_], [b0, ..], [d0, ..]) => {
            for ((&p, &bk), &dk) in points.iter().zip(b0).zip(d0) {
                s = s + p * bk;
                g[0] = g[0] + p * dk;
            }
        }
        ([_, inner @ ..], _, _) => {
            let slab = inner.iter().product();
            for (i, chunk) in points.chunks_exact(slab).enumerate() {
                let (cs, cg) = contract_with_gradient::<P, D>(chunk, inner, &b[1..], &d[1..]);
                s = s + cs * b[0][i];
                g[0] = g[0] + cs * d[0][i];
                for a in 1..dims.len() {
                    g[a] = g[a] + cg[a - 1] * b[0][i];
                }
            }
        }
        _ => {}
    }
    (s, g)
}

/// A patch's value and partial derivatives at `(u, v)`.
#[inline(always)]
fn partials2<P: ControlPoint>(points: &[P], [n, m]: [usize; 2], [u, v]: [f64; 2]) -> (P, P, P) {
    let [mut bu, mut du, mut bv, mut dv] = [[0.0; MAX_DEGREE + 1]; 4];
    basis_and_derivative_into(n, u, &mut bu, &mut du);
    basis_and_derivative_into(m, v, &mut bv, &mut dv);
    let (mut s, mut su, mut sv) = (P::ZERO, P::ZERO, P::ZERO);
    for (i, row) in points.chunks_exact(m + 1).enumerate() {
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

/// A volume's value and gradient at `(u, v, w)`.
#[inline(always)]
fn partials3<P: ControlPoint>(
    points: &[P],
    [n, m, l]: [usize; 3],
    [u, v, w]: [f64; 3],
) -> (P, [P; 3]) {
    let [mut bu, mut du, mut bv, mut dv, mut bw, mut dw] = [[0.0; MAX_DEGREE + 1]; 6];
    basis_and_derivative_into(n, u, &mut bu, &mut du);
    basis_and_derivative_into(m, v, &mut bv, &mut dv);
    basis_and_derivative_into(l, w, &mut bw, &mut dw);
    let (mut s, mut su, mut sv, mut sw) = (P::ZERO, P::ZERO, P::ZERO, P::ZERO);
    for (i, slab) in points.chunks_exact((m + 1) * (l + 1)).enumerate() {
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

/// de Casteljau over a net: every line along the last axis reduced at its parameter, then the
/// resulting net along the one before.
fn casteljau<P: ControlPoint>(points: &[P], dims: &[usize], t: &[f64]) -> P {
    let Some((&n, inner)) = dims.split_first() else {
        return points.first().copied().unwrap_or(P::ZERO);
    };
    let mut column = [P::ZERO; MAX_DEGREE + 1];
    if inner.is_empty() {
        column[..n].copy_from_slice(points);
    } else {
        let slab = inner.iter().product();
        for (slot, s) in column.iter_mut().zip(points.chunks_exact(slab)) {
            *slot = casteljau(s, inner, &t[1..]);
        }
    }
    de_casteljau(&mut column[..n], t[0])
}

/// The grid evaluation behind [`Tensor::eval_grid`]: for each sample of the last axis (its basis
/// row in `tables`), the net contracted along it into `scratch[0]`, then that net's grid over the
/// axes before, appended to `out`. The first axis's table is transposed (a row per basis
/// function): its samples are weighed side by side.
fn grid<P: ControlPoint>(
    points: &[P],
    dims: &[usize],
    tables: &[Vec<f64>],
    scratch: &mut [Vec<P>],
    out: &mut Vec<P>,
) {
    let last = dims.len() - 1;
    let n = dims[last];
    if last == 0 {
        let samples = tables[0].len() / n;
        P::weigh(points, &tables[0], samples, samples, out);
        return;
    }
    let Some((net, rest)) = scratch.split_first_mut() else {
        return;
    };
    for weights in tables[last].chunks_exact(n) {
        for (slot, line) in net.iter_mut().zip(points.chunks_exact(n)) {
            *slot = dot(line, weights);
        }
        grid(net, &dims[..last], &tables[..last], rest, out);
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
    use crate::testutil::{Rng, assert_close};
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn random_patch(rng: &mut Rng, max_degree: usize) -> Patch<DVec3> {
        let degree = [rng.int(1, max_degree), rng.int(1, max_degree)];
        Patch::from_fn(degree, |_| {
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
        let [n, m] = patch.degree();
        let mut s = DVec3::ZERO;
        for i in 0..=n {
            for j in 0..=m {
                s += patch[[i, j]] * bernstein(n, i, u) * bernstein(m, j, v);
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
            let a = patch.eval([u, v]);
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
            let a = patch.eval([u, v]);
            let b = patch.eval_de_casteljau([u, v]);
            assert!((a - b).abs().max_element() < 1e-10, "{a} vs {b}");
        }
    }

    #[test]
    fn patch_interpolates_corners() {
        let mut rng = Rng::new(12);
        let patch = random_patch(&mut rng, 6);
        let [n, m] = patch.degree();
        assert_eq!(patch.eval([0.0, 0.0]), patch[[0, 0]]);
        assert!((patch.eval([1.0, 1.0]) - patch[[n, m]]).abs().max_element() < 1e-14);
        assert!((patch.eval([1.0, 0.0]) - patch[[n, 0]]).abs().max_element() < 1e-14);
    }

    #[test]
    fn patch_grid_equals_pointwise() {
        let mut rng = Rng::new(13);
        for _ in 0..20 {
            let patch = random_patch(&mut rng, 8);
            let us: Vec<f64> = (0..7).map(|_| rng.range(-0.1, 1.1)).collect();
            let vs: Vec<f64> = (0..5).map(|_| rng.range(-0.1, 1.1)).collect();
            let grid = patch.eval_grid([&us, &vs]);
            for (b, &v) in vs.iter().enumerate() {
                for (a, &u) in us.iter().enumerate() {
                    let d = grid[b * us.len() + a] - patch.eval([u, v]);
                    assert!(d.abs().max_element() < 1e-12);
                }
            }
        }
    }

    fn random_volume(rng: &mut Rng, max_degree: usize) -> Volume<DVec4> {
        let degree = [
            rng.int(1, max_degree),
            rng.int(1, max_degree),
            rng.int(1, max_degree),
        ];
        Volume::from_fn(degree, |_| {
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
            let [n, m, l] = vol.degree();
            let (u, v, w) = (
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            );
            let mut direct = DVec4::ZERO;
            for i in 0..=n {
                for j in 0..=m {
                    for k in 0..=l {
                        direct += vol[[i, j, k]]
                            * bernstein(n, i, u)
                            * bernstein(m, j, v)
                            * bernstein(l, k, w);
                    }
                }
            }
            assert!((vol.eval([u, v, w]) - direct).abs().max_element() < 1e-11);
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
            let grid = vol.eval_grid([&us, &vs, &ws]);
            for (c, &w) in ws.iter().enumerate() {
                for (b, &v) in vs.iter().enumerate() {
                    for (a, &u) in us.iter().enumerate() {
                        let d = grid[(c * vs.len() + b) * us.len() + a] - vol.eval([u, v, w]);
                        assert!(d.abs().max_element() < 1e-12);
                    }
                }
            }
        }
    }

    #[test]
    fn volume_rejects_bad_input() {
        assert_eq!(
            Volume::try_new([1, 1, 1], alloc::vec![0.0; 7]),
            Err(PatchError::PointCount {
                expected: 8,
                got: 7
            })
        );
        assert_eq!(
            Volume::<f64>::from_fn([1, 1, 17], |_| 0.0),
            Err(PatchError::Degree { degree: 17 })
        );
    }

    #[test]
    fn patch_rejects_bad_input() {
        assert_eq!(
            Patch::try_new([2, 2], alloc::vec![0.0; 8]),
            Err(PatchError::PointCount {
                expected: 9,
                got: 8
            })
        );
        assert_eq!(
            Patch::try_new([0, 2], alloc::vec![0.0; 3]),
            Err(PatchError::Degree { degree: 0 })
        );
        assert_eq!(
            Patch::<f64>::from_fn([17, 1], |_| 0.0),
            Err(PatchError::Degree { degree: 17 })
        );
        assert_eq!(
            Patch::<f64>::from_fn([usize::MAX, 1], |_| 0.0),
            Err(PatchError::Degree { degree: usize::MAX })
        );
    }

    #[test]
    fn patch_partials_match_finite_differences() {
        let mut rng = Rng::new(21);
        let h = 1e-6;
        for _ in 0..60 {
            let patch = random_patch(&mut rng, 8);
            let (u, v) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (s, [su, sv]) = patch.eval_with_gradient([u, v]);
            assert_close!(s, patch.eval([u, v]), 1e-12);
            let fu = (patch.eval([u + h, v]) - patch.eval([u - h, v])) / (2.0 * h);
            let fv = (patch.eval([u, v + h]) - patch.eval([u, v - h])) / (2.0 * h);
            assert_close!(su, fu, 1e-5, "{su} vs {fu}");
            assert_close!(sv, fv, 1e-5, "{sv} vs {fv}");
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
            let (s, grad) = vol.eval_with_gradient(p);
            assert_close!(s, vol.eval([p[0], p[1], p[2]]), 1e-12);
            for (axis, g) in grad.iter().enumerate() {
                let (mut up, mut down) = (p, p);
                up[axis] += h;
                down[axis] -= h;
                let fd = (vol.eval([up[0], up[1], up[2]]) - vol.eval([down[0], down[1], down[2]]))
                    / (2.0 * h);
                assert_close!(*g, fd, 1e-5, "axis {axis}: {g} vs {fd}");
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
                        Axis::U => patch.eval([x, b]),
                        _ => patch.eval([b, x]),
                    };
                    let (l, r) = match axis {
                        Axis::U => (left.eval([a, b]), right.eval([a, b])),
                        _ => (left.eval([b, a]), right.eval([b, a])),
                    };
                    assert_close!(l, whole(t * a), 1e-10);
                    assert_close!(r, whole(t + (1.0 - t) * a), 1e-10);
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
                let (left, right) = vol.split(axis, t).unwrap();
                for _ in 0..5 {
                    let p = [
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                        rng.range(0.0, 1.0),
                    ];
                    let (mut pl, mut pr) = (p, p);
                    pl[ix] = t * p[ix];
                    pr[ix] = t + (1.0 - t) * p[ix];
                    let at = |v: &Volume<DVec4>, q: [f64; 3]| v.eval([q[0], q[1], q[2]]);
                    assert_close!(at(&left, p), at(&vol, pl), 1e-10);
                    assert_close!(at(&right, p), at(&vol, pr), 1e-10);
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
                let [n, m] = patch.degree();
                let expect = if axis == Axis::U {
                    [n + 1, m]
                } else {
                    [n, m + 1]
                };
                assert_eq!(up.degree(), expect);
                for _ in 0..10 {
                    let (u, v) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                    assert_close!(up.eval([u, v]), patch.eval([u, v]), 1e-10);
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
                    assert_close!(
                        up.eval([p[0], p[1], p[2]]),
                        vol.eval([p[0], p[1], p[2]]),
                        1e-10
                    );
                }
            }
        }
        let top = Patch::from_fn([MAX_DEGREE, 1], |_| 0.0).unwrap();
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
                let p = patch.eval([u, v]);
                assert!(p.cmpge(lo - 1e-12).all() && p.cmple(hi + 1e-12).all());
                let q = vol.eval([u, v, w]);
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

    #[test]
    fn slices_of_a_volume_are_its_layers_and_write_back() {
        let mut rng = Rng::new(27);
        let vol = random_volume(&mut rng, 4);
        let [n, m, l] = vol.degree();
        for axis in Axis::ALL {
            let len = vol.degree()[axis.index()];
            for index in 0..=len {
                let slice = vol.slice(axis, index).unwrap();
                for [a, b] in (0..slice.points().len()).map(|k| slice.multi_index(k).unwrap()) {
                    let at = match axis {
                        Axis::U => [index, a, b],
                        Axis::V => [a, index, b],
                        Axis::W => [a, b, index],
                    };
                    assert_eq!(slice[[a, b]], vol[at]);
                }
                let mut copy = vol.clone();
                let doubled = slice.map(|p| p * 2.0);
                copy.set_slice(axis, index, &doubled).unwrap();
                assert_eq!(copy.slice(axis, index), Some(doubled));
            }
            assert_eq!(vol.slice(axis, len + 1), None);
        }
        let mut copy = vol.clone();
        let wrong = Patch::from_fn([n + 1, m], |_| DVec4::ONE).unwrap();
        assert!(copy.set_slice(Axis::W, 0, &wrong).is_err());
        assert!(
            copy.set_slice(Axis::W, l + 1, &vol.slice(Axis::W, 0).unwrap())
                .is_err()
        );
        assert_eq!(copy, vol);
        assert_eq!(vol.get([n + 1, 0, 0]), None);
        assert_eq!(vol.get([n, m, l]), Some(vol[[n, m, l]]));
    }

    #[test]
    fn nets_of_one_and_four_parameters_evaluate_and_differentiate() {
        let mut rng = Rng::new(28);
        let curve = Tensor::<f64, 1>::from_fn([5], |_| rng.range(-1.0, 1.0)).unwrap();
        let net = Tensor::<f64, 4>::from_fn([2, 1, 3, 2], |_| rng.range(-1.0, 1.0)).unwrap();
        let h = 1e-6;
        for _ in 0..20 {
            let t = rng.range(0.0, 1.0);
            assert_close!(curve.eval([t]), curve.eval_de_casteljau([t]), 1e-12);
            let (s, [d]) = curve.eval_with_gradient([t]);
            assert_close!(s, curve.eval([t]), 1e-12);
            assert_close!(
                d,
                (curve.eval([t + h]) - curve.eval([t - h])) / (2.0 * h),
                1e-6
            );
            let p: [f64; 4] = core::array::from_fn(|_| rng.range(0.0, 1.0));
            assert_close!(net.eval(p), net.eval_de_casteljau(p), 1e-12);
            let (s, g) = net.eval_with_gradient(p);
            assert_close!(s, net.eval(p), 1e-12);
            for (a, &ga) in g.iter().enumerate() {
                let (mut up, mut down) = (p, p);
                up[a] += h;
                down[a] -= h;
                let fd = (net.eval(up) - net.eval(down)) / (2.0 * h);
                assert_close!(ga, fd, 1e-6, "axis {a}");
            }
            let grid = net.eval_grid([&[p[0], 0.5], &[p[1]], &[p[2], 0.1], &[p[3]]]);
            assert_close!(grid[0], net.eval(p), 1e-12);
            assert_close!(grid[3], net.eval([0.5, p[1], 0.1, p[3]]), 1e-12);
        }
    }
}
