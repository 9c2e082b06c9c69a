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

use alloc::boxed::Box;
use core::fmt;

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
}
