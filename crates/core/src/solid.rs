//! Bézier solids: the F-rep `f(p) ≥ 0` defined by a net whose extra coordinate ξ is the function,
//! in the plane ([`Solid2`], a patch) and in space ([`Solid3`], a volume), one generic
//! [`Solid<D>`].

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::fmt;

use once_cell::race::OnceBox;

use glam::DVec2;

use crate::dim::{Control, Dim, Dimension, Point};
use crate::inverse::{Forward, InverseMap, Method, QueryStats, Share, Value, solve_jac};
use crate::rfunc::{clip, clip_to_box, clip_with_gradient, intersect, strip};
use crate::tensor::{Axis, PatchError, Tensor, multi_index};

/// The parameter accuracy of the inverse map behind `f` (Bézier clipping's box size).
pub const INVERSE_ACCURACY: f64 = 1e-12;

/// The largest magnitude of a control point coordinate (x, y, z or ξ): far beyond any model, and
/// small enough that no evaluation overflows (Bernstein sums stay below 2^16 · 10^12).
const MAX_COORDINATE: f64 = 1e12;

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
    /// A coordinate's magnitude is above [`Solid::MAX_COORDINATE`].
    OutOfRange,
    /// A control point, row or slice index past the end of the net (or an axis it does not have).
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
            Self::OutOfRange => write!(f, "a coordinate's magnitude is above {MAX_COORDINATE:e}"),
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

/// Every coordinate finite and within [`MAX_COORDINATE`].
fn check_values(mut values: impl Iterator<Item = f64>) -> Result<(), SolidError> {
    values.try_for_each(|v| {
        if !v.is_finite() {
            Err(SolidError::NonFinite)
        } else if v.abs() > MAX_COORDINATE {
            Err(SolidError::OutOfRange)
        } else {
            Ok(())
        }
    })
}

/// A Bézier solid in `D` dimensions: a net of control points `P_I = (x, ξ)`, `x` in `D`-space.
///
/// On a regular grid (`P_I^x = min + (I / n)·(max − min)` coordinate by coordinate) linear precision
/// makes the inverse map a scaling, and `f(p) = S_ξ(t) & F_s(t)` exactly (paper §3.2–§3.3.1).
///
/// Any other net is a space mapping (paper §3.3.2): `f(p)` is the largest clipped `S_ξ` over the
/// preimages of `p` (the extended space mapping of `papers/README.md`), negative and continuous
/// outside the image; see [`crate::inverse`].
///
/// Every index into the net (a point, a row, a slice) is checked: past the net, reads say `None`
/// and edits [`SolidError::Index`], leaving the solid unchanged.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    net: Tensor<Control<D>, D>,
    /// The regular grid's box, or the bounds of the moved net (which contain its image).
    min: [f64; D],
    max: [f64; D],
    /// The inverse map of a space mapping, built on first use; `None` on a regular grid.
    map: Option<LazyMap<D>>,
}

/// The inverse map of a space mapping, built when `f` is first asked for: a solid made only to be
/// edited, sliced or written (a piecewise model's global net, each step of a drag whose frame
/// evaluates something else) never pays for it. The map is a function of the net, so two solids
/// of equal nets are equal whether or not either has built it.
#[derive(Clone, Debug, Default)]
struct LazyMap<const D: usize>(OnceBox<InverseMap<D>>);

impl<const D: usize> PartialEq for LazyMap<D> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<const D: usize> LazyMap<D>
where
    Dim<D>: Dimension<D>,
{
    fn get(&self, net: &Tensor<Control<D>, D>) -> &InverseMap<D> {
        self.0.get_or_init(|| Box::new(InverseMap::new(net)))
    }
}

/// A 2D Bézier solid: a patch with control points `P_ij = (x, y, ξ)`.
pub type Solid2 = Solid<2>;

/// A 3D Bézier solid: a volume with control points `P_ijk = (x, y, z, ξ)`.
pub type Solid3 = Solid<3>;

/// The box of a regular axis-aligned grid with positive size, `None` for anything else.
pub(crate) fn regular_box<const D: usize>(
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
        let idx = multi_index(dims, index);
        (0..D).all(|c| {
            let want = min[c] + size[c] * (idx[c] as f64 / (dims[c] - 1) as f64);
            (p[c] - want).abs() <= tol
        })
    });
    regular.then_some((min, max))
}

