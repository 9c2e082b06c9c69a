//! The tests' HyperFun interpreter: a thin adaptor over the strict reader ([`super::read`]), so
//! every export test runs its file through HyperFun's own grammar and arithmetic. A refusal or a
//! runtime error fails the test with the reader's message, its line and position, and that line.

use super::read;

/// A parsed file, evaluating the body `my_model` (else the first).
pub(crate) struct Program {
    program: read::Program,
    text: alloc::string::String,
}

/// Panics with `error` and the line of `text` it points at.
fn fail(text: &str, error: &read::HfError, what: &str) -> ! {
    let line = text
        .lines()
        .nth(error.line.saturating_sub(1) as usize)
        .unwrap_or("");
    let shown: alloc::string::String = line.chars().take(300).collect();
    panic!("the strict HyperFun reader {what}: {error}\n  | {shown}");
}

impl Program {
    pub(crate) fn new(text: &str) -> Self {
        match read::Program::parse(text) {
            Ok(program) => Self {
                program,
                text: text.into(),
            },
            Err(e) => fail(text, &e, "refuses the file"),
        }
    }

    /// `my_model` at the point `x`.
    pub(crate) fn run(&self, x: [f64; 3]) -> f64 {
        match self.program.eval(x) {
            Ok(v) => v,
            Err(e) => fail(&self.text, &e, &alloc::format!("fails at {x:?}")),
        }
    }
}

/// `my_model` of the file `text` at the point `x` (parsed anew: use [`Program`] for many points).
pub(crate) fn eval(text: &str, x: [f64; 3]) -> f64 {
    Program::new(text).run(x)
}
