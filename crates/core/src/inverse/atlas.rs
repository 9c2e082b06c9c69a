//! An atlas of a control net's map `S: [0, 1]^D → R^D`, for nets that may fold: the parameter box
//! cut, once, into pieces on which the map is simple, with a bounding-volume tree of their images.
//!
//! Each piece keeps
//!
//! - the bounds of its image (the hull of its restricted net's control points, so exact),
//! - whether the map is *certified injective* on it: with `A` the mean of the Jacobian's Bernstein
//!   coefficients and `r` a bound on `‖J(u) − A‖` over the piece (the coefficients' largest distance
//!   from `A`, column by column), `‖A⁻¹‖ r ≤ ½` makes `S(a) − S(b) = M (a − b)` with `M` within `r`
//!   of `A`, so invertible: at most one preimage, and Newton's iteration contracts,
//! - a low-degree approximation of the map (at most [`APPROX_DEGREE`] per axis, interpolating at
//!   Chebyshev–Lobatto nodes) with a sound bound on its error: the approximation raised back to the
//!   piece's degree differs from the restricted net by at most that bound in every coefficient, so
//!   by convexity everywhere on the piece.
//!
//! The preimages of `p` are then found without touching the whole domain: walk the tree to the
//! pieces whose image bounds hold `p`; take seeds from the cheap approximation (from the centre of
//! a certified piece; elsewhere by clipping it, widened by its error bound, so that no region where
//! the true map can meet `p` is passed over); refine them by Newton's method on the approximation,
//! which costs a few dozen operations; polish what lands in the piece by Newton's method on the
//! true net. A fold runs through pieces that cannot be certified; they are cut no finer than the
//! atlas's budget, and each piece's clipping is capped, so a query near a fold costs a bounded
//! amount of work. Where two preimages merge at a fold the approximation may show one where the
//! net has two; `f` jumps there anyway.

// Coordinates index several fixed-size arrays at once; iterator chains would hide the algebra.
#![allow(clippy::needless_range_loop)]

use alloc::collections::VecDeque;
use alloc::vec;
use alloc::vec::Vec;

use super::clip::{Bernstein, ClipLimits, ClipStats, clip_seeds};
use crate::bernstein::{bernstein, binomial};

/// The largest degree per axis of a piece's approximation.
pub(crate) const APPROX_DEGREE: usize = 3;

/// A piece whose approximation errs by less than this fraction of its image's extent is not cut
/// further for the approximation's sake.
const APPROX_TOLERANCE: f64 = 0.02;

/// The contraction a certified piece guarantees: `‖A⁻¹‖ r` at most this.
const CERTIFY_RATIO: f64 = 0.5;

/// The thinnest piece along any axis, in parameters.
const MIN_WIDTH: f64 = 1.0 / (1u64 << 20) as f64;

/// How finely an atlas may cut the parameter box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct AtlasBudget {
    /// The most pieces.
    pub(crate) max_pieces: usize,
}

/// The work all the queries of a plan may spend together, in evaluations of one control point
/// (one such unit is a few instructions): about a second of one core. Maps that share a command
/// (a tree's leaves, a piecewise solid's cells) share it too (see [`Share`]).
const PLAN_WORK: u64 = 1 << 30;

/// The least work one query may spend, however many are planned or spent: a few evaluations of
/// the largest net (shared among the maps a query reaches, see [`Share`]).
const MIN_QUERY_WORK: u64 = 1 << 15;

/// The evaluations of its own net one query of a shared map may always spend, up to
/// [`MIN_QUERY_WORK`]: enough to seed and polish a few pieces of its atlas, so that a map among
/// hundreds still finds its preimages (256 folded trilinear cells lost their solid with less).
const LEAST_QUERY_EVALUATIONS: u64 = 512;

/// The most work one query may spend: about ten milliseconds (a probe of `f` under the pointer
/// runs on the page's thread), shared as [`MIN_QUERY_WORK`] is.
const MAX_QUERY_WORK: u64 = 1 << 21;

/// The cost of the finest atlas one map always gets, in control points times pieces (so a small
/// net always gets a fine atlas); maps that share a command share eight times as much.
const CHEAP_ATLAS: usize = 1 << 18;

