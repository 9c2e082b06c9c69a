//! Values: numbers, truth values, sequences, functions and complexes.

use std::fmt::{self, Write as _};
use std::rc::Rc;

use crate::complex::Complex;
use crate::meter::{self, buffer_bytes, rc_bytes};
use crate::parse::{Arith, Def};

/// A value of the language.
#[derive(Clone, Debug)]
pub enum Value {
    /// A real number.
    Num(f64),
    /// `TRUE` or `FALSE`, what predicates give.
    Bool(bool),
    /// `< a, b, … >`
    Seq(Rc<Items>),
    /// A function.
    Fun(Rc<Fun>),
    /// A simplicial complex (a polyhedral complex in PLaSM's words).
    Pol(Rc<Complex>),
}

/// The items of a sequence. Dropping a deep value (a sequence of sequences of …, or functions
/// built on functions, statement after statement) does not recurse: the children of each value
/// whose last reference goes are moved to a stack of our own.
///
/// A sequence is made by [`Value::seq`], which counts its bytes against the memory budget of a
/// run; they are given back when it is dropped.
#[derive(Debug)]
pub struct Items(Vec<Value>);

impl Items {
    /// Bytes of a sequence of `capacity` items: its `Rc` and its buffer.
    pub(crate) const fn bytes(capacity: usize) -> usize {
        rc_bytes::<Items>() + buffer_bytes::<Value>(capacity)
    }
}

impl core::ops::Deref for Items {
    type Target = Vec<Value>;
    fn deref(&self) -> &Vec<Value> {
        &self.0
    }
}

impl Drop for Items {
    fn drop(&mut self) {
        meter::credit(Items::bytes(self.0.capacity()));
        drop_iteratively(core::mem::take(&mut self.0));
    }
}

impl Drop for Fun {
    fn drop(&mut self) {
        meter::credit(self.bytes());
        let children = match self {
            Fun::Prim(_) => return,
            Fun::Partial(_, v)
            | Fun::Compose(v)
            | Fun::Cons(v)
            | Fun::Lift(_, v)
            | Fun::User(_, v) => core::mem::take(v),
        };
        drop_iteratively(children);
    }
}

/// Drops values with a stack of our own rather than the call stack: each value whose last
/// reference this is gives its children to the stack before it goes, childless.
fn drop_iteratively(mut stack: Vec<Value>) {
    while let Some(v) = stack.pop() {
        match v {
            Value::Seq(rc) => {
                if let Ok(mut items) = Rc::try_unwrap(rc) {
                    stack.append(&mut items.0);
                }
            }
            Value::Fun(rc) => {
                if let Ok(mut fun) = Rc::try_unwrap(rc) {
                    match &mut fun {
                        Fun::Prim(_) => {}
                        Fun::Partial(_, v)
                        | Fun::Compose(v)
                        | Fun::Cons(v)
                        | Fun::Lift(_, v)
                        | Fun::User(_, v) => stack.append(v),
                    }
                }
            }
            _ => {}
        }
    }
}

/// A function value. Functions are data, not closures, so that errors inside them can name what
/// went wrong and so that a script's functions can be shown.
#[derive(Debug)]
pub enum Fun {
    /// A built-in function.
    Prim(Prim),
    /// A built-in function of several curried arguments with the first ones given: `K:1`,
    /// `AA:f`, `C:EQ:0`.
    Partial(Prim, Vec<Value>),
    /// `f ~ g ~ …`, outermost first.
    Compose(Vec<Value>),
    /// `CONS:< f, g, … >`: `x ↦ < f:x, g:x, … >`.
    Cons(Vec<Value>),
    /// Arithmetic between functions: `x ↦ op:< f:x, g:x, … >`, where items that are not
    /// functions stand for themselves (`K:1 - ID`).
    Lift(Arith, Vec<Value>),
    /// A `DEF` with parameters and the argument groups given so far.
    User(Rc<Def>, Vec<Value>),
}

