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

/// Points evaluated together, one operation at a time over all of them.
pub(crate) const LANES: usize = 64;

/// The most operations of a kernel; a larger map is interpreted.
const MAX_OPS: usize = 100_000;

#[derive(Clone, Copy, Debug)]
enum Op {
    Const(f64),
    Coord(usize),
    /// The interpreter's fold of `op` over slots `[start, start + len)` of `args`.
    Fold(Arith, u32, u32),
    /// The same of two slots (most operations), without the indirection.
    Two(Arith, u32, u32),
    Math(fn(f64) -> f64, u32),
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
    /// Shapes by id, and ids by shape: a node's result is keyed by its input's id, so that a
    /// wide input is hashed once, not at every use.
    shapes: Vec<Shape>,
    ids: HashMap<Shape, u32>,
    memo: HashMap<(usize, u32), u32>,
    consts: HashMap<u64, u32>,
    depth: u32,
    max_depth: u32,
    /// Work left (operations, and items of shapes made), from the run's step budget.
    budget: u64,
    /// Bytes left, from the run's memory budget: for the compiler's tables and the kernel's
    /// slots (an operation's slot holds [`LANES`] numbers).
    room: u64,
}

/// The widest point a kernel takes.
const MAX_DIM: usize = 4096;

impl Kernel {
    /// The kernel of `f` on points of `dim` coordinates, if `f` is made of what it compiles,
    /// nests at most `max_depth` deep (the interpreter's call limit) and compiles within `budget`
    /// units of work and `room` bytes (its tables, and the kernel with its slots).
    pub(crate) fn compile(
        f: &Value,
        dim: usize,
        max_depth: u32,
        budget: u64,
        room: u64,
    ) -> Option<Kernel> {
        if dim > MAX_DIM {
            return None;
        }
        let mut c = Compiler {
            ops: Vec::new(),
            args: Vec::new(),
            shapes: Vec::new(),
            ids: HashMap::new(),
            memo: HashMap::new(),
            consts: HashMap::new(),
            depth: 0,
            max_depth,
            budget,
            room,
        };
        let coords = (0..dim)
            .map(|i| c.push(Op::Coord(i)))
            .collect::<Option<Vec<_>>>()?;
        let input = c.intern(Shape::Vector(coords))?;
        let output = c.value(f, input)?;
        let output = c.shapes[output as usize].clone();
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

    /// Bytes that the kernel holds while `MAP` runs it: its operations and their arguments, its
    /// output, and the slots and images of a block of points.
    pub(crate) fn bytes(&self) -> usize {
        let output = match &self.output {
            Shape::Scalar(_) => 0,
            Shape::Vector(v) => v.capacity(),
        };
        (self.ops.capacity() * size_of::<Op>())
            + (self.args.capacity() + output) * size_of::<u32>()
            + (self.ops.len() + self.out_dim()) * LANES * size_of::<f64>()
            + LANES
    }

    /// Coordinates of each image.
    pub(crate) fn out_dim(&self) -> usize {
        match &self.output {
            Shape::Scalar(_) => 1,
            Shape::Vector(v) => v.len(),
        }
    }

    /// The images of up to [`LANES`] points (`points`, `dim` coordinates each) into `out`
    /// ([`Kernel::out_dim`] each), one operation at a time over all of them; `bad[l]` is set
    /// where a value on the way for point `l` is not finite (the caller asks the interpreter,
    /// which says why).
    pub(crate) fn eval_block(
        &self,
        points: &[f64],
        dim: usize,
        slots: &mut Vec<f64>,
        out: &mut Vec<f64>,
        bad: &mut Vec<bool>,
    ) {
        let count = points.len().checked_div(dim).unwrap_or(0).min(LANES);
        slots.clear();
        slots.resize(self.ops.len() * LANES, 0.0);
        bad.clear();
        bad.resize(count, false);
        for (k, op) in self.ops.iter().enumerate() {
            let (before, rest) = slots.split_at_mut(k * LANES);
            let dst = &mut rest[..count];
            let lane = |s: u32| &before[s as usize * LANES..s as usize * LANES + count];
            match *op {
                Op::Const(c) => dst.fill(c),
                Op::Coord(i) => {
                    for (l, x) in dst.iter_mut().enumerate() {
                        *x = points[l * dim + i];
                    }
                }
                Op::Two(op, a, b) => {
                    let (xa, xb) = (lane(a), lane(b));
                    for l in 0..count {
                        dst[l] = fold(op, [xa[l], xb[l]].into_iter());
                    }
                }
                Op::Fold(op, start, len) => {
                    let args = &self.args[start as usize..(start + len) as usize];
                    for (l, x) in dst.iter_mut().enumerate() {
                        *x = fold(op, args.iter().map(|&a| before[a as usize * LANES + l]));
                    }
                }
                Op::Math(f, a) => {
                    let xa = lane(a);
                    for l in 0..count {
                        dst[l] = f(xa[l]);
                    }
                }
            }
            for (b, x) in bad.iter_mut().zip(dst.iter()) {
                *b |= !x.is_finite();
            }
        }
        out.clear();
        for l in 0..count {
            match &self.output {
                Shape::Scalar(s) => out.push(slots[*s as usize * LANES + l]),
                Shape::Vector(v) => out.extend(v.iter().map(|&s| slots[s as usize * LANES + l])),
            }
        }
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
        Arith::Pow => xs
            .rev()
            .reduce(|e, b| crate::eval::power(b, e))
            .unwrap_or(f64::NAN),
    }
}

/// Bytes of an entry of a hash table of `K` to `V`, with room for the table's spare capacity
/// (a table grows by doubling, to at most 8/7 of its entries when full).
const fn entry_bytes<K, V>() -> u64 {
    (2 * (size_of::<K>() + size_of::<V>()) + 2) as u64
}

impl Compiler {
    fn spend(&mut self, work: usize) -> Option<()> {
        self.budget = self.budget.checked_sub(work as u64)?;
        (self.ops.len() <= MAX_OPS).then_some(())
    }

