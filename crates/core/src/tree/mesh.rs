//! The boundary of a tree: a closed triangle mesh of a 3D tree, the zero contour of a 2D one.
//!
//! The region is the tree's bounds ([`Tree::bounds`]) or a box the caller gives (for a tree that
//! may be unbounded). `f` is sampled on a grid about half a cell past the region on every side (a
//! cell for contours), moved off round numbers by an odd fraction of a cell, marched, and every vertex put on `f = 0` by a root search along its grid edge.
//! Within its own bounds a tree is negative on the outer samples, so the mesh is closed; within a
//! given box the field is `f & box` (the R-function intersection with the box's own function),
//! which is negative outside the box, so the mesh is closed there too, cut by the box's faces.

use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

use super::{Shape, Step, Tree};
use crate::dim::{Dim, Dimension};
use crate::math::{illinois, sampling_box};
use crate::mesh::Mesh;
use crate::mesh::polygonize::{
    Block, BlockRoots, Keyed, Marcher, make_and_weld, polygonize_blocks, split_run,
};
use crate::mesh::{EdgeRoots, SampleGrid};
use crate::mesh::{Piece, Share};
use crate::rfunc::{intersect, intersect_with_partials};

/// The most cells along the longest side of the region.
pub const MAX_RESOLUTION: usize = 512;

/// Why a tree could not be meshed or contoured.
#[derive(Clone, Debug, PartialEq)]
pub enum TreeMeshError {
    /// The tree has no finite bounds (a half-space, a cylinder, a morph past `[0, 1]`, a blend of
    /// a space-mapped solid) and no box was given.
    Unbounded,
    /// The box given is not finite, or empty.
    Region,
    /// The resolution is 0 or above [`MAX_RESOLUTION`].
    Resolution {
        /// The resolution given.
        got: usize,
    },
    /// The accuracy is not a positive finite number.
    Accuracy,
    /// The mesh or contour came out empty while the solid has an inside point: its parts are
    /// finer than the grid's cells (never an empty success).
    Lost {
        /// An inside point (a 2D one's third coordinate 0).
        at: [f64; 3],
        /// `f` there.
        f: f64,
        /// The resolution the grid was made at.
        resolution: usize,
    },
    /// A section's plane misses the box the model fills (or the box given).
    Plane {
        /// The axis across which the plane lies (0 for x).
        axis: usize,
        /// Where it crosses that axis.
        at: f64,
        /// The box's extent along the axis.
        lo: f64,
        /// See `lo`.
        hi: f64,
    },
}

impl fmt::Display for TreeMeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unbounded => f.write_str(
                "the model may be unbounded (a half-space, a cylinder, a morph past 0..1 or a \
                 blend of a space-mapped solid reaches past any box): give a box to mesh it in",
            ),
            Self::Region => f.write_str("the box must be finite, with min below max on every axis"),
            Self::Resolution { got } => {
                write!(f, "resolution {got} is outside 1..={MAX_RESOLUTION}")
            }
            Self::Accuracy => f.write_str("the accuracy must be a positive finite number"),
            Self::Lost {
                at,
                f: value,
                resolution,
            } => {
                write!(
                    f,
                    "the solid is inside at ({}, {}, {}) (f = {value:e}), but its boundary came \
                     out empty at resolution {resolution}: it is finer than the cells there; mesh \
                     at a finer one or in a smaller box",
                    at[0], at[1], at[2]
                )
            }
            Self::Plane { axis, at, lo, hi } => {
                let name = ["x", "y", "z"].get(*axis).copied().unwrap_or("?");
                write!(
                    f,
                    "the plane {name} = {at} misses the model: it fills {name} from {lo} to {hi}"
                )
            }
        }
    }
}

impl core::error::Error for TreeMeshError {}

/// The box to sample and, for a box the caller gave, the box's own function to cut by.
pub(super) struct Region<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    pub(super) lo: [f64; D],
    pub(super) hi: [f64; D],
    pub(super) clip: Option<Shape<D>>,
}

/// How far the sampling grid is moved off the region's corner, in cells. Parts are placed on round
/// numbers (a box from 0.25 to 2), and a sample exactly on a part's boundary (`f = 0` exactly)
/// gives coincident vertices and triangles of no area, which mesh readers refuse; a grid moved by
/// an odd fraction of a cell is on round numbers nowhere. It stays under half a cell, so the outer
/// samples are still past the region on every side.
pub(super) const GRID_SHIFT: f64 = 0.072_334_815_9;

/// The region to sample (`None` for an empty solid).
pub(super) fn region<const D: usize>(
    bounds: Option<([f64; D], [f64; D])>,
    given: Option<([f64; D], [f64; D])>,
    resolution: usize,
    accuracy: f64,
) -> Result<Option<Region<D>>, TreeMeshError>
where
    Dim<D>: Dimension<D>,
{
    if resolution == 0 || resolution > MAX_RESOLUTION {
        return Err(TreeMeshError::Resolution { got: resolution });
    }
    if !(accuracy.is_finite() && accuracy > 0.0) {
        return Err(TreeMeshError::Accuracy);
    }
    match given {
        Some((lo, hi)) => {
            if (0..D).any(|i| !(lo[i].is_finite() && hi[i].is_finite() && lo[i] < hi[i])) {
                return Err(TreeMeshError::Region);
            }
            // Only as much of the box as the tree can fill, when it is bounded.
            let (lo, hi) = match bounds {
                Some((blo, bhi)) => (
                    core::array::from_fn(|i| lo[i].max(blo[i])),
                    core::array::from_fn(|i| hi[i].min(bhi[i])),
                ),
                None => (lo, hi),
            };
            if (0..D).any(|i| lo[i] > hi[i]) {
                return Ok(None);
            }
            let clip = Some(Shape::Box { min: lo, max: hi });
            let (lo, hi) = sampling_box(lo, hi);
            Ok(Some(Region { lo, hi, clip }))
        }
        None => {
            let (lo, hi) = bounds.ok_or(TreeMeshError::Unbounded)?;
            if (0..D).any(|i| lo[i] > hi[i]) {
                return Ok(None); // an empty solid
            }
            let (lo, hi) = sampling_box(lo, hi);
            Ok(Some(Region { lo, hi, clip: None }))
        }
    }
}

