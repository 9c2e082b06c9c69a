//! Booleans of ESC solids as chain algebra (the paper's §5), evaluated at points.
//!
//! For normal chains `δ₁`, `δ₂` (associated functions `f₁`, `f₂` with values 0 and 1) the paper's
//! theorems give the chains of the results, whose associated functions are, at every point:
//!
//! | result | chain | `f` |
//! |---|---|---|
//! | `A ∩ B` | `Σ aᵢ·bⱼ·ExCell(Eᵢ ∩ Fⱼ)` (Theorem 2) | `f₁·f₂` |
//! | `A ∪ B` | `δ₁ + δ₂ − δ_{A∩B}` (Theorem 3) | `f₁ + f₂ − f₁·f₂` |
//! | `Aᶜ` | `δ_R − δ₁` (Theorem 4) | `1 − f₁` |
//! | `A − B` | `δ₁ − δ_{A∩B}` (Theorem 5, normal form) | `f₁ − f₁·f₂` |
//!
//! Each result is again a normal chain, so expressions compose into trees ([`Expr`]). Evaluation
//! is lazy: where `f₁ = 0`, an intersection or difference does not ask for `f₂`.
//!
//! An expression is also written as text over named solids ([`Expr::parse`], [`Expr::text`]):
//! `|` union, `&` intersection, `-` difference, `!` complement, and brackets. `!` binds tightest,
//! then `&` (the chains' product), then `|` and `-` (sums), left to right:
//! `!A | B & C - D` is `((!A) | (B & C)) - D`. The set symbols `∪ ∩ − ¬` and `\` (difference) and
//! `~` (complement) are read too.
//!
//! ```
//! use bezsolid_core::esc::{Expr, Op};
//!
//! let names = ["A", "B", "C", "D"];
//! let e = Expr::parse("(A | B) - (C & D)", &names).unwrap();
//! let ab = Expr::binary(Op::Union, Expr::Solid(0), Expr::Solid(1));
//! let cd = Expr::binary(Op::Intersection, Expr::Solid(2), Expr::Solid(3));
//! assert_eq!(e, Expr::binary(Op::Difference, ab, cd));
//! assert_eq!(e.text(&names), "A | B - C & D");
//! assert_eq!(Expr::parse("!(A|B)", &names).unwrap().text(&names), "!(A | B)");
//! assert!(Expr::parse("A | E", &names).is_err());
//! ```

use alloc::boxed::Box;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;

/// The longest expression text read, in characters.
pub const MAX_EXPR_CHARS: usize = 4096;
/// The deepest nesting of brackets and complements in an expression's text.
pub const MAX_EXPR_DEPTH: usize = 64;
/// The most solids an expression's text may name (counting repeats).
pub const MAX_EXPR_TERMS: usize = 256;

/// A binary Boolean operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    /// `A ∪ B`.
    Union,
    /// `A ∩ B`.
    Intersection,
    /// `A − B`.
    Difference,
}

impl Op {
    /// Every operation, in the order the modeler lists them.
    pub const ALL: [Op; 3] = [Op::Union, Op::Intersection, Op::Difference];

    /// The command-line name: `union`, `intersection`, `difference`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Union => "union",
            Self::Intersection => "intersection",
            Self::Difference => "difference",
        }
    }

    /// The operation named `name` (`union`/`or`/`|`, `intersection`/`and`/`&`,
    /// `difference`/`minus`/`-`).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "union" | "or" | "|" => Some(Self::Union),
            "intersection" | "and" | "&" => Some(Self::Intersection),
            "difference" | "minus" | "-" => Some(Self::Difference),
            _ => None,
        }
    }

    /// The associated function of the result from those of the operands (values 0 or 1).
    #[must_use]
    pub fn apply(self, f1: i32, f2: i32) -> i32 {
        match self {
            Self::Union => f1 + f2 - f1 * f2,
            Self::Intersection => f1 * f2,
            Self::Difference => f1 - f1 * f2,
        }
    }

    /// The paper's intermediate picture (Figs. 12, 14, 16): the partial chain before its last,
    /// correcting term (`δ₁ + δ₂` for a union, `δ₁` for an intersection or a difference). Returns
    /// `(in the partial chain, marked)`, where a marked point is in the partial chain but its value
    /// there is not the final one: counted twice by a union, outside `B` for an intersection,
    /// inside `B` for a difference. The final term removes exactly the marked points' excess.
    #[must_use]
    pub fn partial(self, f1: i32, f2: i32) -> (bool, bool) {
        let partial = match self {
            Self::Union => f1 + f2,
            Self::Intersection | Self::Difference => f1,
        };
        let final_value = self.apply(f1, f2);
        (partial >= 1, partial >= 1 && partial != final_value)
    }
}

