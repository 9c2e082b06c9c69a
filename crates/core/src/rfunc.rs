//! R-functions and functional clipping (first paper, §3.3.1).
//!
//! The R0 system: `f1 & f2 = f1 + f2 − √(f1² + f2²)` is positive exactly where both arguments are,
//! `f1 | f2 = f1 + f2 + √(f1² + f2²)` where either is, and `−f` is the complement. Functional clipping
//! `√(f1² + f2²)` is computed as `hypot`, which does not overflow for large values, and the sum
//! `f1 + f2 ∓ √(…)` is rewritten as `2·f1·f2 / (f1 + f2 ± √(…))` where it would cancel. Both are
//! finite for finite or infinite arguments of any magnitude (they saturate at `±f64::MAX`). Functional clipping
//! intersects the patch's function with the parameter square so that it is negative outside it:
//! `S_clip(u, v) = S_ξ(u, v) & F_s(u, v)`, `F_s(u, v) = F_b(u) & F_b(v)`, `F_b(t) = t(1 − t)`.

use crate::math::hypot;

/// R-function intersection `f1 & f2 = f1 + f2 − √(f1² + f2²)`.
#[must_use]
#[inline]
pub fn intersect(f1: f64, f2: f64) -> f64 {
    if f1.abs().max(f2.abs()) > LARGE {
        return saturating(f1, f2, false);
    }
    let (s, h) = (f1 + f2, hypot(f1, f2));
    if s > 0.0 {
        // s − h cancels when one argument dwarfs the other; (s − h)(s + h) = 2·f1·f2 does not.
        let v = 2.0 * f1 * (f2 / (s + h));
        if v == 0.0 && f1 != 0.0 && f2 != 0.0 {
            // The quotient underflowed (1e-300 against 1e200): the larger over the sum first.
            tiny(f1, f2, s + h)
        } else {
            v
        }
    } else {
        s - h
    }
}

/// `2·f1·f2 / sum` where `f2 / sum` underflowed: the larger argument over `sum` (about 1 or 2)
/// times the smaller one, which keeps the smaller one's sign and magnitude.
#[cold]
fn tiny(f1: f64, f2: f64, sum: f64) -> f64 {
    let (big, small) = if f1.abs() >= f2.abs() {
        (f1, f2)
    } else {
        (f2, f1)
    };
    2.0 * (big / sum) * small
}

/// Past this magnitude an R-function's sum or root may overflow: its arguments are scaled down
/// first ([`saturating`]).
const LARGE: f64 = f64::MAX / 8.0;

/// `op(f1, f2)` for arguments of any magnitude, infinities included: both are taken within
/// `±f64::MAX` and scaled by `2⁻⁸` (exact: the R-functions are positively homogeneous,
/// `op(k·a, k·b) = k·op(a, b)` for `k > 0`, and a power of two scales every step of the sums
/// without rounding), and the value is scaled back within `±f64::MAX`. So `&` and `|` of huge,
/// maximal or infinite values stay finite and keep the order and the signs of the R-functions;
/// only NaN gives NaN.
#[cold]
fn saturating(f1: f64, f2: f64, union: bool) -> f64 {
    const DOWN: f64 = 1.0 / 256.0;
    let (a, b) = (
        f1.clamp(-f64::MAX, f64::MAX) * DOWN,
        f2.clamp(-f64::MAX, f64::MAX) * DOWN,
    );
    let (s, h) = (a + b, hypot(a, b));
    // As `intersect` and `union` compute it, with the larger argument over the sum first (the
    // smaller one's quotient by the sum would lose its digits below the normal range).
    let v = match (union, s > 0.0, s < 0.0) {
        (false, true, _) => tiny(a, b, s + h),
        (false, false, _) => s - h,
        (true, _, true) => tiny(a, b, s - h),
        (true, _, false) => s + h,
    };
    (v * 256.0).clamp(-f64::MAX, f64::MAX)
}

/// [`intersect`] with its partial derivatives `(f1 & f2, ∂/∂f1, ∂/∂f2)`: `∂/∂f1 = 1 − f1/√(f1² + f2²)`.
/// At `f1 = f2 = 0`, where `&` has no derivative, both partials are taken along the diagonal:
/// `1 − 1/√2`.
#[must_use]
#[inline]
pub fn intersect_with_partials(f1: f64, f2: f64) -> (f64, f64, f64) {
    let h = hypot(f1, f2);
    if h == 0.0 {
        let d = 1.0 - core::f64::consts::FRAC_1_SQRT_2;
        return (0.0, d, d);
    }
    (intersect(f1, f2), 1.0 - f1 / h, 1.0 - f2 / h)
}

