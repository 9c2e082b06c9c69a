//! `MAP`'s fast path. A map built of built-ins (selectors, constants, `ID`, arithmetic between
//! functions, composition, `CONS`, `C`, the math functions), as every map of the paper is by the
//! time `MAP` applies it, is compiled once into straight-line arithmetic on `f64`: one slot per
//! distinct node and input, so that what the script shares (Script 4.4's Bernstein basis, used by
//! every coordinate) is computed once per point. The arithmetic is the interpreter's, operation
//! for operation, so the points are the same to the bit; a point where anything is not finite is
//! evaluated again by the interpreter, which gives the error it would have given.

use std::collections::HashMap;
use std::rc::Rc;

use crate::parse::Arith;
use crate::value::{Fun, Prim, Value};

/// The most operations of a kernel; a larger map is interpreted.
const MAX_OPS: usize = 100_000;

#[derive(Clone, Copy, Debug)]
enum Op {
    Const(f64),
    Coord(usize),
    /// The interpreter's fold of `op` over slots `[start, start + len)` of `args`.
    Fold(Arith, u32, u32),
    Math(Prim, u32),
}

/// What a compiled node gives: one number (a slot) or a sequence of numbers.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Shape {
    Scalar(u32),
    Vector(Vec<u32>),
}

/// A compiled map from points of `dim` coordinates.
pub(crate) struct Kernel {
    ops: Vec<Op>,
    args: Vec<u32>,
    output: Shape,
}

struct Compiler {
    ops: Vec<Op>,
    args: Vec<u32>,
    memo: HashMap<(usize, Shape), Shape>,
    consts: HashMap<u64, u32>,
}

impl Kernel {
    /// The kernel of `f` on points of `dim` coordinates, if `f` is made of what it compiles.
    pub(crate) fn compile(f: &Value, dim: usize) -> Option<Kernel> {
        let mut c = Compiler {
            ops: Vec::new(),
            args: Vec::new(),
            memo: HashMap::new(),
            consts: HashMap::new(),
        };
        let input = Shape::Vector((0..dim).map(|i| c.push(Op::Coord(i))).collect());
        let output = c.value(f, &input)?;
        if output == Shape::Vector(Vec::new()) {
            return None; // no coordinates: the interpreter says why
        }
        Some(Kernel {
            ops: c.ops,
            args: c.args,
            output,
        })
    }

    /// Operations per point.
    pub(crate) fn len(&self) -> usize {
        self.ops.len()
    }

    /// The image of `point` into `out`; false where a value on the way is not finite (the caller
    /// asks the interpreter, which says why).
    pub(crate) fn eval(&self, point: &[f64], slots: &mut Vec<f64>, out: &mut Vec<f64>) -> bool {
        slots.clear();
        let mut finite = true;
        for op in &self.ops {
            let x = match *op {
                Op::Const(c) => c,
                Op::Coord(i) => point[i],
                Op::Fold(op, start, len) => {
                    let args = &self.args[start as usize..(start + len) as usize];
                    fold(op, args.iter().map(|&a| slots[a as usize]))
                }
                Op::Math(p, a) => math(p, slots[a as usize]),
            };
            finite &= x.is_finite();
            slots.push(x);
        }
        out.clear();
        match &self.output {
            Shape::Scalar(s) => out.push(slots[*s as usize]),
            Shape::Vector(v) => out.extend(v.iter().map(|&s| slots[s as usize])),
        }
        finite
    }
}

/// The interpreter's arithmetic on numbers (`Interp::arith`), for nonempty `xs`.
fn fold(op: Arith, mut xs: impl DoubleEndedIterator<Item = f64> + Clone) -> f64 {
    match op {
        Arith::Add => xs.sum(),
        Arith::Mul => xs.product(),
        Arith::Sub => {
            let a = xs.next().unwrap_or(f64::NAN);
            match xs.clone().next() {
                None => -a,
                Some(_) => xs.fold(a, |s, b| s - b),
            }
        }
        Arith::Div => {
            let a = xs.next().unwrap_or(f64::NAN);
            match xs.clone().next() {
                None => 1.0 / a,
                Some(_) => xs.fold(a, |s, b| if b == 0.0 { f64::NAN } else { s / b }),
            }
        }
        Arith::Pow => xs.rev().reduce(|e, b| b.powf(e)).unwrap_or(f64::NAN),
    }
}

fn math(p: Prim, x: f64) -> f64 {
    match p {
        Prim::Sin => x.sin(),
        Prim::Cos => x.cos(),
        Prim::Tan => x.tan(),
        Prim::Asin => x.asin(),
        Prim::Acos => x.acos(),
        Prim::Atan => x.atan(),
        Prim::Sqrt => x.sqrt(),
        Prim::Exp => x.exp(),
        Prim::Ln => x.ln(),
        Prim::Abs => x.abs(),
        _ => f64::NAN,
    }
}

fn is_math(p: Prim) -> bool {
    matches!(
        p,
        Prim::Sin
            | Prim::Cos
            | Prim::Tan
            | Prim::Asin
            | Prim::Acos
            | Prim::Atan
            | Prim::Sqrt
            | Prim::Exp
            | Prim::Ln
            | Prim::Abs
    )
}

