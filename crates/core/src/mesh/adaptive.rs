//! Meshing whose cost follows the surface: the grid's cells are split into boxes, top down, and a
//! box is dropped where bounds prove the field has one sign on it; only the boxes that may hold the
//! surface are sampled, as blocks, and marched ([`super::polygonize::polygonize_blocks`]).
//!
//! For a Bézier solid the bounds are exact in the sense of Bernstein form: `S_ξ` restricted to a box
//! of parameters is again a polynomial of the same degrees, whose Bernstein coefficients (the net
//! subdivided by de Casteljau along each axis) enclose its values there (the convex hull property).
//! A box is dropped only when its coefficients clear zero by a margin far above their rounding, so
//! every sample the uniform grid would take there has the sign the box was given.

use alloc::vec::Vec;

use super::polygonize::Block;
use crate::bernstein::{MAX_DEGREE, casteljau_level};

/// Boxes of at most this many cells per side are sampled whole rather than bounded again.
pub(crate) const LEAF_CELLS: usize = 8;

/// What an adaptive meshing did: how much of the grid the bounds let it skip.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdaptiveStats {
    /// Cells of the grid.
    pub cells: usize,
    /// Cells in boxes the bounds proved all inside or all outside (no surface, no samples).
    pub skipped: usize,
    /// Boxes bounded.
    pub bounded: usize,
    /// Blocks sampled and marched.
    pub blocks: usize,
    /// Samples evaluated (a sample on the face between two blocks counts in each).
    pub evaluated: usize,
}

impl AdaptiveStats {
    /// The counts of a part of the grid's boxes added to these (`cells` is the grid's, kept).
    #[cfg(feature = "parallel")]
    fn add(&mut self, part: Self) {
        self.skipped += part.skipped;
        self.bounded += part.bounded;
        self.blocks += part.blocks;
        self.evaluated += part.evaluated;
    }
}

/// The net `net` (degrees `degree`, last index fastest) of a polynomial on a box, split along
/// `axis` at the fraction `t` of the box's side: `left` and `right` become the nets of the same
/// polynomial on the two parts (de Casteljau along every line of the axis).
pub(crate) fn split_net(
    net: &[f64],
    degree: [usize; 3],
    axis: usize,
    t: f64,
    left: &mut Vec<f64>,
    right: &mut Vec<f64>,
) {
    // A net of one degree on every axis (the common case) has its own code, with the degree a
    // constant; others take the general one.
    let [n, m, l] = degree;
    if n == m && m == l {
        match n {
            1 => return split_in::<2>(net, [1; 3], axis, t, left, right),
            2 => return split_in::<3>(net, [2; 3], axis, t, left, right),
            3 => return split_in::<4>(net, [3; 3], axis, t, left, right),
            4 => return split_in::<5>(net, [4; 3], axis, t, left, right),
            5 => return split_in::<6>(net, [5; 3], axis, t, left, right),
            _ => {}
        }
    }
    split_in::<{ MAX_DEGREE + 1 }>(net, degree, axis, t, left, right);
}

/// [`split_net`] for degrees below `L`.
#[inline(always)]
fn split_in<const L: usize>(
    net: &[f64],
    degree: [usize; 3],
    axis: usize,
    t: f64,
    left: &mut Vec<f64>,
    right: &mut Vec<f64>,
) {
    let dims = degree.map(|d| d + 1);
    let strides = [dims[1] * dims[2], dims[2], 1];
    left.clear();
    left.extend_from_slice(net);
    right.clear();
    right.extend_from_slice(net);
    // Of one degree on every axis, `degree[0]`: a constant where the caller passed constants
    // (`degree[axis]` with `axis` unknown is a load, and the loops would not unroll).
    let d = if degree[1] == degree[0] && degree[2] == degree[0] {
        degree[0]
    } else {
        degree[axis]
    };
    let (len, stride) = (d + 1, strides[axis]);
    let outer: usize = dims[..axis].iter().product();
    let mut p = [0.0; L];
    for o in 0..outer {
        for inner in 0..stride {
            let start = o * len * stride + inner;
            for (i, slot) in p[..len].iter_mut().enumerate() {
                *slot = net[start + i * stride];
            }
            // After level k, p[i] is the i-th point of that level: the left part takes the
            // first point of each level, the right part the last.
            for k in 1..=d {
                casteljau_level(&mut p, t, d - k);
                left[start + k * stride] = p[0];
                right[start + (d - k) * stride] = p[d - k];
            }
        }
    }
}

