//! What a leaf of a tree is, in its own coordinates: the primitives' formulas of DESIGN §5 and
//! their gradients, and the Bézier and piecewise leaves, regular ones with their `ξ` nets kept
//! apart for the interval bounds.

use alloc::boxed::Box;
use alloc::vec::Vec;

use crate::dim::{Dim, Dimension};
use crate::inverse::Method;
use crate::math::sqrt;
use crate::rfunc::intersect;
use crate::solid::Solid;
use crate::tensor::Tensor;

/// What a leaf is, in its own coordinates.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Shape<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    /// A patch or volume solid; a regular one keeps its `ξ` net apart, to evaluate `ξ` alone.
    Bezier(Box<Solid<D>>, Option<Box<Regular<D>>>),
    /// `radius² − ‖p − center‖²`.
    Ball { center: [f64; D], radius: f64 },
    /// `s_0 & s_1 (& s_2)`, `s_i = (p_i − min_i)(max_i − p_i)`.
    Box { min: [f64; D], max: [f64; D] },
    /// `radius²` less the squared distance from the line along axis `axis` through `center`.
    Cylinder {
        center: [f64; D],
        axis: usize,
        radius: f64,
    },
    /// `minor² − (√(a² + b²) − major)² − c²`.
    Torus {
        center: [f64; D],
        axis: usize,
        major: f64,
        minor: f64,
    },
    /// `offset − normal · p`.
    Half { normal: [f64; D], offset: f64 },
    /// A piecewise solid; a regular one keeps its cells' `ξ` nets apart, for bounds.
    Piecewise(
        Box<crate::piecewise::Piecewise<D>>,
        Option<Box<RegularCells<D>>>,
    ),
    /// A HyperFun program cut by its box.
    Hyperfun(Box<HfLeaf<D>>),
}

impl<const D: usize> Shape<D>
where
    Dim<D>: Dimension<D>,
{
    /// `f` at `p` (in the leaf's coordinates) and, for a Bézier leaf, its preimages and whether
    /// the query ran out of its work budget.
    pub(super) fn eval(&self, p: [f64; D]) -> (f64, usize, bool) {
        self.eval_by(p, Method::Fast)
    }

    /// [`Self::eval`] with the preimages of a space-mapped leaf found by `method`.
    pub(super) fn eval_by(&self, p: [f64; D], method: Method) -> (f64, usize, bool) {
        let (f, n) = match self {
            Self::Bezier(_, Some(r)) => {
                let t = r.scaled(p);
                let inside = t.iter().all(|&x| (0.0..=1.0).contains(&x));
                return (
                    crate::rfunc::clip(r.xi.eval(t), t),
                    usize::from(inside),
                    false,
                );
            }
            Self::Bezier(solid, None) => {
                let v = solid.evaluate(Dim::<D>::point(p), method);
                return (v.f, v.preimages, v.exhausted);
            }
            Self::Piecewise(solid, _) => {
                let v = solid.evaluate(Dim::<D>::point(p), method);
                return (v.f, v.preimages, v.exhausted);
            }
            Self::Hyperfun(h) => {
                let (f, exhausted) = h.eval(p);
                return (f, 0, exhausted);
            }
            Self::Ball { center, radius } => {
                let d2: f64 = (0..D)
                    .map(|i| (p[i] - center[i]) * (p[i] - center[i]))
                    .sum();
                (radius * radius - d2, 0)
            }
            Self::Box { min, max } => {
                let s = |i: usize| (p[i] - min[i]) * (max[i] - p[i]);
                let f = (1..D).fold(s(0), |f, i| intersect(f, s(i)));
                (f, 0)
            }
            Self::Cylinder {
                center,
                axis,
                radius,
            } => {
                let d2: f64 = (0..D)
                    .filter(|&i| i != *axis)
                    .map(|i| (p[i] - center[i]) * (p[i] - center[i]))
                    .sum();
                (radius * radius - d2, 0)
            }
            Self::Torus {
                center,
                axis,
                major,
                minor,
            } => {
                let across: f64 = (0..D)
                    .filter(|&i| i != *axis)
                    .map(|i| (p[i] - center[i]) * (p[i] - center[i]))
                    .sum();
                let along = p[*axis] - center[*axis];
                let ring = sqrt(across) - major;
                (minor * minor - ring * ring - along * along, 0)
            }
            Self::Half { normal, offset } => {
                let dot: f64 = (0..D).map(|i| normal[i] * p[i]).sum();
                (offset - dot, 0)
            }
        };
        (f, n, false)
    }
}

