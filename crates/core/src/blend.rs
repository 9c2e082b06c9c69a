//! Transfinite blending (Paoluzzi, the third paper): curves, surfaces and solids as vector-valued
//! maps, built by blending lower-dimensional maps with a polynomial basis, in a variable-free
//! algebra where maps add and multiply like numbers.
//!
//! - [`Fun`]: a scalar map `ℝᵈ → ℝ` as a value: the identity on the first coordinate, constants
//!   (`K`), selectors (`S1`, `S2`, …), arithmetic between maps and numbers, composition.
//! - A vector-valued map is a sequence of coordinate maps (`Vec<Fun>`), as the paper recommends
//!   (its `CONS` builds one function only where needed).
//! - [`bernstein_basis`] and [`hermite_basis`], in any parameter `u` (a map, usually a selector).
//! - [`bezier`] and [`hermite`]: transfinite Bézier of any degree and cubic Hermite, whose handles
//!   are points, vectors or maps of any domain and range dimension (Scripts 4.3 and 4.5).
//! - [`Complex`], [`interval`], [`Complex::product`] and [`Complex::map`]: `MAP` of a map over a
//!   simplicial decomposition of an interval or a product of intervals.
//! - [`patch_from_curves`], [`volume_from_patches`]: a transfinite Bézier blend of Bézier curves
//!   (surfaces) of one degree is a tensor-product patch (volume): its control net, so that a solid
//!   can be built from boundary curves and then edited as a Bézier solid.
//!
//! ```
//! use bezsolid_core::blend::{bezier, Fun, Handle};
//!
//! // A quadratic Bézier curve in the plane, blended from points with the basis in S1.
//! let c = bezier(&Fun::select(0), &[
//!     Handle::point(&[0.0, 0.0]), Handle::point(&[1.0, 2.0]), Handle::point(&[2.0, 0.0]),
//! ]).unwrap();
//! assert_eq!(c[0].eval(&[0.5]), 1.0);
//! assert_eq!(c[1].eval(&[0.5]), 1.0);
//! ```

use alloc::rc::Rc;
use alloc::vec::Vec;
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::tensor::{ControlPoint, PatchError};
use crate::{BezierCurve, Patch, Volume};
use glam::DVec3;

/// A scalar function of a point's coordinates.
type Scalar = dyn Fn(&[f64]) -> f64;

/// A scalar map `ℝᵈ → ℝ`, evaluated at a point given by its coordinates. Cheap to clone (shared).
#[derive(Clone)]
pub struct Fun(Rc<Scalar>);

impl fmt::Debug for Fun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Fun")
    }
}

impl Fun {
    /// The map `x ↦ f(x)`.
    pub fn from_fn(f: impl Fn(&[f64]) -> f64 + 'static) -> Self {
        Self(Rc::new(f))
    }

    /// The constant map `K:c`.
    #[must_use]
    pub fn constant(c: f64) -> Self {
        Self::from_fn(move |_| c)
    }

    /// The selector of coordinate `i` (0-based; PLaSM's `S1` is `select(0)`); 0 past the end.
    #[must_use]
    pub fn select(i: usize) -> Self {
        Self::from_fn(move |x| x.get(i).copied().unwrap_or(0.0))
    }

    /// The identity of a one-parameter map (`ID` on numbers): the first coordinate.
    #[must_use]
    pub fn id() -> Self {
        Self::select(0)
    }

    /// The value at `x`.
    #[must_use]
    pub fn eval(&self, x: &[f64]) -> f64 {
        (self.0)(x)
    }

    /// `outer ∘ self` for a scalar `outer: ℝ → ℝ`.
    #[must_use]
    pub fn then(&self, outer: impl Fn(f64) -> f64 + 'static) -> Self {
        let inner = self.clone();
        Self::from_fn(move |x| outer(inner.eval(x)))
    }

    /// `outer ∘ self`, `outer` a map of one parameter.
    #[must_use]
    pub fn compose_into(&self, outer: &Fun) -> Self {
        let (inner, outer) = (self.clone(), outer.clone());
        Self::from_fn(move |x| outer.eval(&[inner.eval(x)]))
    }

    /// `self ∘ (inner₁, …, innerₖ)`: `self` evaluated at the point whose coordinates are the
    /// `inner` maps' values (`f ~ CONS:<g, h>`).
    #[must_use]
    pub fn compose(&self, inner: &[Fun]) -> Self {
        let (outer, inner) = (self.clone(), inner.to_vec());
        Self::from_fn(move |x| {
            let y: Vec<f64> = inner.iter().map(|g| g.eval(x)).collect();
            outer.eval(&y)
        })
    }

    /// `self ** k` (a real power, as PLaSM's `**`).
    #[must_use]
    pub fn powf(&self, k: f64) -> Self {
        self.then(move |v| libm::pow(v, k))
    }

    /// `self ** k` for a natural `k`, by repeated multiplication (exact for small `k`).
    #[must_use]
    pub fn powi(&self, k: u32) -> Self {
        self.then(move |v| (0..k).fold(1.0, |acc, _| acc * v))
    }
}

macro_rules! fun_ops {
    ($($trait:ident $method:ident $op:tt),*) => {$(
        impl $trait<Fun> for Fun {
            type Output = Fun;
            fn $method(self, rhs: Fun) -> Fun {
                Fun::from_fn(move |x| self.eval(x) $op rhs.eval(x))
            }
        }
        impl $trait<&Fun> for &Fun {
            type Output = Fun;
            fn $method(self, rhs: &Fun) -> Fun {
                self.clone() $op rhs.clone()
            }
        }
        impl $trait<f64> for Fun {
            type Output = Fun;
            fn $method(self, rhs: f64) -> Fun {
                Fun::from_fn(move |x| self.eval(x) $op rhs)
            }
        }
        impl $trait<Fun> for f64 {
            type Output = Fun;
            fn $method(self, rhs: Fun) -> Fun {
                Fun::from_fn(move |x| self $op rhs.eval(x))
            }
        }
    )*};
}

