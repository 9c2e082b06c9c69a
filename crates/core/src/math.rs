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

/// The box `[lo, hi]` widened, around its middle, along every side too thin to hold distinct
/// samples: each side is at least a millionth of the longest side, and at least `2⁻³⁶` of the
/// largest coordinate magnitude (a grid of 512 cells over it has cells of a hundred units in the
/// last place or more) and 1e-300, so that a grid over it has cells wider than rounding and a
/// margin outside it. A net whose points share a coordinate (to within rounding) has such a side.
/// The box is placed by the model's own extent: a unit sphere at 1e8 keeps its box of side 2 (a
/// millionth of the coordinate, 100, made it a speck in one cell).
pub(crate) fn sampling_box<const D: usize>(
    mut lo: [f64; D],
    mut hi: [f64; D],
) -> ([f64; D], [f64; D]) {
    let side = (0..D).map(|a| hi[a] - lo[a]).fold(0.0f64, f64::max);
    let magnitude = (0..D)
        .map(|a| lo[a].abs().max(hi[a].abs()))
        .fold(0.0f64, f64::max);
    let least = (side * 1e-6)
        .max(magnitude * 1.455_191_522_836_685_2e-11)
        .max(1e-300);
    for a in 0..D {
        if hi[a] - lo[a] < least {
            let middle = 0.5 * lo[a] + 0.5 * hi[a];
            (lo[a], hi[a]) = (middle - 0.5 * least, middle + 0.5 * least);
        }
    }
    (lo, hi)
}

/// The most evaluations [`illinois`] makes.
pub(crate) const ROOT_STEPS: u32 = 60;

/// Where [`illinois`] stops closing in on a jump (of the unit interval).
const JUMP_WIDTH: f64 = 1e-9;

/// A zero of `g` on `[0, 1]`, where `g(0) = f0` and `g(1) = f1` have opposite signs: Illinois
/// regula falsi, safeguarded by bisection so that the bracket at least halves every two steps, in
/// at most [`ROOT_STEPS`] evaluations of `g`. The best `t` found once `|g(t)| ≤ accuracy`. Where
/// `g` jumps across zero instead (`f` where a space mapping folds), `|g|` stops shrinking: after
/// three such steps only bisection is used, the bracket closes on the jump (to `1e-9`), and its
/// middle is returned: the vertex lies on the fold.
pub(crate) fn illinois(mut g: impl FnMut(f64) -> f64, f0: f64, f1: f64, accuracy: f64) -> f64 {
    let (mut t0, mut t1, mut f0, mut f1) = (0.0, 1.0, f0, f1);
    let mut best = if f0.abs() <= f1.abs() {
        (t0, f0)
    } else {
        (t1, f1)
    };
    let mut side = 0i8;
    // The bracket's width two steps ago, and the steps since it halved; the steps in a row that
    // did not halve the best |g|.
    let (mut reference, mut since, mut stalled) = (1.0f64, 0u32, 0u32);
    for _ in 0..ROOT_STEPS {
        let jump = stalled >= 3;
        if best.1.abs() <= accuracy || t1 - t0 <= if jump { JUMP_WIDTH } else { 1e-12 } {
            break;
        }
        let bisect = since >= 2 || jump;
        let denom = f1 - f0;
        let mut t = if denom != 0.0 && !bisect {
            (t0 * f1 - t1 * f0) / denom
        } else {
            0.5 * (t0 + t1)
        };
        if !(t > t0 && t < t1) {
            t = 0.5 * (t0 + t1);
        }
        let ft = g(t);
        if ft.abs() <= 0.5 * best.1.abs() {
            stalled = 0;
        } else {
            stalled += 1;
        }
        if ft.abs() < best.1.abs() {
            best = (t, ft);
        }
        if (ft > 0.0) == (f1 > 0.0) {
            t1 = t;
            f1 = ft;
            if side == 1 {
                f0 *= 0.5;
            }
            side = 1;
        } else {
            t0 = t;
            f0 = ft;
            if side == -1 {
                f1 *= 0.5;
            }
            side = -1;
        }
        since += 1;
        if t1 - t0 <= 0.5 * reference || bisect {
            reference = t1 - t0;
            since = 0;
        }
    }
    if best.1.abs() <= accuracy {
        best.0
    } else {
        0.5 * (t0 + t1)
    }
}
