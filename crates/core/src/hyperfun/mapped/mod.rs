//! A space-mapped Bézier leaf in HyperFun: the inverse map written in the language itself.
//!
//! `f(x)` is the largest clipped `S_ξ(u) & F_s(u)` over the preimages `u` of `x` in the closed
//! parameter box (`S(u) = x`), and where `x` has none the negative continuation: `S_ξ & F_s` at the
//! root of the polynomial map extended past the box, forced negative (the first paper's §3.3.2 and
//! DESIGN §5, as `eval` computes it). The file finds the preimages as `eval` does on its fast
//! path, with HyperFun's arrays, loops and conditionals:
//!
//! - Newton's method from the inverse map's spline guess first, as `eval`'s continuation runs it:
//!   where the map is certified injective, a root in the box is the one preimage and a root past
//!   it is the continuation's (`S` and its Jacobian summed factored along the axes, `sums.rs`;
//!   each step by Cramer's rule, stopped by `eval`'s tolerances relative to the net's extent);
//! - a table of seeds over the parameter box with their images (constants, computed here by the
//!   forward map): an injective map tries its few nearest seeds where Newton from the guess
//!   fails inside the net's box; a map that may fold tries its nearest seed and every seed whose
//!   image lies within a radius that bounds how far a seed's image can be from a preimage's;
//! - the largest clipped value over the roots in the box, else the continuation (`program.rs`).
//!
//! Where the map is certified injective the value is `eval`'s to rounding; where it folds the seeds
//! are denser (three per degree along each axis), which finds the roots that `eval`'s atlas finds
//! except within rounding of a fold.

// Axes index the net's counts, the seed tables and the names at once.
#![allow(clippy::needless_range_loop)]

mod program;
mod sums;

pub(super) use program::{indent, write_mapped};

use alloc::vec::Vec;

use crate::dim::Control;
use crate::dim::{Dim, Dimension};
use crate::inverse::tps::Kernel;
use crate::inverse::{Forward, InverseMap};
use crate::solid::Solid;
use crate::tensor::Tensor;

/// The most seeds one leaf's table holds.
const MAX_SEEDS: usize = 4096;

/// Newton steps from a seed towards a root in the box (as many as eval's fast path takes).
const ROOT_STEPS: usize = 12;

/// The seeds an injective map tries where Newton from the guess fails: the nearest few to the
/// point, among those within the radius (the others cannot be a preimage's nearest seed).
const NEAREST_SEEDS: usize = 4;

/// A seed's Newton iterate this far from the box's centre along an axis (in parameters) has left
/// for a root past the box: the seed is dropped.
const SEED_ESCAPE: f64 = 2.0;

/// The continuation's Newton escapes where eval's does (`|u| ≥ 8`).
const ESCAPE: f64 = 8.0;

/// A Newton step this short has settled (the residual is checked once more), as in `eval`. Past
/// the box (the continuation, `|u|` up to 8) the polynomial's terms cancel and a root may never
/// settle to this: `eval` then takes the spline guess, and the file does the same unless its own
/// rounding, which differs, lets it settle (a few points in a thousand far outside a net, both
/// values negative).
const SETTLED_STEP: f64 = 1e-13;

/// A positive number below any determinant or value the file meets, and one above any squared
/// distance: exponents whose digits after the first are zeros, which HyperFun's scanner reads
/// right (it misreads `1e-15` as `1e-5`; see [`super::num`]).
const TINY: &str = "1e-300";
const HUGE: &str = "1e300";

/// A space-mapped Bézier leaf as its export needs it, whatever its dimension.
pub(super) struct MappedLeaf {
    /// Control points per axis.
    dims: Vec<usize>,
    /// The control points' spatial coordinates, one list per coordinate, in storage order (the
    /// last axis fastest).
    spatial: Vec<Vec<f64>>,
    /// The control points' ξ in the same order.
    xi: Vec<f64>,
    /// Whether the map is certified injective (one preimage at most).
    injective: bool,
    /// The net's extent: the unit of residuals.
    scale: f64,
    /// The seeds' parameters, one list per axis.
    seeds: Vec<Vec<f64>>,
    /// The seeds' images, one list per coordinate.
    images: Vec<Vec<f64>>,
    /// A seed whose image is farther than this from the point is not the nearest seed of any of
    /// its preimages.
    radius: f64,
    /// Where the continuation's Newton starts: the inverse map's spline guess, as `eval` starts
    /// it ([`crate::inverse::InverseMap::outside`]); `None` for a cell that is a linear map (no
    /// inverse map), whose continuation starts at the nearest seed and converges in one step.
    guess: Option<Guess>,
    /// The control points' bounding box, per coordinate: it holds the image.
    bounds: Vec<(f64, f64)>,
}

/// A spline guess's numbers ([`crate::inverse::tps::Spline::parts`]), one list per coordinate.
struct Guess {
    kernel: Kernel,
    centre: Vec<f64>,
    inv_scale: f64,
    /// The normalised sites, one list per coordinate.
    sites: Vec<Vec<f64>>,
    /// The sites' weights, one list per parameter.
    weights: Vec<Vec<f64>>,
    /// Row 0 the constant, row `1 + c` the coefficients of coordinate `c`.
    affine: Vec<Vec<f64>>,
}

