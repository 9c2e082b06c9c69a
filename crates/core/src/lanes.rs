//! The kernel of the grid evaluations: a net's line of coefficients weighed against the basis rows
//! of many samples at once, samples side by side in SIMD lanes.
//!
//! A sample's value is `Σ_i c_i · b_i(t)`, summed from zero in the order of `i` — the order a
//! sample is summed in one at a time, so [`Tensor::eval_grid`](crate::Tensor::eval_grid) and the
//! adaptive mesher's blocks agree to the bit. Across samples nothing is shared, so the sums of neighbouring
//! samples run in the lanes of one vector: `f64x2` of wasm `simd128` where the build enables it
//! (the page's and the tools' modules do), and the compiler's vectors natively (SSE2 on x86-64,
//! NEON on aarch64) from the same blocked loop. No fused multiply-add: a fused sum rounds once
//! where the scalar path rounds twice, and the paths would part by an ulp.

use alloc::vec;
use alloc::vec::Vec;

use crate::bernstein::MAX_DEGREE;

/// Samples summed together in [`weigh`]'s inner loop: two vectors of two lanes, or four lanes of
/// one; the sums of a block stay in registers while the coefficients go by.
const BLOCK: usize = 4;

/// Appends `out[k] = Σ_i coeffs[i] · rows[i · stride + k]` for every `k < count` to `out`, summed
/// from zero in the order of `i`: the basis rows are stored transposed, one row per coefficient with
/// a value per sample, `stride` values apart. `out` grows by `count` zeros, which the sums then
/// overwrite block by block.
///
/// # Panics
/// Where `rows` is shorter than `(coeffs.len() − 1) · stride + count` (a caller's bug: the tables
/// are sized with the samples).
#[inline]
pub(crate) fn weigh(coeffs: &[f64], rows: &[f64], stride: usize, count: usize, out: &mut Vec<f64>) {
    if let Some(last) = coeffs.len().checked_sub(1) {
        assert!(rows.len() >= last * stride + count, "basis rows too short");
    }
    let start = out.len();
    // Zeros first, then the sums over them: a fill is cheap beside a push a value.
    out.resize(start + count, 0.0);
    let out = &mut out[start..];
    // A fixed count of coefficients (degrees 1 to 7) unrolls the inner loop.
    match coeffs.len() {
        2 => fixed::<2>(coeffs, rows, stride, out),
        3 => fixed::<3>(coeffs, rows, stride, out),
        4 => fixed::<4>(coeffs, rows, stride, out),
        5 => fixed::<5>(coeffs, rows, stride, out),
        6 => fixed::<6>(coeffs, rows, stride, out),
        7 => fixed::<7>(coeffs, rows, stride, out),
        8 => fixed::<8>(coeffs, rows, stride, out),
        _ => {
            let mut lines = [&[][..]; MAX_DEGREE + 1];
            for (i, line) in lines.iter_mut().enumerate().take(coeffs.len()) {
                *line = &rows[i * stride..i * stride + out.len()];
            }
            blocks(coeffs, &lines[..coeffs.len()], out);
        }
    }
}

/// [`weigh`] for `N` coefficients.
#[inline(always)]
fn fixed<const N: usize>(coeffs: &[f64], rows: &[f64], stride: usize, out: &mut [f64]) {
    let len = out.len();
    let c: [f64; N] = core::array::from_fn(|i| coeffs[i]);
    let lines: [&[f64]; N] = core::array::from_fn(|i| &rows[i * stride..i * stride + len]);
    blocks(&c, &lines, out);
}

/// `out[k] = Σ_i coeffs[i] · lines[i][k]`: [`BLOCK`] samples at a time, then the rest one by one.
/// Every line is `out.len()` long.
#[inline(always)]
fn blocks(coeffs: &[f64], lines: &[&[f64]], out: &mut [f64]) {
    let done = out.len() / BLOCK * BLOCK;
    let mut chunks = out.chunks_exact_mut(BLOCK);
    for (b, sums) in (&mut chunks).enumerate() {
        block(coeffs, lines, b * BLOCK, sums);
    }
    for (j, slot) in chunks.into_remainder().iter_mut().enumerate() {
        *slot = coeffs
            .iter()
            .zip(lines)
            .fold(0.0, |acc, (&c, line)| acc + c * line[done + j]);
    }
}

