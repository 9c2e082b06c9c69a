//! # bezsolid-core
//!
//! The geometry of bezsolid: solids defined by Bézier patches (2D) and volumes (3D) by extended space
//! mapping (Schmitt, Pasko, Schlick). A patch `S(u, v) = Σ_i Σ_j P_ij B_i^n(u) B_j^m(v)` with control
//! points `P_ij = (x, y, ξ)` defines the 2D solid `f(x, y) ≥ 0`, where `f(x, y) = S_ξ(u, v)` at the
//! parameters with `(S_x, S_y)(u, v) = (x, y)`, clipped to the parameter square by R-functions.
//!
//! A tour, from the bottom up:
//!
//! - [`bernstein`]: binomials and the Bernstein basis `B_i^n(t) = C(n,i) tⁱ(1−t)ⁿ⁻ⁱ`.
//! - [`BezierCurve`]: curves of any degree: evaluation, derivative, de Casteljau split, elevation.
//! - [`Patch`], [`Volume`]: tensor-product Bézier patches and volumes of any degree (1 to
//!   [`MAX_DEGREE`]) per axis: evaluation in basis form and by de Casteljau, partial derivatives, de
//!   Casteljau split, degree elevation, bounds, and grid evaluation one axis at a time.
//! - [`triangular`]: triangular Bézier patches of any degree.
//! - [`rfunc`]: the R-function intersection `f1 & f2 = f1 + f2 − √(f1² + f2²)` and the functional
//!   clipping `F_s(u, v) = F_b(u) & F_b(v)`, `F_b(t) = t(1 − t)` of the paper's §3.3.1.
//! - [`Solid2`]: a patch solid: `f(p)`, `∇f(p)`, function-mapping (ξ) and space-mapping (moved
//!   control points) edits, the paper's Fig. 9.
//! - [`Solid3`]: the same for a volume, `f(x, y, z) = S_ξ(u, v, w) & F_s(u, v, w)`, and its
//!   polygonization ([`Solid3::polygonize`]).
//! - [`inverse`]: the inverse of a space mapping: Bézier clipping for every preimage, the paper's
//!   spline-guess hybrid, a seeded Newton fast path, an injectivity certificate; folds give
//!   `f = max` over the preimages.
//! - [`contour`]: marching squares to closed polylines with the solid on their left; cross-sections of
//!   volumes.
//! - [`mesh`]: indexed meshes, a manifold marching cubes, manifold checks, and the STL, OBJ, PLY and
//!   SVG writers.
//! - [`hyperfun`]: HyperFun export.
//! - [`esc`]: free-form solids over triangle meshes (the second paper): PN triangles, extended
//!   simplicial chains, point-in-solid and Booleans.
//! - [`blend`]: transfinite Bézier and Hermite blending of maps (the third paper), and its tie to
//!   tensor-product patches and volumes.
//! - [`presets`]: Fig. 9, a blob, a ring and a fish.
//! - [`model`]: the model file of DESIGN §5 (serde derives behind the `serde` feature).
//! - `link` (feature `link`): share links, `#v1.` + base64url(deflate(postcard(model))), decoded
//!   with caps and typed errors.
//!
//! ```
//! use bezsolid_core::{Solid2, contour::{contour_grid, Grid2}};
//! use glam::DVec2;
//!
//! let solid = Solid2::fig9();
//! assert!(solid.f(DVec2::new(0.5, 0.5)) > 0.0); // the middle is inside
//! assert!(solid.f(DVec2::new(0.02, 0.02)) < 0.0); // a corner is outside
//! assert!(solid.f(DVec2::new(1.5, 0.5)) < 0.0); // clipping: negative outside the square
//!
//! let grid = Grid2::new(DVec2::splat(-0.1), DVec2::splat(1.1), 64, 64);
//! let loops = contour_grid(&grid, |p| solid.f(p), 1e-9);
//! assert_eq!(loops.len(), 1);
//! assert!(loops[0].closed);
//! ```
//!
//! ## Features
//!
//! - `serde`: `Serialize`/`Deserialize` for the [`model`] types, in the model file's JSON shape.
//! - `link`: the share-link codec (`link`), with `postcard`, `miniz_oxide` and `base64`.
//! - `std` (default): `std::error::Error` is implemented through `core::error::Error` either way; `std`
//!   makes glam use the platform's math instead of `libm`. Without it the crate is `no_std` + `alloc`
//!   (CI builds it so for `wasm32-unknown-unknown`).
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

extern crate alloc;
#[cfg(any(feature = "std", test))]
extern crate std;

pub mod bernstein;
pub mod blend;
pub mod contour;
mod curve;
mod dim;
pub mod esc;
pub mod hyperfun;
pub mod inverse;
mod lanes;
#[cfg(feature = "link")]
pub mod link;
mod math;
pub mod mesh;
pub mod model;
pub mod piecewise;
pub mod presets;
pub mod rfunc;
mod solid;
mod tensor;
pub mod tree;
pub mod triangular;

pub use bernstein::MAX_DEGREE;
pub use curve::BezierCurve;
pub use dim::{Control, Dim, Dimension, Point};
pub use solid::{INVERSE_ACCURACY, Solid, Solid2, Solid3, SolidError};
pub use tensor::{Axis, ControlPoint, Patch, PatchError, Tensor, Volume};

#[cfg(test)]
pub(crate) mod testutil;
