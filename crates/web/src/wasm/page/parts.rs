//! The [`Modeler`]'s models of many solids: the outliner's edits, and keeping the editor's open
//! part and the tree in step.

use super::*;

#[wasm_bindgen]
impl Modeler {
    /// What the outliner shows of a model of many solids, as JSON ([`Parts::to_json`]: the
    /// rows, the selection, the part open in the editors, the selection's numbers), or
    /// `undefined` for a model of one solid.
    #[must_use]
    pub fn outline(&self) -> Option<String> {
        self.parts.as_ref().map(Parts::to_json)
    }

    /// Selects the node at `path` (child indices from the root); a Bézier part opens in the 2D
    /// and 3D editors.
    ///
    /// # Errors
    ///
    /// No such node.
    pub fn outline_select(&mut self, path: Vec<u32>) -> Result<(), JsError> {
        let path: Vec<usize> = path.into_iter().map(|i| i as usize).collect();
        self.with_parts(|parts, editor| parts.select(&path, editor))
    }

    /// Adds a part beside the selection (a model of one solid becomes a union of two); the new
    /// part is selected. One undo step.
    ///
    /// # Errors
    ///
    /// A kind of the other dimension, or a model past its caps.
    pub fn outline_add(&mut self, kind: PartKind) -> Result<(), JsError> {
        let kind = kind.try_into()?;
        self.with_parts(|parts, editor| parts.add(kind, editor))
    }

    /// The program and box of the selected part if it is a HyperFun program, JSON
    /// `{program, box}` (`box` as six numbers), else `undefined`.
    #[must_use]
    pub fn outline_hyperfun(&self) -> Option<String> {
        let (program, [lo, hi]) = self.parts.as_ref()?.selected_hyperfun()?;
        let bounds: Vec<f64> = lo.iter().chain(&hi).copied().collect();
        Some(serde_json::json!({"program": program, "box": bounds}).to_string())
    }

    /// Puts `program` in its box (`[x0, y0, z0, x1, y1, z1]`) in place of the selected
    /// HyperFun part. One undo step.
    ///
    /// # Errors
    ///
    /// A selection that is no HyperFun part, a box that is not one, or a program the tree
    /// refuses: nothing changes.
    pub fn outline_set_hyperfun(&mut self, program: &str, bounds: &[f64]) -> Result<(), JsError> {
        let &[x0, y0, z0, x1, y1, z1] = bounds else {
            return Err(JsError::new("a box is six numbers x0, y0, z0, x1, y1, z1"));
        };
        let bounds = [[x0, y0, z0], [x1, y1, z1]];
        self.with_parts(|parts, editor| parts.set_hyperfun(program, bounds, editor))
    }

    /// Adds a cell along `axis` to the selected Bézier part, after its last (the last cells
    /// mirrored across their face; a single patch or volume becomes a piecewise one). One undo
    /// step.
    ///
    /// # Errors
    ///
    /// No Bézier part selected, an axis the part lacks, or a net past what the editor takes.
    pub fn add_cell(&mut self, axis: ParamAxis) -> Result<(), JsError> {
        let axis = bezsolid_core::Axis::from(axis).index();
        self.with_parts(|parts, editor| parts.add_cell(axis, editor))
    }

    /// Removes the selected part's last cell along `axis` (one cell left everywhere: a single
    /// patch or volume again). One undo step.
    ///
    /// # Errors
    ///
    /// No Bézier part selected, or one cell along `axis`.
    pub fn remove_cell(&mut self, axis: ParamAxis) -> Result<(), JsError> {
        let axis = bezsolid_core::Axis::from(axis).index();
        self.with_parts(|parts, editor| parts.remove_cell(axis, editor))
    }

    /// Puts an operation or a transform around the selection. One undo step.
    ///
    /// # Errors
    ///
    /// A model past its caps.
    pub fn outline_wrap(&mut self, operation: PartOperation) -> Result<(), JsError> {
        let op = operation.try_into()?;
        self.with_parts(|parts, editor| parts.wrap(op, editor))
    }

