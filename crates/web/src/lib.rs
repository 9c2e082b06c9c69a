//! # bezsolid-web
//!
//! The bezsolid modeler in the browser. The state of each view lives in plain Rust ([`app`]) and is
//! tested natively; the wasm-bindgen glue and the wgpu renderer exist only on `wasm32` and are the one
//! place that branches on the target.

pub mod app;
pub mod camera;
pub mod document;
pub mod freeform;
pub mod scene;
pub mod script;
pub mod view3d;

#[cfg(target_arch = "wasm32")]
mod render;
#[cfg(target_arch = "wasm32")]
mod render3d;
#[cfg(target_arch = "wasm32")]
pub mod wasm;
