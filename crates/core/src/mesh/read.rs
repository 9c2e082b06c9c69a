//! Reading triangle meshes that bound solids, from bytes (core does no file I/O): the steps every
//! [`Format`]'s reader shares.
//!
//! The input is untrusted: every reader returns a typed [`ReadError`] instead of panicking, and
//! nothing is allocated in proportion to a count the file claims before that count is checked
//! against the caps ([`MAX_FILE_BYTES`], [`MAX_TRIANGLES`], [`MAX_VERTICES`]).
//!
//! [`read`] turns a file into a [`Mesh`] that bounds a solid:
//!
//! 1. [`Format::detect`] the format and parse it ([`Format::parse`]) into a [`RawMesh`];
//! 2. weld vertices with exactly equal coordinates (STL has no indices; OBJ and PLY files often
//!    repeat positions too) and drop vertices that no triangle uses;
//! 3. [`validate`]: every edge has two triangles running it opposite ways, no triangle is
//!    degenerate and the triangles around every vertex form one fan; all defects are counted
//!    ([`MeshDefects`]);
//! 4. orient: a closed mesh with negative volume was written inside out, and is turned over;
//! 5. vertex normals: the file's own (OBJ `vn`, PLY `nx ny nz`) where it gives one for every
//!    vertex, otherwise [`angle_weighted_normals`].

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

use super::manifold::{MeshDefects, corners, validate};
use super::{Format, Mesh, stl};

/// The most triangles a file may have (after fan-splitting OBJ polygons): a binary STL of this size
/// is 10 MB, and the solids of this project are meant for thousands of triangles, not millions.
/// A file past it is refused ([`ReadError`]'s "more than 200000 triangles"), in the command line,
/// the page and the node package alike; a model file's mesh operand has the same cap. README.md
/// says it with the other input caps.
pub const MAX_TRIANGLES: usize = 200_000;

/// The most vertices a mesh may have: OBJ `v` (and `vn`) statements as read, STL corners after
/// welding. Refused past it as [`MAX_TRIANGLES`] is.
pub const MAX_VERTICES: usize = 200_000;

/// The largest file accepted, in bytes (128 MiB).
pub const MAX_FILE_BYTES: usize = 128 << 20;

/// A mesh as a file gives it, before welding, validation and orientation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RawMesh {
    /// Vertex positions, all finite: OBJ `v` statements in file order, or STL corners, three per
    /// facet.
    pub positions: Vec<DVec3>,
    /// Per vertex, the sum of the file's unit normals at the face corners that use it (not
    /// normalised, so that welded vertices can add theirs): present only for an OBJ file that gives
    /// a `vn` at every face corner, or a PLY file with `nx ny nz` on its vertices.
    pub normals: Option<Vec<DVec3>>,
    /// Triangles as indices into `positions`, all in range; polygons are split into fans.
    pub triangles: Vec<[u32; 3]>,
}

/// Why a file could not be read as a closed solid mesh.
#[derive(Clone, Debug, PartialEq)]
pub enum ReadError {
    /// The file is larger than a cap allows.
    TooLarge {
        /// What was counted: `"bytes"`, `"triangles"`, `"vertices"` or `"normals"`.
        what: &'static str,
        /// The count when reading stopped: the whole count where the file states it (bytes, binary
        /// STL triangles), otherwise the first count past the cap.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// The file has no triangles.
    Empty,
    /// A text file does not follow its format.
    Parse {
        /// The 1-based line number.
        line: usize,
        /// What is wrong there.
        reason: &'static str,
    },
    /// A binary STL whose length is not the one its triangle count needs: it was cut short, or it is
    /// not a mesh file at all.
    Truncated {
        /// The length the header's triangle count needs (84 for a file shorter than its header).
        expected_bytes: u64,
        /// The file's length.
        got_bytes: u64,
    },
    /// A vertex coordinate is NaN or infinite.
    NotFinite {
        /// The vertex's 1-based number in the file (for STL, corners count three per facet).
        vertex: usize,
    },
    /// An OBJ face refers to a vertex or normal that does not exist (or to index 0).
    BadIndex {
        /// The 1-based line number.
        line: usize,
        /// The index as written (negative indices count back from the latest vertex).
        index: i64,
    },
    /// A triangle of a mesh given as lists (a model file, not a file read here) names a vertex
    /// that does not exist.
    TriangleIndex {
        /// The triangle's 0-based number.
        triangle: usize,
        /// The vertex index it names.
        index: u32,
    },
    /// A binary file (PLY) does not follow its format.
    Malformed {
        /// What is wrong.
        reason: &'static str,
    },
    /// The mesh is not a closed, consistently oriented 2-manifold.
    Defects(MeshDefects),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooLarge { what, max, .. } => write!(
                f,
                "the file is too large: it has more than {max} {what}, the most this reader takes"
            ),
            Self::Empty => f.write_str("the file has no triangles"),
            Self::Parse { line, reason } => write!(f, "line {line}: {reason}"),
            Self::Truncated {
                expected_bytes,
                got_bytes,
            } => write!(
                f,
                "the file looks like a binary STL but is truncated or damaged: its header calls for \
                 {expected_bytes} bytes and the file has {got_bytes}"
            ),
            Self::NotFinite { vertex } => {
                write!(
                    f,
                    "vertex {vertex} has a coordinate that is not a finite number"
                )
            }
            Self::BadIndex { line, index: 0 } => {
                write!(f, "line {line}: index 0 is not valid (OBJ counts from 1)")
            }
            Self::BadIndex { line, index } => {
                write!(
                    f,
                    "line {line}: index {index} refers to nothing defined before it"
                )
            }
            Self::TriangleIndex { triangle, index } => write!(
                f,
                "triangle {triangle} names vertex {index}, which does not exist"
            ),
            Self::Malformed { reason } => write!(f, "the file is damaged: {reason}"),
            Self::Defects(defects) => write!(f, "{defects}"),
        }
    }
}

