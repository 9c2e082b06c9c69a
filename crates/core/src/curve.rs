//! Bézier curves `C(t) = Σ_i P_i B_i^n(t)` of any degree 1 to [`MAX_DEGREE`].

use alloc::vec::Vec;

use crate::bernstein::{MAX_DEGREE, basis_array};
use crate::tensor::{ControlPoint, PatchError};

/// A Bézier curve of degree `n = points.len() − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct BezierCurve<P> {
    points: Vec<P>,
}

impl<P: ControlPoint> BezierCurve<P> {
    /// A curve through its `n + 1` control points, `1 ≤ n ≤ MAX_DEGREE`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] for fewer than 2 or more than `MAX_DEGREE + 1` points.
    pub fn try_new(points: Vec<P>) -> Result<Self, PatchError> {
        let n = points.len().saturating_sub(1);
        if n == 0 || n > MAX_DEGREE {
            return Err(PatchError::Degree { degree: n });
        }
        Ok(Self { points })
    }

    /// The degree `n`.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// The control points.
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// `C(t)` in basis form.
    #[must_use]
    pub fn eval(&self, t: f64) -> P {
        let b = basis_array(self.degree(), t);
        self.points
            .iter()
            .zip(&b)
            .fold(P::ZERO, |acc, (p, &w)| acc + *p * w)
    }

    /// `C(t)` by de Casteljau (the reference for [`BezierCurve::eval`]).
    #[must_use]
    pub fn eval_de_casteljau(&self, t: f64) -> P {
        self.split(t).0.points[self.degree()]
    }

    /// The derivative `C′(t) = n Σ_i (P_(i+1) − P_i) B_i^(n−1)(t)` as a curve of degree `n − 1`; `None`
    /// for a line, whose derivative is the constant `P_1 − P_0`.
    #[must_use]
    pub fn derivative(&self) -> Option<Self> {
        let n = self.degree();
        (n >= 2).then(|| Self {
            points: self
                .points
                .windows(2)
                .map(|w| (w[1] - w[0]) * n as f64)
                .collect(),
        })
    }

    /// `C′(t)`.
    #[must_use]
    pub fn eval_derivative(&self, t: f64) -> P {
        match self.derivative() {
            Some(d) => d.eval(t),
            None => self.points[1] - self.points[0],
        }
    }

    /// De Casteljau split at `t`: the curves on `[0, t]` and `[t, 1]`, each reparametrised to `[0, 1]`.
    #[must_use]
    pub fn split(&self, t: f64) -> (Self, Self) {
        let n = self.degree();
        let mut work = self.points.clone();
        let mut left = Vec::with_capacity(n + 1);
        let mut right = Vec::with_capacity(n + 1);
        left.push(work[0]);
        right.push(work[n]);
        for k in 1..=n {
            for i in 0..=n - k {
                work[i] = work[i] * (1.0 - t) + work[i + 1] * t;
            }
            left.push(work[0]);
            right.push(work[n - k]);
        }
        right.reverse();
        (Self { points: left }, Self { points: right })
    }

    /// The componentwise box of the control points, which holds the curve over `[0, 1]`.
    #[must_use]
    pub fn bounds(&self) -> (P, P) {
        crate::tensor::bounds_of(&self.points)
    }

    /// Degree elevation by one: the same curve with `n + 2` control points,
    /// `Q_i = (i/(n+1)) P_(i−1) + (1 − i/(n+1)) P_i`.
    ///
    /// # Errors
    ///
    /// [`PatchError::Degree`] when the curve already has degree `MAX_DEGREE`.
    pub fn elevate(&self) -> Result<Self, PatchError> {
        let n = self.degree();
        if n + 1 > MAX_DEGREE {
            return Err(PatchError::Degree { degree: n + 1 });
        }
        let mut q = Vec::with_capacity(n + 2);
        q.push(self.points[0]);
        for i in 1..=n {
            let a = i as f64 / (n + 1) as f64;
            q.push(self.points[i - 1] * a + self.points[i] * (1.0 - a));
        }
        q.push(self.points[n]);
        Ok(Self { points: q })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn random_curve(rng: &mut Rng) -> BezierCurve<DVec3> {
        let n = rng.int(1, MAX_DEGREE);
        let pts = (0..=n).map(|_| {
            DVec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            )
        });
        BezierCurve::try_new(pts.collect()).unwrap()
    }

    #[test]
    fn curve_basis_form_equals_de_casteljau() {
        let mut rng = Rng::new(50);
        for _ in 0..200 {
            let c = random_curve(&mut rng);
            let t = rng.range(-0.2, 1.2);
            assert!((c.eval(t) - c.eval_de_casteljau(t)).abs().max_element() < 1e-9);
        }
    }

    #[test]
    fn curve_derivative_matches_finite_differences() {
        let mut rng = Rng::new(51);
        for _ in 0..200 {
            let c = random_curve(&mut rng);
            let t = rng.range(0.05, 0.95);
            let h = 1e-6;
            let fd = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
            let d = c.eval_derivative(t);
            assert!(
                (fd - d).abs().max_element() < 1e-5 * d.abs().max_element().max(1.0),
                "{fd} vs {d}"
            );
        }
    }

    #[test]
    fn curve_split_halves_reproduce_the_curve() {
        let mut rng = Rng::new(52);
        for _ in 0..100 {
            let c = random_curve(&mut rng);
            let t = rng.range(0.1, 0.9);
            let (a, b) = c.split(t);
            for _ in 0..10 {
                let s = rng.range(0.0, 1.0);
                assert!((a.eval(s) - c.eval(s * t)).abs().max_element() < 1e-9);
                assert!((b.eval(s) - c.eval(t + s * (1.0 - t))).abs().max_element() < 1e-9);
            }
        }
    }

    #[test]
    fn curve_elevation_preserves_every_point() {
        let mut rng = Rng::new(53);
        for _ in 0..100 {
            let c = random_curve(&mut rng);
            let Ok(e) = c.elevate() else {
                assert_eq!(c.degree(), MAX_DEGREE);
                continue;
            };
            assert_eq!(e.degree(), c.degree() + 1);
            for _ in 0..10 {
                let s = rng.range(0.0, 1.0);
                assert!((e.eval(s) - c.eval(s)).abs().max_element() < 1e-10);
            }
        }
    }

    #[test]
    fn curve_rejects_bad_degrees() {
        assert!(BezierCurve::<f64>::try_new(alloc::vec![1.0]).is_err());
        assert!(BezierCurve::<f64>::try_new(alloc::vec![0.0; MAX_DEGREE + 2]).is_err());
    }
}
