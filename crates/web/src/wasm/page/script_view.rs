//! The Script mode's view for the page ([`ScriptViewer`]).

use super::*;

orbit_view!(ScriptViewer);

/// The Script mode's view: the drawing of a script's run and an orbit camera.
#[wasm_bindgen]
#[derive(Default)]
pub struct ScriptViewer {
    state: crate::script::ScriptView,
}

#[wasm_bindgen]
impl ScriptViewer {
    /// An empty view.
    #[wasm_bindgen(constructor)]
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Shows a drawing made by [`headless_plasm`]; frames it if `refit` or the camera was not
    /// moved.
    ///
    /// # Errors
    ///
    /// Data that is not whole triangles.
    pub fn set_drawing(&mut self, floats: &[f32], refit: bool) -> Result<(), JsError> {
        self.state.set_drawing(floats, refit).map_err(JsError::from)
    }

    /// Triangles drawn.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.state.triangle_count()
    }
}
