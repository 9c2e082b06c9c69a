//! # bezsolid-web
//!
//! The bezsolid modeler in the browser. Everything but the GPU and the page lives in plain Rust and
//! is tested natively, one concept per module:
//!
//! - [`editor`]: the model, the selection, the drag under way and the undo history, which every view
//!   edits through;
//! - [`view2d`]: the 2D contour view's viewport and input; [`frame2d`]: what it draws;
//! - [`view3d`]: the 3D view of a patch or a volume; [`camera`]: the orbit camera every 3D view
//!   contains; [`scene`]: what a 3D view hands the renderer, and the cache of a surface drawn coarse
//!   now and fine from the worker;
//! - [`freeform`]: the Free-form mode; [`script`]: the Script mode; [`hyperfun`]: the HyperFun
//!   mode;
//! - [`outline`]: a model of many solids as the outliner edits it, a node at a time; [`parts`]:
//!   such a model in the page, its one undo history, and the Bézier part open in the editor;
//! - [`panel`]: what the Bézier mode's panel shows, one snapshot per frame;
//! - [`document`]: files, links and exports of the editor's model; [`jobs`]: the worker's protocol;
//! - [`error`]: the one error type;
//! - [`color`]: the colours the views share.
//!
//! The wasm-bindgen glue and the wgpu renderer exist only on `wasm32` and are the one place that
//! branches on the target.

pub mod camera;
pub mod color;
pub mod document;
pub mod editor;
pub mod error;
pub mod frame2d;
pub mod freeform;
pub mod history;
pub mod hyperfun;
pub mod jobs;
pub mod outline;
pub mod panel;
pub mod parts;
pub mod scene;
pub mod script;
pub mod view2d;
pub mod view3d;

#[cfg(all(target_arch = "wasm32", feature = "page"))]
mod render;
#[cfg(all(target_arch = "wasm32", feature = "page"))]
mod render3d;
#[cfg(target_arch = "wasm32")]
pub mod wasm;
