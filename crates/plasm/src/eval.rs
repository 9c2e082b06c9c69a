//! The evaluator.

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use crate::complex::Complex;
use crate::kernel::{Kernel, LANES};
use crate::meter::{self, Charge, buffer_bytes};
use crate::parse::{Arith, Def, Expr, Local, Stmt, parse};
use crate::prelude::{self, in_prelude};
use crate::value::{Fun, Items, NAMES, Prim, Value};
use crate::{Error, ErrorKind, Limits, Span, Warning};

/// The value of one top-level expression.
#[derive(Clone, Debug)]
pub struct Shown {
    /// The expression's place.
    pub span: Span,
    /// Its value.
    pub value: Value,
    /// For a complex made by `MAP` (the expression's value itself), the map and its domain, so
    /// that the map can be sampled again (to fit a Bézier net, for instance).
    pub map: Option<MapOf>,
}

/// A map and the complex `MAP` applied it to.
#[derive(Clone, Debug)]
pub struct MapOf {
    /// The map (a function; a sequence of coordinate functions is made one with `CONS`).
    pub f: Value,
    /// Its domain.
    pub domain: Rc<Complex>,
}

/// What a run gives: the values of the top-level expressions before the first error, the
/// warnings, and the error if any.
#[derive(Clone, Debug)]
pub struct Run {
    /// Values of the top-level expressions, in order.
    pub shown: Vec<Shown>,
    /// Readings worth saying.
    pub warnings: Vec<Warning>,
    /// The error that stopped the run.
    pub error: Option<Error>,
    /// Steps taken.
    pub steps: u64,
    /// The most bytes of values that the run held at once, as its memory budget counts them
    /// ([`Limits::memory`]; measured at each step).
    pub memory: u64,
}

impl Run {
    /// The values, or the error.
    ///
    /// # Errors
    ///
    /// The run's error.
    pub fn into_result(self) -> Result<Vec<Shown>, Error> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.shown),
        }
    }
}

/// An interpreter: the global definitions persist from one [`Interp::run`] to the next.
pub struct Interp {
    globals: HashMap<Rc<str>, (Rc<str>, Value)>,
    /// The prelude's definitions (see [`crate::prelude`]), under the globals.
    prelude: HashMap<Rc<str>, (Rc<str>, Value)>,
    /// The last `MAP`: its result, its map and its domain.
    last_map: Option<(Rc<Complex>, MapOf)>,
    limits: Limits,
    steps: u64,
    /// What the thread's values held when the run began ([`meter::live`]), and the most the
    /// run has held beyond that.
    base: i64,
    peak: i64,
    depth: u32,
    /// Expressions under evaluation, nested (over all calls under way).
    nesting: u32,
}

/// The most expressions nested in evaluation at once, over all calls under way.
const MAX_EVAL_NESTING: u32 = 600;

impl Default for Interp {
    fn default() -> Self {
        Self::new()
    }
}

#[derive(Clone)]
enum Slot {
    Todo,
    Busy,
    Done(Value),
}

/// A bound parameter: its key (upper case), its spelling, its value.
type Param = (Rc<str>, Rc<str>, Value);

/// The names a body sees besides the globals: its parameters and its `WHERE` locals, evaluated
/// once, on first use, so that they may refer to one another in any order.
struct Env<'a> {
    params: Vec<Param>,
    locals: &'a [Local],
    slots: RefCell<Vec<Slot>>,
    /// Whether the body is the prelude's: it sees the prelude's definitions, not the script's.
    prelude: bool,
    /// The bytes of the parameters and the slots, held while the call is under way.
    _held: Charge,
}

impl<'a> Env<'a> {
    fn new(params: Vec<Param>, locals: &'a [Local]) -> Self {
        let held = Charge::new(
            buffer_bytes::<Param>(params.capacity()) + buffer_bytes::<Slot>(locals.len()),
        );
        Env {
            params,
            locals,
            slots: RefCell::new(vec![Slot::Todo; locals.len()]),
            prelude: false,
            _held: held,
        }
    }
}

type R<T> = Result<T, Error>;

fn type_error<T>(at: Span, message: String) -> R<T> {
    Err(Error::new(ErrorKind::Type, at, message))
}

fn whole(x: f64) -> Option<i64> {
    (x.fract() == 0.0 && x.abs() < 9e15).then_some(x as i64)
}

impl Interp {
    /// An interpreter with the default [`Limits`].
    pub fn new() -> Self {
        Self::with_limits(Limits::default())
    }

    /// An interpreter with the given limits, and the prelude defined.
    pub fn with_limits(limits: Limits) -> Self {
        let mut interp = Self::without_prelude(Limits::default());
        interp.load_prelude();
        interp.limits = limits;
        interp
    }

    /// An interpreter with the given limits and without the prelude: only the built-ins.
    pub fn without_prelude(limits: Limits) -> Self {
        Interp {
            globals: HashMap::new(),
            prelude: HashMap::new(),
            last_map: None,
            limits,
            steps: 0,
            base: meter::live(),
            peak: 0,
            depth: 0,
            nesting: 0,
        }
    }

    /// Defines the prelude, under the default limits; its steps are not a script's.
    fn load_prelude(&mut self) {
        let stmts = prelude::statements();
        for stmt in stmts.iter() {
            let Stmt::Def(def) = stmt else { continue };
            let value = if def.groups.is_empty() {
                let mut env = Env::new(Vec::new(), &def.locals);
                env.prelude = true;
                self.eval(&def.body, &env)
                    .expect("the prelude's definitions evaluate")
            } else {
                Value::fun(Fun::User(def.clone(), Vec::new()))
            };
            self.prelude
                .insert(def.key.clone(), (def.name.clone(), value));
        }
        self.steps = 0;
        self.peak = 0;
        self.base = meter::live();
    }

