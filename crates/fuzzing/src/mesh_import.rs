//! The `mesh_import` target: OBJ, STL (binary and ASCII) and PLY files, as the free-form mode imports
//! them.

use bezsolid_core::esc::EscSolid;
use bezsolid_core::mesh::{self, Format, RawMesh};
use glam::DVec3;

/// The most triangles of an imported mesh that is also made into a free-form solid and asked
/// about a point: building the chain grows with the mesh, and the import is the target.
const MAX_SOLID_TRIANGLES: usize = 2_000;

/// Reads the bytes as a mesh file, each format's parser on its own and then as [`mesh::read`] does.
///
/// - The parsers ([`Format::parse`]) give finite positions and
///   triangle indices in range, as [`RawMesh`] promises.
/// - A mesh that reads is closed and manifold ([`Mesh::check_closed_manifold`]), oriented outward
///   (volume ≥ 0), with one finite unit (or zero) normal per vertex, and every vertex used.
/// - A small one becomes a free-form solid whose bounds are finite and which holds no point
///   outside them.
///
/// # Panics
///
/// On a bug: a broken promise above, or any panic inside the readers.
///
/// [`Mesh::check_closed_manifold`]: bezsolid_core::mesh::Mesh::check_closed_manifold
pub fn mesh_import(data: &[u8]) {
    let _ = Format::detect(data);
    for raw in Format::ALL.into_iter().filter_map(|f| f.parse(data).ok()) {
        check_raw(&raw);
    }
    let Ok(mesh) = mesh::read(data) else {
        return;
    };
    if let Err(e) = mesh.check_closed_manifold() {
        panic!("an imported mesh is not a closed manifold: {e}");
    }
    assert!(
        mesh.positions.iter().all(|p| p.is_finite()),
        "an imported vertex is not finite"
    );
    assert_eq!(
        mesh.normals.len(),
        mesh.positions.len(),
        "one normal per vertex"
    );
    for n in &mesh.normals {
        assert!(
            n.is_finite() && (*n == DVec3::ZERO || (n.length() - 1.0).abs() < 1e-9),
            "a vertex normal {n} is neither unit nor zero"
        );
    }
    let mut used = vec![false; mesh.positions.len()];
    for t in &mesh.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "an imported vertex is not used");
    let volume = mesh.volume();
    assert!(
        volume >= 0.0 || volume.is_nan(),
        "an imported mesh is inside out (volume {volume})"
    );
    if mesh.triangles.len() <= MAX_SOLID_TRIANGLES
        && let Ok(solid) = EscSolid::new(&mesh)
    {
        let (lo, hi) = solid.bounds();
        assert!(
            lo.is_finite() && hi.is_finite() && lo.cmple(hi).all(),
            "a free-form solid's bounds {lo} .. {hi}"
        );
        let outside = hi + (hi - lo).max(DVec3::ONE);
        if outside.is_finite() {
            assert!(
                !solid.contains(outside),
                "a free-form solid holds {outside}, outside its bounds {lo} .. {hi}"
            );
        }
    }
}

fn check_raw(raw: &RawMesh) {
    assert!(
        raw.positions.iter().all(|p| p.is_finite()),
        "a parsed vertex is not finite"
    );
    let n = raw.positions.len();
    assert!(
        raw.triangles.iter().flatten().all(|&i| (i as usize) < n),
        "a parsed triangle's index is past the {n} vertices"
    );
    if let Some(normals) = &raw.normals {
        assert_eq!(normals.len(), n, "one normal sum per parsed vertex");
    }
}
