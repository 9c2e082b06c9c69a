//! Bézier solids: the F-rep `f(p) ≥ 0` defined by a patch whose extra coordinate ξ is the function.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::fmt;

use glam::{DVec2, DVec3, DVec4};

use crate::inverse::{Forward, InverseMap, Method, QueryStats, Value, solve_jac};
use crate::rfunc::{clip2, clip2_with_gradient, clip3, clip3_with_gradient};
use crate::tensor::{Axis, Patch, PatchError, Volume, other_axes};

/// The parameter accuracy of the inverse map behind `f` (Bézier clipping's box size).
pub const INVERSE_ACCURACY: f64 = 1e-12;

/// Why a solid could not be built or edited.
///
/// Its message says the inner error's too (the page shows `to_string()` alone), so
/// [`source`](core::error::Error::source) gives none: a chain printed link by link (`anyhow`'s
/// `{:#}`) says each cause once, as the Rust API guidelines ask (C-GOOD-ERR: one or the other).
#[derive(Clone, Debug, PartialEq)]
pub enum SolidError {
    /// The control net is not a valid patch.
    Patch(PatchError),
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// A coordinate's magnitude is above [`Solid2::MAX_COORDINATE`].
    OutOfRange,
    /// A control point or row index past the end of the net.
    Index {
        /// The index given.
        index: usize,
        /// The number of points or rows along that axis.
        len: usize,
    },
}

impl fmt::Display for SolidError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Patch(e) => write!(f, "invalid control net: {e}"),
            Self::NonFinite => {
                f.write_str("a control point has a coordinate that is not a finite number")
            }
            Self::OutOfRange => write!(
                f,
                "a coordinate's magnitude is above {:e}",
                Solid2::MAX_COORDINATE
            ),
            Self::Index { index, len } => write!(
                f,
                "index {index} is past the {len} control points along that axis"
            ),
        }
    }
}

impl core::error::Error for SolidError {}

impl From<PatchError> for SolidError {
    fn from(e: PatchError) -> Self {
        Self::Patch(e)
    }
}

/// Every coordinate finite and within [`Solid2::MAX_COORDINATE`].
fn check_values(mut values: impl Iterator<Item = f64>) -> Result<(), SolidError> {
    values.try_for_each(|v| {
        if !v.is_finite() {
            Err(SolidError::NonFinite)
        } else if v.abs() > Solid2::MAX_COORDINATE {
            Err(SolidError::OutOfRange)
        } else {
            Ok(())
        }
    })
}

/// A 2D Bézier solid: a patch with control points `P_ij = (x, y, ξ)`.
///
/// On a regular grid (`P_ij^x = x0 + (i/n)(x1 − x0)`, `P_ij^y = y0 + (j/m)(y1 − y0)`) linear precision
/// gives `S_x = x0 + u(x1 − x0)`, `S_y = y0 + v(y1 − y0)`: the inverse map is a scaling, and
/// `f(x, y) = S_ξ(u, v) & F_s(u, v)` exactly (paper §3.2–§3.3.1).
///
/// Any other net is a space mapping (paper §3.3.2): `f(p)` is the largest clipped `S_ξ` over the
/// preimages of `p` (the extended space mapping of `papers/README.md`), negative and continuous
/// outside the image; see [`crate::inverse`].
#[derive(Clone, Debug, PartialEq)]
pub struct Solid2 {
    patch: Patch<DVec3>,
    /// The regular grid's box, or the bounds of the moved net (which contain its image).
    min: DVec2,
    max: DVec2,
    /// The inverse map of a space mapping; `None` on a regular grid.
    map: Option<Box<InverseMap<2>>>,
}

/// The box of a regular axis-aligned grid with positive size, `None` for anything else.
fn regular_box<const D: usize>(
    dims: [usize; D],
    points: &[[f64; D]],
) -> Option<([f64; D], [f64; D])> {
    let (min, max) = (points[0], points[points.len() - 1]);
    let size: [f64; D] = core::array::from_fn(|c| max[c] - min[c]);
    if !size.iter().all(|&w| w > 0.0) {
        return None;
    }
    // Tolerance relative to the box: the file may round coordinates to a few digits.
    let tol = 1e-9
        * (0..D)
            .map(|c| size[c].max(min[c].abs()).max(max[c].abs()))
            .fold(0.0, f64::max);
    let regular = points.iter().enumerate().all(|(index, p)| {
        let idx = crate::inverse::multi_index(dims, index);
        (0..D).all(|c| {
            let want = min[c] + size[c] * (idx[c] as f64 / (dims[c] - 1) as f64);
            (p[c] - want).abs() <= tol
        })
    });
    regular.then_some((min, max))
}