impl Fun {
    /// Bytes of a function: its `Rc` and the buffer of its arguments.
    fn bytes(&self) -> usize {
        let args = match self {
            Fun::Prim(_) => 0,
            Fun::Partial(_, v)
            | Fun::Compose(v)
            | Fun::Cons(v)
            | Fun::Lift(_, v)
            | Fun::User(_, v) => v.capacity(),
        };
        rc_bytes::<Fun>() + buffer_bytes::<Value>(args)
    }
}

macro_rules! prims {
    ($($variant:ident $name:literal $arity:literal $doc:literal,)*) => {
        /// A built-in function.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Prim {
            /// An arithmetic operator applied to a sequence: `+:<1, 2, 3>` is 6.
            Arith(Arith),
            /// The selector `S1`, `S2`, …: item `i` (from 1) of a sequence.
            Select(u32),
            $(#[doc = $doc] $variant,)*
        }

        /// Built-in names other than the selectors and the constants, upper case.
        pub(crate) const NAMES: &[(&str, Prim)] = &[$(($name, Prim::$variant),)*];

        impl Prim {
            /// Arguments taken one at a time before it acts (`K:a:b` takes 2).
            pub fn arity(self) -> usize {
                match self {
                    Prim::Arith(_) | Prim::Select(_) => 1,
                    $(Prim::$variant => $arity,)*
                }
            }

            /// The name in scripts.
            pub fn name(self) -> String {
                match self {
                    Prim::Arith(a) => a.symbol().into(),
                    Prim::Select(i) => format!("S{i}"),
                    $(Prim::$variant => $name.into(),)*
                }
            }
        }
    };
}

prims! {
    Id "ID" 1 "`ID:x` is `x`.",
    K "K" 2 "`K:a:x` is `a`: `K:a` is the constant function.",
    AA "AA" 2 "`AA:f:<a, b>` is `<f:a, f:b>`.",
    C "C" 3 "`C:f:a:x` is `f:<x, a>`: `C:f:a` fixes the right operand, as the paper's `Pred = C:-:1` (the predecessor) needs.",
    If "IF" 2 "`IF:<p, f, g>:x` is `f:x` where `p:x` is true, else `g:x`.",
    Cons "CONS" 1 "`CONS:<f, g>` is the function `x ↦ <f:x, g:x>`.",
    Comp "COMP" 1 "`COMP:<f, g>` is `f ~ g`.",
    Trans "TRANS" 1 "Transposes a sequence of sequences (shorter ones padded with 0).",
    Distl "DISTL" 1 "`DISTL:<a, <b, c>>` is `<<a, b>, <a, c>>`.",
    Distr "DISTR" 1 "`DISTR:<<a, b>, c>` is `<<a, c>, <b, c>>`.",
    Sel "SEL" 2 "`SEL:i:s` is item `i` of `s`, from 1.",
    Len "LEN" 1 "The length of a sequence.",
    First "FIRST" 1 "The first item.",
    Last "LAST" 1 "The last item.",
    Tail "TAIL" 1 "All items but the first.",
    Reverse "REVERSE" 1 "The items in reverse order.",
    Cat "CAT" 1 "Concatenates a sequence of sequences.",
    Al "AL" 1 "`AL:<a, <b, c>>` is `<a, b, c>`.",
    Ar "AR" 1 "`AR:<<a, b>, c>` is `<a, b, c>`.",
    Intsto "INTSTO" 1 "`INTSTO:n` is `<1, 2, …, n>`.",
    Repeat "#" 2 "`#:n:x` is `n` copies of `x`.",
    InnerProd "INNERPROD" 1 "`InnerProd:<a, b>` is `Σ aᵢ * bᵢ`, of numbers or functions.",
    Eq "EQ" 1 "Whether all items of a sequence are equal.",
    Or "OR" 1 "Whether any item is true.",
    And "AND" 1 "Whether every item is true.",
    Not "NOT" 1 "Negation.",
    Sin "SIN" 1 "Sine.",
    Cos "COS" 1 "Cosine.",
    Tan "TAN" 1 "Tangent.",
    Asin "ASIN" 1 "Arc sine.",
    Acos "ACOS" 1 "Arc cosine.",
    Atan "ATAN" 1 "Arc tangent.",
    Sqrt "SQRT" 1 "Square root.",
    Exp "EXP" 1 "Exponential.",
    Ln "LN" 1 "Natural logarithm.",
    Abs "ABS" 1 "Absolute value.",
    IsReal "ISREAL" 1 "Whether a value is a number.",
    IsNum "ISNUM" 1 "Whether a value is a number.",
    IsInt "ISINT" 1 "Whether a value is a whole number.",
    IsIntPos "ISINTPOS" 1 "Whether a value is a whole number above 0.",
    IsNat "ISNAT" 1 "Whether a value is a whole number, 0 or above.",
    IsBool "ISBOOL" 1 "Whether a value is TRUE or FALSE.",
    IsFun "ISFUN" 1 "Whether a value is a function.",
    IsSeq "ISSEQ" 1 "Whether a value is a sequence.",
    IsSeqOf "ISSEQOF" 2 "`IsSeqOf:p:s`: whether `s` is a sequence whose items all satisfy `p`.",
    IsPoint "ISPOINT" 1 "Whether a value is a sequence of numbers.",
    IsVect "ISVECT" 1 "Whether a value is a sequence of numbers.",
    IsPol "ISPOL" 1 "Whether a value is a complex.",
    Quote "QUOTE" 1 "`QUOTE:<1, -1, 2>`: segments of the positive lengths, gaps for the negative.",
    T "T" 3 "`T:i:d:pol` (or `T:<i, j>:<d, e>:pol`) translates coordinate `i` by `d`.",
    S "S" 3 "`S:i:s:pol` scales coordinate `i` by `s`.",
    Map "MAP" 2 "`MAP:f:pol` maps each point of a complex by `f` (a function or a sequence of coordinate functions).",
    Interval "INTERVAL" 2 "`interval:<a, b>:n`: `[a, b]` in `n` segments.",
    Intervals "INTERVALS" 2 "`Intervals:a:n`: `[0, a]` in `n` segments.",
    Domain "DOMAIN" 1 "`Domain:n`: `[0, 1]` in `n` segments.",
}