    /// Removes the selection. One undo step.
    ///
    /// # Errors
    ///
    /// For the root.
    pub fn outline_remove(&mut self) -> Result<(), JsError> {
        self.with_parts(Parts::remove)
    }

    /// Moves the selection `by` places among its siblings. One undo step.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn outline_reorder(&mut self, by: i32) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.reorder(by as isize, editor))
    }

    /// Names the selection (an empty name takes a shown part's name away). One undo step.
    ///
    /// # Errors
    ///
    /// A name past 256 bytes.
    pub fn outline_rename(&mut self, name: &str) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.rename(name, editor))
    }

    /// Hides the selection from the views, or shows it again (the model and its exports keep
    /// it). One undo step.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn outline_hide(&mut self) -> Result<(), JsError> {
        self.with_parts(Parts::toggle_hidden)
    }

    /// The model file (JSON) of what the views show: the model, less the hidden parts of a model
    /// of many solids (what the worker meshes for the 3D view); `undefined` when all is hidden.
    #[must_use]
    pub fn view_json(&self) -> Option<String> {
        let shown = match &self.parts {
            Some(parts) => parts.shown(&self.editor)?,
            None => document::model_file(&self.editor).solid,
        };
        // Cut at the section's plane: the model intersected with the half-space below it.
        let spec = match self.view3.cap() {
            Some(cap) => crate::view3d::capped(shown, cap),
            None => shown,
        };
        serde_json::to_string(&ModelFile::from_spec(spec)).ok()
    }

    /// Sets a number of the selection (`radius`, `center[0]`, `a0`, `t`, `translate[2]`, …);
    /// settings of one field in a row are one undo step.
    ///
    /// # Errors
    ///
    /// A field the node lacks or a value its rules refuse: nothing changes.
    pub fn outline_set(&mut self, field: &str, value: f64) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.set(field, value, editor))
    }
}

impl Modeler {
    /// Whether the editor holds the model, or the open Bézier part of a model of many solids
    /// (with none open, what it holds is not in the model: it is not edited).
    pub(super) fn part_open(&self) -> bool {
        self.parts.as_ref().is_none_or(|p| p.open().is_some())
    }

    /// Whether the 2D view shows points to pick: a part is open and no true section is drawn
    /// instead of its slice.
    pub(super) fn points_shown(&self) -> bool {
        self.part_open() && self.section_plane().is_none() && self.parameter_plane().is_none()
    }

    /// [`Self::part_open`], or the error that says what to do.
    pub(super) fn need_part(&self) -> Result<(), JsError> {
        if self.part_open() {
            Ok(())
        } else {
            Err(JsError::new(
                "select a Bézier part under Parts to edit its control points",
            ))
        }
    }

    /// Runs an edit of the model of many solids (a model of one solid becomes one first); on
    /// error nothing changes.
    pub(super) fn with_parts(
        &mut self,
        edit: impl FnOnce(&mut Parts, &mut Editor) -> Result<(), Error>,
    ) -> Result<(), JsError> {
        if self.editor.busy() {
            return Err(JsError::new("finish the drag first"));
        }
        let Some(mut parts) = self.parts.take() else {
            // The first edit of a model of one solid: on a copy, kept only if the edit is made.
            let mut editor = self.editor.clone();
            let mut parts = Parts::of_editor(&mut editor)?;
            edit(&mut parts, &mut editor)?;
            self.editor = editor;
            self.parts = Some(parts);
            self.follow_parts();
            return Ok(());
        };
        let result = edit(&mut parts, &mut self.editor);
        self.parts = Some(parts);
        self.follow_parts();
        Ok(result?)
    }