/// One map's part of a command whose queries reach several maps: the leaves of a tree, the cells
/// of a piecewise solid. The command's work and atlases are the budget of one map, split among
/// the maps by how many of its queries each is expected to take, so that a model of 200 folded
/// leaves costs what one folded net costs, not 200 times as much.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Share {
    /// The fraction of the command's queries expected to reach the map: how much of the model's
    /// extent its image covers (at most 1).
    pub reach: f64,
    /// How many maps one query reaches on average: the sum of the maps' reaches, at least 1.
    pub load: f64,
}

impl Share {
    /// A map that has the command to itself.
    pub const WHOLE: Self = Self {
        reach: 1.0,
        load: 1.0,
    };

    /// The share of `reach` among maps whose reaches sum to `load`, both brought into range
    /// (a reach within `[2⁻³⁰, 1]`, a load at least 1 and the reach).
    #[must_use]
    pub fn new(reach: f64, load: f64) -> Self {
        let reach = if reach.is_nan() {
            1.0
        } else {
            reach.clamp(1.0 / (1u64 << 30) as f64, 1.0)
        };
        let load = if load.is_nan() {
            1.0
        } else {
            load.max(1.0).max(reach)
        };
        Self { reach, load }
    }

    /// The map's part of the command's work: `reach / load`.
    #[must_use]
    pub fn weight(self) -> f64 {
        self.reach / self.load
    }

    /// The map's part of the command's atlases: eight times its weight, at most all of it.
    fn atlas_weight(self) -> f64 {
        (8.0 * self.weight()).min(1.0)
    }
}

impl AtlasBudget {
    /// The work one of `queries` planned queries of a command may spend in a map of `share` and
    /// `points` control points when `spent` has been spent since the map was made: an equal share
    /// of [`PLAN_WORK`] among the queries and the maps each reaches while the map's part lasts,
    /// within [`MIN_QUERY_WORK`] and [`MAX_QUERY_WORK`] split among those maps (the most where
    /// nothing was planned) but no less than [`LEAST_QUERY_EVALUATIONS`] of the net; the least
    /// once the map's part is spent, so that queries past the plan (a contour's vertices after
    /// its grid) add little.
    pub(crate) fn query_work(queries: usize, spent: u64, share: Share, points: usize) -> u64 {
        let own = (LEAST_QUERY_EVALUATIONS * points as u64).min(MIN_QUERY_WORK);
        let floor = ((MIN_QUERY_WORK as f64 / share.load) as u64)
            .max(own)
            .max(1);
        let most = ((MAX_QUERY_WORK as f64 / share.load) as u64).max(floor);
        if spent as f64 >= PLAN_WORK as f64 * share.weight() {
            return floor;
        }
        if queries == 0 {
            return most;
        }
        ((PLAN_WORK as f64 / (queries as f64 * share.load)) as u64).clamp(floor, most)
    }

    /// The budget for about `queries` queries of a command on a net of dimension `dim` with
    /// `points` control points, of which the map takes `share`. Cutting a piece costs about as
    /// much as 16 queries, and both cost more the more points the net has: about one piece per
    /// 16 of the map's queries, and at least as many as a fixed cost allows (`2¹⁸ / points`, so
    /// a small net always gets a fine atlas), between 64 and 4096 (a patch, or a small volume)
    /// or 1024 (a volume whose pieces cost more to cut). Shared maps split eight such budgets by
    /// their weight (no fewer than 8 pieces each).
    pub(crate) fn for_queries(dim: usize, points: usize, queries: usize, share: Share) -> Self {
        let part = share.atlas_weight();
        let scaled = |n: usize| ((n as f64 * part) as usize).max(8);
        let most = scaled(if dim == 2 || points <= 125 {
            4096
        } else {
            1024
        });
        let cheap = scaled(CHEAP_ATLAS / points.max(1));
        let own = (queries as f64 * share.reach) as usize;
        Self {
            max_pieces: (own / 16).max(cheap).clamp(scaled(64), most),
        }
    }
}

/// A node of the tree: the bounds of its image and either two children (`first` and `first + 1`)
/// or a piece.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node<const D: usize> {
    xlo: [f64; D],
    xhi: [f64; D],
    first: u32,
    piece: bool,
}

/// A leaf of the tree: a box of parameters and what the map does on it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Piece<const D: usize> {
    /// The parameter box.
    pub(crate) lo: [f64; D],
    pub(crate) hi: [f64; D],
    /// The map is certified injective on the box.
    pub(crate) certified: bool,
    /// The map over the box's local parameters, approximated.
    approx: Bernstein<D, D>,
    /// The approximation's error bound per coordinate.
    band: [f64; D],
}

