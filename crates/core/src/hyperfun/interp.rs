//! A HyperFun interpreter for the tests: the subset the export writes, from the language's
//! definitions. A program is parsed once into statements and run at many points.
//!
//! - Statements: `array a[n];`, assignments to a variable, an array element or a whole array
//!   (`a = [1, -2];`), `if (c) then … [else …] endif;`, `while (c) loop … endloop;`.
//! - Expressions: numbers, variables, `x[k]` and array elements, `+ - * / ^`, unary minus, calls,
//!   and the set operations `|`, `&`, `\` (lowest precedence), which HyperFun defines as the
//!   R-functions `f1 + f2 ± sqrt(f1² + f2²)`.
//! - Logical expressions: `< > <= >= = /=`, `and`, `or`, `not`, parentheses.
//! - Functions: `sqrt`, `abs`, and the library's `hfSphere`, `hfCylinderX/Y/Z`, `hfBlendUni` and
//!   `hfBlendInt` as the HyperFun library defines them.

use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Id(String),
    Sym(char),
}

fn lex(text: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    let c: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < c.len() {
        match c[i] {
            ' ' | '\n' | '\t' | '\r' => i += 1,
            '-' if c.get(i + 1) == Some(&'-') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
            }
            d if d.is_ascii_digit() || d == '.' => {
                let start = i;
                while i < c.len()
                    && (c[i].is_ascii_digit()
                        || c[i] == '.'
                        || c[i] == 'e'
                        || ((c[i] == '-' || c[i] == '+') && c[i - 1] == 'e'))
                {
                    i += 1;
                }
                let s: String = c[start..i].iter().collect();
                out.push(Tok::Num(s.parse().unwrap()));
            }
            a if a.is_ascii_alphabetic() || a == '_' => {
                let start = i;
                while i < c.len() && (c[i].is_ascii_alphanumeric() || c[i] == '_') {
                    i += 1;
                }
                // HyperFun is case-insensitive.
                out.push(Tok::Id(
                    c[start..i].iter().collect::<String>().to_lowercase(),
                ));
            }
            s => {
                out.push(Tok::Sym(s));
                i += 1;
            }
        }
    }
    out
}

#[derive(Clone, Copy, Debug)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Or,
    And,
    Minus,
}

#[derive(Clone, Copy, Debug)]
enum Rel {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

#[derive(Debug)]
enum Expr {
    Num(f64),
    Var(usize),
    Elem(usize, Box<Expr>),
    Neg(Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
    Call(String, Vec<Expr>),
}

#[derive(Debug)]
enum Cond {
    Rel(Rel, Expr, Expr),
    And(Box<Cond>, Box<Cond>),
    Or(Box<Cond>, Box<Cond>),
    Not(Box<Cond>),
}

#[derive(Debug)]
enum Stmt {
    Array(usize, usize),
    Set(usize, Expr),
    SetElem(usize, Expr, Expr),
    SetArray(usize, Vec<Expr>),
    If(Cond, Vec<Stmt>, Vec<Stmt>),
    While(Cond, Vec<Stmt>),
}

#[derive(Clone, Debug)]
enum Val {
    Num(f64),
    Arr(Vec<f64>),
}

impl Val {
    fn num(&self) -> f64 {
        match self {
            Val::Num(v) => *v,
            Val::Arr(_) => panic!("an array where a number is wanted"),
        }
    }
    fn arr(&self) -> &[f64] {
        match self {
            Val::Arr(a) => a,
            Val::Num(_) => panic!("a number where an array is wanted"),
        }
    }
}

struct Parser<'a> {
    t: &'a [Tok],
    i: usize,
    names: BTreeMap<String, usize>,
}

impl Parser<'_> {
    fn slot(&mut self, name: &str) -> usize {
        let next = self.names.len();
        *self.names.entry(String::from(name)).or_insert(next)
    }
    fn peek(&self) -> Option<&Tok> {
        self.t.get(self.i)
    }
    fn eat(&mut self, s: char) -> bool {
        if self.peek() == Some(&Tok::Sym(s)) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn expect(&mut self, s: char) {
        assert!(self.eat(s), "expected {s:?} at token {:?}", self.peek());
    }
    fn word(&mut self, w: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Id(s)) if s == w) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn at_word(&self, words: &[&str]) -> bool {
        matches!(self.peek(), Some(Tok::Id(s)) if words.contains(&s.as_str()))
    }
    fn id(&mut self) -> String {
        match self.t[self.i].clone() {
            Tok::Id(s) => {
                self.i += 1;
                s
            }
            t => panic!("expected a name, found {t:?}"),
        }
    }