impl fmt::Display for Op {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A Boolean expression over numbered solids.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    /// Solid number `i`.
    Solid(usize),
    /// The complement.
    Complement(Box<Expr>),
    /// A binary operation.
    Binary(Op, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// `a op b`.
    #[must_use]
    pub fn binary(op: Op, a: Expr, b: Expr) -> Self {
        Self::Binary(op, Box::new(a), Box::new(b))
    }

    /// The complement of `a`.
    #[must_use]
    pub fn complement(a: Expr) -> Self {
        Self::Complement(Box::new(a))
    }

    /// The associated function of the expression's chain, from those of the solids: `f(i)` is
    /// solid `i`'s value (0 or 1) at the point. Solids the result does not depend on there are not
    /// asked.
    pub fn value(&self, f: &mut impl FnMut(usize) -> i32) -> i32 {
        match self {
            Self::Solid(i) => f(*i),
            Self::Complement(a) => 1 - a.value(f),
            Self::Binary(op, a, b) => {
                let fa = a.value(f);
                match op {
                    Op::Intersection | Op::Difference if fa == 0 => 0,
                    Op::Union if fa == 1 => 1,
                    _ => op.apply(fa, b.value(f)),
                }
            }
        }
    }

    /// The largest solid number used, plus one.
    #[must_use]
    pub fn arity(&self) -> usize {
        match self {
            Self::Solid(i) => i + 1,
            Self::Complement(a) => a.arity(),
            Self::Binary(_, a, b) => a.arity().max(b.arity()),
        }
    }

    /// The expression in `text`, whose solids are named by `names` (solid `i` is `names[i]`).
    ///
    /// A name is a letter or `_` followed by letters, digits and `_`. Whitespace is free.
    ///
    /// # Errors
    ///
    /// [`ExprError`]: text past [`MAX_EXPR_CHARS`], nesting past [`MAX_EXPR_DEPTH`], more than
    /// [`MAX_EXPR_TERMS`] names, a name not in `names`, or a symbol where it cannot be, with its
    /// place.
    pub fn parse(text: &str, names: &[impl AsRef<str>]) -> Result<Self, ExprError> {
        let chars = text.chars().count();
        if chars > MAX_EXPR_CHARS {
            return Err(ExprError::TooLong(chars));
        }
        let tokens = tokens(text)?;
        if tokens.is_empty() {
            return Err(ExprError::Empty);
        }
        let mut parser = Parser {
            tokens,
            at: 0,
            depth: 0,
            terms: 0,
            names: names.iter().map(AsRef::as_ref).collect(),
        };
        let expr = parser.union()?;
        match parser.tokens.get(parser.at) {
            None => Ok(expr),
            Some(t) => Err(ExprError::Unexpected {
                found: t.kind.to_string(),
                at: t.at,
                expected: if t.kind == Token::Close {
                    "an operation or the end (this `)` closes no bracket)"
                } else {
                    "an operation (| & -) or the end"
                },
            }),
        }
    }

    /// The expression as text over `names` (solid `i` is `names[i]`, or `#i` past them), with the
    /// brackets it needs and no more: [`Expr::parse`] of the text gives the expression back.
    #[must_use]
    pub fn text(&self, names: &[impl AsRef<str>]) -> String {
        let mut out = String::new();
        self.write(names, &mut out);
        out
    }

    /// How tightly the expression's top binds: 0 for `|` and `-`, 1 for `&`, 2 for the rest.
    fn precedence(&self) -> u8 {
        match self {
            Self::Binary(Op::Union | Op::Difference, ..) => 0,
            Self::Binary(Op::Intersection, ..) => 1,
            Self::Solid(_) | Self::Complement(_) => 2,
        }
    }

    fn write(&self, names: &[impl AsRef<str>], out: &mut String) {
        let bracketed = |e: &Self, bracket: bool, out: &mut String| {
            if bracket {
                out.push('(');
                e.write(names, out);
                out.push(')');
            } else {
                e.write(names, out);
            }
        };
        match self {
            Self::Solid(i) => match names.get(*i) {
                Some(name) => out.push_str(name.as_ref()),
                None => {
                    out.push('#');
                    out.push_str(&i.to_string());
                }
            },
            Self::Complement(a) => {
                out.push('!');
                bracketed(a, a.precedence() < 2, out);
            }
            Self::Binary(op, a, b) => {
                let p = self.precedence();
                bracketed(a, a.precedence() < p, out);
                out.push_str(match op {
                    Op::Union => " | ",
                    Op::Intersection => " & ",
                    Op::Difference => " - ",
                });
                // Left to right: a right operand of the same binding keeps its brackets.
                bracketed(b, b.precedence() <= p, out);
            }
        }
    }
}

/// Why an expression's text was refused. Places (`at`) count characters from 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExprError {
    /// Nothing but whitespace.
    Empty,
    /// Longer than [`MAX_EXPR_CHARS`]: its length in characters.
    TooLong(usize),
    /// Brackets and complements nested deeper than [`MAX_EXPR_DEPTH`].
    TooDeep {
        /// Where the nesting went past the cap.
        at: usize,
    },
    /// More than [`MAX_EXPR_TERMS`] names.
    TooManyTerms,
    /// A character that is no symbol or name.
    Character {
        /// The character.
        found: char,
        /// Its place.
        at: usize,
    },
    /// A name that is no solid's.
    UnknownName {
        /// The name.
        name: String,
        /// Its place.
        at: usize,
        /// The solids' names, comma-separated.
        known: String,
    },
    /// A symbol (or the end) where something else must be.
    Unexpected {
        /// What was found (`the end` at the end).
        found: String,
        /// Its place.
        at: usize,
        /// What can be there.
        expected: &'static str,
    },
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "the expression is empty"),
            Self::TooLong(n) => write!(
                f,
                "the expression has {n} characters; at most {MAX_EXPR_CHARS} are read"
            ),
            Self::TooDeep { at } => write!(
                f,
                "the expression nests brackets and complements more than {MAX_EXPR_DEPTH} deep (at character {at})"
            ),
            Self::TooManyTerms => write!(
                f,
                "the expression names solids more than {MAX_EXPR_TERMS} times"
            ),
            Self::Character { found, at } => write!(
                f,
                "unexpected {found:?} at character {at}: use names, | & - ! and brackets"
            ),
            Self::UnknownName { name, at, known } => write!(
                f,
                "no solid is named {name:?} (at character {at}); the solids are {known}"
            ),
            Self::Unexpected {
                found,
                at,
                expected,
            } => write!(f, "expected {expected} at character {at}, found {found}"),
        }
    }
}