/// See the module documentation.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Atlas<const D: usize> {
    nodes: Vec<Node<D>>,
    pieces: Vec<Piece<D>>,
    /// The slack on image bounds for rounding (in space).
    slack: f64,
}

impl<const D: usize> Atlas<D> {
    /// The atlas of the spatial net `net` (coefficients over the unit box), cut within `budget`.
    pub(crate) fn build(net: &Bernstein<D, D>, budget: AtlasBudget) -> Self {
        let (lo, hi) = super::bounds(&net.coefs);
        let scale = (0..D)
            .map(|c| (hi[c] - lo[c]).max(lo[c].abs()).max(hi[c].abs()))
            .fold(0.0f64, f64::max);
        let mut atlas = Self {
            nodes: vec![Node {
                xlo: lo,
                xhi: hi,
                first: 0,
                piece: false,
            }],
            pieces: Vec::new(),
            slack: scale * 1e-12,
        };
        let mut line = Vec::new();
        let reducer = Reducer::new(net.dims);
        // Breadth first, so that the budget cuts the whole box evenly.
        let mut queue = VecDeque::from([(0usize, net.clone(), [0.0; D], [1.0; D])]);
        while let Some((index, t, lo, hi)) = queue.pop_front() {
            let shape = Shape::of(&t);
            let room = atlas.pieces.len() + queue.len() + 2 <= budget.max_pieces;
            let extent = {
                let n = &atlas.nodes[index];
                (0..D).map(|c| n.xhi[c] - n.xlo[c]).fold(0.0f64, f64::max)
            };
            // A piece that cannot be certified is cut while the budget allows, without the cost
            // of approximating it; a certified one is cut while its approximation is coarse.
            let mut approx = None;
            let split = shape.split_axis(lo, hi).filter(|_| room).filter(|_| {
                if !shape.certified {
                    return true;
                }
                let (a, band) = reducer.approximate(&t);
                let coarse = band.iter().any(|&b| b > APPROX_TOLERANCE * extent);
                approx = Some((a, band));
                coarse
            });
            match split {
                Some(axis) => {
                    let (left, right) = t.halves(axis, &mut line);
                    let mid = 0.5 * (lo[axis] + hi[axis]);
                    let first = atlas.nodes.len();
                    atlas.nodes[index].first = first as u32;
                    for (half, lo_h, hi_h) in [
                        (left, lo, with(hi, axis, mid)),
                        (right, with(lo, axis, mid), hi),
                    ] {
                        let (xlo, xhi) = super::bounds(&half.coefs);
                        queue.push_back((atlas.nodes.len(), half, lo_h, hi_h));
                        atlas.nodes.push(Node {
                            xlo,
                            xhi,
                            first: 0,
                            piece: false,
                        });
                    }
                }
                None => {
                    let (approx, band) = approx.unwrap_or_else(|| reducer.approximate(&t));
                    let node = &mut atlas.nodes[index];
                    node.piece = true;
                    node.first = atlas.pieces.len() as u32;
                    atlas.pieces.push(Piece {
                        lo,
                        hi,
                        certified: shape.certified,
                        approx,
                        band,
                    });
                }
            }
        }
        atlas
    }

    /// The number of pieces.
    pub(crate) fn len(&self) -> usize {
        self.pieces.len()
    }

    /// How many pieces are certified injective.
    pub(crate) fn certified(&self) -> usize {
        self.pieces.iter().filter(|p| p.certified).count()
    }

    /// Calls `visit` with every piece whose image bounds hold `p` (with a rounding slack).
    pub(crate) fn pieces_at(&self, p: [f64; D], mut visit: impl FnMut(&Piece<D>)) {
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = &self.nodes[i];
            let holds =
                (0..D).all(|c| p[c] >= n.xlo[c] - self.slack && p[c] <= n.xhi[c] + self.slack);
            if !holds {
                continue;
            }
            if n.piece {
                visit(&self.pieces[n.first as usize]);
            } else {
                stack.push(n.first as usize + 1);
                stack.push(n.first as usize);
            }
        }
    }
}

