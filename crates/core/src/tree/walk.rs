//! The walk of a tree's mesh grid: boxes of cells bounded by interval arithmetic from the whole
//! grid down, those of one sign skipped, the rest split in eight down to blocks sampled whole,
//! each with the tree's program pruned to it; on rayon's pool below the second level, and with
//! the leaves' ranges kept between walks for cheap edits ([`RangeMemo`]).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::DVec3;

use super::mesh::{Field, MeshStats, Plan};
use super::{Interval, Shape, Step, Tree};
use crate::mesh::SampleGrid;
use crate::mesh::adaptive::octants;
use crate::mesh::polygonize::Block;

/// Boxes of at most this many cells per side are sampled whole rather than bounded again.
const LEAF_CELLS: usize = 4;

/// What bounding one box of cells gave ([`Tree::bound_box`]).
enum Bounded {
    Skipped,
    Block(Block, Option<Vec<Step>>),
    Split([usize; 3]),
}

impl Tree<3> {
    /// The blocks of `grid` ([`Tree::blocks_plan`]), the leaves' ranges over its boxes taken
    /// from `memo` where it holds them, and kept there for the next walk.
    pub(super) fn walk(
        &self,
        grid: SampleGrid,
        clip: Option<Shape<3>>,
        accuracy: f64,
        memo: Option<&mut RangeMemo>,
    ) -> Plan<'_> {
        let field = Field::new(self, clip);
        let [nx, ny, nz] = grid.dims;
        let mut stats = MeshStats {
            cells: (nx - 1) * (ny - 1) * (nz - 1),
            ..MeshStats::default()
        };
        // The magnitude of f in the region: a sample on a block's face within `tau` of zero by a
        // pruned program takes the whole tree's value, so that both blocks beside the face see
        // one sign (a pruned program has the tree's signs; rounding, far below `tau`, does not).
        let whole = self.interval(
            grid.point(0, 0, 0).to_array(),
            grid.point(nx - 1, ny - 1, nz - 1).to_array(),
        );
        let scale = whole.lo.abs().max(whole.hi.abs());
        let tau = if scale.is_finite() {
            accuracy.max(1e-10 * scale)
        } else {
            accuracy
        };
        let root = ([0usize; 3], [nx - 1, ny - 1, nz - 1]);
        let (programs, blocks) = match memo {
            // Kept ranges are looked up and made in the walk's order: one thread.
            Some(memo) => self.walk_from(&grid, field.clip.as_ref(), root, Some(memo), &mut stats),
            #[cfg(feature = "parallel")]
            None => self.walk_on_pool(&grid, field.clip.as_ref(), root, &mut stats),
            #[cfg(not(feature = "parallel"))]
            None => self.walk_from(&grid, field.clip.as_ref(), root, None, &mut stats),
        };
        Plan {
            grid,
            field,
            accuracy,
            tau,
            programs,
            blocks,
            stats,
        }
    }

    /// Boxes of cells from `root` down, bounded by intervals: one sign, no surface (skipped);
    /// else split in eight, down to boxes sampled whole as blocks, each with its pruned program
    /// (a block's tag: its program's index in the programs returned). Depth first, the high
    /// corner first; the counts added to `stats`.
    pub(super) fn walk_from(
        &self,
        grid: &SampleGrid,
        clip: Option<&Shape<3>>,
        root: ([usize; 3], [usize; 3]),
        mut memo: Option<&mut RangeMemo>,
        stats: &mut MeshStats,
    ) -> (Vec<Vec<Step>>, Vec<Block>) {
        let mut programs: Vec<Vec<Step>> = Vec::new();
        let mut blocks: Vec<Block> = Vec::new();
        let mut todo = alloc::vec![root];
        let mut scratch = (Vec::with_capacity(self.leaves.len()), Vec::new());
        while let Some((lo, hi)) = todo.pop() {
            match self.bound_box(
                grid,
                clip,
                (lo, hi),
                memo.as_deref_mut(),
                &mut scratch,
                stats,
            ) {
                Bounded::Skipped => {}
                Bounded::Block(mut block, program) => {
                    block.tag = match program {
                        Some(program) => {
                            programs.push(program);
                            (programs.len() - 1) as u32
                        }
                        None => u32::MAX,
                    };
                    blocks.push(block);
                }
                Bounded::Split(mid) => todo.extend(octants(lo, mid, hi).map(|(_, child)| child)),
            }
        }
        (programs, blocks)
    }

    /// [`Tree::walk_from`] with the boxes of the second level walked on rayon's pool: the same
    /// blocks in the same order, the same programs.
    #[cfg(feature = "parallel")]
    pub(super) fn walk_on_pool(
        &self,
        grid: &SampleGrid,
        clip: Option<&Shape<3>>,
        root: ([usize; 3], [usize; 3]),
        stats: &mut MeshStats,
    ) -> (Vec<Vec<Step>>, Vec<Block>) {
        use rayon::prelude::*;
        /// A box still to walk, or a block found on the way down.
        enum Found {
            Box([usize; 3], [usize; 3]),
            Block(Block, Option<Vec<Step>>),
        }
        let mut scratch = (Vec::with_capacity(self.leaves.len()), Vec::new());
        let mut frontier = alloc::vec![Found::Box(root.0, root.1)];
        for _ in 0..2 {
            let mut next = Vec::new();
            for found in frontier {
                let Found::Box(lo, hi) = found else {
                    next.push(found);
                    continue;
                };
                match self.bound_box(grid, clip, (lo, hi), None, &mut scratch, stats) {
                    Bounded::Skipped => {}
                    Bounded::Block(block, program) => next.push(Found::Block(block, program)),
                    // The walk takes the children from the high corner down.
                    Bounded::Split(mid) => next.extend(
                        octants(lo, mid, hi)
                            .rev()
                            .map(|(_, (a, b))| Found::Box(a, b)),
                    ),
                }
            }
            frontier = next;
        }
        let walked: Vec<(Vec<Vec<Step>>, Vec<Block>, MeshStats)> = frontier
            .into_par_iter()
            .map(|found| match found {
                Found::Box(lo, hi) => {
                    let mut part = MeshStats::default();
                    let (programs, blocks) = self.walk_from(grid, clip, (lo, hi), None, &mut part);
                    (programs, blocks, part)
                }
                Found::Block(block, program) => {
                    let programs = program.into_iter().collect();
                    (programs, alloc::vec![block], MeshStats::default())
                }
            })
            .collect();
        let (mut programs, mut blocks) = (Vec::new(), Vec::new());
        for (part_programs, part_blocks, part) in walked {
            let base = programs.len() as u32;
            blocks.extend(part_blocks.into_iter().map(|mut block| {
                if block.tag != u32::MAX {
                    block.tag += base;
                }
                block
            }));
            programs.extend(part_programs);
            stats.skipped += part.skipped;
            stats.evaluated += part.evaluated;
        }
        (programs, blocks)
    }

    /// The box of cells `[lo, hi]` bounded: one sign (skipped, its cells counted), a block to
    /// sample with its pruned program (its tag not set yet), or the cut to split it at.
    fn bound_box(
        &self,
        grid: &SampleGrid,
        clip: Option<&Shape<3>>,
        (lo, hi): ([usize; 3], [usize; 3]),
        memo: Option<&mut RangeMemo>,
        (leaves, scratch): &mut (Vec<Interval>, Vec<f64>),
        stats: &mut MeshStats,
    ) -> Bounded {
        let (plo, phi) = (
            grid.point(lo[0], lo[1], lo[2]),
            grid.point(hi[0], hi[1], hi[2]),
        );
        match memo {
            Some(memo) => memo.ranges(self, (lo, hi), plo, phi, leaves, scratch),
            None => self.leaf_ranges(plo.to_array(), phi.to_array(), leaves),
        }
        let mut range = self.range_of(leaves);
        if let Some(b) = clip {
            range = range.intersect_box(b, plo.to_array(), phi.to_array());
        }
        let size = [0, 1, 2].map(|k| hi[k] - lo[k]);
        if range.hi < 0.0 || range.lo > 0.0 {
            stats.skipped += size.iter().product::<usize>();
            Bounded::Skipped
        } else if size.iter().all(|&s| s <= LEAF_CELLS) {
            // The box's own program, without the operands that cannot decide a sign in it:
            // the tree's signs, zero set and normals there, for the cost of what is near.
            stats.evaluated += size.iter().map(|s| s + 1).product::<usize>();
            Bounded::Block(Block { lo, size, tag: 0 }, self.pruned_of(leaves))
        } else {
            Bounded::Split([0, 1, 2].map(|k| lo[k] + size[k] / 2))
        }
    }
}