impl Compiler {
    fn push(&mut self, op: Op) -> u32 {
        self.ops.push(op);
        (self.ops.len() - 1) as u32
    }

    fn constant(&mut self, c: f64) -> u32 {
        if let Some(&s) = self.consts.get(&c.to_bits()) {
            return s;
        }
        let s = self.push(Op::Const(c));
        self.consts.insert(c.to_bits(), s);
        s
    }

    fn fold(&mut self, op: Arith, slots: &[u32]) -> Option<Shape> {
        // The interpreter refuses `-`, `/` and `**` of nothing.
        if slots.is_empty() && !matches!(op, Arith::Add | Arith::Mul) {
            return None;
        }
        let start = self.args.len() as u32;
        self.args.extend_from_slice(slots);
        Some(Shape::Scalar(self.push(Op::Fold(
            op,
            start,
            slots.len() as u32,
        ))))
    }

    /// A value standing for itself: a number, or a sequence of numbers.
    fn data(&mut self, v: &Value) -> Option<Shape> {
        match v {
            Value::Num(c) => Some(Shape::Scalar(self.constant(*c))),
            Value::Seq(items) => Some(Shape::Vector(
                items
                    .iter()
                    .map(|x| x.as_num().map(|c| self.constant(c)))
                    .collect::<Option<_>>()?,
            )),
            _ => None,
        }
    }

    /// `f` applied to `input`.
    fn value(&mut self, f: &Value, input: &Shape) -> Option<Shape> {
        let Value::Fun(fun) = f else {
            return None;
        };
        if self.ops.len() > MAX_OPS {
            return None;
        }
        let key = (Rc::as_ptr(fun) as usize, input.clone());
        if let Some(s) = self.memo.get(&key) {
            return Some(s.clone());
        }
        let out = self.fun(fun, input)?;
        self.memo.insert(key, out.clone());
        Some(out)
    }

    fn fun(&mut self, fun: &Fun, input: &Shape) -> Option<Shape> {
        match fun {
            Fun::Prim(p) => self.prim(*p, input),
            Fun::Partial(Prim::K, args) => self.data(args.first()?),
            Fun::Partial(Prim::Sel, args) => {
                let i = args.first()?.as_num()?;
                self.select(i, input)
            }
            Fun::Partial(Prim::C, args) => {
                // C:f:a:x is f:<x, a>.
                let [f, a] = args.as_slice() else {
                    return None;
                };
                let Shape::Scalar(x) = input else {
                    return None;
                };
                let Shape::Scalar(a) = self.data(a)? else {
                    return None;
                };
                self.value(f, &Shape::Vector(vec![*x, a]))
            }
            Fun::Partial(Prim::AA, args) => {
                let Shape::Vector(xs) = input else {
                    return None;
                };
                let f = args.first()?;
                let mut out = Vec::with_capacity(xs.len());
                for &x in xs {
                    let Shape::Scalar(s) = self.value(f, &Shape::Scalar(x))? else {
                        return None;
                    };
                    out.push(s);
                }
                Some(Shape::Vector(out))
            }
            Fun::Partial(..) | Fun::User(..) => None,
            Fun::Compose(fs) => {
                let mut v = input.clone();
                for f in fs.iter().rev() {
                    v = self.value(f, &v)?;
                }
                Some(v)
            }
            Fun::Cons(fs) => {
                let mut out = Vec::with_capacity(fs.len());
                for f in fs {
                    let Shape::Scalar(s) = self.value(f, input)? else {
                        return None;
                    };
                    out.push(s);
                }
                Some(Shape::Vector(out))
            }
            Fun::Lift(op, items) => {
                let mut slots = Vec::with_capacity(items.len());
                for item in items {
                    let shape = match item {
                        Value::Fun(_) => self.value(item, input)?,
                        Value::Num(c) => Shape::Scalar(self.constant(*c)),
                        _ => return None,
                    };
                    let Shape::Scalar(s) = shape else {
                        return None;
                    };
                    slots.push(s);
                }
                self.fold(*op, &slots)
            }
        }
    }

    fn select(&mut self, i: f64, input: &Shape) -> Option<Shape> {
        let Shape::Vector(xs) = input else {
            return None;
        };
        let k = i as usize;
        (i.fract() == 0.0 && k >= 1)
            .then(|| xs.get(k - 1).map(|&s| Shape::Scalar(s)))
            .flatten()
    }

    fn prim(&mut self, p: Prim, input: &Shape) -> Option<Shape> {
        match (p, input) {
            (Prim::Id, _) => Some(input.clone()),
            (Prim::Select(i), _) => self.select(f64::from(i), input),
            (Prim::Arith(op), Shape::Vector(xs)) => {
                let xs = xs.clone();
                self.fold(op, &xs)
            }
            (Prim::Arith(Arith::Sub), Shape::Scalar(x)) => {
                let x = *x;
                self.fold(Arith::Sub, &[x])
            }
            (p, Shape::Scalar(x)) if is_math(p) => {
                let x = *x;
                Some(Shape::Scalar(self.push(Op::Math(p, x))))
            }
            _ => None,
        }
    }
}