impl<const D: usize> Piece<D> {
    /// Seeds for the preimages of `p` in the piece, as global parameters, at most `max` of them.
    ///
    /// A certified piece starts from its centre, any other piece from the roots of its
    /// approximation `Q` within the error band (clipping, spread out). Each start is polished by
    /// Newton's method on `Q`, which costs a few dozen operations where the net's own evaluation
    /// costs thousands; a root of `Q` outside the piece by more than a tenth of it is dropped (a
    /// preimage there belongs to a neighbour, whose image bounds hold `p` too).
    ///
    /// `work` grows by what this costs, in evaluations of one control point: a Newton step on the
    /// approximation about one per coefficient and coordinate, a clipping pass (two restrictions
    /// and two hulls per axis) about four.
    pub(crate) fn seeds(
        &self,
        p: [f64; D],
        max: usize,
        stats: &mut ClipStats,
        work: &mut u64,
    ) -> Vec<[f64; D]> {
        let unit = (self.approx.coefs.len() * D) as u64;
        let starts = if self.certified {
            alloc::vec![[0.5; D]]
        } else {
            let system = self.approx.minus(p);
            let limits = ClipLimits {
                accuracy: 2e-2,
                max_passes: 48,
            };
            // The pass cap is the piece's own; the query's total is kept for its own cap.
            let mut own = ClipStats::default();
            let found = clip_seeds(&system, self.band, limits, &mut own);
            stats.passes += own.passes;
            stats.splits += own.splits;
            stats.capped |= own.capped;
            *work += u64::from(own.passes) * unit * 4;
            let mut kept: Vec<[f64; D]> = Vec::new();
            for s in found {
                if kept.len() == max {
                    break;
                }
                // Seeds closer than a hundredth of the piece are one seed.
                if kept.iter().all(|k| super::max_abs_diff(*k, s) > 1e-2) {
                    kept.push(s);
                }
            }
            kept
        };
        let mut seeds: Vec<[f64; D]> = Vec::with_capacity(starts.len());
        let fresh = |seeds: &[[f64; D]], t: [f64; D], apart: f64| {
            seeds.iter().all(|k| super::max_abs_diff(*k, t) > apart)
        };
        for start in starts {
            let t = match newton_on(&self.approx, p, start, &mut || *work += unit) {
                Approach::Root(t) if t.iter().all(|&x| (-0.1..=1.1).contains(&x)) => t,
                Approach::Root(_) | Approach::Away => continue,
                // Singular or slow: near a fold, where the net's own Newton may still get there.
                Approach::Unsure => start,
            };
            if fresh(&seeds, t, 1e-6) {
                seeds.push(t);
            } else if !self.certified && fresh(&seeds, start, 1e-2) {
                // Two starts that end at one root of `Q` near a fold, where `Q`'s roots may merge
                // before the net's do: the start itself is kept for the net's Newton.
                seeds.push(start);
            }
        }
        seeds
            .iter()
            .map(|t| core::array::from_fn(|a| self.lo[a] + (self.hi[a] - self.lo[a]) * t[a]))
            .collect()
    }
}

/// Where Newton's method on an approximation went.
enum Approach<const D: usize> {
    /// To a root (which may lie outside the piece).
    Root([f64; D]),
    /// Far from the piece: no root of its own there.
    Away,
    /// Nowhere certain: a singular Jacobian, or slow convergence (a fold).
    Unsure,
}

/// Newton's method for `Q(t) = p` on a low-degree net from `t`: the root once a step is below
/// `1e-10`; calls `step` before each step.
fn newton_on<const D: usize>(
    q: &Bernstein<D, D>,
    p: [f64; D],
    mut t: [f64; D],
    step: &mut impl FnMut(),
) -> Approach<D> {
    for _ in 0..10 {
        step();
        let (x, jac) = eval_with_jacobian(q, t);
        let r: [f64; D] = core::array::from_fn(|e| x[e] - p[e]);
        let Some(delta) = super::solve_jac(&jac, r) else {
            return Approach::Unsure;
        };
        for a in 0..D {
            t[a] -= delta[a];
        }
        if !t.iter().all(|x| x.abs() < 4.0) {
            return Approach::Away;
        }
        if delta.iter().all(|d| d.abs() < 1e-10) {
            return Approach::Root(t);
        }
    }
    Approach::Unsure
}

