//! Indexed triangle meshes, the polygonizer that makes them from a sampled field, and the files they
//! are written to: binary [`stl`], [`obj`], binary [`ply`], and [`svg`] for 2D contours. Writers return
//! bytes or strings; core does no file I/O.

use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

mod bezier;
pub mod obj;
pub mod ply;
mod polygonize;
pub mod stl;
pub mod svg;

pub use bezier::{MAX_RESOLUTION, MeshError};
pub use polygonize::{EdgeRoots, LinearRoots, SampleGrid, polygonize};

/// An indexed triangle mesh: triangles are counter-clockwise seen from outside the solid, and
/// `normals[i]` is the outward unit normal at `positions[i]` (from `−∇f`), or zero where unknown.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// One outward unit normal per vertex.
    pub normals: Vec<DVec3>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
}

/// Why a mesh is not a closed, consistently oriented 2-manifold.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ManifoldError {
    /// A triangle uses a vertex index past the end, or the same vertex twice.
    BadTriangle {
        /// The triangle's index.
        triangle: usize,
    },
    /// An edge has a number of faces other than two, or two faces that run it the same way.
    Edge {
        /// One end of the edge.
        a: u32,
        /// The other end.
        b: u32,
        /// Faces that run it `a → b`.
        forward: usize,
        /// Faces that run it `b → a`.
        backward: usize,
    },
    /// The triangles around a vertex form more than one fan (two surfaces touch at a point).
    Vertex {
        /// The vertex.
        vertex: u32,
    },
}

impl fmt::Display for ManifoldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadTriangle { triangle } => {
                write!(f, "triangle {triangle} has a bad vertex index")
            }
            Self::Edge {
                a,
                b,
                forward,
                backward,
            } => write!(
                f,
                "edge {a}–{b} has {forward} faces one way and {backward} the other (want 1 and 1)"
            ),
            Self::Vertex { vertex } => {
                write!(f, "the faces around vertex {vertex} are not one fan")
            }
        }
    }
}

impl core::error::Error for ManifoldError {}