/// The most leaf ranges a [`RangeMemo`] keeps (16 bytes each): past it, the ranges of the boxes
/// walked last are bounded again next time.
const MEMO_RANGES: usize = 1 << 20;

/// The leaves' ranges over the boxes of a walk, kept for the next walk over the same grid: a leaf
/// unchanged since has the same ranges.
#[derive(Clone, Debug, Default)]
pub(super) struct RangeMemo {
    /// By leaf of the tree walked: how it changed since the ranges in `kept` were made.
    pub(super) changes: Vec<super::remesh::Change>,
    /// The ranges by leaf over each box (its first and last sample) of the last walk.
    pub(super) kept: BTreeMap<([usize; 3], [usize; 3]), Vec<Interval>>,
    /// This walk's.
    pub(super) made: BTreeMap<([usize; 3], [usize; 3]), Vec<Interval>>,
}

impl RangeMemo {
    /// The ranges of `tree`'s leaves over the box `key` (`[plo, phi]` in space), in `out`.
    fn ranges(
        &mut self,
        tree: &Tree<3>,
        key: ([usize; 3], [usize; 3]),
        plo: DVec3,
        phi: DVec3,
        out: &mut Vec<Interval>,
        scratch: &mut Vec<f64>,
    ) {
        let (lo, hi) = (plo.to_array(), phi.to_array());
        let kept = self.kept.remove(&key);
        out.clear();
        out.extend((0..tree.leaves.len()).map(|i| {
            let known = kept.as_ref().and_then(|k| k.get(i));
            let same = match (self.changes.get(i), tree.leaves.get(i)) {
                (Some(change), Some(leaf)) => change.same_over(leaf, lo, hi),
                _ => false,
            };
            match known {
                Some(&range) if same => range,
                _ => tree.leaf_range(i, lo, hi, scratch),
            }
        }));
        // Kept within a bound (the cache of a worker that meshes a model of many leaves at a
        // fine resolution would otherwise hold a range for every leaf over every box).
        if (self.made.len() + 1) * out.len() <= MEMO_RANGES {
            self.made.insert(key, out.clone());
        }
    }
}