impl core::error::Error for ExprError {}

/// Whether `name` can name a solid in an expression: a letter or `_`, then letters, digits, `_`.
#[must_use]
pub fn is_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Token {
    Name(String),
    Op(Op),
    Not,
    Open,
    Close,
}

impl fmt::Display for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Name(n) => write!(f, "the name {n:?}"),
            Self::Op(op) => write!(f, "the {op}"),
            Self::Not => write!(f, "a complement (!)"),
            Self::Open => write!(f, "\"(\""),
            Self::Close => write!(f, "\")\""),
        }
    }
}

struct Spanned {
    kind: Token,
    at: usize,
}

fn tokens(text: &str) -> Result<Vec<Spanned>, ExprError> {
    let mut out = Vec::new();
    let mut chars = text.chars().enumerate().peekable();
    while let Some((i, c)) = chars.next() {
        let at = i + 1;
        let kind = match c {
            c if c.is_whitespace() => continue,
            '|' | '∪' => Token::Op(Op::Union),
            '&' | '∩' => Token::Op(Op::Intersection),
            '-' | '−' | '\\' => Token::Op(Op::Difference),
            '!' | '¬' | '~' => Token::Not,
            '(' => Token::Open,
            ')' => Token::Close,
            c if c.is_alphabetic() || c == '_' => {
                let mut name = String::from(c);
                while let Some(&(_, c)) = chars.peek() {
                    if !(c.is_alphanumeric() || c == '_') {
                        break;
                    }
                    name.push(c);
                    chars.next();
                }
                Token::Name(name)
            }
            found => return Err(ExprError::Character { found, at }),
        };
        out.push(Spanned { kind, at });
    }
    Ok(out)
}

struct Parser<'a> {
    tokens: Vec<Spanned>,
    at: usize,
    depth: usize,
    terms: usize,
    names: Vec<&'a str>,
}

