//! Interval arithmetic over a tree: a range `[lo, hi]` that holds `f` at every point of a box, so
//! that a mesher can skip the boxes where `f` keeps one sign.
//!
//! Each leaf bounds its own formula over the box mapped into its coordinates (the box around the
//! mapped corners, which holds the mapped box). A regular Bézier leaf restricts its `ξ` net to the
//! box's parameters (de Casteljau, axis by axis): the restricted coefficients bound `S_ξ` there
//! (convex hull property), and its strips bound the clipping function; a space-mapped one is
//! known only to be negative outside its net's hull. The R-functions are increasing in both
//! arguments, so they map the ends of their operands' ranges to the ends of theirs; a blend adds a
//! range for its displacement; a morph is linear.

use alloc::vec::Vec;

use super::{Leaf, Shape, Step, Tree};
use crate::dim::{Dim, Dimension, Point};
use crate::math::sqrt;
use crate::rfunc::{intersect, union};

/// Where nothing finer is known: large enough to say nothing, small enough that squares and the
/// R-functions stay finite.
const UNKNOWN: f64 = 1e150;

/// A range of values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// The least value.
    pub lo: f64,
    /// The greatest value.
    pub hi: f64,
}

impl Interval {
    const ANY: Self = Self {
        lo: -UNKNOWN,
        hi: UNKNOWN,
    };

    fn new(lo: f64, hi: f64) -> Self {
        Self {
            lo: lo.clamp(-UNKNOWN, UNKNOWN),
            hi: hi.clamp(-UNKNOWN, UNKNOWN),
        }
    }

    fn add(self, o: Self) -> Self {
        Self::new(self.lo + o.lo, self.hi + o.hi)
    }

    fn neg(self) -> Self {
        Self::new(-self.hi, -self.lo)
    }

    fn scale(self, k: f64) -> Self {
        if k >= 0.0 {
            Self::new(k * self.lo, k * self.hi)
        } else {
            Self::new(k * self.hi, k * self.lo)
        }
    }

    /// `x²` for `x` in the range.
    fn square(self) -> Self {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        if self.lo <= 0.0 && self.hi >= 0.0 {
            Self::new(0.0, a.max(b))
        } else {
            Self::new(a.min(b), a.max(b))
        }
    }

    fn sqrt(self) -> Self {
        Self::new(sqrt(self.lo.max(0.0)), sqrt(self.hi.max(0.0)))
    }

    fn union(self, o: Self) -> Self {
        Self::new(union(self.lo, o.lo), union(self.hi, o.hi))
    }

    fn intersect(self, o: Self) -> Self {
        Self::new(intersect(self.lo, o.lo), intersect(self.hi, o.hi))
    }
}

impl Interval {
    /// This range cut by the box `b` (the R-function intersection with its function) over the
    /// box `[lo, hi]`.
    pub(super) fn intersect_box<const D: usize>(
        self,
        b: &Shape<D>,
        lo: [f64; D],
        hi: [f64; D],
    ) -> Self
    where
        Dim<D>: Dimension<D>,
    {
        self.intersect(leaf_interval(b, lo, hi, &mut Vec::new()))
    }
}

/// `(x − c)²` for `x` in `[lo, hi]`.
fn offset_square(lo: f64, hi: f64, c: f64) -> Interval {
    Interval::new(lo - c, hi - c).square()
}

