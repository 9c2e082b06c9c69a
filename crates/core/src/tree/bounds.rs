//! Bounds of a tree: a box outside of which `f ≤ 0`, from DESIGN §5's rules (union: the hull;
//! intersection: the overlap; difference: the first operand; transform: the moved box) made sound
//! for blends and morphs, which can reach past their operands.
//!
//! Each node is bounded at a level `L ≤ 0`: a box holding every point where its `f > L`. The root
//! is bounded at 0. A node passes its children the level their values must pass for its own to
//! pass `L`:
//!
//! - `f1 & f2 ≤ min(f1, f2)`, so an intersection's children (and a difference's first) keep `L`;
//! - for `f1, f2 ≤ 0`, `f1 | f2 ≤ (2 − √2)·max(f1, f2)`, so a union's children get `L / (2 − √2)`
//!   (once per fold: `((f1 | f2) | f3)`'s first two get it twice);
//! - a blend's displacement `a0 / (1 + (f1/a1)² + (f2/a2)²)` fades as its operands fall: they
//!   must pass the level where the R-function's fall outweighs it (`blend_level`);
//! - a morph with `0 ≤ t ≤ 1` is at most the larger operand; with `t` outside it is unbounded.
//!
//! Leaves at level `L`: a ball of radius `√(r² − L)`, a box whose half-sides `h` grow to
//! `√(h² − L)`, a torus whose tube grows to `√(minor² − L)`; a regular Bézier leaf is at most its
//! clipping function `F_s`, whose strips `t(1 − t)` pass `L` within `|t − ½| < √(¼ − L)` of the
//! middle of its box; a space-mapped one is bounded (by its net's hull) at level 0 only, and
//! cylinders and half-spaces not at all.

use crate::dim::{Dim, Dimension};
use crate::math::sqrt;
use crate::model::{Rotation, SolidSpec};

use super::{Affine, Leaf, Shape, rotation3, sin_cos};

/// A box `[lo, hi]`; empty where `lo > hi` on some axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Aabb<const D: usize> {
    pub(super) lo: [f64; D],
    pub(super) hi: [f64; D],
}

impl<const D: usize> Aabb<D> {
    fn empty() -> Self {
        Self {
            lo: [f64::INFINITY; D],
            hi: [f64::NEG_INFINITY; D],
        }
    }

    fn is_empty(&self) -> bool {
        (0..D).any(|i| self.lo[i] > self.hi[i])
    }

    fn hull(self, other: Self) -> Self {
        Self {
            lo: core::array::from_fn(|i| self.lo[i].min(other.lo[i])),
            hi: core::array::from_fn(|i| self.hi[i].max(other.hi[i])),
        }
    }

    fn overlap(self, other: Self) -> Self {
        Self {
            lo: core::array::from_fn(|i| self.lo[i].max(other.lo[i])),
            hi: core::array::from_fn(|i| self.hi[i].min(other.hi[i])),
        }
    }

    /// The box around the image of this one under `map`.
    fn mapped(self, map: &Affine<D>) -> Self {
        if self.is_empty() {
            return self;
        }
        let mut out = Self::empty();
        for corner in 0..1usize << D {
            let p: [f64; D] = core::array::from_fn(|i| {
                if corner >> i & 1 == 0 {
                    self.lo[i]
                } else {
                    self.hi[i]
                }
            });
            let q = map.apply(p);
            out = out.hull(Self { lo: q, hi: q });
        }
        out
    }
}

/// The hull of the boxes of every leaf of `spec` that is bounded on its own (at level 0, moved
/// into space by `forward` and the transforms above it), whatever the operations around them:
/// where a model that may be unbounded is worth looking at. `None` when no leaf is bounded.
pub(super) fn parts_hull<'a, const D: usize>(
    spec: &SolidSpec,
    forward: &Affine<D>,
    leaves: &mut impl Iterator<Item = &'a Leaf<D>>,
) -> Option<Aabb<D>>
where
    Dim<D>: Dimension<D>,
{
    let join = |a: Option<Aabb<D>>, b: Option<Aabb<D>>| match (a, b) {
        (Some(a), Some(b)) => Some(a.hull(b)),
        (a, b) => a.or(b),
    };
    match spec {
        SolidSpec::Transform {
            solid,
            translate,
            rotate,
            scale,
        } => {
            let m = transform_forward::<D>(translate, rotate, scale);
            parts_hull(solid, &forward.after(&m), leaves)
        }
        spec if !spec.children().is_empty() => spec
            .children()
            .iter()
            .fold(None, |h, c| join(h, parts_hull(c, forward, leaves))),
        _ => {
            let leaf = leaves.next()?;
            leaf_bounds(&leaf.shape, 0.0)
                .filter(|b| !b.is_empty())
                .map(|b| b.mapped(forward))
        }
    }
}