/// The value of a low-degree net at local parameters `t` and its Jacobian by columns.
fn eval_with_jacobian<const D: usize>(
    net: &Bernstein<D, D>,
    t: [f64; D],
) -> ([f64; D], [[f64; D]; D]) {
    let mut basis = [[0.0; crate::bernstein::MAX_DEGREE + 1]; D];
    let mut slope = [[0.0; crate::bernstein::MAX_DEGREE + 1]; D];
    for a in 0..D {
        crate::bernstein::basis_and_derivative_into(
            net.dims[a] - 1,
            t[a],
            &mut basis[a],
            &mut slope[a],
        );
    }
    let mut x = [0.0; D];
    let mut jac = [[0.0; D]; D];
    // The coefficients in storage order, their multi-index counted along (the last axis fastest).
    let mut idx = [0usize; D];
    for c in &net.coefs {
        let mut w = 1.0;
        for a in 0..D {
            w *= basis[a][idx[a]];
        }
        for e in 0..D {
            x[e] += w * c[e];
        }
        for d in 0..D {
            let mut wd = slope[d][idx[d]];
            for a in 0..D {
                if a != d {
                    wd *= basis[a][idx[a]];
                }
            }
            for e in 0..D {
                jac[d][e] += wd * c[e];
            }
        }
        let mut a = D;
        while a > 0 {
            a -= 1;
            idx[a] += 1;
            if idx[a] < net.dims[a] {
                break;
            }
            idx[a] = 0;
        }
    }
    (x, jac)
}

fn with<const D: usize>(mut a: [f64; D], axis: usize, v: f64) -> [f64; D] {
    a[axis] = v;
    a
}

/// The Jacobian of a restricted net in its local parameters: its mean and spread.
struct Shape<const D: usize> {
    /// `‖A⁻¹‖_F r ≤` [`CERTIFY_RATIO`], with `A` the mean Jacobian and `r` its spread.
    certified: bool,
    /// Per axis, the length of the mean derivative column plus its spread: how far and how
    /// unevenly the piece stretches along that axis.
    stretch: [f64; D],
}

impl<const D: usize> Shape<D> {
    fn of(t: &Bernstein<D, D>) -> Self {
        let mut mean = [[0.0; D]; D];
        let mut spread = [0.0; D];
        for axis in 0..D {
            let coefs = derivative(t, axis);
            let inv = 1.0 / coefs.len() as f64;
            for c in &coefs {
                for r in 0..D {
                    mean[axis][r] += c[r] * inv;
                }
            }
            spread[axis] = coefs
                .iter()
                .map(|c| norm(core::array::from_fn::<f64, D, _>(|r| c[r] - mean[axis][r])))
                .fold(0.0f64, f64::max);
        }
        let r = crate::math::sqrt(spread.iter().map(|s| s * s).sum());
        let ratio = inverse_size(&mean).map_or(f64::INFINITY, |size| size * r);
        let stretch = core::array::from_fn(|a| norm(mean[a]) + spread[a]);
        Self {
            certified: ratio <= CERTIFY_RATIO,
            stretch,
        }
    }

    /// The axis to cut along: the one the piece stretches most along, among those still wider
    /// than [`MIN_WIDTH`]; `None` when none is.
    fn split_axis(&self, lo: [f64; D], hi: [f64; D]) -> Option<usize> {
        (0..D)
            .filter(|&a| hi[a] - lo[a] > MIN_WIDTH)
            .max_by(|&a, &b| self.stretch[a].total_cmp(&self.stretch[b]))
    }
}

fn norm<const D: usize>(v: [f64; D]) -> f64 {
    crate::math::sqrt(v.iter().map(|x| x * x).sum())
}

/// The Bernstein coefficients of `∂S/∂t_axis` (local parameters), in any order.
fn derivative<const D: usize>(t: &Bernstein<D, D>, axis: usize) -> Vec<[f64; D]> {
    let n = t.dims[axis];
    let stride: usize = t.dims[axis + 1..].iter().product();
    let scale = (n - 1) as f64;
    let mut out = Vec::with_capacity(t.coefs.len());
    for (index, c) in t.coefs.iter().enumerate() {
        if (index / stride) % n + 1 < n {
            let next = t.coefs[index + stride];
            out.push(core::array::from_fn(|r| scale * (next[r] - c[r])));
        }
    }
    out
}