/// The componentwise bounds of a point set.
pub(crate) fn point_bounds<const D: usize>(points: &[[f64; D]]) -> ([f64; D], [f64; D]) {
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

/// The multi-indices of a grid with `lens` points per axis, the first axis fastest.
pub(crate) fn odometer<const D: usize>(lens: [usize; D]) -> impl Iterator<Item = [usize; D]> {
    let count: usize = lens.iter().product();
    let mut at = [0; D];
    (0..count).map(move |_| {
        let here = at;
        for (i, &len) in at.iter_mut().zip(&lens) {
            *i += 1;
            if *i < len {
                break;
            }
            *i = 0;
        }
        here
    })
}

/// Every index within the degree, or the first that is not as [`SolidError::Index`].
fn check_index<const D: usize>(degree: [usize; D], index: [usize; D]) -> Result<(), SolidError> {
    match index.iter().zip(&degree).find(|(i, d)| i > d) {
        Some((&index, &d)) => Err(SolidError::Index { index, len: d + 1 }),
        None => Ok(()),
    }
}

impl<const D: usize> Solid<D>
where
    Dim<D>: Dimension<D>,
{
    /// The largest magnitude of a control point coordinate (x, y, z or ξ): far beyond any model,
    /// and small enough that no evaluation overflows (Bernstein sums stay below 2^16 · 10^12).
    pub const MAX_COORDINATE: f64 = MAX_COORDINATE;

    /// A solid on the regular grid over the box `[min, max]` with `ξ(P_I) = xi(I)`.
    ///
    /// # Errors
    ///
    /// [`SolidError`] for a degree out of range, a non-finite value or an empty box.
    pub fn regular(
        degree: [usize; D],
        min: Point<D>,
        max: Point<D>,
        mut xi: impl FnMut([usize; D]) -> f64,
    ) -> Result<Self, SolidError> {
        let (lo, hi) = (Dim::<D>::coords(min), Dim::<D>::coords(max));
        let net = Tensor::from_fn(degree, |index| {
            let x = core::array::from_fn(|c| {
                let t = index[c] as f64 / degree[c] as f64;
                lo[c] + (hi[c] - lo[c]) * t
            });
            Dim::<D>::control(x, xi(index))
        })?;
        Self::try_from_net(net)
    }

    /// A solid from a control net with finite values: a regular grid, or a space mapping.
    ///
    /// # Errors
    ///
    /// [`SolidError::NonFinite`] or [`SolidError::OutOfRange`] for a bad coordinate.
    pub fn try_from_net(net: Tensor<Control<D>, D>) -> Result<Self, SolidError> {
        check_values(net.points().iter().flat_map(|&c| {
            let (x, xi) = Dim::<D>::split(c);
            x.into_iter().chain([xi])
        }))?;
        let mut solid = Self {
            net,
            min: [0.0; D],
            max: [1.0; D],
            map: None,
        };
        solid.remap();
        Ok(solid)
    }

    /// Recognise a regular grid or build the inverse map, after the net's coordinates changed.
    fn remap(&mut self) {
        let spatial = self.net.spatial();
        if let Some((min, max)) = regular_box(self.net.dims(), &spatial) {
            (self.min, self.max) = (min, max);
            self.map = None;
        } else {
            (self.min, self.max) = point_bounds(&spatial);
            self.map = Some(LazyMap::default());
        }
    }

    /// The inverse map of a space mapping (built on the first call that needs it); `None` on a
    /// regular grid.
    #[must_use]
    pub fn inverse(&self) -> Option<&InverseMap<D>> {
        self.map.as_ref().map(|map| map.get(&self.net))
    }

    /// Whether the net is a space mapping (not a regular grid), without building its inverse map.
    #[must_use]
    pub fn is_space_mapped(&self) -> bool {
        self.map.is_some()
    }

    /// Says that about `queries` evaluations of `f` are coming, before the first (see
    /// [`InverseMap::plan`]); nothing for a regular grid.
    pub fn plan(&self, queries: usize) {
        if let Some(map) = self.inverse() {
            map.plan(queries);
        }
    }

    /// Says that the solid's map takes `share` of the commands to come, with other maps (see
    /// [`InverseMap::share`]); nothing for a regular grid.
    pub fn share(&self, share: Share) {
        if let Some(map) = self.inverse() {
            map.share(share);
        }
    }

    /// [`Solid::plan`], with the work of every query fixed at the plan's share (see
    /// [`InverseMap::fix_query_work`]): what a mesh that samples points twice needs.
    pub fn fix_query_work(&self, queries: usize) {
        if let Some(map) = self.inverse() {
            map.fix_query_work(queries);
        }
    }

    /// How many evaluations of `f` so far ran out of their work budget where the net folds very
    /// many times over ([`InverseMap::exhausted`]); 0 for a regular grid.
    #[must_use]
    pub fn exhausted(&self) -> usize {
        self.map
            .as_ref()
            .and_then(|map| map.0.get())
            .map_or(0, InverseMap::exhausted)
    }

    /// The solid of the same `S_ξ` on the regular grid over the unit box: the solid in parameter
    /// space.
    #[must_use]
    pub fn in_parameter_space(&self) -> Self {
        let net = Tensor::from_fn(self.degree(), |index| {
            let x = core::array::from_fn(|c| index[c] as f64 / self.net.degree()[c] as f64);
            Dim::<D>::control(x, Dim::<D>::split(self.net[index]).1)
        })
        .unwrap_or_else(|_| unreachable!("the degree of a valid net"));
        Self {
            net,
            min: [0.0; D],
            max: [1.0; D],
            map: None,
        }
    }

    /// The parameters of `p` under the regular grid's scaling (any point, inside or not).
    fn scaled(&self, p: [f64; D]) -> [f64; D] {
        core::array::from_fn(|c| (p[c] - self.min[c]) / (self.max[c] - self.min[c]))
    }

    /// `f(p)` with the number of preimages of `p` and the parameters `f` was taken at, by `method`
    /// (the regular grid's scaling ignores it).
    #[must_use]
    pub fn evaluate(&self, p: Point<D>, method: Method) -> Value<D> {
        self.evaluate_seeded(Dim::<D>::coords(p), method, None)
    }

    fn evaluate_seeded(&self, p: [f64; D], method: Method, seed: Option<[f64; D]>) -> Value<D> {
        match self.inverse() {
            None => {
                let t = self.scaled(p);
                let inside = t.iter().all(|&x| (0.0..=1.0).contains(&x));
                Value {
                    f: clip(Dim::<D>::split(self.net.eval(t)).1, t),
                    preimages: usize::from(inside),
                    u: t,
                    exhausted: false,
                }
            }
            Some(map) => map.f_seeded(
                &self.net,
                p,
                method,
                seed,
                INVERSE_ACCURACY,
                &mut QueryStats::default(),
            ),
        }
    }

    /// Space mapping: move control point `P_I` to `x` (ξ unchanged).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] past the end of the net, [`SolidError::NonFinite`] or
    /// [`SolidError::OutOfRange`] for a bad coordinate; the solid is unchanged then.
    pub fn set_point(&mut self, index: [usize; D], x: Point<D>) -> Result<(), SolidError> {
        let x = Dim::<D>::coords(x);
        check_values(x.into_iter())?;
        check_index(self.degree(), index)?;
        let p = &mut self.net[index];
        *p = Dim::<D>::control(x, Dim::<D>::split(*p).1);
        self.remap();
        Ok(())
    }

    /// The control points whose index along `axis` is `index` (a row of a patch, a slice of a
    /// volume), or [`SolidError::Index`] past the end.
    fn layer(&self, axis: Axis, index: usize) -> Result<Vec<[usize; D]>, SolidError> {
        let a = axis.index();
        let len = if a < D { self.net.dims()[a] } else { 0 };
        if index >= len {
            return Err(SolidError::Index { index, len });
        }
        Ok((0..self.net.points().len())
            .map(|k| multi_index(self.net.dims(), k))
            .filter(|at| at[a] == index)
            .collect())
    }

    /// Space mapping on a whole layer: every control point whose index along `axis` is `index` (a
    /// row of a patch, a slice of a volume) moved by `delta`.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a layer past the end or an axis the net does not have,
    /// [`SolidError::NonFinite`] or [`SolidError::OutOfRange`] for a coordinate it would produce;
    /// the solid is unchanged then.
    pub fn move_layer(
        &mut self,
        axis: Axis,
        index: usize,
        delta: Point<D>,
    ) -> Result<(), SolidError> {
        let layer = self.layer(axis, index)?;
        let delta = Dim::<D>::coords(delta);
        let moved: Vec<([f64; D], f64)> = layer
            .iter()
            .map(|&at| {
                let (x, xi) = Dim::<D>::split(self.net[at]);
                (core::array::from_fn(|c| x[c] + delta[c]), xi)
            })
            .collect();
        check_values(moved.iter().flat_map(|(x, _)| x.iter().copied()))?;
        for (&at, (x, xi)) in layer.iter().zip(moved) {
            self.net[at] = Dim::<D>::control(x, xi);
        }
        self.remap();
        Ok(())
    }

    /// Function mapping on a whole layer: ξ of every control point whose index along `axis` is
    /// `index` set to `xi` (a row of a patch; the slice the paper's interface opens in the patch
    /// editor).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a layer past the end or an axis the net does not have,
    /// [`SolidError::NonFinite`] or [`SolidError::OutOfRange`] for a bad value; the solid is
    /// unchanged then.
    pub fn set_layer_xi(&mut self, axis: Axis, index: usize, xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        for at in self.layer(axis, index)? {
            let (x, _) = Dim::<D>::split(self.net[at]);
            self.net[at] = Dim::<D>::control(x, xi);
        }
        Ok(())
    }

    /// The control net.
    #[must_use]
    pub fn net(&self) -> &Tensor<Control<D>, D> {
        &self.net
    }

    /// The degree along each axis.
    #[must_use]
    pub fn degree(&self) -> [usize; D] {
        self.net.degree()
    }

    /// The box `[min, max]` of the control grid (the solid's domain); for a space mapping, the
    /// bounds of the control points, which contain the image.
    #[must_use]
    pub fn domain(&self) -> (Point<D>, Point<D>) {
        (Dim::<D>::point(self.min), Dim::<D>::point(self.max))
    }

    /// The parameters of the point `p`: a scaling on a regular grid; for a space mapping, the
    /// preimage that gives `f` (or the continuation's parameters where there is none).
    #[must_use]
    pub fn to_param(&self, p: Point<D>) -> Point<D> {
        match self.map {
            None => Dim::<D>::point(self.scaled(Dim::<D>::coords(p))),
            Some(_) => Dim::<D>::point(self.evaluate(p, Method::Fast).u),
        }
    }

    /// ξ of control point `P_I`, `None` past the end of the net.
    #[must_use]
    pub fn xi(&self, index: [usize; D]) -> Option<f64> {
        self.net.get(index).map(|c| Dim::<D>::split(c).1)
    }

    /// Function mapping: set ξ of control point `P_I` (moves it along its vertical line).
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] past the end of the net, [`SolidError::NonFinite`] for NaN or
    /// infinity, [`SolidError::OutOfRange`] beyond [`Solid::MAX_COORDINATE`]; the solid is
    /// unchanged then.
    pub fn set_xi(&mut self, index: [usize; D], xi: f64) -> Result<(), SolidError> {
        check_values(core::iter::once(xi))?;
        check_index(self.degree(), index)?;
        let (x, _) = Dim::<D>::split(self.net[index]);
        self.net[index] = Dim::<D>::control(x, xi);
        Ok(())
    }

    /// The scalar net `S_ξ`: the ξ coordinates of the control points.
    #[must_use]
    pub fn xi_net(&self) -> Tensor<f64, D> {
        self.net.map(|c| Dim::<D>::split(c).1)
    }

    /// The defining function `f(p) = S_ξ(t) & F_s(t)`: positive inside the solid, negative outside,
    /// and negative everywhere outside the domain (for a space mapping: the largest over the
    /// preimages of `p`, by [`Method::Fast`]).
    #[must_use]
    pub fn f(&self, p: Point<D>) -> f64 {
        self.evaluate(p, Method::Fast).f
    }

    /// `f(p)` and its gradient `∇f(p)` (the chain rule through the clipping and the scaling, or the
    /// inverse Jacobian of a space mapping at the preimage that gives `f`).
    #[must_use]
    pub fn f_with_gradient(&self, p: Point<D>) -> (f64, Point<D>) {
        let t = Dim::<D>::coords(self.to_param(p));
        let e = self.net.forward(t);
        let (f, g) = clip_with_gradient(e.xi, e.dxi, t);
        let g = match self.map {
            None => core::array::from_fn(|c| g[c] / (self.max[c] - self.min[c])),
            Some(_) => to_space_gradient(&e.jac, g),
        };
        (f, Dim::<D>::point(saturated(g)))
    }

    /// `f` at every point of the grid `xs[0] × xs[1] × …`, the first axis fastest (a patch's
    /// `(xs[a], ys[b])` at `b·|xs| + a`, a volume's `(xs[a], ys[b], zs[c])` at
    /// `(c·|ys| + b)·|xs| + a`), by grid evaluation (a space mapping: Newton seeded from the
    /// previous point's parameters, each row's first point from the previous row's, verified,
    /// clipping where that fails).
    #[must_use]
    pub fn f_grid(&self, axes: [&[f64]; D]) -> Vec<f64> {
        self.f_grid_in_steps(axes, |_, _| {})
    }

    /// [`Self::f_grid`], calling `progress(done, total)` as each layer along the last axis is
    /// begun, `done` layers being finished, out of `total` (a space mapping's grid: its points
    /// each need the inverse map).
    #[must_use]
    pub fn f_grid_in_steps(
        &self,
        axes: [&[f64]; D],
        mut progress: impl FnMut(usize, usize),
    ) -> Vec<f64> {
        self.f_grid_reporting(axes, &mut progress)
    }

    /// [`Self::f_grid_in_steps`] compiled once, here, whatever the caller's `progress` (the
    /// inverse map's work is not made again, unoptimised, in a caller's crate).
    fn f_grid_reporting(
        &self,
        axes: [&[f64]; D],
        progress: &mut dyn FnMut(usize, usize),
    ) -> Vec<f64> {
        let count = axes.iter().map(|a| a.len()).product();
        let lens = axes.map(<[f64]>::len);
        if self.map.is_some() {
            self.plan(count);
            let mut out = Vec::with_capacity(count);
            let mut row_seed = None;
            let mut seed = None;
            let layer = count / lens[D - 1].max(1);
            for (k, at) in odometer(lens).enumerate() {
                let p = core::array::from_fn(|c| axes[c][at[c]]);
                let first = at[0] == 0;
                if first {
                    seed = row_seed;
                }
                if layer > 0 && k % layer == 0 && k > 0 {
                    progress(k / layer, lens[D - 1]);
                }
                let v = self.evaluate_seeded(p, Method::Fast, seed);
                seed = Some(v.u);
                if first {
                    row_seed = seed;
                }
                debug_assert_eq!(out.len(), k);
                out.push(v.f);
            }
            return out;
        }
        let ts: [Vec<f64>; D] = core::array::from_fn(|c| {
            let (lo, hi) = (self.min[c], self.max[c]);
            axes[c].iter().map(|x| (x - lo) / (hi - lo)).collect()
        });
        let mut values = self
            .xi_net()
            .eval_grid(ts.each_ref().map(|t: &Vec<f64>| t.as_slice()));
        // The clipping box F_s(t) = F_b(t_0) & F_b(t_1) & … in the paper's order: the box of every
        // axis but the last once per row of the grid's last axis, then the last axis's strip and
        // S_ξ per point (the same operations as `clip` at each point, fewer of them).
        let strips: [Vec<f64>; D] =
            core::array::from_fn(|c| ts[c].iter().map(|&t| strip(t)).collect());
        let Some((last, first)) = strips.split_last() else {
            return values;
        };
        let prefix = first.split_first().map(|(head, rest)| {
            rest.iter().fold(head.clone(), |prefix, axis| {
                axis.iter()
                    .flat_map(|&b| prefix.iter().map(move |&p| intersect(p, b)))
                    .collect()
            })
        });
        match prefix {
            Some(prefix) => {
                for (row, &b) in values.chunks_mut(prefix.len().max(1)).zip(last) {
                    for (s, &p) in row.iter_mut().zip(&prefix) {
                        *s = clip_to_box(*s, intersect(p, b));
                    }
                }
            }
            None => {
                for (s, &b) in values.iter_mut().zip(last) {
                    *s = clip_to_box(*s, b);
                }
            }
        }
        values
    }
}