/// [`BLOCK`] sums of [`weigh`], samples `k..k + BLOCK`, in wasm `simd128` vectors.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
#[inline(always)]
fn block(coeffs: &[f64], lines: &[&[f64]], k: usize, sums: &mut [f64]) {
    use core::arch::wasm32::{f64x2, f64x2_add, f64x2_extract_lane, f64x2_mul, f64x2_splat};
    let zero = f64x2_splat(0.0);
    let (mut lo, mut hi) = (zero, zero);
    for (&c, line) in coeffs.iter().zip(lines) {
        let c = f64x2_splat(c);
        let r = &line[k..k + BLOCK];
        lo = f64x2_add(lo, f64x2_mul(c, f64x2(r[0], r[1])));
        hi = f64x2_add(hi, f64x2_mul(c, f64x2(r[2], r[3])));
    }
    sums[0] = f64x2_extract_lane::<0>(lo);
    sums[1] = f64x2_extract_lane::<1>(lo);
    sums[2] = f64x2_extract_lane::<0>(hi);
    sums[3] = f64x2_extract_lane::<1>(hi);
}

/// [`BLOCK`] sums of [`weigh`], samples `k..k + BLOCK`: independent lanes the compiler puts in
/// vectors.
#[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
#[inline(always)]
fn block(coeffs: &[f64], lines: &[&[f64]], k: usize, sums: &mut [f64]) {
    let mut acc = [0.0; BLOCK];
    for (&c, line) in coeffs.iter().zip(lines) {
        for (a, &b) in acc.iter_mut().zip(&line[k..k + BLOCK]) {
            *a += c * b;
        }
    }
    sums.copy_from_slice(&acc);
}

/// The basis rows of `samples` sample rows of `width` values each (`table[s · width + i]`), turned
/// to one row per basis function with a value per sample (`out[i · samples + s]`): the layout
/// [`weigh`] reads.
pub(crate) fn transpose(table: &[f64], width: usize) -> Vec<f64> {
    if width == 0 {
        return Vec::new();
    }
    let samples = table.len() / width;
    let mut out = vec![0.0; table.len()];
    for (s, row) in table.chunks_exact(width).enumerate() {
        for (i, &b) in row.iter().enumerate() {
            out[i * samples + s] = b;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums of one sample as every scalar path makes them.
    fn scalar(coeffs: &[f64], column: impl Iterator<Item = f64>) -> f64 {
        coeffs
            .iter()
            .zip(column)
            .fold(0.0, |acc, (c, b)| acc + c * b)
    }

    #[test]
    fn the_lanes_sum_as_one_sample_at_a_time_does_to_the_bit() {
        // Values whose sums round differently in another order or fused.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for width in [1, 2, 5, 9, 17] {
            for samples in [0, 1, 3, 4, 7, 64, 129] {
                let table: Vec<f64> = (0..samples * width).map(|_| next() * 1e3).collect();
                let coeffs: Vec<f64> = (0..width).map(|_| next() * 1e-3 + next()).collect();
                let rows = transpose(&table, width);
                // The whole range, and a part of it from an offset, as a block of a grid reads it.
                let mut out = vec![f64::NAN];
                weigh(&coeffs, &rows, samples, samples, &mut out);
                assert!(out.remove(0).is_nan(), "what was there stays");
                for (s, &got) in out.iter().enumerate() {
                    let want = scalar(&coeffs, table[s * width..(s + 1) * width].iter().copied());
                    assert_eq!(
                        got.to_bits(),
                        want.to_bits(),
                        "sample {s} of {samples}, width {width}"
                    );
                }
                if samples > 2 {
                    let mut part = Vec::new();
                    weigh(&coeffs, &rows[1..], samples, samples - 2, &mut part);
                    assert_eq!(part, out[1..samples - 1]);
                }
            }
        }
    }

    #[test]
    fn a_sum_of_no_coefficients_is_zero() {
        let mut out = Vec::new();
        weigh(&[], &[], 6, 6, &mut out);
        assert_eq!(out, [0.0; 6]);
        assert!(transpose(&[], 0).is_empty());
    }
}