    /// Opens a model file: a model of many solids, or in one a model of one solid, replaces the
    /// whole model as one undo step of the tree; otherwise the editor opens it as before.
    pub(super) fn open_file(&mut self, file: ModelFile) -> Result<(), JsError> {
        if self.parts.is_none() && !file.solid.is_tree() {
            let solid = file.to_solid().map_err(Error::from)?;
            document::open(&mut self.editor, solid);
            self.view3.fit(&self.editor);
            return Ok(());
        }
        file.to_tree().map_err(Error::from)?;
        self.with_parts(|parts, editor| parts.replace_root(file.solid, editor))?;
        // The surface drawn is the previous model's: frame the new one by its bounds.
        self.view3.forget_surface();
        self.view3.fit(&self.editor);
        Ok(())
    }

    /// Replaces the open part by `scratch`'s model (a new grid; one undo step).
    pub(super) fn replace_part(&mut self, scratch: &Editor) -> Result<(), JsError> {
        let node = document::model_file(scratch).solid;
        self.with_parts(|parts, editor| parts.replace_open(node, editor))
    }

    /// Writes what the editor changed back into the tree, and brings the 3D view's frame of the
    /// tree (the part's placement, the selection's box, the model's box) up to date.
    pub(super) fn follow_parts(&mut self) {
        let Some(parts) = &mut self.parts else {
            self.plane = None;
            return;
        };
        parts.sync(&self.editor);
        let revision = self.editor.revision();
        if parts.outline().dimension() == 2
            && self.plane.as_ref().is_none_or(|(r, ..)| *r != revision)
        {
            let shown = parts
                .shown(&self.editor)
                .map(|s| ModelFile::from_spec(s).to_tree());
            self.plane = match shown {
                Some(Ok(bezsolid_core::tree::ModelTree::Plane(t))) => {
                    let mapped = parts.has_space_mapped_part(&self.editor);
                    Some((revision, t, mapped))
                }
                _ => None,
            };
        } else if parts.outline().dimension() != 2 {
            self.plane = None;
        }
        if self.editor.busy() || self.whole_revision == Some(self.editor.revision()) {
            return;
        }
        self.whole_revision = Some(self.editor.revision());
        if parts.outline().dimension() != 3 {
            self.view3.set_whole(None);
            let placement = parts
                .open()
                .map_or(glam::DAffine2::IDENTITY, |p| parts.placement2(p));
            let scene = self
                .plane
                .as_ref()
                .and_then(|(_, t, _)| t.bounds())
                .map(|(lo, hi)| {
                    let (lo, hi) = (DVec2::from_array(lo), DVec2::from_array(hi));
                    if parts.open().is_none() {
                        return (lo, hi);
                    }
                    // The open part's domain, placed, is in sight too.
                    let (a, b) = self.editor.solid().domain();
                    [a, b, DVec2::new(a.x, b.y), DVec2::new(b.x, a.y)]
                        .map(|c| placement.transform_point2(c))
                        .iter()
                        .fold((lo, hi), |(lo, hi), &c| (lo.min(c), hi.max(c)))
                });
            self.view2.set_scene(scene);
            self.view2.set_placement(placement);
            return;
        }
        self.view2.set_scene(None);
        self.view2.set_placement(glam::DAffine2::IDENTITY);
        let first = self.view3.whole().is_none();
        let open = parts.open();
        let bounds = match parts.tree(&self.editor) {
            Ok(bezsolid_core::tree::ModelTree::Space(t)) => t
                .bounds()
                .map(|(lo, hi)| (glam::DVec3::from_array(lo), glam::DVec3::from_array(hi))),
            _ => None,
        };
        let whole = Whole {
            placement: open.map_or(glam::DAffine3::IDENTITY, |p| parts.placement(p)),
            part: open.is_some() && self.editor.volume().is_some(),
            frame: parts.bounds_of(parts.outline().selected(), &self.editor),
            bounds,
            handles: open.is_none(),
            shown: parts.shown(&self.editor).is_some(),
        };
        self.view3.set_whole(Some(whole));
        if first {
            self.view3.fit(&self.editor);
        }
    }
}
