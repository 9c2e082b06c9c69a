//! Binary STL: an 80-byte header, a little-endian `u32` triangle count, then per triangle the facet
//! normal and three corners as `f32` and a zero `u16`. Corners are counter-clockwise seen from
//! outside, as STL readers expect.

use alloc::vec::Vec;

use glam::DVec3;

use super::Mesh;

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
