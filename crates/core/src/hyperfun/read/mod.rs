//! A strict HyperFun reader: parses a `.hf` text exactly as HyperFun's own interpreter (the C
//! interpreter of HyperFun 1.x, by Osipov and Adzhiev) accepts it, with its messages at its
//! places, and evaluates its models as that interpreter does: the same doubles wherever only
//! arithmetic and square roots are involved (checked against it on thousands of random programs
//! and points, and on this crate's exports); the transcendental functions are `libm`'s, which may
//! differ from the C library's in the last place.
//!
//! ```
//! use bezsolid_core::hyperfun::read::{HfErrorKind, Program};
//!
//! let text = "-- a unit ball, blended with a torus
//! my_model(x[3], a[1]) {
//!   array centre[3];
//!   centre = [0, 0, 0];
//!   ball = hfSphere(x, centre, 1);
//!   ring = hfTorusZ(x, centre, 1, 0.25);
//!   my_model = hfBlendUni(ball, ring, 0.1, 1, 1);
//! }";
//! let program = Program::parse(text).unwrap();
//! assert!(program.eval([0.0, 0.0, 0.0]).unwrap() > 0.0);
//! assert!(program.eval([3.0, 0.0, 0.0]).unwrap() < 0.0);
//!
//! // HyperFun's refusals, with its messages at its places.
//! let err = Program::parse("my_model(x[3], a[1]) { s = 1; my_model = s; }").unwrap_err();
//! assert_eq!(err.to_string(), "line 1, position 28: Left bracket expected");
//! let err = Program::parse("m(x[3], a[1]) { d = 1e-7; m = 1 / d; }").unwrap();
//! let err = err.eval([0.0; 3]).unwrap_err();
//! assert_eq!((err.kind, &*err.message), (HfErrorKind::Runtime, "Division by zero"));
//! ```
//!
//! # The language, as HyperFun's interpreter has it
//!
//! - **Words**: names are lower-cased (`Foo` is `foo`); `x`, `a`, `s`, the keywords (`and or not
//!   xor array if then else endif while loop endloop`) and the 108 names of HyperFun's function
//!   table (below) can never name a variable, an array or a body. Comments are `--` to the end
//!   of the line.
//! - **Numbers** are read digit by digit, and an exponent's sign applies to its first digit only:
//!   `1e-15` reads as `1e-5` (precisely 9.9999999999999805e-06, as HyperFun computes
//!   `exp(k·ln 10)`). `05` and `1e05` are refused, as are `1e0` and `.`.
//! - **Bodies**: `name(x[n], a[n] [, s[n]]) { array declarations; statements; name = expr; }`,
//!   the `a` array mandatory; the body named `my_model` is evaluated, else the first. A body
//!   may call a body defined before it, `b(x, a)` or `b(x, a, s)`, on copies of those arrays
//!   (its `s` comes back).
//! - **Variables** are declared by their first assignment in the text; reading one before that
//!   assignment is refused ("Unassigned identificator used in expression"), reading one that
//!   was not assigned in this evaluation fails ("Not initialized variable"). A whole array is
//!   assigned only constants, exactly as many as it has items (`p = [1, -2, 3];`).
//! - **Expressions**: `+ - & | \ @` share the lowest level (`&` and `@` the R-function
//!   intersection `f1 + f2 − √(f1² + f2²)`, `|` the union, `\` the difference), then `* /`, then
//!   `^` (left to right: `2^3^2` = 64), then the signs (`-x^2` = `(-x)^2`). Every operator's
//!   right operand is evaluated before its left one, and a call's arguments from the last.
//! - **Conditions** (after `if` and `while` only): `and` and `or` share one level (`1 or 0 and 0`
//!   is false); a `(` at the start of an operand always opens a nested condition, so
//!   `if (a - b) * c > 0` is refused ("Right parenthes expected").
//! - **EPS = 1e-6**: dividing by less than it is an error ("Division by zero"), `=` holds within
//!   it, a value is true when at least it, and an exponent within it above an integer is an
//!   integer power computed by repeated products.
//!
//! # What this reader adds
//!
//! - It takes `\r\n` line ends (files saved on Windows), where HyperFun refuses the `\r`.
//! - **Caps** against hostile input, each a [`HfErrorKind::Limit`] error: [`MAX_SOURCE_BYTES`] of
//!   text, [`MAX_DEPTH`] levels of nesting, [`MAX_CELLS`] numbers in all arrays and variables,
//!   [`MAX_NAMES`] names, [`MAX_CODE`] operations and constants, and [`MAX_OPERATIONS`] operations
//!   per evaluation (a `while` that never ends stops there).
//! - **Where HyperFun's behaviour is undefined** (a library function reading past the end of a
//!   short array or a zero-size one, a body call whose argument is not an array, a zero-length
//!   `hfConvLine` segment, which stops HyperFun's process, `hfBezierVolume` with more than 21
//!   control points per axis or too few weights), it is an [`HfErrorKind::Unsupported`] error
//!   rather than a guess. `hfBezierVolume`'s work buffers are sized anew for every call (HyperFun
//!   sizes them once, at the first call). C's `(int)` of NaN or a number past its range gives
//!   `INT_MIN`, as on the x86 machines HyperFun runs on (`mod(1e300, 7)` is −2, an index of
//!   1e300 is out of range, `2^1e10` is 1).
//! - The state HyperFun keeps between points: [`Program::eval`] starts every evaluation with `s`
//!   all zero (HyperFun's first point); an [`Evaluator`] keeps `s` from one point to the next, as
//!   HyperFun's hosts do, and refills `x` and `a` every point.
//!
//! # Library functions
//!
//! Evaluated, from the library's definitions (the primitives return HyperFun's
//! `-1111111111111` when the point array has not 3 items):
//! the built-ins `sqrt exp log logd sin cos tan asin acos atan abs sinh cosh tanh sign mod max
//! min atan2 ceil floor int frac` (`sign` is always 1, HyperFun's bug); `hfSphere`,
//! `hfEllipsoid`, `hfBlock`, `hfCylinderX/Y/Z`, `hfEllCylX/Y/Z`, `hfTorusX/Y/Z`, `hfConeX/Y/Z`,
//! `hfEllConeX/Y/Z`, `hfSuperell`, `hfBlendUni`, `hfBlendInt`, `hfBlobby`, `hfMetaball`,
//! `hfSoft`, `hfConvPoint`, `hfConvLine`, `hfConvTriangle`, `hfBezierVolume`, `hfNoiseG`; the
//! transformations, which change their array in place and return 1: `hfScale3D`, `hfShift3D`,
//! `hfRotate3DX/Y/Z`, `hfTwistX/Y/Z`, `hfTaperX/Y/Z`, `hfStretch3D`; and `hfA_Clamp`,
//! `hfA_Floor`, `hfA_Pulse`, `hfA_Step`, `hfA_Modulo`, `hfSawtooth`.
//!
//! Reserved but refused where they are called ([`HfErrorKind::Unsupported`]): `hfConvArc`,
//! `hfConvLineR`, `hfConvCurve`, `hfConvMesh`, `hfSpaceMapCubic`, `hfSpaceMapExp`, `hfR` (a
//! callback of HyperFun's R port), the attribute functions `hfA_Wave`, `hfA_CheckerBoard`,
//! `hfA_Union`, `hfA_Crackles`, `hfA_Circles`, `hfA_NoiseG`, `hfA_NoiseP`, `hfA_Turbulence`,
//! `hfA_SetColor`, `hfA_SetAttributes`, `hfA_Lerp`, `hfA_Cerp`, `hfA_LookUpTable`,
//! `hfA_SmoothLookUpTable`, `hfA_SmoothStep`, `hfA_Spline`, `hfA_RGBToHSV`, `hfA_HSVToRGB` (some
//! draw from `rand()`), and the distance functions `hfDConeX/Y/Z`, `hfDCylinder`,
//! `hfDEllipsoid`, `hfDTorusX/Y/Z`, `hfDUni`, `hfDInt`, `hfDSub`, `hfDBlendUni`, `hfDBlendInt`.

