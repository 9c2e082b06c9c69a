//! Binary little-endian PLY: vertices with `float` position and normal, faces as a `uchar` count and
//! `int` indices, counter-clockwise from outside.

use alloc::format;
use alloc::vec::Vec;

use super::Mesh;

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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::tests::test_mesh;
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
}
