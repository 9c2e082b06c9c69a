//! STL. Written binary: an 80-byte header, a little-endian `u32` triangle count, then per triangle
//! the facet normal and three corners as `f32` and a zero `u16`; corners are counter-clockwise seen
//! from outside, as STL readers expect. Read binary or ASCII (`solid`, `facet … endfacet` blocks,
//! `endsolid`).

use alloc::vec::Vec;

use glam::DVec3;

use super::read::{MAX_TRIANGLES, three_numbers, too_many};
use super::{Mesh, RawMesh, ReadError};

/// The header: it must not begin with `solid`, which marks ASCII STL.
const HEADER: &[u8] = b"binary STL written by bezsolid";

/// The binary STL of `mesh`. Facet normals are the triangles' own (from their corners), which is
/// what STL means by them; degenerate triangles get a zero normal.
#[must_use]
pub fn write_stl(mesh: &Mesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    out.extend_from_slice(HEADER);
    out.resize(80, b' ');
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        for p in [normal, a, b, c] {
            push_vec3(&mut out, p);
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}

fn push_vec3(out: &mut Vec<u8>, p: DVec3) {
    for x in p.to_array() {
        out.extend_from_slice(&(x as f32).to_le_bytes());
    }
}

/// Parses an STL file, binary or ASCII. Binary when its length matches its triangle count, ASCII
/// when it starts with `solid`, otherwise binary (and then truncated). Facet normals are ignored:
/// they are flat, and [`read`](super::read) computes smooth ones. Corners are not welded.
///
/// # Errors
///
/// [`ReadError::Truncated`] for a binary file of the wrong length, [`ReadError::Parse`] with the
/// line for malformed ASCII (including a file that ends before `endsolid`),
/// [`ReadError::NotFinite`], or [`ReadError::TooLarge`] past [`MAX_TRIANGLES`] triangles.
pub fn parse_stl(bytes: &[u8]) -> Result<RawMesh, ReadError> {
    match binary_stl_count(bytes) {
        Some(count) if binary_stl_len(count) == bytes.len() as u64 => {
            parse_binary_stl(bytes, count)
        }
        _ if starts_with_solid(bytes) => parse_ascii_stl(bytes),
        count => Err(ReadError::Truncated {
            expected_bytes: count.map_or(84, binary_stl_len),
            got_bytes: bytes.len() as u64,
        }),
    }
}

/// Whether the bytes are a binary STL: at least 84 bytes long and exactly `84 + 50·count` bytes,
/// `count` being the little-endian `u32` at offset 80.
pub(crate) fn is_binary(bytes: &[u8]) -> bool {
    binary_stl_count(bytes).is_some_and(|count| binary_stl_len(count) == bytes.len() as u64)
}

/// Whether the bytes look like an ASCII STL: `solid` first (after white space), `facet` later.
pub(crate) fn is_ascii(bytes: &[u8]) -> bool {
    starts_with_solid(bytes) && bytes.windows(5).any(|w| w.eq_ignore_ascii_case(b"facet"))
}

/// The triangle count of a binary STL header, if the file is long enough to have one.
fn binary_stl_count(bytes: &[u8]) -> Option<u32> {
    match bytes.get(80..84)? {
        &[a, b, c, d] => Some(u32::from_le_bytes([a, b, c, d])),
        _ => None,
    }
}

fn binary_stl_len(count: u32) -> u64 {
    84 + 50 * u64::from(count)
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace());
    start
        .and_then(|s| bytes.get(s..s + 5))
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
}

/// Whether the bytes hold control characters that text does not (binary data, UTF-16, …), at a
/// length where a binary STL header fits.
pub(crate) fn looks_binary(bytes: &[u8]) -> bool {
    bytes.len() >= 84
        && bytes
            .iter()
            .any(|&b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0c))
}

fn parse_binary_stl(bytes: &[u8], count: u32) -> Result<RawMesh, ReadError> {
    let count = count as usize;
    if count > MAX_TRIANGLES {
        return Err(ReadError::TooLarge {
            what: "triangles",
            count,
            max: MAX_TRIANGLES,
        });
    }
    let body = bytes.get(84..).unwrap_or_default();
    let mut positions = Vec::with_capacity(3 * count);
    let mut triangles = Vec::with_capacity(count);
    for facet in body.chunks_exact(50).take(count) {
        // 12 bytes of normal, then three corners of 12 bytes, then the 2-byte attribute.
        let corners = facet.get(12..48).unwrap_or_default();
        for corner in corners.chunks_exact(12) {
            let mut xyz = [0.0f64; 3];
            for (x, b) in xyz.iter_mut().zip(corner.chunks_exact(4)) {
                if let &[b0, b1, b2, b3] = b {
                    *x = f64::from(f32::from_le_bytes([b0, b1, b2, b3]));
                }
            }
            let p = DVec3::from_array(xyz);
            positions.push(p);
            if !p.is_finite() {
                return Err(ReadError::NotFinite {
                    vertex: positions.len(),
                });
            }
        }
        let base = triangles.len() as u32 * 3;
        triangles.push([base, base + 1, base + 2]);
    }
    Ok(RawMesh {
        positions,
        normals: None,
        triangles,
    })
}

