//! The machine: runs a body's operations on a value stack over the frames' cells, with HyperFun's
//! arithmetic (its `EPS` tests, its integer powers, its runtime errors at their places) and a work
//! budget.
//!
//! Each body has one frame of cells (`x`, `a`, `s`, then its variables and arrays). A body only
//! calls bodies defined before it, so no body is ever entered twice at once and one frame each
//! is enough. Whether a variable or array item was assigned in the current run of its body is a
//! stamp: the cell's stamp equals the run's number, which is new for every run (no clearing).

use alloc::borrow::Cow;
use alloc::format;
use alloc::vec::Vec;

use super::code::{Bin, Op};
use super::library::{self, Arr, F1, F2, LibStop, r_and, r_or};
use super::parse::Compiled;
use super::{HfError, HfErrorKind, MAX_OPERATIONS};

/// HyperFun's `EPS` (`0.1e-5`): divisors, `=`, truth, and powers are tested against it.
pub(crate) const EPS: f64 = 1e-6;

/// C's `(int)` of a double as x86 computes it: truncation, and `INT_MIN` for NaN and anything out
/// of range (C leaves that undefined; HyperFun's builds on x86 give `INT_MIN`).
pub(crate) fn c_int(v: f64) -> i32 {
    if v.is_nan() || v >= 2_147_483_648.0 || v <= -2_147_483_649.0 {
        i32::MIN
    } else {
        v as i32
    }
}

/// HyperFun's `HF_round`: half up (`2.5 → 3`, `−2.5 → −2`), then C's `(int)`.
pub(crate) fn hf_round(d: f64) -> i32 {
    let c = libm::ceil(d);
    c_int(if c - d > 0.5 { c - 1.0 } else { c })
}

/// The runtime messages (HyperFun's `Error_Strings`, verbatim).
mod msg {
    pub(super) const NOT_INITIALIZED: &str = "Not initialized variable";
    pub(super) const DIVISION: &str = "Division by zero";
    pub(super) const NEGATIVE_POWER: &str = "Negative value for power";
    pub(super) const ROOT: &str = "Negative value for square root";
    pub(super) const LOG: &str = "Negative for log function";
    pub(super) const UNASSIGNED: &str = "Unassigned identificator used in expression";
    pub(super) const ITEMS: &str = "Some items of array are unassigned";
    pub(super) const RANGE: &str = "Array index out of range";
    pub(super) const ASIN: &str = "Argument must be in range -1.0 .. +1.0";
    pub(super) const TAN: &str = "Cannot compute tan for this argument";
    pub(super) const ZERO_POWER: &str = "Zero value in negative or zero power";
}

/// A stamp number past which a run starts them over (a run takes at most one per operation).
const STAMP_RESET: u32 = u32::MAX - (1 << 30);

/// A body interrupted by a call: where to go on.
#[derive(Clone, Copy, Debug)]
struct Frame {
    body: usize,
    pc: usize,
    stamp: u32,
    site: usize,
}

/// The machine's memory: all frames' cells, their stamps, the value stack, the calls under way.
#[derive(Clone, Debug)]
pub(crate) struct Machine {
    pub(crate) cells: Vec<f64>,
    stamps: Vec<u32>,
    stack: Vec<f64>,
    frames: Vec<Frame>,
    next_stamp: u32,
    /// The operations the last completed run took (its work, as the budget counts it).
    pub(crate) operations: u64,
    /// The most operations a run may take ([`MAX_OPERATIONS`] unless set lower).
    pub(crate) limit: u64,
}

impl Machine {
    pub(crate) fn new(program: &Compiled) -> Self {
        let depth = program
            .bodies
            .iter()
            .map(|b| b.max_depth)
            .max()
            .unwrap_or(0);
        Self {
            cells: alloc::vec![0.0; program.cells],
            stamps: alloc::vec![0; program.cells],
            stack: Vec::with_capacity(depth + 1),
            frames: Vec::new(),
            next_stamp: 1,
            operations: 0,
            limit: MAX_OPERATIONS,
        }
    }

    fn pop(&mut self) -> f64 {
        self.stack.pop().unwrap_or(f64::NAN)
    }

    fn stamp(&mut self) -> u32 {
        let s = self.next_stamp;
        self.next_stamp += 1;
        s
    }

    /// Whether every item of `arr` was assigned in the run stamped `stamp`.
    fn assigned(&self, arr: Arr, stamp: u32) -> bool {
        let (b, n) = (arr.base as usize, arr.len as usize);
        self.stamps[b..b + n].iter().all(|&s| s == stamp)
    }

