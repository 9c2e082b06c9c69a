//! The parser: HyperFun's grammar, its checks in its order and its messages at its places, into
//! [`Body`]s of operations.
//!
//! HyperFun's parser goes on after an error (its hosts report only the first); this one stops at
//! the first, which is the same error. Its grammar, from HyperFun's `int_parse_N.c`:
//!
//! ```text
//! body      := NAME '(' x '[' NUM ']' ',' a '[' NUM ']' [ ',' s '[' NUM ']' ] ')'
//!              '{' { array NAME '[' NUM ']' { ',' NAME '[' NUM ']' } ';' } { statement }
//!              NAME '=' expr ';' '}'
//! statement := NAME '=' expr ';' | ARRAY '[' expr ']' '=' expr ';' | ARRAY '=' '[' item {',' item} ']' ';'
//!            | 'if' cond 'then' {statement} ['else' {statement}] 'endif' ';'
//!            | 'while' cond 'loop' {statement} 'endloop' ';'
//! cond      := cmp { (and | or) cmp }          cmp := bool { (= | /= | < | <= | > | >=) bool }
//! bool      := not bool | '(' cond ')' | expr
//! expr      := term { (+ | - | & | '|' | \ | @) term }    term := factor { (* | /) factor }
//! factor    := unary { ^ unary }                          unary := (+ | - | ~) unary | primary
//! ```

use alloc::borrow::Cow;
use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use super::code::{Arg, ArrRef, Body, Kind, Node, Op, emit};
use super::library::Arr;
use super::run::hf_round;
use super::scan::{Pos, Scanner, Tok};
use super::{HfError, HfErrorKind, MAX_CELLS, MAX_CODE, MAX_DEPTH, MAX_NAMES, MAX_SOURCE_BYTES};

/// HyperFun's parse messages (its `Error_Strings`, verbatim).
pub(super) mod msg {
    pub(in super::super) const BODY_NAME: &str = "Body name expected";
    pub(in super::super) const NOT_UNIQUE: &str = "Body name is not unique";
    pub(in super::super) const LEFT_PAREN: &str = "Left parenthes expected";
    pub(in super::super) const X: &str = "\"X\" expected";
    pub(in super::super) const LEFT_BRACKET: &str = "Left bracket expected";
    pub(in super::super) const REAL: &str = "Real number expected";
    pub(in super::super) const SIZE: &str = "Array size must be greater zero";
    pub(in super::super) const RIGHT_BRACKET: &str = "Right bracket expected";
    pub(in super::super) const COMMA: &str = "Comma expected";
    pub(in super::super) const A: &str = "\"A\" expected";
    pub(in super::super) const S: &str = "\"S\" expected";
    pub(in super::super) const RIGHT_PAREN: &str = "Right parenthes expected";
    pub(in super::super) const LEFT_BRACE: &str = "Left brace expected";
    pub(in super::super) const ASSIGN: &str = "Assign mark expected";
    pub(in super::super) const SEMICOLON: &str = "Semicolon expected";
    pub(in super::super) const ARGUMENT: &str = "Error in argument in function call";
    pub(in super::super) const ITEMS: &str = "Wrong number of items in array";
    pub(in super::super) const ARRAY_NAME: &str = "Only array name expected";
    pub(in super::super) const THEN: &str = "Reserved word \"then\" expected";
    pub(in super::super) const ENDIF: &str = "Reserved word \"endif\" expected";
    pub(in super::super) const ELSE_ENDIF: &str = "Reserved words \"else\" or \"endif\" expected";
    pub(in super::super) const LOOP: &str = "Reserved word \"loop\" expected";
    pub(in super::super) const ENDLOOP: &str = "Reserved word \"endloop\" expected";
    pub(in super::super) const IDENTIFIER: &str = "Identifier expected";
    pub(in super::super) const RIGHT_BRACE: &str = "Right brace expected";
    pub(in super::super) const UNASSIGNED: &str = "Unassigned identificator used in expression";
    pub(in super::super) const EXPRESSION: &str = "Expression expected";
    pub(in super::super) const BRACKET_OR_ASSIGN: &str = "Left bracket or assign mark expected";
}

