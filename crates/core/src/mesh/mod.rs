//! Indexed triangle meshes, the polygonizer that makes them from a sampled field, and the files they
//! are read from and written to: one [`Format`] per file kind ([`obj`], binary and ASCII [`stl`],
//! binary and ASCII [`ply`]), each module with its reader beside its writer, and [`svg`] for 2D
//! contours. Reading is shared ([`read`], [`from_raw`]) and so is the one check that triangles
//! bound a solid ([`validate`], [`Mesh::check_closed_manifold`]). A solid of several pieces or with
//! cavities has one shell per piece of its surface, oriented by nesting ([`orient_shells`]). Core
//! does no file I/O: readers take bytes, writers return them.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::str::FromStr;

use glam::DVec3;

pub(crate) mod adaptive;
mod bezier;
pub mod exchange;
mod manifold;
pub mod obj;
pub mod ply;
pub(crate) mod polygonize;
mod read;
mod shells;
pub mod stl;
pub mod svg;

pub use adaptive::AdaptiveStats;
pub use bezier::{MAX_RESOLUTION, MeshError};
pub use manifold::{MeshDefects, validate};
pub use polygonize::{EdgeRoots, LinearRoots, Piece, SampleGrid, Share, polygonize};
pub use read::{
    MAX_FILE_BYTES, MAX_TRIANGLES, MAX_VERTICES, RawMesh, ReadError, angle_weighted_normals,
    from_raw, read,
};
pub use shells::{MAX_SHELL_WORK, ShellError, ShellOrientation, orient_shells, shells};

/// A mesh file format: what the command line, the page and scripts export to and import from.
/// With the `serde` feature it is written as its extension (`"obj"`, `"stl"`, `"ply"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Format {
    /// Wavefront OBJ (text): positions, normals, faces.
    Obj,
    /// STL: written binary; read binary or ASCII.
    Stl,
    /// PLY: written binary little-endian with normals; read ASCII or binary of either byte order.
    Ply,
}

impl Format {
    /// Every format.
    pub const ALL: [Self; 3] = [Self::Stl, Self::Obj, Self::Ply];

    /// The file name extension, lower case and without the dot (`"obj"`, `"stl"`, `"ply"`).
    #[must_use]
    pub const fn extension(self) -> &'static str {
        match self {
            Self::Obj => "obj",
            Self::Stl => "stl",
            Self::Ply => "ply",
        }
    }

    /// The media type of a file of this format.
    #[must_use]
    pub const fn media_type(self) -> &'static str {
        match self {
            Self::Obj => "model/obj",
            Self::Stl => "model/stl",
            Self::Ply => "application/octet-stream",
        }
    }

    /// The format of a file named `path`, by its extension (any case); `None` for another.
    #[must_use]
    pub fn of_path(path: &str) -> Option<Self> {
        let (_, ext) = path.rsplit_once('.')?;
        ext.parse().ok()
    }

    /// The format of a file from its bytes: PLY when it starts with `ply` and a line end; binary
    /// STL when it is at least 84 bytes long and exactly `84 + 50·count` bytes, `count` being the
    /// little-endian `u32` at offset 80; ASCII STL when it starts (after white space) with `solid`
    /// and contains `facet`; OBJ otherwise.
    #[must_use]
    pub fn detect(bytes: &[u8]) -> Self {
        if ply::starts_with_magic(bytes) {
            Self::Ply
        } else if stl::is_binary(bytes) || stl::is_ascii(bytes) {
            Self::Stl
        } else {
            Self::Obj
        }
    }

    /// The file of `mesh` in this format.
    #[must_use]
    pub fn write(self, mesh: &Mesh) -> Vec<u8> {
        match self {
            Self::Obj => obj::write_obj(mesh).into_bytes(),
            Self::Stl => stl::write_stl(mesh),
            Self::Ply => ply::write_ply(mesh),
        }
    }

    /// The vertices and triangles of a file of this format as it gives them (no welding, checks
    /// or orientation: see [`Format::read`]).
    ///
    /// # Errors
    ///
    /// [`ReadError`] for a file that does not follow the format or passes a cap.
    pub fn parse(self, bytes: &[u8]) -> Result<RawMesh, ReadError> {
        match self {
            Self::Obj => obj::parse_obj(bytes),
            Self::Stl => stl::parse_stl(bytes),
            Self::Ply => ply::parse_ply(bytes),
        }
    }

    /// A file of this format as a closed, outward-oriented mesh with unit vertex normals (the
    /// steps of [`read`], with the format given).
    ///
    /// # Errors
    ///
    /// [`ReadError`]: the file is too large, malformed, empty, or not a closed solid.
    pub fn read(self, bytes: &[u8]) -> Result<Mesh, ReadError> {
        read::check_size(bytes)?;
        from_raw(&self.parse(bytes)?)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

/// A mesh format name that is none of `stl`, `obj`, `ply`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownFormat(pub String);

impl fmt::Display for UnknownFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown mesh format `{}`: the formats are stl, obj and ply",
            self.0
        )
    }
}

impl core::error::Error for UnknownFormat {}

impl FromStr for Format {
    type Err = UnknownFormat;

