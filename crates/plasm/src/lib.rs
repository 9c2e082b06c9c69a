//! # bezsolid-plasm
//!
//! The subset of PLaSM (Paoluzzi's functional language for geometry, after Backus's FL) that the
//! transfinite blending paper is written in, so that its scripts run verbatim:
//!
//! ```
//! use bezsolid_plasm::Interp;
//!
//! let mut plasm = Interp::new();
//! let run = plasm
//!     .run("DEF SQR = ID * ID; MAP:(CONS:< S1, SQR ~ S1 >):(interval:<0, 1>:4);")
//!     .into_result()
//!     .unwrap();
//! let curve = run[0].value.as_pol().unwrap();
//! assert_eq!((curve.point_count(), curve.cell_count()), (5, 4));
//! assert_eq!(curve.point(2), &[0.5, 0.25]);
//! ```
//!
//! The language: `DEF name (params :: Pred)… = expr WHERE locals END;`, sequences `< >`,
//! application `:`, composition `~`, `[f, g]` (that is `CONS:<f, g>`), arithmetic `+ - * / **`
//! on numbers and, pointwise, on functions (`K:1 - ID`), ranges `0..n`, and the built-ins of
//! [`value::Prim`], with `PI`, `TRUE` and `FALSE`. Names are case-insensitive, as in PLaSM
//! (the paper writes both `k:2` and `K:2`, `IsReal` and `isReal`). Comments run from `%` to the
//! next `%` or the end of the line. A `DEF` may redefine a built-in (Script 3.1 defines `SQRT`).
//!
//! Where the paper's text is damaged, the reading is stated in a [`Warning`]: a `~` with no left
//! operand is read as `* ~` (Script 4.2's Bernstein), and sequences continued after a `,` outside
//! brackets as one sequence (Script 4.4's `<<0,0,0>>, <<10,0,0>>`). `TRANS` pads shorter
//! sequences with 0, so that a plane curve blends with 3D handles as the curve at z = 0 (Scripts
//! 4.6 and 4.7). `Domain:n`, which the paper uses but does not define, is `Intervals:1:n`. `C:f:a` fixes
//! the right operand (`C:f:a:x` is `f:<x, a>`), since the paper's `Pred = C:-:1` is the
//! predecessor that its `Choose` recursion needs.
//!
//! The paper's toolbox is a prelude, defined before every script ([`prelude`], [`PRELUDE_NAMES`]):
//! `Bezier`, `CubicHermite`, `BernsteinBasis`, `Bernstein`, `HermiteBasis`, `Choose`, `Fact`,
//! `Pred` and their kin, so that a script may use them without defining them. A script's own
//! `DEF` of a name wins, so the paper's scripts run verbatim to the same results:
//!
//! ```
//! use bezsolid_plasm::Interp;
//!
//! let run = Interp::new().run("Fact:5; MAP:(Bezier:S1:<<0,0,0>,<1,1,0>>):(Domain:8);");
//! assert_eq!(run.shown[0].value.as_num(), Some(120.0));
//! assert_eq!(run.shown[1].value.as_pol().unwrap().point(4), &[0.5, 0.5, 0.0]);
//! assert_eq!(Interp::new().run("DEF Fact = 1; Fact;").shown[0].value.as_num(), Some(1.0));
//! ```
//!
//! Scripts are untrusted: every error has a line and column, and [`Limits`] bound the steps, the
//! depth of calls, the length of sequences, the cells of complexes and the memory that a run's
//! values hold, so a script ends with an error rather than a hang, an overflow of the stack, a
//! panic or an exhausted memory.
//!
//! The memory budget counts bytes as values are built and gives them back as they are dropped:
//! what is held at once counts, not what was ever built. A sequence counts its items (16 bytes
//! each), a function its arguments, a complex its coordinates and cells, each with its `Rc` and
//! what the allocator adds to a block; the interpreter adds the buffers it fills while a script
//! runs (the results of `AA` or `CONS` on their way, the frames of calls, `MAP`'s points). It
//! is checked at every step and before anything large is built, and [`Run::memory`] says the
//! most a run held:
//!
//! ```
//! use bezsolid_plasm::{ErrorKind, Interp, Limits};
//!
//! let small = Limits { memory: 1 << 20, ..Limits::default() };
//! // A range of 50,000 numbers holds 800 KB: twenty are built, one at a time.
//! let run = Interp::with_limits(small).run("DEF n (i::IsNat) = LEN:(1..50000); +:(AA:n:(1..20));");
//! assert_eq!(run.shown[0].value.as_num(), Some(1e6));
//! assert!(run.memory > 800_000 && run.memory < 1 << 20);
//! // Two are not held at once.
//! let run = Interp::with_limits(small).run("DEF a = 1..50000;\nDEF b = 1..50000;");
//! let e = run.error.unwrap();
//! assert_eq!((e.kind, e.span.line, e.span.col), (ErrorKind::Limit, 2, 10));
//! assert!(e.message.starts_with("the script builds more than 1 MiB"));
//! ```