    /// Counts `bytes` more against the room left; `None` past it.
    fn hold(&mut self, bytes: u64) -> Option<()> {
        self.room = self.room.checked_sub(bytes)?;
        Some(())
    }

    fn push(&mut self, op: Op) -> Option<u32> {
        self.spend(1)?;
        // The operation (twice, for the vector's spare capacity) and its slot in a block.
        self.hold((2 * size_of::<Op>() + LANES * size_of::<f64>()) as u64)?;
        self.ops.push(op);
        Some((self.ops.len() - 1) as u32)
    }

    fn intern(&mut self, shape: Shape) -> Option<u32> {
        if let Shape::Vector(v) = &shape {
            self.spend(v.len())?;
        }
        if let Some(&id) = self.ids.get(&shape) {
            return Some(id);
        }
        // Held twice, in `shapes` and as a key of `ids`.
        let items = match &shape {
            Shape::Scalar(_) => 0,
            Shape::Vector(v) => v.len(),
        };
        self.hold(
            2 * (items * size_of::<u32>()) as u64
                + 2 * size_of::<Shape>() as u64
                + entry_bytes::<Shape, u32>(),
        )?;
        self.shapes.push(shape.clone());
        let id = (self.shapes.len() - 1) as u32;
        self.ids.insert(shape, id);
        Some(id)
    }

    fn scalar(&mut self, slot: u32) -> Option<u32> {
        self.intern(Shape::Scalar(slot))
    }

    fn constant(&mut self, c: f64) -> Option<u32> {
        if let Some(&s) = self.consts.get(&c.to_bits()) {
            return Some(s);
        }
        let s = self.push(Op::Const(c))?;
        self.hold(entry_bytes::<u64, u32>())?;
        self.consts.insert(c.to_bits(), s);
        Some(s)
    }

    /// The interpreter's `op` of the slots, as a shape.
    fn fold(&mut self, op: Arith, slots: &[u32]) -> Option<u32> {
        // The interpreter refuses `-`, `/` and `**` of nothing.
        if slots.is_empty() && !matches!(op, Arith::Add | Arith::Mul) {
            return None;
        }
        self.spend(slots.len())?;
        let slot = if let [a, b] = *slots {
            self.push(Op::Two(op, a, b))?
        } else {
            let start = self.args.len() as u32;
            self.hold(2 * size_of_val(slots) as u64)?;
            self.args.extend_from_slice(slots);
            self.push(Op::Fold(op, start, slots.len() as u32))?
        };
        self.scalar(slot)
    }