impl<const D: usize> Shape<D>
where
    Dim<D>: Dimension<D>,
{
    /// `f` and `∇f` at `p`, in the leaf's coordinates.
    pub(super) fn gradient(&self, p: [f64; D]) -> (f64, [f64; D]) {
        match self {
            Self::Bezier(solid, _) => {
                let (f, g) = solid.f_with_gradient(Dim::<D>::point(p));
                (f, Dim::<D>::coords(g))
            }
            Self::Piecewise(solid, _) => {
                let (f, g) = solid.f_with_gradient(Dim::<D>::point(p));
                (f, Dim::<D>::coords(g))
            }
            Self::Ball { center, .. } => (
                self.eval(p).0,
                core::array::from_fn(|i| -2.0 * (p[i] - center[i])),
            ),
            Self::Box { min, max } => {
                let s = |i: usize| (p[i] - min[i]) * (max[i] - p[i]);
                let ds = |i: usize| max[i] + min[i] - 2.0 * p[i];
                let mut f = s(0);
                let mut g = [0.0; D];
                g[0] = ds(0);
                for i in 1..D {
                    let (v, da, db) = crate::rfunc::intersect_with_partials(f, s(i));
                    for gc in &mut g {
                        *gc *= da;
                    }
                    g[i] = db * ds(i);
                    f = v;
                }
                (f, g)
            }
            Self::Cylinder { center, axis, .. } => (
                self.eval(p).0,
                core::array::from_fn(|i| {
                    if i == *axis {
                        0.0
                    } else {
                        -2.0 * (p[i] - center[i])
                    }
                }),
            ),
            Self::Torus {
                center,
                axis,
                major,
                ..
            } => {
                let across: f64 = (0..D)
                    .filter(|&i| i != *axis)
                    .map(|i| (p[i] - center[i]) * (p[i] - center[i]))
                    .sum();
                let rho = sqrt(across);
                let ring = rho - major;
                (
                    self.eval(p).0,
                    core::array::from_fn(|i| {
                        if i == *axis {
                            -2.0 * (p[i] - center[i])
                        } else if rho == 0.0 {
                            0.0
                        } else {
                            -2.0 * ring * (p[i] - center[i]) / rho
                        }
                    }),
                )
            }
            Self::Half { normal, offset } => {
                let dot: f64 = (0..D).map(|i| normal[i] * p[i]).sum();
                (offset - dot, core::array::from_fn(|i| -normal[i]))
            }
            Self::Hyperfun(h) => h.gradient(p),
        }
    }
}

/// The largest magnitude a HyperFun leaf's program value keeps (past it, clamped: the
/// R-functions over it stay finite).
const HF_LIMIT: f64 = 1e100;
/// The operations of the strict reader a HyperFun leaf's program may take at one point when no
/// plan shares a budget (about 3 ms).
pub(super) const HF_POINT_OPERATIONS: u64 = 1_000_000;
/// The operations the points of one plan share, over all HyperFun leaves (about a second, as
/// the folded nets' budget).
const HF_PLAN_OPERATIONS: u64 = 300_000_000;
/// The least a point gets of a plan's budget: a hundred times what a leaf of a few primitives
/// takes.
const HF_MIN_OPERATIONS: u64 = 20_000;
/// The most numbers a HyperFun leaf's arrays and variables may take (its evaluator's memory, 768
/// KiB).
pub(super) const HF_MAX_CELLS: usize = 1 << 16;

/// A HyperFun program as a leaf: `program & box`, the R-conjunction of the program's value (at
/// the point, its coordinates past `D` zero) and the box's `s_0 & s_1 (& s_2)` (as
/// [`Shape::Box`]), so that the leaf is the program's solid within its box, negative outside the
/// box whatever the program gives there: `f ≤ box` bounds it. Where the program fails (HyperFun's
/// runtime error, its work cap) or gives no finite number, its value is −1 (outside); past its
/// work cap the evaluation also says it ran out (the value is approximate there).
#[derive(Debug)]
pub(super) struct HfLeaf<const D: usize> {
    /// The program's text (what two leaves are compared by).
    pub(super) text: alloc::string::String,
    pub(super) program: crate::hyperfun::read::Program,
    pub(super) min: [f64; D],
    pub(super) max: [f64; D],
    /// The operations one point may take: [`HF_POINT_OPERATIONS`], or a plan's share.
    pub(super) limit: core::sync::atomic::AtomicU64,
}

impl<const D: usize> Clone for HfLeaf<D> {
    fn clone(&self) -> Self {
        Self {
            text: self.text.clone(),
            program: self.program.clone(),
            min: self.min,
            max: self.max,
            limit: core::sync::atomic::AtomicU64::new(
                self.limit.load(core::sync::atomic::Ordering::Relaxed),
            ),
        }
    }
}

impl<const D: usize> PartialEq for HfLeaf<D> {
    fn eq(&self, o: &Self) -> bool {
        self.text == o.text && self.min == o.min && self.max == o.max
    }
}

