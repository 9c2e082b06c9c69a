//! Wavefront OBJ: `v` lines (shortest round-trip decimal, so they read back to the same `f64`), `vn`
//! lines with the vertex normals, and `f a//a b//b c//c` faces (1-based), counter-clockwise from
//! outside.

use alloc::string::String;
use core::fmt::Write as _;

use alloc::vec::Vec;

use glam::DVec3;

use super::read::{MAX_TRIANGLES, MAX_VERTICES, integer, three_numbers, too_many};
use super::{Mesh, RawMesh, ReadError};

/// The OBJ text of `mesh`. Normals are written when there is one per vertex.
#[must_use]
pub fn write_obj(mesh: &Mesh) -> String {
    let mut out = String::with_capacity(40 * (mesh.positions.len() * 2 + mesh.triangles.len()));
    let _ = writeln!(
        out,
        "# written by bezsolid: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    for p in &mesh.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    let normals = mesh.normals.len() == mesh.positions.len();
    if normals {
        for n in &mesh.normals {
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if normals {
            let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
        } else {
            let _ = writeln!(out, "f {a} {b} {c}");
        }
    }
    out
}

/// Parses an OBJ file: `v x y z [w …]` (extra values such as `w` or colours are ignored), `vn`, and
/// `f` with `v`, `v/vt`, `v//vn` or `v/vt/vn` corners, negative (relative) indices, and polygons
/// split into fans from their first corner; `#` starts a comment; every other statement (`vt`, `o`,
/// `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, …) is ignored. A face may only refer to vertices and
/// normals defined above it.
///
/// # Errors
///
/// [`ReadError::Parse`] or [`ReadError::BadIndex`] with the line, [`ReadError::NotFinite`],
/// or [`ReadError::TooLarge`] past [`MAX_VERTICES`] vertices or normals or [`MAX_TRIANGLES`]
/// triangles.
pub fn parse_obj(text: &[u8]) -> Result<RawMesh, ReadError> {
    let text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
    let mut positions: Vec<DVec3> = Vec::new();
    let mut file_normals: Vec<DVec3> = Vec::new();
    // Per position, the sum of the normals at its face corners.
    let mut sums: Vec<DVec3> = Vec::new();
    let mut every_corner_has_a_normal = true;
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (k, line) in text.split(|&b| b == b'\n').enumerate() {
        let line_no = k + 1;
        let line = line.split(|&b| b == b'#').next().unwrap_or_default();
        let mut tokens = line
            .split(u8::is_ascii_whitespace)
            .filter(|t| !t.is_empty());
        let Some(keyword) = tokens.next() else {
            continue;
        };
        match keyword {
            b"v" => {
                let p = three_numbers(&mut tokens).ok_or(ReadError::Parse {
                    line: line_no,
                    reason: "a vertex needs three numbers: `v x y z`",
                })?;
                if positions.len() == MAX_VERTICES {
                    return Err(too_many("vertices", MAX_VERTICES));
                }
                positions.push(p);
                sums.push(DVec3::ZERO);
                if !p.is_finite() {
                    return Err(ReadError::NotFinite {
                        vertex: positions.len(),
                    });
                }
            }
            b"vn" => {
                let n = three_numbers(&mut tokens).ok_or(ReadError::Parse {
                    line: line_no,
                    reason: "a normal needs three numbers: `vn x y z`",
                })?;
                if file_normals.len() == MAX_VERTICES {
                    return Err(too_many("normals", MAX_VERTICES));
                }
                // A non-finite or zero normal counts as none at the corners that use it.
                file_normals.push(if n.is_finite() {
                    n.normalize_or_zero()
                } else {
                    DVec3::ZERO
                });
            }
            b"f" => {
                // Split into a fan as the corners come: no buffer as long as the line.
                let mut first = None;
                let mut previous = None;
                let mut corners = 0usize;
                for token in tokens {
                    let (v, vn) = face_corner(token, line_no, positions.len(), file_normals.len())?;
                    match vn.and_then(|i| file_normals.get(i)) {
                        Some(&n) => {
                            if let Some(s) = sums.get_mut(v) {
                                *s += n;
                            }
                        }
                        None => every_corner_has_a_normal = false,
                    }
                    // `v` < positions.len() ≤ MAX_VERTICES, so it fits.
                    let v = v as u32;
                    corners += 1;
                    match (first, previous) {
                        (Some(a), Some(b)) => {
                            if triangles.len() == MAX_TRIANGLES {
                                return Err(too_many("triangles", MAX_TRIANGLES));
                            }
                            triangles.push([a, b, v]);
                        }
                        (None, _) => first = Some(v),
                        (Some(_), None) => {}
                    }
                    if corners >= 2 {
                        previous = Some(v);
                    }
                }
                if corners < 3 {
                    return Err(ReadError::Parse {
                        line: line_no,
                        reason: "a face needs at least three vertices",
                    });
                }
            }
            _ => {}
        }
    }
    Ok(RawMesh {
        positions,
        normals: (every_corner_has_a_normal && !triangles.is_empty()).then_some(sums),
        triangles,
    })
}

/// One face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`: the 0-based vertex and normal indices.
fn face_corner(
    token: &[u8],
    line: usize,
    vertices: usize,
    normals: usize,
) -> Result<(usize, Option<usize>), ReadError> {
    let malformed = ReadError::Parse {
        line,
        reason: "a face corner must be `v`, `v/vt`, `v//vn` or `v/vt/vn` with integer indices",
    };
    let mut parts = token.split(|&b| b == b'/');
    let v = parts.next().and_then(integer).ok_or(malformed.clone())?;
    let _texture = parts.next();
    let vn = match parts.next() {
        None | Some(b"") => None,
        Some(part) => Some(integer(part).ok_or(malformed.clone())?),
    };
    if parts.next().is_some() {
        return Err(malformed);
    }
    let resolve = |index: i64, count: usize| {
        let count = i64::try_from(count).unwrap_or(i64::MAX);
        let i = if index < 0 { count + index } else { index - 1 };
        if index != 0 && (0..count).contains(&i) {
            usize::try_from(i).map_err(|_| ReadError::BadIndex { line, index })
        } else {
            Err(ReadError::BadIndex { line, index })
        }
    };
    Ok((
        resolve(v, vertices)?,
        vn.map(|vn| resolve(vn, normals)).transpose()?,
    ))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::tests::test_mesh;
    use alloc::vec::Vec;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// Positions, normals and triangles of an OBJ text; `None` if malformed.
    pub(crate) fn read_obj(text: &str) -> Option<Mesh> {
        let mut mesh = Mesh::default();
        for line in text.lines() {
            let mut words = line.split_whitespace();
            let key = words.next();
            let vec3 = |words: core::str::SplitWhitespace<'_>| -> Option<DVec3> {
                let v: Vec<f64> = words.map(|w| w.parse().ok()).collect::<Option<_>>()?;
                (v.len() == 3).then(|| DVec3::new(v[0], v[1], v[2]))
            };
            match key {
                Some("v") => mesh.positions.push(vec3(words)?),
                Some("vn") => mesh.normals.push(vec3(words)?),
                Some("f") => {
                    let idx: Vec<u32> = words
                        .map(|w| w.split('/').next()?.parse::<u32>().ok()?.checked_sub(1))
                        .collect::<Option<_>>()?;
                    mesh.triangles.push(idx.try_into().ok()?);
                }
                _ => {}
            }
        }
        Some(mesh)
    }

    #[test]
    fn obj_parses_back_to_the_same_mesh() {
        let mesh = test_mesh();
        assert_eq!(read_obj(&write_obj(&mesh)).unwrap(), mesh);
        let bare = Mesh {
            normals: Vec::new(),
            ..mesh
        };
        let text = write_obj(&bare);
        assert!(!text.contains("vn"));
        assert_eq!(read_obj(&text).unwrap(), bare);
    }
}