impl core::error::Error for ReadError {}

/// Reads a mesh file of any [`Format`] (told by [`Format::detect`]) into a closed,
/// outward-oriented mesh with unit vertex normals and no unused vertices (the steps are in the
/// module documentation).
///
/// # Errors
///
/// [`ReadError`]: the file is too large, malformed, empty, or not a closed solid.
pub fn read(bytes: &[u8]) -> Result<Mesh, ReadError> {
    check_size(bytes)?;
    let format = match Format::detect(bytes) {
        // Control characters do not occur in text: this is a binary STL of the wrong length.
        Format::Obj if stl::looks_binary(bytes) => Format::Stl,
        format => format,
    };
    from_raw(&format.parse(bytes)?)
}

/// [`ReadError::TooLarge`] past [`MAX_FILE_BYTES`].
pub(crate) fn check_size(bytes: &[u8]) -> Result<(), ReadError> {
    if bytes.len() > MAX_FILE_BYTES {
        return Err(ReadError::TooLarge {
            what: "bytes",
            count: bytes.len(),
            max: MAX_FILE_BYTES,
        });
    }
    Ok(())
}

/// [`ReadError::TooLarge`] for a count that passed its cap while reading.
pub(crate) fn too_many(what: &'static str, max: usize) -> ReadError {
    ReadError::TooLarge {
        what,
        count: max + 1,
        max,
    }
}

/// A closed, outward-oriented mesh with unit vertex normals from parsed (or hand-made) vertices
/// and triangles: weld, check the caps, validate, orient, normals (the steps of [`read`](super::read)
/// after parsing).
///
/// # Errors
///
/// [`ReadError`]: too many triangles or vertices, a bad index, a coordinate that is not finite,
/// no triangles, or not a closed solid.
pub fn from_raw(raw: &RawMesh) -> Result<Mesh, ReadError> {
    if raw.triangles.len() > MAX_TRIANGLES {
        return Err(ReadError::TooLarge {
            what: "triangles",
            count: raw.triangles.len(),
            max: MAX_TRIANGLES,
        });
    }
    if let Some(vertex) = raw.positions.iter().position(|p| !p.is_finite()) {
        return Err(ReadError::NotFinite { vertex: vertex + 1 });
    }
    if raw.triangles.is_empty() {
        return Err(ReadError::Empty);
    }
    // The parsers check their indices with line numbers; lists from elsewhere are checked here.
    let n = raw.positions.len();
    for (triangle, tri) in raw.triangles.iter().enumerate() {
        if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
            return Err(ReadError::TriangleIndex { triangle, index });
        }
    }
    let (positions, file_normals, triangles) = weld(raw)?;
    if positions.len() > MAX_VERTICES {
        return Err(ReadError::TooLarge {
            what: "vertices",
            count: positions.len(),
            max: MAX_VERTICES,
        });
    }
    validate(&positions, &triangles).map_err(ReadError::Defects)?;
    let mut mesh = Mesh {
        positions,
        normals: Vec::new(),
        triangles,
    };
    if mesh.volume() < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    let computed = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh.normals = file_normals
        .and_then(|sums| agreeing_normals(sums, &computed))
        .unwrap_or(computed);
    Ok(mesh)
}