/// The middles of the boxes of the leaves of `spec` that are bounded on their own, moved into
/// space as [`parts_hull`] moves them, in `out`: points to look for the inside of a solid at,
/// where a grid finds none.
pub(super) fn leaf_middles<'a, const D: usize>(
    spec: &SolidSpec,
    forward: &Affine<D>,
    leaves: &mut impl Iterator<Item = &'a Leaf<D>>,
    out: &mut alloc::vec::Vec<[f64; D]>,
) where
    Dim<D>: Dimension<D>,
{
    match spec {
        SolidSpec::Transform {
            solid,
            translate,
            rotate,
            scale,
        } => {
            let m = transform_forward::<D>(translate, rotate, scale);
            leaf_middles(solid, &forward.after(&m), leaves, out);
        }
        spec if !spec.children().is_empty() => {
            for child in spec.children() {
                leaf_middles(child, forward, leaves, out);
            }
        }
        _ => {
            let Some(leaf) = leaves.next() else {
                return;
            };
            if let Some(b) = leaf_bounds(&leaf.shape, 0.0).filter(|b| !b.is_empty()) {
                out.push(forward.apply(core::array::from_fn(|i| 0.5 * b.lo[i] + 0.5 * b.hi[i])));
            }
        }
    }
}

/// `1 / (2 − √2)`: how much further a union's operands must pass a negative level.
const UNION_LEVEL: f64 = 1.707_106_781_186_547_5;

/// `UNION_LEVEL` to the power `folds`.
fn grow_level(folds: usize) -> f64 {
    (0..folds).fold(1.0, |k, _| k * UNION_LEVEL)
}

/// The hull of `boxes` (empty for none).
pub(super) fn hull_of<const D: usize>(boxes: &[Aabb<D>]) -> Aabb<D> {
    boxes.iter().fold(Aabb::empty(), |h, b| h.hull(*b))
}

/// The most boxes [`boxes`] keeps for a node: past it they are joined into their hull.
const MAX_BOXES: usize = 64;

