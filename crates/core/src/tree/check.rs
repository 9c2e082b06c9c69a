//! The numbers a tree's nodes may hold: finite, and within the magnitudes that `f` can be
//! evaluated with in `f64` along the node's path.
//!
//! Every coordinate, offset, blend amplitude and morph parameter lies within `±1e12` (the bound of
//! a Bézier net's control values, [`Solid::MAX_COORDINATE`]), and every size that scales a formula
//! (a radius, a torus's radii, a blend's `a1` and `a2`, a transform's scale) between `1e-12` and
//! `1e12` in magnitude; the scales of the transforms on the way down to a solid multiply to within
//! the same range. So a leaf's own numbers square without overflow or underflow, its map from
//! space and back have entries within `1e12`, and what still overflows is the point itself, far
//! away, which [`super::far`] evaluates at the ends of the doubles.

use alloc::format;

use super::error;
use crate::model::ModelError;
use crate::solid::Solid;

/// The largest magnitude of a coordinate or a size.
pub(super) const MAX_MAGNITUDE: f64 = Solid::<3>::MAX_COORDINATE;

/// The smallest magnitude of a size (a radius, a scale).
pub(super) const MIN_SIZE: f64 = 1.0 / MAX_MAGNITUDE;

fn refused(path: &str, message: impl Into<alloc::string::String>) -> ModelError {
    ModelError::Tree(error(path, message))
}

/// A finite number (of any magnitude: an angle).
pub(super) fn finite(v: f64, path: &str) -> Result<(), ModelError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(refused(path, format!("{v} is not a finite number")))
    }
}

/// A finite number within `±MAX_MAGNITUDE`.
pub(super) fn bounded(v: f64, path: &str) -> Result<(), ModelError> {
    finite(v, path)?;
    if v.abs() > MAX_MAGNITUDE {
        Err(refused(
            path,
            format!("{v:e} is too large: at most {MAX_MAGNITUDE:e} in magnitude"),
        ))
    } else {
        Ok(())
    }
}

/// A size: within `MIN_SIZE..=MAX_MAGNITUDE` in magnitude.
fn size(v: f64, path: &str) -> Result<(), ModelError> {
    bounded(v, path)?;
    if v.abs() < MIN_SIZE {
        Err(refused(
            path,
            format!("{v:e} is too small: a size is at least {MIN_SIZE:e} in magnitude"),
        ))
    } else {
        Ok(())
    }
}

/// A positive size (a radius).
pub(super) fn positive(v: f64, path: &str) -> Result<(), ModelError> {
    finite(v, path)?;
    if v > 0.0 {
        size(v, path)
    } else {
        Err(refused(path, format!("must be positive (it is {v})")))
    }
}

/// A size of either sign (a blend's `a1`, a scale).
pub(super) fn non_zero(v: f64, path: &str) -> Result<(), ModelError> {
    finite(v, path)?;
    if v == 0.0 {
        Err(refused(path, "must not be zero"))
    } else {
        size(v, path)
    }
}

/// `values` as `D` numbers within `±MAX_MAGNITUDE`.
pub(super) fn finite_array<const D: usize>(
    values: &[f64],
    path: &str,
) -> Result<[f64; D], ModelError> {
    let array: [f64; D] = values.try_into().map_err(|_| {
        refused(
            path,
            format!("{} numbers where a {D}D tree takes {D}", values.len()),
        )
    })?;
    for (i, v) in array.iter().enumerate() {
        bounded(*v, &format!("{path}[{i}]"))?;
    }
    Ok(array)
}

/// The least and greatest factor by which the transforms down to a node scale lengths (a turn
/// keeps them), given the range `(lo, hi)` above it and this transform's scale: within
/// `MIN_SIZE..=MAX_MAGNITUDE`, or refused at `path`.
pub(super) fn scale_range(
    (lo, hi): (f64, f64),
    scale: &[f64],
    path: &str,
) -> Result<(f64, f64), ModelError> {
    let least = scale.iter().fold(f64::INFINITY, |m, s| m.min(s.abs()));
    let most = scale.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    let (lo, hi) = (lo * least, hi * most);
    if lo < MIN_SIZE || hi > MAX_MAGNITUDE {
        let overall = if lo < MIN_SIZE { lo } else { hi };
        return Err(refused(
            path,
            format!(
                "the transforms down to here scale by {overall:e} overall; their scales must \
                 multiply to within {MIN_SIZE:e} and {MAX_MAGNITUDE:e}"
            ),
        ));
    }
    Ok((lo, hi))
}
