//! The `hyperfun` target: the strict HyperFun reader (`hyperfun::read`) on any text.

use bezsolid_core::hyperfun::read::{HfError, HfErrorKind, MAX_OPERATIONS, Program};

/// The points a program is evaluated at after the origin: ordinary ones near the origin, where
/// models are, then far ones, to `±f64::MAX`.
const NEAR: usize = 3;
const FAR: usize = 3;

/// The points (counted from the origin, 0) where a fresh evaluation is compared with the
/// evaluator that evaluated the points before: one near, one far.
const COMPARED: [usize; 2] = [NEAR, NEAR + FAR];

/// Reads the bytes as a HyperFun text (invalid UTF-8 replaced by U+FFFD) with
/// [`Program::parse`]; a program that parses is evaluated by one [`Evaluator`] at the origin, at 3
/// points near it and 3 far ones, with parameters `a`, all drawn from a hash of the bytes (finite:
/// in [−2, 2], and far, to `±f64::MAX`). Errors are answers, of any kind; the target checks:
///
/// - an error's line and position count from 1 (as [`HfError`] says), it prints, and it is not
///   one the reader calls a bug of its own;
/// - the body evaluated is one of the program's;
/// - at the last near point and the last far one, where the evaluator's `s` is still all zero,
///   its answer (after the points before) and [`Program::eval_with`]'s (a fresh evaluation) are
///   the same, bit for bit: the memory an evaluator keeps between points changes nothing but `s`.
///
/// The evaluator keeps `s` from point to point, as HyperFun's hosts do. Further points are
/// evaluated only while the work of those before stays under one evaluation's cap
/// ([`MAX_OPERATIONS`], a few tenths of a second): a program that runs to the cap at one point
/// runs to it at the next, and a campaign would spend its time there.
///
/// [`Evaluator`]: bezsolid_core::hyperfun::read::Evaluator
///
/// # Panics
///
/// On a bug: a broken promise above, or any panic (an overflow of the stack included) in the
/// scanner, the parser, the compiler or the evaluator.
pub fn hyperfun(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let program = match Program::parse(&text) {
        Ok(program) => program,
        Err(e) => {
            check_error(&e);
            return;
        }
    };
    let body = program.body();
    assert!(
        program.body_names().any(|n| n == body),
        "the body evaluated, {body:?}, is not among the program's"
    );
    let _ = program.dims();
    let mut draw = Draw::new(data);
    let a: Vec<f64> = (0..4).map(|_| draw.near()).collect();
    let mut evaluator = program.evaluator();
    let mut work = 0;
    for i in 0..=NEAR + FAR {
        if work >= MAX_OPERATIONS {
            break;
        }
        let x: [f64; 3] = core::array::from_fn(|_| match i {
            0 => 0.0,
            i if i <= NEAR => draw.near(),
            _ => draw.far(),
        });
        let clean = evaluator.s().iter().all(|v| v.to_bits() == 0);
        let got = evaluator.eval(&x, &a);
        // The operations of a successful evaluation; an error's are not told: the cap's where
        // it was the cap.
        let cost = match &got {
            Ok(_) => evaluator.operations(),
            Err(e) => {
                check_error(e);
                if e.kind == HfErrorKind::Limit {
                    MAX_OPERATIONS
                } else {
                    0
                }
            }
        };
        work += cost;
        if COMPARED.contains(&i) && clean && work < MAX_OPERATIONS {
            work += cost;
            let fresh = program.eval_with(x, &a);
            let same = match (&got, &fresh) {
                (Ok(u), Ok(v)) => u.to_bits() == v.to_bits(),
                (Err(e), Err(f)) => e == f,
                _ => false,
            };
            assert!(
                same,
                "at {x:?} (point {i}) the evaluator gives {got:?}, a fresh evaluation {fresh:?}"
            );
        }
    }
}

/// An error's place counts from 1, it prints, and it is not one the reader calls its own bug.
fn check_error(e: &HfError) {
    assert!(
        !e.message.contains("a bug of this reader"),
        "the reader reports a bug of its own: {e:?}"
    );
    assert!(
        e.line >= 1 && e.position >= 1,
        "an error at line {}, position {} (both count from 1): {e:?}",
        e.line,
        e.position
    );
    let _ = e.to_string();
}

/// Finite numbers drawn from a hash of the input (splitmix64 from FNV-1a), so that the bytes stay
/// the text: a seed is a `.hf` file as written, and a mutation of the text also moves the points.
struct Draw(u64);

impl Draw {
    fn new(data: &[u8]) -> Self {
        let hash = data.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        });
        Self(hash)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in [−2, 2], where models are (in steps of 2⁻²⁰), 0 one time in 16.
    fn near(&mut self) -> f64 {
        let r = self.next();
        if r & 15 == 0 {
            return 0.0;
        }
        ((r >> 44) as f64 / f64::from(1 << 20)) * 4.0 - 2.0
    }

    /// A finite number of any size: ±`f64::MAX`, ±1e300, ±1e12, a subnormal, or any finite double.
    fn far(&mut self) -> f64 {
        let r = self.next();
        let sign = if r & 1 == 0 { 1.0 } else { -1.0 };
        match (r >> 1) % 6 {
            0 => sign * f64::MAX,
            1 => sign * 1e300,
            2 => sign * 1e12,
            3 => sign * 5e-324,
            4 => sign * 1e6 * ((r >> 12) as f64 / (1_u64 << 52) as f64),
            _ => {
                let v = f64::from_bits(self.next());
                if v.is_finite() { v } else { sign * 1e200 }
            }
        }
    }
}