use alloc::borrow::Cow;
use core::fmt;

mod code;
mod expr;
mod library;
#[cfg(test)]
mod library_tests;
mod parse;
mod run;
mod scan;
#[cfg(test)]
mod tests;

use parse::Compiled;
use run::Machine;
use scan::Pos;

/// The longest text read, in bytes.
pub const MAX_SOURCE_BYTES: usize = 32 << 20;
/// The deepest nesting of parentheses, signs, calls, conditions and `if`/`while` statements. The
/// parser recurses along it: at the cap it takes at most 192 KiB of stack optimised and 384 KiB
/// unoptimised (measured on x86-64), inside a browser's 1 MiB; no model nests a tenth as deep.
pub const MAX_DEPTH: usize = 200;
/// The most numbers all bodies' arrays (`x`, `a`, `s` and declared ones) and variables hold
/// together (16 Mi: 192 MiB of cells and stamps).
pub const MAX_CELLS: usize = 1 << 24;
/// The most names (bodies, variables, arrays) of a text.
pub const MAX_NAMES: usize = 1 << 20;
/// The most operations and whole-array constants a text compiles to (4 Mi, about 100 MiB).
pub const MAX_CODE: usize = 1 << 22;
/// The most operations one evaluation runs (each loop step, product of an integer power and
/// array item copied or checked counts): about a second.
pub const MAX_OPERATIONS: u64 = 100_000_000;