/// `‖A⁻¹‖_F` of the matrix `A` with columns `cols`; `None` when it is singular or not finite.
fn inverse_size<const D: usize>(cols: &[[f64; D]; D]) -> Option<f64> {
    let mut sum = 0.0;
    for c in 0..D {
        let mut unit = [0.0; D];
        unit[c] = 1.0;
        sum += super::solve_jac(cols, unit)?
            .iter()
            .map(|v| v * v)
            .sum::<f64>();
    }
    let size = crate::math::sqrt(sum);
    size.is_finite().then_some(size)
}

/// The matrices that approximate nets of one set of degrees: per axis, the reduction to degree
/// `min(n, APPROX_DEGREE)` and the elevation back (`None` where the degree is low already).
struct Reducer<const D: usize> {
    axes: [Option<(Matrix, Matrix)>; D],
}

impl<const D: usize> Reducer<D> {
    fn new(dims: [usize; D]) -> Self {
        Self {
            axes: dims.map(|points| {
                let n = points - 1;
                let k = n.min(APPROX_DEGREE);
                (k < n).then(|| (reduction(n, k), elevation(k, n)))
            }),
        }
    }

    /// The interpolant of degree `min(n, APPROX_DEGREE)` per axis of the restricted net `t` and
    /// the bound on its error per component.
    fn approximate(&self, t: &Bernstein<D, D>) -> (Bernstein<D, D>, [f64; D]) {
        if self.axes.iter().all(Option::is_none) {
            return (t.clone(), [0.0; D]);
        }
        let mut approx = t.clone();
        for (axis, m) in self.axes.iter().enumerate() {
            if let Some((down, _)) = m {
                approx = apply(&approx, axis, down);
            }
        }
        let mut back = approx.clone();
        for (axis, m) in self.axes.iter().enumerate() {
            if let Some((_, up)) = m {
                back = apply(&back, axis, up);
            }
        }
        let mut band = [0.0f64; D];
        let mut size = [0.0f64; D];
        for (a, b) in t.coefs.iter().zip(&back.coefs) {
            for e in 0..D {
                band[e] = band[e].max((a[e] - b[e]).abs());
                size[e] = size[e].max(a[e].abs());
            }
        }
        // Rounding in the interpolation and the elevation, and a little more.
        for e in 0..D {
            band[e] += size[e] * 1e-13;
        }
        (approx, band)
    }
}

/// A matrix of `rows × cols`, row-major.
struct Matrix {
    rows: usize,
    cols: usize,
    m: Vec<f64>,
}

/// `t` with the matrix applied along `axis` (its `cols` coefficients become `rows`).
fn apply<const D: usize>(t: &Bernstein<D, D>, axis: usize, m: &Matrix) -> Bernstein<D, D> {
    debug_assert_eq!(t.dims[axis], m.cols);
    let stride: usize = t.dims[axis + 1..].iter().product();
    let outer = t.coefs.len() / (m.cols * stride);
    let mut dims = t.dims;
    dims[axis] = m.rows;
    let mut coefs = vec![[0.0; D]; outer * m.rows * stride];
    for o in 0..outer {
        for s in 0..stride {
            for r in 0..m.rows {
                let mut acc = [0.0; D];
                for c in 0..m.cols {
                    let w = m.m[r * m.cols + c];
                    let x = t.coefs[(o * m.cols + c) * stride + s];
                    for e in 0..D {
                        acc[e] += w * x[e];
                    }
                }
                coefs[(o * m.rows + r) * stride + s] = acc;
            }
        }
    }
    Bernstein { dims, coefs }
}