impl Prim {
    /// The function of a math built-in (`SIN`, …, `ABS`): the one table the interpreter and
    /// `MAP`'s compiler both use, so that they agree to the bit.
    pub(crate) fn unary_math(self) -> Option<fn(f64) -> f64> {
        Some(match self {
            Prim::Sin => f64::sin,
            Prim::Cos => f64::cos,
            Prim::Tan => f64::tan,
            Prim::Asin => f64::asin,
            Prim::Acos => f64::acos,
            Prim::Atan => f64::atan,
            Prim::Sqrt => f64::sqrt,
            Prim::Exp => f64::exp,
            Prim::Ln => f64::ln,
            Prim::Abs => f64::abs,
            _ => return None,
        })
    }
}

impl Value {
    /// A sequence. Its bytes count against the memory budget of a run until it is dropped.
    pub fn seq(items: Vec<Value>) -> Value {
        meter::charge(Items::bytes(items.capacity()));
        Value::Seq(Rc::new(Items(items)))
    }

    /// A function value. Its bytes count against the memory budget of a run until it is
    /// dropped. A [`Fun`] gives its bytes back when it is dropped: make one only to pass it here.
    pub fn fun(f: Fun) -> Value {
        meter::charge(f.bytes());
        Value::Fun(Rc::new(f))
    }

    /// The number, if it is one.
    pub fn as_num(&self) -> Option<f64> {
        match self {
            Value::Num(x) => Some(*x),
            _ => None,
        }
    }

    /// The items, if it is a sequence.
    pub fn as_seq(&self) -> Option<&[Value]> {
        match self {
            Value::Seq(s) => Some(s),
            _ => None,
        }
    }

    /// The complex, if it is one.
    pub fn as_pol(&self) -> Option<&Complex> {
        match self {
            Value::Pol(p) => Some(p),
            _ => None,
        }
    }

    /// The numbers of a sequence of numbers (a point).
    pub fn as_point(&self) -> Option<Vec<f64>> {
        self.as_seq()?.iter().map(Value::as_num).collect()
    }

    /// What kind of value, for messages: "a number", "a sequence of 3", …
    pub fn kind(&self) -> String {
        match self {
            Value::Num(_) => "a number".into(),
            Value::Bool(_) => "a truth value".into(),
            Value::Seq(s) => format!("a sequence of {}", s.len()),
            Value::Fun(_) => "a function".into(),
            Value::Pol(_) => "a complex".into(),
        }
    }

