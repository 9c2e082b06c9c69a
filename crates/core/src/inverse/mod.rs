//! The inverse of a space mapping: the parameters `u` with `S(u) = p` when the control points of a
//! patch (`D = 2`) or volume (`D = 3`) have moved in space (the first paper's §3.3.2).
//!
//! Three ways to the same answer, all tested against the first:
//!
//! - [`Method::Clipping`]: Bézier clipping of `S(u) − p = 0` over the whole parameter box: every
//!   preimage, the reference.
//! - [`Method::Hybrid`]: the paper's procedure: a spline guess ([`tps`]), clipping in a box around it,
//!   and whole-domain clipping when that box holds no root (or when the map may fold).
//! - [`Method::Fast`]: where the map is certified injective, Newton's method from a seed table of
//!   the forward map, verified; elsewhere, and where those seeds miss, the map's *atlas*: the
//!   parameter box cut once into pieces, each with the bounds of its image, an injectivity
//!   certificate where it has one and a low-degree approximation with a sound error bound; a query
//!   walks to the pieces whose image holds the point, seeds from the approximations and polishes
//!   on the net, in bounded work ([`InverseMap::plan`]).
//!
//! The map is *certified injective* when `det J` is one-signed on the parameter box (its Bernstein
//! coefficients, refined by subdivision) and the image of the box's boundary is simple (non-adjacent
//! boundary pieces have disjoint bounds; adjacent boundary curves are jointly monotone in 2D). A local
//! homeomorphism of a closed ball that is injective on its boundary is injective, so a certified
//! map has at most one preimage and Newton's root is the only one. In 3D, adjacent boundary pieces
//! are not checked against each other: there the certificate rests on `det J ≠ 0` near shared edges.

//!
//! The parts, one file each: [`clip`] (Bézier clipping), [`tps`] (the spline guess), `newton.rs`
//! (Newton's method and the tolerances that say a root is reached), `certify.rs` (the injectivity
//! certificate), `atlas.rs` (the pieces of a map that may fold, with their work budgets),
//! `query.rs` (a query through the atlas: the plan of its work, the walk to the pieces, the polish).

// Coordinates index several fixed-size arrays at once; iterator chains would hide the algebra.
#![allow(clippy::needless_range_loop)]

pub(crate) mod atlas;
mod certify;
pub mod clip;
mod newton;
mod query;
pub mod tps;

pub use atlas::Share;

use alloc::vec::Vec;
use core::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use once_cell::race::OnceBox;

use crate::dim::{Control, Dim, Dimension};
use crate::tensor::Tensor;
use atlas::Atlas;
use clip::{Bernstein, ClipLimits, ClipStats, clip_roots};
use newton::{Until, VERIFIED_RESIDUAL, newton};
use tps::{Kernel, Spline};

/// Candidate roots closer than this (in parameters) are one root: the seam between split boxes, or
/// the cluster of boxes around a tangential root.
const MERGE: f64 = 1e-6;

/// The most seeds one atlas piece gives a query.
const MAX_PIECE_SEEDS: usize = 8;

/// The most preimages one query through the atlas gathers (a net collapsed to a point has a
/// continuum of them); past it the query is exhausted.
const MAX_ATLAS_ROOTS: usize = 256;

/// How the preimages of a point are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Bézier clipping over the whole parameter box.
    Clipping,
    /// The paper's hybrid: spline guess, clipping in a box around it, whole-domain clipping after.
    Hybrid,
    /// Newton from a seed table where the map is certified injective, the hybrid as fallback.
    Fast,
}

impl Method {
    /// Every method, the reference first.
    pub const ALL: [Self; 3] = [Self::Clipping, Self::Hybrid, Self::Fast];
}

/// What one query did (for iteration histograms).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryStats {
    /// Newton steps taken.
    pub newton_steps: u32,
    /// Clipping work.
    pub clip: ClipStats,
    /// Whether the query fell back from its method's first attempt.
    pub fallback: bool,
    /// Atlas pieces whose image bounds held the point (a map that may fold).
    pub atlas_pieces: u32,
    /// Newton solves started from the atlas's seeds.
    pub atlas_solves: u32,
    /// The work spent through the atlas, in evaluations of one control point.
    pub work: u64,
    /// Whether the query's work budget ran out before every piece was searched: preimages may be
    /// missing (see [`InverseMap::plan`]).
    pub exhausted: bool,
}

