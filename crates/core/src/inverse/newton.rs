//! Newton's method for `S(u) = p`: the step every inverse path ends with, and the tolerances that
//! say when it has arrived.
//!
//! Parameters live in the unit box `[0, 1]^D` and residuals are measured against the net's
//! extent (`scale`, the largest coordinate magnitude of its control points), so every tolerance
//! below is relative and holds for a net of any size.

use super::{Forward, QueryStats, max_abs_diff, solve_jac};

/// A residual at most this fraction of the net's extent is rounding noise of the evaluation
/// itself (a few units in the last place of `f64`): the iterate is a root.
pub(crate) const ROUNDING_RESIDUAL: f64 = 1e-15;

/// A Newton step no longer than this (in parameters) has settled: the iterate sits at the
/// rounding level of the parameters, and only its residual is left to check.
pub(crate) const SETTLED_STEP: f64 = 1e-13;

/// After a settled step, a residual up to this fraction of the net's extent still marks a root:
/// at a fold's double root Newton converges only linearly and the residual stays well above
/// rounding, yet six orders of magnitude below any feature of the model.
pub(crate) const ROOT_RESIDUAL: f64 = 1e-9;

/// A residual up to this fraction of the net's extent verifies a root of the fast path: near
/// rounding, yet loose enough for the evaluation's own error at high degree.
pub(crate) const VERIFIED_RESIDUAL: f64 = 1e-13;

/// Once a step is below this, quadratic convergence puts the next iterate within about its square
/// (`1e-14`) of the root: the fast path stops there and lets the evaluation it needs anyway verify.
pub(crate) const QUICK_STEP: f64 = 1e-7;

/// Parameters this far outside the unit box mean Newton has left for another branch of the
/// polynomial: the iteration is abandoned.
pub(crate) const ESCAPE: f64 = 8.0;

/// When [`newton`] stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Until {
    /// At a root: the residual at [`ROUNDING_RESIDUAL`], or a [settled](SETTLED_STEP) step whose
    /// residual, checked with one more evaluation, is within [`ROOT_RESIDUAL`].
    Root,
    /// At a step below [`QUICK_STEP`], with no closing evaluation: the caller verifies the
    /// iterate with the evaluation it needs anyway (and steps on where that fails).
    QuickStep,
}

/// Newton's method for `S(u) = p` from `u`, at most `max_steps` steps, stopping as `until` says;
/// `None` when it diverges ([`ESCAPE`]), stalls or meets a singular Jacobian. `scale` is the net's
/// extent, the unit of its residuals.
pub(crate) fn newton<const D: usize, F: Forward<D>>(
    net: &F,
    p: [f64; D],
    mut u: [f64; D],
    scale: f64,
    max_steps: u32,
    until: Until,
    stats: &mut QueryStats,
) -> Option<[f64; D]> {
    let rounding = scale.max(f64::MIN_POSITIVE) * ROUNDING_RESIDUAL;
    for _ in 0..max_steps {
        let e = net.forward(u);
        let r: [f64; D] = core::array::from_fn(|c| e.x[c] - p[c]);
        if until == Until::Root && r.iter().all(|v| v.abs() <= rounding) {
            return Some(u);
        }
        let delta = solve_jac(&e.jac, r)?;
        stats.newton_steps += 1;
        for c in 0..D {
            u[c] -= delta[c];
        }
        if !u.iter().all(|t| t.abs() < ESCAPE) {
            return None;
        }
        let step = delta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        match until {
            Until::QuickStep if step <= QUICK_STEP => return Some(u),
            Until::Root if step <= SETTLED_STEP => {
                let res = max_abs_diff(net.forward(u).x, p);
                return (res <= scale * ROOT_RESIDUAL).then_some(u);
            }
            _ => {}
        }
    }
    None
}
