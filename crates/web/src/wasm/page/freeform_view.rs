//! The Free-form mode's view for the page ([`FreeFormView`]).

use super::*;

orbit_view!(FreeFormView);

/// The Free-form mode ([`crate::freeform`]) for the page: its scene draws on the 3D view's
/// [`Viewer3`].
#[wasm_bindgen]
pub struct FreeFormView {
    state: FreeForm,
}

impl Default for FreeFormView {
    fn default() -> Self {
        Self::new()
    }
}

#[wasm_bindgen]
impl FreeFormView {
    /// The default scene (the blob minus a torus).
    #[wasm_bindgen(constructor)]
    #[must_use]
    pub fn new() -> Self {
        Self {
            state: FreeForm::new(),
        }
    }

    /// Operand `slot` (0: A, 1: B) becomes a built-in example.
    ///
    /// # Errors
    ///
    /// An unknown example or slot.
    pub fn set_example(&mut self, slot: usize, example: FreeFormExample) -> Result<(), JsError> {
        Ok(self.state.set_example(slot, example.try_into()?)?)
    }

    /// Operand `slot` becomes the mesh in the OBJ or STL file `bytes`, named `name`.
    ///
    /// # Errors
    ///
    /// What is wrong with the file (malformed, too large, not closed) or the slot.
    pub fn import_mesh(&mut self, slot: usize, name: &str, bytes: &[u8]) -> Result<(), JsError> {
        let mesh =
            bezsolid_core::mesh::read(bytes).map_err(|e| JsError::new(&format!("{name}: {e}")))?;
        self.state
            .set_mesh(slot, name, &mesh)
            .map_err(|e| JsError::new(&format!("{name}: {e}")))
    }

    /// Moves operand `slot` by `(x, y, z)`.
    ///
    /// # Errors
    ///
    /// An unknown slot or numbers that are not finite.
    pub fn set_offset(&mut self, slot: usize, x: f64, y: f64, z: f64) -> Result<(), JsError> {
        self.state
            .set_offset(slot, [x, y, z])
            .map_err(JsError::from)
    }

    /// `union`, `intersection` or `difference` over every solid, `complement` (of A alone), or
    /// `none` (A alone).
    ///
    /// # Errors
    ///
    /// An unknown operation.
    pub fn set_operation(&mut self, operation: Operation) -> Result<(), JsError> {
        Ok(self.state.set_combine(operation.try_into()?)?)
    }

    /// The operation as [`FreeFormView::set_operation`] names it, or `expression` for any other
    /// expression.
    #[must_use]
    pub fn operation(&self) -> String {
        self.state
            .combine()
            .map_or_else(|| "expression".into(), |c| Operation::from(c).text().into())
    }

    /// Combines the solids by an expression over their names: `|` union, `&` intersection,
    /// `-` difference, `!` complement, brackets.
    ///
    /// # Errors
    ///
    /// What is wrong with the text and where (the scene is kept).
    pub fn set_expression(&mut self, text: &str) -> Result<(), JsError> {
        Ok(self.state.set_expression(text)?)
    }

    /// The expression over the solids' names.
    #[must_use]
    pub fn expression(&self) -> String {
        self.state.expression()
    }

    /// The solids' names in the expression (`A`, `B`, …).
    #[must_use]
    pub fn letters(&self) -> Vec<String> {
        self.state.letters()
    }

    /// The number of solids.
    #[must_use]
    pub fn operand_count(&self) -> usize {
        self.state.operand_count()
    }

    /// Adds a built-in example beside the scene, joining the union; returns its slot.
    ///
    /// # Errors
    ///
    /// Past the most solids a model has.
    pub fn add_operand(&mut self, example: FreeFormExample) -> Result<usize, JsError> {
        Ok(self.state.add_operand(example.try_into()?)?)
    }

    /// Removes solid `slot` (and it from the expression).
    ///
    /// # Errors
    ///
    /// An unknown slot, or the last solid.
    pub fn remove_operand(&mut self, slot: usize) -> Result<(), JsError> {
        Ok(self.state.remove_operand(slot)?)
    }

    /// Places solid `slot`: offset, rotation about x, y, z in degrees, scale per axis.
    ///
    /// # Errors
    ///
    /// An unknown slot, or numbers that are refused (not finite, a zero scale).
    #[allow(clippy::too_many_arguments)] // nine numbers, as the panel's fields give them
    pub fn set_placement(
        &mut self,
        slot: usize,
        x: f64,
        y: f64,
        z: f64,
        rx: f64,
        ry: f64,
        rz: f64,
        sx: f64,
        sy: f64,
        sz: f64,
    ) -> Result<(), JsError> {
        Ok(self
            .state
            .set_placement(slot, [x, y, z], [rx, ry, rz], [sx, sy, sz])?)
    }

    /// Solid `slot`'s crease angle: edges whose faces turn by more than `degrees` stay sharp.
    ///
    /// # Errors
    ///
    /// An unknown slot or an angle outside 0 to 180.
    pub fn set_crease(&mut self, slot: usize, degrees: f64) -> Result<(), JsError> {
        Ok(self.state.set_crease(slot, degrees)?)
    }

    /// Solid `slot`'s crease angle in degrees, or `undefined`.
    #[must_use]
    pub fn crease(&self, slot: usize) -> Option<f64> {
        self.state.crease(slot)
    }