    /// Runs a script: its `DEF`s join the globals, and the values of its other statements are
    /// returned. A run stops at its first error, keeping what came before.
    pub fn run(&mut self, src: &str) -> Run {
        self.steps = 0;
        self.depth = 0;
        self.base = meter::live();
        self.peak = 0;
        let mut run = Run {
            shown: Vec::new(),
            warnings: Vec::new(),
            error: None,
            steps: 0,
            memory: 0,
        };
        if src.len() > self.limits.source {
            run.error = Some(Error::new(
                ErrorKind::Limit,
                Span {
                    line: 1,
                    col: 1,
                    ..Span::default()
                },
                format!(
                    "the script is {} bytes, past the limit of {}",
                    src.len(),
                    self.limits.source
                ),
            ));
            return run;
        }
        let stmts = match parse(src, &mut run.warnings) {
            Ok(s) => s,
            Err(e) => {
                run.error = Some(e);
                return run;
            }
        };
        // Numbers of points and cells in the results so far: what is drawn and exported is
        // bounded, however often a result repeats.
        let mut held = 0usize;
        let most = self.limits.cells.saturating_mul(8);
        for stmt in stmts {
            self.depth = 0;
            self.nesting = 0;
            let place = match &stmt {
                Stmt::Def(def) => def.body.span(),
                Stmt::Expr(e) => e.span(),
            };
            let r = match stmt {
                Stmt::Def(def) => self.define(def),
                Stmt::Expr(e) => {
                    let empty = Env::new(Vec::new(), &[]);
                    self.last_map = None;
                    self.eval(&e, &empty).and_then(|value| {
                        let map = match (&value, self.last_map.take()) {
                            (Value::Pol(p), Some((made, map))) if Rc::ptr_eq(p, &made) => Some(map),
                            _ => None,
                        };
                        if let Value::Pol(c) = &value {
                            held = held.saturating_add(c.points.len() + c.cells.len());
                        }
                        run.shown.push(Shown {
                            span: e.span(),
                            value,
                            map,
                        });
                        if held > most {
                            return Err(Error::new(
                                ErrorKind::Limit,
                                e.span(),
                                format!(
                                    "the results so far hold {held} numbers of points and cells, \
                                     past the limit of {most} for all results"
                                ),
                            ));
                        }
                        Ok(())
                    })
                }
            };
            if let Err(mut e) = r {
                // Errors inside the prelude are placed at their call (`call_def`); should one
                // escape, it is placed at the statement, never at a line of the prelude.
                if in_prelude(e.span) {
                    e.span = place;
                }
                run.error = Some(e);
                break;
            }
        }
        run.steps = self.steps;
        run.memory = self.peak.max(0) as u64;
        run
    }

    /// A global definition (by any case): the script's, or else the prelude's.
    pub fn global(&self, name: &str) -> Option<&Value> {
        let key = name.to_ascii_uppercase();
        self.globals
            .get(key.as_str())
            .or_else(|| self.prelude.get(key.as_str()))
            .map(|g| &g.1)
    }

    /// Applies a function value to a point, as `MAP` does: for tests and callers that sample a
    /// script's maps. The steps count against the budget of the last run, which goes on.
    ///
    /// # Errors
    ///
    /// As a run.
    pub fn call(&mut self, f: &Value, point: &[f64]) -> Result<Value, Error> {
        self.depth = 0;
        self.nesting = 0;
        let f = match f {
            Value::Seq(fs) => Value::fun(Fun::Cons(fs.to_vec())),
            other => other.clone(),
        };
        let x = Value::seq(point.iter().map(|&c| Value::Num(c)).collect());
        self.apply(&f, x, Span::default())
    }

    fn define(&mut self, def: Rc<Def>) -> R<()> {
        let value = if def.groups.is_empty() {
            let env = Env::new(Vec::new(), &def.locals);
            self.eval(&def.body, &env)?
        } else {
            Value::fun(Fun::User(def.clone(), Vec::new()))
        };
        self.globals
            .insert(def.key.clone(), (def.name.clone(), value));
        Ok(())
    }

    fn tick(&mut self, n: u64, at: Span) -> R<()> {
        self.steps += n;
        if self.steps > self.limits.steps {
            return Err(Error::new(
                ErrorKind::Limit,
                at,
                format!(
                    "stopped after {} steps: an endless loop, or more work than a script may do \
                     at once",
                    self.limits.steps
                ),
            ));
        }
        // What the run holds, at every step: whatever built it was counted as it was built.
        let held = meter::live() - self.base;
        self.peak = self.peak.max(held);
        if held > self.limits.memory as i64 {
            return Err(self.too_much_memory(at));
        }
        Ok(())
    }

    /// Whether the run may build `bytes` more than it holds: checked before anything large is
    /// built, so that the budget is not passed by one large value before the next step sees it.
    fn room(&self, bytes: u128, at: Span) -> R<()> {
        let held = (meter::live() - self.base).max(0) as u128;
        if held.saturating_add(bytes) > self.limits.memory as u128 {
            return Err(self.too_much_memory(at));
        }
        Ok(())
    }

    /// The bytes left to the run under its memory budget.
    fn room_left(&self) -> u64 {
        (self.limits.memory as i64 - (meter::live() - self.base)).max(0) as u64
    }

    /// A buffer of `n` values that the run fills while it evaluates more of the script, counted
    /// against the memory budget while it is filled (the sequence or function it becomes is
    /// counted in its turn).
    fn buffer(&self, n: usize, at: Span) -> R<(Vec<Value>, Charge)> {
        let bytes = buffer_bytes::<Value>(n);
        self.room(bytes as u128, at)?;
        Ok((Vec::with_capacity(n), Charge::new(bytes)))
    }

    #[cold]
    #[inline(never)]
    fn too_much_memory(&self, at: Span) -> Error {
        let most = self.limits.memory;
        let most = if most.is_multiple_of(1 << 20) {
            format!("{} MiB", most >> 20)
        } else {
            format!("{most} bytes")
        };
        Error::new(
            ErrorKind::Limit,
            at,
            format!(
                "the script builds more than {most} of values held at once (sequences, \
                 functions, complexes): past the memory limit"
            ),
        )
    }

    /// A name's value. Names match case-insensitively, but a name written exactly as defined
    /// wins over one that matches only so: in the paper's `Choose (n,k::IsNat)`, `K:1` is the
    /// built-in `K`, not the parameter `k`, while Script 4.5's `k:2` is `K:2`.
    fn lookup(&mut self, key: &Rc<str>, spelled: &str, at: Span, env: &Env<'_>) -> R<Value> {
        for exact in [true, false] {
            let hit = |k: &Rc<str>, s: &str| if exact { s == spelled } else { k == key };
            if let Some((_, _, v)) = env.params.iter().rev().find(|(k, s, _)| hit(k, s)) {
                return Ok(v.clone());
            }
            if let Some(i) = env.locals.iter().position(|l| hit(&l.key, &l.name)) {
                return self.local(env, i, spelled, at);
            }
            // A script sees its globals, then the prelude's names that it has not defined; the
            // prelude sees only its own.
            let global = if env.prelude {
                self.prelude.get(key)
            } else {
                self.globals.get(key).or_else(|| self.prelude.get(key))
            };
            if let Some((s, v)) = global
                && (!exact || &**s == spelled)
            {
                return Ok(v.clone());
            }
            if (!exact || spelled == &**key)
                && let Some(v) = builtin(key)
            {
                return Ok(v);
            }
        }
        let mut message = format!("unknown name `{spelled}`");
        if let Some(near) = self.nearest(key, env) {
            message.push_str(&format!("; did you mean `{near}`?"));
        }
        Err(Error::new(ErrorKind::Name, at, message))
    }

    /// Local `i` of a `WHERE`, evaluated on first use.
    fn local(&mut self, env: &Env<'_>, i: usize, spelled: &str, at: Span) -> R<Value> {
        let slot = env.slots.borrow()[i].clone();
        match slot {
            Slot::Done(v) => Ok(v),
            Slot::Busy => Err(Error::new(
                ErrorKind::Name,
                at,
                format!("`{spelled}` is defined in terms of itself"),
            )),
            Slot::Todo => {
                env.slots.borrow_mut()[i] = Slot::Busy;
                let v = self.eval(&env.locals[i].expr, env)?;
                env.slots.borrow_mut()[i] = Slot::Done(v.clone());
                Ok(v)
            }
        }
    }