/// `S(u)` with its Jacobian and `S_ξ` with its gradient, at one parameter point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eval<const D: usize> {
    /// The spatial coordinates `(S_x, S_y[, S_z])`.
    pub x: [f64; D],
    /// `jac[c][r] = ∂S_r/∂u_c`: column `c` is the derivative along parameter `c`.
    pub jac: [[f64; D]; D],
    /// `S_ξ`.
    pub xi: f64,
    /// `∂S_ξ/∂u_c`.
    pub dxi: [f64; D],
}

/// A control net whose spatial part maps parameters to space: a patch `(x, y, ξ)` or a volume
/// `(x, y, z, ξ)`.
pub trait Forward<const D: usize> {
    /// `S` and its derivatives at `u`.
    fn forward(&self, u: [f64; D]) -> Eval<D>;
    /// The points per axis.
    fn dims(&self) -> [usize; D];
    /// The spatial coordinates of the control points, in storage order.
    fn spatial(&self) -> Vec<[f64; D]>;
}

impl<const D: usize> Forward<D> for Tensor<Control<D>, D>
where
    Dim<D>: Dimension<D>,
{
    fn forward(&self, u: [f64; D]) -> Eval<D> {
        let (s, ds) = self.eval_with_gradient(u);
        let (x, xi) = Dim::<D>::split(s);
        let mut jac = [[0.0; D]; D];
        let mut dxi = [0.0; D];
        for (c, &d) in ds.iter().enumerate() {
            (jac[c], dxi[c]) = Dim::<D>::split(d);
        }
        Eval { x, jac, xi, dxi }
    }
    fn dims(&self) -> [usize; D] {
        Tensor::dims(self)
    }
    fn spatial(&self) -> Vec<[f64; D]> {
        self.points()
            .iter()
            .map(|&c| Dim::<D>::split(c).0)
            .collect()
    }
}

/// The clipped defining function `S_ξ(u) & F_s(u)` at a parameter point.
pub(crate) fn clipped<const D: usize>(xi: f64, u: [f64; D]) -> f64 {
    crate::rfunc::clip(xi, u)
}