impl Solid<2> {
    /// The first paper's Fig. 9 after its three steps: a 3×3 grid (degree 2) over the unit square,
    /// flat at ξ = 0.25, the four corners pulled down to −1 and the centre pulled up to +1: one blob
    /// in the middle of the square.
    #[must_use]
    pub fn fig9() -> Self {
        Self::regular([2, 2], DVec2::ZERO, DVec2::ONE, |index| match index {
            [1, 1] => 1.0,
            [0 | 2, 0 | 2] => -1.0,
            _ => 0.25,
        })
        .unwrap_or_else(|_| unreachable!("the Fig. 9 preset is a valid regular grid"))
    }
}

impl Solid<3> {
    /// The slice of the control net with `index` along `axis`, as a 2D solid in the slice's plane:
    /// points `(a, b, ξ)` with `a, b` the coordinates of the two other axes in increasing order
    /// (x y across `W`, x z across `V`, y z across `U`): the paper's cross-section chooser (Fig. 11).
    /// `None` past the net.
    #[must_use]
    pub fn slice(&self, axis: Axis, index: usize) -> Option<Solid<2>> {
        let (a, b) = axis.others();
        let (a, b) = (a.index(), b.index());
        let patch = self.net.slice(axis, index)?;
        Solid::try_from_net(patch.map(|v| glam::DVec3::new(v[a], v[b], v.w))).ok()
    }

