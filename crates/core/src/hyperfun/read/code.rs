//! The compiled form: each body's flat list of stack-machine operations over numbered cells, and
//! the emitter that turns a parsed expression into operations in HyperFun's order of evaluation.
//!
//! HyperFun evaluates every operator's right operand before its left one and a call's arguments
//! from the last to the first (its code is postfix and its evaluator walks it backwards). The
//! emitter writes the right operand's operations first, so the machine runs them straight through
//! and errors (and the library's in-place changes) happen in HyperFun's order. The parser keeps an
//! expression as a tree of [`Node`]s in an arena and the emitter walks it with a stack of its own,
//! so a chain of ten thousand `+` compiles without deep recursion.

use alloc::vec::Vec;

use super::library::{Arr, F1, F2, Lib};
use super::scan::Pos;

/// The binary operators of expressions and conditions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Bin {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    /// `&` and `@`: the R-function intersection.
    And,
    /// `|`: the R-function union.
    Or,
    /// `\`: the R-function difference.
    Minus,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Equal,
    NotEqual,
    /// `and` of a condition.
    Both,
    /// `or` of a condition.
    Either,
}

/// One operation of the machine. Each has a place in the text for its errors (the body's `pos`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    /// Pushes a number.
    Const(f64),
    /// Pushes a scalar variable (error: "Not initialized variable").
    Var(u32),
    /// Pushes an `x`, `a` or `s` item at a known index (always assigned).
    Cell(u32),
    /// Pushes a declared array's item at a known index (error: unassigned).
    Item(u32),
    /// Pops an index, pushes that item of `x`, `a` or `s` (error: out of range).
    Index {
        base: u32,
        len: u32,
    },
    /// Pops an index, pushes that item of a declared array (errors: out of range, here; unassigned,
    /// at `name`).
    Elem {
        base: u32,
        len: u32,
        name: Pos,
    },
    /// `-v` (and `~v`).
    Neg,
    /// `not v`.
    Not,
    /// Pops the left operand, then the right one, pushes the result.
    Bin(Bin),
    F1(F1),
    /// Pops the first argument, then the second.
    F2(F2),
    /// Errs if an item of an array argument is unassigned ("Some items of array are unassigned").
    Check {
        base: u32,
        len: u32,
    },
    /// Calls the body's library call site: pops its real arguments (first on top), pushes the value.
    Lib(u32),
    /// Calls the body's body call site, pushes its value.
    Call(u32),
    /// Pops into a scalar variable.
    Store(u32),
    /// Pops an index of an element assignment, checks it against `len`, pushes it as an integer.
    Slot {
        len: u32,
    },
    /// Pops a value, then an index from [`Op::Slot`], stores the value there.
    StoreElem {
        base: u32,
        tracked: bool,
    },
    /// A whole-array assignment: `len` constants from the body's table at `from`.
    Fill {
        base: u32,
        len: u32,
        from: u32,
        tracked: bool,
    },
    Jump(u32),
    /// Pops a condition, jumps when it is false (`|v| < 1e-6`).
    JumpUnless(u32),
    /// Pops the body's value and ends it.
    Return,
}

impl Op {
    /// How the operation changes the depth of the value stack.
    fn effect(self, lib_reals: impl Fn(u32) -> usize) -> isize {
        match self {
            Op::Const(_) | Op::Var(_) | Op::Cell(_) | Op::Item(_) | Op::Call(_) => 1,
            Op::Index { .. }
            | Op::Elem { .. }
            | Op::Neg
            | Op::Not
            | Op::F1(_)
            | Op::Check { .. }
            | Op::Slot { .. }
            | Op::Fill { .. }
            | Op::Jump(_) => 0,
            Op::Bin(_) | Op::F2(_) | Op::Store(_) | Op::JumpUnless(_) | Op::Return => -1,
            Op::StoreElem { .. } => -2,
            Op::Lib(site) => 1 - lib_reals(site) as isize,
        }
    }
}

/// A library call: the function and its array arguments in source order.
#[derive(Clone, Debug)]
pub(crate) struct LibSite {
    pub(crate) lib: Lib,
    pub(crate) arrays: Vec<Arr>,
    pub(crate) reals: usize,
}

/// A call of an earlier body: its arrays `x`, `a`, `s` from the caller's, whether each is a
/// declared array (whose items may be unassigned), and where HyperFun reports an unassigned item
/// of each (one argument later than the argument itself, its quirk).
#[derive(Clone, Debug)]
pub(crate) struct CallSite {
    pub(crate) callee: u32,
    pub(crate) args: [Arr; 3],
    pub(crate) tracked: [bool; 3],
    pub(crate) report: [Pos; 3],
}

/// A compiled body.
#[derive(Clone, Debug)]
pub(crate) struct Body {
    /// The lower-cased name.
    pub(crate) name: alloc::string::String,
    pub(crate) x: Arr,
    pub(crate) a: Arr,
    pub(crate) s: Arr,
    pub(crate) code: Vec<Op>,
    /// Where each operation's errors are reported.
    pub(crate) pos: Vec<Pos>,
    /// Whole-array assignments' constants.
    pub(crate) consts: Vec<f64>,
    pub(crate) libs: Vec<LibSite>,
    pub(crate) calls: Vec<CallSite>,
    /// The value stack's depth at the operation being emitted, and its most.
    depth: isize,
    pub(crate) max_depth: usize,
}

