//! Parts far apart: a solid whose parts lie far from each other (a sphere and a torus 1000 apart,
//! a detail beside a large body) is meshed part by part, each at the resolution asked in a box of
//! its own, not on one grid over the hull of all of them, where each part got less than a cell.
//! The parts are the tree's bounding boxes ([`super::bounds::boxes`]: a union's are its
//! operands') gathered while any two are nearer each other than the longer side of either
//! ([`super::bounds::clusters`]).

use alloc::vec::Vec;

use super::Tree;
use super::mesh::{MeshStats, TreeMeshError};
use crate::mesh::polygonize::Keyed;
use crate::mesh::{Mesh, Share};

impl Tree<3> {
    /// Parts far apart ([`Tree::far_parts`]), each meshed at `resolution` in a box of its own:
    /// share `k` of `n` makes parts `k`, `k + n`, … whole, on vertices no other share has
    /// (the parts' grids never meet); `progress` over the parts, each an equal share.
    pub(super) fn mesh_parts(
        &self,
        resolution: usize,
        accuracy: f64,
        share: Share,
        mut progress: Option<&mut dyn FnMut(usize, usize)>,
    ) -> Result<(Keyed, MeshStats), TreeMeshError> {
        const STEPS: usize = 1000;
        let count = self.clusters.len();
        let (mut mesh, mut keys) = (Mesh::default(), Vec::new());
        let mut stats = MeshStats::default();
        for (k, part) in self.clusters.iter().enumerate() {
            if k % share.count() != share.index() {
                continue;
            }
            let reporting = progress.is_some();
            let mut report = |done: usize, total: usize| {
                if let Some(outer) = progress.as_mut() {
                    outer(k * STEPS + done * STEPS / total.max(1), count * STEPS);
                }
            };
            let report: Option<&mut dyn FnMut(usize, usize)> =
                if reporting { Some(&mut report) } else { None };
            let ((piece, _), part_stats) = self.mesh_area(
                Some((part.lo, part.hi)),
                resolution,
                accuracy,
                None,
                Share::WHOLE,
                report,
            )?;
            mesh.append(&piece);
            keys.resize(mesh.positions.len(), crate::mesh::Piece::UNSHARED);
            stats.cells += part_stats.cells;
            stats.skipped += part_stats.skipped;
            stats.evaluated += part_stats.evaluated;
        }
        if let Some(outer) = progress.as_mut() {
            outer(count * STEPS, count * STEPS);
        }
        Ok(((mesh, keys), stats))
    }