/// Boxes in space whose union holds every point where `spec`'s `f > level` (none for an empty
/// solid; `None` where it may be unbounded), given `forward` (the node's coordinates to space)
/// and its leaves, in the order the builder compiled them; the tree's bounds are their hull: a union's are its operands', so that parts far
/// apart keep boxes of their own ([`clusters`]); an intersection's the overlaps of its operands'.
pub(super) fn boxes<'a, const D: usize>(
    spec: &SolidSpec,
    level: f64,
    forward: &Affine<D>,
    leaves: &mut impl Iterator<Item = &'a Leaf<D>>,
) -> Option<alloc::vec::Vec<Aabb<D>>>
where
    Dim<D>: Dimension<D>,
{
    use alloc::vec::Vec;
    let capped = |mut b: Vec<Aabb<D>>| {
        b.retain(|b| !b.is_empty());
        if b.len() > MAX_BOXES {
            b = alloc::vec![hull_of(&b)];
        }
        b
    };
    // Both operands' boxes (the union of their sets).
    let join = |a: Option<Vec<Aabb<D>>>, b: Option<Vec<Aabb<D>>>| match (a, b) {
        (Some(mut a), Some(b)) => {
            a.extend(b);
            Some(capped(a))
        }
        _ => None,
    };
    // The overlaps (the intersection of their sets); an unbounded operand bounds nothing.
    let meet = |a: Option<Vec<Aabb<D>>>, b: Option<Vec<Aabb<D>>>| match (a, b) {
        (Some(a), Some(b)) => {
            let pairs = a.len() * b.len();
            Some(capped(if pairs > MAX_BOXES {
                alloc::vec![hull_of(&a).overlap(hull_of(&b))]
            } else {
                a.iter()
                    .flat_map(|x| b.iter().map(|y| x.overlap(*y)))
                    .collect()
            }))
        }
        (a, b) => a.or(b),
    };
    match spec {
        SolidSpec::Union { of } => {
            let n = of.len();
            let mut all = Some(Vec::new());
            for (i, child) in of.iter().enumerate() {
                let folds = n - i.max(1);
                all = join(
                    all,
                    boxes(child, level * grow_level(folds), forward, leaves),
                );
            }
            all
        }
        SolidSpec::Intersection { of } => {
            let mut overlap = None;
            for child in of {
                overlap = meet(overlap, boxes(child, level, forward, leaves));
            }
            overlap
        }
        SolidSpec::Difference { of } => {
            let mut first = None;
            for (i, child) in of.iter().enumerate() {
                let b = boxes(child, level, forward, leaves);
                if i == 0 {
                    first = b;
                }
            }
            first
        }
        SolidSpec::BlendUnion { of, a0, a1, a2 }
        | SolidSpec::BlendIntersection { of, a0, a1, a2 } => {
            let union = matches!(spec, SolidSpec::BlendUnion { .. });
            let level = blend_level(level, *a0, a1.abs().max(a2.abs()), union);
            let mut parts = of.iter().map(|c| boxes(c, level, forward, leaves));
            let (a, b) = (parts.next().flatten(), parts.next().flatten());
            if union { join(a, b) } else { meet(a, b) }
        }
        SolidSpec::Morph { of, t } => {
            let parts: Vec<_> = of
                .iter()
                .map(|c| boxes(c, level, forward, leaves))
                .collect();
            if !(0.0..=1.0).contains(t) {
                return None;
            }
            parts.into_iter().fold(Some(Vec::new()), join)
        }
        SolidSpec::Transform {
            solid,
            translate,
            rotate,
            scale,
        } => {
            let m = transform_forward::<D>(translate, rotate, scale);
            boxes(solid, level, &forward.after(&m), leaves)
        }
        SolidSpec::Part { solid, .. } => boxes(solid, level, forward, leaves),
        _ => {
            let leaf = leaves.next()?;
            leaf_bounds(&leaf.shape, level).map(|b| capped(alloc::vec![b.mapped(forward)]))
        }
    }
}

/// `boxes` gathered into parts far apart ([`crate::math::far_parts`]).
pub(super) fn clusters<const D: usize>(boxes: &[Aabb<D>]) -> alloc::vec::Vec<Aabb<D>> {
    let pairs: alloc::vec::Vec<_> = boxes
        .iter()
        .filter(|b| !b.is_empty())
        .map(|b| (b.lo, b.hi))
        .collect();
    crate::math::far_parts(&pairs)
        .into_iter()
        .map(|(lo, hi)| Aabb { lo, hi })
        .collect()
}

