//! A tree's mesh again after an edit, remaking only the blocks the edit can change
//! ([`MeshCache`]).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use super::mesh::{Plan, RangeMemo, Reads};
use super::{Leaf, Shape, Step, Tree, TreeMeshError};
use crate::mesh::polygonize::{Block, Keyed, Marcher, weld_kept};
use crate::mesh::{Piece, SampleGrid, Share};

/// A tree's mesh kept block by block, for [`Tree::polygonize_share_cached`]: what an edit leaves
/// unchanged is not made again. One cache follows one share of one mesh (the resolution and the
/// region may change: a cache that does not fit starts again).
///
/// The mesher samples a block of the grid by the block's pruned program: the operands that can
/// decide a sign in it. Its samples, the roots on its edges and their normals are that program's
/// values on those leaves alone, save where the whole tree is read (a face sample within a hair of
/// zero, the corners of an ambiguous face, a root the program leaves past the accuracy). So a block
/// whose program is the same after an edit, every leaf it reads unchanged, and that read nothing
/// of the whole tree, meshes as it did: its piece is kept. The leaves' interval ranges over the
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

impl MeshCache {
    /// An empty cache.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether the piece kept for a block of `program` in `tree` is the one meshing it again would
    /// make, with the face samples' threshold `tau`.
    fn holds(&self, kept: &Kept, program: Option<&[Step]>, tree: &Tree<3>, tau: f64) -> bool {
        if kept.program.as_deref() != program {
            return false;
        }
        let same_leaf = |i: usize| match (self.leaves.get(i), tree.leaves.get(i)) {
            (Some(a), Some(b)) => a == b,
            _ => false,
        };
        match program {
            // The whole tree: kept only if nothing of it changed.
            None => {
                self.steps == tree.steps
                    && self.leaves.len() == tree.leaves.len()
                    && (0..tree.leaves.len()).all(same_leaf)
            }
            // Its own leaves, and nothing of the whole tree: a face sample that now falls within
            // `tau` of zero would take the whole tree's value.
            Some(steps) => {
                !kept.reads.whole
                    && kept.reads.near >= tau
                    && steps.iter().all(|s| match *s {
                        Step::Leaf(i) => same_leaf(i),
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
        let mut memo = RangeMemo {
            same: (0..self.leaves.len())
                .map(|i| cache.leaves.get(i) == self.leaves.get(i))
                .collect(),
            kept: core::mem::take(&mut cache.ranges.kept),
            made: BTreeMap::new(),
        };
        let plan = self.walk(grid, clip, accuracy, Some(&mut memo));
        let blocks = share.of_blocks(&plan.blocks);
        let key = |b: &Block| (b.lo, b.size);
        // The blocks to mesh again: not in the cache, or changed.
        let stale: Vec<usize> = (0..blocks.len())
            .filter(|&i| {
                !cache
                    .blocks
                    .get(&key(&blocks[i]))
                    .is_some_and(|kept| cache.holds(kept, plan.program(&blocks[i]), self, plan.tau))
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

/// The pieces of `blocks[i]` for each `i` in `stale`, in that order, each meshed alone (on every
/// thread with the `parallel` feature).
fn made(plan: &Plan<'_>, blocks: &[Block], stale: &[usize]) -> Vec<(Keyed, Reads)> {
    let marcher = Marcher::new();
    let one = |&i: &usize| plan.mesh(core::slice::from_ref(&blocks[i]), &marcher);
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        stale.par_iter().map(one).collect()
    }
    #[cfg(not(feature = "parallel"))]
    stale.iter().map(one).collect()
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