    fn nearest(&self, key: &str, env: &Env<'_>) -> Option<String> {
        if key.len() > 64 {
            return None;
        }
        let mut names: Vec<String> = self.globals.values().map(|g| g.0.to_string()).collect();
        names.extend(self.prelude.values().map(|g| g.0.to_string()));
        names.extend(NAMES.iter().map(|n| n.0.to_string()));
        names.extend(env.params.iter().map(|p| p.1.to_string()));
        names.extend(env.locals.iter().map(|l| l.name.to_string()));
        names.extend(["PI".to_string()]);
        let limit = if key.len() <= 3 { 1 } else { 2 };
        names
            .into_iter()
            .map(|n| (distance(key, &n.to_ascii_uppercase()), n))
            .filter(|(d, _)| *d <= limit)
            .min_by_key(|(d, _)| *d)
            .map(|(_, n)| n)
    }

    fn eval(&mut self, e: &Expr, env: &Env<'_>) -> R<Value> {
        self.tick(1, e.span())?;
        match e {
            Expr::Num(x, _) => Ok(Value::Num(*x)),
            Expr::Name(key, spelled, at) => self.lookup(key, spelled, *at, env),
            _ => {
                // Expressions nest inside calls: their depth, summed over the calls under way,
                // is bounded too, so that neither can overflow the stack.
                if self.nesting >= MAX_EVAL_NESTING {
                    return Err(Error::new(
                        ErrorKind::Limit,
                        e.span(),
                        format!(
                            "expressions nested more than {MAX_EVAL_NESTING} deep across calls: \
                             endless recursion?"
                        ),
                    ));
                }
                self.nesting += 1;
                let r = self.eval_nested(e, env);
                self.nesting -= 1;
                r
            }
        }
    }

    fn eval_nested(&mut self, e: &Expr, env: &Env<'_>) -> R<Value> {
        match e {
            Expr::Apply(f, x, at) => {
                let fv = self.eval(f, env)?;
                let xv = self.eval(x, env)?;
                if !matches!(fv, Value::Fun(_)) {
                    return not_applicable(f.span(), &fv, &xv);
                }
                self.apply(&fv, xv, *at)
            }
            _ => self.eval_other(e, env),
        }
    }

    /// The rarer expressions, apart so that [`Interp::eval`]'s frame, which recursion stacks,
    /// stays small.
    #[inline(never)]
    fn eval_other(&mut self, e: &Expr, env: &Env<'_>) -> R<Value> {
        match e {
            // `eval` and `eval_nested` take these first; here only for a complete match.
            Expr::Num(x, _) => Ok(Value::Num(*x)),
            Expr::Name(key, spelled, at) => self.lookup(key, spelled, *at, env),
            Expr::Apply(..) => self.eval_nested(e, env),
            Expr::Seq(items, at) => {
                self.tick(items.len() as u64, *at)?;
                let (mut v, _held) = self.buffer(items.len(), *at)?;
                for x in items {
                    v.push(self.eval(x, env)?);
                }
                Ok(Value::seq(v))
            }
            Expr::Cons(items, at) => {
                let (mut fs, _held) = self.buffer(items.len(), *at)?;
                for x in items {
                    let v = self.eval(x, env)?;
                    fs.push(function(v, x.span(), "an item of [ … ]")?);
                }
                Ok(Value::fun(Fun::Cons(fs)))
            }
            Expr::Op(op, _) => Ok(Value::fun(Fun::Prim(Prim::Arith(*op)))),
            Expr::Infix(op, a, b, at) => {
                let av = self.eval(a, env)?;
                let bv = self.eval(b, env)?;
                self.arith(*op, vec![av, bv], *at)
            }
            Expr::Compose(parts, at) => {
                let (mut fs, mut held) = self.buffer(parts.len(), *at)?;
                for p in parts {
                    let v = self.eval(p, env)?;
                    match function(v, p.span(), "an operand of `~`")? {
                        Value::Fun(f) => match &*f {
                            Fun::Compose(inner) => {
                                self.room(buffer_bytes::<Value>(inner.len()) as u128, *at)?;
                                fs.extend(inner.iter().cloned());
                                held.set(buffer_bytes::<Value>(fs.capacity()));
                            }
                            _ => fs.push(Value::Fun(f)),
                        },
                        v => fs.push(v),
                    }
                }
                self.tick(fs.len() as u64, *at)?;
                Ok(Value::fun(Fun::Compose(fs)))
            }
            Expr::Neg(x, at) => {
                let v = self.eval(x, env)?;
                self.arith(Arith::Sub, vec![v], *at)
            }
            Expr::Range(a, b, at) => {
                let av = self.eval(a, env)?;
                let bv = self.eval(b, env)?;
                let (Some(lo), Some(hi)) =
                    (av.as_num().and_then(whole), bv.as_num().and_then(whole))
                else {
                    return type_error(
                        *at,
                        format!("`..` takes two whole numbers, not {av} and {bv}"),
                    );
                };
                let n = (hi - lo + 1).max(0) as u64;
                self.items(n, *at)?;
                Ok(Value::seq(
                    (lo..=hi).map(|i| Value::Num(i as f64)).collect(),
                ))
            }
        }
    }

    /// Checks, and counts as steps, the `n` items of a sequence about to be built.
    fn items(&mut self, n: u64, at: Span) -> R<()> {
        if n > self.limits.items as u64 {
            return Err(Error::new(
                ErrorKind::Limit,
                at,
                format!(
                    "a sequence of {n} items, past the limit of {}",
                    self.limits.items
                ),
            ));
        }
        self.room(Items::bytes(n as usize) as u128, at)?;
        self.tick(n, at)
    }

    /// `f:x`.
    fn apply(&mut self, f: &Value, x: Value, at: Span) -> R<Value> {
        self.tick(1, at)?;
        let Value::Fun(fun) = f else {
            return not_applicable(at, f, &x);
        };
        if self.depth >= self.limits.depth {
            return Err(too_deep(at, self.limits.depth));
        }
        self.depth += 1;
        let r = self.apply_fun(fun, x, at);
        self.depth -= 1;
        r
    }

