//! PLY (Turk's polygon file format). Written binary little-endian: vertices with `float` position
//! and normal, faces as a `uchar` count and `int` indices, counter-clockwise from outside. Read in
//! any of its three encodings (`ascii`, `binary_little_endian`, `binary_big_endian`): the `vertex`
//! element's `x y z` (and `nx ny nz` where present), the `face` element's index list (polygons
//! split into fans), every other element and property skipped.

use alloc::format;
use alloc::vec::Vec;

use glam::DVec3;

use super::read::{MAX_TRIANGLES, MAX_VERTICES, too_many};
use super::{Mesh, RawMesh, ReadError};

/// The binary PLY of `mesh`. Vertices without a normal get a zero one.
#[must_use]
pub fn write_ply(mesh: &Mesh) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by bezsolid\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    let mut out =
        Vec::with_capacity(header.len() + 24 * mesh.positions.len() + 13 * mesh.triangles.len());
    out.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        let n = mesh.normals.get(i).copied().unwrap_or_default();
        for x in p.to_array().into_iter().chain(n.to_array()) {
            out.extend_from_slice(&(x as f32).to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        out.push(3);
        for &i in t {
            out.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    out
}

/// Whether the bytes start with PLY's magic line, `ply` and a line end.
pub(crate) fn starts_with_magic(bytes: &[u8]) -> bool {
    bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n")
}

/// The longest header read: far beyond any real file's, so that a file without `end_header` is not
/// searched to its end.
const MAX_HEADER_BYTES: usize = 64 << 10;

/// A scalar type of PLY, with its size in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

/// A property of an element: a scalar, or a list with its count type and item type.
#[derive(Clone, Debug, PartialEq)]
struct Property {
    name: Vec<u8>,
    kind: Scalar,
    list: Option<Scalar>,
}

#[derive(Clone, Debug, PartialEq)]
struct Element {
    name: Vec<u8>,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Where the values of the body come from: whitespace-separated numbers (ASCII, with line numbers
/// for errors) or packed scalars.
struct Body<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
    line: usize,
}

impl Body<'_> {
    fn truncated() -> ReadError {
        ReadError::Malformed {
            reason: "the PLY body ends before the elements its header declares",
        }
    }

    /// The next value of type `kind`, as `f64` (every PLY scalar fits exactly).
    fn value(&mut self, kind: Scalar) -> Result<f64, ReadError> {
        if self.encoding == Encoding::Ascii {
            return self.token();
        }
        let n = kind.size();
        let raw = self
            .bytes
            .get(self.at..self.at + n)
            .ok_or_else(Self::truncated)?;
        self.at += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.encoding == Encoding::Big {
            b[..n].reverse();
        }
        Ok(match kind {
            Scalar::I8 => f64::from(i8::from_le_bytes([b[0]])),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// The next ASCII number.
    fn token(&mut self) -> Result<f64, ReadError> {
        while let Some(&c) = self.bytes.get(self.at) {
            if c == b'\n' {
                self.line += 1;
            }
            if !c.is_ascii_whitespace() {
                break;
            }
            self.at += 1;
        }
        let start = self.at;
        while self
            .bytes
            .get(self.at)
            .is_some_and(|c| !c.is_ascii_whitespace())
        {
            self.at += 1;
        }
        if start == self.at {
            return Err(Self::truncated());
        }
        super::read::number(&self.bytes[start..self.at]).ok_or(ReadError::Parse {
            line: self.line,
            reason: "a PLY value is not a number",
        })
    }

    /// A list's length: a whole number no larger than `max`.
    fn count(&mut self, kind: Scalar, max: usize) -> Result<usize, ReadError> {
        let n = self.value(kind)?;
        if libm::trunc(n) != n || !(0.0..=max as f64).contains(&n) {
            return Err(ReadError::Malformed {
                reason: "a PLY list has a negative, fractional or huge length",
            });
        }
        Ok(n as usize)
    }
}

/// Parses a PLY file (see the module documentation): positions, per-vertex normals when the
/// vertices carry `nx ny nz`, and triangles (polygons split into fans from their first corner).
///
/// # Errors
///
/// [`ReadError::Parse`] for a header that does not follow the format (with its line),
/// [`ReadError::Malformed`] for a body that does not, [`ReadError::BadIndex`] for a face index past
/// the vertices, [`ReadError::NotFinite`], or [`ReadError::TooLarge`] past [`MAX_VERTICES`]
/// vertices or [`MAX_TRIANGLES`] triangles.
pub fn parse_ply(bytes: &[u8]) -> Result<RawMesh, ReadError> {
    let (encoding, elements, body_start, header_lines) = header(bytes)?;
    let mut body = Body {
        bytes,
        at: body_start,
        encoding,
        line: header_lines + 1,
    };
    let mut positions = Vec::new();
    let mut normals: Option<Vec<DVec3>> = None;
    let mut triangles = Vec::new();
    for element in &elements {
        // An element without properties takes no bytes, however many it declares.
        if element.properties.is_empty() {
            continue;
        }
        let is_vertex = element.name == b"vertex";
        let is_face = element.name == b"face";
        let find = |name: &[u8]| element.properties.iter().position(|p| p.name == name);
        let xyz = [find(b"x"), find(b"y"), find(b"z")];
        let nxyz = [find(b"nx"), find(b"ny"), find(b"nz")];
        if is_vertex {
            if !positions.is_empty() || normals.is_some() {
                return Err(ReadError::Parse {
                    line: 0,
                    reason: "a PLY file has one vertex element",
                });
            }
            if xyz.iter().any(Option::is_none) {
                return Err(ReadError::Parse {
                    line: 0,
                    reason: "PLY vertices need x, y and z properties",
                });
            }
            if element.count > MAX_VERTICES {
                return Err(ReadError::TooLarge {
                    what: "vertices",
                    count: element.count,
                    max: MAX_VERTICES,
                });
            }
            if nxyz.iter().all(Option::is_some) {
                normals = Some(Vec::with_capacity(element.count));
            }
            positions.reserve(element.count);
        }
        let indices = element.properties.iter().position(|p| {
            p.list.is_some() && (p.name == b"vertex_indices" || p.name == b"vertex_index")
        });
        if is_face && indices.is_none() {
            return Err(ReadError::Parse {
                line: 0,
                reason: "PLY faces need a vertex_indices list",
            });
        }
        let mut values = [0.0f64; 6];
        let mut corners: Vec<u32> = Vec::new();
        for _ in 0..element.count {
            for (k, property) in element.properties.iter().enumerate() {
                match property.list {
                    Some(count_kind) => {
                        let n = body.count(count_kind, MAX_VERTICES)?;
                        let keep = is_face && Some(k) == indices;
                        corners.clear();
                        for _ in 0..n {
                            let v = body.value(property.kind)?;
                            if keep {
                                if libm::trunc(v) != v || !(0.0..u32::MAX as f64).contains(&v) {
                                    return Err(ReadError::BadIndex {
                                        line: body.line,
                                        index: v as i64,
                                    });
                                }
                                corners.push(v as u32);
                            }
                        }
                        if keep {
                            if n < 3 {
                                return Err(ReadError::Malformed {
                                    reason: "a PLY face has fewer than three vertices",
                                });
                            }
                            for w in 1..n - 1 {
                                if triangles.len() == MAX_TRIANGLES {
                                    return Err(too_many("triangles", MAX_TRIANGLES));
                                }
                                triangles.push([corners[0], corners[w], corners[w + 1]]);
                            }
                        }
                    }
                    None => {
                        let v = body.value(property.kind)?;
                        if let Some(slot) = xyz.iter().chain(&nxyz).position(|&p| p == Some(k)) {
                            values[slot] = v;
                        }
                    }
                }
            }
            if is_vertex {
                let p = DVec3::new(values[0], values[1], values[2]);
                positions.push(p);
                if !p.is_finite() {
                    return Err(ReadError::NotFinite {
                        vertex: positions.len(),
                    });
                }
                if let Some(normals) = &mut normals {
                    let n = DVec3::new(values[3], values[4], values[5]);
                    normals.push(if n.is_finite() {
                        n.normalize_or_zero()
                    } else {
                        DVec3::ZERO
                    });
                }
            }
        }
    }
    if let Some((triangle, &index)) = triangles.iter().enumerate().find_map(|(t, tri)| {
        tri.iter()
            .find(|&&i| i as usize >= positions.len())
            .map(|i| (t, i))
    }) {
        return Err(ReadError::TriangleIndex { triangle, index });
    }
    Ok(RawMesh {
        positions,
        normals,
        triangles,
    })
}

/// The header of a PLY file: its encoding, its elements, where the body starts, and how many
/// lines the header has.
fn header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, usize, usize), ReadError> {
    let bad = |line: usize, reason: &'static str| ReadError::Parse { line, reason };
    if !starts_with_magic(bytes) {
        return Err(bad(1, "a PLY file starts with the line `ply`"));
    }
    let end = bytes
        .windows(10)
        .take(MAX_HEADER_BYTES)
        .position(|w| w == b"end_header")
        .ok_or(bad(1, "the PLY header has no `end_header` line"))?;
    // The body starts after the line end that follows `end_header`.
    let mut body = end + 10;
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) == Some(&b'\n') {
        body += 1;
    }
    let text =
        core::str::from_utf8(&bytes[..end]).map_err(|_| bad(1, "the PLY header is not text"))?;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut lines = 0;
    for (k, line) in text.lines().enumerate() {
        lines = k + 2;
        let line_no = k + 1;
        let mut words = line.split_ascii_whitespace();
        match words.next() {
            Some("format") => {
                encoding = Some(match words.next() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::Little,
                    Some("binary_big_endian") => Encoding::Big,
                    _ => return Err(bad(line_no, "unknown PLY format")),
                });
            }
            Some("element") => {
                let name = words
                    .next()
                    .ok_or(bad(line_no, "an element needs a name"))?;
                // Parsed as u64 on every target; a count past usize saturates (and is refused
                // at the caps where it matters).
                let count: u64 = words
                    .next()
                    .and_then(|c| c.parse().ok())
                    .ok_or(bad(line_no, "an element needs a count"))?;
                let count = usize::try_from(count).unwrap_or(usize::MAX);
                elements.push(Element {
                    name: name.as_bytes().into(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or(bad(line_no, "a property before any element"))?;
                let first = words
                    .next()
                    .ok_or(bad(line_no, "a property needs a type"))?;
                let unknown = bad(line_no, "unknown PLY property type");
                let (list, kind) = if first == "list" {
                    let count = words
                        .next()
                        .and_then(Scalar::parse)
                        .ok_or(unknown.clone())?;
                    if matches!(count, Scalar::F32 | Scalar::F64) {
                        return Err(bad(line_no, "a PLY list count must be an integer type"));
                    }
                    let item = words.next().and_then(Scalar::parse).ok_or(unknown)?;
                    (Some(count), item)
                } else {
                    (None, Scalar::parse(first).ok_or(unknown)?)
                };
                let name = words
                    .next()
                    .ok_or(bad(line_no, "a property needs a name"))?;
                element.properties.push(Property {
                    name: name.as_bytes().into(),
                    kind,
                    list,
                });
            }
            Some("ply" | "comment" | "obj_info") | None => {}
            Some(_) => return Err(bad(line_no, "unknown PLY header line")),
        }
    }
    let encoding = encoding.ok_or(bad(2, "the PLY header has no `format` line"))?;
    Ok((encoding, elements, body, lines))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::tests::test_mesh;
    use crate::mesh::{Format, ReadError};
    use alloc::string::ToString;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// `f32` positions and normals, and triangles, of a binary PLY as written here; `None` if
    /// malformed.
    /// Vertices (position then normal) and triangles.
    pub(crate) type Ply = (Vec<[f32; 6]>, Vec<[u32; 3]>);

    pub(crate) fn read_ply(bytes: &[u8]) -> Option<Ply> {
        let end = b"end_header\n";
        let split = bytes.windows(end.len()).position(|w| w == end)? + end.len();
        let header = core::str::from_utf8(&bytes[..split]).ok()?;
        let count = |name: &str| -> Option<usize> {
            header
                .lines()
                .find_map(|l| l.strip_prefix(name))?
                .trim()
                .parse()
                .ok()
        };
        let (nv, nf) = (count("element vertex ")?, count("element face ")?);
        let body = &bytes[split..];
        if body.len() != 24 * nv + 13 * nf {
            return None;
        }
        let f = |at: usize| f32::from_le_bytes(body[at..at + 4].try_into().unwrap());
        let vertices = (0..nv)
            .map(|v| core::array::from_fn(|k| f(24 * v + 4 * k)))
            .collect();
        let mut faces = Vec::with_capacity(nf);
        for t in 0..nf {
            let at = 24 * nv + 13 * t;
            if body[at] != 3 {
                return None;
            }
            faces.push(core::array::from_fn(|k| {
                i32::from_le_bytes(body[at + 1 + 4 * k..at + 5 + 4 * k].try_into().unwrap()) as u32
            }));
        }
        Some((vertices, faces))
    }

    #[test]
    fn ply_parses_back_to_the_same_mesh() {
        let mesh = test_mesh();
        let (vertices, faces) = read_ply(&write_ply(&mesh)).unwrap();
        assert_eq!(faces, mesh.triangles);
        assert_eq!(vertices.len(), mesh.positions.len());
        for (v, (p, n)) in vertices
            .iter()
            .zip(mesh.positions.iter().zip(&mesh.normals))
        {
            let want: [f32; 6] =
                core::array::from_fn(|k| if k < 3 { p[k] as f32 } else { n[k - 3] as f32 });
            assert_eq!(*v, want);
        }
    }

    /// A mesh that bounds a solid with no flat triangle (the marching-cubes test mesh has some
    /// where samples are exactly zero, which reading rejects).
    fn solid_mesh() -> Mesh {
        crate::esc::examples::Example::Icosphere.mesh()
    }

    const CUBE_ASCII: &str = "ply\nformat ascii 1.0\ncomment a unit cube of quads\n\
        element vertex 8\nproperty float x\nproperty float y\nproperty float z\n\
        element face 6\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
        4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

    #[test]
    fn ply_reads_what_it_writes() {
        let mesh = solid_mesh();
        let back = Format::Ply.read(&write_ply(&mesh)).unwrap();
        assert_eq!(back.triangles.len(), mesh.triangles.len());
        assert_eq!(back.positions.len(), mesh.positions.len());
        // f32 in the file: the same solid to single precision, with the file's normals.
        assert!((back.volume() - mesh.volume()).abs() < 1e-5 * mesh.volume());
        for (p, n) in back.positions.iter().zip(&back.normals) {
            let k = mesh
                .positions
                .iter()
                .position(|q| (*q - *p).length() < 1e-5)
                .unwrap();
            assert!((mesh.normals[k] - *n).length() < 1e-5);
        }
    }

    #[test]
    fn ply_reads_ascii_quads_and_big_endian_doubles() {
        let cube = Format::Ply.read(CUBE_ASCII.as_bytes()).unwrap();
        assert_eq!(cube.triangles.len(), 12);
        assert!((cube.volume() - 1.0).abs() < 1e-12);
        // The same cube, binary big-endian with doubles, a ushort count and an extra element.
        let mut big = b"ply\r\nformat binary_big_endian 1.0\r\nelement vertex 8\r\n\
            property double x\r\nproperty double y\r\nproperty double z\r\nproperty uchar red\r\n\
            element face 6\r\nproperty list ushort uint vertex_indices\r\n\
            element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
            .to_vec();
        let raw = Format::Ply.parse(CUBE_ASCII.as_bytes()).unwrap();
        for p in &raw.positions {
            for x in p.to_array() {
                big.extend_from_slice(&x.to_be_bytes());
            }
            big.push(200);
        }
        for face in CUBE_ASCII.lines().skip(18) {
            let ids: Vec<u32> = face
                .split(' ')
                .skip(1)
                .map(|t| t.parse().unwrap())
                .collect();
            big.extend_from_slice(&(ids.len() as u16).to_be_bytes());
            for i in ids {
                big.extend_from_slice(&i.to_be_bytes());
            }
        }
        big.extend_from_slice(&[0, 0, 0, 1, 0, 0, 0, 2]);
        assert_eq!(Format::detect(&big), Format::Ply);
        let again = crate::mesh::read(&big).unwrap();
        assert_eq!(again.triangles, cube.triangles);
        assert_eq!(again.positions, cube.positions);
    }

    #[test]
    fn ply_errors_are_typed_and_bounded() {
        let cube = CUBE_ASCII.as_bytes();
        let parse = |text: &str| Format::Ply.parse(text.as_bytes());
        assert!(matches!(
            Format::Ply.parse(&cube[..cube.len() - 30]),
            Err(ReadError::Malformed { .. })
        ));
        assert!(matches!(
            parse("ply\nformat ascii 1.0\nelement vertex 1\n"),
            Err(ReadError::Parse { .. })
        ));
        assert!(matches!(
            parse("ply\nformat ebcdic 1.0\nend_header\n"),
            Err(ReadError::Parse { line: 2, .. })
        ));
        assert!(matches!(
            parse(
                "ply\nformat ascii 1.0\nelement vertex 9999999999\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
            ),
            Err(ReadError::TooLarge {
                what: "vertices",
                ..
            })
        ));
        // A huge element without properties takes no time.
        let nothing = parse(
            "ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\nend_header\n",
        )
        .unwrap();
        assert!(nothing.triangles.is_empty());
        assert_eq!(crate::mesh::from_raw(&nothing), Err(ReadError::Empty));
        let bad_index = CUBE_ASCII.replace("4 3 0 4 7", "4 3 0 4 8");
        assert!(matches!(
            parse(&bad_index),
            Err(ReadError::TriangleIndex { index: 8, .. })
        ));
        let nan = CUBE_ASCII.replace("1 1 1\n", "1 nan 1\n");
        assert_eq!(parse(&nan), Err(ReadError::NotFinite { vertex: 7 }));
        let word = CUBE_ASCII.replace("1 1 1\n", "1 one 1\n");
        assert!(matches!(parse(&word), Err(ReadError::Parse { .. })));
        let huge_list = CUBE_ASCII.replace("4 3 0 4 7", "4000000000 3 0 4 7");
        assert!(matches!(
            parse(&huge_list),
            Err(ReadError::Malformed { .. })
        ));
    }

    #[test]
    fn formats_are_named_written_and_read_as_one() {
        let mesh = solid_mesh();
        for format in Format::ALL {
            assert_eq!(format.to_string().parse::<Format>(), Ok(format));
            let upper = format!("a/b/Model.{}", format.extension().to_uppercase());
            assert_eq!(Format::of_path(&upper), Some(format));
            let file = format.write(&mesh);
            assert_eq!(Format::detect(&file), format);
            let back = format.read(&file).unwrap();
            back.check_closed_manifold().unwrap();
            assert!((back.volume() - mesh.volume()).abs() < 1e-5 * mesh.volume());
        }
        assert_eq!(".ply".parse::<Format>(), Ok(Format::Ply));
        let err = "gltf".parse::<Format>().unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown mesh format `gltf`: the formats are stl, obj and ply"
        );
        assert_eq!(Format::of_path("model"), None);
    }
}