impl<const D: usize> HfLeaf<D> {
    /// The box as a [`Shape::Box`], for its bounds.
    pub(super) fn cut(&self) -> Shape<D>
    where
        Dim<D>: Dimension<D>,
    {
        Shape::Box {
            min: self.min,
            max: self.max,
        }
    }

    /// Shares the plan's budget among `queries` points (see [`crate::solid::Solid::plan`]).
    pub(super) fn plan(&self, queries: usize) {
        let share = HF_PLAN_OPERATIONS / (queries.max(1) as u64);
        let limit = share.clamp(HF_MIN_OPERATIONS, HF_POINT_OPERATIONS);
        self.limit
            .store(limit, core::sync::atomic::Ordering::Relaxed);
    }

    /// The program's own value at `p`, clamped to `±HF_LIMIT` (−1 where it fails), and whether
    /// it ran out of its work.
    pub(super) fn program_value(&self, p: [f64; D]) -> (f64, bool) {
        let mut x = [0.0; 3];
        for (c, v) in x.iter_mut().zip(p) {
            *c = v;
        }
        let mut run = self.program.evaluator();
        run.set_limit(self.limit.load(core::sync::atomic::Ordering::Relaxed));
        match run.eval(&x, &[]) {
            Ok(v) if !v.is_nan() => (v.clamp(-HF_LIMIT, HF_LIMIT), false),
            Ok(_) => (-1.0, false),
            Err(e) => (-1.0, e.kind == crate::hyperfun::read::HfErrorKind::Limit),
        }
    }

    fn eval(&self, p: [f64; D]) -> (f64, bool) {
        let s = |i: usize| (p[i] - self.min[i]) * (self.max[i] - p[i]);
        let cut = (1..D).fold(s(0), |f, i| intersect(f, s(i)));
        let (v, exhausted) = self.program_value(p);
        (intersect(v, cut), exhausted)
    }

    /// `f` and its gradient by central differences (a program has no derivatives of its own),
    /// a step of a millionth of the box's largest side.
    fn gradient(&self, p: [f64; D]) -> (f64, [f64; D]) {
        let side = (0..D).fold(0.0_f64, |m, i| m.max(self.max[i] - self.min[i]));
        let h = side * 1e-6;
        let g = core::array::from_fn(|i| {
            let (mut a, mut b) = (p, p);
            a[i] -= h;
            b[i] += h;
            (self.eval(b).0 - self.eval(a).0) / (2.0 * h)
        });
        (self.eval(p).0, g)
    }
}

/// A regular Bézier leaf's `ξ` net and box: `f = S_ξ(t) & F_s(t)` with `t` the point scaled to
/// the box, computed as the solid computes it (the same sums in the same order), without its
/// `x, y, z` components.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Regular<const D: usize> {
    pub(super) xi: Tensor<f64, D>,
    pub(super) min: [f64; D],
    pub(super) max: [f64; D],
}

impl<const D: usize> Regular<D> {
    pub(super) fn of(solid: &Solid<D>) -> Option<Self>
    where
        Dim<D>: Dimension<D>,
    {
        if solid.is_space_mapped() {
            return None;
        }
        let (min, max) = solid.domain();
        Some(Self {
            xi: solid.xi_net(),
            min: Dim::<D>::coords(min),
            max: Dim::<D>::coords(max),
        })
    }

    /// The parameters of `p` (any point, inside the box or not).
    pub(super) fn scaled(&self, p: [f64; D]) -> [f64; D] {
        core::array::from_fn(|c| (p[c] - self.min[c]) / (self.max[c] - self.min[c]))
    }
}

/// A regular piecewise leaf's cells' `ξ` nets (in the net's order, the last axis fastest) and its
/// box: what its interval bounds read.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct RegularCells<const D: usize> {
    pub(super) xi: Vec<Tensor<f64, D>>,
    pub(super) cells: [usize; D],
    pub(super) min: [f64; D],
    pub(super) max: [f64; D],
}

impl<const D: usize> RegularCells<D> {
    pub(super) fn of(solid: &crate::piecewise::Piecewise<D>) -> Option<Self>
    where
        Dim<D>: Dimension<D>,
    {
        if !solid.is_regular() {
            return None;
        }
        let cells = solid.cells();
        let count: usize = cells.iter().product();
        let xi = (0..count)
            .map(|k| {
                let cell = crate::tensor::multi_index(cells, k);
                solid.part(cell).map(Solid::xi_net)
            })
            .collect::<Option<Vec<_>>>()?;
        let (min, max) = solid.domain();
        Some(Self {
            xi,
            cells,
            min: Dim::<D>::coords(min),
            max: Dim::<D>::coords(max),
        })
    }

    /// The global parameters of `p` (any point, inside the box or not).
    pub(super) fn scaled(&self, p: [f64; D]) -> [f64; D] {
        core::array::from_fn(|c| (p[c] - self.min[c]) / (self.max[c] - self.min[c]))
    }
}
