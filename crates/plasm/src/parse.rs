//! The parser: tokens to statements.
//!
//! Precedence, from the loosest: `..`, then `+ -`, then `* /`, then `**` (to the right), then
//! composition `~`, then application `:` (to the left), which binds tightest, so
//! `Choose ~ AA:Pred * /` is `(Choose ~ (AA:Pred)) * /`. An operator where an operand is expected
//! and not followed by one is the operator's function: `AA:+`, `C:-:1`, `* ~ INTSTO`, a trailing `/`.
//! `a op b` means `op:<a, b>`.

use std::rc::Rc;

use crate::lex::{Tok, lex};
use crate::{Error, ErrorKind, Span, Warning};

/// The most brackets and operators nested in one expression: each operator of a chain
/// (`a - b - c`, `f:x:y`, `f ~ g ~ h`) nests the expression one level deeper, as a bracket does.
pub(crate) const MAX_NESTING: u32 = 256;

/// An arithmetic operator, as a value or infix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `**`
    Pow,
}

impl Arith {
    /// The operator as written.
    pub fn symbol(self) -> &'static str {
        match self {
            Arith::Add => "+",
            Arith::Sub => "-",
            Arith::Mul => "*",
            Arith::Div => "/",
            Arith::Pow => "**",
        }
    }

    fn of(tok: &Tok) -> Option<Arith> {
        Some(match tok {
            Tok::Plus => Arith::Add,
            Tok::Minus => Arith::Sub,
            Tok::Star => Arith::Mul,
            Tok::Slash => Arith::Div,
            Tok::Pow => Arith::Pow,
            _ => return None,
        })
    }
}

/// An expression.
#[derive(Clone, Debug)]
pub(crate) enum Expr {
    Num(f64, Span),
    /// A name: its key (upper case) and its spelling.
    Name(Rc<str>, Rc<str>, Span),
    /// `< a, b, … >`
    Seq(Vec<Expr>, Span),
    /// `[ f, g, … ]`, that is `CONS:< f, g, … >`.
    Cons(Vec<Expr>, Span),
    /// An operator used as a function.
    Op(Arith, Span),
    /// `f:x`
    Apply(Box<Expr>, Box<Expr>, Span),
    /// `a op b`, that is `op:<a, b>`; the span is the operator's.
    Infix(Arith, Box<Expr>, Box<Expr>, Span),
    /// `f ~ g ~ …`, outermost first.
    Compose(Vec<Expr>, Span),
    /// `-x`
    Neg(Box<Expr>, Span),
    /// `a..b`
    Range(Box<Expr>, Box<Expr>, Span),
}

impl Expr {
    pub(crate) fn span(&self) -> Span {
        match self {
            Expr::Num(_, s)
            | Expr::Name(_, _, s)
            | Expr::Seq(_, s)
            | Expr::Cons(_, s)
            | Expr::Op(_, s)
            | Expr::Apply(_, _, s)
            | Expr::Infix(_, _, _, s)
            | Expr::Compose(_, s)
            | Expr::Neg(_, s)
            | Expr::Range(_, _, s) => *s,
        }
    }
}

/// One group of parameters, `(a, b :: Pred)`: a group of one binds its argument, a group of
/// several binds the items of a sequence of that length.
#[derive(Debug)]
pub(crate) struct Group {
    pub(crate) names: Vec<(Rc<str>, Rc<str>)>,
    pub(crate) pred: Expr,
    /// The predicate as written, for messages.
    pub(crate) pred_text: String,
}

/// A local definition of `WHERE … END`.
#[derive(Debug)]
pub(crate) struct Local {
    pub(crate) key: Rc<str>,
    pub(crate) name: Rc<str>,
    pub(crate) expr: Expr,
}

/// A definition with parameters, `DEF name (params)… = body WHERE locals END`, as a function
/// value holds it.
#[derive(Debug)]
pub struct Def {
    pub(crate) key: Rc<str>,
    pub(crate) name: Rc<str>,
    pub(crate) groups: Vec<Group>,
    pub(crate) body: Expr,
    pub(crate) locals: Vec<Local>,
}

impl Def {
    /// The name, as written in its `DEF`.
    pub fn name(&self) -> &str {
        &self.name
    }
}

/// A statement.
#[derive(Debug)]
pub(crate) enum Stmt {
    Def(Rc<Def>),
    Expr(Expr),
}

struct Parser<'w> {
    src: &'w str,
    toks: Vec<(Tok, Span)>,
    pos: usize,
    depth: u32,
    warnings: &'w mut Vec<Warning>,
}

/// Parses a whole script.
pub(crate) fn parse(src: &str, warnings: &mut Vec<Warning>) -> Result<Vec<Stmt>, Error> {
    parse_from(src, 1, warnings)
}

