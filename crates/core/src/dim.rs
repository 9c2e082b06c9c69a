//! The dimensions bezsolid models in, as types: [`Dim<2>`] (patches in the plane) and [`Dim<3>`]
//! (volumes in space), each with the glam types of its points.
//!
//! Code generic over the dimension takes `const D: usize` with the bound `Dim<D>: Dimension<D>`
//! and speaks of [`Point<D>`] (`DVec2`, `DVec3`) and [`Control<D>`] (`DVec3`, `DVec4`: the
//! coordinates with ξ last).

use core::fmt;
use core::ops::{Add, Div, Mul, Sub};

use glam::{DVec2, DVec3, DVec4};

use crate::tensor::ControlPoint;

/// The dimension `D` as a type, to hang its point types on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Dim<const D: usize>;

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Dim<2> {}
    impl Sealed for super::Dim<3> {}
}

/// The point types of a dimension, and the moves between them and arrays. Implemented for
/// [`Dim<2>`] and [`Dim<3>`] only.
pub trait Dimension<const D: usize>: sealed::Sealed {
    /// A point (or vector) in space: `DVec2` or `DVec3`.
    type Point: Copy
        + fmt::Debug
        + PartialEq
        + Add<Output = Self::Point>
        + Sub<Output = Self::Point>
        + Mul<Output = Self::Point>
        + Div<Output = Self::Point>
        + Mul<f64, Output = Self::Point>;
    /// A control point of a solid, its coordinates with ξ last: `DVec3` or `DVec4`.
    type Control: ControlPoint;
    /// The point of an array of coordinates.
    fn point(x: [f64; D]) -> Self::Point;
    /// The coordinates of a point.
    fn coords(p: Self::Point) -> [f64; D];
    /// The control point at `x` with value `xi`.
    fn control(x: [f64; D], xi: f64) -> Self::Control;
    /// A control point's coordinates and ξ.
    fn split(c: Self::Control) -> ([f64; D], f64);
}

/// A point in `D`-space: `DVec2` or `DVec3`.
pub type Point<const D: usize> = <Dim<D> as Dimension<D>>::Point;

/// A control point of a `D`-dimensional solid, `(x, y, ξ)` or `(x, y, z, ξ)`.
pub type Control<const D: usize> = <Dim<D> as Dimension<D>>::Control;

impl Dimension<2> for Dim<2> {
    type Point = DVec2;
    type Control = DVec3;
    #[inline]
    fn point(x: [f64; 2]) -> DVec2 {
        DVec2::from_array(x)
    }
    #[inline]
    fn coords(p: DVec2) -> [f64; 2] {
        p.to_array()
    }
    #[inline]
    fn control([x, y]: [f64; 2], xi: f64) -> DVec3 {
        DVec3::new(x, y, xi)
    }
    #[inline]
    fn split(c: DVec3) -> ([f64; 2], f64) {
        ([c.x, c.y], c.z)
    }
}

impl Dimension<3> for Dim<3> {
    type Point = DVec3;
    type Control = DVec4;
    #[inline]
    fn point(x: [f64; 3]) -> DVec3 {
        DVec3::from_array(x)
    }
    #[inline]
    fn coords(p: DVec3) -> [f64; 3] {
        p.to_array()
    }
    #[inline]
    fn control([x, y, z]: [f64; 3], xi: f64) -> DVec4 {
        DVec4::new(x, y, z, xi)
    }
    #[inline]
    fn split(c: DVec4) -> ([f64; 3], f64) {
        ([c.x, c.y, c.z], c.w)
    }
}
