//! A leaf's value where its formula overflows: a point so far from the leaf, in the leaf's own
//! coordinates, that a square or a sum passes `f64::MAX` (a sphere's `r² − ‖p − c‖²` at
//! `p = 1e200`, a half-space's `offset − n · p` with `n · p = ∞ − ∞`).
//!
//! The point and the leaf's numbers are scaled by `2⁻⁶⁰⁰` (exact) and the formula evaluated
//! there: every leaf's formula is homogeneous (of degree 2 for the quadrics and the box, 1 for a
//! half-space), so its value is the scaled value scaled back, which saturates at `±f64::MAX`. The
//! numbers of [`super::check`] keep the scaled ones finite for any finite point. A Bézier leaf
//! is negative far from its net (its clipping is), so `−f64::MAX` there.

use super::{Leaf, Shape};
use crate::dim::{Dim, Dimension};
use crate::inverse::Method;
use crate::math::sqrt;
use crate::rfunc::intersect;

/// `2⁻⁶⁰⁰`: points up to `f64::MAX` become about `1e127`, whose squares are finite.
const DOWN: f64 = 2.409_919_865_102_884e-181;
/// `2³⁰⁰`: half of the way back up, taken twice for a square.
const HALF_UP: f64 = 2.037_035_976_334_486e90;

/// `v` within `±f64::MAX` (NaN stays NaN: nothing here makes one).
pub(super) fn saturate(v: f64) -> f64 {
    v.clamp(-f64::MAX, f64::MAX)
}