    /// Copies `from`'s items over `to`'s (equal lengths).
    fn copy(&mut self, from: Arr, to: Arr) {
        let (f, t, n) = (
            from.base as usize,
            to.base as usize,
            from.len.min(to.len) as usize,
        );
        self.cells.copy_within(f..f + n, t);
    }

    /// Runs the body `main` at the point `x` with the parameters `a` (missing items are 0). Its
    /// `s` items keep what the last run left, as in HyperFun's hosts.
    pub(crate) fn run(
        &mut self,
        program: &Compiled,
        main: usize,
        x: &[f64],
        a: &[f64],
    ) -> Result<f64, HfError> {
        let body = &program.bodies[main];
        for (arr, values) in [(body.x, x), (body.a, a)] {
            for i in 0..arr.len as usize {
                self.cells[arr.base as usize + i] = values.get(i).copied().unwrap_or(0.0);
            }
        }
        if self.next_stamp > STAMP_RESET {
            self.stamps.fill(0);
            self.next_stamp = 1;
        }
        self.stack.clear();
        self.frames.clear();
        let mut budget = self.limit;
        let mut cur = main;
        let mut stamp = self.stamp();
        let mut pc = 0;
        let mut body = body;
        loop {
            let Some(&op) = body.code.get(pc) else {
                let message = "the reader's code ran off a body's end (a bug of this reader)";
                return Err(fail(
                    program,
                    cur,
                    pc.saturating_sub(1),
                    HfErrorKind::Unsupported,
                    message,
                ));
            };
            pc += 1;
            let (here, at) = (cur, pc - 1);
            let runtime =
                move |message: &'static str| fail(program, here, at, HfErrorKind::Runtime, message);
            let Some(left) = budget.checked_sub(1) else {
                return Err(over_budget(program, here, at, self.limit));
            };
            budget = left;
            match op {
                Op::Const(v) => self.stack.push(v),
                Op::Var(c) => {
                    if self.stamps[c as usize] != stamp {
                        return Err(runtime(msg::NOT_INITIALIZED));
                    }
                    self.stack.push(self.cells[c as usize]);
                }
                Op::Cell(c) => self.stack.push(self.cells[c as usize]),
                Op::Item(c) => {
                    if self.stamps[c as usize] != stamp {
                        return Err(runtime(msg::UNASSIGNED));
                    }
                    self.stack.push(self.cells[c as usize]);
                }
                Op::Index { base, len } => {
                    let i = hf_round(self.pop());
                    if i < 1 || i as u32 > len {
                        return Err(runtime(msg::RANGE));
                    }
                    self.stack.push(self.cells[(base + i as u32 - 1) as usize]);
                }
                Op::Elem { base, len, name } => {
                    let i = hf_round(self.pop());
                    if i < 1 || i as u32 > len {
                        return Err(runtime(msg::RANGE));
                    }
                    let c = (base + i as u32 - 1) as usize;
                    if self.stamps[c] != stamp {
                        return Err(HfError::at(HfErrorKind::Runtime, name, msg::UNASSIGNED));
                    }
                    self.stack.push(self.cells[c]);
                }
                Op::Neg => {
                    let v = self.pop();
                    self.stack.push(-v);
                }
                Op::Not => {
                    let v = self.pop();
                    self.stack.push(if v.abs() < EPS { 1.0 } else { 0.0 });
                }
                Op::Bin(op) => {
                    let l = self.pop();
                    let r = self.pop();
                    let v = match op {
                        Bin::Add => l + r,
                        Bin::Sub => l - r,
                        Bin::Mul => l * r,
                        Bin::Div => {
                            if r.abs() < EPS {
                                return Err(runtime(msg::DIVISION));
                            }
                            l / r
                        }
                        Bin::Pow => match power(l, r, &mut budget) {
                            Ok(v) => v,
                            Err(Stop::Error(message)) => return Err(runtime(message)),
                            Err(Stop::Budget) => {
                                return Err(over_budget(program, here, at, self.limit));
                            }
                        },
                        Bin::And => r_and(l, r),
                        Bin::Or => r_or(l, r),
                        Bin::Minus => r_and(l, -r),
                        Bin::Less => truth(l < r),
                        Bin::LessEqual => truth(l <= r),
                        Bin::Greater => truth(l > r),
                        Bin::GreaterEqual => truth(l >= r),
                        Bin::Equal => truth((r - l).abs() < EPS),
                        Bin::NotEqual => truth((r - l).abs() >= EPS),
                        Bin::Both => truth(l.abs() >= EPS && r.abs() >= EPS),
                        Bin::Either => truth(!(l.abs() < EPS && r.abs() < EPS)),
                    };
                    self.stack.push(v);
                }
                Op::F1(f) => {
                    let v = self.pop();
                    self.stack.push(builtin1(f, v).map_err(runtime)?);
                }
                Op::F2(f) => {
                    let p = self.pop();
                    let q = self.pop();
                    self.stack.push(builtin2(f, p, q));
                }
                Op::Check { base, len } => {
                    budget = budget.saturating_sub(u64::from(len));
                    if !self.assigned(Arr { base, len }, stamp) {
                        return Err(runtime(msg::ITEMS));
                    }
                }
                Op::Lib(site) => {
                    let site = &body.libs[site as usize];
                    let mut r = [0.0; 8];
                    for v in r.iter_mut().take(site.reals) {
                        *v = self.pop();
                    }
                    let v = library::call(
                        site.lib,
                        &r[..site.reals],
                        &site.arrays,
                        &mut self.cells,
                        &mut budget,
                    );
                    match v {
                        Ok(v) => self.stack.push(v),
                        Err(LibStop::Budget) => {
                            return Err(over_budget(program, here, at, self.limit));
                        }
                        Err(LibStop::Undefined(message)) => {
                            return Err(fail(program, here, at, HfErrorKind::Unsupported, message));
                        }
                    }
                }
                Op::Call(site) => {
                    let call = &body.calls[site as usize];
                    let callee = &program.bodies[call.callee as usize];
                    for (k, to) in [callee.x, callee.a, callee.s].into_iter().enumerate() {
                        let from = call.args[k];
                        budget = budget.saturating_sub(u64::from(from.len));
                        if call.tracked[k] && !self.assigned(from, stamp) {
                            let at = call.report[k];
                            return Err(HfError::at(HfErrorKind::Runtime, at, msg::ITEMS));
                        }
                        self.copy(from, to);
                    }
                    self.frames.push(Frame {
                        body: cur,
                        pc,
                        stamp,
                        site: site as usize,
                    });
                    cur = call.callee as usize;
                    body = callee;
                    pc = 0;
                    stamp = self.stamp();
                }
                Op::Store(c) => {
                    self.cells[c as usize] = self.pop();
                    self.stamps[c as usize] = stamp;
                }
                Op::Slot { len } => {
                    let i = hf_round(self.pop());
                    if i < 1 || i as u32 > len {
                        return Err(runtime(msg::RANGE));
                    }
                    self.stack.push(f64::from(i));
                }
                Op::StoreElem { base, tracked } => {
                    let v = self.pop();
                    let c = (base as usize + self.pop() as usize).saturating_sub(1);
                    self.cells[c] = v;
                    if tracked {
                        self.stamps[c] = stamp;
                    }
                }
                Op::Fill {
                    base,
                    len,
                    from,
                    tracked,
                } => {
                    let (b, n, f) = (base as usize, len as usize, from as usize);
                    budget = budget.saturating_sub(len.into());
                    self.cells[b..b + n].copy_from_slice(&body.consts[f..f + n]);
                    if tracked {
                        self.stamps[b..b + n].fill(stamp);
                    }
                }
                Op::Jump(to) => pc = to as usize,
                Op::JumpUnless(to) => {
                    // True is |v| ≥ EPS, so NaN is false.
                    let holds = self.pop().abs() >= EPS;
                    if !holds {
                        pc = to as usize;
                    }
                }
                Op::Return => {
                    let v = self.pop();
                    let Some(frame) = self.frames.pop() else {
                        self.operations = self.limit - budget;
                        return Ok(v);
                    };
                    let caller = &program.bodies[frame.body];
                    let call = &caller.calls[frame.site];
                    self.copy(body.s, call.args[2]);
                    (cur, body, pc, stamp) = (frame.body, caller, frame.pc, frame.stamp);
                    self.stack.push(v);
                }
            }
        }
    }
}

fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

/// An error at operation `at` of `body`.
fn fail(
    program: &Compiled,
    body: usize,
    at: usize,
    kind: HfErrorKind,
    message: impl Into<Cow<'static, str>>,
) -> HfError {
    let pos = program.bodies[body]
        .pos
        .get(at)
        .copied()
        .unwrap_or_default();
    HfError::at(kind, pos, message)
}

fn over_budget(program: &Compiled, body: usize, at: usize, limit: u64) -> HfError {
    let message = format!("the model runs past {limit} operations at one point");
    fail(program, body, at, HfErrorKind::Limit, message)
}

enum Stop {
    Error(&'static str),
    Budget,
}

/// `b ^ e` as HyperFun computes it: 0 for a base under `EPS` (an error for an exponent at most
/// `EPS`), repeated products for an exponent within `EPS` above an integer, else `exp(e·ln b)`.
fn power(b: f64, e: f64, budget: &mut u64) -> Result<f64, Stop> {
    if b.abs() < EPS {
        return if e <= EPS {
            Err(Stop::Error(msg::ZERO_POWER))
        } else {
            Ok(0.0)
        };
    }
    if e - libm::floor(e) < EPS {
        let n = hf_round(e.abs()).max(0) as u64;
        let mut v = repeated_product(b, n, budget)?;
        if e < 0.0 {
            v = 1.0 / v;
        }
        return Ok(v);
    }
    if b < 0.0 {
        return Err(Stop::Error(msg::NEGATIVE_POWER));
    }
    Ok(libm::exp(e * libm::log(b)))
}

/// `1·b·b·…·b` with `n` factors, rounded at each product as HyperFun's loop does. Once the
/// products repeat with period 1 or 2 (0, ±∞, a stuck subnormal, ±1) the rest follows from the
/// parity of the count; otherwise each product is one operation of the budget.
fn repeated_product(b: f64, n: u64, budget: &mut u64) -> Result<f64, Stop> {
    let mut seq = [1.0f64; 3];
    for k in 1..=n {
        *budget = budget.checked_sub(1).ok_or(Stop::Budget)?;
        let v = seq[2] * b;
        if v.is_nan() {
            return Ok(v);
        }
        (seq[0], seq[1], seq[2]) = (seq[1], seq[2], v);
        if k >= 2 && seq[2].to_bits() == seq[0].to_bits() {
            // Period 2 from here: seq[2] at k, seq[1] at k − 1.
            return Ok(if (n - k).is_multiple_of(2) {
                seq[2]
            } else {
                seq[1]
            });
        }
    }
    Ok(seq[2])
}

fn builtin1(f: F1, v: f64) -> Result<f64, &'static str> {
    Ok(match f {
        F1::Sqrt => {
            if v < 0.0 {
                return Err(msg::ROOT);
            }
            crate::math::sqrt(v)
        }
        F1::Exp => libm::exp(v),
        F1::Log | F1::Logd => {
            if v.is_nan() || v <= 0.0 {
                return Err(msg::LOG);
            }
            if f == F1::Log {
                libm::log(v)
            } else {
                libm::log10(v)
            }
        }
        F1::Sin => libm::sin(v),
        F1::Cos => libm::cos(v),
        F1::Tan => {
            if libm::cos(v).abs() < EPS {
                return Err(msg::TAN);
            }
            libm::tan(v)
        }
        F1::Asin | F1::Acos => {
            if v.abs() > 1.0 {
                return Err(msg::ASIN);
            }
            if f == F1::Asin {
                libm::asin(v)
            } else {
                libm::acos(v)
            }
        }
        F1::Atan => libm::atan(v),
        F1::Abs => v.abs(),
        F1::Sinh => libm::sinh(v),
        F1::Cosh => libm::cosh(v),
        F1::Tanh => libm::tanh(v),
        // HyperFun's `sign` sets −1 for a negative argument, then 1 over it, always.
        F1::Sign => 1.0,
        F1::Ceil => libm::ceil(v),
        F1::Floor => libm::floor(v),
        F1::Int => libm::trunc(v),
        // C's `modf`: the fraction keeps the argument's sign, and is ±0 for ±∞.
        F1::Frac => {
            if v.is_infinite() {
                libm::copysign(0.0, v)
            } else {
                libm::copysign(v - libm::trunc(v), v)
            }
        }
    })
}

fn builtin2(f: F2, p: f64, q: f64) -> f64 {
    match f {
        F2::Mod => libm::fmod(f64::from(hf_round(p)), f64::from(hf_round(q))),
        F2::Max => {
            if p > q {
                p
            } else {
                q
            }
        }
        F2::Min => {
            if p < q {
                p
            } else {
                q
            }
        }
        F2::Atan2 => libm::atan2(p, q),
    }
}