impl Guess {
    fn of<const D: usize>(map: &InverseMap<D>) -> Self {
        let parts = map.spline().parts();
        Self {
            kernel: parts.kernel,
            centre: parts.centre.to_vec(),
            inv_scale: parts.inv_scale,
            sites: (0..D)
                .map(|c| parts.sites.iter().map(|s| s[c]).collect())
                .collect(),
            weights: (0..D)
                .map(|a| parts.weights.iter().map(|w| w[a]).collect())
                .collect(),
            affine: parts.affine.iter().map(|row| row.to_vec()).collect(),
        }
    }
}

/// The parts of a space-mapped solid; `None` for a regular grid (which has a closed form).
pub(super) fn mapped_leaf<const D: usize>(s: &Solid<D>) -> Option<MappedLeaf>
where
    Dim<D>: Dimension<D>,
{
    Some(mapped_net(s.net(), Some(s.inverse()?)))
}

/// The parts of any net as a space mapping with its inverse map, or without one a regular cell of
/// a moved piecewise solid (whose map is linear and injective).
pub(super) fn mapped_net<const D: usize>(
    net: &Tensor<Control<D>, D>,
    map: Option<&InverseMap<D>>,
) -> MappedLeaf
where
    Dim<D>: Dimension<D>,
{
    let injective = map.is_none_or(InverseMap::injective);
    let dims = net.dims();
    let points: Vec<([f64; D], f64)> = net.points().iter().map(|&c| Dim::<D>::split(c)).collect();
    let spatial: Vec<Vec<f64>> = (0..D)
        .map(|c| points.iter().map(|(x, _)| x[c]).collect())
        .collect();
    let xi = points.iter().map(|&(_, v)| v).collect();
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for (x, _) in &points {
        for c in 0..D {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let scale = (0..D)
        .map(|c| (hi[c] - lo[c]).max(lo[c].abs()).max(hi[c].abs()))
        .fold(0.0f64, f64::max);
    // Seeds per axis: a few per degree, more where the map may fold, within the table's cap.
    let per_degree = if injective { 1 } else { 3 };
    let mut grid: [usize; D] = core::array::from_fn(|a| per_degree * (dims[a] - 1) + 2);
    while grid.iter().product::<usize>() > MAX_SEEDS {
        let widest = (0..D).max_by_key(|&a| grid[a]).unwrap_or(0);
        grid[widest] -= 1;
    }
    let count: usize = grid.iter().product();
    let mut seeds: Vec<Vec<f64>> = (0..D).map(|_| Vec::with_capacity(count)).collect();
    let mut images: Vec<Vec<f64>> = (0..D).map(|_| Vec::with_capacity(count)).collect();
    for flat in 0..count {
        let mut rest = flat;
        let mut u = [0.0; D];
        for a in (0..D).rev() {
            u[a] = (rest % grid[a]) as f64 / (grid[a] - 1) as f64;
            rest /= grid[a];
        }
        let e = net.forward(u);
        for a in 0..D {
            seeds[a].push(u[a]);
            images[a].push(e.x[a]);
        }
    }
    // |∂S/∂u_a| ≤ n_a · the longest step between neighbours along a; a preimage's nearest seed
    // is within half a spacing along each axis. Twice that where the map may fold, so that the
    // next seeds are tried too.
    let reach = if injective { 0.5 } else { 1.0 };
    let radius = reach
        * (0..D)
            .map(|a| {
                let n = dims[a] - 1;
                let stride: usize = dims[a + 1..].iter().product();
                let longest = (0..points.len())
                    .filter(|i| (i / stride) % dims[a] < n)
                    .map(|i| {
                        let (p, q) = (points[i].0, points[i + stride].0);
                        libm::sqrt((0..D).map(|c| (q[c] - p[c]) * (q[c] - p[c])).sum::<f64>())
                    })
                    .fold(0.0f64, f64::max);
                n as f64 * longest / (grid[a] - 1) as f64
            })
            .sum::<f64>();
    MappedLeaf {
        dims: dims.to_vec(),
        spatial,
        xi,
        injective,
        scale: scale.max(f64::MIN_POSITIVE),
        seeds,
        images,
        radius,
        guess: map.map(Guess::of),
        bounds: (0..D).map(|c| (lo[c], hi[c])).collect(),
    }
}

impl MappedLeaf {
    /// The continuation's Newton steps at most, as `InverseMap::outside`: 30 where the map is
    /// injective, else 8 (within a query budget that a single point never exhausts).
    fn outside_steps(&self) -> usize {
        if self.injective { 30 } else { 8 }
    }

    /// How many numbers the export writes for this leaf (its arrays' lengths).
    pub(super) fn numbers(&self) -> usize {
        let d = self.dims.len();
        let guess = self.guess.as_ref().map_or(0, |g| 2 * d * g.sites[0].len());
        (d + 1) * self.xi.len() + 2 * d * self.seeds[0].len() + guess
    }
}