    /// `"stl"`, `"obj"` or `"ply"`, in any case, with or without a leading dot.
    fn from_str(s: &str) -> Result<Self, UnknownFormat> {
        let name = s.strip_prefix('.').unwrap_or(s);
        Self::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(name))
            .ok_or_else(|| UnknownFormat(s.into()))
    }
}

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

/// The measurements of a closed mesh ([`Mesh::measure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measure {
    /// The enclosed volume.
    pub volume: f64,
    /// The surface area.
    pub area: f64,
    /// The low corner of the bounding box (the origin for an empty mesh).
    pub min: DVec3,
    /// The high corner of the bounding box.
    pub max: DVec3,
}

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

    /// Appends `other`'s vertices, normals and triangles (its indices moved past this mesh's
    /// vertices): two meshes side by side, sharing nothing.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
    }

    /// The enclosed volume by the divergence theorem, `Σ (a · (b × c)) / 6`: positive for a closed
    /// mesh oriented outward.
    #[must_use]
    pub fn volume(&self) -> f64 {
        // Taken about the middle of the bounds: the same for a closed mesh, without the
        // cancellation of large products for a small mesh far from the origin. Each term is
        // `(a − o) · ((b − a) × (c − a))`, the same triple product with the cross product of the
        // triangle's own short edges: `(b − o) × (c − o)` of two long, nearly parallel vectors
        // cancelled (two parts 3e5 apart read 0.5 % off).
        let o = self
            .bounds()
            .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
            .map_or(DVec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                (a - o).dot((b - a).cross(c - a))
            })
            .sum::<f64>()
            / 6.0
    }

    /// The box of the vertices that triangles use, `(min, max)`; `None` for a mesh without
    /// triangles.
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut used = self
            .triangles
            .iter()
            .flatten()
            .filter_map(|&i| self.positions.get(i as usize));
        let first = *used.next()?;
        Some(used.fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))))
    }

    /// What [`Mesh::volume`], [`Mesh::area`] and [`Mesh::bounds`] say of the mesh: exact for the
    /// mesh (the divergence theorem), so as near the solid as the mesh's resolution.
    #[must_use]
    pub fn measure(&self) -> Measure {
        let (min, max) = self.bounds().unwrap_or((DVec3::ZERO, DVec3::ZERO));
        Measure {
            volume: self.volume(),
            area: self.area(),
            min,
            max,
        }
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

    /// Checks that the mesh is a closed, consistently oriented 2-manifold: every edge has exactly
    /// two faces that run it in opposite directions, the faces around every vertex form one fan, no
    /// face repeats a vertex or names one past the end. The topology of [`validate`], which also
    /// rejects faces of (almost) no area: marching cubes makes those where a sample is exactly
    /// zero, and they bound the solid all the same.
    ///
    /// # Errors
    ///
    /// Every defect, counted, as [`MeshDefects`].
    pub fn check_closed_manifold(&self) -> Result<(), MeshDefects> {
        manifold::check(&self.positions, &self.triangles, false)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use alloc::vec;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A box with a box-shaped hole walked inward: the volume and area of the two shells
    /// together, the box of the outer one; an empty mesh measures nothing.
    #[test]
    fn a_mesh_is_measured_by_the_divergence_theorem() {
        let (lo, hi) = (DVec3::new(-1.0, 2.0, 10.0), DVec3::new(2.0, 4.0, 14.0));
        let (mut positions, mut triangles) = crate::testutil::box_mesh(lo, hi, 0);
        let (hole, mut inward) =
            crate::testutil::box_mesh(DVec3::new(0.0, 2.5, 11.0), DVec3::new(1.0, 3.5, 12.0), 8);
        for t in &mut inward {
            t.swap(1, 2);
        }
        positions.extend(hole);
        triangles.extend(inward);
        let mesh = Mesh {
            normals: vec![DVec3::Z; positions.len()],
            positions,
            triangles,
        };
        let m = mesh.measure();
        assert!(
            (m.volume - (3.0 * 2.0 * 4.0 - 1.0)).abs() < 1e-12,
            "{}",
            m.volume
        );
        let outer = 2.0 * (3.0 * 2.0 + 3.0 * 4.0 + 2.0 * 4.0);
        assert!((m.area - (outer + 6.0)).abs() < 1e-12, "{}", m.area);
        assert_eq!((m.min, m.max), (lo, hi));
        assert_eq!(Mesh::default().bounds(), None);
        assert_eq!(Mesh::default().measure().volume, 0.0);
    }

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
        assert_eq!(
            mesh.check_closed_manifold().map_err(|d| d.open_edges),
            Err(3)
        );
        let mut flipped = test_mesh();
        flipped.triangles[0].swap(0, 1);
        assert_eq!(
            flipped
                .check_closed_manifold()
                .map_err(|d| d.inconsistent_edges),
            Err(3)
        );
        let mut bad = test_mesh();
        bad.triangles[0][0] = u32::MAX;
        assert_eq!(
            bad.check_closed_manifold()
                .map_err(|d| d.degenerate_triangles),
            Err(1)
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
            Err(MeshDefects {
                non_manifold_vertices: 1,
                ..MeshDefects::default()
            })
        );
    }
}