    fn apply_fun(&mut self, fun: &Rc<Fun>, x: Value, at: Span) -> R<Value> {
        match &**fun {
            Fun::Prim(p) => {
                if p.arity() == 1 {
                    self.prim(*p, vec![x], at)
                } else {
                    Ok(Value::fun(Fun::Partial(*p, vec![x])))
                }
            }
            Fun::Partial(p, args) => {
                if args.len() + 1 == p.arity() {
                    let mut args = args.clone();
                    args.push(x);
                    self.prim(*p, args, at)
                } else {
                    Ok(Value::fun(Fun::Partial(*p, more(args, x))))
                }
            }
            Fun::Compose(fs) => {
                let mut v = x;
                for f in fs.iter().rev() {
                    v = self.apply(f, v, at)?;
                }
                Ok(v)
            }
            Fun::Cons(fs) => {
                let (mut out, _held) = self.buffer(fs.len(), at)?;
                for f in fs {
                    out.push(self.apply(f, x.clone(), at)?);
                }
                Ok(Value::seq(out))
            }
            Fun::Lift(op, items) => {
                let (mut v, _held) = self.buffer(items.len(), at)?;
                for f in items {
                    v.push(match f {
                        Value::Fun(_) => self.apply(f, x.clone(), at)?,
                        other => other.clone(),
                    });
                }
                self.arith(*op, v, at)
            }
            Fun::User(def, groups) => {
                if groups.len() + 1 == def.groups.len() {
                    self.call_def(def.clone(), more(groups, x), at)
                } else {
                    Ok(Value::fun(Fun::User(def.clone(), more(groups, x))))
                }
            }
        }
    }

    fn call_def(&mut self, def: Rc<Def>, args: Vec<Value>, at: Span) -> R<Value> {
        let ours = in_prelude(def.body.span());
        let r = self.bind(&def, args, at).and_then(|params| {
            let mut env = Env::new(params, &def.locals);
            env.prelude = ours;
            self.eval(&def.body, &env)
        });
        match r {
            // Called from a script: an error at a place in the prelude is placed at the call.
            Err(e) if ours && !in_prelude(at) && in_prelude(e.span) => {
                Err(placed_at_call(e, &def, at))
            }
            r => r,
        }
    }

    /// The parameters of a call, each checked by its predicate.
    #[inline(never)]
    fn bind(&mut self, def: &Def, args: Vec<Value>, at: Span) -> R<Vec<Param>> {
        let mut params = Vec::new();
        for (g, arg) in def.groups.iter().zip(args) {
            let bound: Vec<Value> = if g.names.len() == 1 {
                vec![arg]
            } else {
                match arg.as_seq() {
                    Some(items) if items.len() == g.names.len() => items.to_vec(),
                    _ => {
                        let names: Vec<&str> = g.names.iter().map(|n| &*n.1).collect();
                        return type_error(
                            at,
                            format!(
                                "{} takes <{}>, a sequence of {}, not {arg}",
                                def.name,
                                names.join(", "),
                                names.len()
                            ),
                        );
                    }
                }
            };
            let empty = Env::new(Vec::new(), &[]);
            let pred = self.eval(&g.pred, &empty)?;
            for ((key, name), v) in g.names.iter().zip(bound) {
                match self.apply(&pred, v.clone(), at)? {
                    Value::Bool(true) => {}
                    Value::Bool(false) => {
                        return type_error(
                            at,
                            format!(
                                "{}: parameter `{name}` = {v} does not satisfy {}",
                                def.name, g.pred_text
                            ),
                        );
                    }
                    other => {
                        return type_error(
                            g.pred.span(),
                            format!(
                                "the predicate of `{name}` in {} gives {other}, not TRUE or FALSE",
                                def.name
                            ),
                        );
                    }
                }
                params.push((key.clone(), name.clone(), v));
            }
        }
        Ok(params)
    }

    /// `op:<items>` on numbers, pointwise on functions, or the product of complexes.
    fn arith(&mut self, op: Arith, items: Vec<Value>, at: Span) -> R<Value> {
        let sym = op.symbol();
        self.tick(items.len() as u64 / 4, at)?;
        if items.iter().all(|v| matches!(v, Value::Num(_))) {
            let x: Vec<f64> = items.iter().filter_map(Value::as_num).collect();
            let r = match (op, x.as_slice()) {
                (Arith::Add, _) => x.iter().sum(),
                (Arith::Mul, _) => x.iter().product(),
                (_, []) => return type_error(at, format!("`{sym}` of no numbers")),
                (Arith::Sub, [a]) => -a,
                (Arith::Sub, [a, rest @ ..]) => rest.iter().fold(*a, |s, b| s - b),
                (Arith::Div, [a, rest @ ..]) => {
                    if rest.contains(&0.0) {
                        return Err(Error::new(
                            ErrorKind::Math,
                            at,
                            format!("division by zero: {}", Value::seq(items.clone())),
                        ));
                    }
                    if rest.is_empty() {
                        1.0 / a
                    } else {
                        rest.iter().fold(*a, |s, b| s / b)
                    }
                }
                (Arith::Pow, _) => x
                    .iter()
                    .rev()
                    .copied()
                    .reduce(|e, b| power(b, e))
                    .unwrap_or(1.0),
            };
            if !r.is_finite() {
                return Err(Error::new(
                    ErrorKind::Math,
                    at,
                    format!(
                        "`{sym}` of {} is not a finite number",
                        Value::seq(items.clone())
                    ),
                ));
            }
            return Ok(Value::Num(r));
        }
        if items
            .iter()
            .all(|v| matches!(v, Value::Num(_) | Value::Fun(_)))
        {
            // x ↦ op:<items(x)>; sums and products of sums and products are one node.
            let n = items
                .iter()
                .map(|v| same_lift(op, v).map_or(1, <[Value]>::len) as u64)
                .sum();
            self.items(n, at)?;
            let mut flat = Vec::with_capacity(n as usize);
            for v in &items {
                match same_lift(op, v) {
                    Some(xs) => flat.extend(xs.iter().cloned()),
                    None => flat.push(v.clone()),
                }
            }
            return Ok(Value::fun(Fun::Lift(op, flat)));
        }
        if op == Arith::Mul && items.len() >= 2 && items.iter().all(|v| v.as_pol().is_some()) {
            let limit = |e| Error::new(ErrorKind::Limit, at, format!("`*`: {e}"));
            let Value::Pol(first) = &items[0] else {
                unreachable!("all are complexes")
            };
            let mut acc = first.clone();
            for b in &items[1..] {
                let b = b.as_pol().expect("a complex");
                acc.product_fits(b, self.limits.cells).map_err(limit)?;
                self.room(acc.product_bytes(b), at)?;
                acc = Rc::new(acc.product(b, self.limits.cells).map_err(limit)?);
                self.tick(acc.cells.len() as u64 / 4, at)?;
            }
            return Ok(Value::Pol(acc));
        }
        let bad = items
            .iter()
            .find(|v| !matches!(v, Value::Num(_) | Value::Fun(_)))
            .unwrap_or(&items[0]);
        let what = if op == Arith::Mul {
            "numbers, functions or complexes (their product)"
        } else {
            "numbers or functions"
        };
        type_error(
            at,
            format!("`{sym}` takes {what}, but got {} ({bad})", bad.kind()),
        )
    }