    /// Solid `slot`'s placement: offset, rotation (degrees) and scale, nine numbers, or
    /// `undefined`.
    #[must_use]
    pub fn placement(&self, slot: usize) -> Option<Vec<f64>> {
        self.state
            .placement(slot)
            .map(|(o, r, s)| [o, r, s].concat())
    }

    /// Begins dragging solid `slot` from CSS pixel `(x, y)` of the view: it moves in the plane
    /// facing the view. Returns whether it began.
    pub fn move_start(&mut self, slot: usize, x: f64, y: f64) -> bool {
        self.state.move_start(slot, glam::DVec2::new(x, y))
    }

    /// Moves the dragged solid under the pointer; returns whether it moved.
    pub fn move_to(&mut self, x: f64, y: f64) -> bool {
        self.state.move_to(glam::DVec2::new(x, y))
    }

    /// Ends the drag (one undo step).
    pub fn move_end(&mut self) {
        self.state.move_end();
    }

    /// Operand `slot`'s name (an example's or the imported file's), or `undefined`.
    #[must_use]
    pub fn operand_name(&self, slot: usize) -> Option<String> {
        self.state.operand(slot).map(|o| o.0)
    }

    /// Whether operand `slot` is a built-in example (else an imported mesh).
    #[must_use]
    pub fn operand_is_example(&self, slot: usize) -> bool {
        self.state.operand(slot).is_some_and(|o| o.2)
    }

    /// Operand `slot`'s offset `[x, y, z]`, or `undefined`.
    #[must_use]
    pub fn operand_offset(&self, slot: usize) -> Option<Vec<f64>> {
        self.state.operand(slot).map(|o| o.1.to_vec())
    }

    /// The triangles of each operand's mesh.
    #[must_use]
    pub fn triangle_counts(&self) -> Vec<u32> {
        self.state
            .boolean()
            .solids
            .iter()
            .map(|s| s.triangles().len() as u32)
            .collect()
    }

    /// What the view shows: `result`, `points` or `operands`.
    ///
    /// # Errors
    ///
    /// Another name.
    pub fn set_display(&mut self, display: FreeFormDisplay) -> Result<(), JsError> {
        self.state.set_display(display.try_into()?);
        Ok(())
    }

    /// The result surface's resolution at rest; returns the value taken.
    pub fn set_resolution(&mut self, cells: u32) -> u32 {
        self.state.set_resolution(cells as usize) as u32
    }

    /// The result surface's resolution at rest (cells along the longest side of an export).
    #[must_use]
    pub fn resolution(&self) -> u32 {
        self.state.resolution() as u32
    }

    /// Undoes the last change of an operand, its place or the operation.
    pub fn undo(&mut self) -> bool {
        self.state.undo()
    }

    /// Redoes the last undone change.
    pub fn redo(&mut self) -> bool {
        self.state.redo()
    }

    /// Whether there is a change to undo.
    pub fn can_undo(&self) -> bool {
        self.state.can_undo()
    }

    /// Whether there is an undone change to redo.
    pub fn can_redo(&self) -> bool {
        self.state.can_redo()
    }

    /// Forgets the undo and redo steps (after restoring the autosaved scene).
    pub fn forget_history(&mut self) {
        self.state.forget_history();
    }

    /// Changes whenever the scene does (for saving only what changed).
    #[must_use]
    pub fn revision(&self) -> f64 {
        self.state.revision() as f64
    }

    /// The fine surface wanted from the worker: `[revision, resolution]`, once.
    pub fn surface_request(&mut self) -> Option<Vec<f64>> {
        self.state
            .surface_request()
            .map(|(r, n)| vec![r as f64, n as f64])
    }

    /// The worker's fine surface; returns whether it was taken (not stale).
    pub fn set_surface(&mut self, revision: f64, resolution: u32, data: &[f32]) -> bool {
        self.state
            .set_surface(revision as u64, resolution as usize, data)
    }

    /// `[triangles, resolution]` of the result's surface drawn now, or `undefined`.
    #[must_use]
    pub fn surface_info(&self) -> Option<Vec<u32>> {
        self.state
            .surface_info()
            .map(|(t, r)| vec![t as u32, r as u32])
    }

    /// `[points in the partial chain or result, marked]` of the point mesh last drawn, or
    /// `undefined` before it is drawn.
    #[must_use]
    pub fn point_counts(&self) -> Option<Vec<u32>> {
        self.state
            .point_counts()
            .map(|(a, b)| vec![a as u32, b as u32])
    }

    /// The model file (JSON): indented, or compact when it holds an imported mesh (a 200 k-triangle
    /// mesh indented would pass the 16 MiB a model file may have).
    #[must_use]
    pub fn model_json(&self) -> String {
        crate::freeform::model_json(&self.state.model_file())
    }

    /// Opens a free-form model file or link.
    ///
    /// # Errors
    ///
    /// What is wrong with it (the scene is kept).
    pub fn open(&mut self, text: &str) -> Result<(), JsError> {
        let file = crate::freeform::read_file(text)?;
        self.state.open(&file).map_err(JsError::from)
    }

    /// The share link fragment `#v1.…`.
    ///
    /// # Errors
    ///
    /// When an imported mesh makes the model too large for a link (save the model file instead).
    pub fn link(&self) -> Result<String, JsError> {
        bezsolid_core::link::encode(&self.state.model_file()).map_err(|e| {
            JsError::new(&format!(
                "{e}. An imported mesh travels in the model file: use Export → Model file"
            ))
        })
    }
}
