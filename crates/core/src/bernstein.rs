//! Binomials and the Bernstein basis `B_i^n(t) = C(n,i) tⁱ(1−t)ⁿ⁻ⁱ`, `i = 0..n`.

/// The highest degree per axis that bezsolid supports (DESIGN §5: degree ≤ 16 per axis).
pub const MAX_DEGREE: usize = 16;

/// The binomial coefficient `C(n, k)` as `f64`: exact for every `n ≤ MAX_DEGREE` (and far beyond),
/// never overflowing (it saturates to infinity for huge `n`).
///
/// Returns 0 when `k > n`.
#[must_use]
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut c = 1.0;
    for i in 0..k {
        // c · (n − i) / (i + 1) is an integer at every step, exact while it fits in 53 bits.
        c = c * (n - i) as f64 / (i + 1) as f64;
    }
    c
}

/// One Bernstein polynomial `B_i^n(t)`; 0 when `i > n`.
#[must_use]
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    binomial(n, i) * powi(t, i) * powi(1.0 - t, n - i)
}

/// All `n + 1` values `B_0^n(t) … B_n^n(t)`, written to `out[..=n]`, by the triangular recurrence
/// `B_i^k = (1−t) B_i^(k−1) + t B_(i−1)^(k−1)` (stable for any `t`, no binomials).
///
/// # Panics
///
/// If `out.len() <= n`.
pub fn basis(n: usize, t: f64, out: &mut [f64]) {
    assert!(out.len() > n, "basis of degree {n} needs {} slots", n + 1);
    let s = 1.0 - t;
    out[0] = 1.0;
    for k in 1..=n {
        let mut prev = 0.0;
        for slot in out.iter_mut().take(k) {
            let b = *slot;
            *slot = s * b + prev;
            prev = t * b;
        }
        out[k] = prev;
    }
}

/// The basis of degree `n` at `t` in a fixed array (entries past `n` are 0).
///
/// # Panics
///
/// If `n > MAX_DEGREE`.
#[must_use]
#[inline]
pub fn basis_array(n: usize, t: f64) -> [f64; MAX_DEGREE + 1] {
    let mut out = [0.0; MAX_DEGREE + 1];
    basis(n, t, &mut out);
    out
}

/// The basis of degree `n` at `t` and its derivative, `d/dt B_i^n(t) = n·(B_(i−1)^(n−1)(t) − B_i^(n−1)(t))`
/// (entries past `n` are 0).
///
/// # Panics
///
/// If `n > MAX_DEGREE`.
#[must_use]
#[inline]
pub fn basis_and_derivative(n: usize, t: f64) -> ([f64; MAX_DEGREE + 1], [f64; MAX_DEGREE + 1]) {
    let mut value = [0.0; MAX_DEGREE + 1];
    let mut slope = [0.0; MAX_DEGREE + 1];
    basis_and_derivative_into(n, t, &mut value, &mut slope);
    (value, slope)
}

/// [`basis_and_derivative`] into the caller's arrays (no 272-byte return to copy in hot loops);
/// entries past `n` are left as they were.
///
/// # Panics
///
/// If `n > MAX_DEGREE`.
#[inline]
pub fn basis_and_derivative_into(
    n: usize,
    t: f64,
    value: &mut [f64; MAX_DEGREE + 1],
    slope: &mut [f64; MAX_DEGREE + 1],
) {
    if n == 0 {
        value[0] = 1.0;
        slope[0] = 0.0;
        return;
    }
    // One triangle, of degree n − 1, in place; its last step, taken from the top down so that
    // every entry still holds the lower degree when read, gives the values, and the differences
    // the derivative.
    basis(n - 1, t, value);
    let (s, scale) = (1.0 - t, n as f64);
    for i in (1..=n).rev() {
        let (hi, lo) = (if i < n { value[i] } else { 0.0 }, value[i - 1]);
        slope[i] = scale * (lo - hi);
        value[i] = s * hi + t * lo;
    }
    slope[0] = -scale * value[0];
    value[0] *= s;
}

