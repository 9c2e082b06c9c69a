//! The JavaScript face of the modeler, in two halves built as separate modules so that the page
//! fetches only what its first frame and editing need:
//!
//! - the page's module (feature `page`): [`start`] brings up wgpu on a canvas and returns a
//!   `Modeler` whose methods the page calls on input and on animation frames, with the 3D, Free-form
//!   and Script views; built twice, with WebGPU alone and with the WebGL2 fallback (feature
//!   `webgl`), and the page picks one before it downloads either;
//! - the tools' module (feature `tools`): the worker's `run_job` and the headless functions (node,
//!   and the page without workers), fetched when first used.
//!
//! Logic stays in the plain-Rust modules ([`crate::editor`], [`crate::view2d`], …); the choices
//! the page names (drag modes, axes, formats, operations, displays) are the enums of [`names`].

mod names;
#[cfg(feature = "page")]
mod page;
#[cfg(feature = "tools")]
mod tools;

#[cfg(feature = "page")]
pub use names::Backend;
pub use names::{
    DragMode, FreeFormDisplay, FreeFormExample, MeshFormat, Operation, ParamAxis, PartKind,
    PartOperation,
};
#[cfg(feature = "page")]
pub use page::*;
#[cfg(feature = "tools")]
pub use tools::*;

use wasm_bindgen::prelude::*;

// Small and wanted by both halves: which mode a file opens in, a script's file and link, the
// Script mode's prelude and examples.

/// Whether a model file or link holds a free-form model.
#[wasm_bindgen]
#[must_use]
pub fn is_free_form(text: &str) -> bool {
    crate::freeform::is_free_form(text)
}

/// The script of a model file or link, if it holds one.
#[wasm_bindgen]
#[must_use]
pub fn script_of(text: &str) -> Option<String> {
    crate::script::script_of(text)
}

/// The model file (JSON) of a script.
#[wasm_bindgen]
#[must_use]
pub fn script_model_json(script: &str) -> String {
    crate::script::model_json(script)
}

/// The share link's fragment (`#v1.…`) of a script.
///
/// # Errors
///
/// A script too long for a link.
#[wasm_bindgen]
pub fn script_link(script: &str) -> Result<String, JsError> {
    crate::script::link(script).map_err(JsError::from)
}

/// The program and box of a HyperFun model file or link, JSON `{program, box}` (`box` as six
/// numbers), if it is one.
#[wasm_bindgen]
#[must_use]
pub fn hyperfun_of(text: &str) -> Option<String> {
    crate::hyperfun::program_of(text)
}

/// Whether `text` is one of bezsolid's HyperFun exports that carries its model.
#[wasm_bindgen]
#[must_use]
pub fn hyperfun_carries_model(text: &str) -> bool {
    crate::hyperfun::carries_model(text)
}

/// The model file (JSON) of a HyperFun program in its box (`[x0, y0, z0, x1, y1, z1]`).
///
/// # Errors
///
/// A box that is not one, or a program too long.
#[wasm_bindgen]
pub fn hyperfun_model_json(program: &str, bounds: &[f64]) -> Result<String, JsError> {
    crate::hyperfun::model_json(program, bounds).map_err(JsError::from)
}

/// The share link's fragment (`#v1.…`) of a HyperFun program in its box.
///
/// # Errors
///
/// A box that is not one, or a program too long for a link.
#[wasm_bindgen]
pub fn hyperfun_link(program: &str, bounds: &[f64]) -> Result<String, JsError> {
    crate::hyperfun::link(program, bounds).map_err(JsError::from)
}

/// The prelude every script runs after (the paper's toolbox), JSON: `{names, text}`.
#[wasm_bindgen]
#[must_use]
pub fn plasm_prelude() -> String {
    serde_json::json!({
        "names": bezsolid_plasm::PRELUDE_NAMES,
        "text": bezsolid_plasm::prelude(),
    })
    .to_string()
}

/// The paper's examples, JSON: `[{id, title, source}]`.
#[wasm_bindgen]
#[must_use]
pub fn plasm_examples() -> String {
    let list: Vec<serde_json::Value> = bezsolid_plasm::scripts::EXAMPLES
        .iter()
        .map(|e| serde_json::json!({"id": e.id, "title": e.title, "source": e.source()}))
        .collect();
    serde_json::Value::Array(list).to_string()
}
