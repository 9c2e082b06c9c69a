//! The parser's expressions and conditions: operators at HyperFun's levels, items of arrays,
//! and calls of functions and bodies with HyperFun's argument checks.

use alloc::boxed::Box;
use alloc::format;
use alloc::vec::Vec;

use super::code::{Arg, ArrRef, Bin, CallSite, Kind, LibSite};
use super::library::{Arr, Function, Imp, Param, too_short};
use super::parse::{Name, Parser, Res, msg};
use super::scan::{Pos, Tok};
use super::{HfError, HfErrorKind};

impl Parser<'_> {
    // ---- conditions ----------------------------------------------------------------------------

    /// `cmp { (and | or) cmp }`: one level, left to right.
    pub(super) fn condition(&mut self) -> Res<u32> {
        let mut l = self.comparison()?;
        loop {
            let op = match self.sc.tok {
                Tok::And => Bin::Both,
                Tok::Or => Bin::Either,
                _ => return Ok(l),
            };
            let pos = self.sc.pos;
            self.sc.next();
            let r = self.comparison()?;
            l = self.node(Kind::Bin(op, l, r), pos, self.first(l))?;
        }
    }

    fn comparison(&mut self) -> Res<u32> {
        let mut l = self.boolean()?;
        loop {
            let op = match self.sc.tok {
                Tok::NotEqual => Bin::NotEqual,
                Tok::Less => Bin::Less,
                Tok::LessEqual => Bin::LessEqual,
                Tok::Greater => Bin::Greater,
                Tok::GreaterEqual => Bin::GreaterEqual,
                Tok::Assign => Bin::Equal,
                _ => return Ok(l),
            };
            let pos = self.sc.pos;
            self.sc.next();
            let r = self.boolean()?;
            l = self.node(Kind::Bin(op, l, r), pos, self.first(l))?;
        }
    }

    /// `not b`, `( cond )` (a `(` here always opens a condition) or an expression.
    fn boolean(&mut self) -> Res<u32> {
        self.enter()?;
        let id = match self.sc.tok {
            Tok::Not => {
                let pos = self.sc.pos;
                self.sc.next();
                let a = self.boolean()?;
                self.node(Kind::Not(a), pos, self.first(a))?
            }
            Tok::LParen => {
                self.sc.next();
                let c = self.condition()?;
                self.check(Tok::RParen, msg::RIGHT_PAREN)?;
                self.sc.next();
                c
            }
            _ => self.expr()?,
        };
        self.leave();
        Ok(id)
    }

    // ---- expressions ---------------------------------------------------------------------------

    /// `term { (+ | - | & | '|' | \ | @) term }`: all six at one level, left to right.
    pub(super) fn expr(&mut self) -> Res<u32> {
        self.enter()?;
        let mut l = self.term()?;
        loop {
            let op = match self.sc.tok {
                Tok::Plus => Bin::Add,
                Tok::Minus => Bin::Sub,
                Tok::Amp | Tok::At => Bin::And,
                Tok::Bar => Bin::Or,
                Tok::Backslash => Bin::Minus,
                _ => break,
            };
            let pos = self.sc.pos;
            self.sc.next();
            let r = self.term()?;
            l = self.node(Kind::Bin(op, l, r), pos, self.first(l))?;
        }
        self.leave();
        Ok(l)
    }

    fn term(&mut self) -> Res<u32> {
        let mut l = self.factor()?;
        loop {
            let op = match self.sc.tok {
                Tok::Star => Bin::Mul,
                Tok::Slash => Bin::Div,
                _ => return Ok(l),
            };
            let pos = self.sc.pos;
            self.sc.next();
            let r = self.factor()?;
            l = self.node(Kind::Bin(op, l, r), pos, self.first(l))?;
        }
    }

    /// `unary { ^ unary }`: left to right, so `2^3^2` is 64.
    fn factor(&mut self) -> Res<u32> {
        let mut l = self.unary()?;
        while self.sc.tok == Tok::Pow {
            let pos = self.sc.pos;
            self.sc.next();
            let r = self.unary()?;
            l = self.node(Kind::Bin(Bin::Pow, l, r), pos, self.first(l))?;
        }
        Ok(l)
    }

    /// Signs bind tighter than `^`: `-x^2` is `(-x)^2`.
    fn unary(&mut self) -> Res<u32> {
        let tok = self.sc.tok;
        if !matches!(tok, Tok::Plus | Tok::Minus | Tok::Tilde) {
            return self.primary();
        }
        self.enter()?;
        let pos = self.sc.pos;
        self.sc.next();
        let a = self.unary()?;
        let id = match tok {
            Tok::Plus => a,
            _ => self.node(Kind::Neg(a), pos, self.first(a))?,
        };
        self.leave();
        Ok(id)
    }

    fn primary(&mut self) -> Res<u32> {
        let pos = self.sc.pos;
        match self.sc.tok {
            Tok::Num => {
                let v = self.sc.num;
                self.sc.next();
                self.node(Kind::Num(v), pos, pos)
            }
            Tok::LParen => {
                self.sc.next();
                let e = self.expr()?;
                self.check(Tok::RParen, msg::RIGHT_PAREN)?;
                self.sc.next();
                Ok(e)
            }
            Tok::X => self.item(self.body.x, false),
            Tok::A => self.item(self.body.a, false),
            Tok::S => self.item(self.body.s, false),
            Tok::Ident => match self.names.get(&self.sc.text).copied() {
                Some(Name::Array(arr)) => self.item(arr, true),
                Some(Name::Scalar(cell)) => {
                    self.sc.next();
                    self.node(Kind::Var(cell), pos, pos)
                }
                None => match self.known.get(&self.sc.text).copied() {
                    Some(callee) => self.body_call(callee),
                    None => Err(self.error(msg::UNASSIGNED)),
                },
            },
            Tok::Func => self.function(),
            _ => Err(self.error(msg::EXPRESSION)),
        }
    }

    /// `p[i]` with the array's name current.
    fn item(&mut self, arr: Arr, tracked: bool) -> Res<u32> {
        let name = self.sc.pos;
        self.next_is(Tok::LBracket, msg::LEFT_BRACKET)?;
        self.sc.next();
        let index = self.expr()?;
        self.check(Tok::RBracket, msg::RIGHT_BRACKET)?;
        self.sc.next();
        let first = self.first(index);
        let arr = ArrRef { arr, tracked };
        self.node(Kind::Elem { arr, index, name }, first, first)
    }

    /// An array passed whole: `x`, `a`, `s` or a declared array; `None` for another token.
    fn array_argument(&self) -> Res<Option<ArrRef>> {
        let arr = |arr, tracked| Ok(Some(ArrRef { arr, tracked }));
        match self.sc.tok {
            Tok::X => arr(self.body.x, false),
            Tok::A => arr(self.body.a, false),
            Tok::S => arr(self.body.s, false),
            Tok::Ident => match self.names.get(&self.sc.text) {
                Some(Name::Array(a)) => arr(*a, true),
                _ => Err(self.error(msg::ARRAY_NAME)),
            },
            _ => Ok(None),
        }
    }

    /// A built-in or library function's call, with its name current.
    fn function(&mut self) -> Res<u32> {
        let f = self.sc.func;
        let pos = self.sc.pos;
        if f.imp == Imp::Unsupported {
            return Err(self.not_evaluated(f));
        }
        self.next_is(Tok::LParen, msg::LEFT_PAREN)?;
        self.sc.next();
        // This call's arguments, apart from those of calls inside them.
        let mut args = Vec::with_capacity(f.params.len());
        let n = f.params.len();
        for i in 0..n {
            match f.param(i) {
                Param::R => {
                    let e = self.expr()?;
                    args.push(Arg::Real(e));
                }
                Param::A => match self.array_argument()? {
                    Some(a) => {
                        if a.arr.len == 0 {
                            return Err(self.ours(
                                HfErrorKind::Unsupported,
                                "an array of no items passed to a library function (HyperFun \
                                 reads it from nowhere)",
                            ));
                        }
                        args.push(Arg::Array(a, self.sc.pos));
                        self.sc.next();
                    }
                    None => return Err(self.error(msg::ARGUMENT)),
                },
            }
            if i + 1 < n {
                self.check(Tok::Comma, msg::COMMA)?;
                self.sc.next();
            }
        }
        self.check(Tok::RParen, msg::RIGHT_PAREN)?;
        self.sc.next();
        self.call_node(f, pos, args)
    }

    /// The node of a call of `f` at `pos` with its parsed `args`, its array sizes checked (off the
    /// recursion: its frame is not on the stack while arguments nest).
    #[inline(never)]
    fn call_node(&mut self, f: &'static Function, pos: Pos, args: Vec<Arg>) -> Res<u32> {
        let first = match args[0] {
            Arg::Real(e) => self.first(e),
            Arg::Array(_, at) => at,
        };
        let kind = match (f.imp, args.as_slice()) {
            (Imp::F1(g), &[Arg::Real(a)]) => Kind::F1(g, a),
            (Imp::F2(g), &[Arg::Real(a), Arg::Real(b)]) => Kind::F2(g, a, b),
            (Imp::Lib(lib), _) => {
                let arrays: Vec<(Arr, Pos)> = args
                    .iter()
                    .filter_map(|a| match *a {
                        Arg::Array(r, at) => Some((r.arr, at)),
                        Arg::Real(_) => None,
                    })
                    .collect();
                let sizes: Vec<u32> = arrays.iter().map(|a| a.0.len).collect();
                if let Some((i, need)) = too_short(lib, &sizes) {
                    let message = format!(
                        "{} reads {need} items of this array, which has {} (HyperFun reads past \
                         its end)",
                        f.name, sizes[i]
                    );
                    return Err(Box::new(HfError::at(
                        HfErrorKind::Unsupported,
                        arrays[i].1,
                        message,
                    )));
                }
                let site = self.body.libs.len() as u32;
                self.body.libs.push(LibSite {
                    lib,
                    arrays: arrays.iter().map(|a| a.0).collect(),
                    reals: args.len() - arrays.len(),
                });
                let from = self.args.len() as u32;
                self.args.extend_from_slice(&args);
                Kind::Lib {
                    site,
                    from,
                    to: self.args.len() as u32,
                }
            }
            // The table's built-ins take reals, and unsupported names were refused above.
            _ => {
                let message = format!("{} has a table entry this reader cannot call", f.name);
                return Err(Box::new(HfError::at(
                    HfErrorKind::Unsupported,
                    pos,
                    message,
                )));
            }
        };
        self.node(kind, pos, first)
    }

    #[cold]
    #[inline(never)]
    fn not_evaluated(&self, f: &Function) -> Box<HfError> {
        let message = format!(
            "{} is a HyperFun library function this reader does not evaluate",
            f.name
        );
        self.ours(HfErrorKind::Unsupported, message)
    }

    /// A call of the earlier body `callee`, with its name current.
    fn body_call(&mut self, callee: u32) -> Res<u32> {
        let pos = self.sc.pos;
        let dims = {
            let b = &self.bodies[callee as usize];
            [b.x.len, b.a.len, b.s.len]
        };
        self.next_is(Tok::LParen, msg::LEFT_PAREN)?;
        let mut args = [ArrRef {
            arr: self.body.s,
            tracked: false,
        }; 3];
        let mut at = [pos; 3];
        for k in 0..3 {
            self.sc.next();
            if k == 1 {
                self.check(Tok::Comma, msg::COMMA)?;
                self.sc.next();
            }
            if k == 2 {
                if self.sc.tok == Tok::RParen {
                    // `B(x, a)`: B must have one `s` item, the caller's first `s` item is passed.
                    if dims[2] != 1 {
                        return Err(self.error(msg::ITEMS));
                    }
                    if self.body.s.len == 0 {
                        return Err(self.ours(
                            HfErrorKind::Unsupported,
                            "a body call passes s[1] of a body that has no s items (s[0])",
                        ));
                    }
                    args[2].arr.len = 1;
                    at[2] = self.sc.pos;
                    break;
                }
                self.check(Tok::Comma, msg::COMMA)?;
                self.sc.next();
            }
            let Some(arg) = self.array_argument()? else {
                return Err(self.ours(
                    HfErrorKind::Unsupported,
                    "a body's argument must be x, a, s or an array (HyperFun takes this one \
                     unchecked and evaluates garbage)",
                ));
            };
            if arg.arr.len != dims[k] {
                return Err(self.error(msg::ITEMS));
            }
            args[k] = arg;
            at[k] = self.sc.pos;
            if k == 2 {
                self.next_is(Tok::RParen, msg::RIGHT_PAREN)?;
            }
        }
        self.sc.next();
        let site = self.body.calls.len() as u32;
        self.body.calls.push(CallSite {
            callee,
            args: args.map(|a| a.arr),
            tracked: args.map(|a| a.tracked),
            report: [at[1], at[2], at[2]],
        });
        self.node(Kind::Call(site), pos, at[2])
    }
}