/// The level a blend's operands must pass for the blend to pass `level` (≤ 0), with `a` the
/// larger of `|a1|` and `|a2|`.
///
/// Where both operands are at most `−g` (the union's case; for the intersection, where one is),
/// the R-function is at most `−c·g` (`c = 2 − √2` for `|`, 1 for `&`) and the displacement
/// `a0 / (1 + (f1/a1)² + (f2/a2)²)` at most `a0 / (1 + g²/a²)`, for the operand nearest zero
/// (the union) or farthest (the intersection) gives `g`. Their sum falls below `level` past the
/// root `g*` of `c·g = |level| + a0 / (1 + g²/a²)` (its left side grows with `g`, its right side
/// shrinks), so `−g*` is the operands' level. Where `a0 ≤ 0` the displacement only lowers `f`. The
/// root is bisected to its upper end: `a0 = 1e4` with unit `a1, a2` bounds a blend of unit spheres
/// at `g* ≈ 26`, not at `a0 / c ≈ 17 000` as the displacement's largest value alone would.
fn blend_level(level: f64, a0: f64, a: f64, union: bool) -> f64 {
    let c = if union { 1.0 / UNION_LEVEL } else { 1.0 };
    let need = -level;
    if a0 <= 0.0 {
        return level / c;
    }
    let gap = |g: f64| c * g - need - a0 / (1.0 + (g / a) * (g / a));
    let (mut lo, mut hi) = (0.0, (need + a0) / c);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if gap(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    -hi
}

/// A leaf's bounds at `level` in its own coordinates.
fn leaf_bounds<const D: usize>(shape: &Shape<D>, level: f64) -> Option<Aabb<D>>
where
    Dim<D>: Dimension<D>,
{
    let grow = |h: f64| sqrt(h * h - level);
    Some(match shape {
        Shape::Ball { center, radius } => {
            let r = grow(*radius);
            Aabb {
                lo: core::array::from_fn(|i| center[i] - r),
                hi: core::array::from_fn(|i| center[i] + r),
            }
        }
        Shape::Box { min, max } => Aabb {
            lo: core::array::from_fn(|i| (min[i] + max[i]) / 2.0 - grow((max[i] - min[i]) / 2.0)),
            hi: core::array::from_fn(|i| (min[i] + max[i]) / 2.0 + grow((max[i] - min[i]) / 2.0)),
        },
        Shape::Torus {
            center,
            axis,
            major,
            minor,
        } => {
            let tube = grow(*minor);
            let reach = |i: usize| if i == *axis { tube } else { major + tube };
            Aabb {
                lo: core::array::from_fn(|i| center[i] - reach(i)),
                hi: core::array::from_fn(|i| center[i] + reach(i)),
            }
        }
        Shape::Bezier(solid, _) => {
            let (lo, hi) = solid.domain();
            let (lo, hi) = (Dim::<D>::coords(lo), Dim::<D>::coords(hi));
            if solid.is_space_mapped() {
                // A space mapping: negative outside its net's hull, and no more is known.
                if level < 0.0 {
                    return None;
                }
                Aabb { lo, hi }
            } else {
                let s = sqrt(0.25 - level);
                Aabb {
                    lo: core::array::from_fn(|i| lo[i] + (0.5 - s) * (hi[i] - lo[i])),
                    hi: core::array::from_fn(|i| lo[i] + (0.5 + s) * (hi[i] - lo[i])),
                }
            }
        }
        Shape::Piecewise(solid, _) => {
            let (lo, hi) = solid.domain();
            let (lo, hi) = (Dim::<D>::coords(lo), Dim::<D>::coords(hi));
            if solid.is_regular() {
                // Clipped on the global box as a single solid on its own.
                let s = sqrt(0.25 - level);
                Aabb {
                    lo: core::array::from_fn(|i| lo[i] + (0.5 - s) * (hi[i] - lo[i])),
                    hi: core::array::from_fn(|i| lo[i] + (0.5 + s) * (hi[i] - lo[i])),
                }
            } else {
                if level < 0.0 {
                    return None;
                }
                Aabb { lo, hi }
            }
        }
        Shape::Cylinder { .. } | Shape::Half { .. } => return None,
        // f = program & box ≤ box: where f ≥ level, the box's f is too.
        Shape::Hyperfun(h) => return leaf_bounds(&h.cut(), level),
    })
}

/// `M = T · Rz · Ry · Rx · S` (in 2D `T · R · S`) of a checked transform.
fn transform_forward<const D: usize>(
    translate: &Option<alloc::vec::Vec<f64>>,
    rotate: &Option<Rotation>,
    scale: &Option<alloc::vec::Vec<f64>>,
) -> Affine<D> {
    let t: [f64; D] = translate
        .as_deref()
        .and_then(|t| t.try_into().ok())
        .unwrap_or([0.0; D]);
    let s: [f64; D] = scale
        .as_deref()
        .and_then(|s| s.try_into().ok())
        .unwrap_or([1.0; D]);
    let mut r = Affine::<D>::IDENTITY.m;
    match rotate {
        Some(Rotation::Angle(a)) if D == 2 => {
            let (sin, cos) = sin_cos(*a);
            r[0][0] = cos;
            r[0][1] = -sin;
            r[1][0] = sin;
            r[1][1] = cos;
        }
        Some(Rotation::Angles(angles)) if D == 3 => {
            for (row, m_row) in r.iter_mut().zip(rotation3(*angles)) {
                row.copy_from_slice(&m_row);
            }
        }
        _ => {}
    }
    Affine {
        m: core::array::from_fn(|i| core::array::from_fn(|j| r[i][j] * s[j])),
        t,
    }
}