    /// Structural equality of numbers, truth values and sequences; functions and complexes are
    /// equal only to themselves. `budget` is the most items it may visit (it is decreased by
    /// those it does); `None` where it runs out or the values nest past 256 levels.
    pub fn same(&self, other: &Value, budget: &mut u64) -> Option<bool> {
        self.same_at(other, budget, 0)
    }

    fn same_at(&self, other: &Value, budget: &mut u64, depth: u32) -> Option<bool> {
        *budget = budget.checked_sub(1)?;
        Some(match (self, other) {
            (Value::Num(a), Value::Num(b)) => a == b,
            (Value::Bool(a), Value::Bool(b)) => a == b,
            (Value::Seq(a), Value::Seq(b)) => {
                if Rc::ptr_eq(a, b) {
                    return Some(true);
                }
                if depth >= 256 {
                    return None;
                }
                if a.len() != b.len() {
                    return Some(false);
                }
                for (x, y) in a.iter().zip(b.iter()) {
                    if !x.same_at(y, budget, depth + 1)? {
                        return Some(false);
                    }
                }
                true
            }
            (Value::Fun(a), Value::Fun(b)) => Rc::ptr_eq(a, b),
            (Value::Pol(a), Value::Pol(b)) => {
                if !Rc::ptr_eq(a, b) {
                    *budget = budget.checked_sub((a.points.len() + a.cells.len()) as u64)?;
                }
                Rc::ptr_eq(a, b) || a == b
            }
            _ => false,
        })
    }
}

/// At most this many characters of a value are shown.
const SHOWN: usize = 160;

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = String::new();
        write_value(&mut s, self, 0);
        if s.chars().count() > SHOWN {
            s = s.chars().take(SHOWN).collect::<String>() + "…";
        }
        f.write_str(&s)
    }
}

fn write_value(out: &mut String, v: &Value, depth: u32) {
    if out.len() > SHOWN * 4 || depth > 64 {
        out.push('…');
        return;
    }
    match v {
        Value::Num(x) => {
            let _ = write!(out, "{x}");
        }
        Value::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
        Value::Seq(items) => {
            out.push('<');
            for (i, x) in items.iter().enumerate() {
                if out.len() > SHOWN * 4 {
                    break;
                }
                if i > 0 {
                    out.push_str(", ");
                }
                write_value(out, x, depth + 1);
            }
            out.push('>');
        }
        Value::Fun(fun) => write_fun(out, fun, depth + 1),
        Value::Pol(p) => {
            let cells = match p.order {
                1 => "points",
                2 => "segments",
                3 => "triangles",
                _ => "tetrahedra",
            };
            let _ = write!(
                out,
                "a complex of {} {cells} on {} points in {}D",
                p.cell_count(),
                p.point_count(),
                p.dim
            );
        }
    }
}

fn write_fun(out: &mut String, fun: &Fun, depth: u32) {
    let list = |out: &mut String, items: &[Value], sep: &str| {
        for (i, x) in items.iter().enumerate() {
            if out.len() > SHOWN * 4 {
                break;
            }
            if i > 0 {
                out.push_str(sep);
            }
            write_value(out, x, depth);
        }
    };
    match fun {
        Fun::Prim(p) => out.push_str(&p.name()),
        Fun::Partial(p, args) => {
            out.push_str(&p.name());
            out.push(':');
            list(out, args, ":");
        }
        Fun::Compose(fs) => {
            out.push('(');
            list(out, fs, " ~ ");
            out.push(')');
        }
        Fun::Cons(fs) => {
            out.push('[');
            list(out, fs, ", ");
            out.push(']');
        }
        Fun::Lift(op, items) => {
            out.push('(');
            if items.len() == 1 {
                out.push_str(op.symbol());
            }
            list(out, items, &format!(" {} ", op.symbol()));
            out.push(')');
        }
        Fun::User(def, args) => {
            out.push_str(&def.name);
            for a in args {
                out.push(':');
                write_value(out, a, depth);
            }
        }
    }
}
