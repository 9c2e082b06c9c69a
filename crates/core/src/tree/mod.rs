//! Models of many solids (DESIGN §5): Bézier solids beside primitives, combined by R-function set
//! operations, blends and morphs, and moved by transforms.
//!
//! A model file's `solid` may be a tree of [`SolidSpec`](crate::model::SolidSpec) nodes.
//! [`ModelFile::to_tree`](crate::model::ModelFile::to_tree) checks it (`build.rs`; caps, finite
//! numbers within their ranges, one dimension, positive radii, …; an error names the node's path, such
//! as `solid.of[2].solid.radius`) and compiles it into a [`Tree`]: its leaves, each with the affine
//! map from space to the leaf's own coordinates that the transforms above it compose to, and the
//! operations as a postfix program over them. Evaluation runs the program on a small stack, so a
//! tree of any allowed shape costs no recursion.
//!
//! Every node's `f` is the formula of DESIGN §5, with `&` and `|` the R-functions
//! `f1 & f2 = f1 + f2 − √(f1² + f2²)` and `f1 | f2 = f1 + f2 + √(f1² + f2²)` ([`crate::rfunc`]).
//! A single patch or volume is a tree of one leaf, with the same `f` and preimages.
//!
//! ```
//! use bezsolid_core::model::{ModelFile, SolidSpec};
//! use bezsolid_core::tree::ModelTree;
//!
//! // {"kind": "union", "of": [{"kind": "circle", …}, {"kind": "rectangle", …}]}
//! let file = ModelFile::from_spec(SolidSpec::Union {
//!     of: vec![
//!         SolidSpec::Circle { center: [0.0, 0.0], radius: 1.0 },
//!         SolidSpec::Rectangle { min: [0.0, -0.5], max: [2.0, 0.5] },
//!     ],
//! });
//! let ModelTree::Plane(tree) = file.to_tree().unwrap() else { unreachable!() };
//! assert!(tree.f(glam::DVec2::new(1.5, 0.0)) > 0.0);
//! assert!(tree.f(glam::DVec2::new(0.0, 2.0)) < 0.0);
//! ```

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use crate::dim::{Dim, Dimension, Point};
use crate::inverse::{Method, Share};
use crate::rfunc::{intersect, union};
use crate::solid::Solid;
pub(crate) use build::{piecewise, rotation3, sin_cos};
use shape::Shape;

mod bounds;
mod build;
mod check;
mod far;
#[cfg(test)]
mod hyperfun_tests;
mod interval;
mod mesh;
mod parts;
mod remesh;
mod section;
mod shape;
mod walk;

pub use interval::Interval;
pub use mesh::{MAX_RESOLUTION, MeshStats, TreeMeshError};
pub use remesh::{MeshCache, Remeshed};
pub use section::plane_axes;

/// The deepest a tree may be: a node and its children count 2.
pub const MAX_DEPTH: usize = 32;
/// The most nodes a tree may have (every node counts, leaves and operations).
pub const MAX_NODES: usize = 256;

/// A checked tree of a model file: all 2D or all 3D.
#[derive(Clone, Debug)]
pub enum ModelTree {
    /// A 2D tree (patches, circles, rectangles, half-planes).
    Plane(Tree<2>),
    /// A 3D tree (volumes, spheres, boxes, cylinders, tori, half-spaces).
    Space(Tree<3>),
}

/// Why a tree was refused: the node's path in the model file and what is wrong there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeError {
    /// The path of the node or field, as in `solid.of[2].solid.radius`.
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for TreeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl core::error::Error for TreeError {}

fn error(path: &str, message: impl Into<String>) -> TreeError {
    TreeError {
        path: path.into(),
        message: message.into(),
    }
}

/// The determinant of a square matrix of 2 or 3 rows (1 for any other size).
fn determinant<const D: usize>(m: &[[f64; D]; D]) -> f64 {
    match D {
        2 => m[0][0] * m[1][1] - m[0][1] * m[1][0],
        3 => {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        }
        _ => 1.0,
    }
}

/// An affine map `x ↦ m·x + t` of space into a leaf's own coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine<const D: usize> {
    m: [[f64; D]; D],
    t: [f64; D],
}

impl<const D: usize> Affine<D> {
    const IDENTITY: Self = Self {
        m: {
            let mut m = [[0.0; D]; D];
            let mut i = 0;
            while i < D {
                m[i][i] = 1.0;
                i += 1;
            }
            m
        },
        t: [0.0; D],
    };

    /// The scale and the offset per axis when the map keeps the axes apart (no rotation):
    /// `q_c = scale_c · x_c + t_c`.
    fn separable(&self) -> Option<([f64; D], [f64; D])> {
        let apart = (0..D).all(|r| (0..D).all(|c| r == c || self.m[r][c] == 0.0));
        apart.then(|| (core::array::from_fn(|c| self.m[c][c]), self.t))
    }

    fn apply(&self, x: [f64; D]) -> [f64; D] {
        core::array::from_fn(|r| {
            let mut s = self.t[r];
            for (c, xc) in x.iter().enumerate() {
                s += self.m[r][c] * xc;
            }
            s
        })
    }

    /// `self ∘ other`: first `other`, then `self`.
    fn after(&self, other: &Self) -> Self {
        let m = core::array::from_fn(|r| {
            core::array::from_fn(|c| (0..D).map(|k| self.m[r][k] * other.m[k][c]).sum())
        });
        Self {
            m,
            t: self.apply(other.t),
        }
    }
}

/// A leaf and the map from space into its coordinates.
#[derive(Clone, Debug, PartialEq)]
struct Leaf<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    shape: Shape<D>,
    map: Option<Affine<D>>,
}

/// One instruction of the postfix program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Step {
    /// Push leaf `i`'s value.
    Leaf(usize),
    /// Pop `n` values, push `f1 | f2 | …`.
    Union(usize),
    /// Pop `n` values, push `f1 & f2 & …`.
    Intersection(usize),
    /// Pop `n` values, push `f1 & (−f2) & …`.
    Difference(usize),
    /// Pop 2, push `(f1 | f2)` (or `&` when not `union`) `+ a0 / (1 + (f1/a1)² + (f2/a2)²)`.
    Blend {
        union: bool,
        a0: f64,
        a1: f64,
        a2: f64,
    },
    /// Pop 2, push `(1 − t) f1 + t f2`.
    Morph(f64),
}

impl Step {
    /// How many values it takes from the stack.
    pub(crate) fn arity(self) -> usize {
        match self {
            Self::Leaf(_) => 0,
            Self::Union(n) | Self::Intersection(n) | Self::Difference(n) => n,
            Self::Blend { .. } | Self::Morph(_) => 2,
        }
    }
}

/// A checked tree of `D` dimensions, ready to evaluate.
#[derive(Clone, Debug)]
pub struct Tree<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    leaves: Vec<Leaf<D>>,
    steps: Vec<Step>,
    /// The deepest the evaluation stack gets.
    stack: usize,
    /// A box outside of which `f ≤ 0` (`None`: the solid may be unbounded).
    bounds: Option<bounds::Aabb<D>>,
    /// See [`Tree::parts_box`].
    parts: Option<bounds::Aabb<D>>,
    /// The middles of the boxes of the leaves bounded on their own, in space: where to look for
    /// an inside point ([`Tree::inside_point`]).
    middles: Vec<[f64; D]>,
    /// The parts of the bounds far apart from each other, each meshed in a box of its own (one
    /// where the solid's parts are near; none where it may be unbounded or is empty).
    clusters: Vec<bounds::Aabb<D>>,
}

