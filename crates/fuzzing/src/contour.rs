//! The `contour` target: zero contours of patch solids on random small nets.

use bezsolid_core::contour::{sample_grid, solid_contour};

use crate::input::Input;
use crate::net;

/// The largest degree per axis of the nets here.
const MAX_DEGREE: usize = 6;
/// The most cells per side of the contour's grid.
const MAX_RESOLUTION: usize = 16;

/// Decodes a patch solid (degree at most 6 per axis, points moved, folded, collapsed or lined up)
/// and traces its zero contour ([`solid_contour`]) at 2 to 16 cells per side, to an accuracy
/// between 10⁻³ and 10⁻¹².
///
/// Every polyline is closed (the grid has a margin where `f < 0`) and has at least three
/// vertices, all finite and within the grid: the box of the control points and one cell more.
///
/// # Panics
///
/// On a bug: a broken promise above, a valid net refused, or any panic in the contouring.
pub fn contour(data: &[u8]) {
    let mut input = Input::new(data);
    let resolution = 2 + input.below(MAX_RESOLUTION - 1);
    let accuracy = [1e-3, 1e-6, 1e-9, 1e-12][input.below(4)];
    let solid = net::solid2(&mut input, MAX_DEGREE);
    // The grid of the sampled path; the forward-mapped path's vertices lie in the domain, inside it.
    let grid = sample_grid(&solid, resolution);
    let (lo, hi) = (grid.point(0, 0), grid.point(grid.nx() - 1, grid.ny() - 1));
    let slack = (hi - lo).max_element() * 1e-9 + hi.abs().max(lo.abs()).max_element() * 1e-12;
    for line in solid_contour(&solid, resolution, accuracy) {
        assert!(line.closed, "an open contour: {line:?}");
        assert!(
            line.points.len() >= 3,
            "a contour of {} vertices",
            line.points.len()
        );
        for p in &line.points {
            assert!(p.is_finite(), "a contour vertex {p}");
            assert!(
                p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                "a contour vertex {p} outside the grid over {lo} .. {hi} at {resolution} cells"
            );
        }
    }
}