fun_ops!(Add add +, Sub sub -, Mul mul *, Div div /);

impl Neg for Fun {
    type Output = Fun;
    fn neg(self) -> Fun {
        Fun::from_fn(move |x| -self.eval(x))
    }
}

/// A vector-valued map as its coordinate maps.
pub type VecMap = Vec<Fun>;

/// Evaluates a vector-valued map at `x`.
#[must_use]
pub fn eval(map: &[Fun], x: &[f64]) -> Vec<f64> {
    map.iter().map(|f| f.eval(x)).collect()
}

/// The Bernstein polynomial `β_iⁿ ∘ u = C(n, i) uⁱ (1 − u)ⁿ⁻ⁱ` (`0 ≤ i ≤ n ≤ MAX_DEGREE`, else 0).
#[must_use]
pub fn bernstein(u: &Fun, n: usize, i: usize) -> Fun {
    if i > n || n > crate::MAX_DEGREE {
        return Fun::constant(0.0);
    }
    u.then(move |t| crate::bernstein::bernstein(n, i, t))
}

/// The Bernstein basis `(β_0ⁿ, …, β_nⁿ) ∘ u`.
#[must_use]
pub fn bernstein_basis(u: &Fun, n: usize) -> Vec<Fun> {
    (0..=n).map(|i| bernstein(u, n, i)).collect()
}

/// The cubic Hermite basis `(η₀, η₁, η₂, η₃) ∘ u`: `η₀ = 2u³ − 3u² + 1`, `η₁ = −2u³ + 3u²`,
/// `η₂ = u³ − 2u² + u`, `η₃ = u³ − u²`, so that `p0 η₀ + p1 η₁ + t0 η₂ + t1 η₃` has the values
/// `p0`, `p1` and the derivatives `t0`, `t1` at `u = 0, 1`.
#[must_use]
pub fn hermite_basis(u: &Fun) -> [Fun; 4] {
    [
        u.then(|t| 2.0 * t * t * t - 3.0 * t * t + 1.0),
        u.then(|t| -2.0 * t * t * t + 3.0 * t * t),
        u.then(|t| t * t * t - 2.0 * t * t + t),
        u.then(|t| t * t * t - t * t),
    ]
}

/// A geometric handle of a blend: a point or vector (its coordinates), or a map (its coordinate
/// maps), which may depend on any number of parameters.
#[derive(Clone, Debug)]
pub enum Handle {
    /// Numbers, made constant maps.
    Point(Vec<f64>),
    /// Coordinate maps.
    Map(VecMap),
}

impl Handle {
    /// A point or vector.
    #[must_use]
    pub fn point(x: &[f64]) -> Self {
        Self::Point(x.to_vec())
    }

    fn dim(&self) -> usize {
        match self {
            Self::Point(p) => p.len(),
            Self::Map(m) => m.len(),
        }
    }

    fn coordinate(&self, j: usize) -> Fun {
        match self {
            Self::Point(p) => Fun::constant(p[j]),
            Self::Map(m) => m[j].clone(),
        }
    }
}

/// Why a blend cannot be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BlendError {
    /// No handles, or more than `MAX_DEGREE + 1`.
    Count(usize),
    /// Handles of different dimensions.
    Dimensions {
        /// The first handle's dimension.
        first: usize,
        /// The offending handle's.
        other: usize,
    },
    /// Curves or patches of different degrees, which make no tensor net (elevate them first).
    Degrees,
    /// A decomposition larger than [`MAX_CELLS`].
    TooManyCells(usize),
    /// Control nets that do not make a patch or volume.
    Net(PatchError),
    /// A map that is not defined (or not finite) at a parameter point, for [`fit_patch`] and
    /// [`fit_volume`].
    Undefined,
    /// A map that is not a polynomial of degree at most `MAX_DEGREE` in each parameter.
    NotPolynomial,
}

impl fmt::Display for BlendError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Count(n) => write!(
                f,
                "a blend takes 1 to {} handles, not {n}",
                crate::MAX_DEGREE + 1
            ),
            Self::Dimensions { first, other } => write!(
                f,
                "the handles have {first} and {other} coordinates: they must all have the same"
            ),
            Self::Degrees => f.write_str(
                "the curves or patches have different degrees: elevate them to one degree first",
            ),
            Self::TooManyCells(n) => {
                write!(
                    f,
                    "{n} cells is more than the {MAX_CELLS} a decomposition may have"
                )
            }
            Self::Net(e) => write!(f, "{e}"),
            Self::Undefined => f.write_str("the map is not defined everywhere on its domain"),
            Self::NotPolynomial => write!(
                f,
                "the map is not a polynomial of degree at most {} in each parameter, so it has \
                 no Bézier control net",
                crate::MAX_DEGREE
            ),
        }
    }
}

impl core::error::Error for BlendError {}

fn dimension(handles: &[Handle]) -> Result<usize, BlendError> {
    let first = handles.first().ok_or(BlendError::Count(0))?.dim();
    if let Some(h) = handles.iter().find(|h| h.dim() != first) {
        return Err(BlendError::Dimensions {
            first,
            other: h.dim(),
        });
    }
    Ok(first)
}

