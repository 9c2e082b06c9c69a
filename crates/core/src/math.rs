//! Scalar math that works with and without `std`.

/// `√(x² + y²)` without overflow or underflow: the plain formula (a hardware square root) where the
/// squares are safely inside the range of `f64`, the careful library `hypot` elsewhere.
#[inline]
pub(crate) fn hypot(x: f64, y: f64) -> f64 {
    let big = x.abs().max(y.abs());
    if big > 1e-150 && big < 1e150 {
        return sqrt(x * x + y * y);
    }
    #[cfg(feature = "std")]
    {
        x.hypot(y)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::hypot(x, y)
    }
}

/// `√x`.
#[inline]
pub(crate) fn sqrt(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}