/// The boxes of cells `[lo, hi]` is cut into at `mid` (a cut at `hi` on an axis is no cut), with
/// their corner numbers (bit `k` set: the high side along axis `k`), lowest first; boxes of no
/// width left out.
pub(crate) fn octants(
    lo: [usize; 3],
    mid: [usize; 3],
    hi: [usize; 3],
) -> impl DoubleEndedIterator<Item = (usize, ([usize; 3], [usize; 3]))> {
    (0..8).filter_map(move |corner| {
        let side = |k: usize| {
            if corner >> k & 1 == 0 {
                (lo[k], mid[k])
            } else {
                (mid[k], hi[k])
            }
        };
        let [a, b, c] = [side(0), side(1), side(2)];
        (a.0 < a.1 && b.0 < b.1 && c.0 < c.1)
            .then_some((corner, ([a.0, b.0, c.0], [a.1, b.1, c.1])))
    })
}

/// The least and greatest of `net`'s coefficients, which bound its polynomial; anything NaN
/// bounds nothing.
fn range(net: &[f64]) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in net {
        if v.is_nan() {
            return (f64::NEG_INFINITY, f64::INFINITY);
        }
        // Comparisons, not `f64::min`: no NaN comes here, and wasm has no instruction for the
        // library's NaN rule (each would be a call).
        if v < lo {
            lo = v;
        }
        if v > hi {
            hi = v;
        }
    }
    (lo, hi)
}

/// The blocks of cells of a grid whose samples are at parameters `params` (per axis, increasing;
/// those outside `[0, 1]` are outside the solid whatever `S_ξ` is) that the Bernstein bounds of
/// `net` cannot prove free of the surface, in a fixed order, and what the bounding did.
///
/// A box's net is its parent's split at the box's cut (on the parameters clamped to `[0, 1]`,
/// where the root's net is the solid's own), so a box costs one de Casteljau pass per line, shared
/// with its siblings. The order is the walk's, depth first with the low corner first; with the
/// `parallel` feature the boxes of the second level are walked on the thread pool and their blocks
/// joined in that order, so the blocks are the same whichever way they were found.
pub(crate) fn blocks(
    net: &[f64],
    degree: [usize; 3],
    params: &[Vec<f64>; 3],
) -> (Vec<Block>, AdaptiveStats) {
    let dims = [0, 1, 2].map(|k| params[k].len());
    let mut stats = AdaptiveStats::default();
    let mut out = Vec::new();
    if dims.iter().any(|&d| d < 2) {
        return (out, stats);
    }
    stats.cells = dims.iter().map(|d| d - 1).product();
    // Far above the rounding of the splits (a few ulps of the largest coefficient per level).
    let scale = net.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let bounder = Bounder {
        degree,
        params,
        margin: 1e-12 * scale,
    };
    let root = ([0usize; 3], dims.map(|d| d - 1));
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        // The first two levels walked here, breadth first but in the walk's order: blocks found
        // on the way stay in their place among the boxes left to walk.
        let mut frontier = alloc::vec![Found::Box(root.0, root.1, net.to_vec())];
        let mut scratch = Scratch::new(net.len());
        for _ in 0..2 {
            let mut next = Vec::new();
            for found in frontier {
                let Found::Box(lo, hi, net) = found else {
                    next.push(found);
                    continue;
                };
                match bounder.visit(lo, hi, &net, &mut scratch, &mut stats) {
                    Visit::Done(None) => {}
                    Visit::Done(Some(block)) => next.push(Found::Block(block)),
                    Visit::Split(mid) => {
                        next.extend(octants(lo, mid, hi).map(|(corner, (a, b))| {
                            Found::Box(a, b, scratch.parts[corner].clone())
                        }));
                    }
                }
            }
            frontier = next;
        }
        let walked: Vec<(Vec<Block>, AdaptiveStats)> = frontier
            .into_par_iter()
            .map(|found| match found {
                Found::Block(block) => (alloc::vec![block], AdaptiveStats::default()),
                Found::Box(lo, hi, net) => {
                    let (mut out, mut stats) = (Vec::new(), AdaptiveStats::default());
                    bounder.walk((lo, hi), &net, &mut out, &mut stats);
                    (out, stats)
                }
            })
            .collect();
        out.reserve(walked.iter().map(|(blocks, _)| blocks.len()).sum());
        for (blocks, part) in walked {
            out.extend(blocks);
            stats.add(part);
        }
    }
    #[cfg(not(feature = "parallel"))]
    bounder.walk(root, net, &mut out, &mut stats);
    (out, stats)
}

/// A box met on the way down, still to be walked with its net, or a block found.
#[cfg(feature = "parallel")]
enum Found {
    Box([usize; 3], [usize; 3], Vec<f64>),
    Block(Block),
}