    /// The parts of the solid far apart from each other, each meshed in a box of its own: boxes
    /// holding the solid between them, no two nearer each other than the longer side of either
    /// (a sphere and a torus 1000 apart are two parts; one grid over both gave each less than a
    /// cell). One box where the parts are near; none for an empty or unbounded solid.
    #[must_use]
    pub fn far_parts(&self) -> Vec<([f64; 3], [f64; 3])> {
        self.clusters.iter().map(|b| (b.lo, b.hi)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Piece;
    use crate::model::{CoordAxis, ModelFile, SolidSpec as S};
    use crate::tree::ModelTree;
    use alloc::boxed::Box;
    use alloc::vec;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn space(spec: S) -> Tree<3> {
        match ModelFile::from_spec(spec).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => panic!("2D"),
        }
    }

    fn sphere(center: [f64; 3], radius: f64) -> S {
        S::Sphere { center, radius }
    }

    fn torus(center: [f64; 3]) -> S {
        S::Torus {
            center,
            axis: CoordAxis::Z,
            major: 2.0,
            minor: 0.5,
        }
    }

    fn moved(solid: S, by: [f64; 3]) -> S {
        S::Transform {
            solid: Box::new(solid),
            translate: Some(by.to_vec()),
            rotate: None,
            scale: None,
        }
    }

    /// A sphere and a torus 1000 apart (0 triangles on one grid over both), a detail of radius
    /// 0.001 500 away from a unit sphere: each part meshed as it is alone, closed, in its place.
    #[test]
    fn parts_far_apart_are_meshed_each_where_it_is() {
        for (a, b) in [
            (sphere([0.0; 3], 1.0), torus([1000.0, 0.0, 0.0])),
            (sphere([0.0; 3], 1.0), sphere([500.0, 3.0, 0.0], 1e-3)),
            (
                torus([0.0; 3]),
                moved(sphere([0.0; 3], 1.0), [-3e5, 2e5, 1e4]),
            ),
        ] {
            let both = space(S::Union {
                of: vec![a.clone(), b.clone()],
            });
            assert_eq!(both.far_parts().len(), 2);
            let mesh = both.polygonize(32, 1e-10, None).unwrap();
            mesh.check_closed_manifold().unwrap();
            let alone: Vec<Mesh> = [a, b]
                .into_iter()
                .map(|s| space(s).polygonize(32, 1e-10, None).unwrap())
                .collect();
            let triangles: usize = alone.iter().map(Mesh::triangle_count).sum();
            assert_eq!(mesh.triangle_count(), triangles);
            let volume: f64 = alone.iter().map(Mesh::volume).sum();
            assert!((mesh.volume() - volume).abs() <= 1e-6 * volume, "{volume}");
            for p in mesh.positions.iter().step_by(11) {
                assert!(both.f(*p).abs() < 1e-6, "{p}");
            }
            // The page's workers make it in shares that weld into the same mesh.
            for n in [2, 3] {
                let pieces = (0..n)
                    .map(|k| {
                        both.polygonize_share(32, 1e-10, None, Share::new(k, n).unwrap())
                            .unwrap()
                    })
                    .collect();
                let welded = Piece::weld(pieces);
                assert_eq!(welded.triangle_count(), mesh.triangle_count());
                welded.check_closed_manifold().unwrap();
            }
        }
        // Parts near each other are one part, on one grid.
        let near = space(S::Union {
            of: vec![sphere([0.0; 3], 1.0), sphere([3.5, 0.0, 0.0], 1.0)],
        });
        assert_eq!(near.far_parts().len(), 1);
    }

    /// A unit sphere at 1e8 meshes as it does at the origin (a millionth of its coordinate,
    /// 100, was the least side of its sampling box: 0 triangles).
    #[test]
    fn a_solid_far_from_the_origin_meshes_as_at_the_origin() {
        let home = space(sphere([0.0; 3], 1.0))
            .polygonize(48, 1e-9, None)
            .unwrap();
        for at in [1e8, -3e9] {
            let far = space(sphere([at, 0.0, 0.0], 1.0))
                .polygonize(48, 1e-9, None)
                .unwrap();
            far.check_closed_manifold().unwrap();
            assert_eq!(far.triangle_count(), home.triangle_count(), "at {at}");
            // To the precision of f64 there: units in the last place of `at`.
            let ulp = at.abs() * f64::EPSILON;
            for (p, q) in far.positions.iter().zip(&home.positions) {
                assert!(
                    (*p - DVec3::new(at, 0.0, 0.0) - *q).abs().max_element()
                        < 1e-4 + 4.0 * ulp.sqrt()
                );
            }
            assert!((far.volume() - home.volume()).abs() < 1e-3 * home.volume());
        }
    }

    /// A mesh that comes out empty while the solid has an inside point is an error, never an
    /// empty success (a box a billionth thick, between two samples of any grid).
    #[test]
    fn an_empty_mesh_of_a_solid_with_an_inside_point_is_an_error() {
        let thin = space(S::Box {
            min: [0.0, 0.0, 0.0],
            max: [1.0, 1.0, 1e-9],
        });
        match thin.polygonize(64, 1e-12, None) {
            Err(TreeMeshError::Lost { at, f, resolution }) => {
                assert!(f > 0.0 && resolution == 64);
                assert!(thin.f(DVec3::from_array(at)) > 0.0);
            }
            other => panic!("{other:?}"),
        }
        // A 2D tree's contour likewise.
        let strip = match ModelFile::from_spec(S::Rectangle {
            min: [0.0, 0.0],
            max: [1.0, 1e-9],
        })
        .to_tree()
        .unwrap()
        {
            ModelTree::Plane(t) => t,
            ModelTree::Space(_) => panic!("3D"),
        };
        assert!(matches!(
            strip.contour(64, 1e-12, None),
            Err(TreeMeshError::Lost { resolution: 64, .. })
        ));
        // An empty solid is an empty mesh, as before.
        let none = space(S::Intersection {
            of: vec![sphere([0.0; 3], 1.0), sphere([5.0, 0.0, 0.0], 1.0)],
        });
        assert_eq!(none.polygonize(16, 1e-9, None).unwrap().triangle_count(), 0);
    }
}