impl Parser<'_> {
    /// `term (('|' | '-') term)*`.
    fn union(&mut self) -> Result<Expr, ExprError> {
        let mut e = self.intersection()?;
        while let Some(Token::Op(op @ (Op::Union | Op::Difference))) =
            self.tokens.get(self.at).map(|t| &t.kind)
        {
            let op = *op;
            self.at += 1;
            e = Expr::binary(op, e, self.intersection()?);
        }
        Ok(e)
    }

    /// `factor ('&' factor)*`.
    fn intersection(&mut self) -> Result<Expr, ExprError> {
        let mut e = self.factor()?;
        while let Some(Token::Op(Op::Intersection)) = self.tokens.get(self.at).map(|t| &t.kind) {
            self.at += 1;
            e = Expr::binary(Op::Intersection, e, self.factor()?);
        }
        Ok(e)
    }

    /// `'!' factor | '(' union ')' | name`.
    fn factor(&mut self) -> Result<Expr, ExprError> {
        let end = self.tokens.last().map_or(1, |t| t.at + 1);
        let Some(token) = self.tokens.get(self.at) else {
            return Err(ExprError::Unexpected {
                found: "the end".into(),
                at: end,
                expected: "a name, ! or (",
            });
        };
        let at = token.at;
        self.at += 1;
        match &token.kind {
            Token::Name(name) => {
                self.terms += 1;
                if self.terms > MAX_EXPR_TERMS {
                    return Err(ExprError::TooManyTerms);
                }
                match self.names.iter().position(|n| n == name) {
                    Some(i) => Ok(Expr::Solid(i)),
                    None => Err(ExprError::UnknownName {
                        name: name.clone(),
                        at,
                        known: self.names.join(", "),
                    }),
                }
            }
            Token::Not => {
                self.nest(at)?;
                let e = Expr::complement(self.factor()?);
                self.depth -= 1;
                Ok(e)
            }
            Token::Open => {
                self.nest(at)?;
                let e = self.union()?;
                self.depth -= 1;
                match self.tokens.get(self.at) {
                    Some(Spanned {
                        kind: Token::Close, ..
                    }) => {
                        self.at += 1;
                        Ok(e)
                    }
                    other => Err(ExprError::Unexpected {
                        found: other.map_or_else(|| "the end".into(), |t| t.kind.to_string()),
                        at: other.map_or(end, |t| t.at),
                        expected: "an operation or \")\" to close a bracket",
                    }),
                }
            }
            other => Err(ExprError::Unexpected {
                found: other.to_string(),
                at,
                expected: "a name, ! or (",
            }),
        }
    }

    fn nest(&mut self, at: usize) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_EXPR_DEPTH {
            return Err(ExprError::TooDeep { at });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_algebra_is_the_set_operations() {
        for f1 in 0..2 {
            for f2 in 0..2 {
                let (a, b) = (f1 == 1, f2 == 1);
                assert_eq!(Op::Union.apply(f1, f2) == 1, a || b);
                assert_eq!(Op::Intersection.apply(f1, f2) == 1, a && b);
                assert_eq!(Op::Difference.apply(f1, f2) == 1, a && !b);
                for op in Op::ALL {
                    assert!(
                        (0..=1).contains(&op.apply(f1, f2)),
                        "normal chains stay normal"
                    );
                    let expr = Expr::binary(op, Expr::Solid(0), Expr::Solid(1));
                    assert_eq!(expr.value(&mut |i| [f1, f2][i]), op.apply(f1, f2));
                }
            }
        }
    }

    #[test]
    fn the_partial_chains_mark_what_the_last_term_removes() {
        assert_eq!(Op::Union.partial(1, 1), (true, true));
        assert_eq!(Op::Union.partial(1, 0), (true, false));
        assert_eq!(Op::Intersection.partial(1, 0), (true, true));
        assert_eq!(Op::Intersection.partial(1, 1), (true, false));
        assert_eq!(Op::Difference.partial(1, 1), (true, true));
        assert_eq!(Op::Difference.partial(0, 1), (false, false));
        for op in Op::ALL {
            assert_eq!(Op::from_name(op.name()), Some(op));
        }
    }

    #[test]
    fn text_binds_complement_then_intersection_then_union_and_difference_left_to_right() {
        let names = ["A", "B", "C", "D"];
        let s = |i| Expr::Solid(i);
        let parse = |t: &str| Expr::parse(t, &names).unwrap();
        assert_eq!(
            parse("!A | B & C - D"),
            Expr::binary(
                Op::Difference,
                Expr::binary(
                    Op::Union,
                    Expr::complement(s(0)),
                    Expr::binary(Op::Intersection, s(1), s(2))
                ),
                s(3)
            )
        );
        assert_eq!(
            parse("A - B - C"),
            Expr::binary(
                Op::Difference,
                Expr::binary(Op::Difference, s(0), s(1)),
                s(2)
            )
        );
        assert_eq!(
            parse("A-(B-C)"),
            Expr::binary(
                Op::Difference,
                s(0),
                Expr::binary(Op::Difference, s(1), s(2))
            )
        );
        assert_eq!(parse("¬(A ∪ B) ∩ C − D"), parse("!(A|B)&C-D"));
        assert_eq!(parse("~A \\ B"), parse("!A - B"));
        assert_eq!(parse(" ( ( A ) ) "), s(0));
        // Names of more than a letter.
        let long = ["left_wing", "Body2"];
        assert_eq!(
            Expr::parse("Body2&!left_wing", &long).unwrap(),
            Expr::binary(Op::Intersection, s(1), Expr::complement(s(0)))
        );
    }

    #[test]
    fn text_round_trips_every_expression() {
        let names = ["A", "B", "C"];
        let mut seed = 7_u64;
        let mut next = move |n: u64| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) % n
        };
        fn random(next: &mut impl FnMut(u64) -> u64, depth: u32) -> Expr {
            match if depth == 0 { 0 } else { next(5) } {
                0 => Expr::Solid(next(3) as usize),
                1 => Expr::complement(random(next, depth - 1)),
                k => Expr::binary(
                    Op::ALL[k as usize - 2],
                    random(next, depth - 1),
                    random(next, depth - 1),
                ),
            }
        }
        for _ in 0..500 {
            let e = random(&mut next, 5);
            let text = e.text(&names);
            assert_eq!(Expr::parse(&text, &names).as_ref(), Ok(&e), "{text}");
            // The same values at every point as the expression it came from.
            for bits in 0..8 {
                let f = |i: usize| (bits >> i) & 1;
                let again = Expr::parse(&text, &names).unwrap();
                assert_eq!(again.value(&mut |i| f(i)), e.value(&mut |i| f(i)));
            }
        }
    }

    #[test]
    fn bad_text_is_refused_with_its_place() {
        let names = ["A", "B"];
        let err = |t: &str| Expr::parse(t, &names).unwrap_err();
        assert_eq!(err(""), ExprError::Empty);
        assert_eq!(err("  "), ExprError::Empty);
        assert!(
            matches!(err("A | C"), ExprError::UnknownName { at: 5, ref name, .. } if name == "C")
        );
        assert!(err("A | C").to_string().contains("the solids are A, B"));
        assert!(matches!(
            err("A # B"),
            ExprError::Character { found: '#', at: 3 }
        ));
        assert!(matches!(err("A |"), ExprError::Unexpected { at: 4, .. }));
        assert!(matches!(err("(A | B"), ExprError::Unexpected { at: 7, .. }));
        assert!(matches!(err("A B"), ExprError::Unexpected { at: 3, .. }));
        assert!(matches!(err("A)"), ExprError::Unexpected { at: 2, .. }));
        assert!(matches!(err("| A"), ExprError::Unexpected { at: 1, .. }));
        // Caps: nesting, names and length, before any deep recursion.
        let deep = "(".repeat(MAX_EXPR_DEPTH + 1) + "A" + &")".repeat(MAX_EXPR_DEPTH + 1);
        assert!(matches!(err(&deep), ExprError::TooDeep { .. }));
        let nots = "!".repeat(100_000) + "A";
        assert!(matches!(err(&nots), ExprError::TooLong(_)));
        assert!(matches!(err(&"!".repeat(1000)), ExprError::TooDeep { .. }));
        let many = ["A"; MAX_EXPR_TERMS + 1].join("|");
        assert_eq!(err(&many), ExprError::TooManyTerms);
        let at_caps = "(".repeat(MAX_EXPR_DEPTH) + "A" + &")".repeat(MAX_EXPR_DEPTH);
        assert_eq!(Expr::parse(&at_caps, &names), Ok(Expr::Solid(0)));
        assert!(is_name("A_1") && is_name("_x") && is_name("Ω") && !is_name("1A") && !is_name(""));
    }

    #[test]
    fn any_text_parses_or_is_refused_and_what_parses_round_trips() {
        let names = ["A", "B", "wing"];
        let pieces = [
            "A", "B", "wing", "C", "|", "&", "-", "!", "(", ")", " ", "∪", "¬", "\\", "#", "1", "_",
        ];
        let mut seed = 3_u64;
        let mut next = move |n: usize| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) as usize % n
        };
        let mut parsed = 0;
        for _ in 0..5000 {
            let len = 1 + next(12);
            let text: String = (0..len).map(|_| pieces[next(pieces.len())]).collect();
            if let Ok(e) = Expr::parse(&text, &names) {
                parsed += 1;
                assert!(e.arity() <= names.len());
                assert_eq!(Expr::parse(&e.text(&names), &names), Ok(e), "{text}");
            }
        }
        assert!(parsed > 50, "only {parsed} texts parsed");
    }
}