impl<const D: usize> Tree<D>
where
    Dim<D>: Dimension<D>,
{
    /// A range holding `f` at every point of the box `[lo, hi]`.
    #[must_use]
    pub fn interval(&self, lo: [f64; D], hi: [f64; D]) -> Interval {
        let mut leaves = Vec::with_capacity(self.leaves.len());
        self.leaf_ranges(lo, hi, &mut leaves);
        self.range_of(&leaves)
    }

    /// Each leaf's range over the box `[lo, hi]`, by leaf, in `out`.
    pub(crate) fn leaf_ranges(&self, lo: [f64; D], hi: [f64; D], out: &mut Vec<Interval>) {
        let mut scratch = Vec::new();
        out.clear();
        out.extend((0..self.leaves.len()).map(|i| self.leaf_range(i, lo, hi, &mut scratch)));
    }

    /// Leaf `i`'s range over the box `[lo, hi]` (`scratch`: room for a Bézier leaf's net).
    pub(crate) fn leaf_range(
        &self,
        i: usize,
        lo: [f64; D],
        hi: [f64; D],
        scratch: &mut Vec<f64>,
    ) -> Interval {
        match self.leaves.get(i) {
            Some(leaf) => {
                let (llo, lhi) = mapped_box(leaf, lo, hi);
                leaf_interval(&leaf.shape, llo, lhi, scratch)
            }
            None => Interval::ANY,
        }
    }

    /// The range of `f` over a box from its leaves' ranges there ([`Tree::leaf_ranges`]).
    pub(crate) fn range_of(&self, leaves: &[Interval]) -> Interval {
        let mut stack: Vec<Interval> = Vec::with_capacity(self.stack);
        for step in &self.steps {
            match *step {
                Step::Leaf(i) => stack.push(leaves.get(i).copied().unwrap_or(Interval::ANY)),
                step => {
                    let first = stack.len().saturating_sub(step.arity());
                    let range = combine(step, &stack[first..]);
                    stack.truncate(first);
                    stack.push(range);
                }
            }
        }
        stack.pop().unwrap_or(Interval::ANY)
    }
}

/// The range of an operation's value from its operands' ranges.
fn combine(step: Step, operands: &[Interval]) -> Interval {
    let fold = |op: fn(Interval, Interval) -> Interval| {
        operands.iter().copied().reduce(op).unwrap_or(Interval::ANY)
    };
    match step {
        Step::Leaf(_) => Interval::ANY,
        Step::Union(_) => fold(Interval::union),
        Step::Intersection(_) => fold(Interval::intersect),
        Step::Difference(_) => fold(|a, b| a.intersect(b.neg())),
        Step::Blend {
            union: u,
            a0,
            a1,
            a2,
        } => {
            let [f1, f2] = [0, 1].map(|k| operands.get(k).copied().unwrap_or(Interval::ANY));
            let base = if u { f1.union(f2) } else { f1.intersect(f2) };
            let den = Interval::new(1.0, 1.0)
                .add(f1.scale(1.0 / a1).square())
                .add(f2.scale(1.0 / a2).square());
            let shift = if a0 >= 0.0 {
                Interval::new(a0 / den.hi, a0 / den.lo)
            } else {
                Interval::new(a0 / den.lo, a0 / den.hi)
            };
            base.add(shift)
        }
        Step::Morph(t) => {
            let [f1, f2] = [0, 1].map(|k| operands.get(k).copied().unwrap_or(Interval::ANY));
            f1.scale(1.0 - t).add(f2.scale(t))
        }
    }
}

/// The box `[lo, hi]` in a leaf's coordinates: around the images of its corners.
pub(super) fn mapped_box<const D: usize>(
    leaf: &Leaf<D>,
    lo: [f64; D],
    hi: [f64; D],
) -> ([f64; D], [f64; D])
where
    Dim<D>: Dimension<D>,
{
    let Some(m) = &leaf.map else {
        return (lo, hi);
    };
    // Per output coordinate: the linear part's extremes over the box, plus the shift.
    let mut out_lo = m.t;
    let mut out_hi = m.t;
    for r in 0..D {
        for c in 0..D {
            let (a, b) = (m.m[r][c] * lo[c], m.m[r][c] * hi[c]);
            out_lo[r] += a.min(b);
            out_hi[r] += a.max(b);
        }
    }
    (out_lo, out_hi)
}