/// What bounding one box gave: nothing more to do (a block to sample, or no surface), or the cut
/// at `mid` whose children's nets are in [`Scratch::parts`] by corner.
enum Visit {
    Done(Option<Block>),
    Split([usize; 3]),
}

/// The nets one box's split is made in, reused from box to box.
struct Scratch {
    parts: [Vec<f64>; 8],
    spare: Vec<f64>,
}

impl Scratch {
    fn new(size_of_net: usize) -> Self {
        Self {
            parts: Default::default(),
            spare: Vec::with_capacity(size_of_net),
        }
    }
}

/// The bounding of boxes of one grid's cells by the Bernstein nets of `S_ξ` on them.
struct Bounder<'a> {
    degree: [usize; 3],
    params: &'a [Vec<f64>; 3],
    /// A box is dropped only where its coefficients clear zero by this much.
    margin: f64,
}

impl Bounder<'_> {
    /// The box of cells `[lo, hi]` whose net is `net`, and every box under it, walked depth
    /// first (the low corner first): its blocks appended to `out`.
    fn walk(
        &self,
        root: ([usize; 3], [usize; 3]),
        net: &[f64],
        out: &mut Vec<Block>,
        stats: &mut AdaptiveStats,
    ) {
        let size_of_net = net.len();
        let mut scratch = Scratch::new(size_of_net);
        // The nets of the boxes waiting in `todo`, in the same order (a stack beside a stack).
        let mut nets: Vec<f64> = net.to_vec();
        let mut todo = alloc::vec![root];
        let mut current = alloc::vec![0.0; size_of_net];
        while let Some((lo, hi)) = todo.pop() {
            let at = nets.len() - size_of_net;
            current.copy_from_slice(&nets[at..]);
            nets.truncate(at);
            match self.visit(lo, hi, &current, &mut scratch, stats) {
                Visit::Done(block) => out.extend(block),
                Visit::Split(mid) => {
                    for (corner, child) in octants(lo, mid, hi).rev() {
                        todo.push(child);
                        nets.extend_from_slice(&scratch.parts[corner]);
                    }
                }
            }
        }
    }

    /// One box of cells `[lo, hi]` with its net `current`: dropped where its bounds clear zero,
    /// a block where it is no more than a leaf, else split (the children's nets in `scratch`).
    fn visit(
        &self,
        lo: [usize; 3],
        hi: [usize; 3],
        current: &[f64],
        scratch: &mut Scratch,
        stats: &mut AdaptiveStats,
    ) -> Visit {
        let params = self.params;
        let clamped = |k: usize, i: usize| params[k][i].clamp(0.0, 1.0);
        let size = [0, 1, 2].map(|k| hi[k] - lo[k]);
        stats.bounded += 1;
        let (min, max) = range(current);
        // Outside: `S_ξ < 0` in the box, and samples past the box's faces are outside anyway.
        // Inside: `S_ξ > 0` and every sample strictly within the box's faces.
        let interior = (0..3).all(|k| params[k][lo[k]] > 0.0 && params[k][hi[k]] < 1.0);
        if max < -self.margin || (min > self.margin && interior) {
            stats.skipped += size.iter().product::<usize>();
            return Visit::Done(None);
        }
        if size.iter().all(|&s| s <= LEAF_CELLS) {
            stats.blocks += 1;
            stats.evaluated += size.iter().map(|s| s + 1).product::<usize>();
            return Visit::Done(Some(Block { lo, size, tag: 0 }));
        }
        // Halve the sides longer than a leaf: `parts[corner]` is the net of the child on the
        // low (bit clear) or high side of each cut.
        let mid = [0, 1, 2].map(|k| {
            if size[k] > LEAF_CELLS {
                lo[k] + size[k] / 2
            } else {
                hi[k]
            }
        });
        let Scratch { parts, spare } = scratch;
        parts[0].clear();
        parts[0].extend_from_slice(current);
        let (mut made, mut count) = ([0usize; 8], 1);
        for k in 0..3 {
            if mid[k] == hi[k] {
                continue;
            }
            let t =
                (clamped(k, mid[k]) - clamped(k, lo[k])) / (clamped(k, hi[k]) - clamped(k, lo[k]));
            // A cut that is not inside the side (a box of no width) leaves nets that bound nothing.
            let t = if (0.0..=1.0).contains(&t) {
                t
            } else {
                f64::NAN
            };
            for i in 0..count {
                let corner = made[i];
                let [low, high] = parts
                    .get_disjoint_mut([corner, corner | 1 << k])
                    .unwrap_or_else(|_| unreachable!("two corners"));
                spare.clone_from(low);
                split_net(spare, self.degree, k, t, low, high);
                made[count + i] = corner | 1 << k;
            }
            count *= 2;
        }
        Visit::Split(mid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Volume;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The split of a net of one degree on every axis (its degree a constant) is the general
    /// code's, bit for bit.
    #[test]
    fn the_split_for_one_degree_is_the_general_split() {
        let mut rng = Rng::new(11);
        for d in 1..=6 {
            let net = Volume::from_fn([d; 3], |_| rng.range(-1.0, 1.0)).unwrap();
            for axis in 0..3 {
                let t = rng.range(0.1, 0.9);
                let (mut left, mut right) = (Vec::new(), Vec::new());
                split_net(net.points(), [d; 3], axis, t, &mut left, &mut right);
                let (mut left2, mut right2) = (Vec::new(), Vec::new());
                split_in::<{ MAX_DEGREE + 1 }>(
                    net.points(),
                    [d; 3],
                    axis,
                    t,
                    &mut left2,
                    &mut right2,
                );
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&left), bits(&left2), "degree {d}, axis {axis}");
                assert_eq!(bits(&right), bits(&right2), "degree {d}, axis {axis}");
            }
        }
    }

    #[test]
    fn split_nets_are_the_same_polynomial_and_bound_it() {
        let mut rng = Rng::new(7);
        for _ in 0..200 {
            let degree = [rng.int(1, 5), rng.int(1, 5), rng.int(1, 5)];
            let net = Volume::from_fn(degree, |_| rng.range(-1.0, 1.0))
                .unwrap_or_else(|_| unreachable!("valid degrees"));
            let axis = rng.int(0, 2);
            let t = rng.range(0.01, 0.99);
            let (mut left, mut right) = (Vec::new(), Vec::new());
            split_net(net.points(), degree, axis, t, &mut left, &mut right);
            for (part, lo, hi) in [(left, 0.0, t), (right, t, 1.0)] {
                let (min, max) = range(&part);
                let part =
                    Volume::try_new(degree, part).unwrap_or_else(|_| unreachable!("the same size"));
                for _ in 0..20 {
                    let s: [f64; 3] = core::array::from_fn(|_| rng.range(0.0, 1.0));
                    let mut at = s;
                    at[axis] = lo + (hi - lo) * s[axis];
                    let (whole, piece) = (net.eval(at), part.eval(s));
                    assert!((whole - piece).abs() < 1e-12, "{whole} {piece}");
                    assert!(min - 1e-12 <= whole && whole <= max + 1e-12);
                }
            }
        }
    }

    /// The blocks found with the second level's boxes walked apart (on the pool, where there is
    /// one) are the blocks of one walk from the root, in the same order, with the same counts.
    #[test]
    fn the_blocks_are_those_of_one_walk() {
        let mut rng = Rng::new(5);
        for _ in 0..12 {
            let degree = [rng.int(1, 5), rng.int(1, 5), rng.int(1, 5)];
            // A ball-like field: positive in the middle, negative at the corners, so that
            // boxes are dropped both ways and the surface crosses many.
            let net = Volume::from_fn(degree, |[i, j, k]| {
                let d = |a: usize, n: usize| (a as f64 / n as f64 - 0.5).powi(2);
                0.2 - d(i, degree[0]) - d(j, degree[1]) - d(k, degree[2]) + rng.range(-0.05, 0.05)
            })
            .unwrap_or_else(|_| unreachable!("valid degrees"));
            let params: [Vec<f64>; 3] = core::array::from_fn(|_| {
                let n = rng.int(2, 90);
                (0..n)
                    .map(|a| (a as f64 - 0.5) / (n as f64 - 2.0))
                    .collect()
            });
            let (found, stats) = blocks(net.points(), degree, &params);
            let bounder = Bounder {
                degree,
                params: &params,
                margin: 1e-12 * net.points().iter().fold(0.0f64, |m, v| m.max(v.abs())),
            };
            let (mut walked, mut walk_stats) = (Vec::new(), AdaptiveStats::default());
            walk_stats.cells = params.iter().map(|p| p.len() - 1).product();
            let root = ([0; 3], params.each_ref().map(|p| p.len() - 1));
            bounder.walk(root, net.points(), &mut walked, &mut walk_stats);
            assert_eq!(found, walked);
            assert_eq!(stats, walk_stats);
            assert!(stats.skipped > 0 || stats.cells < 1000, "{stats:?}");
        }
    }

    #[test]
    fn a_nan_bounds_nothing() {
        assert_eq!(
            range(&[1.0, f64::NAN, 2.0]),
            (f64::NEG_INFINITY, f64::INFINITY)
        );
        assert_eq!(range(&[1.0, -3.0, 2.0]), (-3.0, 2.0));
    }
}