/// The file's normals, normalised and turned to the outside, if they are usable: every vertex has
/// one, and each is on the outer side of the surface (positive dot product with the angle-weighted
/// normal). Otherwise `None`, and the computed normals are used.
fn agreeing_normals(mut sums: Vec<DVec3>, computed: &[DVec3]) -> Option<Vec<DVec3>> {
    for n in &mut sums {
        // Sums of unit vectors: an absolute threshold is relative.
        if n.length() < 1e-9 {
            return None;
        }
        *n = n.normalize();
    }
    // A file written inside out has its normals inside out too, usually.
    let agreement: f64 = sums.iter().zip(computed).map(|(a, b)| a.dot(*b)).sum();
    if agreement < 0.0 {
        for n in &mut sums {
            *n = -*n;
        }
    }
    sums.iter()
        .zip(computed)
        .all(|(a, b)| a.dot(*b) > 0.0)
        .then_some(sums)
}

/// Welds vertices with exactly equal coordinates and keeps only the vertices that triangles use,
/// numbered by first use: the positions, the summed file normals (if any) and the triangles.
#[allow(clippy::type_complexity)]
fn weld(raw: &RawMesh) -> Result<(Vec<DVec3>, Option<Vec<DVec3>>, Vec<[u32; 3]>), ReadError> {
    let n = raw.positions.len();
    // `+ 0.0` turns −0 into +0, so that the two weld.
    let key = |i: u32| {
        let p = raw.positions.get(i as usize).copied().unwrap_or(DVec3::NAN) + 0.0;
        [p.x, p.y, p.z]
    };
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_unstable_by(|&a, &b| {
        let (ka, kb) = (key(a), key(b));
        ka[0]
            .total_cmp(&kb[0])
            .then(ka[1].total_cmp(&kb[1]))
            .then(ka[2].total_cmp(&kb[2]))
            .then(a.cmp(&b))
    });
    // The representative of each vertex: the first in file order with the same coordinates.
    let mut rep: Vec<u32> = (0..n as u32).collect();
    for group in order.chunk_by(|&a, &b| key(a) == key(b)) {
        if let Some(&first) = group.first() {
            for &i in group {
                if let Some(r) = rep.get_mut(i as usize) {
                    *r = first;
                }
            }
        }
    }
    let sums = raw.normals.as_ref().map(|normals| {
        let mut sums = vec![DVec3::ZERO; n];
        for (i, &normal) in normals.iter().enumerate() {
            if let Some(s) = rep.get(i).and_then(|&r| sums.get_mut(r as usize)) {
                *s += normal;
            }
        }
        sums
    });
    let mut new_index = vec![u32::MAX; n];
    let mut positions = Vec::new();
    let mut normals = sums.as_ref().map(|_| Vec::new());
    let mut triangles = Vec::with_capacity(raw.triangles.len());
    for tri in &raw.triangles {
        let mut out = [0u32; 3];
        for (o, &i) in out.iter_mut().zip(tri) {
            let bad = ReadError::BadIndex {
                line: 0,
                index: i64::from(i) + 1,
            };
            let r = *rep.get(i as usize).ok_or(bad.clone())?;
            let slot = new_index.get_mut(r as usize).ok_or(bad.clone())?;
            if *slot == u32::MAX {
                *slot = positions.len() as u32;
                positions.push(*raw.positions.get(r as usize).ok_or(bad)?);
                if let (Some(normals), Some(sums)) = (normals.as_mut(), sums.as_ref()) {
                    normals.push(sums.get(r as usize).copied().unwrap_or(DVec3::ZERO));
                }
            }
            *o = *slot;
        }
        triangles.push(out);
    }
    Ok((positions, normals, triangles))
}