impl<const D: usize> Leaf<D>
where
    Dim<D>: Dimension<D>,
{
    /// `f` at `p` (in space), with the preimages and whether the query ran out of its budget:
    /// the leaf's formula, or its value at the ends of the doubles where that overflows.
    pub(super) fn value(&self, p: [f64; D], method: Method) -> (f64, usize, bool) {
        let q = self.map.map_or(p, |m| m.apply(p));
        let (f, n, out) = self.shape.eval_by(q, method);
        if f.is_finite() {
            (f, n, out)
        } else {
            (self.far(p), n, out)
        }
    }

    /// `f` at `p` (in space) computed in units of `2⁶⁰⁰`, saturated.
    pub(super) fn far(&self, p: [f64; D]) -> f64 {
        let small: [f64; D] = core::array::from_fn(|i| p[i] * DOWN);
        let q = match &self.map {
            None => small,
            Some(m) => core::array::from_fn(|r| {
                let mut s = m.t[r] * DOWN;
                for (c, x) in small.iter().enumerate() {
                    s += m.m[r][c] * x;
                }
                s
            }),
        };
        let sq = |v: f64| v * v;
        // A value of degree 2 in lengths, back in full units.
        let square_up = |v: f64| saturate(v * HALF_UP * HALF_UP * HALF_UP * HALF_UP);
        let off = |i: usize, c: &[f64; D]| q[i] - c[i] * DOWN;
        let f = match &self.shape {
            Shape::Ball { center, radius } => {
                let d2: f64 = (0..D).map(|i| sq(off(i, center))).sum();
                square_up(sq(radius * DOWN) - d2)
            }
            Shape::Box { min, max } => {
                let s = |i: usize| (q[i] - min[i] * DOWN) * (max[i] * DOWN - q[i]);
                square_up((1..D).fold(s(0), |f, i| intersect(f, s(i))))
            }
            Shape::Cylinder {
                center,
                axis,
                radius,
            } => {
                let d2: f64 = (0..D)
                    .filter(|i| i != axis)
                    .map(|i| sq(off(i, center)))
                    .sum();
                square_up(sq(radius * DOWN) - d2)
            }
            Shape::Torus {
                center,
                axis,
                major,
                minor,
            } => {
                let across: f64 = (0..D)
                    .filter(|i| i != axis)
                    .map(|i| sq(off(i, center)))
                    .sum();
                let ring = sqrt(across) - major * DOWN;
                square_up(sq(minor * DOWN) - sq(ring) - sq(off(*axis, center)))
            }
            Shape::Half { normal, offset } => {
                let dot: f64 = (0..D).map(|i| normal[i] * q[i]).sum();
                let v = offset * DOWN - dot;
                saturate(v * HALF_UP * HALF_UP)
            }
            Shape::Bezier(..) | Shape::Piecewise(..) | Shape::Hyperfun(..) => -f64::MAX,
        };
        if f.is_nan() { -f64::MAX } else { f }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::{CoordAxis, ModelFile, Rotation, SolidSpec as S};
    use crate::testutil::Rng;
    use crate::tree::ModelTree;
    use alloc::boxed::Box;
    use alloc::vec;
    use alloc::vec::Vec;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_scales_are_powers_of_two() {
        assert_eq!(super::DOWN, 2f64.powi(-600));
        assert_eq!(super::HALF_UP, 2f64.powi(300));
    }

    /// A magnitude from the edges of what a tree accepts, or an ordinary one.
    fn magnitude(rng: &mut Rng) -> f64 {
        [1e-12, 1e-6, 1.0, 3.0, 1e6, 1e12][rng.int(0, 5)] * rng.range(0.5, 1.0)
    }

    fn signed(rng: &mut Rng) -> f64 {
        let m = magnitude(rng).min(1e12);
        if rng.int(0, 1) == 0 { m } else { -m }
    }

    fn point(rng: &mut Rng) -> [f64; 3] {
        core::array::from_fn(|_| signed(rng))
    }

    /// A random tree of `depth` levels at most with numbers at the edges of what is accepted;
    /// with `transforms` false, no transforms, blends or morphs (its sign is a Boolean of its
    /// leaves' signs).
    fn extreme(rng: &mut Rng, depth: usize, transforms: bool) -> S {
        if depth == 0 || rng.int(0, 3) == 0 {
            return match rng.int(0, if transforms { 4 } else { 3 }) {
                0 => S::Sphere {
                    center: point(rng),
                    radius: magnitude(rng),
                },
                1 => {
                    let (c, h) = (point(rng), magnitude(rng));
                    S::Box {
                        min: c.map(|x| x - h * (1.0 + 1e-3) - x.abs() * 1e-12),
                        max: c.map(|x| x + h * (1.0 + 1e-3) + x.abs() * 1e-12),
                    }
                    .clamp_box()
                }
                2 => S::Torus {
                    center: point(rng),
                    axis: [CoordAxis::X, CoordAxis::Y, CoordAxis::Z][rng.int(0, 2)],
                    major: magnitude(rng),
                    minor: magnitude(rng),
                },
                3 => S::Cylinder {
                    center: point(rng),
                    axis: [CoordAxis::X, CoordAxis::Y, CoordAxis::Z][rng.int(0, 2)],
                    radius: magnitude(rng),
                },
                _ => S::Halfspace {
                    normal: point(rng),
                    offset: signed(rng),
                },
            };
        }
        let two = |rng: &mut Rng| {
            vec![
                extreme(rng, depth - 1, transforms),
                extreme(rng, depth - 1, transforms),
            ]
        };
        match rng.int(0, if transforms { 6 } else { 2 }) {
            0 => S::Union { of: two(rng) },
            1 => S::Intersection { of: two(rng) },
            2 => S::Difference { of: two(rng) },
            3 => S::BlendUnion {
                of: two(rng),
                a0: signed(rng),
                a1: signed(rng),
                a2: signed(rng),
            },
            4 => S::BlendIntersection {
                of: two(rng),
                a0: signed(rng),
                a1: signed(rng),
                a2: signed(rng),
            },
            5 => S::Morph {
                of: two(rng),
                t: signed(rng),
            },
            _ => S::Transform {
                solid: Box::new(extreme(rng, depth - 1, transforms)),
                translate: Some(point(rng).to_vec()),
                rotate: Some(Rotation::Angles(core::array::from_fn(|_| {
                    rng.range(-180.0, 180.0)
                }))),
                scale: Some(core::array::from_fn::<f64, 3, _>(|_| signed(rng)).to_vec()),
            },
        }
    }

    trait ClampBox {
        fn clamp_box(self) -> Self;
    }

    impl ClampBox for S {
        /// A box whose sides stay positive after rounding at its coordinates' magnitude.
        fn clamp_box(self) -> Self {
            match self {
                S::Box { min, max } => S::Box {
                    min: min.map(|x| x.clamp(-1e12, 1e12)),
                    max: core::array::from_fn(|i| {
                        let hi = max[i].clamp(-1e12, 1e12);
                        if hi > min[i].clamp(-1e12, 1e12) {
                            hi
                        } else {
                            1e12
                        }
                    }),
                },
                other => other,
            }
        }
    }

    /// Points from the origin to the largest doubles, and near the tree's own numbers.
    fn probes(rng: &mut Rng) -> Vec<DVec3> {
        let ends = [0.0, 1.0, 1e12, 1e100, 1e154, 2e154, 1e200, 1e300, f64::MAX];
        (0..40)
            .map(|_| {
                DVec3::from_array(core::array::from_fn(|_| {
                    let m = if rng.int(0, 1) == 0 {
                        ends[rng.int(0, ends.len() - 1)]
                    } else {
                        magnitude(rng)
                    };
                    if rng.int(0, 1) == 0 { m } else { -m }
                }))
            })
            .collect()
    }

    /// The sign of a tree of set operations over bounded leaves and cylinders, from its leaves'
    /// own formulas (an overflowing square is far outside): `Some(true)` inside, `None` on a
    /// leaf's zero set or where a formula gives NaN.
    fn sign(spec: &S, p: [f64; 3]) -> Option<bool> {
        let d2 = |c: &[f64], skip: Option<usize>| -> f64 {
            (0..3)
                .filter(|&i| Some(i) != skip)
                .map(|i| (p[i] - c[i]) * (p[i] - c[i]))
                .sum()
        };
        let leaf = |v: f64| (v != 0.0 && !v.is_nan()).then_some(v > 0.0);
        match spec {
            S::Sphere { center, radius } => leaf(radius * radius - d2(center, None)),
            S::Cylinder {
                center,
                axis,
                radius,
            } => leaf(radius * radius - d2(center, Some(axis.index()))),
            S::Torus {
                center,
                axis,
                major,
                minor,
            } => {
                let a = axis.index();
                let ring = d2(center, Some(a)).sqrt() - major;
                let along = p[a] - center[a];
                leaf(minor * minor - ring * ring - along * along)
            }
            S::Box { min, max } => {
                let inside = (0..3).all(|i| min[i] < p[i] && p[i] < max[i]);
                let on = (0..3).any(|i| min[i] == p[i] || p[i] == max[i]);
                (!on).then_some(inside)
            }
            S::Union { of } => {
                let s: Option<Vec<bool>> = of.iter().map(|c| sign(c, p)).collect();
                s.map(|s| s.iter().any(|&b| b))
            }
            S::Intersection { of } => {
                let s: Option<Vec<bool>> = of.iter().map(|c| sign(c, p)).collect();
                s.map(|s| s.iter().all(|&b| b))
            }
            S::Difference { of } => {
                let s: Option<Vec<bool>> = of.iter().map(|c| sign(c, p)).collect();
                s.map(|s| s[0] && s[1..].iter().all(|&b| !b))
            }
            _ => None,
        }
    }

    /// Every accepted tree, however extreme its numbers, gives a finite `f` and gradient at every
    /// finite point, to the largest doubles; a tree of set operations has its leaves' Boolean
    /// sign there. (A union of spheres at 2e154 gave NaN, a huge box NaN everywhere, a scale of
    /// 1e-300 −inf.)
    #[test]
    fn trees_of_extreme_numbers_give_finite_right_signed_values() {
        let mut rng = Rng::new(41);
        let (mut trees, mut signs) = (0, 0);
        for round in 0..800 {
            let transforms = round % 2 == 0;
            let spec = extreme(&mut rng, 3, transforms);
            let Ok(ModelTree::Space(tree)) = ModelFile::from_spec(spec.clone()).to_tree() else {
                continue;
            };
            trees += 1;
            for p in probes(&mut rng) {
                let f = tree.f(p);
                assert!(f.is_finite(), "f = {f} at {p} of {spec:?}");
                let (fg, g) = tree.f_with_gradient(p);
                assert!(
                    fg.is_finite() && g.is_finite(),
                    "∇f = {g} at {p} of {spec:?}"
                );
                if !transforms && let Some(inside) = sign(&spec, p.to_array()) {
                    assert_eq!(f > 0.0, inside, "f = {f} at {p} of {spec:?}");
                    signs += 1;
                }
            }
            let grid = tree.f_grid([&[-1e300, 0.0, 7.0], &[-3.0, 1e12], &[f64::MAX, 1.0]]);
            assert!(grid.iter().all(|v| v.is_finite()), "{grid:?} of {spec:?}");
        }
        assert!(trees > 300 && signs > 3000, "{trees} trees, {signs} signs");
    }
}