    /// Statements up to one of `ends` (not taken) or the body's closing brace.
    fn block(&mut self, ends: &[&str]) -> Vec<Stmt> {
        let mut out = Vec::new();
        while !self.at_word(ends) && self.peek() != Some(&Tok::Sym('}')) {
            out.push(self.statement());
        }
        out
    }

    fn statement(&mut self) -> Stmt {
        let name = self.id();
        match name.as_str() {
            "if" => {
                self.expect('(');
                let c = self.condition();
                self.expect(')');
                assert!(self.word("then"), "expected then at {:?}", self.peek());
                let yes = self.block(&["else", "endif"]);
                let no = if self.word("else") {
                    self.block(&["endif"])
                } else {
                    Vec::new()
                };
                assert!(self.word("endif"), "expected endif at {:?}", self.peek());
                self.expect(';');
                Stmt::If(c, yes, no)
            }
            "while" => {
                self.expect('(');
                let c = self.condition();
                self.expect(')');
                assert!(self.word("loop"), "expected loop at {:?}", self.peek());
                let body = self.block(&["endloop"]);
                assert!(
                    self.word("endloop"),
                    "expected endloop at {:?}",
                    self.peek()
                );
                self.expect(';');
                Stmt::While(c, body)
            }
            "array" => {
                let array = self.id();
                self.expect('[');
                let Some(&Tok::Num(n)) = self.peek() else {
                    panic!("an array's length is a number")
                };
                self.i += 1;
                self.expect(']');
                self.expect(';');
                Stmt::Array(self.slot(&array), n as usize)
            }
            _ => {
                let slot = self.slot(&name);
                if self.eat('[') {
                    let k = self.set_ops();
                    self.expect(']');
                    self.expect('=');
                    let v = self.set_ops();
                    self.expect(';');
                    return Stmt::SetElem(slot, k, v);
                }
                self.expect('=');
                if self.eat('[') {
                    let mut items = Vec::new();
                    loop {
                        items.push(self.set_ops());
                        if self.eat(']') {
                            break;
                        }
                        self.expect(',');
                    }
                    self.expect(';');
                    return Stmt::SetArray(slot, items);
                }
                let v = self.set_ops();
                self.expect(';');
                Stmt::Set(slot, v)
            }
        }
    }

    fn condition(&mut self) -> Cond {
        let mut c = self.conjunction();
        while self.word("or") {
            c = Cond::Or(Box::new(c), Box::new(self.conjunction()));
        }
        c
    }
    fn conjunction(&mut self) -> Cond {
        let mut c = self.relation();
        while self.word("and") {
            c = Cond::And(Box::new(c), Box::new(self.relation()));
        }
        c
    }
    fn relation(&mut self) -> Cond {
        if self.word("not") {
            return Cond::Not(Box::new(self.relation()));
        }
        if self.peek() == Some(&Tok::Sym('(')) && self.logical_group() {
            self.i += 1;
            let c = self.condition();
            self.expect(')');
            return c;
        }
        let a = self.set_ops();
        let rel = match self.t[self.i] {
            Tok::Sym('<') => {
                self.i += 1;
                if self.eat('=') { Rel::Le } else { Rel::Lt }
            }
            Tok::Sym('>') => {
                self.i += 1;
                if self.eat('=') { Rel::Ge } else { Rel::Gt }
            }
            Tok::Sym('=') => {
                self.i += 1;
                Rel::Eq
            }
            Tok::Sym('/') => {
                self.i += 1;
                self.expect('=');
                Rel::Ne
            }
            ref t => panic!("expected a relation, found {t:?}"),
        };
        Cond::Rel(rel, a, self.set_ops())
    }
    /// Whether the parenthesis at the cursor holds a logical expression (a relation or `and`,
    /// `or` at its own depth) rather than a number.
    fn logical_group(&self) -> bool {
        let mut depth = 0;
        for t in &self.t[self.i..] {
            match t {
                Tok::Sym('(') => depth += 1,
                Tok::Sym(')') => {
                    depth -= 1;
                    if depth == 0 {
                        return false;
                    }
                }
                Tok::Sym('<' | '>' | '=') if depth == 1 => return true,
                Tok::Id(w) if depth == 1 && (w == "and" || w == "or") => return true,
                _ => {}
            }
        }
        false
    }