    /// A value standing for itself: a number, or a sequence of numbers.
    fn data(&mut self, v: &Value) -> Option<u32> {
        match v {
            Value::Num(c) => {
                let s = self.constant(*c)?;
                self.scalar(s)
            }
            Value::Seq(items) => {
                let slots = items
                    .iter()
                    .map(|x| x.as_num().and_then(|c| self.constant(c)))
                    .collect::<Option<_>>()?;
                self.intern(Shape::Vector(slots))
            }
            _ => None,
        }
    }

    /// The slot of a scalar shape.
    fn slot(&self, shape: u32) -> Option<u32> {
        match self.shapes[shape as usize] {
            Shape::Scalar(s) => Some(s),
            Shape::Vector(_) => None,
        }
    }

    /// `f` applied to the shape `input`.
    fn value(&mut self, f: &Value, input: u32) -> Option<u32> {
        let Value::Fun(fun) = f else {
            return None;
        };
        let key = (Rc::as_ptr(fun) as usize, input);
        if let Some(&s) = self.memo.get(&key) {
            return Some(s);
        }
        // As deep as the interpreter's calls may go, and no deeper.
        if self.depth >= self.max_depth {
            return None;
        }
        self.depth += 1;
        let out = self.fun(fun, input);
        self.depth -= 1;
        let out = out?;
        self.hold(entry_bytes::<(usize, u32), u32>())?;
        self.memo.insert(key, out);
        Some(out)
    }

    fn fun(&mut self, fun: &Fun, input: u32) -> Option<u32> {
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
                let x = self.slot(input)?;
                let a = self.data(a)?;
                let a = self.slot(a)?;
                let pair = self.intern(Shape::Vector(vec![x, a]))?;
                self.value(f, pair)
            }
            Fun::Partial(Prim::AA, args) => {
                let Shape::Vector(xs) = self.shapes[input as usize].clone() else {
                    return None;
                };
                let f = args.first()?;
                let mut out = Vec::with_capacity(xs.len());
                for x in xs {
                    let item = self.scalar(x)?;
                    let r = self.value(f, item)?;
                    out.push(self.slot(r)?);
                }
                self.intern(Shape::Vector(out))
            }
            Fun::Partial(..) | Fun::User(..) => None,
            Fun::Compose(fs) => {
                let mut v = input;
                for f in fs.iter().rev() {
                    v = self.value(f, v)?;
                }
                Some(v)
            }
            Fun::Cons(fs) => {
                let mut out = Vec::with_capacity(fs.len());
                for f in fs {
                    let r = self.value(f, input)?;
                    out.push(self.slot(r)?);
                }
                self.intern(Shape::Vector(out))
            }
            Fun::Lift(op, items) => {
                let mut slots = Vec::with_capacity(items.len());
                for item in items {
                    let s = match item {
                        Value::Fun(_) => {
                            let r = self.value(item, input)?;
                            self.slot(r)?
                        }
                        Value::Num(c) => self.constant(*c)?,
                        _ => return None,
                    };
                    slots.push(s);
                }
                self.fold(*op, &slots)
            }
        }
    }

    fn select(&mut self, i: f64, input: u32) -> Option<u32> {
        let Shape::Vector(xs) = &self.shapes[input as usize] else {
            return None;
        };
        let k = i as usize;
        let slot = (i.fract() == 0.0 && k >= 1)
            .then(|| xs.get(k - 1).copied())
            .flatten()?;
        self.scalar(slot)
    }

    fn prim(&mut self, p: Prim, input: u32) -> Option<u32> {
        match p {
            Prim::Id => Some(input),
            Prim::Select(i) => self.select(f64::from(i), input),
            Prim::Arith(op) => match &self.shapes[input as usize] {
                Shape::Vector(xs) => {
                    let xs = xs.clone();
                    self.fold(op, &xs)
                }
                Shape::Scalar(x) if op == Arith::Sub => {
                    let x = *x;
                    self.fold(Arith::Sub, &[x])
                }
                Shape::Scalar(_) => None,
            },
            p => {
                let f = p.unary_math()?;
                let x = self.slot(input)?;
                let slot = self.push(Op::Math(f, x))?;
                self.scalar(slot)
            }
        }
    }
}