/// Solve the `D × D` system `J δ = r` given by columns; `None` when singular.
pub(crate) fn solve_jac<const D: usize>(jac: &[[f64; D]; D], r: [f64; D]) -> Option<[f64; D]> {
    // Row-major copy with the right-hand side, Gaussian elimination with partial pivoting.
    let mut a = [[0.0; 4]; 3];
    for row in 0..D {
        for col in 0..D {
            a[row][col] = jac[col][row];
        }
        a[row][D] = r[row];
    }
    let scale = (0..D)
        .flat_map(|c| jac[c].iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for k in 0..D {
        let p = (k..D)
            .max_by(|&x, &y| a[x][k].abs().total_cmp(&a[y][k].abs()))
            .unwrap_or(k);
        if a[p][k].abs() <= scale * 1e-14 {
            return None;
        }
        a.swap(k, p);
        for row in k + 1..D {
            let f = a[row][k] / a[k][k];
            for col in k..=D {
                a[row][col] -= f * a[k][col];
            }
        }
    }
    let mut x = [0.0; D];
    for k in (0..D).rev() {
        let mut s = a[k][D];
        for col in k + 1..D {
            s -= a[k][col] * x[col];
        }
        x[k] = s / a[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

fn max_abs_diff<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    (0..D).fold(0.0f64, |m, c| m.max((a[c] - b[c]).abs()))
}

fn inside_closed<const D: usize>(u: [f64; D], tol: f64) -> bool {
    u.iter().all(|&t| (-tol..=1.0 + tol).contains(&t))
}

fn clamp_unit<const D: usize>(u: [f64; D]) -> [f64; D] {
    u.map(|t| t.clamp(0.0, 1.0))
}

/// How the spline guess is fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GuessFit {
    /// The paper's way: the moved control points to their parameters on the regular grid.
    ControlPoints,
    /// Samples of the forward map `S(u_k) → u_k` on a regular parameter grid.
    ForwardSamples,
}

/// The inverse map of one control net: its spline guess, injectivity certificate and seed table.
///
/// It keeps no reference to the net; every query takes the net it was built from.
#[derive(Debug)]
pub struct InverseMap<const D: usize> {
    tensor: Bernstein<D, D>,
    guess: Spline<D>,
    injective: bool,
    seeds: SeedTable<D>,
    /// The largest extent or coordinate magnitude of the control net, for spatial tolerances.
    scale: f64,
    /// The atlas of a map that may fold, built on its first query.
    atlas: OnceBox<Atlas<D>>,
    /// The queries the atlas is built for (see [`InverseMap::plan`]).
    planned: AtomicUsize,
    /// The queries whose work budget ran out so far.
    exhausted: AtomicUsize,
    /// The work spent through the atlas so far (see
    /// [`AtlasBudget::query_work`](atlas::AtlasBudget::query_work)).
    spent: AtomicU64,
    /// The work every query may spend, whatever was spent before it, where a mesh fixed it
    /// ([`InverseMap::fix_query_work`]); 0 where it is not fixed.
    fixed: AtomicU64,
    /// The map's [`Share`] of its command: the bits of its reach and load.
    reach: AtomicU64,
    load: AtomicU64,
}

impl<const D: usize> Clone for InverseMap<D> {
    fn clone(&self) -> Self {
        Self {
            tensor: self.tensor.clone(),
            guess: self.guess.clone(),
            injective: self.injective,
            seeds: self.seeds.clone(),
            scale: self.scale,
            atlas: self.atlas.clone(),
            planned: AtomicUsize::new(self.planned.load(Ordering::Relaxed)),
            exhausted: AtomicUsize::new(self.exhausted.load(Ordering::Relaxed)),
            spent: AtomicU64::new(self.spent.load(Ordering::Relaxed)),
            fixed: AtomicU64::new(self.fixed.load(Ordering::Relaxed)),
            reach: AtomicU64::new(self.reach.load(Ordering::Relaxed)),
            load: AtomicU64::new(self.load.load(Ordering::Relaxed)),
        }
    }
}

impl<const D: usize> PartialEq for InverseMap<D> {
    /// The same net gives the same map: the atlas, a cache, is left out.
    fn eq(&self, other: &Self) -> bool {
        self.tensor == other.tensor
            && self.guess == other.guess
            && self.injective == other.injective
            && self.seeds == other.seeds
            && self.scale == other.scale
    }
}

impl<const D: usize> InverseMap<D> {
    /// The inverse map of `net` with the default guess ([`GuessFit::ForwardSamples`], chosen by
    /// measurement: see the tests and BENCHMARKS.md).
    pub fn new<F: Forward<D>>(net: &F) -> Self {
        Self::with_guess(net, GuessFit::ForwardSamples)
    }

    /// The inverse map of `net` with the spline guess fitted as `fit` says.
    pub fn with_guess<F: Forward<D>>(net: &F, fit: GuessFit) -> Self {
        let dims = net.dims();
        let tensor = Bernstein {
            dims,
            coefs: net.spatial(),
        };
        let (lo, hi) = bounds(&tensor.coefs);
        // Rounding in S(u) grows with the coordinates' magnitude, not only with the net's extent.
        let scale = (0..D)
            .map(|c| (hi[c] - lo[c]).max(lo[c].abs()).max(hi[c].abs()))
            .fold(0.0f64, f64::max);
        // In 3D the triharmonic r³ guesses better than the biharmonic r (measured by
        // `the_default_guess_is_the_better_one_by_measurement`).
        let kernel = if D == 2 {
            Kernel::ThinPlate
        } else {
            Kernel::Cubic
        };
        let (sites, values) = match fit {
            GuessFit::ControlPoints => control_sites(&tensor),
            GuessFit::ForwardSamples => forward_sites(net, if D == 2 { 9 } else { 5 }),
        };
        let guess = Spline::fit(kernel, &sites, &values);
        let injective = certify::injective(&tensor);
        let seeds = SeedTable::build(net, &guess, lo, hi, if D == 2 { 48 } else { 16 });
        Self {
            tensor,
            guess,
            injective,
            seeds,
            scale,
            atlas: OnceBox::new(),
            planned: AtomicUsize::new(0),
            exhausted: AtomicUsize::new(0),
            spent: AtomicU64::new(0),
            fixed: AtomicU64::new(0),
            reach: AtomicU64::new(1.0f64.to_bits()),
            load: AtomicU64::new(1.0f64.to_bits()),
        }
    }

    /// Whether the map is certified injective (at most one preimage per point).
    #[must_use]
    pub fn injective(&self) -> bool {
        self.injective
    }

    /// The spline guess itself.
    pub(crate) fn spline(&self) -> &Spline<D> {
        &self.guess
    }

    /// The spline guess of `u` at `p`.
    #[must_use]
    pub fn guess(&self, p: [f64; D]) -> [f64; D] {
        self.guess.eval(p)
    }

    /// Every `u` in the closed parameter box with `S(u) = p`, found by `method` to the parameter
    /// `accuracy` (clipping) and polished by Newton's method.
    pub fn preimages<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        method: Method,
        accuracy: f64,
        stats: &mut QueryStats,
    ) -> Vec<[f64; D]> {
        match method {
            Method::Clipping => self.clip(net, p, [0.0; D], [1.0; D], accuracy, stats),
            Method::Hybrid => self.hybrid(net, p, accuracy, stats),
            Method::Fast => self.seeded(net, p, None, accuracy, stats),
        }
    }

    /// [`Method::Fast`] with an explicit Newton seed (a grid neighbour's parameters) tried first.
    /// Its roots are polished to rounding whatever `_accuracy` says (the parameter of the other
    /// methods, kept so that every method is called alike).
    pub fn seeded<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        seed: Option<[f64; D]>,
        _accuracy: f64,
        stats: &mut QueryStats,
    ) -> Vec<[f64; D]> {
        if !self.injective {
            return self
                .atlas_roots(net, p, stats)
                .into_iter()
                .map(|(u, _)| u)
                .collect();
        }
        match self.fast_root(net, p, seed, stats) {
            Some((u, _)) => alloc::vec![u],
            None => {
                // The seeds missed or landed outside: the atlas says, in bounded work, whether a
                // root lies inside.
                stats.fallback = true;
                self.atlas_roots(net, p, stats)
                    .into_iter()
                    .map(|(u, _)| u)
                    .collect()
            }
        }
    }

    /// Newton from `seed`, then from the seed table: the root if it lies in the closed box, with
    /// the evaluation there (which verifies it and gives `S_ξ` for free).
    fn fast_root<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        seed: Option<[f64; D]>,
        stats: &mut QueryStats,
    ) -> Option<([f64; D], Eval<D>)> {
        let table = self.seeds.lookup(p);
        seed.into_iter().chain([table]).find_map(|start| {
            let mut u = newton(net, p, start, self.scale, 12, Until::QuickStep, stats)?;
            for _ in 0..3 {
                if !inside_closed(u, 1e-12) {
                    return None;
                }
                u = clamp_unit(u);
                let e = net.forward(u);
                let r: [f64; D] = core::array::from_fn(|c| e.x[c] - p[c]);
                if r.iter().all(|v| v.abs() <= self.scale * VERIFIED_RESIDUAL) {
                    return Some((u, e));
                }
                // Not yet at rounding level: one more step from this evaluation.
                let delta = solve_jac(&e.jac, r)?;
                stats.newton_steps += 1;
                u = core::array::from_fn(|c| u[c] - delta[c]);
            }
            None
        })
    }

    fn hybrid<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        accuracy: f64,
        stats: &mut QueryStats,
    ) -> Vec<[f64; D]> {
        let g = self.guess(p);
        if inside_closed(g, 0.05) {
            const HALF: f64 = 0.02;
            let lo = g.map(|t| (t - HALF).clamp(0.0, 1.0));
            let hi = g.map(|t| (t + HALF).clamp(0.0, 1.0));
            let roots = self.clip(net, p, lo, hi, accuracy, stats);
            if !roots.is_empty() && self.injective {
                return roots;
            }
        }
        stats.fallback = true;
        self.clip(net, p, [0.0; D], [1.0; D], accuracy, stats)
    }

    fn clip<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        lo: [f64; D],
        hi: [f64; D],
        accuracy: f64,
        stats: &mut QueryStats,
    ) -> Vec<[f64; D]> {
        let limits = ClipLimits {
            accuracy: accuracy.max(1e-15),
            ..ClipLimits::default()
        };
        let candidates = clip_roots(&self.tensor.minus(p), lo, hi, limits, &mut stats.clip);
        let mut roots: Vec<[f64; D]> = Vec::with_capacity(candidates.len().min(4));
        for c in candidates {
            // Polish: Newton from the box centre, kept when it stays close and in the box.
            let u = match newton(net, p, c, self.scale, 6, Until::Root, stats) {
                Some(u) if max_abs_diff(u, c) <= MERGE && inside_closed(u, 1e-12) => clamp_unit(u),
                _ => c,
            };
            if roots.iter().all(|r| max_abs_diff(*r, u) > MERGE) {
                roots.push(u);
            }
        }
        roots
    }

    /// The parameter used for `f` where `p` has no preimage: the root of the polynomial map extended
    /// past the box near it (Newton from the guess), else the spline guess itself.
    ///
    /// Newton gets 30 steps where the map is certified injective, 8 where it may fold (where
    /// most points of a grid can have no preimage and the guess be far from any root), fewer when
    /// the query's work budget runs low.
    pub fn outside<F: Forward<D>>(&self, net: &F, p: [f64; D], stats: &mut QueryStats) -> [f64; D] {
        // A point so far away that the spline overflows gets the box's centre: f is negative
        // there all the same (see below).
        let g = self.guess(p).map(|t| if t.is_finite() { t } else { 0.5 });
        let steps = if self.injective {
            30
        } else {
            // Within what is left of the query's work budget.
            let left =
                self.query_work().saturating_sub(stats.work) / self.tensor.coefs.len() as u64;
            let steps = left.min(8) as u32;
            stats.work += u64::from(steps) * self.tensor.coefs.len() as u64;
            steps
        };
        newton(net, p, g, self.scale, steps, Until::Root, stats).unwrap_or(g)
    }

    /// `f(p)`: the largest clipped `S_ξ` over the preimages, or the negative continuation outside
    /// the image; with the number of preimages and the parameters that gave `f`.
    pub fn f<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        method: Method,
        accuracy: f64,
        stats: &mut QueryStats,
    ) -> Value<D> {
        self.f_seeded(net, p, method, None, accuracy, stats)
    }

    /// [`InverseMap::f`] with a Newton seed for [`Method::Fast`]: the `u` of a neighbouring point's
    /// [`Value`], so that a grid costs a few Newton steps per point.
    pub fn f_seeded<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        method: Method,
        seed: Option<[f64; D]>,
        accuracy: f64,
        stats: &mut QueryStats,
    ) -> Value<D> {
        if method == Method::Fast && !self.injective {
            let roots = self.atlas_roots(net, p, stats);
            return self.value_of(net, p, &roots, stats);
        }
        if method == Method::Fast {
            match self.fast_root(net, p, seed, stats) {
                Some((u, e)) => {
                    return Value {
                        f: clipped(e.xi, u),
                        preimages: 1,
                        u,
                        exhausted: false,
                    };
                }
                None => {
                    // The seeds missed or landed outside: the atlas says, in bounded work,
                    // whether a root lies inside.
                    stats.fallback = true;
                    let roots = self.atlas_roots(net, p, stats);
                    return self.value_of(net, p, &roots, stats);
                }
            }
        }
        let roots = self.preimages(net, p, method, accuracy, stats);
        self.value(net, p, &roots, stats)
    }

    /// `f(p)` from its preimages `roots` (see [`InverseMap::f`]); where there are none, from the
    /// continuation ([`InverseMap::outside`]), the same whichever method found no root.
    pub fn value<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        roots: &[[f64; D]],
        stats: &mut QueryStats,
    ) -> Value<D> {
        let with_xi: Vec<([f64; D], f64)> = roots.iter().map(|&u| (u, net.forward(u).xi)).collect();
        self.value_of(net, p, &with_xi, stats)
    }

    /// [`InverseMap::value`] of preimages whose `S_ξ` is known.
    fn value_of<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        roots: &[([f64; D], f64)],
        stats: &mut QueryStats,
    ) -> Value<D> {
        let best = roots
            .iter()
            .map(|&(u, xi)| (clipped(xi, u), u))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((f, u)) = best {
            return Value {
                f,
                preimages: roots.len(),
                u,
                exhausted: stats.exhausted,
            };
        }
        let u = self.outside(net, p, stats);
        let f = clipped(net.forward(u).xi, u);
        // Outside the image f is negative by definition; the continuation is negative wherever
        // its parameter leaves the box, and forced so where the guess fell back inside it.
        let f = if f < 0.0 { f } else { -f - f64::MIN_POSITIVE };
        Value {
            f,
            preimages: 0,
            u,
            exhausted: stats.exhausted,
        }
    }
}

