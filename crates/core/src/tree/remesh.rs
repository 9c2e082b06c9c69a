//! A tree's mesh again after an edit, remaking only the blocks the edit can change
//! ([`MeshCache`]).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use super::mesh::{Plan, Reads};
use super::walk::RangeMemo;
use super::{Leaf, Shape, Step, Tree, TreeMeshError};
use crate::mesh::polygonize::{Block, Keyed, Marcher, weld_kept};
use crate::mesh::{Piece, SampleGrid, Share};

/// A tree's mesh kept block by block, for [`Tree::polygonize_share_cached`]: what an edit leaves
/// unchanged is not made again. One cache follows one share of one mesh. The grid must stay: an
/// edit that changes the model's bounds (the grid spans them), another resolution, region or
/// share starts the cache again.
///
/// The mesher samples a block of the grid by the block's pruned program: the operands that can
/// decide a sign in it. Its samples, the roots on its edges and their normals are that program's
/// values on those leaves alone, save where the whole tree is read (a face sample within a hair of
/// zero, the corners of an ambiguous face, a root the program leaves past the accuracy). So a block
/// whose program is the same after an edit, every leaf it reads unchanged over the block, and that
/// read nothing of the whole tree, meshes as it did: its piece is kept. (Each root the program
/// finds is checked on the whole tree, and one past the accuracy is searched again on it; an edit
/// of an operand the program left out changes that check's value by next to nothing, and were it to
/// tip a kept root past the accuracy, the fresh root and the kept one would both lie on `f = 0`
/// to within the accuracy, on the same edge.) A regular piecewise solid
/// reads only the cells a point lies in, so an edit of one of its cells leaves it unchanged over
/// the blocks outside that cell. The leaves' interval ranges over the
/// boxes of the grid's octree are kept too, and only an edited leaf's are bounded again. An edit
/// of one solid of a model remakes the blocks near that solid; the rest of the surface is welded
/// from the pieces kept.
///
/// One Bézier solid alone has no such locality: its Bernstein basis does not vanish inside the
/// domain, so a control point moves `f` everywhere, and every block the surface crosses changes.
#[derive(Clone, Debug, Default)]
pub struct MeshCache {
    setting: Option<Setting>,
    /// The tree's program and leaves when the pieces were made.
    steps: Vec<Step>,
    leaves: Vec<Leaf<3>>,
    /// The pieces of the blocks, by the block's first cell and size.
    blocks: BTreeMap<([usize; 3], [usize; 3]), Kept>,
    /// The leaves' ranges over the boxes of the walk that made them.
    ranges: RangeMemo,
}

/// What a mesh's pieces depend on besides the tree.
#[derive(Clone, Debug, PartialEq)]
struct Setting {
    grid: SampleGrid,
    accuracy: f64,
    clip: Option<Shape<3>>,
    share: Share,
}

/// A block's piece of the mesh, and what it was made of.
#[derive(Clone, Debug)]
struct Kept {
    program: Option<Vec<Step>>,
    piece: Keyed,
    reads: Reads,
}

/// How much of a mesh [`Tree::polygonize_share_cached`] made again.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Remeshed {
    /// The blocks of the share (boxes of cells the bounds could not skip).
    pub blocks: usize,
    /// Those whose piece was kept from the cache.
    pub kept: usize,
}

/// How a leaf of the tree being meshed differs from the cache's leaf of the same index.
#[derive(Clone, Debug)]
pub(super) enum Change {
    /// The same leaf.
    Same,
    /// Another leaf, or one changed everywhere.
    Changed,
    /// A regular piecewise leaf with some cells changed, by cell (the last axis fastest): the same
    /// leaf elsewhere, for `f` and the interval bounds read only the cells a point or box is in.
    Cells {
        cells: [usize; 3],
        min: [f64; 3],
        max: [f64; 3],
        changed: Vec<bool>,
    },
}

