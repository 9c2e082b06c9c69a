//! Helpers shared by the unit tests: a small deterministic generator (tests run the same natively and
//! in node, where no OS randomness is needed).

/// xorshift64*: enough for test data, reproducible from its seed.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// Uniform integer in `lo..=hi`.
    pub(crate) fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
}

/// What [`assert_close!`] compares: numbers, glam vectors and arrays of numbers.
pub(crate) trait Approx: Copy + core::fmt::Debug {
    /// The largest difference of a component.
    fn max_abs_diff(self, other: Self) -> f64;
    /// The largest magnitude of a component.
    fn max_abs(self) -> f64;
}

impl Approx for f64 {
    fn max_abs_diff(self, other: Self) -> f64 {
        (self - other).abs()
    }
    fn max_abs(self) -> f64 {
        self.abs()
    }
}

macro_rules! glam_approx {
    ($($t:ty),*) => {$(
        impl Approx for $t {
            fn max_abs_diff(self, other: Self) -> f64 {
                (self - other).abs().max_element()
            }
            fn max_abs(self) -> f64 {
                self.abs().max_element()
            }
        }
    )*};
}
glam_approx!(glam::DVec2, glam::DVec3, glam::DVec4);

impl<const N: usize> Approx for [f64; N] {
    fn max_abs_diff(self, other: Self) -> f64 {
        self.iter()
            .zip(other)
            .fold(0.0, |m, (a, b)| f64::max(m, (a - b).abs()))
    }
    fn max_abs(self) -> f64 {
        self.iter().fold(0.0, |m, a| f64::max(m, a.abs()))
    }
}

/// Asserts that two numbers, vectors or arrays agree to `tol` relative to the larger of them (and
/// absolutely below magnitude 1): `|a − b| ≤ tol · max(|a|, |b|, 1)`, component by component. An
/// optional message follows, as for `assert!`.
macro_rules! assert_close {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {
        $crate::testutil::assert_close!($a, $b, $tol, "")
    };
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        use $crate::testutil::Approx as _;
        let (a, b, tol) = ($a, $b, $tol);
        let scale = a.max_abs().max(b.max_abs()).max(1.0);
        let diff = a.max_abs_diff(b);
        assert!(
            diff <= tol * scale,
            "{a:?} and {b:?} differ by {diff:e}, more than {tol:e} × {scale:e}: {}",
            format_args!($($msg)+)
        );
    }};
}
pub(crate) use assert_close;