/// What kind of error an [`HfError`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HfErrorKind {
    /// HyperFun's parser refuses the text (its message).
    Parse,
    /// HyperFun's evaluator stops (its message).
    Runtime,
    /// A cap of this reader (our message).
    Limit,
    /// HyperFun that this reader does not evaluate: a library function it does not implement, or
    /// a construct whose behaviour HyperFun leaves undefined (our message).
    Unsupported,
}

/// An error of the reader: where, what kind, and the message (HyperFun's own wording, from its
/// `Error_Strings`, for [`HfErrorKind::Parse`] and [`HfErrorKind::Runtime`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HfError {
    /// The 1-based line.
    pub line: u32,
    /// HyperFun's position: the 1-based byte column of the token (a tab counts as one).
    pub position: u32,
    /// What kind of error.
    pub kind: HfErrorKind,
    /// The message.
    pub message: Cow<'static, str>,
}

impl HfError {
    fn at(kind: HfErrorKind, pos: Pos, message: impl Into<Cow<'static, str>>) -> Self {
        Self {
            line: pos.line,
            position: pos.col,
            kind,
            message: message.into(),
        }
    }
}

impl fmt::Display for HfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, position {}: {}",
            self.line, self.position, self.message
        )
    }
}

impl core::error::Error for HfError {}

/// A parsed and compiled HyperFun text, with the body it evaluates.
#[derive(Clone, Debug)]
pub struct Program {
    compiled: Compiled,
    main: usize,
}

impl Program {
    /// Parses `text`, choosing the body named `my_model` if there is one, else the first (as
    /// HyperFun does).
    ///
    /// # Errors
    ///
    /// The first error HyperFun's parser reports ([`HfErrorKind::Parse`]), a cap passed
    /// ([`HfErrorKind::Limit`]), or a call this reader does not evaluate, or a text with no body
    /// ([`HfErrorKind::Unsupported`]).
    pub fn parse(text: &str) -> Result<Self, HfError> {
        let compiled = parse::parse(text)?;
        let main = compiled
            .bodies
            .iter()
            .position(|b| b.name == "my_model")
            .unwrap_or(0);
        Ok(Self { compiled, main })
    }

    /// The bodies' names (lower-cased, as HyperFun keeps them), in the text's order.
    pub fn body_names(&self) -> impl Iterator<Item = &str> {
        self.compiled.bodies.iter().map(|b| b.name.as_str())
    }

    /// The numbers all the text's arrays and variables take (what an [`Evaluator`] allocates).
    #[must_use]
    pub fn cells(&self) -> usize {
        self.compiled.cells
    }