impl Change {
    /// How `new` differs from `old`.
    fn of(old: Option<&Leaf<3>>, new: &Leaf<3>) -> Self {
        let Some(old) = old else {
            return Self::Changed;
        };
        if old == new {
            return Self::Same;
        }
        match (&old.shape, &new.shape) {
            (Shape::Piecewise(a, Some(ra)), Shape::Piecewise(b, Some(rb)))
                if old.map == new.map
                    && a.cells() == b.cells()
                    && a.domain() == b.domain()
                    && (ra.cells, ra.min, ra.max) == (rb.cells, rb.min, rb.max)
                    && ra.xi.len() == rb.xi.len() =>
            {
                let cells = a.cells();
                let changed = (0..ra.xi.len())
                    .map(|k| {
                        let cell = crate::tensor::multi_index(cells, k);
                        ra.xi[k] != rb.xi[k] || a.part(cell) != b.part(cell)
                    })
                    .collect();
                Self::Cells {
                    cells,
                    min: ra.min,
                    max: ra.max,
                    changed,
                }
            }
            _ => Self::Changed,
        }
    }

    /// Whether the leaf (`leaf`, the tree's) is the cache's over the box `[lo, hi]` of space:
    /// for a piecewise leaf, no cell it reads there changed (the cells the box is in).
    pub(super) fn same_over(&self, leaf: &Leaf<3>, lo: [f64; 3], hi: [f64; 3]) -> bool {
        match self {
            Self::Same => true,
            Self::Changed => false,
            Self::Cells {
                cells,
                min,
                max,
                changed,
            } => {
                let (llo, lhi) = super::interval::mapped_box(leaf, lo, hi);
                // As the solid picks its cell (points past the box fall to the first or last).
                let cell = |a: usize, x: f64| {
                    let n = cells[a];
                    let s = (x - min[a]) / (max[a] - min[a]) * n as f64;
                    if s >= n as f64 {
                        n - 1
                    } else if s >= 0.0 {
                        s as usize
                    } else {
                        0
                    }
                };
                // A hair past the box, for a point that rounds onto a face between two cells
                // one way here and the other way where it is evaluated (a few units in the last
                // place of the coordinates, far from the origin too).
                let hair = |a: usize| 1e-9 * (max[a] - min[a]).max(min[a].abs()).max(max[a].abs());
                let first: [usize; 3] = core::array::from_fn(|a| cell(a, llo[a] - hair(a)));
                let last: [usize; 3] = core::array::from_fn(|a| cell(a, lhi[a] + hair(a)));
                (first[0]..=last[0]).all(|i| {
                    (first[1]..=last[1]).all(|j| {
                        (first[2]..=last[2]).all(|k| {
                            !changed
                                .get((i * cells[1] + j) * cells[2] + k)
                                .copied()
                                .unwrap_or(true)
                        })
                    })
                })
            }
        }
    }
}

impl MeshCache {
    /// An empty cache.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether the piece kept for the block spanning `block` (in space), of `program` in
    /// `tree`, is the one meshing it again would make (`changes`: the leaves' changes; `tau`: the
    /// face samples' threshold).
    fn holds(
        &self,
        kept: &Kept,
        block: ([f64; 3], [f64; 3]),
        program: Option<&[Step]>,
        tree: &Tree<3>,
        changes: &[Change],
        tau: f64,
    ) -> bool {
        if kept.program.as_deref() != program {
            return false;
        }
        let same = |i: usize| match (changes.get(i), tree.leaves.get(i)) {
            (Some(change), Some(leaf)) => change.same_over(leaf, block.0, block.1),
            _ => false,
        };
        match program {
            // The whole tree: every leaf the same over the block.
            None => {
                self.steps == tree.steps
                    && self.leaves.len() == tree.leaves.len()
                    && (0..tree.leaves.len()).all(same)
            }
            // Its own leaves, and nothing of the whole tree: a face sample that now falls within
            // `tau` of zero would take the whole tree's value.
            Some(steps) => {
                !kept.reads.whole
                    && kept.reads.near >= tau
                    && steps.iter().all(|s| match *s {
                        Step::Leaf(i) => same(i),
                        _ => true,
                    })
            }
        }
    }
}