    fn set_ops(&mut self) -> Expr {
        let mut a = self.sum();
        loop {
            let op = match self.peek() {
                Some(Tok::Sym('|')) => Op::Or,
                Some(Tok::Sym('&')) => Op::And,
                Some(Tok::Sym('\\')) => Op::Minus,
                _ => return a,
            };
            self.i += 1;
            a = Expr::Bin(op, Box::new(a), Box::new(self.sum()));
        }
    }
    fn sum(&mut self) -> Expr {
        let mut a = self.product();
        loop {
            let op = if self.eat('+') {
                Op::Add
            } else if self.eat('-') {
                Op::Sub
            } else {
                return a;
            };
            a = Expr::Bin(op, Box::new(a), Box::new(self.product()));
        }
    }
    fn product(&mut self) -> Expr {
        let mut a = self.unary();
        loop {
            let op = if self.eat('*') {
                Op::Mul
            } else if self.peek() == Some(&Tok::Sym('/'))
                && self.t.get(self.i + 1) != Some(&Tok::Sym('='))
            {
                self.i += 1;
                Op::Div
            } else {
                return a;
            };
            a = Expr::Bin(op, Box::new(a), Box::new(self.unary()));
        }
    }
    fn unary(&mut self) -> Expr {
        if self.eat('-') {
            return Expr::Neg(Box::new(self.unary()));
        }
        let base = self.primary();
        if self.eat('^') {
            return Expr::Bin(Op::Pow, Box::new(base), Box::new(self.unary()));
        }
        base
    }
    fn primary(&mut self) -> Expr {
        match self.t[self.i].clone() {
            Tok::Num(v) => {
                self.i += 1;
                Expr::Num(v)
            }
            Tok::Sym('(') => {
                self.i += 1;
                let v = self.set_ops();
                self.expect(')');
                v
            }
            Tok::Id(name) => {
                self.i += 1;
                if self.eat('(') {
                    let mut args = Vec::new();
                    if !self.eat(')') {
                        loop {
                            args.push(self.set_ops());
                            if self.eat(')') {
                                break;
                            }
                            self.expect(',');
                        }
                    }
                    return Expr::Call(name, args);
                }
                let slot = self.slot(&name);
                if self.eat('[') {
                    let k = self.set_ops();
                    self.expect(']');
                    return Expr::Elem(slot, Box::new(k));
                }
                Expr::Var(slot)
            }
            t => panic!("unexpected {t:?}"),
        }
    }
}

fn or(a: f64, b: f64) -> f64 {
    a + b + (a * a + b * b).sqrt()
}

fn and(a: f64, b: f64) -> f64 {
    a + b - (a * a + b * b).sqrt()
}

/// A parsed `my_model(x[3], a[1]) { … }`.
pub(crate) struct Program {
    body: Vec<Stmt>,
    slots: usize,
    x: usize,
    result: usize,
}

struct Run {
    vars: Vec<Option<Val>>,
    /// Loop iterations left: a program that loops for ever fails the test.
    budget: u64,
}

impl Program {
    pub(crate) fn new(text: &str) -> Self {
        let t = lex(text);
        let open = t.iter().position(|k| *k == Tok::Sym('{')).expect("a body");
        let head: Vec<&Tok> = t[..open].iter().collect();
        assert!(
            matches!(head.first(), Some(Tok::Id(n)) if n == "my_model"),
            "a my_model head: {head:?}"
        );
        let mut p = Parser {
            t: &t,
            i: open + 1,
            names: BTreeMap::new(),
        };
        let x = p.slot("x");
        let result = p.slot("my_model");
        let body = p.block(&[]);
        p.expect('}');
        Self {
            body,
            slots: p.names.len(),
            x,
            result,
        }
    }

    /// `my_model` at the point `x`.
    pub(crate) fn run(&self, x: [f64; 3]) -> f64 {
        let mut run = Run {
            vars: alloc::vec![None; self.slots],
            budget: 50_000_000,
        };
        run.vars[self.x] = Some(Val::Arr(x.to_vec()));
        run.block(&self.body);
        run.vars[self.result]
            .as_ref()
            .expect("my_model is set")
            .num()
    }
}

