//! R-functions and functional clipping (first paper, §3.3.1).
//!
//! The R0 system: `f1 & f2 = f1 + f2 − √(f1² + f2²)` is positive exactly where both arguments are,
//! `f1 | f2 = f1 + f2 + √(f1² + f2²)` where either is, and `−f` is the complement. Functional clipping
//! `√(f1² + f2²)` is computed as `hypot`, which does not overflow for large values, and the sum
//! `f1 + f2 ∓ √(…)` is rewritten as `2·f1·f2 / (f1 + f2 ± √(…))` where it would cancel. Functional clipping
//! intersects the patch's function with the parameter square so that it is negative outside it:
//! `S_clip(u, v) = S_ξ(u, v) & F_s(u, v)`, `F_s(u, v) = F_b(u) & F_b(v)`, `F_b(t) = t(1 − t)`.

use crate::math::hypot;

/// R-function intersection `f1 & f2 = f1 + f2 − √(f1² + f2²)`.
#[must_use]
#[inline]
pub fn intersect(f1: f64, f2: f64) -> f64 {
    let (s, h) = (f1 + f2, hypot(f1, f2));
    if s > 0.0 {
        // s − h cancels when one argument dwarfs the other; (s − h)(s + h) = 2·f1·f2 does not.
        2.0 * f1 * (f2 / (s + h))
    } else {
        s - h
    }
}

/// R-function union `f1 | f2 = f1 + f2 + √(f1² + f2²)`.
#[must_use]
#[inline]
pub fn union(f1: f64, f2: f64) -> f64 {
    let (s, h) = (f1 + f2, hypot(f1, f2));
    if s < 0.0 {
        // The mirror of `intersect`: no cancellation between s and h.
        2.0 * f1 * (f2 / (s - h))
    } else {
        s + h
    }
}

/// Complement `−f`.
#[must_use]
#[inline]
pub fn negate(f: f64) -> f64 {
    -f
}

/// The unit strip `F_b(t) = t(1 − t)`: positive for `0 < t < 1`.
#[must_use]
#[inline]
pub fn strip(t: f64) -> f64 {
    t * (1.0 - t)
}

/// The unit square `F_s(u, v) = F_b(u) & F_b(v)`.
#[must_use]
#[inline]
pub fn unit_square(u: f64, v: f64) -> f64 {
    intersect(strip(u), strip(v))
}

/// Functional clipping of a patch value `s = S_ξ(u, v)` to the unit square: `s & F_s(u, v)`.
#[must_use]
#[inline]
pub fn clip2(s: f64, u: f64, v: f64) -> f64 {
    intersect(s, unit_square(u, v))
}

/// The unit cube `F_s(u, v, w) = F_b(u) & F_b(v) & F_b(w)`, taken left to right as the paper writes it
/// (`&` is not associative in floating point, nor exactly in value).
#[must_use]
#[inline]
pub fn unit_cube(u: f64, v: f64, w: f64) -> f64 {
    intersect(intersect(strip(u), strip(v)), strip(w))
}

/// Functional clipping of a volume value `s = S_ξ(u, v, w)` to the unit cube: `s & F_s(u, v, w)`.
#[must_use]
#[inline]
pub fn clip3(s: f64, u: f64, v: f64, w: f64) -> f64 {
    intersect(s, unit_cube(u, v, w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn rfunc_intersection_sign_is_logical_and() {
        let mut rng = Rng::new(20);
        for _ in 0..1000 {
            let (a, b) = (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            assert_eq!(intersect(a, b) > 0.0, a > 0.0 && b > 0.0, "{a} & {b}");
            assert_eq!(union(a, b) > 0.0, a > 0.0 || b > 0.0, "{a} | {b}");
        }
        assert_eq!(intersect(2.0, 0.0), 0.0);
    }

    #[test]
    fn rfunc_cube_clipping_negative_outside_same_sign_inside() {
        let mut rng = Rng::new(23);
        for _ in 0..5000 {
            let (u, v, w) = (
                rng.range(-1.0, 2.0),
                rng.range(-1.0, 2.0),
                rng.range(-1.0, 2.0),
            );
            let s = rng.range(-2.0, 2.0);
            let c = clip3(s, u, v, w);
            let inside = [u, v, w].iter().all(|t| 0.0 < *t && *t < 1.0);
            if inside {
                assert_eq!(
                    c > 0.0,
                    s > 0.0,
                    "s = {s} at ({u}, {v}, {w}) clipped to {c}"
                );
            } else {
                assert!(
                    c <= 0.0,
                    "clipped value {c} at ({u}, {v}, {w}) outside the cube"
                );
            }
        }
    }

    /// Regression: `f1² + f2²` overflowed for |f| above ~1e154 and flipped the sign of the solid.
    #[test]
    fn rfunc_large_values_keep_their_sign() {
        for big in [1e154, 1e200, 1e300] {
            assert!(intersect(big, big) > 0.0);
            assert!(intersect(big, 0.5) > 0.0);
            assert!(union(-big, -big) < 0.0);
            assert!(intersect(-big, 0.5) < 0.0);
            assert!(union(-big, 0.5) > 0.0);
        }
        // Away from cancellation the rewritten form agrees with the textbook one.
        let mut rng = Rng::new(22);
        for _ in 0..1000 {
            let (a, b) = (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let h = (a * a + b * b).sqrt();
            assert!((intersect(a, b) - (a + b - h)).abs() < 1e-12);
            assert!((union(a, b) - (a + b + h)).abs() < 1e-12);
        }
    }

    /// Paper Fig. 4: after clipping the function is negative outside the unit square and keeps the
    /// sign of the unclipped function inside.
    #[test]
    fn rfunc_clipping_negative_outside_same_sign_inside() {
        let mut rng = Rng::new(21);
        for _ in 0..5000 {
            let (u, v) = (rng.range(-1.0, 2.0), rng.range(-1.0, 2.0));
            let s = rng.range(-2.0, 2.0);
            let c = clip2(s, u, v);
            let inside = 0.0 < u && u < 1.0 && 0.0 < v && v < 1.0;
            if inside {
                assert_eq!(c > 0.0, s > 0.0, "s = {s} at ({u}, {v}) clipped to {c}");
            } else {
                assert!(
                    c <= 0.0,
                    "clipped value {c} at ({u}, {v}) outside the square"
                );
            }
        }
    }
}