/// `f` and the preimages of one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeValue {
    /// The defining function: positive inside.
    pub f: f64,
    /// The number of preimages summed over the Bézier leaves.
    pub preimages: usize,
    /// Whether a Bézier leaf's query ran out of its work budget (a net that folds very many
    /// times): its preimages, and so `f`, may be incomplete.
    pub exhausted: bool,
}

impl<const D: usize> Tree<D>
where
    Dim<D>: Dimension<D>,
{
    /// `f(p)` and the preimages of `p` summed over the Bézier leaves.
    #[must_use]
    pub fn evaluate(&self, p: Point<D>) -> TreeValue {
        self.evaluate_with(Dim::<D>::coords(p), &mut Vec::with_capacity(self.stack))
    }

    /// [`Tree::evaluate`] with the preimages of space-mapped leaves found by `method`: the paper's
    /// spline guess and Bézier clipping ([`Method::Hybrid`]), clipping over the whole domain
    /// ([`Method::Clipping`]) or this crate's seeded Newton ([`Method::Fast`], what
    /// [`Tree::evaluate`] uses). Regular leaves are scaled whatever the method.
    #[must_use]
    pub fn evaluate_by(&self, p: Point<D>, method: Method) -> TreeValue {
        let mut stack = Vec::with_capacity(self.stack);
        self.evaluate_steps(&self.steps, Dim::<D>::coords(p), &mut stack, method)
    }

    /// [`Tree::evaluate`] with the caller's stack (emptied first), for many points in a row.
    pub(crate) fn evaluate_with(&self, p: [f64; D], stack: &mut Vec<f64>) -> TreeValue {
        self.evaluate_program(&self.steps, p, stack)
    }

    /// [`Tree::evaluate_with`] by `steps`, the tree's program or a pruned one
    /// ([`Tree::pruned`]).
    pub(crate) fn evaluate_program(
        &self,
        steps: &[Step],
        p: [f64; D],
        stack: &mut Vec<f64>,
    ) -> TreeValue {
        self.evaluate_steps(steps, p, stack, Method::Fast)
    }

    fn evaluate_steps(
        &self,
        steps: &[Step],
        p: [f64; D],
        stack: &mut Vec<f64>,
        method: Method,
    ) -> TreeValue {
        let mut preimages = 0;
        let mut exhausted = false;
        let f = run(steps, stack, |i| {
            let (f, n, out) = self.leaves[i].value(p, method);
            preimages += n;
            exhausted |= out;
            f
        });
        TreeValue {
            f,
            preimages,
            exhausted,
        }
    }

    /// `f` on the grid of `axes` (a list of coordinates per axis), laid out as
    /// [`Solid::f_grid`] lays out its own (the first axis fastest). A Bézier leaf whose
    /// transforms keep the axes apart (moves and scales, no turn) keeps its axis-at-a-time grid
    /// path ([`Solid::f_grid`]); every other leaf is evaluated point by point. The grid is taken
    /// in slabs across the last axis, so that the leaves' values held at once stay small.
    #[must_use]
    pub fn f_grid(&self, axes: [&[f64]; D]) -> Vec<f64> {
        let lens = axes.map(<[f64]>::len);
        let count: usize = lens.iter().product();
        let mut out = Vec::with_capacity(count);
        if count == 0 {
            return out;
        }
        let layer: usize = lens[..D - 1].iter().product();
        let per = (GRID_SLAB / layer).max(1);
        let last = axes[D - 1];
        let mut values: Vec<Vec<f64>> = alloc::vec![Vec::new(); self.leaves.len()];
        let mut stack = Vec::with_capacity(self.stack);
        for start in (0..last.len()).step_by(per) {
            let mut slab = axes;
            slab[D - 1] = &last[start..(start + per).min(last.len())];
            for (leaf, v) in self.leaves.iter().zip(&mut values) {
                *v = leaf.grid(slab);
            }
            let n = layer * slab[D - 1].len();
            out.extend((0..n).map(|k| run(&self.steps, &mut stack, |i| values[i][k])));
        }
        out
    }
}

/// The most samples of a grid whose leaves' values [`Tree::f_grid`] holds at once (per leaf).
const GRID_SLAB: usize = 1 << 14;

/// Runs the postfix program `steps` on `stack` (emptied first), leaf `i`'s value being
/// `leaf(i)`; the value left on top.
fn run(steps: &[Step], stack: &mut Vec<f64>, mut leaf: impl FnMut(usize) -> f64) -> f64 {
    stack.clear();
    for step in steps {
        match *step {
            Step::Leaf(i) => stack.push(leaf(i)),
            Step::Union(n) => fold(stack, n, union),
            Step::Intersection(n) => fold(stack, n, intersect),
            Step::Difference(n) => fold(stack, n, |a, b| intersect(a, -b)),
            Step::Blend {
                union: u,
                a0,
                a1,
                a2,
            } => {
                let f2 = stack.pop().unwrap_or(f64::NAN);
                let f1 = stack.pop().unwrap_or(f64::NAN);
                let base = if u { union(f1, f2) } else { intersect(f1, f2) };
                let (r1, r2) = (f1 / a1, f2 / a2);
                stack.push(far::saturate(base + a0 / (1.0 + r1 * r1 + r2 * r2)));
            }
            Step::Morph(t) => {
                let f2 = stack.pop().unwrap_or(f64::NAN);
                let f1 = stack.pop().unwrap_or(f64::NAN);
                stack.push(morph(t, f1, f2));
            }
        }
    }
    stack.pop().unwrap_or(f64::NAN)
}

/// `(1 − t) f1 + t f2`, saturated: where the terms overflow (`|t|` up to `1e12` against values
/// up to `f64::MAX`) it is taken in units of `2⁶⁴`.
fn morph(t: f64, f1: f64, f2: f64) -> f64 {
    let v = (1.0 - t) * f1 + t * f2;
    if v.is_finite() {
        return v;
    }
    const DOWN: f64 = 1.0 / 18_446_744_073_709_551_616.0;
    let small = (1.0 - t) * (f1 * DOWN) + t * (f2 * DOWN);
    far::saturate(small * 18_446_744_073_709_551_616.0)
}

