//! Wavefront OBJ: `v` lines (shortest round-trip decimal, so they read back to the same `f64`), `vn`
//! lines with the vertex normals, and `f a//a b//b c//c` faces (1-based), counter-clockwise from
//! outside.

use alloc::string::String;
use core::fmt::Write as _;

use super::Mesh;

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