/// `f` (and its gradient) of the tree, cut by `clip` where a box was given.
#[derive(Clone)]
pub(super) struct Field<'a, const D: usize>
where
    Dim<D>: Dimension<D>,
{
    tree: &'a Tree<D>,
    pub(super) clip: Option<Shape<D>>,
    stack: Vec<f64>,
}

impl<'a, const D: usize> Field<'a, D>
where
    Dim<D>: Dimension<D>,
{
    /// The field of `tree`, cut by `clip` where a box was given.
    pub(super) fn new(tree: &'a Tree<D>, clip: Option<Shape<D>>) -> Self {
        Self {
            tree,
            clip,
            stack: Vec::with_capacity(tree.stack),
        }
    }

    pub(super) fn f(&mut self, p: [f64; D]) -> f64 {
        self.f_by(None, p)
    }

    /// `f` by a pruned program (see [`Tree::pruned`]), or the tree's own where `None`.
    pub(super) fn f_by(&mut self, program: Option<&[Step]>, p: [f64; D]) -> f64 {
        let steps = program.unwrap_or(&self.tree.steps);
        let f = self.tree.evaluate_program(steps, p, &mut self.stack).f;
        self.clipped(f, p)
    }

    pub(super) fn clipped(&self, f: f64, p: [f64; D]) -> f64 {
        match &self.clip {
            None => f,
            Some(b) => intersect(f, b.eval(p).0),
        }
    }

    /// The outward unit normal `−∇f/|∇f|` (zero where the gradient vanishes), by `program`.
    pub(super) fn normal(&self, program: Option<&[Step]>, p: [f64; D]) -> [f64; D] {
        let (f, g) = self
            .tree
            .gradient_program(program.unwrap_or(&self.tree.steps), p);
        let g = match &self.clip {
            None => g,
            Some(b) => {
                let (fb, gb) = b.gradient(p);
                let (_, da, db) = intersect_with_partials(f, fb);
                core::array::from_fn(|i| da * g[i] + db * gb[i])
            }
        };
        let len = crate::math::sqrt(g.iter().map(|v| v * v).sum());
        if len > 0.0 && len.is_finite() {
            core::array::from_fn(|i| -g[i] / len)
        } else {
            [0.0; D]
        }
    }
}

/// Roots on the edges of a block of the grid, by the block's pruned program (the tree's own where
/// it has none), checked on the whole tree.
struct Roots<'a> {
    field: Field<'a, 3>,
    grid: SampleGrid,
    accuracy: f64,
    /// The pruned programs of the blocks, and the one of the block the walk is in.
    programs: &'a [Vec<Step>],
    program: Option<usize>,
    /// Whether the walk has read the whole tree in the block it is in (an ambiguous face's
    /// corners, a root the block's pruned program left past the accuracy).
    whole: bool,
    /// Per block left: the vertices and triangles made so far, and whether it read the whole tree.
    marks: Vec<(usize, usize, bool)>,
}

impl BlockRoots for Roots<'_> {
    fn enter(&mut self, block: &Block) {
        self.program = (block.tag != u32::MAX).then_some(block.tag as usize);
        self.whole = false;
    }

    fn leave(&mut self, _block: &Block, mesh: &Mesh) {
        self.marks
            .push((mesh.positions.len(), mesh.triangles.len(), self.whole));
    }

    /// The whole tree's value: what the blocks on both sides of a face agree on.
    fn canonical(&mut self, s: [usize; 3], _value: f64) -> f64 {
        self.whole = true;
        self.field.f(self.grid.point(s[0], s[1], s[2]).to_array())
    }
}

impl EdgeRoots for Roots<'_> {
    fn vertex(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3) {
        let a = self.grid.point(lower[0], lower[1], lower[2]);
        let mut step = DVec3::ZERO;
        step[axis] = self.grid.step[axis];
        let b = a + step;
        // The root of the block's pruned program (the tree's zero set there), checked on the
        // whole tree: where rounding leaves it past the accuracy, the whole tree's root on the
        // edge.
        let (programs, program) = (self.programs, self.program);
        let program = program.and_then(|k| programs.get(k)).map(Vec::as_slice);
        let field = &mut self.field;
        let mut t = illinois(
            |t| field.f_by(program, a.lerp(b, t).to_array()),
            f0,
            f1,
            self.accuracy,
        );
        if program.is_some() && field.f(a.lerp(b, t).to_array()).abs() > self.accuracy {
            self.whole = true;
            t = illinois(|t| field.f(a.lerp(b, t).to_array()), f0, f1, self.accuracy);
        }
        let p = a.lerp(b, t);
        (t, DVec3::from_array(field.normal(program, p.to_array())))
    }
}

/// What meshing a tree did: how much of the grid the interval bounds let it skip.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshStats {
    /// Cells of the grid.
    pub cells: usize,
    /// Cells in boxes where the interval bounds proved one sign (no surface, no evaluation).
    pub skipped: usize,
    /// Samples evaluated.
    pub evaluated: usize,
}