/// Transfinite Bézier blending (Script 4.3): `Σᵢ handleᵢ · β_iᵏ ∘ u`, `k` = handles − 1, component
/// by component. `u` is usually the selector of the new parameter (`S1` for a curve of points,
/// `S2` for a surface of curves, …).
///
/// # Errors
///
/// [`BlendError::Count`] for no handles or more than `MAX_DEGREE + 1`, [`BlendError::Dimensions`]
/// for handles of different dimensions.
pub fn bezier(u: &Fun, handles: &[Handle]) -> Result<VecMap, BlendError> {
    if handles.is_empty() || handles.len() > crate::MAX_DEGREE + 1 {
        return Err(BlendError::Count(handles.len()));
    }
    combine(handles, &bernstein_basis(u, handles.len() - 1))
}

/// `Σᵢ handleᵢ · basisᵢ`, coordinate by coordinate.
fn combine(handles: &[Handle], basis: &[Fun]) -> Result<VecMap, BlendError> {
    let n = dimension(handles)?;
    Ok((0..n)
        .map(|j| {
            let terms: Vec<(Fun, Fun)> = handles
                .iter()
                .zip(basis)
                .map(|(h, b)| (h.coordinate(j), b.clone()))
                .collect();
            Fun::from_fn(move |x| terms.iter().map(|(c, b)| c.eval(x) * b.eval(x)).sum())
        })
        .collect())
}

/// Transfinite cubic Hermite blending (Script 4.5): `p0 η₀ + p1 η₁ + t0 η₂ + t1 η₃` in `u`, the
/// handles `[p0, p1, t0, t1]` points, vectors or maps.
///
/// # Errors
///
/// [`BlendError::Dimensions`] for handles of different dimensions.
pub fn hermite(u: &Fun, handles: &[Handle; 4]) -> Result<VecMap, BlendError> {
    combine(handles, &hermite_basis(u))
}

/// The most cells of a [`Complex`].
pub const MAX_CELLS: usize = 4_000_000;

/// A simplicial complex: points and cells (each a list of point indices: 2 for segments, 3 for
/// triangles, 4 for tetrahedra).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Complex {
    /// Point coordinates, all of one dimension.
    pub points: Vec<Vec<f64>>,
    /// Cells by point index.
    pub cells: Vec<Vec<u32>>,
}

/// `[a, b]` split into `n` segments (`interval:<a, b>:n`).
///
/// # Errors
///
/// [`BlendError::TooManyCells`] for `n` past [`MAX_CELLS`] (or 0).
pub fn interval(a: f64, b: f64, n: usize) -> Result<Complex, BlendError> {
    if n == 0 || n > MAX_CELLS {
        return Err(BlendError::TooManyCells(n));
    }
    Ok(Complex {
        points: (0..=n)
            .map(|k| alloc::vec![a + (b - a) * k as f64 / n as f64])
            .collect(),
        cells: (0..n as u32).map(|k| alloc::vec![k, k + 1]).collect(),
    })
}

impl Complex {
    /// The product of two one-dimensional complexes (segments × segments), each square split into
    /// two triangles, counter-clockwise in the product's two coordinates.
    ///
    /// # Errors
    ///
    /// [`BlendError::TooManyCells`] past [`MAX_CELLS`] triangles; [`BlendError::Dimensions`] when
    /// either is not a complex of segments in one dimension.
    pub fn product(&self, other: &Complex) -> Result<Complex, BlendError> {
        for c in [self, other] {
            if c.points.iter().any(|p| p.len() != 1) || c.cells.iter().any(|s| s.len() != 2) {
                return Err(BlendError::Dimensions {
                    first: 1,
                    other: c.points.first().map_or(0, Vec::len),
                });
            }
        }
        let count = self
            .cells
            .len()
            .saturating_mul(other.cells.len())
            .saturating_mul(2);
        let points = self.points.len().saturating_mul(other.points.len());
        if count > MAX_CELLS || points > MAX_CELLS {
            return Err(BlendError::TooManyCells(count.max(points)));
        }
        // Cells name their points (the fields are public): every index in range.
        for c in [self, other] {
            let n = c.points.len();
            if let Some(&i) = c.cells.iter().flatten().find(|&&i| i as usize >= n) {
                return Err(BlendError::Dimensions {
                    first: n,
                    other: i as usize + 1,
                });
            }
        }
        // At most MAX_CELLS points: their indices fit in u32.
        let m = other.points.len();
        let points = self
            .points
            .iter()
            .flat_map(|p| other.points.iter().map(move |q| alloc::vec![p[0], q[0]]))
            .collect();
        let mut cells = Vec::with_capacity(count);
        for a in &self.cells {
            for b in &other.cells {
                let at = |i: u32, j: u32| i * m as u32 + j;
                let (p00, p10, p11, p01) = (
                    at(a[0], b[0]),
                    at(a[1], b[0]),
                    at(a[1], b[1]),
                    at(a[0], b[1]),
                );
                cells.push(alloc::vec![p00, p10, p11]);
                cells.push(alloc::vec![p00, p11, p01]);
            }
        }
        Ok(Complex { points, cells })
    }

    /// `MAP:f:self`: the same cells on the images of the points under the vector-valued map `f`.
    #[must_use]
    pub fn map(&self, f: &[Fun]) -> Complex {
        Complex {
            points: self.points.iter().map(|p| eval(f, p)).collect(),
            cells: self.cells.clone(),
        }
    }
}