fn powi(x: f64, e: usize) -> f64 {
    let mut r = 1.0;
    for _ in 0..e {
        r *= x;
    }
    r
}

/// The longest array of points [`casteljau_level`] steps whole.
pub(crate) const STEP_WHOLE: usize = 8;

/// One level of de Casteljau's scheme: `p[i] ← p[i] + (p[i + 1] − p[i])·t` for `i ≤ last`, the
/// level's points. A short `p` (the nets of one degree on every axis, up to degree 7) is stepped
/// whole, a loop of constant length that unrolls: the entries above `last` are never read by
/// those below, so the level's points are made by the same operations either way.
#[inline(always)]
pub(crate) fn casteljau_level<const L: usize>(p: &mut [f64; L], t: f64, last: usize) {
    let end = if L <= STEP_WHOLE { L - 1 } else { last + 1 };
    for i in 0..end {
        p[i] += (p[i + 1] - p[i]) * t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn binomial_pascal_rows() {
        assert_eq!(binomial(4, 2), 6.0);
        assert_eq!(binomial(16, 8), 12870.0);
        assert_eq!(binomial(3, 5), 0.0);
        assert_eq!(binomial(60, 30), 118_264_581_564_861_424.0);
        assert!(binomial(usize::MAX, 3).is_finite());
        for n in 1..=MAX_DEGREE {
            for k in 1..n {
                assert_eq!(binomial(n, k), binomial(n - 1, k - 1) + binomial(n - 1, k));
            }
        }
    }

    #[test]
    fn basis_derivative_matches_finite_differences() {
        let mut rng = Rng::new(7);
        for n in 1..=MAX_DEGREE {
            for _ in 0..20 {
                let t = rng.range(0.0, 1.0);
                let (value, slope) = basis_and_derivative(n, t);
                assert_eq!(value, basis_array(n, t));
                let h = 1e-6;
                let (up, down) = (basis_array(n, t + h), basis_array(n, t - h));
                for i in 0..=n {
                    let fd = (up[i] - down[i]) / (2.0 * h);
                    assert!(
                        (fd - slope[i]).abs() <= 1e-5 * (1.0 + fd.abs()),
                        "n={n} i={i}"
                    );
                }
                // Σ B_i' = 0: the basis sums to one everywhere.
                assert!(slope.iter().sum::<f64>().abs() < 1e-9 * n as f64 * n as f64);
            }
        }
    }

    #[test]
    fn bernstein_partition_of_unity() {
        let mut rng = Rng::new(1);
        for n in 1..=MAX_DEGREE {
            for _ in 0..50 {
                let t = rng.range(-0.5, 1.5);
                let b = basis_array(n, t);
                let sum: f64 = b.iter().sum();
                // Outside [0, 1] the terms alternate in sign and grow: the error is relative to Σ|B_i|.
                let scale: f64 = b.iter().map(|x| x.abs()).sum();
                assert!(
                    (sum - 1.0).abs() < 1e-14 * scale.max(1.0) * n as f64,
                    "n = {n}, t = {t}: Σ = {sum}"
                );
            }
        }
    }

    #[test]
    fn bernstein_symmetry() {
        let mut rng = Rng::new(2);
        for n in 1..=MAX_DEGREE {
            for _ in 0..20 {
                let t = rng.range(0.0, 1.0);
                for i in 0..=n {
                    let a = bernstein(n, i, t);
                    let b = bernstein(n, n - i, 1.0 - t);
                    assert!((a - b).abs() < 1e-14, "B_{i}^{n}({t}) = {a} ≠ {b}");
                }
            }
        }
    }

    #[test]
    fn bernstein_recurrence_equals_explicit_formula() {
        let mut rng = Rng::new(3);
        for n in 1..=MAX_DEGREE {
            let t = rng.range(0.0, 1.0);
            let b = basis_array(n, t);
            for (i, &bi) in b.iter().enumerate().take(n + 1) {
                assert!((bi - bernstein(n, i, t)).abs() < 1e-13);
            }
            assert!(b[n + 1..].iter().all(|&x| x == 0.0));
        }
    }
}
