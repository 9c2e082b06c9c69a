//! Scalar math that works with and without `std`.

/// `√(x² + y²)` without overflow or underflow.
#[inline]
pub(crate) fn hypot(x: f64, y: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.hypot(y)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::hypot(x, y)
    }
}