    /// The built-ins that apply functions, apart from the others so that the frames on the
    /// path of recursion stay small.
    fn prim(&mut self, p: Prim, args: Vec<Value>, at: Span) -> R<Value> {
        match p {
            Prim::AA => self.prim_aa(args, at),
            Prim::C => self.prim_c(args, at),
            Prim::If => self.prim_if(args, at),
            Prim::IsSeqOf => self.prim_is_seq_of(args, at),
            Prim::Map => self.prim_map(args, at),
            _ => self.plain(p, args, at),
        }
    }

    #[inline(never)]
    fn prim_aa(&mut self, mut args: Vec<Value>, at: Span) -> R<Value> {
        let x = args.pop().expect("arity 2");
        let f = args.pop().expect("arity 2");
        let Value::Seq(s) = &x else {
            return type_error(
                at,
                format!(
                    "AA takes a sequence to apply the function to, not {} ({x})",
                    x.kind()
                ),
            );
        };
        self.items(s.len() as u64, at)?;
        let (mut out, _held) = self.buffer(s.len(), at)?;
        for item in s.iter() {
            out.push(self.apply(&f, item.clone(), at)?);
        }
        Ok(Value::seq(out))
    }

    #[inline(never)]
    fn prim_c(&mut self, mut args: Vec<Value>, at: Span) -> R<Value> {
        let x = args.pop().expect("arity 3");
        let a = args.pop().expect("arity 3");
        let f = args.pop().expect("arity 3");
        // The fixed argument is the right operand: `C:-:1` is the predecessor.
        self.apply(&f, Value::seq(vec![x, a]), at)
    }

    #[inline(never)]
    fn prim_if(&mut self, mut args: Vec<Value>, at: Span) -> R<Value> {
        let x = args.pop().expect("arity 2");

        let s = args.pop().expect("arity 2");
        let Some([test, then, other]) = s.as_seq() else {
            return type_error(at, format!("IF takes <test, then, else>, not {s}"));
        };
        let (test, then, other) = (test.clone(), then.clone(), other.clone());
        match self.apply(&test, x.clone(), at)? {
            Value::Bool(true) => self.apply(&then, x, at),
            Value::Bool(false) => self.apply(&other, x, at),
            v => type_error(
                at,
                format!("IF: the test {test} gives {v}, not TRUE or FALSE"),
            ),
        }
    }

    #[inline(never)]
    fn prim_is_seq_of(&mut self, mut args: Vec<Value>, at: Span) -> R<Value> {
        let x = args.pop().expect("arity 2");

        let pred = args.pop().expect("arity 2");
        let Value::Seq(s) = &x else {
            return Ok(Value::Bool(false));
        };
        for item in s.iter() {
            match self.apply(&pred, item.clone(), at)? {
                Value::Bool(true) => {}
                Value::Bool(false) => return Ok(Value::Bool(false)),
                v => {
                    return type_error(
                        at,
                        format!("IsSeqOf: the predicate gives {v}, not TRUE or FALSE"),
                    );
                }
            }
        }
        Ok(Value::Bool(true))
    }

    #[inline(never)]
    fn prim_map(&mut self, mut args: Vec<Value>, at: Span) -> R<Value> {
        let x = args.pop().expect("arity 2");

        let f = args.pop().expect("arity 2");
        let f = match f {
            Value::Seq(fs) => {
                let fs = fs
                    .iter()
                    .map(|g| function(g.clone(), at, "an item of MAP's sequence"))
                    .collect::<R<Vec<_>>>()?;
                Value::fun(Fun::Cons(fs))
            }
            other => function(other, at, "MAP's map")?,
        };
        let Value::Pol(pol) = &x else {
            return type_error(at, format!("MAP maps a complex, not {} ({x})", x.kind()));
        };
        let mut points = Vec::new();
        let mut dim = None;
        // The fast path where the map compiles; the interpreter for the rest, and for any point
        // where the kernel meets a value that is not finite (to give the interpreter's error).
        let kernel = if self.limits.kernels {
            let budget = self.limits.steps.saturating_sub(self.steps);
            let k = Kernel::compile(&f, pol.dim, self.limits.depth, budget, self.room_left());
            self.tick(k.as_ref().map_or(0, |k| k.len() as u64), at)?;
            k
        } else {
            None
        };
        let _kernel_held = Charge::new(kernel.as_ref().map_or(0, Kernel::bytes));
        let coordinates_cap = self.limits.cells.saturating_mul(16);
        let too_many = || {
            Err(Error::new(
                ErrorKind::Limit,
                at,
                format!("MAP: the points have more than {coordinates_cap} coordinates in all"),
            ))
        };
        let (n, d) = (pol.point_count(), pol.dim);
        let (mut slots, mut image, mut bad) = (Vec::new(), Vec::new(), Vec::new());
        // The points' buffer, counted while it is filled: once the first points tell their
        // dimension, room for all of them is checked and reserved at once.
        let (mut reserved, mut held) = (false, Charge::default());
        let mut i = 0;
        while i < n {
            if let (false, Some(dim)) = (reserved, dim) {
                reserved = true;
                let total = n.saturating_mul(dim);
                if total > coordinates_cap {
                    return too_many();
                }
                self.room(Complex::bytes(total, pol.cells.len()) as u128, at)?;
                points.reserve_exact(total.saturating_sub(points.len()));
                held.set(buffer_bytes::<f64>(points.capacity()));
            }
            let Some(k) = &kernel else {
                self.map_point(&f, pol.point(i), at, &mut dim, &mut points)?;
                i += 1;
                continue;
            };
            // A block of points at once through the kernel; a point where it met a value that is
            // not finite goes to the interpreter, in its place.
            let count = (n - i).min(LANES);
            self.tick(count as u64 * (1 + k.len() as u64 / 10), at)?;
            k.eval_block(
                &pol.points[i * d..(i + count) * d],
                d,
                &mut slots,
                &mut image,
                &mut bad,
            );
            let od = k.out_dim();
            for l in 0..count {
                if bad[l] {
                    self.map_point(&f, pol.point(i + l), at, &mut dim, &mut points)?;
                } else {
                    // A kernel's points all have its output's dimension.
                    dim.get_or_insert(od);
                    points.extend_from_slice(&image[l * od..(l + 1) * od]);
                }
            }
            i += count;
        }
        if points.len() > coordinates_cap {
            return too_many();
        }
        let made = Rc::new(Complex::new(
            dim.unwrap_or(pol.dim),
            points,
            pol.order,
            pol.cells.clone(),
        ));
        self.last_map = Some((
            made.clone(),
            MapOf {
                f,
                domain: pol.clone(),
            },
        ));
        Ok(Value::Pol(made))
    }