/// The componentwise bounds of a point set.
fn point_bounds<const D: usize>(points: &[[f64; D]]) -> ([f64; D], [f64; D]) {
    points
        .iter()
        .fold((points[0], points[0]), |(mut lo, mut hi), p| {
            for c in 0..D {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
            (lo, hi)
        })
}

/// A gradient with its overflowed components saturated (a tiny box's scaling can pass `f64::MAX`)
/// and its undefined ones zero.
fn saturated<const D: usize>(g: [f64; D]) -> [f64; D] {
    g.map(|x| {
        if x.is_nan() {
            0.0
        } else {
            x.clamp(-f64::MAX, f64::MAX)
        }
    })
}

/// The gradient in space from the gradient in parameters: `∇_p f = J^{-T} ∇_u f` (zero where `J` is
/// singular).
fn to_space_gradient<const D: usize>(jac: &[[f64; D]; D], g: [f64; D]) -> [f64; D] {
    let jt: [[f64; D]; D] = core::array::from_fn(|c| core::array::from_fn(|r| jac[r][c]));
    solve_jac(&jt, g).unwrap_or([0.0; D])
}

impl Solid2 {
    /// The largest magnitude of a control point coordinate (x, y or ξ): far beyond any model, and
    /// small enough that no evaluation overflows (Bernstein sums stay below 2^16 · 10^12).
    pub const MAX_COORDINATE: f64 = 1e12;

    /// A solid on the regular grid over the box `[min, max]` with `ξ(P_ij) = xi(i, j)`.
    ///
    /// # Errors
    ///
    /// [`SolidError`] for a degree out of range, a non-finite value or an empty box.
    pub fn regular(
        degree: (usize, usize),
        min: DVec2,
        max: DVec2,
        mut xi: impl FnMut(usize, usize) -> f64,
    ) -> Result<Self, SolidError> {
        let (n, m) = degree;
        let patch = Patch::from_fn(degree, |i, j| {
            let t = DVec2::new(i as f64 / n as f64, j as f64 / m as f64);
            let p = min + (max - min) * t;
            DVec3::new(p.x, p.y, xi(i, j))
        })?;
        Self::try_from_patch(patch)
    }

    /// A solid from a control net with finite values: a regular grid, or a space mapping.
    ///
    /// # Errors
    ///
    /// [`SolidError::NonFinite`] or [`SolidError::OutOfRange`] for a bad coordinate.
    pub fn try_from_patch(patch: Patch<DVec3>) -> Result<Self, SolidError> {
        check_values(patch.points().iter().flat_map(|p| p.to_array()))?;
        let mut solid = Self {
            patch,
            min: DVec2::ZERO,
            max: DVec2::ONE,
            map: None,
        };
        solid.remap();
        Ok(solid)
    }

    /// Recognise a regular grid or build the inverse map, after the net's `(x, y)` changed.
    fn remap(&mut self) {
        let spatial = self.patch.spatial();
        if let Some((min, max)) = regular_box(self.patch.dims(), &spatial) {
            (self.min, self.max) = (DVec2::from_array(min), DVec2::from_array(max));
            self.map = None;
        } else {
            let (min, max) = point_bounds(&spatial);
            (self.min, self.max) = (DVec2::from_array(min), DVec2::from_array(max));
            self.map = Some(Box::new(InverseMap::new(&self.patch)));
        }
    }

    /// The inverse map of a space mapping; `None` on a regular grid.
    #[must_use]
    pub fn inverse(&self) -> Option<&InverseMap<2>> {
        self.map.as_deref()
    }

    /// Says that about `queries` evaluations of `f` are coming, before the first (see
    /// [`InverseMap::plan`]); nothing for a regular grid.
    pub fn plan(&self, queries: usize) {
        if let Some(map) = &self.map {
            map.plan(queries);
        }
    }

    /// How many evaluations of `f` so far ran out of their work budget where the net folds very
    /// many times over ([`InverseMap::exhausted`]); 0 for a regular grid.
    #[must_use]
    pub fn exhausted(&self) -> usize {
        self.map.as_ref().map_or(0, |map| map.exhausted())
    }

    /// The solid of the same `S_ξ` on the regular grid over the unit square: the solid in parameter
    /// space.
    #[must_use]
    pub fn in_parameter_space(&self) -> Self {
        Self::regular(self.degree(), DVec2::ZERO, DVec2::ONE, |i, j| {
            self.patch.point(i, j).z
        })
        .unwrap_or_else(|_| unreachable!("the unit square with the net's valid ξ"))
    }

    /// `f(p)` with the number of preimages of `p` and the parameters `f` was taken at, by `method`
    /// (the regular grid's scaling ignores it).
    #[must_use]
    pub fn evaluate(&self, p: DVec2, method: Method) -> Value<2> {
        self.evaluate_seeded(p, method, None)
    }

    fn evaluate_seeded(&self, p: DVec2, method: Method, seed: Option<[f64; 2]>) -> Value<2> {
        match &self.map {
            None => {
                let uv = (p - self.min) / (self.max - self.min);
                let inside = uv.cmpge(DVec2::ZERO).all() && uv.cmple(DVec2::ONE).all();
                Value {
                    f: clip2(self.patch.eval(uv.x, uv.y).z, uv.x, uv.y),
                    preimages: usize::from(inside),
                    u: uv.to_array(),
                    exhausted: false,
                }
            }
            Some(map) => map.f_seeded(
                &self.patch,
                p.to_array(),
                method,
                seed,
                INVERSE_ACCURACY,
                &mut QueryStats::default(),
            ),
        }
    }

    /// Space mapping: move control point `P_ij` to `(x, y)` in the plane (ξ unchanged).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] past the end of the net, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a bad coordinate; the solid is unchanged then.
    pub fn set_point(&mut self, i: usize, j: usize, xy: DVec2) -> Result<(), SolidError> {
        check_values(xy.to_array().into_iter())?;
        let (n, m) = self.degree();
        for (index, d) in [(i, n), (j, m)] {
            if index > d {
                return Err(SolidError::Index { index, len: d + 1 });
            }
        }
        let p = self.patch.point_mut(i, j);
        (p.x, p.y) = (xy.x, xy.y);
        self.remap();
        Ok(())
    }

    /// Space mapping on a whole row: every `P_ij` with `i = index` (`axis` [`Axis::U`]) or
    /// `j = index` ([`Axis::V`]) moved by `delta` in the plane.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a row past the end or [`Axis::W`], [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a coordinate it would produce; the solid is unchanged then.
    pub fn move_row(&mut self, axis: Axis, index: usize, delta: DVec2) -> Result<(), SolidError> {
        let (n, m) = self.degree();
        let len = match axis {
            Axis::U => n + 1,
            Axis::V => m + 1,
            Axis::W => 0,
        };
        if index >= len {
            return Err(SolidError::Index { index, len });
        }
        let row: Vec<(usize, usize)> = if axis == Axis::U {
            (0..=m).map(|j| (index, j)).collect()
        } else {
            (0..=n).map(|i| (i, index)).collect()
        };
        let moved: Vec<DVec2> = row
            .iter()
            .map(|&(i, j)| self.patch.point(i, j).truncate() + delta)
            .collect();
        check_values(moved.iter().flat_map(|p| p.to_array()))?;
        for (&(i, j), xy) in row.iter().zip(moved) {
            let p = self.patch.point_mut(i, j);
            (p.x, p.y) = (xy.x, xy.y);
        }
        self.remap();
        Ok(())
    }

    /// The first paper's Fig. 9 after its three steps: a 3×3 grid (degree 2) over the unit square,
    /// flat at ξ = 0.25, the four corners pulled down to −1 and the centre pulled up to +1: one blob
    /// in the middle of the square.
    #[must_use]
    pub fn fig9() -> Self {
        Self::regular((2, 2), DVec2::ZERO, DVec2::ONE, |i, j| match (i, j) {
            (1, 1) => 1.0,
            (0 | 2, 0 | 2) => -1.0,
            _ => 0.25,
        })
        .unwrap_or_else(|_| unreachable!("the Fig. 9 preset is a valid regular grid"))
    }

    /// The control net.
    #[must_use]
    pub fn patch(&self) -> &Patch<DVec3> {
        &self.patch
    }

    /// The degree `(n, m)`.
    #[must_use]
    pub fn degree(&self) -> (usize, usize) {
        self.patch.degree()
    }

    /// The box `[min, max]` of the control grid (the solid's domain); for a space mapping, the
    /// bounds of the control points, which contain the image.
    #[must_use]
    pub fn domain(&self) -> (DVec2, DVec2) {
        (self.min, self.max)
    }

    /// `(u, v)` of the point `p`: a scaling on a regular grid; for a space mapping, the preimage that
    /// gives `f` (or the continuation's parameters where there is none).
    #[must_use]
    pub fn to_param(&self, p: DVec2) -> DVec2 {
        match self.map {
            None => (p - self.min) / (self.max - self.min),
            Some(_) => DVec2::from_array(self.evaluate(p, Method::Fast).u),
        }
    }

    /// ξ of control point `P_ij`.
    ///
    /// # Panics
    ///
    /// If `(i, j)` is outside the grid.
    #[must_use]
    pub fn xi(&self, i: usize, j: usize) -> f64 {
        self.patch.point(i, j).z
    }

    /// Function mapping: set ξ of control point `P_ij` (moves it along its vertical cylinder).
    ///
    /// # Errors
    ///
    /// [`SolidError::NonFinite`] for NaN or infinity, [`SolidError::OutOfRange`] beyond
    /// [`Solid2::MAX_COORDINATE`]; the solid is unchanged then.
    ///
    /// # Panics
    ///
    /// If `(i, j)` is outside the grid.
    pub fn set_xi(&mut self, i: usize, j: usize, xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        self.patch.point_mut(i, j).z = xi;
        Ok(())
    }

    /// The defining function `f(p) = S_ξ(u, v) & F_s(u, v)`: positive inside the solid, negative
    /// outside, and negative everywhere outside the domain (for a space mapping: the largest over
    /// the preimages of `p`, by [`Method::Fast`]).
    #[must_use]
    pub fn f(&self, p: DVec2) -> f64 {
        self.evaluate(p, Method::Fast).f
    }

    /// `f(p)` and its gradient `∇f(p)` (the chain rule through the clipping and the scaling, or the
    /// inverse Jacobian of a space mapping at the preimage that gives `f`).
    #[must_use]
    pub fn f_with_gradient(&self, p: DVec2) -> (f64, DVec2) {
        let uv = self.to_param(p);
        let e = self.patch.forward(uv.to_array());
        let (f, g) = clip2_with_gradient(e.xi, e.dxi, uv.x, uv.y);
        let g = match self.map {
            None => DVec2::from_array(g) / (self.max - self.min),
            Some(_) => DVec2::from_array(to_space_gradient(&e.jac, g)),
        };
        (f, DVec2::from_array(saturated(g.to_array())))
    }

    /// Function mapping on a whole row: ξ of every `P_ij` with `i = index` (`axis` [`Axis::U`]) or
    /// `j = index` ([`Axis::V`]) set to `xi`.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a row past the end or [`Axis::W`], and the errors of
    /// [`Solid2::set_xi`]; the solid is unchanged then.
    pub fn set_row_xi(&mut self, axis: Axis, index: usize, xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        let (n, m) = self.degree();
        let len = match axis {
            Axis::U => n + 1,
            Axis::V => m + 1,
            Axis::W => 0,
        };
        if index >= len {
            return Err(SolidError::Index { index, len });
        }
        if axis == Axis::U {
            for j in 0..=m {
                self.patch.point_mut(index, j).z = xi;
            }
        } else {
            for i in 0..=n {
                self.patch.point_mut(i, index).z = xi;
            }
        }
        Ok(())
    }

    /// `f` at every `(xs[a], ys[b])`, row-major by `b` (index `b·xs.len() + a`), by grid evaluation
    /// (a space mapping: Newton seeded from the previous point's parameters, verified, clipping where
    /// that fails).
    #[must_use]
    pub fn f_grid(&self, xs: &[f64], ys: &[f64]) -> Vec<f64> {
        if self.map.is_some() {
            self.plan(xs.len() * ys.len());
            let mut out = Vec::with_capacity(xs.len() * ys.len());
            let mut row_seed = None;
            for &y in ys {
                let mut seed = row_seed;
                for (a, &x) in xs.iter().enumerate() {
                    let v = self.evaluate_seeded(DVec2::new(x, y), Method::Fast, seed);
                    seed = Some(v.u);
                    if a == 0 {
                        row_seed = seed;
                    }
                    out.push(v.f);
                }
            }
            return out;
        }
        let size = self.max - self.min;
        let us: Vec<f64> = xs.iter().map(|x| (x - self.min.x) / size.x).collect();
        let vs: Vec<f64> = ys.iter().map(|y| (y - self.min.y) / size.y).collect();
        let (n, m) = self.degree();
        let xi = Patch::try_new((n, m), self.patch.points().iter().map(|p| p.z).collect())
            .unwrap_or_else(|_| unreachable!("same degree and count as the validated patch"));
        let mut values = xi.eval_grid(&us, &vs);
        for (b, &v) in vs.iter().enumerate() {
            for (a, &u) in us.iter().enumerate() {
                let s = &mut values[b * us.len() + a];
                *s = clip2(*s, u, v);
            }
        }
        values
    }
}

/// A 3D Bézier solid: a volume with control points `P_ijk = (x, y, z, ξ)`.
///
/// On a regular grid over the box `[min, max]` the inverse map is a scaling and
/// `f(x, y, z) = S_ξ(u, v, w) & F_s(u, v, w)` exactly (paper §3.2–§3.3.1); any other net is a space
/// mapping, as for [`Solid2`].
#[derive(Clone, Debug, PartialEq)]
pub struct Solid3 {
    volume: Volume<DVec4>,
    /// The regular grid's box, or the bounds of the moved net.
    min: DVec3,
    max: DVec3,
    /// The inverse map of a space mapping; `None` on a regular grid.
    map: Option<Box<InverseMap<3>>>,
}

impl Solid3 {
    /// A solid on the regular grid over `[min, max]` with `ξ(P_ijk) = xi(i, j, k)`.
    ///
    /// # Errors
    ///
    /// [`SolidError`] for a degree out of range, a bad value or an empty box.
    pub fn regular(
        degree: (usize, usize, usize),
        min: DVec3,
        max: DVec3,
        mut xi: impl FnMut(usize, usize, usize) -> f64,
    ) -> Result<Self, SolidError> {
        let (n, m, l) = degree;
        let volume = Volume::from_fn(degree, |i, j, k| {
            let t = DVec3::new(
                i as f64 / n as f64,
                j as f64 / m as f64,
                k as f64 / l as f64,
            );
            (min + (max - min) * t).extend(xi(i, j, k))
        })?;
        Self::try_from_volume(volume)
    }

    /// A solid from a control net with finite values: a regular grid, or a space mapping.
    ///
    /// # Errors
    ///
    /// [`SolidError::NonFinite`] or [`SolidError::OutOfRange`] for a bad coordinate.
    pub fn try_from_volume(volume: Volume<DVec4>) -> Result<Self, SolidError> {
        check_values(volume.points().iter().flat_map(|p| p.to_array()))?;
        let mut solid = Self {
            volume,
            min: DVec3::ZERO,
            max: DVec3::ONE,
            map: None,
        };
        solid.remap();
        Ok(solid)
    }

    /// Recognise a regular grid or build the inverse map, after the net's `(x, y, z)` changed.
    fn remap(&mut self) {
        let spatial = self.volume.spatial();
        if let Some((min, max)) = regular_box(self.volume.dims(), &spatial) {
            (self.min, self.max) = (DVec3::from_array(min), DVec3::from_array(max));
            self.map = None;
        } else {
            let (min, max) = point_bounds(&spatial);
            (self.min, self.max) = (DVec3::from_array(min), DVec3::from_array(max));
            self.map = Some(Box::new(InverseMap::new(&self.volume)));
        }
    }

    /// The inverse map of a space mapping; `None` on a regular grid.
    #[must_use]
    pub fn inverse(&self) -> Option<&InverseMap<3>> {
        self.map.as_deref()
    }

    /// Says that about `queries` evaluations of `f` are coming, before the first (see
    /// [`InverseMap::plan`]); nothing for a regular grid.
    pub fn plan(&self, queries: usize) {
        if let Some(map) = &self.map {
            map.plan(queries);
        }
    }

    /// How many evaluations of `f` so far ran out of their work budget where the net folds very
    /// many times over ([`InverseMap::exhausted`]); 0 for a regular grid.
    #[must_use]
    pub fn exhausted(&self) -> usize {
        self.map.as_ref().map_or(0, |map| map.exhausted())
    }

    /// `f(p)` with the number of preimages of `p` and the parameters `f` was taken at, by `method`
    /// (the regular grid's scaling ignores it).
    #[must_use]
    pub fn evaluate(&self, p: DVec3, method: Method) -> Value<3> {
        self.evaluate_seeded(p, method, None)
    }

    fn evaluate_seeded(&self, p: DVec3, method: Method, seed: Option<[f64; 3]>) -> Value<3> {
        match &self.map {
            None => {
                let t = (p - self.min) / (self.max - self.min);
                let inside = t.cmpge(DVec3::ZERO).all() && t.cmple(DVec3::ONE).all();
                Value {
                    f: clip3(self.volume.eval(t.x, t.y, t.z).w, t.x, t.y, t.z),
                    preimages: usize::from(inside),
                    u: t.to_array(),
                    exhausted: false,
                }
            }
            Some(map) => map.f_seeded(
                &self.volume,
                p.to_array(),
                method,
                seed,
                INVERSE_ACCURACY,
                &mut QueryStats::default(),
            ),
        }
    }

    /// Space mapping: move control point `P_ijk` to `xyz` (ξ unchanged).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] past the end of the net, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a bad coordinate; the solid is unchanged then.
    pub fn set_point(
        &mut self,
        i: usize,
        j: usize,
        k: usize,
        xyz: DVec3,
    ) -> Result<(), SolidError> {
        check_values(xyz.to_array().into_iter())?;
        let (n, m, l) = self.degree();
        for (index, d) in [(i, n), (j, m), (k, l)] {
            if index > d {
                return Err(SolidError::Index { index, len: d + 1 });
            }
        }
        let p = self.volume.point_mut(i, j, k);
        *p = xyz.extend(p.w);
        self.remap();
        Ok(())
    }

    /// Space mapping on a whole slice: every control point whose index along `axis` is `index`
    /// moved by `delta`.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a slice past the end, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a coordinate it would produce; the solid is unchanged then.
    pub fn move_slice(&mut self, axis: Axis, index: usize, delta: DVec3) -> Result<(), SolidError> {
        let (n, m, l) = self.degree();
        let len = [n, m, l][axis.index()] + 1;
        if index >= len {
            return Err(SolidError::Index { index, len });
        }
        let dims = [n, m, l];
        let (p, q) = other_axes(axis.index());
        let mut slice = Vec::new();
        for a in 0..=dims[p] {
            for b in 0..=dims[q] {
                let mut at = [index; 3];
                at[p] = a;
                at[q] = b;
                slice.push(at);
            }
        }
        let moved: Vec<DVec3> = slice
            .iter()
            .map(|&[i, j, k]| self.volume.point(i, j, k).truncate() + delta)
            .collect();
        check_values(moved.iter().flat_map(|p| p.to_array()))?;
        for (&[i, j, k], xyz) in slice.iter().zip(moved) {
            let p = self.volume.point_mut(i, j, k);
            *p = xyz.extend(p.w);
        }
        self.remap();
        Ok(())
    }

    /// The control net.
    #[must_use]
    pub fn volume(&self) -> &Volume<DVec4> {
        &self.volume
    }

    /// The degree `(n, m, l)`.
    #[must_use]
    pub fn degree(&self) -> (usize, usize, usize) {
        self.volume.degree()
    }

    /// The box `[min, max]` of the control grid; for a space mapping, the bounds of the control
    /// points, which contain the image.
    #[must_use]
    pub fn domain(&self) -> (DVec3, DVec3) {
        (self.min, self.max)
    }

    /// `(u, v, w)` of the point `p`: a scaling on a regular grid; for a space mapping, the preimage
    /// that gives `f` (or the continuation's parameters where there is none).
    #[must_use]
    pub fn to_param(&self, p: DVec3) -> DVec3 {
        match self.map {
            None => (p - self.min) / (self.max - self.min),
            Some(_) => DVec3::from_array(self.evaluate(p, Method::Fast).u),
        }
    }

    /// The defining function `f(p) = S_ξ(u, v, w) & F_s(u, v, w)` (for a space mapping: the largest
    /// over the preimages of `p`, by [`Method::Fast`]).
    #[must_use]
    pub fn f(&self, p: DVec3) -> f64 {
        self.evaluate(p, Method::Fast).f
    }

    /// The scalar volume `S_ξ`: the ξ coordinates of the net.
    #[must_use]
    pub fn xi_volume(&self) -> Volume<f64> {
        Volume::try_new(
            self.degree(),
            self.volume.points().iter().map(|p| p.w).collect(),
        )
        .unwrap_or_else(|_| unreachable!("same degree and count as the validated volume"))
    }

    /// `f(p)` and its gradient `∇f(p)`.
    #[must_use]
    pub fn f_with_gradient(&self, p: DVec3) -> (f64, DVec3) {
        let t = self.to_param(p);
        let e = self.volume.forward(t.to_array());
        let (f, g) = clip3_with_gradient(e.xi, e.dxi, t.x, t.y, t.z);
        let g = match self.map {
            None => DVec3::from_array(g) / (self.max - self.min),
            Some(_) => DVec3::from_array(to_space_gradient(&e.jac, g)),
        };
        (f, DVec3::from_array(saturated(g.to_array())))
    }

    /// ξ of control point `P_ijk`, `None` past the end of the net.
    #[must_use]
    pub fn xi(&self, i: usize, j: usize, k: usize) -> Option<f64> {
        let (n, m, l) = self.degree();
        (i <= n && j <= m && k <= l).then(|| self.volume.point(i, j, k).w)
    }

    /// Function mapping: set ξ of control point `P_ijk`.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] past the end of the net, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a bad value; the solid is unchanged then.
    pub fn set_xi(&mut self, i: usize, j: usize, k: usize, xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        let (n, m, l) = self.degree();
        for (index, d) in [(i, n), (j, m), (k, l)] {
            if index > d {
                return Err(SolidError::Index { index, len: d + 1 });
            }
        }
        self.volume.point_mut(i, j, k).w = xi;
        Ok(())
    }

    /// Function mapping on a whole slice: ξ of every control point whose index along `axis` is
    /// `index` set to `xi` (the slice the paper's interface opens in the patch editor).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a slice past the end, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a bad value; the solid is unchanged then.
    pub fn set_slice_xi(&mut self, axis: Axis, index: usize, xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        let (n, m, l) = self.degree();
        let len = [n, m, l][axis.index()] + 1;
        if index >= len {
            return Err(SolidError::Index { index, len });
        }
        let dims = [n, m, l];
        let (p, q) = other_axes(axis.index());
        for a in 0..=dims[p] {
            for b in 0..=dims[q] {
                let mut at = [index; 3];
                at[p] = a;
                at[q] = b;
                self.volume.point_mut(at[0], at[1], at[2]).w = xi;
            }
        }
        Ok(())
    }

    /// `f` at every `(xs[a], ys[b], zs[c])`, index `(c·|ys| + b)·|xs| + a`, by grid evaluation (a
    /// space mapping: seeded Newton, as [`Solid2::f_grid`]).
    #[must_use]
    pub fn f_grid(&self, xs: &[f64], ys: &[f64], zs: &[f64]) -> Vec<f64> {
        if self.map.is_some() {
            self.plan(xs.len() * ys.len() * zs.len());
            let mut out = Vec::with_capacity(xs.len() * ys.len() * zs.len());
            let mut seed = None;
            for &z in zs {
                for &y in ys {
                    let mut row = seed;
                    for (a, &x) in xs.iter().enumerate() {
                        let v = self.evaluate_seeded(DVec3::new(x, y, z), Method::Fast, row);
                        row = Some(v.u);
                        if a == 0 {
                            seed = row;
                        }
                        out.push(v.f);
                    }
                }
            }
            return out;
        }
        let scale = |ts: &[f64], lo: f64, hi: f64| {
            ts.iter().map(|t| (t - lo) / (hi - lo)).collect::<Vec<_>>()
        };
        let us = scale(xs, self.min.x, self.max.x);
        let vs = scale(ys, self.min.y, self.max.y);
        let ws = scale(zs, self.min.z, self.max.z);
        let xi = self.xi_volume();
        let mut values = xi.eval_grid(&us, &vs, &ws);
        let mut k = 0;
        for &w in &ws {
            for &v in &vs {
                for &u in &us {
                    values[k] = clip3(values[k], u, v, w);
                    k += 1;
                }
            }
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn solid_fig9_is_a_blob_in_the_square() {
        let s = Solid2::fig9();
        assert!(s.f(DVec2::splat(0.5)) > 0.0);
        for p in [
            DVec2::new(0.5, 0.01),
            DVec2::new(0.01, 0.5),
            DVec2::new(0.99, 0.99),
        ] {
            assert!(s.f(p) < 0.0, "{p}");
        }
    }

    #[test]
    fn solid_regular_grid_is_a_scaling() {
        let mut rng = Rng::new(30);
        let min = DVec2::new(-2.0, 1.0);
        let max = DVec2::new(3.0, 1.5);
        let s = Solid2::regular((3, 4), min, max, |_, _| rng.range(-1.0, 1.0)).unwrap();
        for _ in 0..100 {
            let uv = DVec2::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let point = s.patch().eval(uv.x, uv.y);
            // Linear precision: S_x, S_y are the scaling of (u, v).
            let p = min + (max - min) * uv;
            assert!((point.truncate() - p).abs().max_element() < 1e-12);
            assert!((s.f(p) - clip2(point.z, uv.x, uv.y)).abs() < 1e-12);
        }
    }

    #[test]
    fn solid_f_grid_equals_pointwise() {
        // Asymmetric in every way (degree, box, values), so that x and y cannot be confused.
        let mut rng = Rng::new(31);
        let s = Solid2::regular(
            (3, 4),
            DVec2::new(-2.0, 1.0),
            DVec2::new(3.0, 1.5),
            |_, _| rng.range(-1.0, 1.0),
        )
        .unwrap();
        let xs = [-2.5, -1.0, 0.1, 2.2, 3.3];
        let ys = [0.9, 1.1, 1.25, 1.45];
        let grid = s.f_grid(&xs, &ys);
        for (b, &y) in ys.iter().enumerate() {
            for (a, &x) in xs.iter().enumerate() {
                assert!((grid[b * xs.len() + a] - s.f(DVec2::new(x, y))).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn solid_moved_points_are_a_space_mapping_and_nan_is_rejected() {
        let mut patch = Solid2::fig9().patch().clone();
        patch.point_mut(1, 1).x += 0.1;
        let mapped = Solid2::try_from_patch(patch.clone()).unwrap();
        assert!(mapped.inverse().is_some());
        assert!(Solid2::fig9().inverse().is_none());
        patch.point_mut(1, 1).x = f64::NAN;
        assert_eq!(Solid2::try_from_patch(patch), Err(SolidError::NonFinite));
        let mut s = Solid2::fig9();
        assert_eq!(s.set_xi(0, 0, f64::INFINITY), Err(SolidError::NonFinite));
        assert_eq!(s.set_xi(0, 0, 1e200), Err(SolidError::OutOfRange));
        assert_eq!(s, Solid2::fig9());
    }

    #[test]
    fn solid3_regular_is_a_scaling_and_grid_matches() {
        let mut rng = Rng::new(32);
        let (min, max) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 3.0, 2.5));
        let s = Solid3::regular((2, 3, 4), min, max, |_, _, _| rng.range(-1.0, 1.0)).unwrap();
        for _ in 0..50 {
            let t = DVec3::new(
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            );
            let q = s.volume().eval(t.x, t.y, t.z);
            let p = min + (max - min) * t;
            assert!(
                (q.truncate() - p).abs().max_element() < 1e-12,
                "linear precision"
            );
            assert!((s.f(p) - clip3(q.w, t.x, t.y, t.z)).abs() < 1e-12);
        }
        let (xs, ys, zs) = ([-1.2, 0.3, 0.9], [0.0, 1.7], [1.9, 2.2, 2.4, 2.6]);
        let grid = s.f_grid(&xs, &ys, &zs);
        for (c, &z) in zs.iter().enumerate() {
            for (b, &y) in ys.iter().enumerate() {
                for (a, &x) in xs.iter().enumerate() {
                    let want = s.f(DVec3::new(x, y, z));
                    assert!((grid[(c * ys.len() + b) * xs.len() + a] - want).abs() < 1e-12);
                }
            }
        }
        assert!(
            s.f(DVec3::new(0.0, 1.0, 3.0)) < 0.0,
            "negative outside the box"
        );
    }

    #[test]
    fn solid3_irregular_and_flat_grids_are_space_mappings() {
        let s = Solid3::regular((1, 1, 1), DVec3::ZERO, DVec3::ONE, |_, _, _| 1.0).unwrap();
        let mut points = s.volume().points().to_vec();
        points[3].z += 0.2;
        let moved = Solid3::try_from_volume(Volume::try_new((1, 1, 1), points).unwrap()).unwrap();
        assert!(moved.inverse().is_some());
        // A flat box is a degenerate net: defined values, no solid.
        let flat = Solid3::regular(
            (1, 1, 1),
            DVec3::ZERO,
            DVec3::new(1.0, 1.0, 0.0),
            |_, _, _| 1.0,
        )
        .unwrap();
        assert!(flat.inverse().is_some());
        for p in [DVec3::splat(0.5), DVec3::new(0.5, 0.5, 0.0), DVec3::ONE] {
            assert!(flat.f(p).is_finite());
        }
    }

    #[test]
    fn space_mapping_edits_and_back_restore_the_regular_solid_exactly() {
        let mut rng = Rng::new(33);
        let original = Solid2::regular(
            (3, 2),
            DVec2::new(-1.0, 0.0),
            DVec2::new(2.0, 1.0),
            |_, _| rng.range(-1.0, 1.0),
        )
        .unwrap();
        let mut s = original.clone();
        let at = s.patch().point(1, 1).truncate();
        s.set_point(1, 1, at + DVec2::new(0.3, -0.1)).unwrap();
        assert!(s.inverse().is_some());
        let p = DVec2::new(0.2, 0.4);
        assert_ne!(s.f(p), original.f(p));
        s.move_row(Axis::V, 2, DVec2::new(0.0, 0.5)).unwrap();
        assert_eq!(s.patch().point(3, 2).y, 1.5);
        assert_eq!(
            s.set_point(4, 0, DVec2::ZERO),
            Err(SolidError::Index { index: 4, len: 4 })
        );
        assert_eq!(
            s.move_row(Axis::U, 0, DVec2::new(f64::NAN, 0.0)),
            Err(SolidError::NonFinite)
        );
        s.move_row(Axis::V, 2, DVec2::new(0.0, -0.5)).unwrap();
        s.set_point(1, 1, at).unwrap();
        assert!(s.inverse().is_none());
        assert_eq!(s, original);
        let mut v = Solid3::regular((2, 2, 2), DVec3::ZERO, DVec3::ONE, |i, j, k| {
            (i + j + k) as f64 - 2.5
        })
        .unwrap();
        let before = v.clone();
        v.move_slice(Axis::W, 2, DVec3::new(0.0, 0.0, 0.5)).unwrap();
        assert!(v.inverse().is_some());
        assert_eq!(v.domain().1.z, 1.5);
        v.set_point(0, 0, 0, DVec3::splat(-0.1)).unwrap();
        v.set_point(0, 0, 0, DVec3::ZERO).unwrap();
        v.move_slice(Axis::W, 2, DVec3::new(0.0, 0.0, -0.5))
            .unwrap();
        assert_eq!(v, before);
    }

    #[test]
    fn mapped_grids_and_gradients_match_the_reference() {
        let mut rng = Rng::new(34);
        for amp in [0.08, 0.4] {
            let patch = crate::inverse::tests::warped_patch(&mut rng, (3, 3), amp);
            let s = Solid2::try_from_patch(patch).unwrap();
            let (lo, hi) = s.domain();
            let xs: Vec<f64> = (0..17)
                .map(|a| lo.x - 0.1 + (hi.x - lo.x + 0.2) * a as f64 / 16.0)
                .collect();
            let ys: Vec<f64> = (0..13)
                .map(|b| lo.y - 0.1 + (hi.y - lo.y + 0.2) * b as f64 / 12.0)
                .collect();
            let grid = s.f_grid(&xs, &ys);
            for (b, &y) in ys.iter().enumerate() {
                for (a, &x) in xs.iter().enumerate() {
                    let want = s.evaluate(DVec2::new(x, y), Method::Clipping).f;
                    assert!(
                        (grid[b * xs.len() + a] - want).abs() < 1e-9,
                        "{amp} {x} {y}"
                    );
                }
            }
            // Gradients against central differences, at points well inside one preimage's image.
            for _ in 0..20 {
                let u = [rng.range(0.2, 0.8), rng.range(0.2, 0.8)];
                let p = DVec2::from_array(s.patch().forward(u).x);
                let v = s.evaluate(p, Method::Clipping);
                if v.preimages != 1 {
                    continue;
                }
                let (f, g) = s.f_with_gradient(p);
                assert!((f - v.f).abs() < 1e-12);
                let h = 1e-6;
                let fd = DVec2::new(
                    s.f(p + DVec2::X * h) - s.f(p - DVec2::X * h),
                    s.f(p + DVec2::Y * h) - s.f(p - DVec2::Y * h),
                ) / (2.0 * h);
                assert!((fd - g).length() < 1e-5 * g.length().max(1.0), "{fd} {g}");
            }
        }
        let volume = crate::inverse::tests::warped_volume(&mut rng, (2, 3, 2), 0.1);
        let s = Solid3::try_from_volume(volume).unwrap();
        let t = [-0.1, 0.3, 0.6, 1.05];
        let grid = s.f_grid(&t, &t, &t);
        let mut k = 0;
        for &z in &t {
            for &y in &t {
                for &x in &t {
                    let want = s.evaluate(DVec3::new(x, y, z), Method::Clipping).f;
                    assert!((grid[k] - want).abs() < 1e-9);
                    k += 1;
                }
            }
        }
    }

    /// Points far and near, of every magnitude up to `f64::MAX`, around a box at `lo` of size
    /// `size` (per axis).
    fn extreme_points<const D: usize>(
        rng: &mut Rng,
        lo: [f64; D],
        size: [f64; D],
    ) -> Vec<[f64; D]> {
        let mut out = Vec::new();
        for _ in 0..12 {
            // Inside or near the box.
            out.push(core::array::from_fn(|c| {
                lo[c] + size[c] * rng.range(-0.5, 1.5)
            }));
            // Anywhere, at any scale.
            out.push(core::array::from_fn(|_| {
                let e = rng.range(-300.0, 308.0);
                let sign = if rng.range(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
                sign * 10f64.powf(e).min(f64::MAX)
            }));
        }
        out.push([f64::MAX; D]);
        out.push([-f64::MAX; D]);
        out.push(core::array::from_fn(|c| if c == 0 { 1e20 } else { 0.0 }));
        out
    }

    #[test]
    fn f_is_finite_for_every_finite_point_and_negative_outside() {
        let mut rng = Rng::new(35);
        for trial in 0..40 {
            let extent = 10f64.powf(rng.range(-300.0, 11.0));
            let offset = if trial % 3 == 0 {
                0.0
            } else {
                extent * rng.range(-2.0, 2.0)
            };
            let degree = (rng.int(1, 16), rng.int(1, 16));
            let size = [extent, extent * rng.range(0.5, 2.0)];
            let lo = [offset, -offset];
            let mut patch = Solid2::regular(
                degree,
                DVec2::from_array(lo),
                DVec2::from_array(lo) + DVec2::from_array(size),
                |_, _| rng.range(-1.0, 1.0),
            )
            .unwrap()
            .patch()
            .clone();
            // Every other net is space-mapped: one inner point moved by a fraction of the box.
            let moved = trial % 2 == 1 && degree.0 <= 6 && degree.1 <= 6;
            if moved {
                let p = patch.point_mut(degree.0 / 2, degree.1 / 2);
                p.x += size[0] * 0.3;
            }
            let solid = Solid2::try_from_patch(patch).unwrap();
            let (min, max) = solid.domain();
            for p in extreme_points(&mut rng, lo, size) {
                let p = DVec2::from_array(p);
                let v = solid.evaluate(p, Method::Fast);
                assert!(
                    v.f.is_finite(),
                    "f = {} at {p} (box {min}..{max}, {degree:?})",
                    v.f
                );
                let (f, g) = solid.f_with_gradient(p);
                assert!(f.is_finite() && g.is_finite(), "{f} {g} at {p}");
                let outside = p.cmplt(min).any() || p.cmpgt(max).any();
                if outside {
                    assert!(v.f < 0.0, "f = {} ≥ 0 at {p}, outside {min}..{max}", v.f);
                }
            }
            let grid = solid.f_grid(&[min.x, -f64::MAX, 1e300], &[max.y, f64::MAX]);
            assert!(grid.iter().all(|f| f.is_finite()));
        }
        for trial in 0..12 {
            let extent = 10f64.powf(rng.range(-300.0, 11.0));
            let degree = (rng.int(1, 16), rng.int(1, 4), rng.int(1, 3));
            let lo = [extent * rng.range(-2.0, 2.0); 3];
            let size = [extent; 3];
            let mut volume = Solid3::regular(
                degree,
                DVec3::from_array(lo),
                DVec3::from_array(lo) + extent,
                |_, _, _| rng.range(-1.0, 1.0),
            )
            .unwrap()
            .volume()
            .clone();
            if trial % 2 == 1 {
                volume.point_mut(0, 0, 0).x -= extent * 0.4;
            }
            let solid = Solid3::try_from_volume(volume).unwrap();
            let (min, max) = solid.domain();
            for p in extreme_points(&mut rng, lo, size) {
                let p = DVec3::from_array(p);
                let v = solid.evaluate(p, Method::Fast);
                assert!(v.f.is_finite(), "f = {} at {p} ({degree:?})", v.f);
                let (f, g) = solid.f_with_gradient(p);
                assert!(f.is_finite() && g.is_finite(), "{f} {g} at {p}");
                if p.cmplt(min).any() || p.cmpgt(max).any() {
                    assert!(v.f < 0.0, "f = {} ≥ 0 at {p}, outside {min}..{max}", v.f);
                }
            }
        }
    }

    #[test]
    fn solid_raising_a_point_grows_the_solid() {
        let mut s = Solid2::fig9();
        let p = DVec2::new(0.5, 0.2);
        let before = s.f(p);
        s.set_xi(1, 0, 1.0).unwrap();
        assert!(s.f(p) > before);
    }

    #[test]
    fn solid_gradients_match_finite_differences() {
        let mut rng = Rng::new(32);
        let h = 1e-6;
        for _ in 0..40 {
            let (lo2, hi2) = (DVec2::new(-1.0, 0.5), DVec2::new(2.0, 1.5));
            let s2 = Solid2::regular((3, 2), lo2, hi2, |_, _| rng.range(-1.0, 1.0)).unwrap();
            let (lo3, hi3) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(0.5, 2.0, 2.5));
            let s3 = Solid3::regular((2, 3, 2), lo3, hi3, |_, _, _| rng.range(-1.0, 1.0)).unwrap();
            // Inside and a little outside the boxes.
            let t = DVec3::new(
                rng.range(-0.2, 1.2),
                rng.range(-0.2, 1.2),
                rng.range(-0.2, 1.2),
            );
            let p2 = lo2 + (hi2 - lo2) * t.truncate();
            let (f2, g2) = s2.f_with_gradient(p2);
            assert_eq!(f2, s2.f(p2));
            for (axis, e) in [DVec2::X, DVec2::Y].into_iter().enumerate() {
                let fd = (s2.f(p2 + e * h) - s2.f(p2 - e * h)) / (2.0 * h);
                assert!(
                    (fd - g2[axis]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "{p2} axis {axis}: {fd} vs {g2}"
                );
            }
            let p3 = lo3 + (hi3 - lo3) * t;
            let (f3, g3) = s3.f_with_gradient(p3);
            assert!((f3 - s3.f(p3)).abs() <= 1e-12 * (1.0 + f3.abs()));
            for (axis, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                let fd = (s3.f(p3 + e * h) - s3.f(p3 - e * h)) / (2.0 * h);
                assert!(
                    (fd - g3[axis]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "{p3} axis {axis}: {fd} vs {g3}"
                );
            }
        }
    }

    #[test]
    fn row_edits_set_exactly_that_row() {
        for axis in [Axis::U, Axis::V] {
            let mut s =
                Solid2::regular((3, 2), DVec2::ZERO, DVec2::ONE, |i, j| (i * 10 + j) as f64)
                    .unwrap();
            s.set_row_xi(axis, 1, -5.0).unwrap();
            for i in 0..=3 {
                for j in 0..=2 {
                    let in_row = if axis == Axis::U { i == 1 } else { j == 1 };
                    let want = if in_row { -5.0 } else { (i * 10 + j) as f64 };
                    assert_eq!(s.xi(i, j), want, "{axis:?} P_{i}{j}");
                }
            }
            let before = s.clone();
            assert_eq!(
                s.set_row_xi(axis, 4, 0.0),
                Err(SolidError::Index {
                    index: 4,
                    len: if axis == Axis::U { 4 } else { 3 }
                })
            );
            assert_eq!(s.set_row_xi(axis, 0, f64::NAN), Err(SolidError::NonFinite));
            assert_eq!(s, before);
        }
        let mut s = Solid2::fig9();
        assert_eq!(
            s.set_row_xi(Axis::W, 0, 0.0),
            Err(SolidError::Index { index: 0, len: 0 })
        );
    }

    #[test]
    fn point_and_slice_edits_of_volumes_set_exactly_those_points() {
        let start = |i: usize, j: usize, k: usize| (i * 100 + j * 10 + k) as f64;
        for (axis, a) in [(Axis::U, 0), (Axis::V, 1), (Axis::W, 2)] {
            let mut s = Solid3::regular((2, 3, 1), DVec3::ZERO, DVec3::ONE, start).unwrap();
            s.set_slice_xi(axis, 1, -7.0).unwrap();
            s.set_xi(2, 3, 0, 9.0).unwrap();
            for i in 0..=2 {
                for j in 0..=3 {
                    for k in 0..=1 {
                        let want = if (i, j, k) == (2, 3, 0) {
                            9.0
                        } else if [i, j, k][a] == 1 {
                            -7.0
                        } else {
                            start(i, j, k)
                        };
                        assert_eq!(s.xi(i, j, k), Some(want), "{axis:?} P_{i}{j}{k}");
                    }
                }
            }
            assert_eq!(s.xi(3, 0, 0), None);
            let before = s.clone();
            let len = [3, 4, 2][a];
            assert_eq!(
                s.set_slice_xi(axis, len, 0.0),
                Err(SolidError::Index { index: len, len })
            );
            assert_eq!(
                s.set_xi(0, 4, 0, 0.0),
                Err(SolidError::Index { index: 4, len: 4 })
            );
            assert_eq!(s.set_xi(0, 0, 0, f64::INFINITY), Err(SolidError::NonFinite));
            assert_eq!(s.set_slice_xi(axis, 0, 1e300), Err(SolidError::OutOfRange));
            assert_eq!(s, before);
        }
    }
}