/// A name of a body: a scalar variable's cell or a declared array.
#[derive(Clone, Copy, Debug)]
pub(super) enum Name {
    Scalar(u32),
    Array(Arr),
}

/// The parser's results: its error boxed, so that the many `?` of a deep recursion stay small.
pub(super) type Res<T> = Result<T, Box<HfError>>;

/// A parsed text: its bodies in order, and the cells all their frames take together.
#[derive(Clone, Debug)]
pub(crate) struct Compiled {
    pub(crate) bodies: Vec<Body>,
    pub(crate) cells: usize,
}

/// Parses and compiles `text`.
pub(crate) fn parse(text: &str) -> Result<Compiled, HfError> {
    if text.len() > MAX_SOURCE_BYTES {
        let message = format!("the text is longer than {MAX_SOURCE_BYTES} bytes");
        return Err(HfError::at(
            HfErrorKind::Limit,
            Pos { line: 1, col: 1 },
            message,
        ));
    }
    let mut p = Parser {
        sc: Scanner::new(text.as_bytes()),
        bodies: Vec::new(),
        known: BTreeMap::new(),
        cells: 0,
        names_total: 0,
        code_total: 0,
        depth: 0,
        body: Body::new(String::new()),
        names: BTreeMap::new(),
        nodes: Vec::new(),
        args: Vec::new(),
    };
    while p.sc.tok != Tok::End {
        p.body().map_err(|e| *e)?;
    }
    if p.bodies.is_empty() {
        return Err(HfError::at(
            HfErrorKind::Unsupported,
            p.sc.pos,
            "the text defines no body",
        ));
    }
    Ok(Compiled {
        bodies: p.bodies,
        cells: p.cells as usize,
    })
}

pub(super) struct Parser<'a> {
    pub(super) sc: Scanner<'a>,
    pub(super) bodies: Vec<Body>,
    /// The completed bodies by name.
    pub(super) known: BTreeMap<String, u32>,
    /// Cells taken by all frames so far.
    pub(super) cells: u32,
    pub(super) names_total: usize,
    pub(super) code_total: usize,
    /// Nesting of expressions, conditions and statements.
    pub(super) depth: usize,
    /// The body being parsed, its names, and the current statement's expression nodes.
    pub(super) body: Body,
    pub(super) names: BTreeMap<String, Name>,
    pub(super) nodes: Vec<Node>,
    pub(super) args: Vec<Arg>,
}