/// The tensor-product patch equal to the transfinite Bézier blend `Σᵢ curveᵢ(u₁) β_iᵏ(u₂)` of
/// Bézier curves of one degree `m` (`k` = curves − 1): control point `P_ij` is curve `i`'s point
/// `j`, so the patch at `(u, v)` is the blend at `(u₁, u₂) = (v, u)`.
///
/// # Errors
///
/// [`BlendError::Count`] for no curves or more than `MAX_DEGREE + 1`, [`BlendError::Degrees`]
/// for curves of different degrees (elevate them first).
pub fn patch_from_curves<P: ControlPoint>(
    curves: &[BezierCurve<P>],
) -> Result<Patch<P>, BlendError> {
    let first = curves.first().ok_or(BlendError::Count(0))?;
    if curves.len() > crate::MAX_DEGREE + 1 {
        return Err(BlendError::Count(curves.len()));
    }
    let m = first.degree();
    if curves.iter().any(|c| c.degree() != m) {
        return Err(BlendError::Degrees);
    }
    let points = curves
        .iter()
        .flat_map(|c| c.points().iter().copied())
        .collect();
    Patch::try_new([curves.len() - 1, m], points).map_err(BlendError::Net)
}

/// The tensor-product volume equal to the transfinite Bézier blend
/// `Σᵢ patchᵢ(u₁, u₂) β_iᵏ(u₃)` of patches of one degree `(n, m)`: control point `P_ijl` is patch
/// `i`'s `P_jl`, so the volume at `(u, v, w)` is the blend at `(u₁, u₂, u₃) = (v, w, u)`.
///
/// # Errors
///
/// As [`patch_from_curves`], for patches.
pub fn volume_from_patches<P: ControlPoint>(patches: &[Patch<P>]) -> Result<Volume<P>, BlendError> {
    let first = patches.first().ok_or(BlendError::Count(0))?;
    if patches.len() > crate::MAX_DEGREE + 1 {
        return Err(BlendError::Count(patches.len()));
    }
    let [n, m] = first.degree();
    if patches.iter().any(|p| p.degree() != [n, m]) {
        return Err(BlendError::Degrees);
    }
    let points = patches
        .iter()
        .flat_map(|p| p.points().iter().copied())
        .collect();
    Volume::try_new([patches.len() - 1, n, m], points).map_err(BlendError::Net)
}