fn leaf_interval<const D: usize>(
    shape: &Shape<D>,
    lo: [f64; D],
    hi: [f64; D],
    scratch: &mut Vec<f64>,
) -> Interval
where
    Dim<D>: Dimension<D>,
{
    match shape {
        Shape::Ball { center, radius } => {
            let d = (0..D).fold(Interval::new(0.0, 0.0), |s, i| {
                s.add(offset_square(lo[i], hi[i], center[i]))
            });
            Interval::new(radius * radius, radius * radius).add(d.neg())
        }
        Shape::Box { min, max } => {
            let strip = |i: usize| {
                let mid = (min[i] + max[i]) / 2.0;
                let h = (max[i] - min[i]) / 2.0;
                Interval::new(h * h, h * h).add(offset_square(lo[i], hi[i], mid).neg())
            };
            (1..D).fold(strip(0), |f, i| f.intersect(strip(i)))
        }
        Shape::Cylinder {
            center,
            axis,
            radius,
        } => {
            let d = (0..D)
                .filter(|i| i != axis)
                .fold(Interval::new(0.0, 0.0), |s, i| {
                    s.add(offset_square(lo[i], hi[i], center[i]))
                });
            Interval::new(radius * radius, radius * radius).add(d.neg())
        }
        Shape::Torus {
            center,
            axis,
            major,
            minor,
        } => {
            let across = (0..D)
                .filter(|i| i != axis)
                .fold(Interval::new(0.0, 0.0), |s, i| {
                    s.add(offset_square(lo[i], hi[i], center[i]))
                });
            let ring = across.sqrt().add(Interval::new(-major, -major)).square();
            let along = offset_square(lo[*axis], hi[*axis], center[*axis]);
            Interval::new(minor * minor, minor * minor)
                .add(ring.neg())
                .add(along.neg())
        }
        Shape::Half { normal, offset } => {
            let dot = (0..D).fold(Interval::new(0.0, 0.0), |s, i| {
                let (a, b) = (normal[i] * lo[i], normal[i] * hi[i]);
                s.add(Interval::new(a.min(b), a.max(b)))
            });
            Interval::new(*offset, *offset).add(dot.neg())
        }
        Shape::Bezier(solid, None) => moved(solid.domain(), lo, hi),
        // f = program & box ≤ box: the box's bound above, nothing below.
        Shape::Hyperfun(h) => {
            let cut = leaf_interval(&h.cut(), lo, hi, scratch);
            Interval::new(-UNKNOWN, cut.hi)
        }
        Shape::Piecewise(solid, None) => moved(solid.domain(), lo, hi),
        Shape::Piecewise(_, Some(r)) => {
            let (tlo, thi) = (r.scaled(lo), r.scaled(hi));
            let clip = unit_clip(tlo, thi);
            if clip.hi < 0.0 {
                return Interval::new(-UNKNOWN, clip.hi);
            }
            // The hull of the cells' polynomials over the parts of the box in them (the first and
            // last cells' extended past the global box), clipped by the global box's bound.
            let mut first = [0; D];
            let mut last = [0; D];
            for a in 0..D {
                let n = r.cells[a];
                // As the solid picks its cell (truncation is the floor of a non-negative number).
                let cell = |t: f64| {
                    let s = t * n as f64;
                    if s >= n as f64 {
                        n - 1
                    } else if s >= 0.0 {
                        s as usize
                    } else {
                        0
                    }
                };
                first[a] = cell(tlo[a]);
                last[a] = cell(thi[a]);
            }
            let spans: [usize; D] = core::array::from_fn(|a| last[a] - first[a] + 1);
            let mut s = Interval::new(f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..spans.iter().product() {
                let at = crate::tensor::multi_index(spans, k);
                let cell: [usize; D] = core::array::from_fn(|a| first[a] + at[a]);
                let flat = (0..D).fold(0, |k, a| k * r.cells[a] + cell[a]);
                let xi = &r.xi[flat];
                scratch.clear();
                scratch.extend_from_slice(xi.points());
                let dims = xi.dims();
                for axis in 0..D {
                    let n = r.cells[axis] as f64;
                    let c = cell[axis] as f64;
                    let mut a = tlo[axis] * n - c;
                    let mut b = thi[axis] * n - c;
                    if cell[axis] > 0 {
                        a = a.max(0.0);
                    }
                    if cell[axis] + 1 < r.cells[axis] {
                        b = b.min(1.0);
                    }
                    restrict(scratch, &dims, axis, a, b.max(a));
                }
                s = scratch.iter().fold(s, |r, &c| Interval {
                    lo: r.lo.min(c),
                    hi: r.hi.max(c),
                });
            }
            s.intersect(clip)
        }
        Shape::Bezier(_, Some(r)) => {
            let (tlo, thi) = (r.scaled(lo), r.scaled(hi));
            let clip = unit_clip(tlo, thi);
            if clip.hi < 0.0 {
                // Outside the unit box of the parameters: f = S & F_s ≤ F_s < 0, whatever S is.
                return Interval::new(-UNKNOWN, clip.hi);
            }
            // Inside: the polynomial's coefficients over the box's parameters bound S there.
            scratch.clear();
            scratch.extend_from_slice(r.xi.points());
            let dims = r.xi.dims();
            for axis in 0..D {
                restrict(scratch, &dims, axis, tlo[axis], thi[axis]);
            }
            let s =
                scratch
                    .iter()
                    .fold(Interval::new(f64::INFINITY, f64::NEG_INFINITY), |r, &c| {
                        Interval {
                            lo: r.lo.min(c),
                            hi: r.hi.max(c),
                        }
                    });
            s.intersect(clip)
        }
    }
}

/// The unit box's clipping `F_b(t_0) & F_b(t_1) …` over the parameters `[tlo, thi]`.
fn unit_clip<const D: usize>(tlo: [f64; D], thi: [f64; D]) -> Interval {
    let strip = |i: usize| Interval::new(0.25, 0.25).add(offset_square(tlo[i], thi[i], 0.5).neg());
    (1..D).fold(strip(0), |f, i| f.intersect(strip(i)))
}

/// A solid with moved points over `[lo, hi]`: negative outside its net's hull `domain`, and no
/// more is known.
fn moved<const D: usize>(domain: (Point<D>, Point<D>), lo: [f64; D], hi: [f64; D]) -> Interval
where
    Dim<D>: Dimension<D>,
{
    let (min, max) = (Dim::<D>::coords(domain.0), Dim::<D>::coords(domain.1));
    if (0..D).any(|i| hi[i] < min[i] || lo[i] > max[i]) {
        return Interval::new(-UNKNOWN, -f64::MIN_POSITIVE);
    }
    Interval::ANY
}

/// Restricts the Bernstein coefficients `c` (a net of `dims`, last axis fastest) along `axis` from
/// `[0, 1]` to `[a, b]`.
fn restrict(c: &mut [f64], dims: &[usize], axis: usize, a: f64, b: f64) {
    let n = dims[axis];
    let stride: usize = dims[axis + 1..].iter().product();
    let outer: usize = dims[..axis].iter().product();
    let mut line = [0.0; crate::bernstein::MAX_DEGREE + 1];
    for o in 0..outer {
        for s in 0..stride {
            let at = |k: usize| o * n * stride + k * stride + s;
            for (k, l) in line[..n].iter_mut().enumerate() {
                *l = c[at(k)];
            }
            restrict_line(&mut line[..n], a, b);
            for (k, l) in line[..n].iter().enumerate() {
                c[at(k)] = *l;
            }
        }
    }
}

/// One curve's Bernstein coefficients restricted from `[0, 1]` to `[a, b]`.
fn restrict_line(p: &mut [f64], a: f64, b: f64) {
    let n = p.len();
    if n < 2 {
        return;
    }
    if b.abs() >= (1.0 - a).abs() {
        // Keep [0, b] (de Casteljau at b, the left half), then [a/b, 1] of that.
        left_part(p, b);
        right_part(p, a / b);
    } else {
        // Keep [a, 1], then [0, (b − a)/(1 − a)] of that.
        right_part(p, a);
        left_part(p, (b - a) / (1.0 - a));
    }
}

/// The coefficients of `[0, t]`.
fn left_part(p: &mut [f64], t: f64) {
    let n = p.len();
    for r in 1..n {
        for k in (r..n).rev() {
            p[k] = (1.0 - t) * p[k - 1] + t * p[k];
        }
    }
}

/// The coefficients of `[t, 1]`.
fn right_part(p: &mut [f64], t: f64) {
    let n = p.len();
    for r in 1..n {
        for k in 0..n - r {
            p[k] = (1.0 - t) * p[k] + t * p[k + 1];
        }
    }
}

impl<const D: usize> Tree<D>
where
    Dim<D>: Dimension<D>,
{
    /// [`Tree::pruned_of`] over the box `[lo, hi]`.
    #[cfg(test)]
    pub(crate) fn pruned(&self, lo: [f64; D], hi: [f64; D]) -> Option<Vec<Step>> {
        let mut leaves = Vec::with_capacity(self.leaves.len());
        self.leaf_ranges(lo, hi, &mut leaves);
        self.pruned_of(&leaves)
    }

    /// The tree's program over a box, from its leaves' ranges there ([`Tree::leaf_ranges`]),
    /// without the operands of unions, intersections and differences that cannot decide a sign
    /// there: a union's operand negative all over the box
    /// (an intersection's positive; a difference's subtracted one negative). An R-function has the
    /// sign of `max` (`min` for `&`): `f1 | f2` with `f2 < 0` has the sign of `f1` everywhere, is
    /// zero where `f1` is, and its gradient there is `∇f1`. So where every operation between the
    /// left-out operand and the root is an R-function (or a transform), the pruned program has the
    /// tree's signs, zero set and normals in the box; operations under a blend or a morph, whose
    /// values count and not only their signs, are left whole. `None` when nothing is left out.
    pub(crate) fn pruned_of(&self, leaves: &[Interval]) -> Option<Vec<Step>> {
        // Per value on the stack: its range and the steps that made it.
        let mut stack: Vec<(Interval, usize)> = Vec::with_capacity(self.stack);
        let mut removed = alloc::vec![false; self.steps.len()];
        let mut counts: Vec<Option<usize>> = alloc::vec![None; self.steps.len()];
        let mut any = false;
        // Operations under a blend or a morph keep their operands: there the tree's f is not near
        // zero where theirs is, so a pruned operand would move the surface by a first-order amount.
        let mut parent = alloc::vec![usize::MAX; self.steps.len()];
        let mut roots: Vec<usize> = Vec::new();
        for (at, step) in self.steps.iter().enumerate() {
            for child in roots.drain(roots.len().saturating_sub(step.arity())..) {
                parent[child] = at;
            }
            roots.push(at);
        }
        let shielded = |mut at: usize| {
            while let Some(&up) = parent.get(at).filter(|&&up| up != usize::MAX) {
                if matches!(self.steps[up], Step::Blend { .. } | Step::Morph(_)) {
                    return true;
                }
                at = up;
            }
            false
        };
        for (at, step) in self.steps.iter().enumerate() {
            let (range, start) = match *step {
                Step::Leaf(i) => (leaves.get(i).copied().unwrap_or(Interval::ANY), at),
                step => {
                    let first = stack.len().saturating_sub(step.arity());
                    let operands = &stack[first..];
                    if matches!(
                        step,
                        Step::Union(_) | Step::Intersection(_) | Step::Difference(_)
                    ) {
                        let mut keep = operands.len();
                        for (k, &(r, begin)) in operands.iter().enumerate() {
                            let negligible = match step {
                                Step::Union(_) => r.hi < 0.0,
                                Step::Intersection(_) => r.lo > 0.0,
                                _ => k > 0 && r.hi < 0.0,
                            };
                            // One operand always stays.
                            if negligible && keep > 1 && !shielded(at) {
                                keep -= 1;
                                let span = begin..operands.get(k + 1).map_or(at, |o| o.1);
                                removed[span].iter_mut().for_each(|r| *r = true);
                                any = true;
                            }
                        }
                        counts[at] = Some(keep);
                    }
                    let ranges: Vec<Interval> = operands.iter().map(|o| o.0).collect();
                    let start = operands.first().map_or(at, |o| o.1);
                    stack.truncate(first);
                    (combine(step, &ranges), start)
                }
            };
            stack.push((range, start));
        }
        if !any {
            return None;
        }
        Some(
            self.steps
                .iter()
                .enumerate()
                .filter(|&(at, _)| !removed[at])
                .map(|(at, step)| match (*step, counts[at]) {
                    (Step::Union(_), Some(k)) => Step::Union(k),
                    (Step::Intersection(_), Some(k)) => Step::Intersection(k),
                    (Step::Difference(_), Some(k)) => Step::Difference(k),
                    (step, _) => step,
                })
                .collect(),
        )
    }
}