impl Tree<3> {
    /// [`Tree::polygonize_share`], keeping each block's piece of the mesh in `cache` and taking
    /// from it the pieces of the blocks an edit since the last call cannot have changed: blocks
    /// whose pruned program and the leaves it reads are the same, which read nothing of the
    /// whole tree (see [`MeshCache`]). The mesh is the one
    /// [`Tree::polygonize_share`] makes; with it, how many blocks were kept.
    ///
    /// # Errors
    ///
    /// As [`Tree::polygonize`]; the cache is then left as it was.
    pub fn polygonize_share_cached(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
        share: Share,
        cache: &mut MeshCache,
    ) -> Result<(Piece, Remeshed), TreeMeshError> {
        if region.is_none() && self.far_parts().len() > 1 {
            // Parts far apart are meshed each in its own grid, afresh: no cache.
            *cache = MeshCache::default();
            let piece = self.polygonize_share(resolution, accuracy, None, share)?;
            return Ok((piece, Remeshed::default()));
        }
        let Some((grid, clip)) = self.mesh_grid(resolution, accuracy, region)? else {
            *cache = MeshCache::default();
            return Ok((
                Piece {
                    mesh: crate::mesh::Mesh::default(),
                    keys: Vec::new(),
                },
                Remeshed::default(),
            ));
        };
        let setting = Setting {
            grid,
            accuracy,
            clip: clip.clone(),
            share,
        };
        if cache.setting.as_ref() != Some(&setting) {
            cache.blocks.clear();
            cache.ranges.kept.clear();
        }
        // The leaves' ranges over the boxes of the walk: kept for the leaves that did not change.
        let changes: Vec<Change> = self
            .leaves
            .iter()
            .enumerate()
            .map(|(i, leaf)| Change::of(cache.leaves.get(i), leaf))
            .collect();
        let mut memo = RangeMemo {
            changes: changes.clone(),
            kept: core::mem::take(&mut cache.ranges.kept),
            made: BTreeMap::new(),
        };
        let plan = self.walk(grid, clip, accuracy, Some(&mut memo));
        self.fix_query_work(2 * plan.stats.evaluated);
        let blocks = share.of_blocks(&plan.blocks);
        let key = |b: &Block| (b.lo, b.size);
        // The blocks to mesh again: not in the cache, or changed.
        let stale: Vec<usize> = (0..blocks.len())
            .filter(|&i| {
                let b = &blocks[i];
                let corner = |s: [usize; 3]| plan.grid.point(s[0], s[1], s[2]).to_array();
                let span = (corner(b.lo), corner([0, 1, 2].map(|a| b.lo[a] + b.size[a])));
                !cache.blocks.get(&key(b)).is_some_and(|kept| {
                    cache.holds(kept, span, plan.program(b), self, &changes, plan.tau)
                })
            })
            .collect();
        let made = made(&plan, blocks, &stale);
        let mut fresh = BTreeMap::new();
        for (&i, (piece, reads)) in stale.iter().zip(made) {
            let program = plan.program(&blocks[i]).map(<[Step]>::to_vec);
            fresh.insert(
                key(&blocks[i]),
                Kept {
                    program,
                    piece,
                    reads,
                },
            );
        }
        // The blocks of this mesh, each from the fresh pieces or the cache, in order.
        let mut kept = BTreeMap::new();
        for b in blocks {
            let k = key(b);
            if let Some(piece) = fresh.remove(&k).or_else(|| cache.blocks.remove(&k)) {
                kept.insert(k, piece);
            }
        }
        let (mesh, keys) = weld_kept(
            blocks
                .iter()
                .filter_map(|b| kept.get(&key(b)).map(|k| &k.piece)),
        );
        let remeshed = Remeshed {
            blocks: blocks.len(),
            kept: blocks.len() - stale.len(),
        };
        *cache = MeshCache {
            setting: Some(setting),
            steps: self.steps.clone(),
            leaves: self.leaves.clone(),
            blocks: kept,
            ranges: RangeMemo {
                kept: memo.made,
                ..RangeMemo::default()
            },
        };
        Ok((Piece { mesh, keys }, remeshed))
    }
}

