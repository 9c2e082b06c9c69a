//! Moving an operand by dragging it in the 3D view: in the plane through its centre that faces
//! the view, one undo step for the whole drag.

use glam::{DVec2, DVec3};

use super::{FreeForm, Snapshot};

#[derive(Clone, Debug)]
pub(super) struct Moving {
    slot: usize,
    before: Snapshot,
    offset: DVec3,
    normal: DVec3,
    grab: DVec3,
}

impl FreeForm {
    /// Begins a drag that moves operand `slot` in the plane through its centre facing the view,
    /// from CSS pixel `q` of the 3D view. Returns whether it began.
    pub fn move_start(&mut self, slot: usize, q: DVec2) -> bool {
        let Some(o) = self.operands.get(slot) else {
            return false;
        };
        let Some(s) = self.boolean.solids.get(slot) else {
            return false;
        };
        let (lo, hi) = s.bounds();
        let center = (lo + hi) / 2.0;
        let size = self.orbit.size();
        let (_, normal) = self.orbit.ray(size / 2.0);
        let Some(grab) = on_plane(self.orbit.ray(q), center, normal) else {
            return false;
        };
        self.moving = Some(Moving {
            slot,
            before: self.snapshot(),
            offset: DVec3::from_array(o.offset),
            normal,
            grab,
        });
        true
    }

    /// Moves the operand being dragged so that the point first grabbed follows CSS pixel `q`.
    /// Returns whether it moved.
    pub fn move_to(&mut self, q: DVec2) -> bool {
        // The drag's numbers only: its undo step holds the operands, meshes and all.
        let Some((slot, start, normal, grab)) = self
            .moving
            .as_ref()
            .map(|m| (m.slot, m.offset, m.normal, m.grab))
        else {
            return false;
        };
        let Some(at) = on_plane(self.orbit.ray(q), grab, normal) else {
            return false;
        };
        let offset = (start + (at - grab)).to_array();
        let Some((_, rotate, scale)) = self.placement(slot) else {
            return false;
        };
        let revision = self.revision;
        self.place(slot, offset, rotate, scale).is_ok() && self.revision != revision
    }

    /// Ends the drag: the move is one undo step.
    pub fn move_end(&mut self) {
        if let Some(m) = self.moving.take() {
            self.record(m.before);
        }
    }

    /// Whether an operand is being dragged.
    #[must_use]
    pub fn is_moving(&self) -> bool {
        self.moving.is_some()
    }
}

/// Where the ray `(origin, dir)` meets the plane through `p` with normal `n`, in front of the
/// origin.
fn on_plane((origin, dir): (DVec3, DVec3), p: DVec3, n: DVec3) -> Option<DVec3> {
    let d = dir.dot(n);
    if d.abs() < 1e-9 {
        return None;
    }
    let t = (p - origin).dot(n) / d;
    (t > 0.0 && t.is_finite()).then(|| origin + dir * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bezsolid_core::model::SolidSpec;

    #[test]
    fn solids_are_placed_by_numbers_and_by_dragging() {
        let mut f = FreeForm::new();
        f.set_placement(1, [0.0, 0.0, 0.35], [90.0, 0.0, 0.0], [1.0, 1.0, 2.0])
            .unwrap();
        assert_eq!(
            f.placement(1),
            Some(([0.0, 0.0, 0.35], [90.0, 0.0, 0.0], [1.0, 1.0, 2.0]))
        );
        let file = f.model_file();
        assert!(matches!(&file.solid, SolidSpec::Esc { operands, .. }
            if operands[1].rotate == Some([90.0, 0.0, 0.0]) && operands[1].scale == Some([1.0, 1.0, 2.0])));
        // A zero scale is refused and the scene kept.
        assert!(
            f.set_placement(1, [0.0; 3], [0.0; 3], [0.0, 1.0, 1.0])
                .is_err()
        );
        assert_eq!(f.model_file(), file);
        // A drag moves the solid in the plane facing the view, as far as the pointer went there.
        f.resize(800.0, 600.0);
        let (lo, hi) = f.boolean().solids[1].bounds();
        let center = (lo + hi) / 2.0;
        let q0 = f.orbit.screen_of(center).unwrap();
        assert!(f.move_start(1, q0));
        assert!(f.move_to(q0 + DVec2::new(80.0, -40.0)));
        assert!(f.move_to(q0 + DVec2::new(120.0, 0.0)));
        f.move_end();
        let moved = DVec3::from_array(f.placement(1).unwrap().0);
        let (lo, hi) = f.boolean().solids[1].bounds();
        let q1 = f.orbit.screen_of((lo + hi) / 2.0).unwrap();
        assert!(
            (q1 - (q0 + DVec2::new(120.0, 0.0))).length() < 1.0,
            "{q1} under the pointer"
        );
        assert!(moved != DVec3::new(0.0, 0.0, 0.35));
        // One undo step for the whole drag.
        assert!(f.undo());
        assert_eq!(f.model_file(), file);
    }
}