impl<const D: usize> Leaf<D>
where
    Dim<D>: Dimension<D>,
{
    /// The leaf's values on the grid of `axes` (in space), laid out as [`Tree::f_grid`]'s.
    fn grid(&self, axes: [&[f64]; D]) -> Vec<f64> {
        if let Shape::Bezier(solid, _) = &self.shape {
            let apart = self
                .map
                .map_or(Some(([1.0; D], [0.0; D])), |m| m.separable());
            if let Some((scale, shift)) = apart {
                let mapped: [Vec<f64>; D] = core::array::from_fn(|c| {
                    axes[c].iter().map(|&x| scale[c] * x + shift[c]).collect()
                });
                let mut values = solid.f_grid(core::array::from_fn(|c| mapped[c].as_slice()));
                if values.iter().any(|v| !v.is_finite()) {
                    for (v, at) in values
                        .iter_mut()
                        .zip(crate::solid::odometer(axes.map(<[f64]>::len)))
                    {
                        if !v.is_finite() {
                            *v = self.far(core::array::from_fn(|c| axes[c][at[c]]));
                        }
                    }
                }
                return values;
            }
        }
        crate::solid::odometer(axes.map(<[f64]>::len))
            .map(|at| {
                let p = core::array::from_fn(|c| axes[c][at[c]]);
                self.value(p, Method::Fast).0
            })
            .collect()
    }
}

impl<const D: usize> Tree<D>
where
    Dim<D>: Dimension<D>,
{
    /// Prepares the space-mapped leaves (and the moved cells of piecewise ones) for about
    /// `queries` evaluations (see [`Solid::plan`]): their maps share one map's budget (see
    /// [`Share`]), each by the part of the model's box its image's box covers, so that a tree of
    /// many folded nets costs what one costs.
    pub fn plan(&self, queries: usize) {
        self.share_maps();
        for leaf in &self.leaves {
            match &leaf.shape {
                Shape::Bezier(s, None) => s.plan(queries),
                Shape::Piecewise(p, None) => p.plan_cells(queries),
                Shape::Hyperfun(h) => h.plan(queries),
                _ => {}
            }
        }
    }

    /// [`Tree::plan`] with every query's work fixed at the plan's share (see
    /// [`Solid::fix_query_work`]): the values of a mesh's samples then do not depend on the
    /// order they are taken in.
    pub(crate) fn fix_query_work(&self, queries: usize) {
        self.share_maps();
        for leaf in &self.leaves {
            match &leaf.shape {
                Shape::Bezier(s, None) => s.fix_query_work(queries),
                Shape::Piecewise(p, None) => p.fix_cells_query_work(queries),
                Shape::Hyperfun(h) => h.plan(queries),
                _ => {}
            }
        }
    }

    /// Gives every map of the tree (space-mapped leaves, moved cells) its [`Share`] of the
    /// commands to come: the part of the model's box ([`Tree::parts_box`]) its image's box
    /// covers, among the sum of those parts.
    fn share_maps(&self) {
        let whole = self
            .parts
            .map(|b| (0..D).map(|c| b.hi[c] - b.lo[c]).product::<f64>())
            .filter(|v| v.is_finite() && *v > 0.0);
        // The part of the model's box a box of the leaf's own coordinates covers, in space.
        let reach = |leaf: &Leaf<D>, (lo, hi): (Point<D>, Point<D>)| -> f64 {
            let (lo, hi) = (Dim::<D>::coords(lo), Dim::<D>::coords(hi));
            let own: f64 = (0..D).map(|c| hi[c] - lo[c]).product();
            let det = leaf.map.map_or(1.0, |m| determinant(&m.m)).abs();
            match whole {
                Some(whole) if det > 0.0 => (own / det / whole).min(1.0),
                _ => 1.0,
            }
        };
        // Each map-bearing leaf with its reach, and how much it adds to the load (a piecewise
        // leaf's moved cells, each its part of the leaf's reach).
        let shares: Vec<(&Shape<D>, f64, f64)> = self
            .leaves
            .iter()
            .filter_map(|leaf| match &leaf.shape {
                Shape::Bezier(s, None) if s.is_space_mapped() => {
                    let r = reach(leaf, s.domain());
                    Some((&leaf.shape, r, r))
                }
                Shape::Piecewise(p, None) if !p.is_regular() => {
                    let r = reach(leaf, p.domain());
                    Some((&leaf.shape, r, r * p.load()))
                }
                _ => None,
            })
            .collect();
        let load = shares.iter().map(|s| s.2).sum();
        for (shape, reach, _) in shares {
            match shape {
                Shape::Bezier(s, _) => s.share(Share::new(reach, load)),
                Shape::Piecewise(p, _) => p.share(reach, load),
                _ => {}
            }
        }
    }

    /// The defining function at `p`: positive inside.
    #[must_use]
    pub fn f(&self, p: Point<D>) -> f64 {
        self.evaluate(p).f
    }

    /// `f(p)` and its gradient `∇f(p)`: the chain rule through the operations, the transforms
    /// (`∇_p = Aᵀ ∇_q` for a leaf's map `q = A p + t`) and each leaf's own gradient (a Bézier
    /// leaf's as [`Solid::f_with_gradient`] gives it).
    #[must_use]
    pub fn f_with_gradient(&self, p: Point<D>) -> (f64, Point<D>) {
        let (f, g) = self.gradient_program(&self.steps, Dim::<D>::coords(p));
        (f, Dim::<D>::point(g))
    }

    /// `f` and `∇f` at `p` by `steps`, the tree's program or a pruned one.
    pub(crate) fn gradient_program(&self, steps: &[Step], p: [f64; D]) -> (f64, [f64; D]) {
        let mut stack: Vec<(f64, [f64; D])> = Vec::with_capacity(self.stack);
        for step in steps {
            match *step {
                Step::Leaf(i) => {
                    let leaf = &self.leaves[i];
                    let q = leaf.map.map_or(p, |m| m.apply(p));
                    let (f, gq) = leaf.shape.gradient(q);
                    if !(f.is_finite() && gq.iter().all(|g| g.is_finite())) {
                        // Past the ends of the doubles: the value saturated, its slope lost.
                        stack.push((leaf.far(p), [0.0; D]));
                        continue;
                    }
                    let g = match &leaf.map {
                        None => gq,
                        Some(m) => {
                            core::array::from_fn(|j| (0..D).map(|i| m.m[i][j] * gq[i]).sum())
                        }
                    };
                    stack.push((f, g));
                }
                Step::Union(n) => fold_gradient(&mut stack, n, |a, b| {
                    let h = crate::math::hypot(a, b);
                    if h == 0.0 {
                        (0.0, 1.0, 1.0)
                    } else {
                        (union(a, b), 1.0 + a / h, 1.0 + b / h)
                    }
                }),
                Step::Intersection(n) => {
                    fold_gradient(&mut stack, n, crate::rfunc::intersect_with_partials);
                }
                Step::Difference(n) => fold_gradient(&mut stack, n, |a, b| {
                    let (f, da, db) = crate::rfunc::intersect_with_partials(a, -b);
                    (f, da, -db)
                }),
                Step::Blend {
                    union: u,
                    a0,
                    a1,
                    a2,
                } => {
                    let (f2, g2) = stack.pop().unwrap_or((f64::NAN, [f64::NAN; D]));
                    let (f1, g1) = stack.pop().unwrap_or((f64::NAN, [f64::NAN; D]));
                    let (base, d1, d2) = if u {
                        let h = crate::math::hypot(f1, f2);
                        if h == 0.0 {
                            (0.0, 1.0, 1.0)
                        } else {
                            (union(f1, f2), 1.0 + f1 / h, 1.0 + f2 / h)
                        }
                    } else {
                        crate::rfunc::intersect_with_partials(f1, f2)
                    };
                    let (r1, r2) = (f1 / a1, f2 / a2);
                    let den = 1.0 + r1 * r1 + r2 * r2;
                    let f = far::saturate(base + a0 / den);
                    let e1 = d1 - a0 * 2.0 * r1 / a1 / (den * den);
                    let e2 = d2 - a0 * 2.0 * r2 / a2 / (den * den);
                    stack.push((f, core::array::from_fn(|c| e1 * g1[c] + e2 * g2[c])));
                }
                Step::Morph(t) => {
                    let (f2, g2) = stack.pop().unwrap_or((f64::NAN, [f64::NAN; D]));
                    let (f1, g1) = stack.pop().unwrap_or((f64::NAN, [f64::NAN; D]));
                    stack.push((
                        morph(t, f1, f2),
                        core::array::from_fn(|c| (1.0 - t) * g1[c] + t * g2[c]),
                    ));
                }
            }
        }
        let (f, g) = stack.pop().unwrap_or((f64::NAN, [f64::NAN; D]));
        // Past the ends of the doubles (a leaf's slope times a huge factor) there is no useful
        // direction.
        (
            f,
            if g.iter().all(|g| g.is_finite()) {
                g
            } else {
                [0.0; D]
            },
        )
    }

    /// A box `[lo, hi]` outside of which `f ≤ 0`, by the rules of DESIGN §5 (union: the hull,
    /// intersection: the overlap, difference: the first operand, transform: the moved box) and,
    /// for blends and morphs, bounds of the operands at the level they must pass. `None` where the
    /// solid may be unbounded (a half-space or a cylinder not cut by a bounded intersection, a
    /// morph with `t` outside `[0, 1]`, a blend of a space-mapped leaf); `lo > hi` on some axis for
    /// an empty solid.
    #[must_use]
    pub fn bounds(&self) -> Option<([f64; D], [f64; D])> {
        self.bounds.map(|b| (b.lo, b.hi))
    }

    /// A box around every leaf that is bounded on its own (its zero set, moved into place),
    /// whatever the operations around them: where to look at a tree that may be unbounded (a
    /// half-space, a cylinder, a blend of a space-mapped solid), not a bound of its solid. `None`
    /// when no leaf is bounded.
    #[must_use]
    pub fn parts_box(&self) -> Option<([f64; D], [f64; D])> {
        self.parts.map(|b| (b.lo, b.hi))
    }

    /// A point inside the solid (`f > 0`) within the box `[lo, hi]` (anywhere where `None`), if
    /// one of the places looked at is: the middles of the bounds and of every leaf's own box. A
    /// witness that a mesh or contour that came out empty has lost the solid.
    #[must_use]
    pub fn inside_point(&self, within: Option<([f64; D], [f64; D])>) -> Option<(Point<D>, f64)> {
        let middle = self
            .bounds
            .filter(|b| (0..D).all(|i| b.lo[i] <= b.hi[i]))
            .map(|b| core::array::from_fn(|i| 0.5 * b.lo[i] + 0.5 * b.hi[i]));
        middle
            .into_iter()
            .chain(self.middles.iter().copied())
            .filter(|p| {
                within.is_none_or(|(lo, hi)| (0..D).all(|i| lo[i] <= p[i] && p[i] <= hi[i]))
            })
            .map(|p| (Dim::<D>::point(p), self.f(Dim::<D>::point(p))))
            .find(|&(_, f)| f > 0.0)
    }

    /// How many leaves the tree has.
    #[must_use]
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// How many of its leaves are Bézier solids.
    #[must_use]
    pub fn bezier_count(&self) -> usize {
        self.leaves
            .iter()
            .filter(|l| matches!(l.shape, Shape::Bezier(..)))
            .count()
    }

    /// The tree's one leaf when it is a single piecewise solid with no transform.
    #[must_use]
    pub fn as_piecewise(&self) -> Option<&crate::piecewise::Piecewise<D>> {
        match (&self.leaves[..], &self.steps[..]) {
            (
                [
                    Leaf {
                        shape: Shape::Piecewise(s, _),
                        map: None,
                    },
                ],
                [Step::Leaf(0)],
            ) => Some(s),
            _ => None,
        }
    }

    /// The tree's one leaf when it is a single Bézier solid with no transform.
    #[must_use]
    pub fn as_solid(&self) -> Option<&Solid<D>> {
        match (&self.leaves[..], &self.steps[..]) {
            (
                [
                    Leaf {
                        shape: Shape::Bezier(s, _),
                        map: None,
                    },
                ],
                [Step::Leaf(0)],
            ) => Some(s),
            _ => None,
        }
    }
}

