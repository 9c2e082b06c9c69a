//! Radial-basis interpolation `s(p) = a₀ + A·p + Σ_k w_k φ(|p − p_k|)` from `R^D` to `R^D`: the
//! thin-plate spline `φ(r) = r² log r` in 2D and the volume splines `φ(r) = r` (biharmonic) or
//! `φ(r) = r³` (triharmonic) in 3D, the approximate inverse map of the paper's §3.3.2.
//!
//! The fit is made robust for nets a user drags anywhere: coordinates are normalised to the unit
//! ball, coincident sites are merged (their values averaged), the saddle-point system is solved by
//! LU with partial pivoting and the interpolation residual is checked; a system that is singular or
//! inaccurate falls back to the least-squares affine map, and that to a constant.

use alloc::vec;
use alloc::vec::Vec;

use crate::math::sqrt;

/// The radial function `φ`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// `r² log r`: the thin-plate spline, the biharmonic Green's function of 2D.
    ThinPlate,
    /// `r`: the biharmonic Green's function of 3D.
    Linear,
    /// `r³`: the triharmonic Green's function of 3D.
    Cubic,
}

impl Kernel {
    fn phi_r2(self, r2: f64) -> f64 {
        match self {
            Self::ThinPlate => {
                if r2 > 0.0 {
                    0.5 * r2 * libm::log(r2)
                } else {
                    0.0
                }
            }
            Self::Linear => sqrt(r2),
            Self::Cubic => r2 * sqrt(r2),
        }
    }
}

/// Which form the fit took.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplineForm {
    /// The radial-basis interpolant.
    Radial,
    /// The least-squares affine map (the radial system was singular or inaccurate).
    Affine,
    /// The mean value (fewer than `D + 1` distinct sites in general position).
    Constant,
}

/// A fitted spline `R^D → R^D`.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline<const D: usize> {
    kernel: Kernel,
    form: SplineForm,
    centre: [f64; D],
    inv_scale: f64,
    sites: Vec<[f64; D]>,
    weights: Vec<[f64; D]>,
    /// Row 0 the constant, row `1 + c` the coefficient of normalised coordinate `c`.
    affine: Vec<[f64; D]>,
}

/// The relative residual above which an interpolant is not trusted.
const MAX_RESIDUAL: f64 = 1e-6;

impl<const D: usize> Spline<D> {
    /// Fit `s(sites[k]) = values[k]`. Never fails: see the module's fallbacks and [`Spline::form`].
    ///
    /// # Panics
    ///
    /// If `sites` and `values` differ in length.
    #[must_use]
    pub fn fit(kernel: Kernel, sites: &[[f64; D]], values: &[[f64; D]]) -> Self {
        assert_eq!(sites.len(), values.len(), "one value per site");
        let (lo, hi) = sites.iter().fold(
            ([f64::INFINITY; D], [f64::NEG_INFINITY; D]),
            |(mut lo, mut hi), s| {
                for c in 0..D {
                    lo[c] = lo[c].min(s[c]);
                    hi[c] = hi[c].max(s[c]);
                }
                (lo, hi)
            },
        );
        let centre: [f64; D] = core::array::from_fn(|c| {
            if lo[c].is_finite() {
                0.5 * (lo[c] + hi[c])
            } else {
                0.0
            }
        });
        let half = (0..D).map(|c| 0.5 * (hi[c] - lo[c])).fold(0.0f64, f64::max);
        let inv_scale = if half > 0.0 && half.is_finite() {
            1.0 / half
        } else {
            1.0
        };
        let mut spline = Self {
            kernel,
            form: SplineForm::Constant,
            centre,
            inv_scale,
            sites: Vec::new(),
            weights: Vec::new(),
            affine: vec![[0.0; D]; D + 1],
        };
        // Normalise and merge coincident sites.
        let mut merged: Vec<([f64; D], [f64; D], f64)> = Vec::new();
        for (s, v) in sites.iter().zip(values) {
            let q = spline.normalise(*s);
            if let Some(m) = merged.iter_mut().find(|m| dist2(m.0, q) < 1e-18) {
                for c in 0..D {
                    m.1[c] += v[c];
                }
                m.2 += 1.0;
            } else {
                merged.push((q, *v, 1.0));
            }
        }
        let pts: Vec<[f64; D]> = merged.iter().map(|m| m.0).collect();
        let vals: Vec<[f64; D]> = merged
            .iter()
            .map(|m| core::array::from_fn(|c| m.1[c] / m.2))
            .collect();
        if vals.is_empty() {
            return spline;
        }
        let mean: [f64; D] =
            core::array::from_fn(|c| vals.iter().map(|v| v[c]).sum::<f64>() / vals.len() as f64);
        spline.affine[0] = mean;
        if pts.len() > D && spline.fit_radial(&pts, &vals) {
            return spline;
        }
        spline.fit_affine(&pts, &vals);
        spline
    }