    /// One point of `MAP`, interpreted: `f` at `u`, appended to `points`.
    fn map_point(
        &mut self,
        f: &Value,
        u: &[f64],
        at: Span,
        dim: &mut Option<usize>,
        points: &mut Vec<f64>,
    ) -> R<()> {
        let here = || Value::seq(u.iter().map(|&c| Value::Num(c)).collect());
        let image = self.apply(f, here(), at)?;
        let coords = match &image {
            Value::Num(c) => vec![*c],
            other => other.as_point().map_or_else(
                || {
                    type_error(
                        at,
                        format!(
                            "MAP: the map gives {} ({other}) at {}, not a point (a function or \
                             sequence of functions where a number was wanted: use CONS or \
                             compose with S1)",
                            other.kind(),
                            here()
                        ),
                    )
                },
                Ok,
            )?,
        };
        if coords.is_empty() {
            return type_error(
                at,
                format!("MAP: the map gives an empty point at {}", here()),
            );
        }
        if coords.iter().any(|c| !c.is_finite()) {
            return Err(Error::new(
                ErrorKind::Math,
                at,
                format!("MAP: the map is not finite at {image}"),
            ));
        }
        match *dim {
            None => *dim = Some(coords.len()),
            Some(d) if d != coords.len() => {
                return type_error(
                    at,
                    format!(
                        "MAP: the map gives points of {d} and of {} coordinates",
                        coords.len()
                    ),
                );
            }
            _ => {}
        }
        points.extend(coords);
        Ok(())
    }