/// `f` at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Value<const D: usize> {
    /// The defining function.
    pub f: f64,
    /// How many preimages the point has in the closed parameter box.
    pub preimages: usize,
    /// The parameters `f` was taken at: the best preimage, or the continuation's parameter.
    pub u: [f64; D],
    /// Whether the query's work budget ran out (a net that folds very many times): preimages, and
    /// so the largest value, may be missing.
    pub exhausted: bool,
}

fn bounds<const D: usize>(points: &[[f64; D]]) -> ([f64; D], [f64; D]) {
    points.iter().fold(
        ([f64::INFINITY; D], [f64::NEG_INFINITY; D]),
        |(mut lo, mut hi), p| {
            for c in 0..D {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
            (lo, hi)
        },
    )
}

pub(crate) use crate::tensor::multi_index;

/// The paper's fit: each control point (at most about 150, evenly thinned) to its regular-grid
/// parameters.
fn control_sites<const D: usize>(t: &Bernstein<D, D>) -> (Vec<[f64; D]>, Vec<[f64; D]>) {
    let stride = |n: usize| {
        let mut s = 1;
        while (n - 1).div_ceil(s) + 1 > if D == 2 { 12 } else { 5 } {
            s += 1;
        }
        s
    };
    let steps: [usize; D] = core::array::from_fn(|a| stride(t.dims[a]));
    let (mut sites, mut values) = (Vec::new(), Vec::new());
    for (index, c) in t.coefs.iter().enumerate() {
        let idx = multi_index(t.dims, index);
        let keep = (0..D).all(|a| idx[a] % steps[a] == 0 || idx[a] == t.dims[a] - 1);
        if keep {
            sites.push(*c);
            values.push(core::array::from_fn(|a| {
                idx[a] as f64 / (t.dims[a] - 1) as f64
            }));
        }
    }
    (sites, values)
}

/// Forward samples `S(u_k) → u_k` on a `k^D` parameter grid.
fn forward_sites<const D: usize, F: Forward<D>>(
    net: &F,
    k: usize,
) -> (Vec<[f64; D]>, Vec<[f64; D]>) {
    let total = k.pow(D as u32);
    let (mut sites, mut values) = (Vec::with_capacity(total), Vec::with_capacity(total));
    for index in 0..total {
        let idx = multi_index([k; D], index);
        let u: [f64; D] = core::array::from_fn(|a| idx[a] as f64 / (k - 1) as f64);
        sites.push(net.forward(u).x);
        values.push(u);
    }
    (sites, values)
}

/// A regular grid of cells over the control net's bounds, each holding the forward sample whose
/// image fell nearest its centre (or the spline guess where none fell) with the inverse Jacobian
/// there: the seed for `p` is the linearised inverse `u_s + J⁻¹(p − S(u_s))`.
#[derive(Clone, Debug, PartialEq)]
struct SeedTable<const D: usize> {
    lo: [f64; D],
    inv_cell: [f64; D],
    res: usize,
    cells: Vec<Seed<D>>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Seed<const D: usize> {
    u: [f64; D],
    x: [f64; D],
    /// Column `c` of `J⁻¹`; zero where `J` is singular (the seed is then `u` itself).
    jinv: [[f64; D]; D],
}

impl<const D: usize> Seed<D> {
    fn at<F: Forward<D>>(net: &F, u: [f64; D]) -> Self {
        let e = net.forward(u);
        let mut jinv = [[0.0; D]; D];
        for c in 0..D {
            let mut unit = [0.0; D];
            unit[c] = 1.0;
            if let Some(col) = solve_jac(&e.jac, unit) {
                jinv[c] = col;
            } else {
                jinv = [[0.0; D]; D];
                break;
            }
        }
        Self { u, x: e.x, jinv }
    }
}

impl<const D: usize> SeedTable<D> {
    fn build<F: Forward<D>>(
        net: &F,
        guess: &Spline<D>,
        lo: [f64; D],
        hi: [f64; D],
        res: usize,
    ) -> Self {
        let inv_cell: [f64; D] = core::array::from_fn(|c| {
            let w = hi[c] - lo[c];
            if w > 0.0 { res as f64 / w } else { 0.0 }
        });
        let total = res.pow(D as u32);
        let mut cells = alloc::vec![[f64::NAN; D]; total];
        let mut best = alloc::vec![f64::INFINITY; total];
        let mut table = Self {
            lo,
            inv_cell,
            res,
            cells: Vec::new(),
        };
        // About one sample per cell: the affine seeds of cells that get none come from the spline.
        let k = res;
        for index in 0..k.pow(D as u32) {
            let idx = multi_index([k; D], index);
            let u: [f64; D] = core::array::from_fn(|a| (idx[a] as f64 + 0.5) / k as f64);
            let x = net.forward(u).x;
            let cell = table.cell(x);
            let centre = table.centre(cell);
            let d = max_abs_diff(x, centre);
            let flat = table.flat(cell);
            if d < best[flat] {
                best[flat] = d;
                cells[flat] = u;
            }
        }
        for (flat, c) in cells.iter_mut().enumerate() {
            if c[0].is_nan() {
                *c = clamp_unit(guess.eval(table.centre(multi_index([res; D], flat))));
            }
        }
        table.cells = cells.into_iter().map(|u| Seed::at(net, u)).collect();
        table
    }

    fn cell(&self, x: [f64; D]) -> [usize; D] {
        core::array::from_fn(|c| {
            let t = (x[c] - self.lo[c]) * self.inv_cell[c];
            if t > 0.0 {
                (t as usize).min(self.res - 1)
            } else {
                0
            }
        })
    }

    fn centre(&self, cell: [usize; D]) -> [f64; D] {
        core::array::from_fn(|c| {
            if self.inv_cell[c] > 0.0 {
                self.lo[c] + (cell[c] as f64 + 0.5) / self.inv_cell[c]
            } else {
                self.lo[c]
            }
        })
    }

    fn flat(&self, cell: [usize; D]) -> usize {
        cell.iter().fold(0, |acc, &i| acc * self.res + i)
    }

    fn lookup(&self, x: [f64; D]) -> [f64; D] {
        let s = &self.cells[self.flat(self.cell(x))];
        let mut u = s.u;
        for c in 0..D {
            let d = x[c] - s.x[c];
            for r in 0..D {
                u[r] += s.jinv[c][r] * d;
            }
        }
        // A far-off linearisation is no better than the sample itself.
        if u.iter().all(|t| (-0.5..=1.5).contains(t)) {
            u
        } else {
            s.u
        }
    }
}

#[cfg(test)]
pub(crate) mod tests;