#[cfg(test)]
mod fit_tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn fitting_finds_the_degree_and_net_of_a_blend() {
        // Curves of degrees 1, 2, 3 and 2, blended: a patch of degree (3, 3).
        let curves = [
            vec![[0., 0., 0.], [10., 0., 0.]],
            vec![[0., 2., 0.], [8., 3., 0.], [9., 2., 0.]],
            vec![[0., 4., 1.], [7., 5., -1.], [8., 5., 1.], [12., 4., 0.]],
            vec![[0., 6., 0.], [9., 6., 3.], [10., 6., -1.]],
        ];
        let handles: Vec<Handle> = curves
            .iter()
            .map(|c| {
                let hs: Vec<Handle> = c.iter().map(|p| Handle::point(p)).collect();
                Handle::Map(bezier(&Fun::select(0), &hs).unwrap_or_default())
            })
            .collect();
        let surface = bezier(&Fun::select(1), &handles).unwrap_or_default();
        let patch = fit_patch(&mut |u, v| {
            let p = eval(&surface, &[u, v]);
            Some(DVec3::new(p[0], p[1], p[2]))
        })
        .expect("a polynomial");
        assert_eq!(patch.degree(), [3, 3]);
        // The first row of the net is C0 elevated to degree 3.
        let c0 = BezierCurve::try_new(vec![DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0)])
            .and_then(|c| c.elevate())
            .and_then(|c| c.elevate())
            .expect("elevated");
        for j in 0..4 {
            assert!((patch[[j, 0]] - c0.points()[j]).length() < 1e-9);
        }
        // A plane is degree (1, 1); sin is no polynomial; a hole is undefined.
        let plane = fit_patch(&mut |u, v| Some(DVec3::new(u, v, 2.0 * u - v))).expect("a plane");
        assert_eq!(plane.degree(), [1, 1]);
        assert_eq!(
            fit_patch(&mut |u, v| Some(DVec3::new(u, v, (7.0 * u).sin()))).err(),
            Some(BlendError::NotPolynomial)
        );
        assert_eq!(
            fit_patch(&mut |u, v| (u < 0.6).then_some(DVec3::new(u, v, 0.0))).err(),
            Some(BlendError::Undefined)
        );
    }

    #[test]
    fn fitting_finds_the_net_of_a_solid_blended_from_patches() {
        // Three patches of degrees (1, 1), (2, 1) and (1, 2), blended in the first parameter: a
        // volume of degree (2, 2, 2) whose net the fit finds, and which equals the blend.
        let patch = |points: &[[f64; 3]], degree: [usize; 2]| {
            Patch::try_new(
                degree,
                points.iter().map(|p| DVec3::from_array(*p)).collect(),
            )
            .expect("a patch")
        };
        let patches = [
            patch(
                &[[0., 0., 0.], [0., 1., 0.], [1., 0., 0.], [1., 1., 0.2]],
                [1, 1],
            ),
            patch(
                &[
                    [0., 0., 1.],
                    [0., 1., 1.],
                    [0.5, -0.3, 1.2],
                    [0.5, 1.3, 0.8],
                    [1., 0., 1.],
                    [1., 1., 1.],
                ],
                [2, 1],
            ),
            patch(
                &[
                    [0., 0., 2.],
                    [0.1, 0.5, 2.5],
                    [0., 1., 2.],
                    [1., 0., 2.],
                    [0.9, 0.5, 1.5],
                    [1., 1., 2.],
                ],
                [1, 2],
            ),
        ];
        let blend = |u: f64, v: f64, w: f64| -> DVec3 {
            (0..3)
                .map(|i| patches[i].eval([v, w]) * crate::bernstein::bernstein(2, i, u))
                .sum()
        };
        let volume = fit_volume(&mut |u, v, w| Some(blend(u, v, w))).expect("a polynomial");
        assert_eq!(volume.degree(), [2, 2, 2]);
        for t in [[0.2, 0.3, 0.4], [0.9, 0.1, 0.6], [1.0, 0.0, 1.0]] {
            assert!((volume.eval(t) - blend(t[0], t[1], t[2])).length() < 1e-12);
        }
        // The corners of the net are the corners of the first and last patches.
        assert!((volume[[0, 0, 0]] - DVec3::ZERO).length() < 1e-12);
        assert!((volume[[0, 2, 2]] - DVec3::new(1.0, 1.0, 0.2)).length() < 1e-12);
        assert!((volume[[2, 2, 0]] - DVec3::new(1.0, 0.0, 2.0)).length() < 1e-12);
        // A box is degree (1, 1, 1); a twist by sin is no polynomial; a hole is undefined.
        let cube = fit_volume(&mut |u, v, w| Some(DVec3::new(u, 2.0 * v, w - u))).expect("a box");
        assert_eq!(cube.degree(), [1, 1, 1]);
        assert_eq!(
            fit_volume(&mut |u, v, w| Some(DVec3::new(u, v, (30.0 * w).sin()))).err(),
            Some(BlendError::NotPolynomial)
        );
        assert_eq!(
            fit_volume(&mut |u, v, w| (w < 0.6).then_some(DVec3::new(u, v, w))).err(),
            Some(BlendError::Undefined)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bernstein::binomial;
    use crate::testutil::Rng;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn curve(points: &[[f64; 3]]) -> VecMap {
        let handles: Vec<Handle> = points.iter().map(|p| Handle::point(p)).collect();
        bezier(&Fun::select(0), &handles).unwrap()
    }

    #[test]
    fn the_algebra_of_maps_is_pointwise() {
        let id = Fun::id();
        let sqr = &id * &id;
        // Script 3.1's beta: ((1 − u²)/(1 + u²), 2u/(1 + u²)) is on the unit circle.
        let beta = [
            (1.0 - sqr.clone()) / (1.0 + sqr.clone()),
            (2.0 * id.clone()) / (1.0 + sqr.clone()),
        ];
        let arc = interval(0.0, 1.0, 10).unwrap().map(&beta);
        for p in &arc.points {
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
        }
        assert_eq!(arc.cells.len(), 10);
        // alpha = (cos, sin) ∘ (π/2 · id), composed.
        let half_pi = core::f64::consts::FRAC_PI_2 * id.clone();
        let alpha = [half_pi.then(libm::cos), half_pi.then(libm::sin)];
        for p in interval(0.0, 1.0, 7).unwrap().map(&alpha).points {
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
        }
        // gamma = (id, √ ∘ (1 − id²)), with √ as id ** 1/2.
        let sqrt = id.powf(0.5);
        let gamma = [id.clone(), (1.0 - sqr).compose_into(&sqrt)];
        for p in interval(0.0, 1.0, 9).unwrap().map(&gamma).points {
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-12);
        }
        assert_eq!((-id.clone() + 3.0).eval(&[1.0]), 2.0);
        assert_eq!(id.powi(3).eval(&[2.0]), 8.0);
        assert_eq!(
            Fun::select(1)
                .compose(&[Fun::constant(4.0), id])
                .eval(&[7.0]),
            7.0
        );
    }

    #[test]
    fn bernstein_bases_sum_to_one_and_bezier_of_points_is_the_curve() {
        let u = Fun::id();
        let mut rng = Rng::new(4);
        for n in 0..=6 {
            let basis = bernstein_basis(&u, n);
            let t = rng.range(0.0, 1.0);
            let sum: f64 = basis.iter().map(|b| b.eval(&[t])).sum();
            assert!((sum - 1.0).abs() < 1e-14);
        }
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 2.0, 0.5],
            [3.0, -1.0, 1.0],
            [4.0, 0.0, 0.0],
        ];
        let c = curve(&pts);
        let reference =
            BezierCurve::try_new(pts.iter().map(|p| DVec3::from_array(*p)).collect()).unwrap();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let got = DVec3::from_slice(&eval(&c, &[t]));
            assert!((got - reference.eval(t)).length() < 1e-14);
        }
        assert_eq!(bezier(&u, &[]).unwrap_err(), BlendError::Count(0));
        assert!(matches!(
            bezier(&u, &[Handle::point(&[1.0]), Handle::point(&[1.0, 2.0])]),
            Err(BlendError::Dimensions { first: 1, other: 2 })
        ));
    }

    #[test]
    fn script_4_4_the_surface_is_the_sum_of_curves_times_the_cubic_basis() {
        // Curves of degrees 1, 2, 3, 2 (Script 4.4), blended in S2.
        let c = [
            curve(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]),
            curve(&[[0.0, 2.0, 0.0], [8.0, 3.0, 0.0], [9.0, 2.0, 0.0]]),
            curve(&[
                [0.0, 4.0, 1.0],
                [7.0, 5.0, -1.0],
                [8.0, 5.0, 1.0],
                [12.0, 4.0, 0.0],
            ]),
            curve(&[[0.0, 6.0, 0.0], [9.0, 6.0, 3.0], [10.0, 6.0, -1.0]]),
        ];
        let handles: Vec<Handle> = c.iter().map(|m| Handle::Map(m.clone())).collect();
        let surf = bezier(&Fun::select(1), &handles).unwrap();
        let mut rng = Rng::new(8);
        for _ in 0..50 {
            let (u1, u2) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let got = eval(&surf, &[u1, u2]);
            for j in 0..3 {
                let expect: f64 = (0..4)
                    .map(|i| {
                        let b = binomial(3, i)
                            * libm::pow(u2, i as f64)
                            * libm::pow(1.0 - u2, (3 - i) as f64);
                        c[i][j].eval(&[u1]) * b
                    })
                    .sum();
                assert!((got[j] - expect).abs() < 1e-12);
            }
        }
        // MAP over the product of intervals: 20 × 20 squares, two triangles each.
        let domain = interval(0.0, 1.0, 20)
            .unwrap()
            .product(&interval(0.0, 1.0, 20).unwrap())
            .unwrap();
        let mapped = domain.map(&surf);
        assert_eq!(mapped.cells.len(), 800);
        assert_eq!(mapped.points.len(), 441);
        // The boundary curves are interpolated: u2 = 0 is C0, u2 = 1 is C3.
        assert_eq!(eval(&surf, &[0.3, 0.0]), eval(&c[0], &[0.3]));
        let top = eval(&surf, &[0.3, 1.0]);
        for (a, b) in top.iter().zip(eval(&c[3], &[0.3])) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn hermite_end_conditions_hold() {
        let (p0, p1, t0, t1) = ([1.0, 0.0], [0.0, 2.0], [3.0, 1.0], [-1.0, 4.0]);
        let h = hermite(
            &Fun::id(),
            &[
                Handle::point(&p0),
                Handle::point(&p1),
                Handle::point(&t0),
                Handle::point(&t1),
            ],
        )
        .unwrap();
        let d = 1e-6;
        for j in 0..2 {
            assert!((h[j].eval(&[0.0]) - p0[j]).abs() < 1e-15);
            assert!((h[j].eval(&[1.0]) - p1[j]).abs() < 1e-15);
            let d0 = (h[j].eval(&[d]) - h[j].eval(&[-d])) / (2.0 * d);
            let d1 = (h[j].eval(&[1.0 + d]) - h[j].eval(&[1.0 - d])) / (2.0 * d);
            assert!((d0 - t0[j]).abs() < 1e-8, "{d0}");
            assert!((d1 - t1[j]).abs() < 1e-8, "{d1}");
        }
        // Transfinite: blending two curves with tangent curves gives a surface whose edges are
        // the curves.
        let a = curve(&[[0.0, 0.0, 0.0], [1.0, 0.0, 1.0]]);
        let b = curve(&[[0.0, 1.0, 0.0], [1.0, 1.0, -1.0]]);
        let ta = curve(&[[0.0, 1.0, 1.0], [0.0, 1.0, 1.0]]);
        let surf = hermite(
            &Fun::select(1),
            &[
                Handle::Map(a.clone()),
                Handle::Map(b.clone()),
                Handle::Map(ta.clone()),
                Handle::Map(ta),
            ],
        )
        .unwrap();
        assert_eq!(eval(&surf, &[0.4, 0.0]), eval(&a, &[0.4]));
        let e = eval(&surf, &[0.4, 1.0]);
        for (x, y) in e.iter().zip(eval(&b, &[0.4])) {
            assert!((x - y).abs() < 1e-15);
        }
    }

    #[test]
    fn blends_of_bezier_curves_and_patches_are_tensor_nets() {
        let mut rng = Rng::new(12);
        let mut random_curve = |m: usize| {
            BezierCurve::try_new(
                (0..=m)
                    .map(|_| {
                        DVec3::new(
                            rng.range(-1.0, 1.0),
                            rng.range(-1.0, 1.0),
                            rng.range(-1.0, 1.0),
                        )
                    })
                    .collect(),
            )
            .unwrap()
        };
        let curves: Vec<BezierCurve<DVec3>> = (0..4).map(|_| random_curve(2)).collect();
        let patch = patch_from_curves(&curves).unwrap();
        let handles: Vec<Handle> = curves
            .iter()
            .map(|c| {
                let pts: Vec<[f64; 3]> = c.points().iter().map(|p| p.to_array()).collect();
                Handle::Map(curve(&pts))
            })
            .collect();
        let blend = bezier(&Fun::select(1), &handles).unwrap();
        for (u1, u2) in [(0.1, 0.7), (0.5, 0.5), (0.9, 0.2), (0.0, 1.0)] {
            let got = DVec3::from_slice(&eval(&blend, &[u1, u2]));
            assert!((got - patch.eval([u2, u1])).length() < 1e-13);
        }
        // Patches of one degree blend into a volume.
        let patches: Vec<Patch<DVec3>> = (0..3)
            .map(|_| {
                patch_from_curves(&(0..2).map(|_| random_curve(3)).collect::<Vec<_>>()).unwrap()
            })
            .collect();
        let volume = volume_from_patches(&patches).unwrap();
        for (u1, u2, u3) in [(0.2, 0.3, 0.4), (0.9, 0.1, 0.6)] {
            let expect: DVec3 = (0..3)
                .map(|i| {
                    patches[i].eval([u1, u2])
                        * (binomial(2, i)
                            * libm::pow(u3, i as f64)
                            * libm::pow(1.0 - u3, (2 - i) as f64))
                })
                .sum();
            assert!((volume.eval([u3, u1, u2]) - expect).length() < 1e-13);
        }
        // Curves of different degrees must be elevated first.
        assert!(matches!(
            patch_from_curves(&[random_curve(2), random_curve(3)]),
            Err(BlendError::Degrees)
        ));
    }

    #[test]
    fn decompositions_are_capped() {
        assert!(matches!(
            interval(0.0, 1.0, 0),
            Err(BlendError::TooManyCells(0))
        ));
        assert!(interval(0.0, 1.0, MAX_CELLS + 1).is_err());
        let big = interval(0.0, 1.0, 10_000).unwrap();
        assert!(matches!(
            big.product(&big),
            Err(BlendError::TooManyCells(_))
        ));
        let square = big.product(&interval(0.0, 1.0, 1).unwrap()).unwrap();
        assert!(square.product(&big).is_err(), "a product takes segments");
        // Few cells but too many points, and cells naming points that do not exist.
        let dots = Complex {
            points: (0..100_000).map(|k| alloc::vec![f64::from(k)]).collect(),
            cells: alloc::vec![alloc::vec![0, 1]],
        };
        assert!(matches!(
            dots.product(&dots),
            Err(BlendError::TooManyCells(_))
        ));
        let dangling = Complex {
            points: alloc::vec![alloc::vec![0.0], alloc::vec![1.0]],
            cells: alloc::vec![alloc::vec![0, 7]],
        };
        assert!(dangling.product(&interval(0.0, 1.0, 1).unwrap()).is_err());
    }
}