/// R-function union `f1 | f2 = f1 + f2 + √(f1² + f2²)`.
#[must_use]
#[inline]
pub fn union(f1: f64, f2: f64) -> f64 {
    if f1.abs().max(f2.abs()) > LARGE {
        return saturating(f1, f2, true);
    }
    let (s, h) = (f1 + f2, hypot(f1, f2));
    if s < 0.0 {
        // The mirror of `intersect`: no cancellation between s and h.
        let v = 2.0 * f1 * (f2 / (s - h));
        if v == 0.0 && f1 != 0.0 && f2 != 0.0 {
            tiny(f1, f2, s - h)
        } else {
            v
        }
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

/// The unit box of `D` parameters, `F_b(t_0) & F_b(t_1) & …`, taken left to right as the paper
/// writes it (`&` is not associative in floating point, nor exactly in value).
#[must_use]
#[inline]
pub fn unit_box<const D: usize>(t: [f64; D]) -> f64 {
    t[1..]
        .iter()
        .fold(t.first().map_or(0.0, |&t0| strip(t0)), |c, &ta| {
            intersect(c, strip(ta))
        })
}

/// The unit square `F_s(u, v) = F_b(u) & F_b(v)`.
#[must_use]
#[inline]
pub fn unit_square(u: f64, v: f64) -> f64 {
    unit_box([u, v])
}

/// The unit cube `F_s(u, v, w) = F_b(u) & F_b(v) & F_b(w)`.
#[must_use]
#[inline]
pub fn unit_cube(u: f64, v: f64, w: f64) -> f64 {
    unit_box([u, v, w])
}

/// A clipped value that overflowed to infinity or NaN, saturated: far outside the unit box, where
/// the polynomial's terms or the parameters themselves pass `f64::MAX`, the value is negative (the
/// clipping function is), and `−f64::MAX` is the nearest finite value of the right sign. Inside
/// the box nothing overflows (control values are at most 1e12).
#[inline]
fn saturate(f: f64) -> f64 {
    if f.is_finite() { f } else { -f64::MAX }
}

/// Functional clipping of a net's value `s = S_ξ(t)` to the unit box of its parameters:
/// `s & F_s(t)`; finite for any input (see `saturate`).
#[must_use]
#[inline]
pub fn clip<const D: usize>(s: f64, t: [f64; D]) -> f64 {
    clip_to_box(s, unit_box(t))
}

/// [`clip`] given the box's value `F_s(t)` (for grids, which share it between points).
#[must_use]
#[inline]
pub fn clip_to_box(s: f64, unit_box: f64) -> f64 {
    saturate(intersect(s, unit_box))
}

/// [`clip`] of a patch value `S_ξ(u, v)` to the unit square.
#[must_use]
#[inline]
pub fn clip2(s: f64, u: f64, v: f64) -> f64 {
    clip(s, [u, v])
}

/// [`clip`] of a volume value `S_ξ(u, v, w)` to the unit cube.
#[must_use]
#[inline]
pub fn clip3(s: f64, u: f64, v: f64, w: f64) -> f64 {
    clip(s, [u, v, w])
}

/// A gradient with a component that overflowed, as none: where the value saturated there is no
/// useful direction.
fn finite_or_zero<const D: usize>(g: [f64; D]) -> [f64; D] {
    if g.iter().all(|x| x.is_finite()) {
        g
    } else {
        [0.0; D]
    }
}

/// [`clip`] with its gradient in `t`, given `s` and its gradient `ds`: the chain rule through
/// [`intersect_with_partials`], box factor by box factor.
#[must_use]
pub fn clip_with_gradient<const D: usize>(s: f64, ds: [f64; D], t: [f64; D]) -> (f64, [f64; D]) {
    // The box F_s and its gradient, built left to right as `unit_box` is.
    let mut dc = [0.0; D];
    let mut c = 0.0;
    for (a, &ta) in t.iter().enumerate() {
        let ds_a = 1.0 - 2.0 * ta;
        if a == 0 {
            c = strip(ta);
            dc[0] = ds_a;
        } else {
            let (next, pc, pa) = intersect_with_partials(c, strip(ta));
            for g in &mut dc[..a] {
                *g *= pc;
            }
            dc[a] = pa * ds_a;
            c = next;
        }
    }
    let (f, fs, fc) = intersect_with_partials(s, c);
    (
        saturate(f),
        finite_or_zero(core::array::from_fn(|a| fs * ds[a] + fc * dc[a])),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn rfunc_clip_gradients_match_finite_differences() {
        let mut rng = Rng::new(40);
        let h = 1e-6;
        for _ in 0..500 {
            // A smooth stand-in for S_ξ: s = a + b·u + c·v·w.
            let (a, b, c) = (
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let s = |p: [f64; 3]| a + b * p[0] + c * p[1] * p[2];
            let p = [
                rng.range(-0.3, 1.3),
                rng.range(-0.3, 1.3),
                rng.range(-0.3, 1.3),
            ];
            let ds = [b, c * p[2], c * p[1]];
            let (f, grad) = clip_with_gradient(s(p), ds, p);
            assert_eq!(f, clip3(s(p), p[0], p[1], p[2]));
            let (f2, grad2) = clip_with_gradient(s(p), [ds[0], ds[1]], [p[0], p[1]]);
            assert_eq!(f2, clip2(s(p), p[0], p[1]));
            for axis in 0..3 {
                let (mut up, mut down) = (p, p);
                up[axis] += h;
                down[axis] -= h;
                let fd3 = (clip3(s(up), up[0], up[1], up[2])
                    - clip3(s(down), down[0], down[1], down[2]))
                    / (2.0 * h);
                assert!(
                    (fd3 - grad[axis]).abs() < 1e-5 * (1.0 + fd3.abs()),
                    "{p:?} axis {axis}"
                );
                if axis < 2 {
                    let fd2 =
                        (clip2(s(up), up[0], up[1]) - clip2(s(down), down[0], down[1])) / (2.0 * h);
                    assert!((fd2 - grad2[axis]).abs() < 1e-5 * (1.0 + fd2.abs()));
                }
            }
        }
    }

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

    /// `&` and `|` of infinite, maximal and huge values: finite, with the R-functions' signs, and
    /// ordered (increasing in each argument), so that a tree of far or huge solids never gives
    /// NaN (a union of two solids at 2e154 did: `−inf | −inf`).
    #[test]
    fn rfunc_saturate_at_the_ends_of_the_doubles() {
        // Increasing to rounding (the cancellation-free form rounds differently from one
        // argument to the next), and exactly at the saturated ends.
        let values = [
            f64::NEG_INFINITY,
            -f64::MAX,
            -1e300,
            -1e200,
            -1.0,
            -1e-300,
            0.0,
            1e-300,
            1.0,
            1e200,
            1e300,
            f64::MAX,
            f64::INFINITY,
        ];
        for (and, op) in [(true, intersect as fn(f64, f64) -> f64), (false, union)] {
            for (i, &a) in values.iter().enumerate() {
                for (j, &b) in values.iter().enumerate() {
                    let v = op(a, b);
                    assert!(v.is_finite(), "{a} op {b} = {v}");
                    let want = if and {
                        a > 0.0 && b > 0.0
                    } else {
                        a > 0.0 || b > 0.0
                    };
                    assert_eq!(v > 0.0, want, "{a} op {b} = {v}");
                    assert_eq!(
                        v < 0.0,
                        if and {
                            a < 0.0 || b < 0.0
                        } else {
                            a < 0.0 && b < 0.0
                        },
                        "{a} op {b} = {v}"
                    );
                    if let Some(&c) = values.get(j + 1) {
                        assert!(
                            op(a, c) >= v,
                            "not increasing: {a} op {b} = {v} > {a} op {c}"
                        );
                    }
                    if let Some(&c) = values.get(i + 1) {
                        assert!(
                            op(c, b) >= v,
                            "not increasing: {a} op {b} = {v} > {c} op {b}"
                        );
                    }
                }
            }
        }
        // `x & x = (2 − √2)·x` at the largest double as below it; `−∞ | −∞` as the least double's.
        let ratio = intersect(f64::MAX, f64::MAX) / f64::MAX;
        assert!(
            (ratio - (2.0 - core::f64::consts::SQRT_2)).abs() < 1e-15,
            "{ratio}"
        );
        let low = union(f64::NEG_INFINITY, f64::NEG_INFINITY);
        assert_eq!(low, union(-f64::MAX, -f64::MAX));
        assert!((low / -f64::MAX - (2.0 - core::f64::consts::SQRT_2)).abs() < 1e-15);
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