    /// Writes a slice edited in its plane back into the net (the inverse of [`Solid::slice`]): the
    /// slice's two coordinates and ξ replace those of the control points with `index` along
    /// `axis`; the third coordinate is kept.
    ///
    /// # Errors
    ///
    /// [`SolidError::Index`] for a slice past the net, [`SolidError::Patch`] when the slice's degree
    /// is not that of the two other axes; the solid is unchanged then.
    pub fn set_slice(
        &mut self,
        axis: Axis,
        index: usize,
        slice: &Solid<2>,
    ) -> Result<(), SolidError> {
        let Some(mut layer) = self.net.slice(axis, index) else {
            let len = self.net.dims()[axis.index()];
            return Err(SolidError::Index { index, len });
        };
        if layer.degree() != slice.degree() {
            return Err(PatchError::PointCount {
                expected: layer.points().len(),
                got: slice.net.points().len(),
            }
            .into());
        }
        let (a, b) = axis.others();
        let (a, b) = (a.index(), b.index());
        for (flat, s) in slice.net.points().iter().enumerate() {
            let at = multi_index(layer.dims(), flat);
            let v = &mut layer[at];
            (v[a], v[b], v.w) = (s.x, s.y, s.z);
        }
        let mut net = self.net.clone();
        net.set_slice(axis, index, &layer)?;
        *self = Self::try_from_net(net)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rfunc::{clip2, clip3};
    use crate::tensor::Volume;
    use crate::testutil::Rng;
    use glam::DVec3;
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
        let s = Solid2::regular([3, 4], min, max, |[_, _]| rng.range(-1.0, 1.0)).unwrap();
        for _ in 0..100 {
            let uv = DVec2::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let point = s.net().eval([uv.x, uv.y]);
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
            [3, 4],
            DVec2::new(-2.0, 1.0),
            DVec2::new(3.0, 1.5),
            |[_, _]| rng.range(-1.0, 1.0),
        )
        .unwrap();
        let xs = [-2.5, -1.0, 0.1, 2.2, 3.3];
        let ys = [0.9, 1.1, 1.25, 1.45];
        let grid = s.f_grid([&xs, &ys]);
        for (b, &y) in ys.iter().enumerate() {
            for (a, &x) in xs.iter().enumerate() {
                assert!((grid[b * xs.len() + a] - s.f(DVec2::new(x, y))).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn solid_moved_points_are_a_space_mapping_and_nan_is_rejected() {
        let mut patch = Solid2::fig9().net().clone();
        patch[[1, 1]].x += 0.1;
        let mapped = Solid2::try_from_net(patch.clone()).unwrap();
        assert!(mapped.inverse().is_some());
        assert!(Solid2::fig9().inverse().is_none());
        patch[[1, 1]].x = f64::NAN;
        assert_eq!(Solid2::try_from_net(patch), Err(SolidError::NonFinite));
        let mut s = Solid2::fig9();
        assert_eq!(s.set_xi([0, 0], f64::INFINITY), Err(SolidError::NonFinite));
        assert_eq!(s.set_xi([0, 0], 1e200), Err(SolidError::OutOfRange));
        assert_eq!(s, Solid2::fig9());
    }

    #[test]
    fn solid3_regular_is_a_scaling_and_grid_matches() {
        let mut rng = Rng::new(32);
        let (min, max) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 3.0, 2.5));
        let s = Solid3::regular([2, 3, 4], min, max, |[_, _, _]| rng.range(-1.0, 1.0)).unwrap();
        for _ in 0..50 {
            let t = DVec3::new(
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            );
            let q = s.net().eval([t.x, t.y, t.z]);
            let p = min + (max - min) * t;
            assert!(
                (q.truncate() - p).abs().max_element() < 1e-12,
                "linear precision"
            );
            assert!((s.f(p) - clip3(q.w, t.x, t.y, t.z)).abs() < 1e-12);
        }
        let (xs, ys, zs) = ([-1.2, 0.3, 0.9], [0.0, 1.7], [1.9, 2.2, 2.4, 2.6]);
        let grid = s.f_grid([&xs, &ys, &zs]);
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
        let s = Solid3::regular([1, 1, 1], DVec3::ZERO, DVec3::ONE, |[_, _, _]| 1.0).unwrap();
        let mut points = s.net().points().to_vec();
        points[3].z += 0.2;
        let moved = Solid3::try_from_net(Volume::try_new([1, 1, 1], points).unwrap()).unwrap();
        assert!(moved.inverse().is_some());
        // A flat box is a degenerate net: defined values, no solid.
        let flat = Solid3::regular(
            [1, 1, 1],
            DVec3::ZERO,
            DVec3::new(1.0, 1.0, 0.0),
            |[_, _, _]| 1.0,
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
            [3, 2],
            DVec2::new(-1.0, 0.0),
            DVec2::new(2.0, 1.0),
            |[_, _]| rng.range(-1.0, 1.0),
        )
        .unwrap();
        let mut s = original.clone();
        let at = s.net()[[1, 1]].truncate();
        s.set_point([1, 1], at + DVec2::new(0.3, -0.1)).unwrap();
        assert!(s.inverse().is_some());
        let p = DVec2::new(0.2, 0.4);
        assert_ne!(s.f(p), original.f(p));
        s.move_layer(Axis::V, 2, DVec2::new(0.0, 0.5)).unwrap();
        assert_eq!(s.net()[[3, 2]].y, 1.5);
        assert_eq!(
            s.set_point([4, 0], DVec2::ZERO),
            Err(SolidError::Index { index: 4, len: 4 })
        );
        assert_eq!(
            s.move_layer(Axis::U, 0, DVec2::new(f64::NAN, 0.0)),
            Err(SolidError::NonFinite)
        );
        s.move_layer(Axis::V, 2, DVec2::new(0.0, -0.5)).unwrap();
        s.set_point([1, 1], at).unwrap();
        assert!(s.inverse().is_none());
        assert_eq!(s, original);
        let mut v = Solid3::regular([2, 2, 2], DVec3::ZERO, DVec3::ONE, |[i, j, k]| {
            (i + j + k) as f64 - 2.5
        })
        .unwrap();
        let before = v.clone();
        v.move_layer(Axis::W, 2, DVec3::new(0.0, 0.0, 0.5)).unwrap();
        assert!(v.inverse().is_some());
        assert_eq!(v.domain().1.z, 1.5);
        v.set_point([0, 0, 0], DVec3::splat(-0.1)).unwrap();
        v.set_point([0, 0, 0], DVec3::ZERO).unwrap();
        v.move_layer(Axis::W, 2, DVec3::new(0.0, 0.0, -0.5))
            .unwrap();
        assert_eq!(v, before);
    }

    #[test]
    fn mapped_grids_and_gradients_match_the_reference() {
        let mut rng = Rng::new(34);
        for amp in [0.08, 0.4] {
            let patch = crate::inverse::tests::warped_patch(&mut rng, [3, 3], amp);
            let s = Solid2::try_from_net(patch).unwrap();
            let (lo, hi) = s.domain();
            let xs: Vec<f64> = (0..17)
                .map(|a| lo.x - 0.1 + (hi.x - lo.x + 0.2) * a as f64 / 16.0)
                .collect();
            let ys: Vec<f64> = (0..13)
                .map(|b| lo.y - 0.1 + (hi.y - lo.y + 0.2) * b as f64 / 12.0)
                .collect();
            let grid = s.f_grid([&xs, &ys]);
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
                let p = DVec2::from_array(s.net().forward(u).x);
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
        let volume = crate::inverse::tests::warped_volume(&mut rng, [2, 3, 2], 0.1);
        let s = Solid3::try_from_net(volume).unwrap();
        let t = [-0.1, 0.3, 0.6, 1.05];
        let grid = s.f_grid([&t, &t, &t]);
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
            let degree = [rng.int(1, 16), rng.int(1, 16)];
            let size = [extent, extent * rng.range(0.5, 2.0)];
            let lo = [offset, -offset];
            let mut patch = Solid2::regular(
                degree,
                DVec2::from_array(lo),
                DVec2::from_array(lo) + DVec2::from_array(size),
                |_| rng.range(-1.0, 1.0),
            )
            .unwrap()
            .net()
            .clone();
            // Every other net is space-mapped: one inner point moved by a fraction of the box.
            let moved = trial % 2 == 1 && degree[0] <= 6 && degree[1] <= 6;
            if moved {
                let p = &mut patch[[degree[0] / 2, degree[1] / 2]];
                p.x += size[0] * 0.3;
            }
            let solid = Solid2::try_from_net(patch).unwrap();
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
            let grid = solid.f_grid([&[min.x, -f64::MAX, 1e300], &[max.y, f64::MAX]]);
            assert!(grid.iter().all(|f| f.is_finite()));
        }
        for trial in 0..12 {
            let extent = 10f64.powf(rng.range(-300.0, 11.0));
            let degree = [rng.int(1, 16), rng.int(1, 4), rng.int(1, 3)];
            let lo = [extent * rng.range(-2.0, 2.0); 3];
            let size = [extent; 3];
            let mut volume = Solid3::regular(
                degree,
                DVec3::from_array(lo),
                DVec3::from_array(lo) + extent,
                |_| rng.range(-1.0, 1.0),
            )
            .unwrap()
            .net()
            .clone();
            if trial % 2 == 1 {
                volume[[0, 0, 0]].x -= extent * 0.4;
            }
            let solid = Solid3::try_from_net(volume).unwrap();
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
        s.set_xi([1, 0], 1.0).unwrap();
        assert!(s.f(p) > before);
    }

    #[test]
    fn solid_gradients_match_finite_differences() {
        let mut rng = Rng::new(32);
        let h = 1e-6;
        for _ in 0..40 {
            let (lo2, hi2) = (DVec2::new(-1.0, 0.5), DVec2::new(2.0, 1.5));
            let s2 = Solid2::regular([3, 2], lo2, hi2, |[_, _]| rng.range(-1.0, 1.0)).unwrap();
            let (lo3, hi3) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(0.5, 2.0, 2.5));
            let s3 =
                Solid3::regular([2, 3, 2], lo3, hi3, |[_, _, _]| rng.range(-1.0, 1.0)).unwrap();
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
            let mut s = Solid2::regular([3, 2], DVec2::ZERO, DVec2::ONE, |[i, j]| {
                (i * 10 + j) as f64
            })
            .unwrap();
            s.set_layer_xi(axis, 1, -5.0).unwrap();
            for i in 0..=3 {
                for j in 0..=2 {
                    let in_row = if axis == Axis::U { i == 1 } else { j == 1 };
                    let want = if in_row { -5.0 } else { (i * 10 + j) as f64 };
                    assert_eq!(s.xi([i, j]).unwrap(), want, "{axis:?} P_{i}{j}");
                }
            }
            let before = s.clone();
            assert_eq!(
                s.set_layer_xi(axis, 4, 0.0),
                Err(SolidError::Index {
                    index: 4,
                    len: if axis == Axis::U { 4 } else { 3 }
                })
            );
            assert_eq!(
                s.set_layer_xi(axis, 0, f64::NAN),
                Err(SolidError::NonFinite)
            );
            assert_eq!(s, before);
        }
        let mut s = Solid2::fig9();
        assert_eq!(
            s.set_layer_xi(Axis::W, 0, 0.0),
            Err(SolidError::Index { index: 0, len: 0 })
        );
    }

    #[test]
    fn point_and_slice_edits_of_volumes_set_exactly_those_points() {
        let start = |[i, j, k]: [usize; 3]| (i * 100 + j * 10 + k) as f64;
        for (axis, a) in [(Axis::U, 0), (Axis::V, 1), (Axis::W, 2)] {
            let mut s = Solid3::regular([2, 3, 1], DVec3::ZERO, DVec3::ONE, start).unwrap();
            s.set_layer_xi(axis, 1, -7.0).unwrap();
            s.set_xi([2, 3, 0], 9.0).unwrap();
            for i in 0..=2 {
                for j in 0..=3 {
                    for k in 0..=1 {
                        let want = if (i, j, k) == (2, 3, 0) {
                            9.0
                        } else if [i, j, k][a] == 1 {
                            -7.0
                        } else {
                            start([i, j, k])
                        };
                        assert_eq!(s.xi([i, j, k]), Some(want), "{axis:?} P_{i}{j}{k}");
                    }
                }
            }
            assert_eq!(s.xi([3, 0, 0]), None);
            let before = s.clone();
            let len = [3, 4, 2][a];
            assert_eq!(
                s.set_layer_xi(axis, len, 0.0),
                Err(SolidError::Index { index: len, len })
            );
            assert_eq!(
                s.set_xi([0, 4, 0], 0.0),
                Err(SolidError::Index { index: 4, len: 4 })
            );
            assert_eq!(
                s.set_xi([0, 0, 0], f64::INFINITY),
                Err(SolidError::NonFinite)
            );
            assert_eq!(s.set_layer_xi(axis, 0, 1e300), Err(SolidError::OutOfRange));
            assert_eq!(s, before);
        }
    }
}