/// Pops `n` values with their gradients and pushes them folded left to right by `op`, which gives
/// the value and its two partial derivatives.
fn fold_gradient<const D: usize>(
    stack: &mut Vec<(f64, [f64; D])>,
    n: usize,
    op: impl Fn(f64, f64) -> (f64, f64, f64),
) {
    let start = stack.len().saturating_sub(n);
    let mut items = stack.drain(start..);
    let first = items.next().unwrap_or((f64::NAN, [f64::NAN; D]));
    let folded = items.fold(first, |(a, ga), (b, gb)| {
        let (f, da, db) = op(a, b);
        (f, core::array::from_fn(|c| da * ga[c] + db * gb[c]))
    });
    stack.push(folded);
}

/// Pops `n` values and pushes them folded left to right by `op`.
fn fold(stack: &mut Vec<f64>, n: usize, op: impl Fn(f64, f64) -> f64) {
    let start = stack.len().saturating_sub(n);
    let folded = stack[start..]
        .iter()
        .copied()
        .reduce(op)
        .unwrap_or(f64::NAN);
    stack.truncate(start);
    stack.push(folded);
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Rotation;
    use crate::model::SolidSpec as S;
    use crate::model::{CoordAxis, ModelError, ModelFile};
    use crate::solid::Solid2;
    use crate::solid::Solid3;
    use crate::testutil::{Rng, assert_close, random_tree};
    use alloc::boxed::Box;
    use alloc::format;
    use alloc::vec;
    use glam::{DVec2, DVec3};
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    // The formulas of DESIGN §5, written out again here.
    fn and(a: f64, b: f64) -> f64 {
        a + b - (a * a + b * b).sqrt()
    }
    fn or(a: f64, b: f64) -> f64 {
        a + b + (a * a + b * b).sqrt()
    }

    fn plane(spec: S) -> Tree<2> {
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Plane(t) => t,
            ModelTree::Space(_) => panic!("a 3D tree"),
        }
    }

    fn space(spec: S) -> Tree<3> {
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => panic!("a 2D tree"),
        }
    }

    fn refused(spec: S) -> TreeError {
        match ModelFile::from_spec(spec).to_tree() {
            Err(ModelError::Tree(e)) => e,
            other => panic!("not refused as a tree: {other:?}"),
        }
    }

    /// A named part is its solid: the same f everywhere, hidden or not; its name travels through
    /// the model file; a name past the cap is refused at its path.
    #[test]
    fn a_named_part_is_its_solid() {
        let part = |hidden| S::Part {
            solid: Box::new(sphere([0.5, 0.0, 0.0], 1.0)),
            name: "wheel".into(),
            hidden,
        };
        let plain = space(S::Union {
            of: vec![sphere([0.0; 3], 0.7), sphere([0.5, 0.0, 0.0], 1.0)],
        });
        for hidden in [false, true] {
            let named = space(S::Union {
                of: vec![sphere([0.0; 3], 0.7), part(hidden)],
            });
            for p in points3(7, 200) {
                assert_eq!(named.f(p).to_bits(), plain.f(p).to_bits());
            }
            assert_eq!(named.bounds(), plain.bounds());
        }
        let file = ModelFile::from_spec(S::Union {
            of: vec![sphere([0.0; 3], 0.7), part(true)],
        });
        let json = serde_json::to_string(&file).unwrap();
        assert!(json.contains(r#""kind":"part""#) && json.contains(r#""hidden":true"#));
        assert_eq!(serde_json::from_str::<ModelFile>(&json).unwrap(), file);
        let shown = serde_json::to_string(&ModelFile::from_spec(part(false))).unwrap();
        assert!(!shown.contains("hidden"), "a shown part writes no `hidden`");
        // On other kinds `name` and `hidden` are fields no kind has: ignored, whatever they hold.
        let other: ModelFile = serde_json::from_str(
            r#"{"format": "bezsolid", "version": 1, "solid": {"name": 5, "kind": "sphere",
            "hidden": "no", "center": [0, 0, 0], "radius": 1, "name": [1]}}"#,
        )
        .unwrap();
        assert_eq!(other.solid, sphere([0.0; 3], 1.0));
        let e = refused(S::Union {
            of: vec![
                sphere([0.0; 3], 0.7),
                S::Part {
                    solid: Box::new(sphere([0.0; 3], 1.0)),
                    name: "x".repeat(crate::model::MAX_NAME_BYTES + 1),
                    hidden: false,
                },
            ],
        });
        assert_eq!(e.path, "solid.of[1].name");
    }

    /// The grid is the points: random trees (their Bézier leaves under moves and scales keep
    /// the grid path, under turns they are point by point), a moved and scaled volume, a 2D tree,
    /// and a grid of more slabs than one.
    #[test]
    fn grids_are_the_trees_values_at_their_points() {
        let close = |g: f64, f: f64| (g - f).abs() <= 1e-9 * (1.0 + f.abs());
        let mut rng = Rng::new(5);
        let xs: Vec<f64> = (0..9).map(|i| -2.0 + 0.45 * f64::from(i)).collect();
        let ys: Vec<f64> = (0..7).map(|i| -1.7 + 0.5 * f64::from(i)).collect();
        let zs: Vec<f64> = (0..6).map(|i| -1.9 + 0.7 * f64::from(i)).collect();
        let volume = {
            let v = Solid3::regular([2, 3, 2], DVec3::ZERO, DVec3::ONE, |[i, j, k]| {
                0.3 - 0.1 * (i + j + k) as f64
            })
            .unwrap();
            ModelFile::from_solid3(&v).solid
        };
        let mut trees: Vec<Tree<3>> = (0..20).map(|_| space(random_tree(&mut rng, 3))).collect();
        trees.push(space(S::Union {
            of: vec![
                S::Transform {
                    solid: Box::new(volume.clone()),
                    translate: Some(vec![-1.0, 0.5, 0.0]),
                    rotate: None,
                    scale: Some(vec![2.0, -1.0, 0.5]),
                },
                S::Transform {
                    solid: Box::new(volume),
                    translate: None,
                    rotate: Some(Rotation::Angles([0.0, 0.0, 30.0])),
                    scale: None,
                },
            ],
        }));
        for tree in &trees {
            let grid = tree.f_grid([&xs, &ys, &zs]);
            assert_eq!(grid.len(), xs.len() * ys.len() * zs.len());
            for (k, &g) in grid.iter().enumerate() {
                let (a, b, c) = (
                    k % xs.len(),
                    k / xs.len() % ys.len(),
                    k / (xs.len() * ys.len()),
                );
                let f = tree.f(DVec3::new(xs[a], ys[b], zs[c]));
                assert!(close(g, f), "at {k}: grid {g}, point {f}");
            }
        }
        // More samples than a slab: the slabs join up.
        let long: Vec<f64> = (0..200).map(|i| -2.0 + 0.02 * f64::from(i)).collect();
        let tree = &trees[20];
        let grid = tree.f_grid([&long, &long, &zs[..2]]);
        for (k, &g) in grid.iter().enumerate().step_by(997) {
            let (a, b, c) = (k % 200, k / 200 % 200, k / 40_000);
            assert!(close(g, tree.f(DVec3::new(long[a], long[b], zs[c]))));
        }
        let disc = |x: f64| S::Circle {
            center: [x, 0.2],
            radius: 0.8,
        };
        let patch = ModelFile::from_solid2(&Solid2::fig9()).solid;
        let moved = S::Transform {
            solid: Box::new(patch.clone()),
            translate: Some(vec![-1.5, 0.0]),
            rotate: None,
            scale: Some(vec![1.5, 2.0]),
        };
        let turned = S::Transform {
            solid: Box::new(patch),
            translate: None,
            rotate: Some(Rotation::Angle(20.0)),
            scale: None,
        };
        let plane2 = S::BlendUnion {
            of: vec![
                S::Union {
                    of: vec![disc(-1.0), moved, turned],
                },
                disc(1.2),
            ],
            a0: 0.3,
            a1: 1.0,
            a2: 0.5,
        };
        let plane = match ModelFile::from_spec(plane2).to_tree().unwrap() {
            ModelTree::Plane(t) => t,
            ModelTree::Space(_) => panic!("3D"),
        };
        let grid = plane.f_grid([&xs, &ys]);
        for (k, &g) in grid.iter().enumerate() {
            let f = plane.f(glam::DVec2::new(xs[k % xs.len()], ys[k / xs.len()]));
            assert!(close(g, f), "2D at {k}: grid {g}, point {f}");
        }
        assert!(plane.f_grid([&xs, &[]]).is_empty());
    }

    #[test]
    fn the_parts_box_holds_the_bounded_parts_of_an_unbounded_tree() {
        let tree = space(S::Union {
            of: vec![
                sphere([1.0, 0.0, 0.0], 0.5),
                S::Halfspace {
                    normal: [0.0, 0.0, 1.0],
                    offset: 0.0,
                },
                S::Transform {
                    solid: Box::new(sphere([0.0; 3], 1.0)),
                    translate: Some(vec![0.0, 3.0, 0.0]),
                    rotate: None,
                    scale: Some(vec![2.0, 1.0, 1.0]),
                },
            ],
        });
        assert_eq!(tree.bounds(), None, "a half-space is unbounded");
        let (lo, hi) = tree.parts_box().unwrap();
        assert_eq!((lo, hi), ([-2.0, -0.5, -1.0], [2.0, 4.0, 1.0]));
    }

    fn sphere(c: [f64; 3], r: f64) -> S {
        S::Sphere {
            center: c,
            radius: r,
        }
    }

    fn circle(c: [f64; 2], r: f64) -> S {
        S::Circle {
            center: c,
            radius: r,
        }
    }

    fn points3(seed: u64, n: usize) -> Vec<DVec3> {
        let mut rng = Rng::new(seed);
        (0..n)
            .map(|_| {
                DVec3::new(
                    rng.range(-3.0, 3.0),
                    rng.range(-3.0, 3.0),
                    rng.range(-3.0, 3.0),
                )
            })
            .collect()
    }

    #[test]
    fn every_primitive_is_its_formula() {
        let sp = space(sphere([0.5, -1.0, 2.0], 1.5));
        let bx = space(S::Box {
            min: [-1.0, -2.0, 0.0],
            max: [1.0, 0.5, 3.0],
        });
        let cyl = space(S::Cylinder {
            center: [1.0, 2.0, 3.0],
            axis: CoordAxis::Y,
            radius: 0.75,
        });
        let tor = space(S::Torus {
            center: [0.0, 0.5, -0.5],
            axis: CoordAxis::X,
            major: 2.0,
            minor: 0.5,
        });
        let half = space(S::Halfspace {
            normal: [1.0, -2.0, 0.5],
            offset: 0.25,
        });
        for p in points3(1, 200) {
            let [x, y, z] = p.to_array();
            let want = 1.5 * 1.5 - ((x - 0.5).powi(2) + (y + 1.0).powi(2) + (z - 2.0).powi(2));
            assert_close!(sp.f(p), want, 1e-12);
            let s = |v: f64, lo: f64, hi: f64| (v - lo) * (hi - v);
            let want = and(and(s(x, -1.0, 1.0), s(y, -2.0, 0.5)), s(z, 0.0, 3.0));
            assert_close!(bx.f(p), want, 1e-12);
            let want = 0.75 * 0.75 - ((x - 1.0).powi(2) + (z - 3.0).powi(2));
            assert_close!(cyl.f(p), want, 1e-12);
            let (a, b, c) = (y - 0.5, z + 0.5, x);
            let want = 0.25 - ((a * a + b * b).sqrt() - 2.0).powi(2) - c * c;
            assert_close!(tor.f(p), want, 1e-12);
            assert_close!(half.f(p), 0.25 - (x - 2.0 * y + 0.5 * z), 1e-12);
        }
        let ci = plane(circle([1.0, 1.0], 2.0));
        let re = plane(S::Rectangle {
            min: [0.0, 0.0],
            max: [1.0, 2.0],
        });
        let hp = plane(S::Halfplane {
            normal: [0.0, 1.0],
            offset: 1.0,
        });
        for p in points3(2, 100) {
            let q = p.truncate();
            assert_close!(
                ci.f(q),
                4.0 - ((q.x - 1.0).powi(2) + (q.y - 1.0).powi(2)),
                1e-12
            );
            assert_close!(re.f(q), and(q.x * (1.0 - q.x), q.y * (2.0 - q.y)), 1e-12);
            assert_close!(hp.f(q), 1.0 - q.y, 1e-12);
        }
    }

    #[test]
    fn operations_fold_left_to_right_and_agree_in_sign_with_max_and_min() {
        let parts = || {
            vec![
                sphere([0.0, 0.0, 0.0], 1.0),
                sphere([1.0, 0.0, 0.0], 0.8),
                sphere([0.0, 1.2, 0.3], 0.6),
            ]
        };
        let u = space(S::Union { of: parts() });
        let i = space(S::Intersection { of: parts() });
        let d = space(S::Difference { of: parts() });
        let leaves: Vec<Tree<3>> = parts().into_iter().map(space).collect();
        for p in points3(3, 300) {
            let f: Vec<f64> = leaves.iter().map(|t| t.f(p)).collect();
            assert_close!(u.f(p), or(or(f[0], f[1]), f[2]), 1e-12);
            assert_close!(i.f(p), and(and(f[0], f[1]), f[2]), 1e-12);
            assert_close!(d.f(p), and(and(f[0], -f[1]), -f[2]), 1e-12);
            let max = f.iter().copied().fold(f64::MIN, f64::max);
            let min = f.iter().copied().fold(f64::MAX, f64::min);
            if max.abs() > 1e-9 {
                assert_eq!(u.f(p) > 0.0, max > 0.0, "{p}");
            }
            if min.abs() > 1e-9 {
                assert_eq!(i.f(p) > 0.0, min > 0.0, "{p}");
            }
        }
    }

    #[test]
    fn blends_and_morphs_are_their_formulas() {
        let two = || vec![sphere([0.0, 0.0, 0.0], 1.0), sphere([1.5, 0.0, 0.0], 1.0)];
        let (a0, a1, a2) = (0.5, 1.5, 0.75);
        let bu = space(S::BlendUnion {
            of: two(),
            a0,
            a1,
            a2,
        });
        let bi = space(S::BlendIntersection {
            of: two(),
            a0,
            a1,
            a2,
        });
        let mo = space(S::Morph { of: two(), t: 0.3 });
        let (f1, f2) = (
            space(sphere([0.0, 0.0, 0.0], 1.0)),
            space(sphere([1.5, 0.0, 0.0], 1.0)),
        );
        for p in points3(4, 200) {
            let (g1, g2) = (f1.f(p), f2.f(p));
            let disp = a0 / (1.0 + (g1 / a1).powi(2) + (g2 / a2).powi(2));
            assert_close!(bu.f(p), or(g1, g2) + disp, 1e-12);
            assert_close!(bi.f(p), and(g1, g2) + disp, 1e-12);
            assert_close!(mo.f(p), 0.7 * g1 + 0.3 * g2, 1e-12);
        }
    }

    #[test]
    fn transforms_move_the_solid_by_t_rz_ry_rx_s() {
        let (t, r, s) = ([0.5, -1.0, 2.0], [30.0, -45.0, 60.0], [2.0, 0.5, -1.5]);
        let moved = space(S::Transform {
            solid: Box::new(S::Box {
                min: [-1.0, -1.0, -1.0],
                max: [1.0, 0.5, 2.0],
            }),
            translate: Some(t.to_vec()),
            rotate: Some(Rotation::Angles(r)),
            scale: Some(s.to_vec()),
        });
        let plain = space(S::Box {
            min: [-1.0, -1.0, -1.0],
            max: [1.0, 0.5, 2.0],
        });
        // M q for points q of the solid's own space, built from glam's rotations: f(M q) = f0(q).
        let rot = glam::DMat3::from_rotation_z(r[2].to_radians())
            * glam::DMat3::from_rotation_y(r[1].to_radians())
            * glam::DMat3::from_rotation_x(r[0].to_radians());
        for q in points3(5, 200) {
            let p = rot * (q * DVec3::from_array(s)) + DVec3::from_array(t);
            assert_close!(moved.f(p), plain.f(q), 1e-9);
        }
        // 2D: one angle, counter-clockwise; nested transforms compose (outer last).
        let inner = S::Transform {
            solid: Box::new(circle([1.0, 0.0], 0.25)),
            translate: None,
            rotate: Some(Rotation::Angle(90.0)),
            scale: None,
        };
        let outer = plane(S::Transform {
            solid: Box::new(inner),
            translate: Some(vec![10.0, 0.0]),
            rotate: None,
            scale: Some(vec![2.0, 2.0]),
        });
        // The circle's centre (1, 0) turns to (0, 1), scales to (0, 2) and moves to (10, 2);
        // its radius scales to 0.5.
        assert!(outer.f(DVec2::new(10.0, 2.0)) > 0.0);
        assert!(outer.f(DVec2::new(10.0, 2.45)) > 0.0);
        assert!(outer.f(DVec2::new(10.0, 2.55)) < 0.0);
        assert!(outer.f(DVec2::new(2.0, 0.0)) < 0.0);
    }

    #[test]
    fn a_bezier_leaf_is_the_single_solid_and_preimages_add_up() {
        let fig9 = Solid2::fig9();
        let spec = match ModelFile::from_solid2(&fig9).solid {
            s @ S::Patch { .. } => s,
            _ => unreachable!(),
        };
        let one = plane(spec.clone());
        assert!(one.as_solid().is_some());
        let two = plane(S::Union {
            of: vec![spec.clone(), circle([5.0, 5.0], 1.0), spec],
        });
        assert!(two.as_solid().is_none());
        let mut rng = Rng::new(6);
        for _ in 0..100 {
            let p = DVec2::new(rng.range(-0.5, 1.5), rng.range(-0.5, 1.5));
            let v = fig9.evaluate(p, Method::Fast);
            let t = one.evaluate(p);
            assert_eq!((t.f, t.preimages), (v.f, v.preimages));
            let c = 1.0 - ((p.x - 5.0).powi(2) + (p.y - 5.0).powi(2));
            assert_close!(two.f(p), or(or(v.f, c), v.f), 1e-12);
            assert_eq!(two.evaluate(p).preimages, 2 * v.preimages);
        }
    }

    #[test]
    fn numbers_that_f64_cannot_evaluate_are_refused_by_their_path() {
        let scaled = |solid: S, scale: f64| S::Transform {
            solid: Box::new(solid),
            translate: None,
            rotate: None,
            scale: Some(vec![scale; 3]),
        };
        // A sphere of radius 1e200 cut by a unit sphere gave NaN at the origin.
        let e = refused(S::Intersection {
            of: vec![sphere([0.0; 3], 1.0), sphere([0.0; 3], 1e200)],
        });
        assert_eq!(
            alloc::format!("{e}"),
            "solid.of[1].radius: 1e200 is too large: at most 1e12 in magnitude"
        );
        // Two unit spheres at 2e154 gave NaN everywhere.
        let e = refused(S::Union {
            of: vec![
                sphere([2e154, 0.0, 0.0], 1.0),
                sphere([2e154, 3.0, 0.0], 1.0),
            ],
        });
        assert_eq!(e.path, "solid.of[0].center[0]");
        let e = refused(S::Box {
            min: [-1e300; 3],
            max: [1e300; 3],
        });
        assert_eq!(e.path, "solid.min[0]");
        // A scale of 1e-300 gave −inf; 1e160 a NaN volume.
        let e = refused(scaled(sphere([0.0; 3], 1.0), 1e-300));
        assert_eq!(e.path, "solid.scale[0]");
        assert!(e.message.contains("too small"), "{e}");
        assert_eq!(
            refused(scaled(sphere([0.0; 3], 1.0), 1e160)).path,
            "solid.scale[0]"
        );
        // Scales that are each fine but multiply past the range, named where they pass it.
        let e = refused(scaled(scaled(scaled(sphere([0.0; 3], 1.0), 1e5), 1e5), 1e5));
        assert_eq!(e.path, "solid.solid.solid.scale", "{e}");
        assert!(e.message.contains("1e15 overall"), "{e}");
        // Blends and morphs with their parameters past the range.
        let two = || vec![sphere([0.0; 3], 1.0), sphere([1.0, 0.0, 0.0], 1.0)];
        let e = refused(S::BlendUnion {
            of: two(),
            a0: 1e13,
            a1: 1.0,
            a2: 1.0,
        });
        assert_eq!(e.path, "solid.a0");
        let e = refused(S::BlendUnion {
            of: two(),
            a0: 1.0,
            a1: 1e-13,
            a2: 1.0,
        });
        assert_eq!(e.path, "solid.a1");
        assert_eq!(refused(S::Morph { of: two(), t: 1e13 }).path, "solid.t");
        // At the edges, accepted.
        space(scaled(scaled(sphere([1e12, 0.0, 0.0], 1e12), 1e6), 1e6));
        space(scaled(sphere([0.0; 3], 1e-12), 1e-12));
    }

    #[test]
    fn bad_trees_are_refused_with_the_node_path() {
        let e = refused(S::Union {
            of: vec![
                sphere([0.0; 3], 1.0),
                S::Transform {
                    solid: Box::new(sphere([0.0; 3], 0.0)),
                    translate: None,
                    rotate: None,
                    scale: None,
                },
            ],
        });
        assert_eq!(e.path, "solid.of[1].solid.radius");
        let e = refused(S::Union {
            of: vec![sphere([0.0; 3], 1.0), circle([0.0; 2], 1.0)],
        });
        assert_eq!(e.path, "solid.of[1]");
        assert!(e.message.contains("2D node in a 3D tree"), "{e}");
        let e = refused(S::Intersection {
            of: vec![sphere([f64::NAN, 0.0, 0.0], 1.0), sphere([0.0; 3], 1.0)],
        });
        assert_eq!(e.path, "solid.of[0].center[0]");
        let e = refused(S::Transform {
            solid: Box::new(sphere([0.0; 3], 1.0)),
            translate: None,
            rotate: None,
            scale: Some(vec![1.0, 0.0, 1.0]),
        });
        assert_eq!(e.path, "solid.scale[1]");
        let e = refused(S::Transform {
            solid: Box::new(sphere([0.0; 3], 1.0)),
            translate: Some(vec![1.0, 2.0]),
            rotate: None,
            scale: None,
        });
        assert_eq!(e.path, "solid.translate");
        let e = refused(S::Morph {
            of: vec![sphere([0.0; 3], 1.0)],
            t: 0.5,
        });
        assert_eq!(e.path, "solid.of");
        let e = refused(S::BlendUnion {
            of: vec![sphere([0.0; 3], 1.0), sphere([1.0; 3], 1.0)],
            a0: 1.0,
            a1: 0.0,
            a2: 1.0,
        });
        assert_eq!(e.path, "solid.a1");
        let e = refused(S::Union {
            of: vec![
                sphere([0.0; 3], 1.0),
                S::Esc {
                    expression: None,
                    operation: None,
                    operands: Vec::new(),
                },
            ],
        });
        assert_eq!(e.path, "solid.of[1]");
        let e = refused(S::Union { of: Vec::new() });
        assert_eq!(e.path, "solid");
    }

    #[test]
    fn the_caps_hold_for_deep_and_wide_trees() {
        let mut deep = sphere([0.0; 3], 1.0);
        for _ in 0..MAX_DEPTH - 1 {
            deep = S::Transform {
                solid: Box::new(deep),
                translate: Some(vec![0.01, 0.0, 0.0]),
                rotate: None,
                scale: None,
            };
        }
        let t = space(deep.clone());
        assert!(t.f(DVec3::new(0.31, 0.0, 0.0)) > 0.0);
        let too_deep = S::Transform {
            solid: Box::new(deep),
            translate: None,
            rotate: None,
            scale: None,
        };
        let e = refused(too_deep);
        assert!(e.message.contains("deep"), "{e}");
        let wide = S::Union {
            of: (0..MAX_NODES - 1)
                .map(|i| sphere([i as f64, 0.0, 0.0], 0.5))
                .collect(),
        };
        let t = space(wide);
        assert_eq!(t.leaf_count(), MAX_NODES - 1);
        assert!(t.f(DVec3::new(200.0, 0.0, 0.0)) > 0.0);
        let too_wide = S::Union {
            of: (0..MAX_NODES)
                .map(|i| sphere([i as f64, 0.0, 0.0], 0.5))
                .collect(),
        };
        let e = refused(too_wide);
        assert_eq!(e.path, format!("solid.of[{}]", MAX_NODES - 1));
    }

    #[cfg(feature = "serde")]
    #[test]
    fn piecewise_solids_read_and_write_as_model_files_and_say_what_is_wrong() {
        use alloc::string::ToString;
        // Two quadratic-by-linear cells along u over [0, 2] × [0, 1], as DESIGN writes them.
        let points: Vec<String> = (0..5)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| {
                format!(
                    "[{}, {j}, {}]",
                    f64::from(i) / 2.0,
                    if i == 2 { 1 } else { -1 }
                )
            })
            .collect();
        let text = format!(
            r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "piecewise",
                "cells": [2, 1], "degree": [2, 1], "points": [{}]}}}}"#,
            points.join(", ")
        );
        let file: ModelFile = serde_json::from_str(&text).unwrap();
        let ModelTree::Plane(tree) = file.to_tree().unwrap() else {
            panic!("a 2D tree")
        };
        let solid = tree.as_piecewise().expect("one piecewise leaf");
        assert_eq!((solid.cells(), solid.degree()), ([2, 1], [2, 1]));
        assert!(solid.is_regular());
        // ξ = 1 only at the shared column x = 1: inside there, not clipped.
        assert!(tree.f(glam::DVec2::new(1.0, 0.5)) > 0.0);
        assert!(tree.f(glam::DVec2::new(0.2, 0.5)) < 0.0);
        assert!(
            file.to_solid()
                .unwrap_err()
                .to_string()
                .contains("piecewise")
        );
        let json = serde_json::to_string(&file).unwrap();
        assert!(
            json.contains(r#""kind":"piecewise","cells":[2,1]"#),
            "{json}"
        );
        assert_eq!(serde_json::from_str::<ModelFile>(&json).unwrap(), file);
        // The sequence form, as for patches.
        let seq = format!(
            r#"{{"format": "bezsolid", "version": 1, "solid": ["piecewise", [2, 1], [2, 1], [{}]]}}"#,
            points.join(", ")
        );
        assert_eq!(serde_json::from_str::<ModelFile>(&seq).unwrap(), file);
        for (solid, says) in [
            (
                r#"{"kind": "piecewise", "cells": [2, 1], "degree": [2, 1], "points": [[0, 0, 1]]}"#,
                "1 control points: these cells and degree take 10",
            ),
            (
                r#"{"kind": "piecewise", "cells": [1, 1, 1, 1], "degree": [1, 1], "points": []}"#,
                "[cu, cv, cw]",
            ),
            (
                r#"{"kind": "piecewise", "cells": [1, 1, 1], "degree": [1, 1], "points": []}"#,
                "have 3 and 2",
            ),
            (
                r#"{"kind": "piecewise", "cells": [1, 1], "degree": [1, 1],
                    "points": [[0, 0, 1], [0, 1, 1], [1, 0], [1, 1, 1]]}"#,
                "control point 2 has 2 numbers",
            ),
            (
                r#"{"kind": "piecewise", "cells": [1, 40], "degree": [1, 1], "points": []}"#,
                "40 cells along axis v",
            ),
            (
                r#"{"kind": "union", "of": [{"kind": "circle", "center": [0, 0], "radius": 1},
                    {"kind": "piecewise", "cells": [1, 1], "degree": [1, 1], "points": []}]}"#,
                "solid.of[1]: invalid piecewise solid: 0 control points",
            ),
            (
                r#"{"kind": "piecewise", "cells": [1, 1], "degree": [1, 1]}"#,
                "points",
            ),
        ] {
            let text = format!(r#"{{"format": "bezsolid", "version": 1, "solid": {solid}}}"#);
            let e = match serde_json::from_str::<ModelFile>(&text) {
                Ok(file) => file.to_tree().map(drop).unwrap_err().to_string(),
                Err(e) => e.to_string(),
            };
            assert!(e.contains(says), "{solid}: {e}");
        }
    }

    #[test]
    fn trees_read_and_write_as_model_files() {
        use alloc::string::ToString;
        let text = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "difference", "of": [
            {"of": [{"kind": "sphere", "center": [0, 0, 0], "radius": 1},
                    {"kind": "box", "min": [0, 0, 0], "max": [1, 1, 1]}],
             "kind": "blend_union", "a0": 0.5, "a1": 1, "a2": 1},
            {"kind": "transform", "rotate": [0, 90, 0], "translate": [0, 0, 1],
             "solid": {"kind": "cylinder", "center": [0, 0, 0], "axis": "z", "radius": 0.25}},
            {"kind": "morph", "t": 0.5, "of": [
                {"kind": "torus", "center": [0, 0, 0], "axis": "y", "major": 1, "minor": 0.2},
                {"kind": "halfspace", "normal": [0, 0, 1], "offset": -2, "unknown": [1, 2]}]}]}}"#;
        let file: ModelFile = serde_json::from_str(text).unwrap();
        let ModelTree::Space(tree) = file.to_tree().unwrap() else {
            panic!("a 3D tree")
        };
        assert_eq!(tree.leaf_count(), 5);
        let json = serde_json::to_string(&file).unwrap();
        assert!(json.contains(r#""kind":"blend_union""#), "{json}");
        let again: ModelFile = serde_json::from_str(&json).unwrap();
        assert_eq!(again, file);
        for (bad, says) in [
            (
                r#"{"kind": "sphere", "center": [0, 0], "radius": 1}"#,
                "has 2 numbers",
            ),
            (r#"{"kind": "sphere", "center": [0, 0, 0]}"#, "radius"),
            (
                r#"{"kind": "cylinder", "center": [0, 0, 0], "axis": "w", "radius": 1}"#,
                "w",
            ),
            (r#"{"kind": "blob"}"#, "blend_union"),
        ] {
            let text = format!(r#"{{"format": "bezsolid", "version": 1, "solid": {bad}}}"#);
            let e = serde_json::from_str::<ModelFile>(&text)
                .unwrap_err()
                .to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
        // A very deep file is refused by the reader's nesting limit, not the stack.
        let deep = "{\"kind\": \"union\", \"of\": [".repeat(10_000);
        let text = format!(r#"{{"format": "bezsolid", "version": 1, "solid": {deep}"#);
        assert!(serde_json::from_str::<ModelFile>(&text).is_err());
    }
}
