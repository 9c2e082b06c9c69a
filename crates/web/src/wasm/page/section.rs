//! The [`Modeler`]'s true section of a volume: its plane across space or the parameters, its
//! cap in the 3D view, and the whole model of many solids it cuts.

use super::*;

#[wasm_bindgen]
impl Modeler {
    /// Draws the volume's true section by a plane across the control slice's axis (`x` across u,
    /// `y` across v, `z` across w), at `at` from 0 (the box's low face) to 1, instead of the slice
    /// (`on`), or the slice again. The section's control points are not edited: the slice's are,
    /// with the section off.
    pub fn set_section(&mut self, on: bool, at: f64) {
        let was = self.view2.section().is_some();
        self.view2.set_section(on.then_some(at));
        if was && !on && self.parts.is_none() {
            self.view2.set_scene(None);
        }
    }

    /// Cuts the 3D surface at the true section's plane (`on`, while the section is on), the cut
    /// face closed: the solid below the plane is shown (the whole model's, in a model of many
    /// solids).
    pub fn set_section_cap(&mut self, on: bool) {
        self.cap_on = on;
        self.sync_cap();
    }

    /// Gives the 3D view the section's plane as its cap, where the cap is on: where the plane is
    /// now (it follows the box as points move).
    pub(super) fn sync_cap(&mut self) {
        self.follow_space();
        let plane = self.section_plane();
        let cap = plane
            .filter(|_| self.cap_on)
            .map(|(axis, at, _)| (axis, at));
        self.view3.set_cap(cap);
        let shown = plane.and_then(|(axis, at, _)| {
            let (_, _, (lo, hi)) = self.section_box()?;
            Some(crate::view3d::SectionPlane { axis, at, lo, hi })
        });
        self.view3.set_section_plane(shown);
    }

    /// The whole 3D model of many solids as the true section cuts it, when one is open and
    /// compiled ([`Self::follow_space`]).
    pub(super) fn whole_section(&self) -> Option<crate::frame2d::TreeSection<'_>> {
        self.space
            .as_ref()
            .map(|(_, tree, bounds, mapped)| crate::frame2d::TreeSection {
                tree,
                bounds: *bounds,
                mapped: *mapped,
            })
    }

    /// Compiles what the views show of a 3D model of many solids for the true section, while one
    /// is shown across space (the section then cuts the whole model, in its box); forgets it
    /// otherwise.
    pub(super) fn follow_space(&mut self) {
        let wanted = self.view2.section().is_some()
            && !self.section_parameters
            && self.editor.volume().is_some();
        let Some(parts) = self
            .parts
            .as_ref()
            .filter(|p| wanted && p.outline().dimension() == 3)
        else {
            self.space = None;
            return;
        };
        let revision = self.editor.revision();
        if self.space.as_ref().is_some_and(|(r, ..)| *r == revision) {
            return;
        }
        let shown = parts
            .shown(&self.editor)
            .map(|s| ModelFile::from_spec(s).to_tree());
        self.space = match shown {
            Some(Ok(bezsolid_core::tree::ModelTree::Space(t))) => t
                .bounds()
                .filter(|(lo, hi)| (0..3).all(|a| lo[a] < hi[a]))
                .or_else(|| t.parts_box())
                .map(|(lo, hi)| {
                    let bounds = (DVec3::from_array(lo), DVec3::from_array(hi));
                    let mapped = parts.has_space_mapped_part(&self.editor);
                    (revision, t, bounds, mapped)
                }),
            _ => None,
        };
    }

    /// Where the true section's plane lies, from 0 (the box's low face) to 1; `undefined` with
    /// no section.
    #[must_use]
    pub fn section_fraction(&self) -> Option<f64> {
        self.view2.section()
    }

    /// Whether the section's plane is being dragged in the 3D view.
    #[must_use]
    pub fn section_dragged_3d(&self) -> bool {
        self.view3.section_dragged()
    }

    /// The CSS pixel `[x, y]` of the section plane's point at fractions `(s, t)` of its extent
    /// along its two other axes in the 3D view (`0` or `1` on its frame, which a drag moves);
    /// `undefined` with no section.
    #[must_use]
    pub fn section_screen_3d(&self, s: f64, t: f64) -> Option<Vec<f64>> {
        self.view3
            .section_screen(s, t)
            .map(|q| q.to_array().to_vec())
    }

    /// Puts the true section across the volume's parameters (`on`: the plane `u[axis] = t` of
    /// the parameter box, `f` at its points `S(u)`) or across space.
    pub fn set_section_parameters(&mut self, on: bool) {
        self.section_parameters = on;
        self.sync_cap();
    }

    /// The section across the parameters drawn, when one is: its axis (0 = u), the parameter
    /// it lies at, and the volume's box in the plane's axes (where the parameter square is shown).
    pub(super) fn parameter_plane(&self) -> Option<(usize, f64, (DVec2, DVec2))> {
        let (axis, t, (lo, hi)) = self.section_box().filter(|_| self.section_parameters)?;
        let [a, b] = plane_axes(axis);
        Some((
            axis,
            t,
            (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b])),
        ))
    }

    /// The section's axis (the slice's), where it lies from 0 to 1, and the volume's box.
    pub(super) fn section_box(&self) -> Option<(usize, f64, (glam::DVec3, glam::DVec3))> {
        let fraction = self.view2.section()?;
        let volume = self.editor.volume()?;
        let (axis, _) = self.editor.slice()?;
        // Across space in a model of many solids: the whole model's box.
        let bounds = match &self.space {
            Some((_, _, bounds, _)) if !self.section_parameters => *bounds,
            _ => volume.domain(),
        };
        Some((axis.index(), fraction, bounds))
    }

    /// The true section drawn across space, when one is: its axis, where it lies and the
    /// plane's box.
    pub(super) fn section_plane(&self) -> Option<(usize, f64, (DVec2, DVec2))> {
        let (axis, fraction, (lo, hi)) = self.section_box().filter(|_| !self.section_parameters)?;
        let at = lo[axis] + fraction * (hi[axis] - lo[axis]);
        let [a, b] = plane_axes(axis);
        Some((
            axis,
            at,
            (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b])),
        ))
    }
}