    #[inline(never)]
    #[allow(clippy::too_many_lines)]
    fn plain(&mut self, p: Prim, mut args: Vec<Value>, at: Span) -> R<Value> {
        let name = p.name();
        let x = args.pop().expect("arity ≥ 1");
        let seq = |v: &Value, what: &str| -> R<Rc<crate::value::Items>> {
            match v {
                Value::Seq(s) => Ok(s.clone()),
                other => type_error(
                    at,
                    format!("{name} takes {what}, not {} ({other})", other.kind()),
                ),
            }
        };
        let num = |v: &Value| -> R<f64> {
            v.as_num().map_or_else(
                || type_error(at, format!("{name} takes a number, not {} ({v})", v.kind())),
                Ok,
            )
        };
        let truth = |v: &Value| -> R<bool> {
            match v {
                Value::Bool(b) => Ok(*b),
                other => type_error(
                    at,
                    format!("{name} takes TRUE or FALSE, not {} ({other})", other.kind()),
                ),
            }
        };
        let math = |f: fn(f64) -> f64, v: &Value| -> R<Value> {
            let a = match v {
                Value::Num(a) => *a,
                Value::Fun(_) => {
                    return type_error(
                        at,
                        format!("{name} takes a number, not a function: write `{name} ~ f`"),
                    );
                }
                other => {
                    return type_error(
                        at,
                        format!("{name} takes a number, not {} ({other})", other.kind()),
                    );
                }
            };
            let r = f(a);
            if r.is_finite() {
                Ok(Value::Num(r))
            } else {
                Err(Error::new(
                    ErrorKind::Math,
                    at,
                    format!("{name}:{a} is not a finite number"),
                ))
            }
        };
        let is_whole = |v: &Value, min: i64| v.as_num().and_then(whole).is_some_and(|i| i >= min);
        let pair = |v: &Value, what: &str| -> R<(Value, Value)> {
            match v.as_seq() {
                Some([a, b]) => Ok((a.clone(), b.clone())),
                _ => type_error(at, format!("{name} takes {what}, not {v}")),
            }
        };
        match p {
            Prim::Arith(op) => match x {
                Value::Seq(items) => self.arith(op, items.to_vec(), at),
                Value::Num(_) | Value::Fun(_) if op == Arith::Sub => self.arith(op, vec![x], at),
                other => type_error(
                    at,
                    format!(
                        "`{name}` as a function takes a sequence (`{name}:<a, b>`), not {} \
                         ({other})",
                        other.kind()
                    ),
                ),
            },
            Prim::Select(i) => {
                let s = seq(&x, "a sequence")?;
                s.get(i as usize - 1).cloned().map_or_else(
                    || type_error(at, format!("S{i} of a sequence of {} ({x})", s.len())),
                    Ok,
                )
            }
            Prim::Id => Ok(x),
            Prim::K => Ok(args.pop().expect("arity 2")),
            Prim::Cons | Prim::Comp => {
                let s = seq(&x, "a sequence of functions")?;
                self.tick(s.len() as u64, at)?;
                self.room(buffer_bytes::<Value>(s.len()) as u128, at)?;
                let fs = s
                    .iter()
                    .map(|f| function(f.clone(), at, &format!("an item of {name}")))
                    .collect::<R<Vec<_>>>()?;
                Ok(Value::fun(if p == Prim::Cons {
                    Fun::Cons(fs)
                } else {
                    Fun::Compose(fs)
                }))
            }
            Prim::Trans => {
                let s = seq(&x, "a sequence of sequences")?;
                let rows = s
                    .iter()
                    .map(|r| seq(r, "a sequence of sequences"))
                    .collect::<R<Vec<_>>>()?;
                let n = rows.iter().map(|r| r.len()).max().unwrap_or(0);
                self.items((n as u64).saturating_mul(rows.len() as u64), at)?;
                self.room(
                    Items::bytes(n) as u128 + n as u128 * Items::bytes(rows.len()) as u128,
                    at,
                )?;
                Ok(Value::seq(
                    (0..n)
                        .map(|j| {
                            Value::seq(
                                rows.iter()
                                    .map(|r| r.get(j).cloned().unwrap_or(Value::Num(0.0)))
                                    .collect(),
                            )
                        })
                        .collect(),
                ))
            }
            Prim::Distl | Prim::Distr => {
                let (a, b) = pair(&x, "a pair")?;
                let (value, list) = if p == Prim::Distl { (a, b) } else { (b, a) };
                let s = seq(&list, "a pair of a value and a sequence")?;
                self.items(s.len() as u64, at)?;
                self.room(
                    Items::bytes(s.len()) as u128 + s.len() as u128 * Items::bytes(2) as u128,
                    at,
                )?;
                Ok(Value::seq(
                    s.iter()
                        .map(|item| {
                            Value::seq(if p == Prim::Distl {
                                vec![value.clone(), item.clone()]
                            } else {
                                vec![item.clone(), value.clone()]
                            })
                        })
                        .collect(),
                ))
            }
            Prim::Sel => {
                let i = args.pop().expect("arity 2");
                let s = seq(&x, "a sequence")?;
                match i.as_num().and_then(whole) {
                    Some(k) if k >= 1 && (k as usize) <= s.len() => Ok(s[k as usize - 1].clone()),
                    _ => type_error(at, format!("SEL:{i} of a sequence of {}", s.len())),
                }
            }
            Prim::Len => Ok(Value::Num(seq(&x, "a sequence")?.len() as f64)),
            Prim::First | Prim::Last => {
                let s = seq(&x, "a sequence")?;
                let item = if p == Prim::First {
                    s.first()
                } else {
                    s.last()
                };
                item.cloned().map_or_else(
                    || type_error(at, format!("{name} of an empty sequence")),
                    Ok,
                )
            }
            Prim::Tail => {
                let s = seq(&x, "a sequence")?;
                if s.is_empty() {
                    return type_error(at, "TAIL of an empty sequence".into());
                }
                self.tick(s.len() as u64, at)?;
                self.room(Items::bytes(s.len()) as u128, at)?;
                Ok(Value::seq(s[1..].to_vec()))
            }
            Prim::Reverse => {
                let s = seq(&x, "a sequence")?;
                self.tick(s.len() as u64, at)?;
                self.room(Items::bytes(s.len()) as u128, at)?;
                Ok(Value::seq(s.iter().rev().cloned().collect()))
            }
            Prim::Cat => {
                let s = seq(&x, "a sequence of sequences")?;
                let rows = s
                    .iter()
                    .map(|r| seq(r, "a sequence of sequences"))
                    .collect::<R<Vec<_>>>()?;
                self.items(rows.iter().map(|r| r.len() as u64).sum(), at)?;
                Ok(Value::seq(
                    rows.iter().flat_map(|r| r.iter().cloned()).collect(),
                ))
            }
            Prim::Al | Prim::Ar => {
                let (a, b) = pair(&x, "a pair")?;
                let (one, s) = if p == Prim::Al {
                    (a, seq(&b, "a value and a sequence")?)
                } else {
                    (b, seq(&a, "a sequence and a value")?)
                };
                self.items(s.len() as u64 + 1, at)?;
                let mut out = Vec::with_capacity(s.len() + 1);
                if p == Prim::Al {
                    out.push(one);
                    out.extend(s.iter().cloned());
                } else {
                    out.extend(s.iter().cloned());
                    out.push(one);
                }
                Ok(Value::seq(out))
            }
            Prim::Intsto => {
                if !is_whole(&x, 0) {
                    return type_error(at, format!("INTSTO takes a whole number ≥ 0, not {x}"));
                }
                let n = num(&x)? as u64;
                self.items(n, at)?;
                Ok(Value::seq((1..=n).map(|i| Value::Num(i as f64)).collect()))
            }
            Prim::Repeat => {
                let n = args.pop().expect("arity 2");
                if !is_whole(&n, 0) {
                    return type_error(at, format!("# takes a whole number ≥ 0, not {n}"));
                }
                let n = num(&n)? as u64;
                self.items(n, at)?;
                Ok(Value::seq(vec![x; n as usize]))
            }
            Prim::InnerProd => {
                let (a, b) = pair(&x, "a pair of sequences")?;
                let (a, b) = (seq(&a, "two sequences")?, seq(&b, "two sequences")?);
                if a.len() != b.len() {
                    return type_error(
                        at,
                        format!(
                            "InnerProd of sequences of {} and {} items",
                            a.len(),
                            b.len()
                        ),
                    );
                }
                let (mut terms, _held) = self.buffer(a.len(), at)?;
                for (u, v) in a.iter().zip(b.iter()) {
                    terms.push(self.arith(Arith::Mul, vec![u.clone(), v.clone()], at)?);
                }
                self.arith(Arith::Add, terms, at)
            }
            Prim::Eq => {
                let s = seq(&x, "a sequence")?;
                let left = self.limits.steps.saturating_sub(self.steps);
                let mut budget = left;
                let mut all = true;
                for w in s.windows(2) {
                    match w[0].same(&w[1], &mut budget) {
                        Some(true) => {}
                        Some(false) => {
                            all = false;
                            break;
                        }
                        None => {
                            return Err(Error::new(
                                ErrorKind::Limit,
                                at,
                                "EQ: values too large or too deeply nested to compare within the \
                                 limits"
                                    .into(),
                            ));
                        }
                    }
                }
                self.tick(left - budget, at)?;
                Ok(Value::Bool(all))
            }
            Prim::Or | Prim::And => {
                let s = seq(&x, "a sequence of truth values")?;
                self.tick(s.len() as u64, at)?;
                let v = s.iter().map(truth).collect::<R<Vec<_>>>()?;
                Ok(Value::Bool(if p == Prim::Or {
                    v.iter().any(|b| *b)
                } else {
                    v.iter().all(|b| *b)
                }))
            }
            Prim::Not => Ok(Value::Bool(!truth(&x)?)),
            Prim::Sin
            | Prim::Cos
            | Prim::Tan
            | Prim::Asin
            | Prim::Acos
            | Prim::Atan
            | Prim::Sqrt
            | Prim::Exp
            | Prim::Ln
            | Prim::Abs => math(p.unary_math().unwrap_or(f64::abs), &x),
            Prim::IsReal | Prim::IsNum => Ok(Value::Bool(matches!(x, Value::Num(_)))),
            Prim::IsInt => Ok(Value::Bool(is_whole(&x, i64::MIN))),
            Prim::IsIntPos => Ok(Value::Bool(is_whole(&x, 1))),
            Prim::IsNat => Ok(Value::Bool(is_whole(&x, 0))),
            Prim::IsBool => Ok(Value::Bool(matches!(x, Value::Bool(_)))),
            Prim::IsFun => Ok(Value::Bool(matches!(x, Value::Fun(_)))),
            Prim::IsSeq => Ok(Value::Bool(matches!(x, Value::Seq(_)))),
            Prim::IsPoint | Prim::IsVect => {
                self.tick(x.as_seq().map_or(0, <[Value]>::len) as u64, at)?;
                Ok(Value::Bool(x.as_point().is_some()))
            }
            Prim::IsPol => Ok(Value::Bool(matches!(x, Value::Pol(_)))),
            Prim::Quote => {
                let s = seq(&x, "a sequence of lengths")?;
                let mut lengths = Vec::with_capacity(s.len());
                for v in s.iter() {
                    match v.as_num() {
                        Some(d) if d != 0.0 => lengths.push(d),
                        _ => {
                            return type_error(at, format!("QUOTE takes nonzero numbers, not {v}"));
                        }
                    }
                }
                self.cells(lengths.len() as u128, at)?;
                Ok(Value::Pol(Rc::new(Complex::quote(&lengths))))
            }
            Prim::T | Prim::S => {
                let amounts = args.pop().expect("arity 3");
                let coords = args.pop().expect("arity 3");
                let Value::Pol(pol) = &x else {
                    return type_error(
                        at,
                        format!("{name} moves a complex, not {} ({x})", x.kind()),
                    );
                };
                let list = |v: &Value| match v {
                    Value::Num(a) => Some(vec![*a]),
                    other => other.as_point(),
                };
                let (Some(cs), Some(ds)) = (list(&coords), list(&amounts)) else {
                    return type_error(
                        at,
                        format!("{name} takes coordinates and amounts, not {coords} and {amounts}"),
                    );
                };
                if cs.len() != ds.len()
                    || cs
                        .iter()
                        .any(|&c| whole(c).is_none_or(|i| !(1..=16).contains(&i)))
                {
                    return type_error(
                        at,
                        format!(
                            "{name}:{coords}:{amounts}: coordinates are whole numbers from 1 to \
                             16, one per amount"
                        ),
                    );
                }
                let dim = cs.iter().fold(pol.dim, |d, &c| d.max(c as usize));
                let points = if dim > pol.dim {
                    let n = pol.point_count();
                    self.items((n as u64).saturating_mul(dim as u64), at)?;
                    self.room(Complex::bytes(n * dim, pol.cells.len()) as u128, at)?;
                    let mut pts = Vec::with_capacity(n * dim);
                    for i in 0..n {
                        pts.extend_from_slice(pol.point(i));
                        pts.extend(std::iter::repeat_n(0.0, dim - pol.dim));
                    }
                    pts
                } else {
                    self.room(
                        Complex::bytes(pol.points.len(), pol.cells.len()) as u128,
                        at,
                    )?;
                    pol.points.clone()
                };
                let mut out = Complex::new(dim, points, pol.order, pol.cells.clone());
                self.tick(out.points.len() as u64 / 4, at)?;
                for (&c, &d) in cs.iter().zip(&ds) {
                    let c = c as usize - 1;
                    for point in out.points.chunks_mut(dim) {
                        if p == Prim::T {
                            point[c] += d;
                        } else {
                            point[c] *= d;
                        }
                    }
                }
                Ok(Value::Pol(Rc::new(out)))
            }
            Prim::AA | Prim::C | Prim::If | Prim::IsSeqOf | Prim::Map => {
                unreachable!("dispatched by prim")
            }
            Prim::Interval | Prim::Intervals | Prim::Domain => {
                let n = &x;
                if !is_whole(n, 1) {
                    return type_error(
                        at,
                        format!("{name} takes a whole number of segments above 0, not {n}"),
                    );
                }
                let n = num(n)?;
                let (a, b) = match p {
                    Prim::Domain => (0.0, 1.0),
                    Prim::Intervals => (0.0, num(&args.pop().expect("arity 2"))?),
                    _ => {
                        let ab = args.pop().expect("arity 2");
                        let Some([a, b]) = ab
                            .as_point()
                            .as_deref()
                            .map(|v| <[f64; 2]>::try_from(v).unwrap_or([f64::NAN, f64::NAN]))
                        else {
                            return type_error(at, format!("interval takes <a, b>, not {ab}"));
                        };
                        if !(a.is_finite() && b.is_finite()) {
                            return type_error(at, format!("interval takes <a, b>, not {ab}"));
                        }
                        (a, b)
                    }
                };
                self.cells(n as u128, at)?;
                Ok(Value::Pol(Rc::new(Complex::interval(a, b, n as usize))))
            }
        }
    }

