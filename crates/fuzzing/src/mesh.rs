//! The `mesh` target: polygonized surfaces of volume solids on random small nets.

use crate::input::Input;
use crate::net;

/// The largest degree per axis of the nets here.
const MAX_DEGREE: usize = 4;
/// The most cells along the longest side of the box.
const MAX_RESOLUTION: usize = 8;

/// Decodes a volume solid (degree at most 4 per axis, points moved, folded, collapsed or lined
/// up) and polygonizes it ([`bezsolid_core::Solid3::polygonize`]) at 1 to 8 cells along the
/// longest side, to an accuracy between 10⁻³ and 10⁻¹².
///
/// The mesh is a closed, consistently oriented manifold
/// ([`bezsolid_core::mesh::Mesh::check_closed_manifold`]) bounding a volume that is not negative,
/// with one finite normal per vertex and every vertex finite and within the sample grid (the box
/// of the control points and one cell more).
///
/// # Panics
///
/// On a bug: a broken promise above, a valid net or resolution refused, or any panic in the
/// polygonization.
pub fn mesh(data: &[u8]) {
    let mut input = Input::new(data);
    let resolution = 1 + input.below(MAX_RESOLUTION);
    let accuracy = [1e-3, 1e-6, 1e-9, 1e-12][input.below(4)];
    let solid = net::solid3(&mut input, MAX_DEGREE);
    let mesh = solid
        .polygonize(resolution, accuracy)
        .unwrap_or_else(|e| panic!("resolution {resolution} is refused: {e}"));
    if let Err(e) = mesh.check_closed_manifold() {
        panic!("the mesh is not a closed manifold: {e}");
    }
    assert_eq!(
        mesh.normals.len(),
        mesh.positions.len(),
        "one normal per vertex"
    );
    // The sample grid (half a cell past the box, widened where a side is too thin); the
    // forward-mapped path's vertices lie in the domain, inside it.
    let grid = solid
        .mesh_grid(resolution)
        .unwrap_or_else(|e| panic!("resolution {resolution} is refused: {e}"));
    let [nx, ny, nz] = grid.dims;
    let (lo, hi) = (grid.origin, grid.point(nx - 1, ny - 1, nz - 1));
    let cell = grid.step.max_element();
    let slack = cell * 1e-9 + hi.abs().max(lo.abs()).max_element() * 1e-12;
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        assert!(
            p.is_finite() && n.is_finite(),
            "a vertex {p} with normal {n}"
        );
        assert!(
            p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
            "a vertex {p} outside the grid over {lo} .. {hi} at {resolution} cells"
        );
    }
    let volume = mesh.volume();
    let size = (hi - lo).max_element().powi(3);

    assert!(
        volume >= -1e-9 * size || !volume.is_finite(),
        "the mesh bounds a negative volume {volume}"
    );
}
