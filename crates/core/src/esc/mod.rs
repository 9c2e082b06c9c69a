//! Free-form solids as extended simplicial chains (García, Ruiz de Miras, Feito): a closed triangle
//! mesh is smoothed into cubic PN triangles (Vlachos et al. 2001), and the solid they bound is the
//! chain `Σ sᵢ·Sᵢ + aᵢ·ffcᵢ` of one original simplex (tetrahedron to an apex) and one free-form cell
//! per triangle. A point is in the solid where the chain's associated function is 1; Booleans are
//! chain algebra at points.
//!
//! Meshes come from [`crate::mesh::read`] (OBJ, STL, PLY, validated, with caps) or [`examples`].
//!
//! - [`examples`]: the built-in solids (icosphere, torus, blob).
//! - [`pn`]: PN triangles and their normal field.
//! - [`predicates`]: exact orientation with a symbolic perturbation.
//! - [`ray`]: rays against patches and the walls between cells.
//! - [`chain`]: the chain, point-in-solid, and ray parity for comparison.
//! - [`mod@bool`]: Boolean expressions as chain algebra.
//! - [`draw`]: point meshes and surfaces of Boolean results.
//!
//! The types a caller needs are re-exported here: [`EscSolid`] (and [`EscOptions`],
//! [`DEFAULT_CREASE_ANGLE`]), [`Expr`] and [`Op`], [`Boolean`], [`Example`], [`PnSurface`].
//!
//! Edges of the mesh sharper than the crease angle stay sharp (a cube stays a cube, see [`pn`]),
//! and each shell (connected piece) of the mesh is turned to face the way its nesting says, out of
//! the solid, into a cavity ([`crate::mesh::orient_shells`]).
//!
//! ```
//! use bezsolid_core::esc::{EscSolid, Example};
//! use glam::DVec3;
//!
//! let ball = EscSolid::new(&Example::Icosphere.mesh()).unwrap();
//! assert!(ball.contains(DVec3::ZERO));
//! assert!(!ball.contains(DVec3::splat(0.9)));
//! ```

pub mod bool;
pub mod chain;
pub mod draw;
pub mod examples;
mod parts;
pub mod pn;
pub mod predicates;
pub mod ray;

pub use bool::{Expr, ExprError, Op};
pub use chain::{EscError, EscOptions, EscSolid, Stats};
pub use draw::{Boolean, PointMesh};
pub use examples::Example;
pub use pn::{DEFAULT_CREASE_ANGLE, PnSurface};

#[cfg(test)]
mod tests;