/// The tensor-product Bézier patch equal to a polynomial map of the unit square, such as any
/// transfinite Bézier or Hermite blend of Bézier or Hermite curves: a patch, or a solid's net, can
/// be built by blending boundary curves and then edited point by point (the script console's tie
/// to the modeler). `f` is sampled only.
///
/// The degree in each parameter is the least `d` whose `(d + 1)`-th finite differences vanish
/// (to rounding) along three lines; the control points interpolate `f` on the uniform
/// `(n + 1) × (m + 1)` grid; the patch is then checked against `f` at points off the grid.
///
/// # Errors
///
/// [`BlendError::Undefined`] where `f` gives `None` or a coordinate that is not finite,
/// [`BlendError::NotPolynomial`] for a map of higher degree or none.
pub fn fit_patch(f: &mut dyn FnMut(f64, f64) -> Option<DVec3>) -> Result<Patch<DVec3>, BlendError> {
    let mut eval = |u: f64, v: f64| {
        f(u, v)
            .filter(|p| p.is_finite())
            .ok_or(BlendError::Undefined)
    };
    let n = degree_along(&mut |t, line| eval(t, line))?;
    let m = degree_along(&mut |t, line| eval(line, t))?;
    let mut samples = Vec::with_capacity((n + 1) * (m + 1));
    for i in 0..=n {
        for j in 0..=m {
            samples.push(eval(i as f64 / n as f64, j as f64 / m as f64)?);
        }
    }
    // Bernstein collocation at uniform nodes, solved along v, then along u.
    let a_n = collocation(n);
    let a_m = collocation(m);
    let mut rows = Vec::with_capacity(samples.len());
    for i in 0..=n {
        rows.extend(
            solve(&a_m, &samples[i * (m + 1)..(i + 1) * (m + 1)])
                .ok_or(BlendError::NotPolynomial)?,
        );
    }
    let mut points = alloc::vec![DVec3::ZERO; rows.len()];
    for j in 0..=m {
        let column: Vec<DVec3> = (0..=n).map(|i| rows[i * (m + 1) + j]).collect();
        for (i, p) in solve(&a_n, &column)
            .ok_or(BlendError::NotPolynomial)?
            .into_iter()
            .enumerate()
        {
            points[i * (m + 1) + j] = p;
        }
    }
    let patch = Patch::try_new([n, m], points).map_err(BlendError::Net)?;
    let scale = samples
        .iter()
        .fold(1e-300f64, |s, p| s.max(p.abs().max_element()));
    for (u, v) in [
        (0.31, 0.77),
        (0.9, 0.05),
        (0.137, 0.421),
        (0.66, 0.93),
        (0.5, 0.5),
    ] {
        if (patch.eval([u, v]) - eval(u, v)?).abs().max_element() > 1e-10 * scale {
            return Err(BlendError::NotPolynomial);
        }
    }
    Ok(patch)
}