    /// Checks, and counts as steps, the `n` segments of a complex about to be built (by
    /// `QUOTE` or `interval`: at most two points and two indices each).
    fn cells(&mut self, n: u128, at: Span) -> R<()> {
        if n > self.limits.cells as u128 {
            return Err(Error::new(
                ErrorKind::Limit,
                at,
                format!("{n} cells, past the limit of {}", self.limits.cells),
            ));
        }
        let most = 2 * (n as usize + 1);
        self.room(Complex::bytes(most, most) as u128, at)?;
        self.tick(n as u64 / 4, at)
    }
}

fn more(args: &[Value], x: Value) -> Vec<Value> {
    let mut v = Vec::with_capacity(args.len() + 1);
    v.extend(args.iter().cloned());
    v.push(x);
    v
}

#[cold]
#[inline(never)]
fn too_deep(at: Span, depth: u32) -> Error {
    Error::new(
        ErrorKind::Limit,
        at,
        format!("calls nested more than {depth} deep: endless recursion?"),
    )
}

#[cold]
#[inline(never)]
fn not_applicable(at: Span, f: &Value, x: &Value) -> R<Value> {
    type_error(
        at,
        format!(
            "{f} is applied to {x}, but it is {}, not a function",
            f.kind()
        ),
    )
}

/// The items of `v` where it is a sum and `op` is `+` (a product and `*`): they join the items of
/// a sum (product) it is part of.
fn same_lift(op: Arith, v: &Value) -> Option<&[Value]> {
    match v {
        Value::Fun(f) if matches!(op, Arith::Add | Arith::Mul) => match &**f {
            Fun::Lift(inner, xs) if *inner == op => Some(xs),
            _ => None,
        },
        _ => None,
    }
}

/// `v` if it is a function; else a type error saying where it was wanted.
fn function(v: Value, at: Span, what: &str) -> R<Value> {
    match v {
        Value::Fun(_) => Ok(v),
        Value::Seq(ref s) if s.iter().all(|f| matches!(f, Value::Fun(_))) => type_error(
            at,
            format!(
                "{what} must be a function, not a sequence of {} functions: write CONS:… or \
                 [ … ] to make one function of them",
                s.len()
            ),
        ),
        other => type_error(
            at,
            format!("{what} must be a function, not {} ({other})", other.kind()),
        ),
    }
}

/// `b ** e`: by repeated multiplication for a whole exponent up to 64 (the Bernstein and Hermite
/// bases' `u ** i`, several times faster than `powf`), else `powf`. The interpreter and `MAP`'s
/// compiler both use this one, so they agree to the bit.
#[inline]
pub(crate) fn power(b: f64, e: f64) -> f64 {
    if e.fract() == 0.0 && e.abs() <= 64.0 {
        // Squaring and multiplying, inline (`powi` is a call into the runtime).
        let (mut n, mut base, mut r) = (e.abs() as u32, b, 1.0);
        loop {
            if n & 1 == 1 {
                r *= base;
            }
            n >>= 1;
            if n == 0 {
                break;
            }
            base *= base;
        }
        if e < 0.0 { 1.0 / r } else { r }
    } else {
        b.powf(e)
    }
}

/// A built-in value by upper-case name.
fn builtin(key: &str) -> Option<Value> {
    match key {
        "PI" => return Some(Value::Num(std::f64::consts::PI)),
        "TRUE" => return Some(Value::Bool(true)),
        "FALSE" => return Some(Value::Bool(false)),
        _ => {}
    }
    if let Some(digits) = key.strip_prefix('S')
        && !digits.is_empty()
        && digits.len() <= 4
        && digits.bytes().all(|b| b.is_ascii_digit())
        && !digits.starts_with('0')
    {
        return digits
            .parse()
            .ok()
            .map(|i| Value::fun(Fun::Prim(Prim::Select(i))));
    }
    NAMES
        .iter()
        .find(|(n, _)| *n == key)
        .map(|(_, p)| Value::fun(Fun::Prim(*p)))
}

/// An error inside the prelude's `def`, placed at the script's call of it (apart, so that
/// [`Interp::call_def`]'s frame, which recursion stacks, stays small).
#[cold]
#[inline(never)]
fn placed_at_call(mut e: Error, def: &Def, at: Span) -> Error {
    e.span = at;
    e.message = format!("in the prelude's `{}`: {}", def.name, e.message);
    e
}

/// Levenshtein distance, for "did you mean".
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (row[j + 1] + 1)
                .min(row[j] + 1)
                .min(prev + usize::from(ca != cb));
            prev = cur;
        }
    }
    row[b.len()]
}