use std::fmt;

mod complex;
mod eval;
mod kernel;
mod lex;
pub mod mesh;
mod meter;
mod parse;
mod prelude;
pub mod scripts;
pub mod value;

pub use complex::{Complex, ComplexError};
pub use eval::{Interp, MapOf, Run, Shown};
pub use parse::{Arith, Def};
pub use prelude::{PRELUDE_NAMES, prelude};
pub use value::{Fun, Prim, Value};

/// A place in the source: byte offsets and the 1-based line and column (in characters) of the
/// start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// Byte offset of the start.
    pub start: u32,
    /// Byte offset past the end.
    pub end: u32,
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1, in characters.
    pub col: u32,
}

/// What kind of error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The text is not a script: an unbalanced bracket, a missing `;`, …
    Syntax,
    /// A name that is neither defined nor built in.
    Name,
    /// A value of the wrong kind: applying a number, adding a sequence, a parameter that fails
    /// its predicate, …
    Type,
    /// A result that is not a finite number: a division by zero, the root of a negative number.
    Math,
    /// Past one of the [`Limits`].
    Limit,
}

/// An error, located.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// What kind.
    pub kind: ErrorKind,
    /// Where.
    pub span: Span,
    /// What, in words.
    pub message: String,
}

impl Error {
    pub(crate) fn new(kind: ErrorKind, span: Span, message: String) -> Self {
        Error {
            kind,
            span,
            message,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.span.line, self.span.col, self.message
        )
    }
}

impl std::error::Error for Error {}

/// A reading of the source that is worth saying: where the paper's text is damaged.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// Where.
    pub span: Span,
    /// What was read, and why.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.span.line, self.span.col, self.message
        )
    }
}

/// Bounds on a run, so that a script cannot freeze the page or exhaust its memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Function applications and items made, in one run.
    pub steps: u64,
    /// Applications nested inside one another (recursion).
    pub depth: u32,
    /// Items of one sequence.
    pub items: usize,
    /// Cells (and points) of one complex.
    pub cells: usize,
    /// Bytes of values held at once by a run: its sequences, functions and complexes, and the
    /// buffers it fills while it runs, counted as they are built and given back as they are
    /// dropped (so a script that builds and drops large values over and over is not refused),
    /// from what was held when the run began.
    pub memory: usize,
    /// Bytes of source.
    pub source: usize,
    /// Whether `MAP` compiles maps made of built-ins to straight-line arithmetic (the same
    /// numbers, faster); off, every point is interpreted.
    pub kernels: bool,
}

impl Default for Limits {
    /// 20 M steps (about a second), 200 nested calls, 1 M items, 1 M cells, 256 MiB of values
    /// held at once, 256 KiB of source.
    ///
    /// The memory budget is a sixteenth of the 4 GiB that a page's WebAssembly memory may grow
    /// to (and never gives back), and 1,800 times what the largest of the paper's examples holds
    /// at once (Fig. 1's, Scripts 4.2 to 4.4: 145 KiB). Within it a run may hold, say, 16
    /// sequences of a million numbers, or a complex of a million points in 16 dimensions.
    fn default() -> Self {
        Limits {
            steps: 20_000_000,
            depth: 200,
            items: 1_000_000,
            cells: 1_000_000,
            memory: 256 << 20,
            source: 256 * 1024,
            kernels: true,
        }
    }
}

#[cfg(test)]
mod tests;