/// Parses `src` as if its first line were line `first_line` (the prelude's lines lie past any
/// script's).
pub(crate) fn parse_from(
    src: &str,
    first_line: u32,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Stmt>, Error> {
    let mut p = Parser {
        src,
        toks: lex(src, first_line)?,
        pos: 0,
        depth: 0,
        warnings,
    };
    let mut out = Vec::new();
    while p.peek() != &Tok::Eof {
        if p.peek() == &Tok::Semi {
            p.bump();
            continue;
        }
        out.push(p.statement()?);
    }
    Ok(out)
}

fn starts_operand(t: &Tok) -> bool {
    matches!(
        t,
        Tok::Num(_) | Tok::Name(_) | Tok::LParen | Tok::Lt | Tok::LBrack
    )
}

fn key(name: &str) -> Rc<str> {
    name.to_ascii_uppercase().into()
}

fn join(a: Span, b: Span) -> Span {
    Span {
        start: a.start,
        end: b.end.max(a.end),
        line: a.line,
        col: a.col,
    }
}

impl Parser<'_> {
    fn peek(&self) -> &Tok {
        &self.toks[self.pos].0
    }

    fn peek2(&self) -> &Tok {
        &self.toks[(self.pos + 1).min(self.toks.len() - 1)].0
    }

    fn span(&self) -> Span {
        self.toks[self.pos].1
    }

    fn bump(&mut self) -> (Tok, Span) {
        let t = self.toks[self.pos].clone();
        if self.pos + 1 < self.toks.len() {
            self.pos += 1;
        }
        t
    }

    fn error<T>(&self, message: String) -> Result<T, Error> {
        Err(Error::new(ErrorKind::Syntax, self.span(), message))
    }

    fn expect(&mut self, tok: Tok, what: &str) -> Result<Span, Error> {
        if *self.peek() == tok {
            Ok(self.bump().1)
        } else {
            self.error(format!("expected {what}, found {}", self.peek().describe()))
        }
    }

    fn name(&mut self, what: &str) -> Result<(Rc<str>, Rc<str>, Span), Error> {
        match self.peek().clone() {
            Tok::Name(n) => {
                let s = self.bump().1;
                Ok((key(&n), n.into(), s))
            }
            other => self.error(format!("expected {what}, found {}", other.describe())),
        }
    }

    fn statement(&mut self) -> Result<Stmt, Error> {
        if self.peek() == &Tok::Def {
            self.bump();
            let (key, name, _) = self.name("the name being defined after DEF")?;
            let mut groups = Vec::new();
            while self.peek() == &Tok::LParen {
                self.bump();
                let mut names = Vec::new();
                loop {
                    let (k, n, _) = self.name("a parameter name")?;
                    names.push((k, n));
                    if self.peek() == &Tok::Comma {
                        self.bump();
                    } else {
                        break;
                    }
                }
                self.expect(Tok::ColonColon, "`::` and the parameters' predicate")?;
                let pred = self.expr()?;
                let span = pred.span();
                let pred_text = self
                    .src
                    .get(span.start as usize..span.end as usize)
                    .unwrap_or_default()
                    .to_string();
                self.expect(Tok::RParen, "`)` closing the parameters")?;
                groups.push(Group {
                    names,
                    pred,
                    pred_text,
                });
            }
            self.expect(Tok::Eq, "`=` after the definition's name and parameters")?;
            let mut body = self.expr()?;
            self.continued(&mut body)?;
            let mut locals = Vec::new();
            if self.peek() == &Tok::Where {
                self.bump();
                loop {
                    let (k, name, _) = self.name("a local name after WHERE")?;
                    self.expect(Tok::Eq, "`=` after the local name")?;
                    let expr = self.expr()?;
                    locals.push(Local { key: k, name, expr });
                    if self.peek() == &Tok::Comma {
                        self.bump();
                    } else {
                        break;
                    }
                }
                self.expect(
                    Tok::End,
                    "`END` closing WHERE (or `,` before another local)",
                )?;
            }
            self.terminator("the definition")?;
            Ok(Stmt::Def(Rc::new(Def {
                key,
                name,
                groups,
                body,
                locals,
            })))
        } else {
            let mut e = self.expr()?;
            self.continued(&mut e)?;
            self.terminator("the expression")?;
            Ok(Stmt::Expr(e))
        }
    }

    fn terminator(&mut self, what: &str) -> Result<(), Error> {
        match self.peek() {
            Tok::Semi => {
                self.bump();
                Ok(())
            }
            Tok::Eof => Ok(()),
            other => {
                let found = other.describe();
                self.error(format!("expected `;` after {what}, found {found}"))
            }
        }
    }

    /// The paper prints Script 4.4's sequences of points as `<<0,0,0>>, <<10,0,0>>`: a sequence
    /// literal continued after a `,` outside brackets is read as one sequence holding the items of
    /// each, `<<0,0,0>, <10,0,0>>`, with a warning.
    fn continued(&mut self, e: &mut Expr) -> Result<(), Error> {
        if self.peek() != &Tok::Comma {
            return Ok(());
        }
        fn last_seq(e: &mut Expr) -> Option<&mut Vec<Expr>> {
            match e {
                Expr::Seq(items, _) => Some(items),
                Expr::Apply(_, arg, _) => last_seq(arg),
                _ => None,
            }
        }
        let at = self.span();
        if last_seq(e).is_none() {
            return self.error("expected `;`, found `,` (a list outside brackets)".into());
        }
        let mut parts = 1;
        while self.peek() == &Tok::Comma {
            self.bump();
            let more = self.expr()?;
            let Expr::Seq(items, _) = more else {
                return Err(Error::new(
                    ErrorKind::Syntax,
                    more.span(),
                    "expected `;`, found `,` (a list outside brackets)".into(),
                ));
            };
            last_seq(e).expect("checked above").extend(items);
            parts += 1;
        }
        self.warnings.push(Warning {
            span: at,
            message: format!(
                "{parts} sequences separated by `,` outside brackets are read as one sequence of \
                 their items (Script 4.4 is printed so: `<<0,0,0>>, <<10,0,0>>` means \
                 `<<0,0,0>, <10,0,0>>`)"
            ),
        });
        Ok(())
    }

    fn nest(&mut self) -> Result<(), Error> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(Error::new(
                ErrorKind::Limit,
                self.span(),
                format!("expressions nested more than {MAX_NESTING} deep"),
            ));
        }
        Ok(())
    }

    fn expr(&mut self) -> Result<Expr, Error> {
        self.nest()?;
        let e = self.range();
        self.depth -= 1;
        e
    }

    fn range(&mut self) -> Result<Expr, Error> {
        let a = self.additive()?;
        if self.peek() == &Tok::DotDot {
            let at = self.bump().1;
            let b = self.additive()?;
            return Ok(Expr::Range(Box::new(a), Box::new(b), at));
        }
        Ok(a)
    }

    /// The operator at the cursor if it is infix: followed by an operand (or by an operator,
    /// which is then its right operand as a value: `Choose ~ AA:Pred * /`).
    fn binary_op(&self, ops: &[Arith]) -> Option<Arith> {
        Arith::of(self.peek()).filter(|op| {
            ops.contains(op) && (starts_operand(self.peek2()) || Arith::of(self.peek2()).is_some())
        })
    }

    /// Runs `chain`, then gives back the nesting its links took.
    fn chained<T>(
        &mut self,
        chain: impl FnOnce(&mut Self, &mut u32) -> Result<T, Error>,
    ) -> Result<T, Error> {
        let mut links = 0;
        let r = chain(self, &mut links);
        self.depth -= links;
        r
    }

    fn link(&mut self, links: &mut u32) -> Result<(), Error> {
        self.nest()?;
        *links += 1;
        Ok(())
    }

    fn additive(&mut self) -> Result<Expr, Error> {
        self.left_chain(&[Arith::Add, Arith::Sub], Self::multiplicative)
    }

    fn multiplicative(&mut self) -> Result<Expr, Error> {
        self.left_chain(&[Arith::Mul, Arith::Div], Self::power)
    }

    /// `a op b op c …` for `ops`, to the left, with operands from `operand`.
    fn left_chain(
        &mut self,
        ops: &[Arith],
        operand: fn(&mut Self) -> Result<Expr, Error>,
    ) -> Result<Expr, Error> {
        self.chained(|p, links| {
            let mut a = operand(p)?;
            while let Some(op) = p.binary_op(ops) {
                p.link(links)?;
                let at = p.bump().1;
                let b = operand(p)?;
                a = Expr::Infix(op, Box::new(a), Box::new(b), at);
            }
            Ok(a)
        })
    }

    fn power(&mut self) -> Result<Expr, Error> {
        let a = self.compose()?;
        if let Some(op) = self.binary_op(&[Arith::Pow]) {
            let at = self.bump().1;
            self.nest()?;
            let b = self.power();
            self.depth -= 1;
            return Ok(Expr::Infix(op, Box::new(a), Box::new(b?), at));
        }
        Ok(a)
    }

    fn compose(&mut self) -> Result<Expr, Error> {
        let start = self.span();
        let mut parts = Vec::new();
        if self.peek() == &Tok::Tilde {
            // The paper's Script 4.2 prints Bernstein's body as `~ [ … ] ~ u`: the `*` of
            // PLaSM's `* ~ [ … ] ~ u` was lost. Read a missing left operand of `~` as `*`.
            self.warnings.push(Warning {
                span: start,
                message: "`~` has no left operand: read as `* ~` (the product of the items, as \
                          in PLaSM's Bernstein, whose `*` the paper's Script 4.2 lost)"
                    .into(),
            });
            parts.push(Expr::Op(Arith::Mul, start));
        } else {
            parts.push(self.term()?);
        }
        // A composition is one node however long: its parts are a list, not nested.
        while self.peek() == &Tok::Tilde {
            self.bump();
            parts.push(self.term()?);
        }
        if parts.len() == 1 {
            return Ok(parts.pop().expect("one part"));
        }
        let end = parts.last().map_or(start, Expr::span);
        Ok(Expr::Compose(parts, join(start, end)))
    }

    /// `-x` where `x` starts an operand; otherwise an application.
    fn term(&mut self) -> Result<Expr, Error> {
        if self.peek() == &Tok::Minus
            && (starts_operand(self.peek2()) || self.peek2() == &Tok::Minus)
        {
            let at = self.bump().1;
            self.nest()?;
            let x = self.term();
            self.depth -= 1;
            return Ok(negate(x?, at));
        }
        self.application()
    }

    fn application(&mut self) -> Result<Expr, Error> {
        self.chained(|p, links| {
            let mut f = p.primary()?;
            while p.peek() == &Tok::Colon {
                p.link(links)?;
                p.bump();
                let x = p.argument()?;
                let span = join(f.span(), x.span());
                f = Expr::Apply(Box::new(f), Box::new(x), span);
            }
            Ok(f)
        })
    }

    fn argument(&mut self) -> Result<Expr, Error> {
        if self.peek() == &Tok::Minus
            && (starts_operand(self.peek2()) || self.peek2() == &Tok::Minus)
        {
            let at = self.bump().1;
            self.nest()?;
            let x = self.argument();
            self.depth -= 1;
            return Ok(negate(x?, at));
        }
        self.primary()
    }

    fn list(&mut self, close: Tok) -> Result<Vec<Expr>, Error> {
        let mut items = Vec::new();
        if *self.peek() == close {
            self.bump();
            return Ok(items);
        }
        loop {
            items.push(self.expr()?);
            match self.peek() {
                Tok::Comma => {
                    self.bump();
                }
                t if *t == close => {
                    self.bump();
                    return Ok(items);
                }
                other => {
                    let found = other.describe();
                    return self.error(format!(
                        "expected `,` or `{}` closing the list, found {found}",
                        close.symbol()
                    ));
                }
            }
        }
    }

    fn primary(&mut self) -> Result<Expr, Error> {
        let (tok, at) = (self.peek().clone(), self.span());
        match tok {
            Tok::Num(x) => {
                self.bump();
                Ok(Expr::Num(x, at))
            }
            Tok::Name(n) => {
                self.bump();
                Ok(Expr::Name(key(&n), n.into(), at))
            }
            Tok::LParen => {
                self.bump();
                let e = self.expr()?;
                if self.peek() != &Tok::RParen {
                    let found = self.peek().describe();
                    return Err(Error::new(
                        ErrorKind::Syntax,
                        self.span(),
                        format!(
                            "expected `)` closing the `(` of line {}, column {}, found {found}",
                            at.line, at.col
                        ),
                    ));
                }
                self.bump();
                Ok(e)
            }
            Tok::Lt | Tok::LBrack => {
                self.bump();
                self.nest()?;
                let close = if tok == Tok::Lt { Tok::Gt } else { Tok::RBrack };
                let items = self.list(close);
                self.depth -= 1;
                let items = items.map_err(|mut e| {
                    if e.message.starts_with("expected `,` or") {
                        e.message.push_str(&format!(
                            " (the `{}` of line {}, column {})",
                            tok.symbol(),
                            at.line,
                            at.col
                        ));
                    }
                    e
                })?;
                let span = join(at, self.toks[self.pos - 1].1);
                Ok(if tok == Tok::Lt {
                    Expr::Seq(items, span)
                } else {
                    Expr::Cons(items, span)
                })
            }
            ref t if Arith::of(t).is_some() => {
                self.bump();
                Ok(Expr::Op(Arith::of(t).expect("an operator"), at))
            }
            other => self.error(format!(
                "expected an expression, found {}",
                other.describe()
            )),
        }
    }
}

fn negate(x: Expr, at: Span) -> Expr {
    match x {
        Expr::Num(v, s) => Expr::Num(-v, join(at, s)),
        other => {
            let span = join(at, other.span());
            Expr::Neg(Box::new(other), span)
        }
    }
}
