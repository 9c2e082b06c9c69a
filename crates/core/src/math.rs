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

/// The most parts [`far_parts`] gives: past it the nearest are joined.
pub(crate) const MAX_PARTS: usize = 16;

/// Boxes `[lo, hi]` (none empty) gathered into parts far apart, to mesh each on a grid of its own:
/// two boxes nearer each other (along the axis where they are farthest apart) than the longer
/// side of either are one part, the hull of both, and so on until no two parts are that near; at
/// most [`MAX_PARTS`], the nearest (for their size) joined first. A part's grid, a cell or less
/// past it, never reaches another's box.
pub(crate) fn far_parts<const D: usize>(
    boxes: &[([f64; D], [f64; D])],
) -> alloc::vec::Vec<([f64; D], [f64; D])> {
    type Part<const D: usize> = ([f64; D], [f64; D]);
    let side = |b: &Part<D>| (0..D).map(|i| b.1[i] - b.0[i]).fold(0.0f64, f64::max);
    let gap = |a: &Part<D>, b: &Part<D>| {
        (0..D)
            .map(|i| (a.0[i] - b.1[i]).max(b.0[i] - a.1[i]))
            .fold(0.0f64, f64::max)
    };
    // How near two parts are, for their size: below 1 they are one part.
    let nearness = |a: &Part<D>, b: &Part<D>| gap(a, b) / side(a).max(side(b));
    let mut parts = boxes.to_vec();
    loop {
        let mut nearest: Option<(f64, usize, usize)> = None;
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                let n = nearness(&parts[i], &parts[j]);
                if nearest.is_none_or(|(m, _, _)| n < m) {
                    nearest = Some((n, i, j));
                }
            }
        }
        match nearest {
            // Near, or not a number (a side of no length): one part.
            Some((n, i, j)) if n < 1.0 || n.is_nan() || parts.len() > MAX_PARTS => {
                let b = parts.swap_remove(j);
                parts[i] = (
                    core::array::from_fn(|k| parts[i].0[k].min(b.0[k])),
                    core::array::from_fn(|k| parts[i].1[k].max(b.1[k])),
                );
            }
            _ => return parts,
        }
    }
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
