//! # bezsolid-fuzzing
//!
//! The fuzz targets of bezsolid as plain functions of bytes, one per target. Each decodes the bytes
//! into an input of the code it exercises, runs it, and checks what the code promises; it panics
//! only on a bug. Two things call them:
//!
//! - the cargo-fuzz project in `fuzz/` (its own workspace, built with nightly), whose targets are
//!   one line each: `cargo xtask fuzz [--seconds N] [TARGET…]` runs the campaigns;
//! - this crate's `replay` test, in every `cargo test --workspace`, which runs each file of
//!   `fuzz/seeds/<target>/` and `fuzz/regressions/<target>/` through its target on stable Rust.
//!
//! ```
//! // A link from the page, a model file, and a script: none is a bug.
//! bezsolid_fuzzing::link(b"#v1.AAAA");
//! bezsolid_fuzzing::model(br#"{"format": "bezsolid", "version": 1, "solid": {"kind": "plasm", "script": "1 + 1;"}}"#);
//! bezsolid_fuzzing::plasm(b"DEF SQR = ID * ID; SQR:3;");
//! ```
//!
//! The targets ([`TARGETS`]):
//!
//! | target | input | checks |
//! |---|---|---|
//! | [`link()`] | a share link (or, by the first byte, its deflated or inflated data) | round trip of what opens; validation |
//! | [`model()`] | a model file (JSON), every kind | JSON and link round trips; each kind built |
//! | [`mesh_import()`] | an OBJ, binary STL or ASCII STL file | parsers' promises; a mesh that reads is a closed outward manifold |
//! | [`plasm()`] | a PLaSM script | places of errors; finite results; the geometry and OBJ of the results |
//! | [`eval()`] | a patch or volume net and query points | `f` never NaN; `f ≤ 0` outside the control points' box |
//! | [`contour()`] | a small patch net, a resolution | closed polylines of finite vertices within the grid |
//! | [`mesh()`] | a small volume net, a resolution | a closed manifold of finite vertices within the grid |
//! | [`tree()`] | a 3D tree with numbers at the edges of the accepted range | finite `f` and gradient to `±f64::MAX`; sound bounds; a closed mesh or an inside point |
//! | [`hyperfun()`] | a HyperFun text | the strict reader's parse and evaluation: places of errors; a reused evaluator answers as a fresh one |

mod contour;
mod eval;
mod hyperfun;
mod input;
mod link;
mod mesh;
mod mesh_import;
mod model;
mod net;
mod plasm;
mod tree;

pub use contour::contour;
pub use eval::eval;
pub use hyperfun::hyperfun;
pub use link::link;
pub use mesh::mesh;
pub use mesh_import::mesh_import;
pub use model::model;
pub use plasm::{PLASM_STEPS, plasm};
pub use tree::tree;

/// A fuzz target: bytes in, a panic on a bug.
pub type Target = fn(&[u8]);

/// Every target by its name, which is also its folder under `fuzz/seeds/` and
/// `fuzz/regressions/` and its binary in `fuzz/`.
pub const TARGETS: &[(&str, Target)] = &[
    ("link", link),
    ("model", model),
    ("mesh_import", mesh_import),
    ("plasm", plasm),
    ("eval", eval),
    ("contour", contour),
    ("mesh", mesh),
    ("tree", tree),
    ("hyperfun", hyperfun),
];

/// The target of a name.
#[must_use]
pub fn target(name: &str) -> Option<Target> {
    TARGETS.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}
