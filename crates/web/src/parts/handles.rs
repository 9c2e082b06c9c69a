//! Drags of the selection's handles in the 3D view: move, turn and scale, one undo step each.

use super::*;

impl Parts {
    /// Begins a drag of the selection's handle in the 3D view: a selection that is not a
    /// transform gets one around it first (it is then selected). The drag is one undo step.
    ///
    /// # Errors
    ///
    /// A 2D model, or a tree past the caps.
    pub fn begin_handle(&mut self, editor: &mut Editor) -> Result<(), Error> {
        if self.outline.dimension() != 3 {
            return Err(Error::new("handles move the parts of 3D models"));
        }
        self.sync(editor);
        let before = self.snapshot();
        if !matches!(
            self.outline.node(self.outline.selected()),
            Some(SolidSpec::Transform { .. })
        ) {
            let at = self.beside(editor);
            self.outline.wrap(Wrap::Transform, at)?;
            self.reload(editor)?;
        }
        let selected = self.outline.selected().to_vec();
        let Some((translate, rotate, scale)) =
            self.outline.node(&selected).and_then(transform_numbers)
        else {
            return Err(Error::new("the selection has no transform"));
        };
        let mut child = selected.clone();
        child.push(0);
        let pivot = self
            .local_bounds(&child, editor)
            .map_or(DVec3::ZERO, |(lo, hi)| 0.5 * (lo + hi));
        self.gesture = Some(HandleGesture {
            before,
            translate,
            rotate,
            scale,
            parent: self.placement(&selected),
            pivot,
        });
        self.last_set = None;
        Ok(())
    }

    /// Where the handle's drag has got to since it began: a move in space ([`Handle::Move`]),
    /// a turn about z in degrees (`amount.x`, [`Handle::Turn`]), or a scale factor (`amount.x`,
    /// [`Handle::Scale`]). A value the rules refuse is skipped.
    pub fn drag_handle(&mut self, handle: Handle, amount: DVec3, editor: &mut Editor) {
        let Some(g) = &self.gesture else { return };
        let set: Vec<(String, f64)> = match handle {
            Handle::Move => {
                let local = g.parent.matrix3.inverse() * amount;
                let to = g.translate + local;
                (0..3).map(|i| (format!("translate[{i}]"), to[i])).collect()
            }
            Handle::Turn | Handle::Scale => {
                let (mut rotate, mut scale) = (g.rotate, g.scale);
                match handle {
                    Handle::Turn => rotate[2] += amount.x,
                    _ => scale *= amount.x,
                }
                // The pivot stays where it was: t' = t + L·pivot − L'·pivot.
                let t = g.translate + linear(g.rotate, g.scale) * g.pivot
                    - linear(rotate, scale) * g.pivot;
                (0..3)
                    .flat_map(|i| {
                        [
                            (format!("translate[{i}]"), t[i]),
                            (format!("rotate[{i}]"), rotate[i]),
                            (format!("scale[{i}]"), scale[i]),
                        ]
                    })
                    .collect()
            }
        };
        let mut o = self.outline.clone();
        if set
            .iter()
            .all(|(f, v)| v.is_finite() && o.set(f, *v).is_ok())
        {
            self.outline = o;
            editor.touch();
            self.synced = editor.revision();
        }
    }

    /// Ends the handle's drag: one undo step if it changed the model.
    pub fn end_handle(&mut self) {
        if let Some(g) = self.gesture.take() {
            self.push(g.before);
        }
    }

    /// Whether a handle's drag is under way.
    #[must_use]
    pub fn handling(&self) -> bool {
        self.gesture.is_some()
    }
}