    /// The name of the body evaluated.
    #[must_use]
    pub fn body(&self) -> &str {
        &self.compiled.bodies[self.main].name
    }

    /// Evaluates the body `name` (lower case) from now on; `false`, and no change, if there is
    /// none.
    pub fn select(&mut self, name: &str) -> bool {
        match self.compiled.bodies.iter().position(|b| b.name == name) {
            Some(i) => {
                self.main = i;
                true
            }
            None => false,
        }
    }

    /// The sizes of the evaluated body's `x`, `a` and `s` (`s` is 1 when its header has none).
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        let b = &self.compiled.bodies[self.main];
        [b.x.len, b.a.len, b.s.len].map(|n| n as usize)
    }

    /// The value at the point `x` (the first of its coordinates fill the body's `x`, the rest
    /// is 0), with `a` all zero and `s` all zero.
    ///
    /// # Errors
    ///
    /// HyperFun's runtime error ([`HfErrorKind::Runtime`]), the operations cap
    /// ([`HfErrorKind::Limit`]), or an undefined case ([`HfErrorKind::Unsupported`]).
    pub fn eval(&self, x: [f64; 3]) -> Result<f64, HfError> {
        self.eval_with(x, &[])
    }

    /// [`Program::eval`] with the parameters `a` (missing items are 0).
    ///
    /// # Errors
    ///
    /// As [`Program::eval`].
    pub fn eval_with(&self, x: [f64; 3], a: &[f64]) -> Result<f64, HfError> {
        self.evaluator().eval(&x, a)
    }

    /// An evaluator for many points: it keeps its memory, and the `s` array, between them.
    #[must_use]
    pub fn evaluator(&self) -> Evaluator<'_> {
        Evaluator {
            program: self,
            machine: Machine::new(&self.compiled),
        }
    }
}

/// Evaluates a [`Program`] at many points without allocating, keeping the body's `s` items
/// between points as HyperFun's hosts do.
///
/// ```
/// use bezsolid_core::hyperfun::read::Program;
///
/// // `s[1]` counts the points with x > 0 seen so far.
/// let program = Program::parse(
///     "m(x[3], a[1]) { if x[1] > 0 then s[1] = s[1] + 1; endif; m = s[1]; }",
/// ).unwrap();
/// let mut e = program.evaluator();
/// let seen: Vec<f64> = [1.0, 1.0, -1.0].iter().map(|&v| e.eval(&[v], &[]).unwrap()).collect();
/// assert_eq!(seen, [1.0, 2.0, 2.0]);
/// ```
#[derive(Clone, Debug)]
pub struct Evaluator<'p> {
    program: &'p Program,
    machine: Machine,
}

impl Evaluator<'_> {
    /// The value at `x` with the parameters `a` (each fills the body's array from its first
    /// item; missing items are 0, extra ones are ignored).
    ///
    /// # Errors
    ///
    /// As [`Program::eval`].
    pub fn eval(&mut self, x: &[f64], a: &[f64]) -> Result<f64, HfError> {
        let p = self.program;
        self.machine.run(&p.compiled, p.main, x, a)
    }

    /// Caps each evaluation at `limit` operations (at most [`MAX_OPERATIONS`], which it is
    /// unless set): past it an evaluation is a [`HfErrorKind::Limit`] error. A caller sharing a
    /// budget among many points gives each its part.
    pub fn set_limit(&mut self, limit: u64) {
        self.machine.limit = limit.min(MAX_OPERATIONS);
    }

    /// The operations the last successful evaluation took, as [`MAX_OPERATIONS`] counts them:
    /// the work of a point, the same on every machine.
    #[must_use]
    pub fn operations(&self) -> u64 {
        self.machine.operations
    }

    /// The body's `s` items as the last evaluation left them.
    #[must_use]
    pub fn s(&self) -> &[f64] {
        let s = self.program.compiled.bodies[self.program.main].s;
        &self.machine.cells[s.base as usize..(s.base + s.len) as usize]
    }
}