/// The tensor-product Bézier volume equal to a polynomial map of the unit cube, such as any
/// transfinite Bézier or Hermite blend of Bézier or Hermite patches (`Bezier:S3:<…>` of the
/// paper's surfaces): a solid blended from surfaces becomes a net to edit point by point. `f` is
/// sampled only.
///
/// The degree `n` in the first parameter is found as [`fit_patch`] finds its degrees; the slices
/// `f(k/n, ·, ·)` are fitted as patches ([`fit_patch`]) and elevated to one degree; the control
/// patches whose Bernstein blend in the first parameter interpolates the slices are solved for,
/// and [`volume_from_patches`] makes them the volume, so that the volume at `(u, v, w)` is
/// `f(u, v, w)`. The volume is then checked against `f` at points off the grid.
///
/// # Errors
///
/// As [`fit_patch`]: [`BlendError::Undefined`] where `f` gives `None` or a coordinate that is not
/// finite, [`BlendError::NotPolynomial`] for a map of higher degree or none.
pub fn fit_volume(
    f: &mut dyn FnMut(f64, f64, f64) -> Option<DVec3>,
) -> Result<Volume<DVec3>, BlendError> {
    let mut eval = |u: f64, v: f64, w: f64| {
        f(u, v, w)
            .filter(|p| p.is_finite())
            .ok_or(BlendError::Undefined)
    };
    // Lines across the cube, off its faces and diagonals.
    let n = degree_along(&mut |t, line| eval(t, line, 1.0 - 0.61 * line))?;
    let mut slices = Vec::with_capacity(n + 1);
    let mut failed = None;
    for k in 0..=n {
        let u = k as f64 / n as f64;
        let slice = fit_patch(&mut |v, w| match eval(u, v, w) {
            Ok(p) => Some(p),
            Err(e) => {
                failed.get_or_insert(e);
                None
            }
        });
        slices.push(slice.map_err(|e| failed.take().unwrap_or(e))?);
    }
    // One degree for all slices (a slice may be of lower degree, or flat).
    let top = slices.iter().fold([1, 1], |[a, b], s| {
        let [n, m] = s.degree();
        [a.max(n), b.max(m)]
    });
    for s in &mut slices {
        for (axis, a) in [(crate::Axis::U, 0), (crate::Axis::V, 1)] {
            while s.degree()[a] < top[a] {
                *s = s.elevate(axis).map_err(BlendError::Net)?;
            }
        }
    }
    // Control patches C_i with Σ_i C_i β_iⁿ(k/n) = slice k, point by point.
    let a_n = collocation(n);
    let count = (top[0] + 1) * (top[1] + 1);
    let mut control: Vec<Vec<DVec3>> = (0..=n).map(|_| Vec::with_capacity(count)).collect();
    for p in 0..count {
        let column: Vec<DVec3> = slices.iter().map(|s| s.points()[p]).collect();
        let solved = solve(&a_n, &column).ok_or(BlendError::NotPolynomial)?;
        for (c, q) in control.iter_mut().zip(solved) {
            c.push(q);
        }
    }
    let patches = control
        .into_iter()
        .map(|points| Patch::try_new(top, points).map_err(BlendError::Net))
        .collect::<Result<Vec<_>, _>>()?;
    let volume = volume_from_patches(&patches)?;
    let checks = [
        [0.31, 0.77, 0.52],
        [0.9, 0.05, 0.71],
        [0.137, 0.421, 0.96],
        [0.66, 0.93, 0.18],
        [0.5, 0.5, 0.5],
        [0.0, 1.0, 0.0],
    ];
    let mut values = Vec::with_capacity(checks.len());
    for [u, v, w] in checks {
        values.push(eval(u, v, w)?);
    }
    let scale = values
        .iter()
        .chain(slices.iter().flat_map(|s| s.points()))
        .fold(1e-300f64, |s, p| s.max(p.abs().max_element()));
    for (t, value) in checks.into_iter().zip(values) {
        if (volume.eval(t) - value).abs().max_element() > 1e-10 * scale {
            return Err(BlendError::NotPolynomial);
        }
    }
    Ok(volume)
}