/// The map from Bernstein coefficients of degree `n` to those of the degree-`k` polynomial that
/// interpolates it at the Chebyshev–Lobatto nodes of `[0, 1]`.
fn reduction(n: usize, k: usize) -> Matrix {
    let nodes: Vec<f64> = (0..=k)
        .map(|j| 0.5 * (1.0 - libm::cos(core::f64::consts::PI * j as f64 / k as f64)))
        .collect();
    // Collocation: values at the nodes of the degree-k basis, inverted by Gauss–Jordan.
    let size = k + 1;
    let mut a: Vec<f64> = (0..size * size)
        .map(|x| bernstein(k, x % size, nodes[x / size]))
        .collect();
    let mut inv: Vec<f64> = (0..size * size)
        .map(|x| f64::from(u8::from(x / size == x % size)))
        .collect();
    for col in 0..size {
        let pivot = (col..size)
            .max_by(|&x, &y| a[x * size + col].abs().total_cmp(&a[y * size + col].abs()))
            .unwrap_or(col);
        for c in 0..size {
            a.swap(col * size + c, pivot * size + c);
            inv.swap(col * size + c, pivot * size + c);
        }
        let d = a[col * size + col];
        for c in 0..size {
            a[col * size + c] /= d;
            inv[col * size + c] /= d;
        }
        for row in 0..size {
            if row != col {
                let f = a[row * size + col];
                for c in 0..size {
                    a[row * size + c] -= f * a[col * size + c];
                    inv[row * size + c] -= f * inv[col * size + c];
                }
            }
        }
    }
    // Values of the degree-n basis at the nodes, then the collocation inverse.
    let values: Vec<f64> = (0..size * (n + 1))
        .map(|x| bernstein(n, x % (n + 1), nodes[x / (n + 1)]))
        .collect();
    let mut m = vec![0.0; size * (n + 1)];
    for r in 0..size {
        for c in 0..=n {
            m[r * (n + 1) + c] = (0..size)
                .map(|j| inv[r * size + j] * values[j * (n + 1) + c])
                .sum();
        }
    }
    Matrix {
        rows: size,
        cols: n + 1,
        m,
    }
}

/// Degree elevation from `k` to `n` as a matrix.
fn elevation(k: usize, n: usize) -> Matrix {
    let mut m = vec![0.0; (n + 1) * (k + 1)];
    for i in 0..=n {
        for j in i.saturating_sub(n - k)..=k.min(i) {
            m[i * (k + 1) + j] = binomial(k, j) * binomial(n - k, i - j) / binomial(n, i);
        }
    }
    Matrix {
        rows: n + 1,
        cols: k + 1,
        m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn eval<const D: usize>(t: &Bernstein<D, D>, u: [f64; D]) -> [f64; D] {
        let mut out = [0.0; D];
        for (index, c) in t.coefs.iter().enumerate() {
            let idx = super::super::multi_index(t.dims, index);
            let w: f64 = (0..D)
                .map(|a| bernstein(t.dims[a] - 1, idx[a], u[a]))
                .product();
            for e in 0..D {
                out[e] += w * c[e];
            }
        }
        out
    }

    #[test]
    fn the_approximation_is_within_its_band() {
        let mut rng = Rng::new(5);
        for (n, m) in [(5, 2), (8, 8), (16, 3)] {
            let t = Bernstein::<2, 2> {
                dims: [n + 1, m + 1],
                coefs: (0..(n + 1) * (m + 1))
                    .map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)])
                    .collect(),
            };
            let (approx, band) = Reducer::new(t.dims).approximate(&t);
            assert_eq!(approx.dims, [n.min(3) + 1, m.min(3) + 1]);
            for _ in 0..200 {
                let u = [rng.range(0.0, 1.0), rng.range(0.0, 1.0)];
                let (a, b) = (eval(&t, u), eval(&approx, u));
                for e in 0..2 {
                    assert!(
                        (a[e] - b[e]).abs() <= band[e],
                        "{n}x{m}: {} > {}",
                        (a[e] - b[e]).abs(),
                        band[e]
                    );
                }
            }
        }
        // A cubic is its own approximation.
        let t = Bernstein::<2, 2> {
            dims: [4, 4],
            coefs: (0..16).map(|_| [rng.range(-1.0, 1.0), 0.0]).collect(),
        };
        let (approx, band) = Reducer::new(t.dims).approximate(&t);
        assert_eq!((approx, band), (t, [0.0; 2]));
    }

    #[test]
    fn elevation_after_reduction_reproduces_low_degrees() {
        // A quadratic written in degree 7 survives reduction to degree 3 exactly.
        let q = [0.3, -1.0, 2.0];
        let e = elevation(2, 7);
        let high: Vec<f64> = (0..8)
            .map(|i| (0..3).map(|j| e.m[i * 3 + j] * q[j]).sum())
            .collect();
        let r = reduction(7, 3);
        let low: Vec<f64> = (0..4)
            .map(|i| (0..8).map(|j| r.m[i * 8 + j] * high[j]).sum())
            .collect();
        let back = elevation(3, 7);
        for i in 0..8 {
            let v: f64 = (0..4).map(|j| back.m[i * 4 + j] * low[j]).sum();
            assert!((v - high[i]).abs() < 1e-13);
        }
    }
}