impl Parser<'_> {
    pub(super) fn error(&self, message: &'static str) -> Box<HfError> {
        Box::new(HfError::at(HfErrorKind::Parse, self.sc.pos, message))
    }

    #[cold]
    pub(super) fn ours(
        &self,
        kind: HfErrorKind,
        message: impl Into<Cow<'static, str>>,
    ) -> Box<HfError> {
        Box::new(HfError::at(kind, self.sc.pos, message))
    }

    /// Errs with `message` unless the current token is `tok`.
    pub(super) fn check(&self, tok: Tok, message: &'static str) -> Res<()> {
        if self.sc.tok == tok {
            Ok(())
        } else {
            Err(self.error(message))
        }
    }

    /// Moves on, then checks the new token (HyperFun's usual step).
    pub(super) fn next_is(&mut self, tok: Tok, message: &'static str) -> Res<()> {
        self.sc.next();
        self.check(tok, message)
    }

    pub(super) fn enter(&mut self) -> Res<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let message =
                format!("the text nests expressions or statements deeper than {MAX_DEPTH}");
            return Err(self.ours(HfErrorKind::Limit, message));
        }
        Ok(())
    }

    pub(super) fn leave(&mut self) {
        self.depth -= 1;
    }

    fn count_name(&mut self) -> Res<()> {
        self.names_total += 1;
        if self.names_total > MAX_NAMES {
            let message = format!("the text names more than {MAX_NAMES} bodies and variables");
            return Err(self.ours(HfErrorKind::Limit, message));
        }
        Ok(())
    }

    /// Takes `n` cells for a frame.
    fn cells(&mut self, n: u32) -> Res<Arr> {
        let base = self.cells;
        match self.cells.checked_add(n) {
            Some(total) if total as usize <= MAX_CELLS => {
                self.cells = total;
                Ok(Arr { base, len: n })
            }
            _ => {
                let message = format!("the text's arrays and variables pass {MAX_CELLS} numbers");
                Err(self.ours(HfErrorKind::Limit, message))
            }
        }
    }

    /// A size in a header or an array declaration: `round(NUM)`.
    fn size(&self) -> Res<u32> {
        let n = hf_round(self.sc.num);
        if n < 0 || n as usize > MAX_CELLS {
            let message = format!(
                "an array of {:e} items is more than {MAX_CELLS}",
                self.sc.num
            );
            return Err(self.ours(HfErrorKind::Limit, message));
        }
        Ok(n as u32)
    }

    fn emit_op(&mut self, op: Op, pos: Pos) -> Res<u32> {
        let at = self.body.push(op, pos);
        self.count_code(1)?;
        Ok(at)
    }

    fn count_code(&mut self, n: usize) -> Res<()> {
        self.code_total += n;
        if self.code_total > MAX_CODE {
            let message =
                format!("the text compiles to more than {MAX_CODE} operations and constants");
            return Err(self.ours(HfErrorKind::Limit, message));
        }
        Ok(())
    }

    /// Writes the expression `root`'s operations and empties the node arena.
    fn emit_expr(&mut self, root: u32) -> Res<()> {
        let before = self.body.code.len();
        emit(&mut self.body, &self.nodes, &self.args, root);
        self.nodes.clear();
        self.args.clear();
        self.count_code(self.body.code.len() - before)
    }

    pub(super) fn node(&mut self, kind: Kind, pos: Pos, first: Pos) -> Res<u32> {
        if self.nodes.len() >= MAX_CODE {
            let message = format!("an expression of more than {MAX_CODE} operations");
            return Err(self.ours(HfErrorKind::Limit, message));
        }
        self.nodes.push(Node { kind, pos, first });
        Ok((self.nodes.len() - 1) as u32)
    }

    pub(super) fn first(&self, id: u32) -> Pos {
        self.nodes[id as usize].first
    }

    // ---- bodies --------------------------------------------------------------------------------

    fn body(&mut self) -> Res<()> {
        self.check(Tok::Ident, msg::BODY_NAME)?;
        if self.known.contains_key(&self.sc.text) {
            return Err(self.error(msg::NOT_UNIQUE));
        }
        self.count_name()?;
        self.body = Body::new(self.sc.text.clone());
        self.names.clear();
        self.header()?;
        self.sc.next();
        while self.sc.tok == Tok::Array {
            self.array_declaration()?;
        }
        self.statements()?;
        if self.sc.tok != Tok::Ident || self.sc.text != self.body.name {
            return Err(self.error(msg::BODY_NAME));
        }
        self.next_is(Tok::Assign, msg::ASSIGN)?;
        let pos = self.sc.pos;
        self.sc.next();
        let e = self.expr()?;
        self.emit_expr(e)?;
        self.emit_op(Op::Return, pos)?;
        self.check(Tok::Semicolon, msg::SEMICOLON)?;
        self.next_is(Tok::RBrace, msg::RIGHT_BRACE)?;
        self.sc.next();
        let body = core::mem::replace(&mut self.body, Body::new(String::new()));
        self.known
            .insert(body.name.clone(), self.bodies.len() as u32);
        self.bodies.push(body);
        Ok(())
    }

    /// `(x[n], a[n] [, s[n]]) {`, leaving the `{` current.
    fn header(&mut self) -> Res<()> {
        let dim = |p: &mut Self, name: Tok, message: &'static str| -> Res<u32> {
            p.next_is(name, message)?;
            p.next_is(Tok::LBracket, msg::LEFT_BRACKET)?;
            p.next_is(Tok::Num, msg::REAL)?;
            let n = p.size()?;
            p.next_is(Tok::RBracket, msg::RIGHT_BRACKET)?;
            Ok(n)
        };
        self.next_is(Tok::LParen, msg::LEFT_PAREN)?;
        let x = dim(self, Tok::X, msg::X)?;
        self.next_is(Tok::Comma, msg::COMMA)?;
        let a = dim(self, Tok::A, msg::A)?;
        self.sc.next();
        let s = if self.sc.tok == Tok::RParen {
            1
        } else {
            self.check(Tok::Comma, msg::COMMA)?;
            let s = dim(self, Tok::S, msg::S)?;
            self.next_is(Tok::RParen, msg::RIGHT_PAREN)?;
            s
        };
        self.body.x = self.cells(x)?;
        self.body.a = self.cells(a)?;
        self.body.s = self.cells(s)?;
        self.next_is(Tok::LBrace, msg::LEFT_BRACE)
    }

    /// `array p[n], q[m];` with `array` current.
    fn array_declaration(&mut self) -> Res<()> {
        loop {
            self.next_is(Tok::Ident, msg::IDENTIFIER)?;
            let name = self.sc.text.clone();
            self.next_is(Tok::LBracket, msg::LEFT_BRACKET)?;
            self.next_is(Tok::Num, msg::REAL)?;
            if hf_round(self.sc.num) < 1 {
                return Err(self.error(msg::SIZE));
            }
            let n = self.size()?;
            self.next_is(Tok::RBracket, msg::RIGHT_BRACKET)?;
            // A second declaration of a name is taken and ignored: the first one holds.
            if !self.names.contains_key(&name) {
                self.count_name()?;
                let arr = self.cells(n)?;
                self.names.insert(name, Name::Array(arr));
            }
            self.sc.next();
            if self.sc.tok != Tok::Comma {
                break;
            }
        }
        self.check(Tok::Semicolon, msg::SEMICOLON)?;
        self.sc.next();
        Ok(())
    }

    // ---- statements ----------------------------------------------------------------------------

    /// Statements up to the first token that cannot start one.
    fn statements(&mut self) -> Res<()> {
        loop {
            match self.sc.tok {
                Tok::If => self.if_statement()?,
                Tok::While => self.while_statement()?,
                Tok::S => {
                    let s = ArrRef {
                        arr: self.body.s,
                        tracked: false,
                    };
                    self.array_statement(s)?;
                }
                Tok::Ident if self.sc.text != self.body.name => {
                    match self.names.get(&self.sc.text).copied() {
                        Some(Name::Array(arr)) => {
                            self.array_statement(ArrRef { arr, tracked: true })?;
                        }
                        Some(Name::Scalar(cell)) => self.assignment(cell)?,
                        None => {
                            // The first assignment declares the variable, before its value is read.
                            self.count_name()?;
                            let cell = self.cells(1)?.base;
                            self.names.insert(self.sc.text.clone(), Name::Scalar(cell));
                            self.assignment(cell)?;
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    /// `v = expr;` with `v` current.
    fn assignment(&mut self, cell: u32) -> Res<()> {
        self.next_is(Tok::Assign, msg::ASSIGN)?;
        let pos = self.sc.pos;
        self.sc.next();
        let e = self.expr()?;
        self.emit_expr(e)?;
        self.emit_op(Op::Store(cell), pos)?;
        self.check(Tok::Semicolon, msg::SEMICOLON)?;
        self.sc.next();
        Ok(())
    }

    /// `p[i] = expr;` or `p = [c, …];` with the array's name (or `s`) current.
    fn array_statement(&mut self, arr: ArrRef) -> Res<()> {
        self.sc.next();
        match self.sc.tok {
            Tok::LBracket => {
                self.sc.next();
                let at = self.sc.pos;
                let i = self.expr()?;
                self.emit_expr(i)?;
                self.emit_op(Op::Slot { len: arr.arr.len }, at)?;
                self.check(Tok::RBracket, msg::RIGHT_BRACKET)?;
                self.next_is(Tok::Assign, msg::ASSIGN)?;
                self.sc.next();
                let e = self.expr()?;
                self.emit_expr(e)?;
                let op = Op::StoreElem {
                    base: arr.arr.base,
                    tracked: arr.tracked,
                };
                self.emit_op(op, at)?;
                self.check(Tok::Semicolon, msg::SEMICOLON)?;
            }
            Tok::Assign => {
                let at = self.sc.pos;
                self.next_is(Tok::LBracket, msg::LEFT_BRACKET)?;
                if arr.arr.len == 0 {
                    return Err(self.ours(
                        HfErrorKind::Unsupported,
                        "s has no items here (s[0]): HyperFun writes this constant past its end",
                    ));
                }
                let from = self.body.consts.len() as u32;
                self.sc.next();
                self.constant()?;
                for _ in 1..arr.arr.len {
                    self.check(Tok::Comma, msg::COMMA)?;
                    self.sc.next();
                    self.constant()?;
                }
                self.check(Tok::RBracket, msg::RIGHT_BRACKET)?;
                self.next_is(Tok::Semicolon, msg::SEMICOLON)?;
                let op = Op::Fill {
                    base: arr.arr.base,
                    len: arr.arr.len,
                    from,
                    tracked: arr.tracked,
                };
                self.emit_op(op, at)?;
            }
            _ => return Err(self.error(msg::BRACKET_OR_ASSIGN)),
        }
        self.sc.next();
        Ok(())
    }

    /// An item of a whole-array assignment: a number with at most one sign.
    fn constant(&mut self) -> Res<()> {
        let mut sign = 1.0;
        if self.sc.tok == Tok::Minus {
            sign = -1.0;
            self.sc.next();
        } else if self.sc.tok == Tok::Plus {
            self.sc.next();
        }
        self.check(Tok::Num, msg::REAL)?;
        self.count_code(1)?;
        self.body.consts.push(self.sc.num * sign);
        self.sc.next();
        Ok(())
    }

    fn if_statement(&mut self) -> Res<()> {
        self.enter()?;
        let pos = self.sc.pos;
        self.sc.next();
        let c = self.condition()?;
        self.emit_expr(c)?;
        let skip = self.emit_op(Op::JumpUnless(0), pos)?;
        self.check(Tok::Then, msg::THEN)?;
        self.sc.next();
        self.statements()?;
        if self.sc.tok == Tok::Else {
            let over = self.emit_op(Op::Jump(0), self.sc.pos)?;
            self.body.patch(skip, self.body.here());
            self.sc.next();
            self.statements()?;
            self.check(Tok::EndIf, msg::ENDIF)?;
            self.body.patch(over, self.body.here());
        } else {
            self.check(Tok::EndIf, msg::ELSE_ENDIF)?;
            self.body.patch(skip, self.body.here());
        }
        self.next_is(Tok::Semicolon, msg::SEMICOLON)?;
        self.sc.next();
        self.leave();
        Ok(())
    }

    fn while_statement(&mut self) -> Res<()> {
        self.enter()?;
        let pos = self.sc.pos;
        let top = self.body.here();
        self.sc.next();
        let c = self.condition()?;
        self.emit_expr(c)?;
        let exit = self.emit_op(Op::JumpUnless(0), pos)?;
        self.check(Tok::Loop, msg::LOOP)?;
        self.sc.next();
        self.statements()?;
        self.emit_op(Op::Jump(top), pos)?;
        self.body.patch(exit, self.body.here());
        self.check(Tok::EndLoop, msg::ENDLOOP)?;
        self.next_is(Tok::Semicolon, msg::SEMICOLON)?;
        self.sc.next();
        self.leave();
        Ok(())
    }
}