/// Where an ASCII STL parse is: the next statement expected.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stl {
    /// Before `solid`.
    Start,
    /// Inside a solid: `facet` or `endsolid`.
    Solid,
    /// After `facet`: `outer loop`.
    Facet,
    /// Inside a loop with this many vertices read.
    Loop(u8),
    /// After `endloop`: `endfacet`.
    EndLoop,
    /// After `endsolid`: nothing, or another `solid`.
    Done,
}

fn parse_ascii_stl(bytes: &[u8]) -> Result<RawMesh, ReadError> {
    let mut positions = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut state = Stl::Start;
    let mut last_line = 1;
    for (k, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = k + 1;
        let mut tokens = line
            .split(u8::is_ascii_whitespace)
            .filter(|t| !t.is_empty());
        let Some(keyword) = tokens.next() else {
            continue;
        };
        last_line = line_no;
        let is = |word: &[u8]| keyword.eq_ignore_ascii_case(word);
        let error = |reason| ReadError::Parse {
            line: line_no,
            reason,
        };
        state = match state {
            Stl::Start | Stl::Done if is(b"solid") => Stl::Solid,
            Stl::Start => return Err(error("an ASCII STL starts with `solid`")),
            Stl::Done => return Err(error("only another `solid` may follow `endsolid`")),
            Stl::Solid if is(b"facet") => {
                if triangles.len() == MAX_TRIANGLES {
                    return Err(too_many("triangles", MAX_TRIANGLES));
                }
                Stl::Facet
            }
            Stl::Solid if is(b"endsolid") => Stl::Done,
            Stl::Solid => return Err(error("expected `facet` or `endsolid`")),
            Stl::Facet
                if is(b"outer")
                    && tokens
                        .next()
                        .is_some_and(|t| t.eq_ignore_ascii_case(b"loop")) =>
            {
                Stl::Loop(0)
            }
            Stl::Facet => return Err(error("expected `outer loop`")),
            Stl::Loop(n) if is(b"vertex") => {
                if n == 3 {
                    return Err(error("a facet has more than three vertices"));
                }
                let p = three_numbers(&mut tokens)
                    .ok_or(error("a vertex needs three numbers: `vertex x y z`"))?;
                positions.push(p);
                if !p.is_finite() {
                    return Err(ReadError::NotFinite {
                        vertex: positions.len(),
                    });
                }
                Stl::Loop(n + 1)
            }
            Stl::Loop(3) if is(b"endloop") => {
                let base = triangles.len() as u32 * 3;
                triangles.push([base, base + 1, base + 2]);
                Stl::EndLoop
            }
            Stl::Loop(_) if is(b"endloop") => {
                return Err(error("a facet needs three vertices"));
            }
            Stl::Loop(_) => return Err(error("expected `vertex` or `endloop`")),
            Stl::EndLoop if is(b"endfacet") => Stl::Solid,
            Stl::EndLoop => return Err(error("expected `endfacet`")),
        };
    }
    let reason = match state {
        Stl::Done => {
            return Ok(RawMesh {
                positions,
                normals: None,
                triangles,
            });
        }
        Stl::Start => "the file is empty",
        Stl::Solid => "the file ends before `endsolid`",
        Stl::Facet | Stl::Loop(_) | Stl::EndLoop => "the file ends in the middle of a facet",
    };
    Err(ReadError::Parse {
        line: last_line,
        reason,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::tests::test_mesh;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// Triangles of a binary STL, as `f32` corners; `None` if the file is malformed.
    pub(crate) fn read_stl(bytes: &[u8]) -> Option<Vec<[[f32; 3]; 3]>> {
        let count = u32::from_le_bytes(bytes.get(80..84)?.try_into().ok()?) as usize;
        if bytes.len() != 84 + 50 * count {
            return None;
        }
        let f = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        Some(
            (0..count)
                .map(|t| {
                    let base = 84 + 50 * t + 12;
                    core::array::from_fn(|v| core::array::from_fn(|k| f(base + 12 * v + 4 * k)))
                })
                .collect(),
        )
    }

    #[test]
    fn stl_parses_back_to_the_same_triangles() {
        let mesh = test_mesh();
        let bytes = write_stl(&mesh);
        assert!(!bytes.starts_with(b"solid"));
        let tris = read_stl(&bytes).unwrap();
        assert_eq!(tris.len(), mesh.triangle_count());
        for (t, tri) in tris.iter().enumerate() {
            let want = mesh.corners(t).map(|p| p.as_vec3().to_array());
            assert_eq!(*tri, want);
        }
        // Each facet normal is the unit normal of its corners, pointing away from the ball's centre.
        let centre = mesh.positions.iter().sum::<DVec3>() / mesh.positions.len() as f64;
        for (t, tri) in tris.iter().enumerate() {
            let at = 84 + 50 * t;
            let n: [f32; 3] = core::array::from_fn(|k| {
                f32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap())
            });
            let n = DVec3::new(n[0].into(), n[1].into(), n[2].into());
            let [a, b, c] = tri.map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into()));
            // Samples exactly on the sphere give some zero-area triangles: their normal is zero.
            let Some(want) = (b - a).cross(c - a).try_normalize() else {
                assert_eq!(n, DVec3::ZERO, "facet {t}");
                continue;
            };
            assert!((n - want).length() < 1e-4, "facet {t}: {n} vs {want}");
            assert!(n.dot(a - centre) > 0.0, "facet {t} faces in");
        }
    }
}