impl Body {
    pub(crate) fn new(name: alloc::string::String) -> Self {
        Self {
            name,
            x: Arr::default(),
            a: Arr::default(),
            s: Arr::default(),
            code: Vec::new(),
            pos: Vec::new(),
            consts: Vec::new(),
            libs: Vec::new(),
            calls: Vec::new(),
            depth: 0,
            max_depth: 0,
        }
    }

    /// Appends `op`, reported at `pos`; returns its index.
    pub(crate) fn push(&mut self, op: Op, pos: Pos) -> u32 {
        let libs = &self.libs;
        self.depth += op.effect(|site| libs[site as usize].reals);
        self.max_depth = self.max_depth.max(self.depth.max(0) as usize);
        self.code.push(op);
        self.pos.push(pos);
        (self.code.len() - 1) as u32
    }

    /// The index the next operation will have.
    pub(crate) fn here(&self) -> u32 {
        self.code.len() as u32
    }

    /// Points the jump at `at` to `to`.
    pub(crate) fn patch(&mut self, at: u32, to: u32) {
        match &mut self.code[at as usize] {
            Op::Jump(t) | Op::JumpUnless(t) => *t = to,
            _ => {}
        }
    }
}

/// An array argument of a library call or an item read: the array and whether it is a declared
/// array (rather than `x`, `a` or `s`, whose items are always assigned).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ArrRef {
    pub(crate) arr: Arr,
    pub(crate) tracked: bool,
}

/// A parsed expression node.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    Num(f64),
    Var(u32),
    Elem {
        arr: ArrRef,
        index: u32,
        name: Pos,
    },
    Neg(u32),
    Not(u32),
    Bin(Bin, u32, u32),
    F1(F1, u32),
    F2(F2, u32, u32),
    /// A library call: its site and its arguments, `args[from..to]` of the parser's list.
    Lib {
        site: u32,
        from: u32,
        to: u32,
    },
    Call(u32),
}

/// A node: what it is, where its operation reports errors, and where HyperFun reports an index
/// error when the node is an index (the place of the first operation it compiles to).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub(crate) kind: Kind,
    pub(crate) pos: Pos,
    pub(crate) first: Pos,
}

/// A library call's argument.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Arg {
    Real(u32),
    Array(ArrRef, Pos),
}

/// Writes the operations of the expression `root` into `body`, in HyperFun's order of evaluation.
pub(crate) fn emit(body: &mut Body, nodes: &[Node], args: &[Arg], root: u32) {
    enum Task {
        Visit(u32),
        Emit(Op, Pos),
    }
    let mut tasks = alloc::vec![Task::Visit(root)];
    while let Some(task) = tasks.pop() {
        let id = match task {
            Task::Emit(op, pos) => {
                body.push(op, pos);
                continue;
            }
            Task::Visit(id) => id,
        };
        let node = nodes[id as usize];
        let pos = node.pos;
        match node.kind {
            Kind::Num(v) => {
                body.push(Op::Const(v), pos);
            }
            Kind::Var(cell) => {
                body.push(Op::Var(cell), pos);
            }
            Kind::Neg(a) => match nodes[a as usize].kind {
                // −c is exact: the constant, negated once here.
                Kind::Num(v) => {
                    body.push(Op::Const(-v), pos);
                }
                _ => tasks.extend([Task::Emit(Op::Neg, pos), Task::Visit(a)]),
            },
            Kind::Not(a) => tasks.extend([Task::Emit(Op::Not, pos), Task::Visit(a)]),
            Kind::Bin(op, l, r) => {
                tasks.extend([Task::Emit(Op::Bin(op), pos), Task::Visit(l), Task::Visit(r)]);
            }
            Kind::F1(f, a) => tasks.extend([Task::Emit(Op::F1(f), pos), Task::Visit(a)]),
            Kind::F2(f, a, b) => {
                tasks.extend([Task::Emit(Op::F2(f), pos), Task::Visit(a), Task::Visit(b)]);
            }
            Kind::Elem { arr, index, name } => {
                let Arr { base, len } = arr.arr;
                // A constant index in range needs no check at run time.
                if let Kind::Num(v) = nodes[index as usize].kind {
                    let i = super::run::hf_round(v);
                    if i >= 1 && i as u32 <= len {
                        let cell = base + i as u32 - 1;
                        match arr.tracked {
                            true => body.push(Op::Item(cell), name),
                            false => body.push(Op::Cell(cell), name),
                        };
                        continue;
                    }
                }
                let op = match arr.tracked {
                    true => Op::Elem { base, len, name },
                    false => Op::Index { base, len },
                };
                tasks.extend([Task::Emit(op, pos), Task::Visit(index)]);
            }
            Kind::Lib { site, from, to } => {
                tasks.push(Task::Emit(Op::Lib(site), pos));
                for arg in &args[from as usize..to as usize] {
                    match *arg {
                        Arg::Real(a) => tasks.push(Task::Visit(a)),
                        Arg::Array(a, at) if a.tracked => {
                            let Arr { base, len } = a.arr;
                            tasks.push(Task::Emit(Op::Check { base, len }, at));
                        }
                        Arg::Array(..) => {}
                    }
                }
            }
            Kind::Call(site) => {
                body.push(Op::Call(site), pos);
            }
        }
    }
}