    /// Which form the fit took.
    #[must_use]
    pub fn form(&self) -> SplineForm {
        self.form
    }

    fn normalise(&self, p: [f64; D]) -> [f64; D] {
        core::array::from_fn(|c| (p[c] - self.centre[c]) * self.inv_scale)
    }

    fn fit_radial(&mut self, pts: &[[f64; D]], vals: &[[f64; D]]) -> bool {
        let n = pts.len();
        let size = n + D + 1;
        let mut a = vec![0.0; size * size];
        for r in 0..n {
            for c in 0..n {
                a[r * size + c] = self.kernel.phi_r2(dist2(pts[r], pts[c]));
            }
            a[r * size + n] = 1.0;
            a[n * size + r] = 1.0;
            for d in 0..D {
                a[r * size + n + 1 + d] = pts[r][d];
                a[(n + 1 + d) * size + r] = pts[r][d];
            }
        }
        let mut rhs = vec![[0.0; D]; size];
        rhs[..n].copy_from_slice(vals);
        let Some(x) = solve(a, size, rhs) else {
            return false;
        };
        self.sites = pts.to_vec();
        self.weights = x[..n].to_vec();
        self.affine = x[n..].to_vec();
        self.form = SplineForm::Radial;
        let range = vals
            .iter()
            .flat_map(|v| v.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1.0);
        let residual = pts
            .iter()
            .zip(vals)
            .map(|(p, v)| {
                let got = self.eval_normalised(*p);
                (0..D).fold(0.0f64, |m, c| m.max((got[c] - v[c]).abs()))
            })
            .fold(0.0f64, f64::max);
        if residual.is_finite() && residual <= MAX_RESIDUAL * range {
            true
        } else {
            self.sites.clear();
            self.weights.clear();
            false
        }
    }

    fn fit_affine(&mut self, pts: &[[f64; D]], vals: &[[f64; D]]) {
        // Normal equations of the least-squares affine map (pivoted; singular means constant).
        let size = D + 1;
        let mut a = vec![0.0; size * size];
        let mut rhs = vec![[0.0; D]; size];
        for (p, v) in pts.iter().zip(vals) {
            let row: Vec<f64> = core::iter::once(1.0).chain(p.iter().copied()).collect();
            for r in 0..size {
                for c in 0..size {
                    a[r * size + c] += row[r] * row[c];
                }
                for d in 0..D {
                    rhs[r][d] += row[r] * v[d];
                }
            }
        }
        if let Some(x) = solve(a, size, rhs) {
            self.affine = x;
            self.form = SplineForm::Affine;
        }
    }

    fn eval_normalised(&self, q: [f64; D]) -> [f64; D] {
        let mut out = self.affine[0];
        for c in 0..D {
            for d in 0..D {
                out[d] += self.affine[1 + c][d] * q[c];
            }
        }
        for (s, w) in self.sites.iter().zip(&self.weights) {
            let phi = self.kernel.phi_r2(dist2(*s, q));
            for d in 0..D {
                out[d] += w[d] * phi;
            }
        }
        out
    }

    /// `s(p)`.
    #[must_use]
    pub fn eval(&self, p: [f64; D]) -> [f64; D] {
        self.eval_normalised(self.normalise(p))
    }

    /// The fitted spline's numbers, for a program that evaluates it as [`Spline::eval`] does (the
    /// HyperFun export): the kernel, the normalisation `q = (p − centre)·inv_scale`, the sites
    /// (normalised) and their weights, and the affine part (row 0 the constant, row `1 + c` the
    /// coefficient of `q_c`). `s(p) = affine₀ + Σ_c affine_{1+c} q_c + Σ_k w_k φ(|q − site_k|²)`,
    /// summed in that order.
    pub(crate) fn parts(&self) -> SplineParts<'_, D> {
        SplineParts {
            kernel: self.kernel,
            centre: self.centre,
            inv_scale: self.inv_scale,
            sites: &self.sites,
            weights: &self.weights,
            affine: &self.affine,
        }
    }
}

/// A spline's numbers ([`Spline::parts`]).
pub(crate) struct SplineParts<'a, const D: usize> {
    pub(crate) kernel: Kernel,
    pub(crate) centre: [f64; D],
    pub(crate) inv_scale: f64,
    pub(crate) sites: &'a [[f64; D]],
    pub(crate) weights: &'a [[f64; D]],
    pub(crate) affine: &'a [[f64; D]],
}

