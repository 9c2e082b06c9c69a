//! The [`Modeler`]'s 3D view: its size, drawing, gestures and the screen positions of its
//! spheres and handles.

use super::*;

#[wasm_bindgen]
impl Modeler {
    /// Sizes the 3D view: CSS pixels and the device pixel ratio; returns the canvas size in device
    /// pixels.
    pub fn resize_3d(
        &mut self,
        viewer: &mut Viewer3,
        width: f64,
        height: f64,
        dpr: f64,
    ) -> Vec<u32> {
        self.view3.resize(&self.editor, width, height);
        viewer.fit_canvas(width, height, dpr)
    }

    /// Draws the 3D view.
    pub fn render_3d(&mut self, viewer: &mut Viewer3) {
        self.follow_parts();
        self.sync_cap();
        let scene = self.view3.scene(&self.editor);
        viewer.present(&scene);
    }

    /// Pointer pressed in the 3D view: `pan` for the right button; `shift` pans on empty space and
    /// gives the other drag mode on a control point. Returns whether a point was grabbed.
    pub fn pointer_down_3d(&mut self, x: f64, y: f64, pan: bool, shift: bool) -> bool {
        let grabbed = self
            .view3
            .pointer_down(&mut self.editor, DVec2::new(x, y), pan, shift);
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
            && let Err(e) = parts.begin_handle(&mut self.editor)
        {
            // Nothing to move: the gesture ends here.
            self.view3.pointer_up(&mut self.editor);
            web_sys::console::warn_1(&format!("bezsolid: {e}").into());
            return false;
        }
        // The contour view holds still from the start of the drag, as for its own drags.
        self.view2.sync(&self.editor);
        grabbed
    }

    /// Pointer moved in the 3D view; returns whether the camera or the model changed.
    pub fn pointer_move_3d(&mut self, x: f64, y: f64) -> bool {
        let changed = self.view3.pointer_move(&mut self.editor, DVec2::new(x, y));
        if let Some(at) = self.view3.take_section_drag()
            && let Some((a, _, (lo, hi))) = self.section_box()
        {
            // The plane dragged in 3D: the 2D view's section (and the cut) follow.
            let fraction = ((at - lo[a]) / (hi[a] - lo[a])).clamp(0.0, 1.0);
            if fraction.is_finite() {
                self.view2.set_section(Some(fraction));
                self.sync_cap();
            }
        }
        if let (Some((handle, amount)), Some(parts)) = (self.view3.take_handle(), &mut self.parts) {
            parts.drag_handle(handle, amount, &mut self.editor);
            self.follow_parts();
        }
        changed
    }

    /// Pointer released in the 3D view.
    pub fn pointer_up_3d(&mut self) {
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
        {
            parts.end_handle();
        }
        self.view3.pointer_up(&mut self.editor);
    }

    /// Whether a control point is being dragged (in either view).
    #[must_use]
    pub fn editing_3d(&self) -> bool {
        self.editor.dragging()
            || self.editor.volume_dragged().is_some()
            || self.view3.handle_dragged().is_some()
    }

    /// Whether a 3D gesture (orbit, pan or point drag) is under way.
    #[must_use]
    pub fn busy_3d(&self) -> bool {
        self.view3.busy()
    }

    /// Whether a control point's sphere is under CSS pixel `(x, y)` of the 3D view.
    #[must_use]
    pub fn hit_3d(&self, x: f64, y: f64) -> bool {
        let q = DVec2::new(x, y);
        self.view3.pick(&self.editor, q).is_some()
            || self.view3.over_handle(q)
            || self.view3.over_section(q)
    }

    /// The wheel over the 3D view: zooms.
    pub fn wheel_3d(&mut self, delta_y: f64) {
        self.view3.wheel(delta_y);
    }

    /// Two fingers on the 3D view: zoom by their spread's `scale` (now over before) and pan by
    /// their midpoint's move `(dx, dy)` in CSS pixels. Returns whether the camera moved.
    pub fn pinch_3d(&mut self, scale: f64, dx: f64, dy: f64) -> bool {
        self.view3.pinch(scale, DVec2::new(dx, dy))
    }

    /// Cancels the 3D gesture under way (a second finger came down): a point's drag puts the
    /// point back as Esc does; a handle's drag ends as one undo step; an orbit or pan stops.
    pub fn cancel_3d(&mut self) {
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
        {
            parts.end_handle();
        }
        self.view3.cancel(&mut self.editor);
    }

    /// The CSS pixel `[x, y]` of control point `index`'s sphere in the 3D view (`index` as in the
    /// model file), or `undefined`.
    #[must_use]
    pub fn sphere_screen_3d(&self, index: usize) -> Option<Vec<f64>> {
        self.view3
            .screen_of(&self.editor, index)
            .map(|q| q.to_array().to_vec())
    }

    /// The CSS pixel `[x, y]` of the selection's handle in the 3D view (0 moves, 1 turns about
    /// z, 2 scales), or `undefined` when the selection has none.
    #[must_use]
    pub fn handle_screen_3d(&self, which: u32) -> Option<Vec<f64>> {
        let handle = match which {
            0 => Handle::Move,
            1 => Handle::Turn,
            2 => Handle::Scale,
            _ => return None,
        };
        self.view3
            .handle_screen(handle)
            .map(|q| q.to_array().to_vec())
    }

    /// Frames the model in the 3D view again.
    pub fn fit_3d(&mut self) {
        self.view3.fit(&self.editor);
    }
}
