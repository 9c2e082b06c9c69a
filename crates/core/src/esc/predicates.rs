//! Exact orientation of a query point against a plane through three points, with one symbolic
//! perturbation so that no answer is ever "on the plane".
//!
//! [`side`] is the sign of Shewchuk's `orient3d(a, b, c, q) = (a − q)·((b − a) × (c − a))`,
//! evaluated exactly (the `robust` crate). Where it is 0, the query is moved to
//! `q + ε·x̂ + ε²·ŷ + ε³·ẑ` for an infinitesimal `ε`: `orient3d` is affine in `q` with gradient
//! `−N`, `N = (b − a) × (c − a)`, so the sign becomes that of `−N_x`, else `−N_y`, else `−N_z`, and
//! each component of `N` is an exact `orient2d` of the points projected on a coordinate plane. The
//! perturbation is the same for every plane, so every test a point meets is answered for one and the
//! same perturbed point: the tetrahedra of a chain then never share it, and the associated function
//! is exact at every query point. Only a degenerate triple (`a, b, c` collinear) gives 0.

use glam::DVec3;
use robust::{Coord, Coord3D, orient2d, orient3d};

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

fn c2(x: f64, y: f64) -> Coord<f64> {
    Coord { x, y }
}

/// The exact sign of `orient3d(a, b, c, q)` for the perturbed `q` (see the module): `1` when `q` is
/// below the plane through `a, b, c` (counter-clockwise seen from above), `−1` above, `0` only when
/// `a, b, c` are collinear.
#[must_use]
pub fn side(a: DVec3, b: DVec3, c: DVec3, q: DVec3) -> i8 {
    match orient_sign(a, b, c, q) {
        0 => perturbed(a, b, c),
        s => s,
    }
}

/// The exact sign of `orient3d(a, b, c, q)` without the perturbation: 0 when the four points are
/// coplanar.
#[must_use]
pub fn orient_sign(a: DVec3, b: DVec3, c: DVec3, q: DVec3) -> i8 {
    let o = orient3d(c3(a), c3(b), c3(c), c3(q));
    if o > 0.0 {
        1
    } else if o < 0.0 {
        -1
    } else {
        0
    }
}

/// The exact sign of `orient2d(a, b, c)`: `1` when `a, b, c` turn counter-clockwise, `−1`
/// clockwise, `0` when they are collinear.
#[must_use]
pub fn orient2_sign(a: glam::DVec2, b: glam::DVec2, c: glam::DVec2) -> i8 {
    let o = orient2d(c2(a.x, a.y), c2(b.x, b.y), c2(c.x, c.y));
    if o > 0.0 {
        1
    } else if o < 0.0 {
        -1
    } else {
        0
    }
}

/// The sign of `−N_x`, else `−N_y`, else `−N_z`, `N = (b − a) × (c − a)`, each exact.
#[cold]
fn perturbed(a: DVec3, b: DVec3, c: DVec3) -> i8 {
    // N_x = det of the (y, z) projection, N_y of (z, x), N_z of (x, y): orient2d(a, b, c) is the
    // doubled signed area det(b − a, c − a) of the projected triangle.
    let nx = orient2d(c2(a.y, a.z), c2(b.y, b.z), c2(c.y, c.z));
    let ny = orient2d(c2(a.z, a.x), c2(b.z, b.x), c2(c.z, c.x));
    let nz = orient2d(c2(a.x, a.y), c2(b.x, b.y), c2(c.x, c.y));
    for n in [nx, ny, nz] {
        if n > 0.0 {
            return -1;
        }
        if n < 0.0 {
            return 1;
        }
    }
    0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_sign_follows_the_orientation() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        // Counter-clockwise seen from +z: +z is above, so a point there is negative.
        assert_eq!(side(a, b, c, DVec3::Z), -1);
        assert_eq!(side(a, b, c, -DVec3::Z), 1);
        assert_eq!(side(b, a, c, DVec3::Z), 1);
    }

    #[test]
    fn points_on_the_plane_take_the_side_of_the_perturbed_point() {
        let mut rng = Rng::new(7);
        for _ in 0..500 {
            // A plane through three random grid points and a fourth point on it.
            let mut p = || {
                DVec3::new(
                    rng.int(0, 8) as f64,
                    rng.int(0, 8) as f64,
                    rng.int(0, 8) as f64,
                )
            };
            let (a, b, c) = (p(), p(), p());
            let n = (b - a).cross(c - a);
            if n == DVec3::ZERO {
                assert_eq!(side(a, b, c, a), 0);
                continue;
            }
            let q = a + (b - a) * 0.5 + (c - a) * 0.25;
            if orient3d(c3(a), c3(b), c3(c), c3(q)) != 0.0 {
                continue; // the midpoint arithmetic rounded off the plane
            }
            // Moving q a little along x, then y, then z, agrees with the symbolic answer.
            // Powers of two that survive the addition to coordinates up to 8 (doubles carry 52 bits).
            let tiny = [2f64.powi(-12), 2f64.powi(-26), 2f64.powi(-40)];
            let moved = q + DVec3::new(tiny[0], tiny[1], tiny[2]);
            let expect = side(a, b, c, moved);
            assert_eq!(side(a, b, c, q), expect, "{a} {b} {c}");
            // Swapping two corners flips the answer exactly.
            assert_eq!(side(b, a, c, q), -expect);
        }
    }
}