fn dist2<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    (0..D).map(|c| (a[c] - b[c]) * (a[c] - b[c])).sum()
}

/// Solve `A x = b` (`A` row-major `n × n`, `D` right-hand sides) by LU with partial pivoting; `None`
/// when a pivot is negligible against the matrix's scale.
pub(crate) fn solve<const D: usize>(
    mut a: Vec<f64>,
    n: usize,
    mut b: Vec<[f64; D]>,
) -> Option<Vec<[f64; D]>> {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let tiny = scale * 1e-13;
    for k in 0..n {
        let (p, pivot) = (k..n)
            .map(|r| (r, a[r * n + k].abs()))
            .fold((k, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        if pivot <= tiny {
            return None;
        }
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
            b.swap(k, p);
        }
        let inv = 1.0 / a[k * n + k];
        for r in k + 1..n {
            let factor = a[r * n + k] * inv;
            if factor == 0.0 {
                continue;
            }
            for c in k + 1..n {
                a[r * n + c] -= factor * a[k * n + c];
            }
            let bk = b[k];
            for d in 0..D {
                b[r][d] -= factor * bk[d];
            }
        }
    }
    for k in (0..n).rev() {
        let mut x = b[k];
        for c in k + 1..n {
            for d in 0..D {
                x[d] -= a[k * n + c] * b[c][d];
            }
        }
        for v in &mut x {
            *v /= a[k * n + k];
        }
        b[k] = x;
    }
    b.iter().flatten().all(|v| v.is_finite()).then_some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn interpolates_and_reproduces_affine_maps() {
        let mut rng = Rng::new(3);
        for kernel in [Kernel::ThinPlate] {
            let sites: Vec<[f64; 2]> = (0..30)
                .map(|_| [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)])
                .collect();
            let affine = |p: [f64; 2]| [0.3 + 2.0 * p[0] - p[1], -1.0 + 0.5 * p[1]];
            let values: Vec<[f64; 2]> = sites.iter().map(|&p| affine(p)).collect();
            let s = Spline::fit(kernel, &sites, &values);
            assert_eq!(s.form(), SplineForm::Radial);
            for _ in 0..20 {
                let p = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
                let (got, want) = (s.eval(p), affine(p));
                assert!((got[0] - want[0]).abs() < 1e-8 && (got[1] - want[1]).abs() < 1e-8);
            }
        }
        for kernel in [Kernel::Linear, Kernel::Cubic] {
            let sites: Vec<[f64; 3]> = (0..40)
                .map(|_| core::array::from_fn(|_| rng.range(0.0, 2.0)))
                .collect();
            let values: Vec<[f64; 3]> = sites
                .iter()
                .map(|p| [p[0] * p[1], p[2].sin(), p[0] - p[2]])
                .collect();
            let s = Spline::fit(kernel, &sites, &values);
            assert_eq!(s.form(), SplineForm::Radial);
            for (p, v) in sites.iter().zip(&values) {
                let got = s.eval(*p);
                for c in 0..3 {
                    assert!((got[c] - v[c]).abs() < 1e-8, "{kernel:?}");
                }
            }
        }
    }

    #[test]
    fn degenerate_sites_fall_back() {
        // All sites equal: one merged site, the mean.
        let s = Spline::fit(Kernel::ThinPlate, &[[1.0, 1.0]; 5], &[[0.5, 0.25]; 5]);
        assert_eq!(s.form(), SplineForm::Constant);
        assert_eq!(s.eval([7.0, -3.0]), [0.5, 0.25]);
        // Collinear sites: the radial system is singular; the affine fit is singular too.
        let sites: Vec<[f64; 2]> = (0..6).map(|i| [f64::from(i), 2.0 * f64::from(i)]).collect();
        let values: Vec<[f64; 2]> = (0..6).map(|i| [f64::from(i) / 5.0, 0.0]).collect();
        let s = Spline::fit(Kernel::ThinPlate, &sites, &values);
        assert_ne!(s.form(), SplineForm::Radial);
        assert!(s.eval([2.5, 5.0]).iter().all(|v| v.is_finite()));
        // Duplicated sites with different values are averaged, not a singular system.
        let sites = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 1.0]];
        let values = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.0, 0.0]];
        let s = Spline::fit(Kernel::ThinPlate, &sites, &values);
        assert_eq!(s.form(), SplineForm::Radial);
        let v = s.eval([1.0, 1.0]);
        assert!((v[0] - 0.5).abs() < 1e-9 && (v[1] - 0.5).abs() < 1e-9);
    }
}