/// The pieces of `blocks[i]` for each `i` in `stale` (ascending), in that order: each run of
/// consecutive stale blocks meshed in one walk and split into its blocks' pieces (runs on every
/// thread with the `parallel` feature).
fn made(plan: &Plan<'_>, blocks: &[Block], stale: &[usize]) -> Vec<(Keyed, Reads)> {
    let marcher = Marcher::new();
    // Runs of consecutive blocks, none longer than a share of the work for each thread.
    #[cfg(feature = "parallel")]
    let longest = stale
        .len()
        .div_ceil(crate::mesh::polygonize::pieces_for_pool())
        .max(1);
    #[cfg(not(feature = "parallel"))]
    let longest = stale.len().max(1);
    let mut runs: Vec<core::ops::Range<usize>> = Vec::new();
    for &i in stale {
        match runs.last_mut() {
            Some(run) if run.end == i && run.len() < longest => run.end += 1,
            _ => runs.push(i..i + 1),
        }
    }
    let one = |run: &core::ops::Range<usize>| {
        blocks
            .get(run.clone())
            .map_or_else(Vec::new, |part| plan.mesh_each(part, &marcher))
    };
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        runs.par_iter().flat_map_iter(one).collect()
    }
    #[cfg(not(feature = "parallel"))]
    runs.iter().flat_map(one).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Solid3;
    use crate::mesh::Mesh;
    use crate::model::{ModelFile, SolidSpec as S};
    use crate::tree::ModelTree;
    use alloc::vec;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// Four solids in a row, apart: a cubic volume (one of its control values raised by `bump`),
    /// a sphere, another volume and a box (moved by `moved` along y, inside the row's bounds).
    fn row(bump: f64, moved: f64) -> Tree<3> {
        let at = |k: usize| DVec3::new(k as f64 * 1.6, 0.0, 0.0);
        let volume = |k: usize, bump: f64| {
            let lo = at(k) - DVec3::splat(0.6);
            let v = Solid3::regular([3, 3, 3], lo, lo + DVec3::splat(1.2), |[i, j, l]| {
                let d = |a: usize| (a as f64 - 1.5).abs();
                let raised = if [i, j, l] == [1, 2, 1] { bump } else { 0.0 };
                0.6 - 0.18 * (d(i) + d(j) + d(l)) + raised
            })
            .unwrap();
            ModelFile::from_solid3(&v).solid
        };
        let spec = S::Union {
            of: vec![
                volume(0, bump),
                S::Sphere {
                    center: at(1).to_array(),
                    radius: 0.5,
                },
                volume(2, 0.0),
                S::Box {
                    min: (at(3) - DVec3::splat(0.4) + DVec3::Y * moved).to_array(),
                    max: (at(3) + DVec3::splat(0.4) + DVec3::Y * moved).to_array(),
                },
            ],
        };
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => unreachable!("a 3D model"),
        }
    }

    /// The same triangles on the same vertices, each within 1e-12 of the other's.
    fn assert_same(a: &Mesh, b: &Mesh) {
        assert_eq!(a.triangles, b.triangles);
        assert_eq!(a.positions.len(), b.positions.len());
        for (p, q) in a.positions.iter().zip(&b.positions) {
            assert!((*p - *q).length() <= 1e-12, "{p} against {q}");
        }
        for (p, q) in a.normals.iter().zip(&b.normals) {
            assert!((*p - *q).length() <= 1e-12, "{p} against {q}");
        }
    }

    fn fresh(tree: &Tree<3>, resolution: usize, share: Share) -> Piece {
        tree.polygonize_share(resolution, 1e-9, None, share)
            .unwrap()
    }

    #[test]
    fn an_edit_remakes_only_the_blocks_near_the_solid_it_changes() {
        let mut cache = MeshCache::new();
        let first = row(0.0, 0.0);
        let (piece, made) = first
            .polygonize_share_cached(48, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        assert_eq!(made.kept, 0);
        assert!(made.blocks > 20, "{made:?}");
        assert_same(&piece.mesh, &fresh(&first, 48, Share::WHOLE).mesh);
        assert!(piece.mesh.triangle_count() > 1000);
        // The same model again: every block kept.
        let (again, made) = first
            .polygonize_share_cached(48, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        assert_eq!(made.kept, made.blocks);
        assert_same(&again.mesh, &piece.mesh);
        // One control value of the first volume raised: its blocks remade, the others kept, and
        // the mesh the one made from nothing.
        for (bump, moved) in [(0.05, 0.0), (0.1, 0.0), (0.1, 0.1), (0.0, 0.1)] {
            let edited = row(bump, moved);
            let (piece, made) = edited
                .polygonize_share_cached(48, 1e-9, None, Share::WHOLE, &mut cache)
                .unwrap();
            let whole = fresh(&edited, 48, Share::WHOLE).mesh;
            assert_same(&piece.mesh, &whole);
            assert!(
                made.kept * 2 > made.blocks && made.kept < made.blocks,
                "{bump} {moved}: {made:?}"
            );
        }
        // Another resolution: nothing to keep, the same mesh as made from nothing.
        let (piece, made) = first
            .polygonize_share_cached(40, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        assert_eq!(made.kept, 0);
        assert_same(&piece.mesh, &fresh(&first, 40, Share::WHOLE).mesh);
    }

    /// A tube of three cubic cells along x, one inner control value of cell `edited` raised by
    /// `bump`, beside a sphere.
    fn tube(edited: usize, bump: f64) -> Tree<3> {
        use crate::piecewise::Piecewise;
        let (cells, degree) = ([3, 1, 1], [3, 3, 3]);
        let dims = [10, 4, 4];
        let mut points = Vec::new();
        for i in 0..dims[0] {
            for j in 0..dims[1] {
                for k in 0..dims[2] {
                    let d = |a: usize| (a as f64 - 1.5).abs();
                    let raised = if [i, j, k] == [edited * 3 + 1, 1, 2] {
                        bump
                    } else {
                        0.0
                    };
                    let xi = 0.5 - 0.2 * (d(j) + d(k)) + 0.03 * (i % 4) as f64 + raised;
                    points.push(glam::DVec4::new(
                        i as f64 / 3.0,
                        j as f64 / 3.0,
                        k as f64 / 3.0,
                        xi,
                    ));
                }
            }
        }
        let solid = Piecewise::new(cells, degree, points).unwrap();
        let spec = S::Union {
            of: vec![
                S::from_piecewise(&solid),
                S::Sphere {
                    center: [1.5, 0.5, 2.0],
                    radius: 0.4,
                },
            ],
        };
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => unreachable!("a 3D model"),
        }
    }

    #[test]
    fn an_edit_of_one_cell_remakes_the_blocks_near_that_cell() {
        let mut cache = MeshCache::new();
        let first = tube(0, 0.0);
        let _ = first
            .polygonize_share_cached(48, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        // Each state differs from the one before in one cell.
        for (edited, bump) in [(0, 0.1), (0, 0.0), (2, 0.08), (2, 0.0), (1, -0.05)] {
            let tree = tube(edited, bump);
            let (piece, made) = tree
                .polygonize_share_cached(48, 1e-9, None, Share::WHOLE, &mut cache)
                .unwrap();
            assert_same(&piece.mesh, &fresh(&tree, 48, Share::WHOLE).mesh);
            // The blocks in one cell of three remade.
            assert!(
                made.kept * 2 > made.blocks && made.kept < made.blocks,
                "cell {edited}: {made:?}"
            );
        }
    }

    #[test]
    fn shares_kept_apart_join_into_the_mesh() {
        let shares = [Share::new(0, 3), Share::new(1, 3), Share::new(2, 3)].map(Option::unwrap);
        let mut caches = [MeshCache::new(), MeshCache::new(), MeshCache::new()];
        for bump in [0.0, 0.08] {
            let tree = row(bump, 0.0);
            let pieces: Vec<Piece> = shares
                .iter()
                .zip(&mut caches)
                .map(|(&share, cache)| {
                    let (piece, _) = tree
                        .polygonize_share_cached(32, 1e-9, None, share, cache)
                        .unwrap();
                    assert_same(&piece.mesh, &fresh(&tree, 32, share).mesh);
                    piece
                })
                .collect();
            let whole = tree.polygonize(32, 1e-9, None).unwrap();
            assert_same(&Piece::weld(pieces), &whole);
        }
    }

    #[test]
    fn an_empty_model_empties_the_cache() {
        let mut cache = MeshCache::new();
        let _ = row(0.0, 0.0)
            .polygonize_share_cached(16, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        assert!(!cache.blocks.is_empty());
        let empty = match ModelFile::from_spec(S::Intersection {
            of: vec![
                S::Sphere {
                    center: [0.0; 3],
                    radius: 0.5,
                },
                S::Sphere {
                    center: [5.0, 0.0, 0.0],
                    radius: 0.5,
                },
            ],
        })
        .to_tree()
        .unwrap()
        {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => unreachable!("a 3D model"),
        };
        let (piece, made) = empty
            .polygonize_share_cached(16, 1e-9, None, Share::WHOLE, &mut cache)
            .unwrap();
        assert_eq!(piece.mesh.triangle_count(), 0);
        assert_eq!(made.kept, 0);
        // A bad resolution is refused and leaves the cache as it was.
        let before = cache.blocks.len();
        assert!(
            row(0.0, 0.0)
                .polygonize_share_cached(0, 1e-9, None, Share::WHOLE, &mut cache)
                .is_err()
        );
        assert_eq!(cache.blocks.len(), before);
    }
}