/// The least degree `d` (1 to `MAX_DEGREE`) whose `(d + 1)`-th differences of `g(·, line)` on
/// `d + 2` uniform nodes vanish on three lines.
fn degree_along(
    g: &mut dyn FnMut(f64, f64) -> Result<DVec3, BlendError>,
) -> Result<usize, BlendError> {
    let lines = [0.173, 0.5, 0.887];
    for d in 1..=crate::MAX_DEGREE {
        let mut flat = true;
        for &line in &lines {
            let mut values: Vec<DVec3> = (0..=d + 1)
                .map(|k| g(k as f64 / (d + 1) as f64, line))
                .collect::<Result<_, _>>()?;
            let scale = values
                .iter()
                .fold(1e-300f64, |s, p| s.max(p.abs().max_element()));
            for order in 1..=d + 1 {
                for k in 0..values.len() - order {
                    values[k] = values[k + 1] - values[k];
                }
            }
            // Rounding (a few ulps per sample) grows as 2^(d+1) in the differences.
            if values[0].abs().max_element()
                > 64.0 * f64::EPSILON * scale * (1u64 << (d + 1)) as f64
            {
                flat = false;
                break;
            }
        }
        if flat {
            return Ok(d);
        }
    }
    Err(BlendError::NotPolynomial)
}

/// `A[k][j] = β_j^n(k / n)`, row-major.
fn collocation(n: usize) -> Vec<f64> {
    let mut a = Vec::with_capacity((n + 1) * (n + 1));
    for k in 0..=n {
        for j in 0..=n {
            a.push(crate::bernstein::bernstein(n, j, k as f64 / n as f64));
        }
    }
    a
}

/// `x` with `A x = b` (Gaussian elimination with partial pivoting), or `None` for a singular `A`.
fn solve(a: &[f64], b: &[DVec3]) -> Option<Vec<DVec3>> {
    let n = b.len();
    let mut a = a.to_vec();
    let mut b = b.to_vec();
    for col in 0..n {
        let pivot =
            (col..n).max_by(|&r, &s| a[r * n + col].abs().total_cmp(&a[s * n + col].abs()))?;
        if a[pivot * n + col].abs() < 1e-300 {
            return None;
        }
        for k in 0..n {
            a.swap(col * n + k, pivot * n + k);
        }
        b.swap(col, pivot);
        for r in col + 1..n {
            let factor = a[r * n + col] / a[col * n + col];
            for k in col..n {
                a[r * n + k] -= factor * a[col * n + k];
            }
            b[r] = b[r] - b[col] * factor;
        }
    }
    let mut x = alloc::vec![DVec3::ZERO; n];
    for r in (0..n).rev() {
        let mut sum = b[r];
        for k in r + 1..n {
            sum -= x[k] * a[r * n + k];
        }
        x[r] = sum / a[r * n + r];
    }
    Some(x)
}
