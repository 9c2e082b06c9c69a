//! What the Bézier mode's panel shows, at one moment: one snapshot the page reads once per frame
//! ([`Panel`], as JSON), in place of a getter per field.

use serde::Serialize;

use crate::editor::{Editor, Mode};
use crate::frame2d::Frame;
use crate::view3d::View3;

/// The last 2D frame's figures the panel shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FrameFigures {
    /// The lowest and highest `f` sampled inside the domain (the legend's ends).
    pub range: [f64; 2],
    /// Pieces of the zero contour.
    pub contours: usize,
    /// The net may fold: the contour shows every sheet's zero lines.
    pub folded: bool,
    /// Pieces of the unclipped contour of `S_ξ` drawn (0 when it is not shown).
    pub unclipped: usize,
    /// The true section drawn: `[axis, at, area, across]` (axis 0 for x; `across` 1 for a
    /// section across the parameters, whose axis 0 is u, `at` a parameter and area a fraction
    /// of the parameter square, 0 across space).
    pub section: Option<[f64; 4]>,
}

impl From<&Frame> for FrameFigures {
    fn from(frame: &Frame) -> Self {
        Self {
            range: [frame.range.0, frame.range.1],
            contours: frame.contours.len(),
            folded: frame.folded,
            unclipped: frame.unclipped.len(),
            section: frame.section.map(|(axis, at, area)| {
                let across = if frame.section_in_parameters {
                    1.0
                } else {
                    0.0
                };
                [axis as f64, at, area, across]
            }),
        }
    }
}

/// The panel's snapshot.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Panel {
    /// The selected control point `[i, j]` of the patch edited.
    pub selected: Option<[usize; 2]>,
    /// Its `[x, y, ξ]`.
    pub point: Option<[f64; 3]>,
    /// The last frame's figures.
    pub frame: FrameFigures,
    /// The degree of the patch edited (the volume's slice when the model is one).
    pub degree: [usize; 2],
    /// The control points are moved off a regular grid.
    pub space_mapped: bool,
    /// The volume's degree, when the model is one.
    pub volume_degree: Option<[usize; 3]>,
    /// The slice edited: `[axis, index]` (axis 0 = u, 1 = v, 2 = w).
    pub slice: Option<[usize; 2]>,
    /// The cells of a piecewise model (the degrees above are then its global net's).
    pub cells: Option<crate::editor::Cells>,
    /// The surface drawn (a volume's, or a 3D model of many solids'): `[triangles, resolution]`.
    pub surface: Option<[usize; 2]>,
    /// Whether the surface drawn is of the model as it is (not the one before the last edit,
    /// drawn while the new one is being made).
    pub surface_current: bool,
    /// The contour stack drawn: its segments, and whether it is of the model as it is.
    pub stack: Option<(usize, bool)>,
    /// The plane the 3D surface is cut at: `(axis, at)` (axis 0 = x, 1 = y, 2 = z).
    pub cap: Option<(usize, f64)>,
    /// Undo and redo are possible.
    pub can_undo: bool,
    /// See `can_undo`.
    pub can_redo: bool,
    /// The drag mode: `"function"` or `"space"`.
    pub mode: &'static str,
}

impl Panel {
    /// The snapshot of `editor`, its last 2D `frame` and its 3D view.
    #[must_use]
    pub fn of(editor: &Editor, frame: FrameFigures, view3: &View3) -> Self {
        let solid = editor.solid();
        Self {
            selected: editor.selected().map(|(i, j)| [i, j]),
            point: editor.selected_point().map(|p| p.to_array()),
            frame,
            degree: solid.degree(),
            space_mapped: match editor.volume() {
                Some(v) => v.is_space_mapped(),
                None => solid.is_space_mapped(),
            },
            volume_degree: editor.volume().map(bezsolid_core::Solid::degree),
            slice: editor.slice().map(|(axis, index)| [axis.index(), index]),
            cells: editor.cells().cloned(),
            surface: (editor.volume().is_some() || view3.whole().is_some())
                .then(|| view3.surface_info())
                .flatten()
                .map(|(t, r)| [t, r]),
            surface_current: view3.surface_is_current(editor),
            stack: view3.stack_info(editor),
            cap: view3.cap(),
            can_undo: editor.can_undo(),
            can_redo: editor.can_redo(),
            mode: match editor.mode() {
                Mode::Function => "function",
                Mode::Space => "space",
            },
        }
    }

    /// The snapshot as JSON, as the page reads it.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bezsolid_core::Solid2;

    #[test]
    fn the_snapshot_follows_the_editor() {
        let mut editor = Editor::new(Solid2::fig9());
        let view3 = View3::new(&editor);
        let panel = Panel::of(&editor, FrameFigures::default(), &view3);
        assert_eq!(panel.selected, None);
        assert_eq!(panel.degree, [2, 2]);
        assert!(!panel.space_mapped && !panel.can_undo);
        assert_eq!(panel.volume_degree, None);
        editor.select(Some((1, 1)));
        editor.set_selected_xi(0.5).unwrap();
        editor.set_mode(Mode::Space);
        let panel = Panel::of(&editor, FrameFigures::default(), &view3);
        assert_eq!(panel.selected, Some([1, 1]));
        assert_eq!(panel.point, Some([0.5, 0.5, 0.5]));
        assert!(panel.can_undo && !panel.can_redo);
        assert_eq!(panel.mode, "space");
        editor.new_volume(3, 4, 5).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&Panel::of(&editor, FrameFigures::default(), &view3).to_json())
                .unwrap();
        assert_eq!(json["volume_degree"], serde_json::json!([2, 3, 4]));
        assert_eq!(json["slice"], serde_json::json!([2, 2]));
        assert_eq!(json["mode"], "space");
    }
}