/// Unit vertex normals weighted by angle (Thürmer and Wüthrich 1998): at each vertex, the sum over
/// its triangles of the unit face normal times the triangle's interior angle there, normalised.
/// Independent of how a surface is split into triangles. Vertices without a triangle (or whose sum
/// vanishes) get zero; triangles with an index out of range are skipped.
#[must_use]
pub fn angle_weighted_normals(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for tri in triangles {
        let Some(p) = corners(positions, tri) else {
            continue;
        };
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for k in 0..3 {
            let u = p[(k + 1) % 3] - p[k];
            let v = p[(k + 2) % 3] - p[k];
            // atan2(|u × v|, u · v) is accurate for every angle, unlike acos.
            let angle = libm::atan2(u.cross(v).length(), u.dot(v));
            if let Some(n) = normals.get_mut(tri[k] as usize) {
                *n += face * angle;
            }
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}

pub(crate) fn integer(token: &[u8]) -> Option<i64> {
    core::str::from_utf8(token).ok()?.parse().ok()
}

pub(crate) fn number(token: &[u8]) -> Option<f64> {
    core::str::from_utf8(token).ok()?.parse().ok()
}

/// The next three tokens as numbers (they may be NaN or infinite: the caller reports that).
pub(crate) fn three_numbers<'a>(tokens: &mut impl Iterator<Item = &'a [u8]>) -> Option<DVec3> {
    Some(DVec3::new(
        number(tokens.next()?)?,
        number(tokens.next()?)?,
        number(tokens.next()?)?,
    ))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use alloc::format;
    use alloc::string::String;

    use super::*;
    use crate::mesh::obj::parse_obj;
    use crate::mesh::stl::parse_stl;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    const CUBE: &[u8] = include_bytes!("../../tests/fixtures/mesh/cube.obj");
    const TETRA_ASCII: &[u8] = include_bytes!("../../tests/fixtures/mesh/tetra_ascii.stl");
    const TETRA_BINARY: &[u8] = include_bytes!("../../tests/fixtures/mesh/tetra.stl");
    const OPEN: &[u8] = include_bytes!("../../tests/fixtures/mesh/open.obj");
    const NON_MANIFOLD: &[u8] = include_bytes!("../../tests/fixtures/mesh/nonmanifold.obj");
    const FLIPPED: &[u8] = include_bytes!("../../tests/fixtures/mesh/flipped.obj");
    const DEGENERATE: &[u8] = include_bytes!("../../tests/fixtures/mesh/degenerate.obj");
    const TRUNCATED: &[u8] = include_bytes!("../../tests/fixtures/mesh/truncated.stl");
    const TRUNCATED_ASCII: &[u8] = include_bytes!("../../tests/fixtures/mesh/truncated_ascii.stl");
    const GARBAGE: &[u8] = include_bytes!("../../tests/fixtures/mesh/garbage.bin");
    const BAD_INDEX: &[u8] = include_bytes!("../../tests/fixtures/mesh/bad_index.obj");
    const NAN: &[u8] = include_bytes!("../../tests/fixtures/mesh/nan.obj");

    fn assert_solid(mesh: &Mesh) {
        mesh.check_closed_manifold().unwrap();
        assert!(validate(&mesh.positions, &mesh.triangles).is_ok());
        assert!(mesh.volume() > 0.0);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        for n in &mesh.normals {
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
        // Compact: every vertex is used.
        let mut used = vec![false; mesh.positions.len()];
        for t in &mesh.triangles {
            for &i in t {
                used[i as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u));
    }

    fn defects(bytes: &[u8]) -> MeshDefects {
        match read(bytes) {
            Err(ReadError::Defects(d)) => d,
            other => panic!("expected defects, got {other:?}"),
        }
    }

    #[test]
    fn import_detects_formats() {
        assert_eq!(Format::detect(CUBE), Format::Obj);
        assert_eq!(Format::detect(TETRA_ASCII), Format::Stl);
        assert!(stl::is_ascii(TETRA_ASCII) && !stl::is_binary(TETRA_ASCII));
        assert_eq!(Format::detect(TETRA_BINARY), Format::Stl);
        assert!(stl::is_binary(TETRA_BINARY));
        assert_eq!(Format::detect(TRUNCATED), Format::Obj);
        assert_eq!(Format::detect(b""), Format::Obj);
        assert_eq!(Format::detect(b"  \n solid x\nendsolid x\n"), Format::Obj);
        assert_eq!(Format::detect(b"ply\nformat ascii 1.0\n"), Format::Ply);
    }

    #[test]
    fn import_reads_the_cube() {
        let mesh = read(CUBE).unwrap();
        assert_solid(&mesh);
        assert_eq!(mesh.triangles.len(), 12);
        assert_eq!(mesh.positions.len(), 8);
        assert!((mesh.volume() - 1.0).abs() < 1e-12);
        assert_eq!(mesh.euler_characteristic(), 2);
    }

    #[test]
    fn import_angle_weighted_normal_of_a_cube_corner_is_the_diagonal() {
        let mesh = read(CUBE).unwrap();
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let expected = (*p * 2.0 - 1.0) / 3f64.sqrt();
            assert!((*n - expected).length() < 1e-12, "{p} {n}");
        }
    }

    #[test]
    fn import_welds_stl_corners() {
        for bytes in [TETRA_ASCII, TETRA_BINARY] {
            let raw = parse_stl(bytes).unwrap();
            assert_eq!(raw.positions.len(), 12);
            let mesh = read(bytes).unwrap();
            assert_solid(&mesh);
            assert_eq!(mesh.positions.len(), 4);
            assert_eq!(mesh.triangles.len(), 4);
            assert!((mesh.volume() - 1.0 / 6.0).abs() < 1e-12);
            assert_eq!(mesh.euler_characteristic(), 2);
        }
    }

    #[test]
    fn import_welds_negative_zero_with_zero() {
        let text = TETRA_ASCII.to_vec();
        let text = String::from_utf8(text)
            .unwrap()
            .replacen("vertex 0 0 0", "vertex -0 0 -0", 1);
        let mesh = read(text.as_bytes()).unwrap();
        assert_eq!(mesh.positions.len(), 4);
    }

    #[test]
    fn import_turns_an_inside_out_cube_over() {
        let inward = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
            f 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 3 7 8 4\nf 4 8 5 1\nf 6 7 3 2\n";
        let raw = parse_obj(inward).unwrap();
        let before = Mesh {
            positions: raw.positions,
            normals: Vec::new(),
            triangles: raw.triangles,
        };
        assert!(before.volume() < 0.0);
        let mesh = read(inward).unwrap();
        assert_solid(&mesh);
        assert!((mesh.volume() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn import_reads_negative_indices_and_file_normals() {
        // A tetrahedron with relative indices and one `vn` per face (split normals).
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
            vn 0 0 -1\nvn 0 -1 0\nvn -1 0 0\nvn 1 1 1\n\
            f -4//-4 -2//-4 -3//-4\nf 1//2 2//2 4//2\nf -4//3 -1//3 -2//3\nf 2//4 3//4 4//4\n";
        let raw = parse_obj(text).unwrap();
        assert_eq!(
            raw.triangles,
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
        );
        assert!(raw.normals.is_some());
        let mesh = read(text).unwrap();
        assert_solid(&mesh);
        // The origin's normal is the sum of its three faces', (−1, −1, −1)/√3.
        let origin = mesh
            .positions
            .iter()
            .position(|p| *p == DVec3::ZERO)
            .unwrap();
        let n = mesh.normals[origin];
        assert!((n - DVec3::splat(-1.0 / 3f64.sqrt())).length() < 1e-12);
        // The apex (0, 0, 1): faces y = 0, x = 0 and the slanted one.
        let apex = mesh.positions.iter().position(|p| *p == DVec3::Z).unwrap();
        let sum = DVec3::new(0.0, -1.0, 0.0) + DVec3::new(-1.0, 0.0, 0.0) + DVec3::ONE.normalize();
        assert!((mesh.normals[apex] - sum.normalize()).length() < 1e-12);
        // Normals are the file's, not computed: they differ from the angle-weighted ones there.
        let computed = angle_weighted_normals(&mesh.positions, &mesh.triangles);
        assert!((computed[apex] - mesh.normals[apex]).length() > 1e-3);
    }

    #[test]
    fn import_falls_back_to_computed_normals() {
        // One corner without a normal.
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\n\
            f 1//1 3//1 2\nf 1//1 2//1 4//1\nf 1//1 4//1 3//1\nf 2//1 3//1 4//1\n";
        assert!(parse_obj(text).unwrap().normals.is_none());
        let mesh = read(text).unwrap();
        let computed = angle_weighted_normals(&mesh.positions, &mesh.triangles);
        assert_eq!(mesh.normals, computed);
        // Every corner has a normal, but they all point along z: inside at some vertex.
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\n\
            f 1//1 3//1 2//1\nf 1//1 2//1 4//1\nf 1//1 4//1 3//1\nf 2//1 3//1 4//1\n";
        assert!(parse_obj(text).unwrap().normals.is_some());
        let mesh = read(text).unwrap();
        assert_eq!(mesh.normals, computed);
    }

    #[test]
    fn import_reports_open_edges() {
        let d = defects(OPEN);
        assert_eq!(
            d,
            MeshDefects {
                open_edges: 4,
                ..MeshDefects::default()
            }
        );
        let message = format!("{}", ReadError::Defects(d));
        assert_eq!(message, "the mesh is not a closed solid: 4 open edges");
    }

    #[test]
    fn import_reports_non_manifold_edges() {
        let d = defects(NON_MANIFOLD);
        assert_eq!(
            d,
            MeshDefects {
                open_edges: 2,
                non_manifold_edges: 1,
                ..MeshDefects::default()
            }
        );
        let message = format!("{d}");
        assert!(message.contains("2 open edges"), "{message}");
        assert!(
            message.contains("1 edge shared by more than two triangles"),
            "{message}"
        );
    }

    #[test]
    fn import_reports_a_turned_face() {
        let d = defects(FLIPPED);
        assert_eq!(
            d,
            MeshDefects {
                inconsistent_edges: 4,
                ..MeshDefects::default()
            }
        );
        assert!(format!("{d}").contains("4 inconsistently oriented edges"));
    }

    #[test]
    fn import_reports_a_degenerate_triangle() {
        let d = defects(DEGENERATE);
        assert_eq!(
            d,
            MeshDefects {
                degenerate_triangles: 1,
                ..MeshDefects::default()
            }
        );
        assert_eq!(
            format!("{d}"),
            "the mesh is not a closed solid: 1 degenerate triangle"
        );
    }

    #[test]
    fn import_counts_a_non_manifold_vertex() {
        // Two tetrahedra that share only vertex 0.
        let raw = parse_stl(TETRA_ASCII).unwrap();
        let mut positions = raw.positions.clone();
        positions.extend(raw.positions.iter().map(|p| -*p));
        let mut triangles = raw.triangles.clone();
        triangles.extend(
            raw.triangles
                .iter()
                .map(|t| [t[0] + 12, t[2] + 12, t[1] + 12]),
        );
        let mut bytes = Vec::new();
        for p in &positions {
            bytes.extend_from_slice(format!("v {} {} {}\n", p.x, p.y, p.z).as_bytes());
        }
        for t in &triangles {
            let [a, b, c] = t.map(|i| i + 1);
            bytes.extend_from_slice(format!("f {a} {b} {c}\n").as_bytes());
        }
        let d = defects(&bytes);
        assert_eq!(
            d,
            MeshDefects {
                non_manifold_vertices: 1,
                ..MeshDefects::default()
            }
        );
        assert!(format!("{d}").contains("1 non-manifold vertex"));
    }

    #[test]
    fn import_validate_counts_bad_triangles() {
        let positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let d = validate(&positions, &[[0, 1, 1], [0, 1, 7]]).unwrap_err();
        assert_eq!(d.degenerate_triangles, 2);
        assert_eq!(d.open_edges, 0);
        assert!(validate(&positions, &[]).is_ok());
        assert_eq!(
            format!("{d}"),
            "the mesh is not a closed solid: 2 degenerate triangles"
        );
    }

    #[test]
    fn import_reports_truncated_binary_stl() {
        let err = read(TRUNCATED).unwrap_err();
        assert_eq!(
            err,
            ReadError::Truncated {
                expected_bytes: 284,
                got_bytes: 150
            }
        );
        assert!(format!("{err}").contains("truncated"));
        // Shorter than the header.
        assert_eq!(
            parse_stl(&TETRA_BINARY[..50]).unwrap_err(),
            ReadError::Truncated {
                expected_bytes: 84,
                got_bytes: 50
            }
        );
        // One byte too many.
        let mut long = TETRA_BINARY.to_vec();
        long.push(0);
        assert!(matches!(
            read(&long),
            Err(ReadError::Truncated {
                expected_bytes: 284,
                got_bytes: 285
            })
        ));
    }

    #[test]
    fn import_reports_truncated_ascii_stl() {
        let err = read(TRUNCATED_ASCII).unwrap_err();
        assert_eq!(
            err,
            ReadError::Parse {
                line: 18,
                reason: "the file ends in the middle of a facet"
            }
        );
        assert_eq!(
            format!("{err}"),
            "line 18: the file ends in the middle of a facet"
        );
        let no_end = b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n \
            vertex 0 1 0\n endloop\n endfacet\n";
        assert!(matches!(
            parse_stl(no_end),
            Err(ReadError::Parse { line: 8, reason }) if reason.contains("endsolid")
        ));
        let four = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
            vertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid\n";
        assert!(matches!(
            parse_stl(four),
            Err(ReadError::Parse { line: 7, .. })
        ));
        let bad_number = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n";
        assert!(matches!(
            parse_stl(bad_number),
            Err(ReadError::Parse { line: 4, .. })
        ));
    }

    #[test]
    fn import_reports_garbage() {
        let err = read(GARBAGE).unwrap_err();
        assert!(
            matches!(err, ReadError::Truncated { got_bytes: 256, .. }),
            "{err:?}"
        );
        assert!(format!("{err}").contains("binary STL"));
        // Text that is no mesh: no triangles.
        assert_eq!(
            read(b"hello, world\nthis is not a mesh\n"),
            Err(ReadError::Empty)
        );
        assert_eq!(read(b""), Err(ReadError::Empty));
        assert_eq!(format!("{}", ReadError::Empty), "the file has no triangles");
    }

    #[test]
    fn import_reports_bad_indices() {
        let err = read(BAD_INDEX).unwrap_err();
        assert_eq!(err, ReadError::BadIndex { line: 12, index: 9 });
        assert!(format!("{err}").starts_with("line 12: index 9"));
        let zero = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n";
        let err = read(zero).unwrap_err();
        assert_eq!(err, ReadError::BadIndex { line: 4, index: 0 });
        assert!(format!("{err}").contains("index 0"));
        let behind = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n";
        assert_eq!(
            read(behind),
            Err(ReadError::BadIndex { line: 4, index: -4 })
        );
        let normal = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n";
        assert_eq!(read(normal), Err(ReadError::BadIndex { line: 5, index: 2 }));
        let two = b"v 0 0 0\nv 1 0 0\nf 1 2\n";
        assert!(matches!(read(two), Err(ReadError::Parse { line: 3, .. })));
        let word = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 three\n";
        assert!(matches!(read(word), Err(ReadError::Parse { line: 4, .. })));
    }

    #[test]
    fn import_reports_not_finite_coordinates() {
        let err = read(NAN).unwrap_err();
        assert_eq!(err, ReadError::NotFinite { vertex: 3 });
        assert!(format!("{err}").contains("not a finite number"));
        assert_eq!(
            read(b"v 1e400 0 0\n"),
            Err(ReadError::NotFinite { vertex: 1 })
        );
        // A NaN in a binary STL corner.
        let mut bytes = TETRA_BINARY.to_vec();
        bytes[84 + 12 + 12 + 4..84 + 12 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(read(&bytes), Err(ReadError::NotFinite { vertex: 2 }));
    }

    #[test]
    fn the_readme_states_the_caps_of_mesh_files() {
        let readme = include_str!("../../../../README.md");
        let words = readme.split_whitespace().collect::<Vec<_>>().join(" ");
        let thousands = |n: usize| format!("{},{:03}", n / 1000, n % 1000);
        for said in [
            format!("a mesh file {} MiB", MAX_FILE_BYTES >> 20),
            format!("{} triangles", thousands(MAX_TRIANGLES)),
            format!("{} vertices", thousands(MAX_VERTICES)),
        ] {
            assert!(words.contains(&said), "README.md does not say {said:?}");
        }
    }

    #[test]
    fn import_caps_sizes() {
        // A binary STL that claims too many triangles: refused before anything is allocated.
        let count = MAX_TRIANGLES + 1;
        let mut bytes = vec![b' '; 84 + 50 * count];
        bytes[80..84].copy_from_slice(&(count as u32).to_le_bytes());
        let err = read(&bytes).unwrap_err();
        assert_eq!(
            err,
            ReadError::TooLarge {
                what: "triangles",
                count,
                max: MAX_TRIANGLES
            }
        );
        assert!(format!("{err}").contains("more than 200000 triangles"));
        // Too many OBJ vertices.
        let mut text = Vec::new();
        for _ in 0..=MAX_VERTICES {
            text.extend_from_slice(b"v 0 0 0\n");
        }
        assert!(matches!(
            parse_obj(&text),
            Err(ReadError::TooLarge {
                what: "vertices",
                ..
            })
        ));
        // Too many triangles from one polygon.
        let mut polygon = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf".to_vec();
        for k in 0..MAX_TRIANGLES + 2 {
            polygon.extend_from_slice(if k % 2 == 0 { b" 1" } else { b" 2" });
        }
        polygon.extend_from_slice(b" 3\n");
        assert!(matches!(
            parse_obj(&polygon),
            Err(ReadError::TooLarge {
                what: "triangles",
                ..
            })
        ));
    }

    #[test]
    #[cfg(not(target_arch = "wasm32"))]
    fn import_caps_the_file_size() {
        let bytes = vec![0u8; MAX_FILE_BYTES + 1];
        assert!(matches!(
            read(&bytes),
            Err(ReadError::TooLarge { what: "bytes", .. })
        ));
    }

    #[test]
    fn import_reads_polygons_and_ignores_other_statements() {
        let text = b"# a square pyramid\r\no pyramid\r\nv 0 0 0 1\r\nv 1 0 0\r\nv 1 1 0\r\n\
            v 0 1 0\r\nv 0.5 0.5 1 0.2 0.3 0.4\r\nvt 0 0\r\nl 1 2\r\np 1\r\nfoo bar\r\n\
            f 1/1 4/1 3/1 2/1 # the base\r\nf 1 2 5\r\nf 2 3 5\r\nf 3 4 5\r\nf 4 1 5\r\n";
        let raw = parse_obj(text).unwrap();
        assert_eq!(raw.triangles.len(), 6);
        assert_eq!(raw.triangles[0], [0, 3, 2]);
        assert_eq!(raw.triangles[1], [0, 2, 1]);
        let mesh = read(text).unwrap();
        assert_solid(&mesh);
        assert!((mesh.volume() - 1.0 / 3.0).abs() < 1e-12);
    }

    /// A random byte string: text of mesh keywords and numbers, or raw bytes.
    fn random_input(rng: &mut Rng) -> Vec<u8> {
        const WORDS: [&str; 16] = [
            "v", "vn", "f", "solid", "facet", "normal", "outer", "loop", "vertex", "endloop",
            "endfacet", "endsolid", "1", "-1", "0.5", "1/2/3",
        ];
        let len = rng.int(0, 300);
        if rng.int(0, 1) == 0 {
            (0..len).map(|_| rng.next_u64() as u8).collect()
        } else {
            let mut out = Vec::new();
            for _ in 0..len / 3 {
                let word = WORDS[rng.int(0, WORDS.len() - 1)];
                out.extend_from_slice(word.as_bytes());
                out.push(if rng.int(0, 3) == 0 { b'\n' } else { b' ' });
            }
            out
        }
    }

    fn mutate(rng: &mut Rng, good: &[u8]) -> Vec<u8> {
        let mut bytes = good.to_vec();
        match rng.int(0, 3) {
            0 => bytes.truncate(rng.int(0, good.len())),
            1 => {
                for _ in 0..rng.int(1, 4) {
                    let at = rng.int(0, bytes.len() - 1);
                    bytes[at] = rng.next_u64() as u8;
                }
            }
            2 => {
                const LINES: [&str; 8] = [
                    "f 1 2 3\n",
                    "f -1 -2 -9\n",
                    "v 1 2\n",
                    "vn 0 0 0\n",
                    "f 1//1 2//1 3//1\n",
                    "v nan inf 0\n",
                    "f 1 1 1 1\n",
                    "endsolid\n",
                ];
                let at = rng.int(0, bytes.len());
                let line = LINES[rng.int(0, LINES.len() - 1)];
                bytes.splice(at..at, line.bytes());
            }
            _ => {
                // Swap two digits, which keeps the text parseable but moves vertices.
                let digits: Vec<usize> = (0..bytes.len())
                    .filter(|&i| bytes[i].is_ascii_digit())
                    .collect();
                if digits.len() >= 2 {
                    let a = digits[rng.int(0, digits.len() - 1)];
                    let b = digits[rng.int(0, digits.len() - 1)];
                    bytes.swap(a, b);
                }
            }
        }
        bytes
    }

    #[test]
    fn import_never_panics_on_random_input() {
        let mut rng = Rng::new(11);
        let goods = [CUBE, TETRA_ASCII, TETRA_BINARY, DEGENERATE, NON_MANIFOLD];
        let (mut ok, mut err) = (0, 0);
        for k in 0..600 {
            let bytes = if k % 3 == 0 {
                random_input(&mut rng)
            } else {
                let good = goods[rng.int(0, goods.len() - 1)];
                mutate(&mut rng, good)
            };
            match read(&bytes) {
                Ok(mesh) => {
                    ok += 1;
                    mesh.check_closed_manifold().unwrap();
                    assert!(mesh.volume() >= 0.0);
                    assert_eq!(mesh.normals.len(), mesh.positions.len());
                }
                Err(e) => {
                    err += 1;
                    assert!(!format!("{e}").is_empty());
                }
            }
        }
        // Both outcomes happen: the mutations are neither all harmless nor all fatal.
        assert!(ok > 10 && err > 10, "{ok} ok, {err} errors");
    }
}