impl Mesh {
    /// The number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The three corners of triangle `t`.
    ///
    /// # Panics
    ///
    /// If `t` or one of its indices is out of range.
    #[must_use]
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// The enclosed volume by the divergence theorem, `Σ (a · (b × c)) / 6`: positive for a closed
    /// mesh oriented outward.
    #[must_use]
    pub fn volume(&self) -> f64 {
        // Taken about the middle of the bounds: the same for a closed mesh, without the
        // cancellation of large products for a small mesh far from the origin.
        let (lo, hi) = self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let o = if lo.is_finite() && hi.is_finite() {
            (lo + hi) * 0.5
        } else {
            DVec3::ZERO
        };
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t).map(|p| p - o);
                a.dot(b.cross(c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// The surface area.
    #[must_use]
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                (b - a).cross(c - a).length()
            })
            .sum::<f64>()
            / 2.0
    }

    /// The Euler characteristic `V − E + F` of the mesh's vertices, edges and triangles (2 for a
    /// sphere, 0 for a torus). Counts only vertices used by a triangle.
    #[must_use]
    pub fn euler_characteristic(&self) -> i64 {
        let mut used = alloc::vec![false; self.positions.len()];
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(self.triangles.len() * 3);
        for tri in &self.triangles {
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                if let Some(u) = used.get_mut(a as usize) {
                    *u = true;
                }
                edges.push((a.min(b), a.max(b)));
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let v = used.iter().filter(|&&u| u).count() as i64;
        v - edges.len() as i64 + self.triangles.len() as i64
    }

    /// Checks that the mesh is a closed, consistently oriented 2-manifold: every edge has exactly two
    /// faces that run it in opposite directions, and the faces around every vertex form one fan.
    ///
    /// # Errors
    ///
    /// The first defect found, as a [`ManifoldError`].
    pub fn check_closed_manifold(&self) -> Result<(), ManifoldError> {
        let n = self.positions.len();
        // Directed edges (a, b, triangle), sorted by their undirected key.
        let mut edges: Vec<(u32, u32, bool)> = Vec::with_capacity(self.triangles.len() * 3);
        for (t, tri) in self.triangles.iter().enumerate() {
            if tri.iter().any(|&i| i as usize >= n)
                || tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
            {
                return Err(ManifoldError::BadTriangle { triangle: t });
            }
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                edges.push((a.min(b), a.max(b), a < b));
            }
        }
        edges.sort_unstable();
        for group in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1) {
            let forward = group.iter().filter(|e| e.2).count();
            let backward = group.len() - forward;
            if forward != 1 || backward != 1 {
                return Err(ManifoldError::Edge {
                    a: group[0].0,
                    b: group[0].1,
                    forward,
                    backward,
                });
            }
        }
        // Every edge is now shared by two faces, so around each vertex the faces chain into cycles:
        // the vertex is manifold when they form exactly one. Follow, for each vertex, the map from the
        // edge a face enters by to the edge it leaves by.
        let mut around: Vec<(u32, u32, u32)> = Vec::with_capacity(self.triangles.len() * 3);
        for tri in &self.triangles {
            for e in 0..3 {
                // At corner tri[e], the face runs from tri[e + 2] to tri[e + 1] around it.
                around.push((tri[e], tri[(e + 2) % 3], tri[(e + 1) % 3]));
            }
        }
        around.sort_unstable();
        for fan in around.chunk_by(|x, y| x.0 == y.0) {
            // Each "from" neighbour appears once; follow next = to until back at the start.
            let next = |from: u32| {
                fan.binary_search_by(|probe| probe.1.cmp(&from))
                    .ok()
                    .map(|i| fan[i].2)
            };
            let start = fan[0].1;
            let mut at = start;
            let mut steps = 0;
            loop {
                at = match next(at) {
                    Some(to) => to,
                    None => return Err(ManifoldError::Vertex { vertex: fan[0].0 }),
                };
                steps += 1;
                if at == start || steps > fan.len() {
                    break;
                }
            }
            if steps != fan.len() {
                return Err(ManifoldError::Vertex { vertex: fan[0].0 });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A small closed mesh with normals and awkward coordinates: a ball polygonized by linear marching
    /// cubes, shifted off the grid.
    pub(crate) fn test_mesh() -> Mesh {
        let dims = [9, 9, 9];
        let grid = SampleGrid {
            origin: DVec3::new(-1.0 / 3.0, 0.1, 7.0),
            step: DVec3::splat(0.125),
            dims,
        };
        let mut values = Vec::new();
        for c in 0..9 {
            for b in 0..9 {
                for a in 0..9 {
                    let q = DVec3::new(a as f64, b as f64, c as f64) - 4.0;
                    values.push(9.0 - q.length_squared());
                }
            }
        }
        let mut mesh = polygonize(&grid, &values, &mut LinearRoots);
        let centre = grid.point(4, 4, 4);
        mesh.normals = mesh
            .positions
            .iter()
            .map(|&p| (p - centre).normalize())
            .collect();
        mesh
    }

    #[test]
    fn the_test_mesh_is_closed_with_the_euler_characteristic_of_a_sphere() {
        let mesh = test_mesh();
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), 2);
        assert!(mesh.volume() > 0.0 && mesh.area() > 0.0);
    }

    #[test]
    fn defects_are_found() {
        let mut mesh = test_mesh();
        mesh.triangles.pop();
        assert!(matches!(
            mesh.check_closed_manifold(),
            Err(ManifoldError::Edge { .. })
        ));
        let mut flipped = test_mesh();
        flipped.triangles[0].swap(0, 1);
        assert!(matches!(
            flipped.check_closed_manifold(),
            Err(ManifoldError::Edge { .. })
        ));
        let mut bad = test_mesh();
        bad.triangles[0][0] = u32::MAX;
        assert_eq!(
            bad.check_closed_manifold(),
            Err(ManifoldError::BadTriangle { triangle: 0 })
        );
        // Two balls touching at one vertex: every edge is fine, the vertex is not.
        let a = test_mesh();
        let mut two = a.clone();
        let shift = a.positions.len() as u32;
        two.positions
            .extend(a.positions.iter().map(|p| *p + DVec3::X * 10.0));
        two.normals.extend(a.normals.iter().copied());
        two.triangles.extend(
            a.triangles
                .iter()
                .map(|t| t.map(|i| if i == 0 { 0 } else { i + shift })),
        );
        assert_eq!(
            two.check_closed_manifold(),
            Err(ManifoldError::Vertex { vertex: 0 })
        );
    }
}