impl Tree<3> {
    /// The closed, outward-oriented triangle mesh of the solid's boundary at `resolution` cells
    /// along the longest side of its bounds (or of `region`, a box `[lo, hi]` to mesh within, cut
    /// by its faces): vertices on `f = 0` to within `accuracy` (in `f`), normals `−∇f`. An empty
    /// solid gives an empty mesh.
    ///
    /// # Errors
    ///
    /// [`TreeMeshError`]: no bounds and no region, a bad region, resolution or accuracy; an
    /// empty mesh where the solid has an inside point ([`TreeMeshError::Lost`]).
    pub fn polygonize(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Mesh, TreeMeshError> {
        self.polygonize_with_stats(resolution, accuracy, region)
            .map(|(mesh, _)| mesh)
    }

    /// [`Tree::polygonize`], with how much of the grid it skipped.
    ///
    /// # Errors
    ///
    /// As [`Tree::polygonize`].
    pub fn polygonize_with_stats(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<(Mesh, MeshStats), TreeMeshError> {
        let ((mesh, _), stats) =
            self.mesh_in_steps(resolution, accuracy, region, Share::WHOLE, None)?;
        Ok((mesh, stats))
    }

    /// [`Tree::polygonize_with_stats`], calling `progress(done, total)` as the grid's cells are
    /// decided (in fiftieths or coarser, and at the end with `done == total`): the share of the work that
    /// grows with the grid.
    ///
    /// # Errors
    ///
    /// As [`Tree::polygonize`].
    pub fn polygonize_in_steps(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<(Mesh, MeshStats), TreeMeshError> {
        let ((mesh, _), stats) = self.mesh_in_steps(
            resolution,
            accuracy,
            region,
            Share::WHOLE,
            Some(&mut progress),
        )?;
        Ok((mesh, stats))
    }

    /// [`Tree::polygonize`] made in parts: the piece of `share` ([`Piece::weld`] of all the
    /// shares' pieces, in order, is that mesh, and their triangles one after another are its
    /// triangles, a vertex two shares have found by each to within `accuracy`).
    ///
    /// # Errors
    ///
    /// As [`Tree::polygonize`].
    pub fn polygonize_share(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
        share: Share,
    ) -> Result<Piece, TreeMeshError> {
        let ((mesh, keys), _) = self.mesh_in_steps(resolution, accuracy, region, share, None)?;
        Ok(Piece { mesh, keys })
    }

    /// The blocks of `share` of the grid, meshed in pieces of consecutive blocks welded in order
    /// ([`make_and_weld`]: on every thread of the pool with the `parallel` feature); `progress`
    /// as [`Tree::polygonize_in_steps`] says (over this share's cells), told as the pieces are
    /// welded. Not generic in `progress`, so that it is compiled once, here, whatever the
    /// caller's.
    fn mesh_in_steps(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
        share: Share,
        progress: Option<&mut dyn FnMut(usize, usize)>,
    ) -> Result<(Keyed, MeshStats), TreeMeshError> {
        if region.is_none() && self.clusters.len() > 1 {
            return self.mesh_parts(resolution, accuracy, share, progress);
        }
        self.mesh_area(None, resolution, accuracy, region, share, progress)
    }

    /// [`Tree::mesh_in_steps`] within `area` (the tree's bounds where `None`).
    pub(super) fn mesh_area(
        &self,
        area: Option<([f64; 3], [f64; 3])>,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
        share: Share,
        mut progress: Option<&mut dyn FnMut(usize, usize)>,
    ) -> Result<(Keyed, MeshStats), TreeMeshError> {
        let reporting = progress.is_some();
        let mut progress = |done, total| {
            if let Some(report) = progress.as_mut() {
                report(done, total);
            }
        };
        let Some(plan) = self.blocks_plan(area, resolution, accuracy, region)? else {
            progress(1, 1);
            return Ok(((Mesh::default(), Vec::new()), MeshStats::default()));
        };
        // The samples and, about as many again, the roots' evaluations, each with the same work
        // wherever and whenever it is taken: the blocks beside a face see one sign there.
        self.fix_query_work(2 * plan.stats.evaluated);
        let (stats, total) = (plan.stats, plan.stats.cells);
        if stats.skipped < total {
            progress(stats.skipped, total);
        }
        let blocks = share.of_blocks(&plan.blocks);
        // Each piece of consecutive blocks on its own field and roots, welded in order: the mesh
        // one walk over all the blocks gives (on one thread or many). Fiftieths at least where
        // someone is told of the progress; else one piece on one thread (a piece costs its weld).
        let marcher = Marcher::new();
        #[cfg(feature = "parallel")]
        let pieces = crate::mesh::polygonize::pieces_taken_in_turn();
        #[cfg(not(feature = "parallel"))]
        let pieces = 1;
        let pieces = if reporting { pieces.max(50) } else { pieces };
        let parts: Vec<&[Block]> = blocks
            .chunks(blocks.len().div_ceil(pieces).max(1))
            .collect();
        let mut done = stats.skipped;
        let mesh = make_and_weld(
            parts.len(),
            |k| plan.mesh(parts[k], &marcher),
            |k| {
                done += parts[k]
                    .iter()
                    .map(|b| b.size.iter().product::<usize>())
                    .sum::<usize>();
                if done < total {
                    progress(done, total);
                }
            },
        );
        progress(total, total);
        if share.count() == 1 && mesh.0.triangles.is_empty() {
            self.lost(resolution, region.or(area))?;
        }
        Ok((mesh, stats))
    }

    /// An error where the solid has an inside point (within `region`, where given): its boundary
    /// came out empty, so the grid lost it.
    fn lost(
        &self,
        resolution: usize,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<(), TreeMeshError> {
        match self.inside_point(region) {
            Some((p, f)) => Err(TreeMeshError::Lost {
                at: p.to_array(),
                f,
                resolution,
            }),
            None => Ok(()),
        }
    }

    /// The grid of the mesh at `resolution` and its blocks: boxes of cells bounded by intervals,
    /// one sign (no surface) skipped, else split in eight down to boxes sampled whole, each with
    /// its pruned program. `None` for an empty solid.
    pub(super) fn blocks_plan(
        &self,
        area: Option<([f64; 3], [f64; 3])>,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Option<Plan<'_>>, TreeMeshError> {
        Ok(self
            .mesh_grid_in(area, resolution, accuracy, region)?
            .map(|(grid, clip)| self.walk(grid, clip, accuracy, None)))
    }

    /// The grid of the mesh at `resolution` (about half a cell past the region on every side)
    /// and the box to cut by where one was given; `None` for an empty solid.
    pub(super) fn mesh_grid(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Option<(SampleGrid, Option<Shape<3>>)>, TreeMeshError> {
        self.mesh_grid_in(None, resolution, accuracy, region)
    }

    /// [`Tree::mesh_grid`] over `area` (a part of the bounds holding the solid there) where
    /// given.
    fn mesh_grid_in(
        &self,
        area: Option<([f64; 3], [f64; 3])>,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Option<(SampleGrid, Option<Shape<3>>)>, TreeMeshError> {
        let Some(Region { lo, hi, clip }) =
            self::region(area.or(self.bounds()), region, resolution, accuracy)?
        else {
            return Ok(None);
        };
        let (lo, hi) = (DVec3::from_array(lo), DVec3::from_array(hi));
        let size = hi - lo;
        let cell = size.max_element() / resolution as f64;
        let cells = (size / cell)
            .ceil()
            .max(DVec3::ONE)
            .min(DVec3::splat(resolution as f64));
        let step = size / cells;
        let grid = SampleGrid {
            origin: lo - step * (0.5 - GRID_SHIFT),
            step,
            dims: cells.to_array().map(|c| c as usize + 2),
        };
        Ok(Some((grid, clip)))
    }
}

/// The grid of a tree's mesh, its blocks and their pruned programs ([`Tree::blocks_plan`]).
pub(super) struct Plan<'a> {
    pub(super) grid: SampleGrid,
    pub(super) field: Field<'a, 3>,
    pub(super) accuracy: f64,
    /// Below this, a pruned program's value on a block's face gives way to the whole tree's.
    pub(super) tau: f64,
    /// The pruned programs, by [`Block::tag`] (`u32::MAX`: the whole tree).
    pub(super) programs: Vec<Vec<Step>>,
    pub(super) blocks: Vec<Block>,
    pub(super) stats: MeshStats,
}

/// What meshing a run of blocks read besides their own programs.
#[derive(Clone, Copy, Debug)]
pub(super) struct Reads {
    /// The least `|f|` a pruned program gave on a block's face (∞ where there is none).
    pub(super) near: f64,
    /// Whether the whole tree was read in a block with a pruned program: a face sample within
    /// `tau` of zero, an ambiguous face's corners, a root checked past the accuracy.
    pub(super) whole: bool,
}

impl Plan<'_> {
    /// The pruned program of `block` (`None`: the whole tree's).
    pub(super) fn program(&self, block: &Block) -> Option<&[Step]> {
        (block.tag != u32::MAX)
            .then(|| self.programs.get(block.tag as usize).map(Vec::as_slice))
            .flatten()
    }

    /// The mesh of consecutive blocks `part`, to be welded in order with the others'.
    pub(super) fn mesh(&self, part: &[Block], marcher: &Marcher) -> Keyed {
        self.mesh_marked(part, marcher).0
    }

    /// The pieces of consecutive blocks `part`, one a block, each with what it read: welded in
    /// order, the mesh of `part`.
    pub(super) fn mesh_each(&self, part: &[Block], marcher: &Marcher) -> Vec<(Keyed, Reads)> {
        let (run, reads, marks) = self.mesh_marked(part, marcher);
        let ends: Vec<(usize, usize)> = marks.iter().map(|&(v, t, _)| (v, t)).collect();
        split_run(&run, &ends)
            .into_iter()
            .zip(reads.into_iter().zip(marks))
            .map(|(piece, (reads, (_, _, whole)))| {
                (
                    piece,
                    Reads {
                        whole: reads.whole || whole,
                        ..reads
                    },
                )
            })
            .collect()
    }

    /// The mesh of consecutive blocks `part`, what each block read, and each block's marks (the
    /// vertices and triangles made up to its end, whether its roots read the whole tree).
    fn mesh_marked(
        &self,
        part: &[Block],
        marcher: &Marcher,
    ) -> (Keyed, Vec<Reads>, Vec<(usize, usize, bool)>) {
        let mut sampler = self.field.clone();
        let (grid, tau) = (self.grid, self.tau);
        let mut reads = Vec::with_capacity(part.len());
        let sample = |block: &Block, out: &mut Vec<f64>| {
            let program = self.program(block);
            let mut read = Reads {
                near: f64::INFINITY,
                whole: false,
            };
            for c in block.lo[2]..=block.lo[2] + block.size[2] {
                for b in block.lo[1]..=block.lo[1] + block.size[1] {
                    for a in block.lo[0]..=block.lo[0] + block.size[0] {
                        let p = grid.point(a, b, c).to_array();
                        let mut v = sampler.f_by(program, p);
                        if program.is_some() && block.on_face([a, b, c]) {
                            read.near = read.near.min(v.abs());
                            if v.abs() < tau {
                                read.whole = true;
                                v = sampler.f(p);
                            }
                        }
                        out.push(v);
                    }
                }
            }
            reads.push(read);
        };
        let mut roots = Roots {
            field: self.field.clone(),
            grid,
            accuracy: self.accuracy,
            programs: &self.programs,
            program: None,
            whole: false,
            marks: Vec::with_capacity(part.len()),
        };
        let keyed = polygonize_blocks(&grid, part, sample, &mut roots, marcher);
        (keyed, reads, roots.marks)
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::contour::Polyline;
    use crate::model::{ModelFile, Rotation, SolidSpec as S};
    use crate::testutil::{Rng, random_point as point, random_tree};
    use crate::tree::ModelTree;
    use crate::tree::plane_axes;
    use alloc::boxed::Box;
    use alloc::vec;
    use glam::DVec2;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn space(spec: S) -> Tree<3> {
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => panic!("2D"),
        }
    }

    /// Faces of boxes on nice numbers (where a grid at nice numbers would sample `f = 0` exactly
    /// and make triangles of no area): every triangle has an area, and the STL written reads back
    /// as a closed mesh.
    #[test]
    fn faces_on_round_numbers_make_no_flat_triangles() {
        for resolution in [4, 8, 16, 24] {
            let tree = space(S::Union {
                of: vec![
                    S::Box {
                        min: [0.0; 3],
                        max: [1.0; 3],
                    },
                    S::Box {
                        min: [0.25; 3],
                        max: [2.0; 3],
                    },
                ],
            });
            let mesh = tree.polygonize(resolution, 1e-9, None).unwrap();
            for t in 0..mesh.triangle_count() {
                let [a, b, c] = mesh.corners(t);
                assert!(
                    (b - a).cross(c - a).length() > 0.0,
                    "triangle {t} at {resolution}"
                );
            }
            let back = crate::mesh::Format::Stl
                .read(&crate::mesh::Format::Stl.write(&mesh))
                .unwrap();
            back.check_closed_manifold().unwrap();
        }
    }

    #[test]
    fn bounds_hold_every_inside_point_of_random_trees() {
        let mut rng = Rng::new(11);
        for _ in 0..60 {
            let tree = space(random_tree(&mut rng, 3));
            let (lo, hi) = tree.bounds().expect("a bounded tree");
            for _ in 0..2000 {
                let p = point(&mut rng, 4.0);
                if tree.f(glam::DVec3::from_array(p)) > 0.0 {
                    assert!(
                        (0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i]),
                        "{p:?} is inside but outside the bounds {lo:?} .. {hi:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn intervals_hold_every_value_in_their_box() {
        let mut rng = Rng::new(14);
        for _ in 0..60 {
            let tree = space(random_tree(&mut rng, 3));
            for _ in 0..20 {
                let c = point(&mut rng, 1.5);
                let h = [
                    rng.range(0.01, 0.8),
                    rng.range(0.01, 0.8),
                    rng.range(0.01, 0.8),
                ];
                let lo: [f64; 3] = core::array::from_fn(|i| c[i] - h[i]);
                let hi: [f64; 3] = core::array::from_fn(|i| c[i] + h[i]);
                let range = tree.interval(lo, hi);
                for _ in 0..50 {
                    let p: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                    let f = tree.f(glam::DVec3::from_array(p));
                    let slack = 1e-9 * f.abs().max(1.0);
                    assert!(
                        range.lo - slack <= f && f <= range.hi + slack,
                        "{p:?}: f = {f} outside {range:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn pruned_programs_keep_the_signs_and_the_zero_set() {
        let mut rng = Rng::new(16);
        let mut pruned = 0;
        for _ in 0..80 {
            let tree = space(S::Union {
                of: vec![
                    random_tree(&mut rng, 2),
                    random_tree(&mut rng, 2),
                    random_tree(&mut rng, 2),
                ],
            });
            for _ in 0..10 {
                let c = point(&mut rng, 1.5);
                let h = rng.range(0.05, 0.5);
                let (lo, hi) = (c.map(|v| v - h), c.map(|v| v + h));
                let Some(program) = tree.pruned(lo, hi) else {
                    continue;
                };
                pruned += 1;
                assert!(program.len() < tree.steps.len());
                let mut stack = Vec::new();
                for _ in 0..40 {
                    let p: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                    let full = tree.evaluate_with(p, &mut stack).f;
                    let part = tree.evaluate_program(&program, p, &mut stack).f;
                    if full.abs() > 1e-12 {
                        assert_eq!(full > 0.0, part > 0.0, "{p:?}: {full} and {part}");
                    }
                }
            }
        }
        assert!(pruned > 50, "{pruned} boxes pruned");
    }

    #[test]
    fn skipping_cells_changes_nothing_but_the_work() {
        let mut rng = Rng::new(15);
        let mut skipped = 0;
        for _ in 0..8 {
            let tree = space(random_tree(&mut rng, 3));
            let mut steps = Vec::new();
            let (mesh, stats) = tree
                .polygonize_in_steps(40, 1e-10, None, |done, total| steps.push((done, total)))
                .unwrap();
            mesh.check_closed_manifold().unwrap();
            assert!(stats.skipped <= stats.cells);
            // Progress in order, at most about fifty steps, ending with every cell decided.
            assert_eq!(steps.last(), Some(&(stats.cells, stats.cells)));
            assert!(
                steps.len() <= 52 && steps.windows(2).all(|w| w[0].0 < w[1].0),
                "{steps:?}"
            );
            assert!(steps.iter().all(|&(_, total)| total == stats.cells));
            skipped += stats.skipped;
            // Every vertex is on the surface (a wrong skip would leave a hole or a stray piece,
            // which the closed-manifold check and this catch).
            for p in mesh.positions.iter().step_by(31) {
                let (f, g) = tree.f_with_gradient(*p);
                assert!(f.abs() <= 1e-9 * g.length().max(1.0), "{p}: {f}");
            }
        }
        assert!(skipped > 0, "the bounds skip some cells");
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn threads_mesh_random_trees_as_one_thread_does() {
        let mut rng = Rng::new(16);
        let pool = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let (one, three) = (pool(1), pool(3));
        let mut triangles = 0;
        for _ in 0..8 {
            let tree = space(random_tree(&mut rng, 3));
            let a = one.install(|| tree.polygonize(36, 1e-10, None).unwrap());
            let b = three.install(|| tree.polygonize(36, 1e-10, None).unwrap());
            assert_eq!(a, b);
            // Made in rounds to report its progress, the same mesh.
            let mut reports = 0;
            let (c, _) = three.install(|| {
                tree.polygonize_in_steps(36, 1e-10, None, |_, _| reports += 1)
                    .unwrap()
            });
            assert_eq!(a, c);
            assert!(reports >= 1);
            triangles += a.triangle_count();
        }
        assert!(triangles > 1000);
    }

    /// The boxes of the second level walked on a pool of threads give the one walk's blocks, in
    /// its order, with the same programs and counts; and the mesh is the one thread's.
    #[cfg(feature = "parallel")]
    #[test]
    fn the_walk_on_many_threads_is_the_walk_on_one() {
        let mut rng = Rng::new(23);
        let mut walked_blocks = 0;
        for _ in 0..6 {
            let tree = space(random_tree(&mut rng, 3));
            let Some((grid, clip)) = tree.mesh_grid(40, 1e-10, None).unwrap() else {
                continue;
            };
            let [nx, ny, nz] = grid.dims;
            let root = ([0; 3], [nx - 1, ny - 1, nz - 1]);
            let mut one = MeshStats::default();
            let (programs, blocks) = tree.walk_from(&grid, clip.as_ref(), root, None, &mut one);
            walked_blocks += blocks.len();
            let one_mesh = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap()
                .install(|| tree.polygonize(40, 1e-10, None).unwrap());
            for threads in [2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut many = MeshStats::default();
                let walked =
                    pool.install(|| tree.walk_on_pool(&grid, clip.as_ref(), root, &mut many));
                assert_eq!(walked.1, blocks, "{threads} threads: blocks");
                assert_eq!(walked.0, programs, "{threads} threads: programs");
                assert_eq!(many, one, "{threads} threads: counts");
                let mesh = pool.install(|| tree.polygonize(40, 1e-10, None).unwrap());
                assert_eq!(mesh, one_mesh, "{threads} threads: mesh");
            }
        }
        assert!(walked_blocks > 100, "{walked_blocks} blocks");
    }

    /// A tree's mesh made in shares: welded in order, the pieces are the whole mesh; one after
    /// another, their triangles are its triangles, on vertices within 1e-9.
    #[test]
    fn shares_of_random_trees_weld_into_the_whole_mesh() {
        let mut rng = Rng::new(17);
        let mut triangles = 0;
        for _ in 0..6 {
            let tree = space(random_tree(&mut rng, 3));
            let whole = tree.polygonize(30, 1e-10, None).unwrap();
            for count in [2, 5] {
                let pieces: Vec<Piece> = (0..count)
                    .map(|k| {
                        let share = Share::new(k, count).unwrap();
                        tree.polygonize_share(30, 1e-10, None, share).unwrap()
                    })
                    .collect();
                let listed: Vec<_> = pieces
                    .iter()
                    .flat_map(|p| {
                        p.mesh
                            .triangles
                            .iter()
                            .map(|t| t.map(|v| p.mesh.positions[v as usize]))
                    })
                    .collect();
                let want: Vec<_> = whole
                    .triangles
                    .iter()
                    .map(|t| t.map(|v| whole.positions[v as usize]))
                    .collect();
                assert_eq!(listed.len(), want.len(), "{count} shares: triangles");
                let apart = listed
                    .iter()
                    .zip(&want)
                    .flat_map(|(a, b)| (0..3).map(move |k| a[k].distance(b[k])))
                    .fold(0.0f64, f64::max);
                // A vertex two shares have is found by each with its block's pruned program: the
                // same root to within the accuracy (the welded mesh keeps the first, exactly).
                assert!(apart <= 1e-9, "{count} shares: vertices {apart:e} apart");
                assert_eq!(Piece::weld(pieces), whole, "{count} shares: welded");
            }
            triangles += whole.triangle_count();
        }
        assert!(triangles > 1000);
    }

    #[test]
    fn gradients_match_finite_differences() {
        let mut rng = Rng::new(12);
        for _ in 0..40 {
            let tree = space(random_tree(&mut rng, 3));
            for _ in 0..20 {
                let p = glam::DVec3::from_array(point(&mut rng, 1.5));
                let (f, g) = tree.f_with_gradient(p);
                assert_eq!(f, tree.f(p));
                let h = 1e-6;
                let fd = glam::DVec3::new(
                    tree.f(p + glam::DVec3::X * h) - tree.f(p - glam::DVec3::X * h),
                    tree.f(p + glam::DVec3::Y * h) - tree.f(p - glam::DVec3::Y * h),
                    tree.f(p + glam::DVec3::Z * h) - tree.f(p - glam::DVec3::Z * h),
                ) / (2.0 * h);
                assert!(
                    (g - fd).length() <= 1e-4 * fd.length().max(1.0),
                    "{p}: {g} vs {fd}"
                );
            }
        }
    }

    #[test]
    fn strong_blends_are_bounded_by_their_formula_and_meshed_whole() {
        // Two unit spheres blended with a0 of 1e4 and 1e5: the mesh stopped at x = 4.26 (a box of
        // ±130 from the displacement's largest value, 44 triangles at 64), or had none.
        let mut rng = Rng::new(17);
        for (a0, reach) in [(1e4, 4.5), (1e5, 6.5)] {
            let tree = space(S::BlendUnion {
                of: alloc::vec![
                    S::Sphere {
                        center: [-1.0, 0.0, 0.0],
                        radius: 1.0
                    },
                    S::Sphere {
                        center: [1.0, 0.0, 0.0],
                        radius: 1.0
                    },
                ],
                a0,
                a1: 1.0,
                a2: 1.0,
            });
            assert!(tree.f(glam::DVec3::new(reach, 0.0, 0.0)) > 0.0);
            let (lo, hi) = tree.bounds().unwrap();
            // Within twice the solid's reach, and holding every inside point of a wider box.
            assert!(
                hi[0] < 2.0 * reach && lo[0] > -2.0 * reach,
                "{lo:?} .. {hi:?}"
            );
            let wide = 3.0 * reach;
            let n = 100_000;
            let mut inside = 0;
            for _ in 0..n {
                let p = point(&mut rng, wide);
                if tree.f(glam::DVec3::from_array(p)) > 0.0 {
                    inside += 1;
                    assert!(
                        (0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i]),
                        "{p:?} is inside but outside the bounds {lo:?} .. {hi:?}"
                    );
                }
            }
            let mc = (2.0 * wide).powi(3) * inside as f64 / n as f64;
            let mesh = tree.polygonize(64, 1e-10, None).unwrap();
            mesh.check_closed_manifold().unwrap();
            let v = mesh.volume();
            assert!(
                (v - mc).abs() <= 0.05 * mc,
                "a0 = {a0}: mesh {v} vs Monte Carlo {mc}"
            );
        }
    }

    #[test]
    fn meshes_of_random_trees_are_closed_and_hold_their_volume() {
        let mut rng = Rng::new(13);
        let mut checked = 0;
        while checked < 6 {
            let tree = space(random_tree(&mut rng, 2));
            let (lo, hi) = tree.bounds().unwrap();
            if (0..3).any(|i| lo[i] > hi[i]) {
                continue;
            }
            // Monte Carlo volume in the bounds.
            let n = 60_000;
            let inside = (0..n)
                .filter(|_| {
                    let p = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                    tree.f(glam::DVec3::from_array(p)) > 0.0
                })
                .count();
            let box_volume: f64 = (0..3).map(|i| hi[i] - lo[i]).product();
            let mc = box_volume * inside as f64 / n as f64;
            if inside < n / 20 {
                continue; // too thin a solid for a fair comparison
            }
            let mesh = tree.polygonize(64, 1e-10, None).unwrap();
            mesh.check_closed_manifold().unwrap();
            let v = mesh.volume();
            // The Monte Carlo estimate's own error is under 1.5 % at these counts (3 sigma).
            assert!((v - mc).abs() <= 0.03 * mc, "mesh {v} vs Monte Carlo {mc}");
            for (k, p) in mesh.positions.iter().enumerate().step_by(97) {
                let (f, g) = tree.f_with_gradient(*p);
                assert!(f.abs() <= 1e-9 * g.length().max(1.0), "vertex {k}: f = {f}");
            }
            checked += 1;
        }
    }

    /// Piecewise leaves, regular or moved, alone and in a tree: their intervals and bounds hold
    /// their values, and their meshes are closed, hold their volume and lie on `f = 0`.
    #[test]
    fn piecewise_leaves_bound_and_mesh_like_any_leaf() {
        let mut rng = Rng::new(19);
        for round in 0..6 {
            let moved = round % 2 == 1;
            let leaf = crate::testutil::random_piecewise3(&mut rng, moved);
            let spec = if round < 4 {
                leaf
            } else {
                S::Difference {
                    of: vec![
                        leaf,
                        S::Sphere {
                            center: point(&mut rng, 0.3),
                            radius: 0.3,
                        },
                    ],
                }
            };
            let tree = space(spec);
            for _ in 0..20 {
                let c = point(&mut rng, 1.0);
                let h: [f64; 3] = core::array::from_fn(|_| rng.range(0.01, 0.6));
                let lo: [f64; 3] = core::array::from_fn(|i| c[i] - h[i]);
                let hi: [f64; 3] = core::array::from_fn(|i| c[i] + h[i]);
                let range = tree.interval(lo, hi);
                for _ in 0..30 {
                    let p: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                    let f = tree.f(glam::DVec3::from_array(p));
                    let slack = 1e-9 * f.abs().max(1.0);
                    assert!(
                        range.lo - slack <= f && f <= range.hi + slack,
                        "{p:?}: f = {f} outside {range:?}"
                    );
                }
            }
            let (lo, hi) = tree.bounds().expect("bounded");
            let n = 20_000;
            let mut inside = 0;
            for _ in 0..n {
                let p = point(&mut rng, 1.5);
                if tree.f(glam::DVec3::from_array(p)) > 0.0 {
                    assert!((0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i]), "{p:?}");
                }
                let q: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                inside += usize::from(tree.f(glam::DVec3::from_array(q)) > 0.0);
            }
            let box_volume: f64 = (0..3).map(|i| hi[i] - lo[i]).product();
            let mc = box_volume * inside as f64 / n as f64;
            let mesh = tree
                .polygonize(if moved { 24 } else { 48 }, 1e-10, None)
                .unwrap();
            mesh.check_closed_manifold().unwrap();
            let v = mesh.volume();
            assert!((v - mc).abs() <= 0.06 * mc, "mesh {v} vs Monte Carlo {mc}");
            for (k, p) in mesh.positions.iter().enumerate().step_by(41) {
                let (f, g) = tree.f_with_gradient(*p);
                assert!(f.abs() <= 1e-9 * g.length().max(1.0), "vertex {k}: f = {f}");
            }
        }
    }

    /// Sections of random trees: every vertex on `f = 0` of the plane, the loops' area that of
    /// the solid's section sampled on the plane; a ball's section is the circle it must be; a
    /// plane past the model is refused with its extent.
    #[test]
    fn sections_lie_on_the_zero_set_and_hold_the_area_of_the_cut() {
        use alloc::format;
        use alloc::string::ToString;
        let mut rng = Rng::new(29);
        let mut checked = 0;
        while checked < 8 {
            let tree = space(random_tree(&mut rng, 2));
            let Some((lo, hi)) = tree.bounds() else {
                continue;
            };
            if (0..3).any(|i| lo[i] > hi[i]) {
                continue;
            }
            let axis = rng.int(0, 2);
            let at = rng.range(lo[axis], hi[axis]);
            let lines = tree.section(axis, at, 96, 1e-10, None).unwrap();
            let [a, b] = plane_axes(axis);
            let place = |q: DVec2| {
                let mut p = [at; 3];
                p[a] = q.x;
                p[b] = q.y;
                glam::DVec3::from_array(p)
            };
            for line in &lines {
                for &q in &line.points {
                    let (f, g) = tree.f_with_gradient(place(q));
                    assert!(f.abs() <= 1e-9 * g.length().max(1.0), "f = {f} at {q}");
                }
            }
            let area: f64 = lines
                .iter()
                .filter(|l| l.closed)
                .map(Polyline::signed_area)
                .sum();
            let n = 40_000;
            let inside = (0..n)
                .filter(|_| {
                    let q = DVec2::new(rng.range(lo[a], hi[a]), rng.range(lo[b], hi[b]));
                    tree.f(place(q)) > 0.0
                })
                .count();
            let rect = (hi[a] - lo[a]) * (hi[b] - lo[b]);
            let mc = rect * inside as f64 / n as f64;
            if inside < n / 20 {
                continue; // too thin a cut for a fair comparison
            }
            assert!(
                (area - mc).abs() <= 0.04 * mc,
                "section area {area} vs {mc}"
            );
            checked += 1;
        }
        // A ball of radius 1 cut at z = 0.6: a circle of radius 0.8.
        let ball = space(S::Sphere {
            center: [0.0; 3],
            radius: 1.0,
        });
        let lines = ball.section(2, 0.6, 128, 1e-12, None).unwrap();
        assert_eq!(lines.len(), 1);
        for q in &lines[0].points {
            assert!((q.length() - 0.8).abs() < 1e-9, "{q}");
        }
        let (lo, hi) = ball.bounds().unwrap();
        assert_eq!(
            ball.section(2, 3.0, 64, 1e-9, None)
                .unwrap_err()
                .to_string(),
            format!(
                "the plane z = 3 misses the model: it fills z from {} to {}",
                lo[2], hi[2]
            )
        );
    }

    #[test]
    fn a_box_meshes_unbounded_trees_and_cuts_them_closed() {
        let half = space(S::Halfspace {
            normal: [0.0, 0.0, 1.0],
            offset: 0.0,
        });
        assert_eq!(half.bounds(), None);
        assert_eq!(
            half.polygonize(8, 1e-9, None),
            Err(TreeMeshError::Unbounded)
        );
        let mesh = half
            .polygonize(16, 1e-9, Some(([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])))
            .unwrap();
        mesh.check_closed_manifold().unwrap();
        // The lower half of the box: volume 4.
        assert!((mesh.volume() - 4.0).abs() < 0.05, "{}", mesh.volume());
        assert!(half.polygonize(0, 1e-9, None).is_err());
        assert_eq!(
            half.polygonize(8, 1e-9, Some(([0.0; 3], [0.0; 3]))),
            Err(TreeMeshError::Region)
        );
    }

    #[test]
    fn contours_of_2d_trees_lie_on_the_zero_set() {
        let tree = match ModelFile::from_spec(S::BlendUnion {
            of: vec![
                S::Circle {
                    center: [0.0, 0.0],
                    radius: 1.0,
                },
                S::Transform {
                    solid: Box::new(S::Rectangle {
                        min: [-0.3, -1.5],
                        max: [0.3, 1.5],
                    }),
                    translate: Some(vec![1.0, 0.0]),
                    rotate: Some(Rotation::Angle(30.0)),
                    scale: None,
                },
            ],
            a0: 0.3,
            a1: 1.0,
            a2: 1.0,
        })
        .to_tree()
        .unwrap()
        {
            ModelTree::Plane(t) => t,
            ModelTree::Space(_) => panic!("3D"),
        };
        let lines = tree.contour(128, 1e-12, None).unwrap();
        assert_eq!(lines.len(), 1, "one outline");
        assert!(lines[0].closed);
        assert!(
            lines[0].signed_area() > 3.0,
            "counter-clockwise around the solid"
        );
        for p in &lines[0].points {
            let (f, g) = tree.f_with_gradient(*p);
            assert!(f.abs() <= 1e-9 * g.length().max(1.0), "{p}: {f}");
        }
    }
}