impl Run {
    fn block(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            self.statement(s);
        }
    }
    fn statement(&mut self, s: &Stmt) {
        match s {
            Stmt::Array(slot, n) => self.vars[*slot] = Some(Val::Arr(alloc::vec![0.0; *n])),
            Stmt::Set(slot, e) => {
                let v = self.val(e);
                self.vars[*slot] = Some(v);
            }
            Stmt::SetElem(slot, k, e) => {
                let k = self.num(k) as usize;
                let v = self.num(e);
                match &mut self.vars[*slot] {
                    Some(Val::Arr(a)) => a[k - 1] = v,
                    _ => panic!("an element of what is not an array"),
                }
            }
            Stmt::SetArray(slot, items) => {
                let v: Vec<f64> = items.iter().map(|e| self.num(e)).collect();
                if let Some(Val::Arr(a)) = &self.vars[*slot] {
                    assert_eq!(a.len(), v.len(), "an array's constants fill it");
                }
                self.vars[*slot] = Some(Val::Arr(v));
            }
            Stmt::If(c, yes, no) => {
                if self.holds(c) {
                    self.block(yes);
                } else {
                    self.block(no);
                }
            }
            Stmt::While(c, body) => {
                while self.holds(c) {
                    self.budget = self
                        .budget
                        .checked_sub(1)
                        .expect("a loop that does not end");
                    self.block(body);
                }
            }
        }
    }
    fn holds(&self, c: &Cond) -> bool {
        match c {
            Cond::Rel(r, a, b) => {
                let (a, b) = (self.num(a), self.num(b));
                match r {
                    Rel::Lt => a < b,
                    Rel::Le => a <= b,
                    Rel::Gt => a > b,
                    Rel::Ge => a >= b,
                    Rel::Eq => a == b,
                    Rel::Ne => a != b,
                }
            }
            Cond::And(a, b) => self.holds(a) && self.holds(b),
            Cond::Or(a, b) => self.holds(a) || self.holds(b),
            Cond::Not(a) => !self.holds(a),
        }
    }
    fn val(&self, e: &Expr) -> Val {
        match e {
            Expr::Var(slot) => self.vars[*slot]
                .clone()
                .expect("a variable used before it is set"),
            _ => Val::Num(self.num(e)),
        }
    }
    fn num(&self, e: &Expr) -> f64 {
        match e {
            Expr::Num(v) => *v,
            Expr::Var(slot) => self.vars[*slot]
                .as_ref()
                .expect("a variable used before it is set")
                .num(),
            Expr::Elem(slot, k) => {
                let k = self.num(k) as usize;
                self.vars[*slot]
                    .as_ref()
                    .expect("an array used before it is set")
                    .arr()[k - 1]
            }
            Expr::Neg(a) => -self.num(a),
            Expr::Bin(op, a, b) => {
                let (a, b) = (self.num(a), self.num(b));
                match op {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Pow => a.powf(b),
                    Op::Or => or(a, b),
                    Op::And => and(a, b),
                    Op::Minus => and(a, -b),
                }
            }
            Expr::Call(name, args) => {
                let a: Vec<Val> = args.iter().map(|e| self.val(e)).collect();
                call(name, &a)
            }
        }
    }
}

fn call(name: &str, a: &[Val]) -> f64 {
    let sq = |v: f64| v * v;
    match name {
        "sqrt" => a[0].num().sqrt(),
        "abs" => a[0].num().abs(),
        "hfsphere" => {
            let (x, c, r) = (a[0].arr(), a[1].arr(), a[2].num());
            r * r - (0..3).map(|i| sq(x[i] - c[i])).sum::<f64>()
        }
        "hfcylinderx" | "hfcylindery" | "hfcylinderz" => {
            let skip = match name {
                "hfcylinderx" => 0,
                "hfcylindery" => 1,
                _ => 2,
            };
            let (x, c, r) = (a[0].arr(), a[1].arr(), a[2].num());
            r * r
                - (0..3)
                    .filter(|&i| i != skip)
                    .map(|i| sq(x[i] - c[i]))
                    .sum::<f64>()
        }
        "hfblenduni" | "hfblendint" => {
            let [f1, f2, a0, a1, a2] = [0, 1, 2, 3, 4].map(|k| a[k].num());
            let base = if name == "hfblenduni" {
                or(f1, f2)
            } else {
                and(f1, f2)
            };
            base + a0 / (1.0 + sq(f1 / a1) + sq(f2 / a2))
        }
        _ => panic!("no function {name}"),
    }
}

/// `my_model` of the file `text` at the point `x` (parsed anew: use [`Program`] for many points).
pub(crate) fn eval(text: &str, x: [f64; 3]) -> f64 {
    Program::new(text).run(x)
}
