//! The 2D contour view's viewport and input, as plain Rust: the world box it shows (fitted to the
//! domain, held still once a point is dragged, zoomed and panned as maps are), CSS pixels to world
//! and back, picking, drags, the wheel, two-finger pinches and keys. Every edit goes through the [`Editor`]; what the view draws is built by
//! [`crate::frame2d`].

use glam::{DAffine2, DVec2};

use crate::editor::{Editor, Mode, XI_KEY_STEP};

/// Radius of a drawn control point, in CSS pixels.
pub const POINT_RADIUS: f64 = 7.0;
/// How far from a control point's centre a click still picks it, in CSS pixels.
pub const PICK_RADIUS: f64 = 14.0;
/// ξ change per CSS pixel of vertical drag: 120 px move a point by one unit of ξ.
pub const XI_PER_PIXEL: f64 = 1.0 / 120.0;
/// Empty border around the domain box, as a fraction of its larger side.
const MARGIN: f64 = 0.14;
/// Zoom: the world units per CSS pixel are multiplied by `exp(deltaY · ZOOM_PER_WHEEL)` (a notch of
/// 100 is ×1.105; wheel up zooms in), as the 3D camera's wheel; one event does at most ×e.
const ZOOM_PER_WHEEL: f64 = 0.001;
/// The closest zoom: the fitted picture magnified this many times.
pub const MAX_ZOOM: f64 = 200.0;
/// The farthest zoom: the fitted picture this many times smaller (1/20).
pub const MIN_ZOOM: f64 = 0.05;
/// How far the view's centre may go from the fitted one, in fitted viewport sizes: at the farthest
/// zoom (20 fitted viewports across) the domain can still be brought back into sight.
const PAN_REACH: f64 = 20.0;
/// The most one pinch step changes the zoom (a jump of the fingers' spread is not a zoom).
const PINCH_STEP: f64 = 5.0;

/// The 2D view: its viewport, the world box it holds still, and the pointer of a drag it began.
#[derive(Clone, Debug)]
pub struct View2 {
    /// The view held still (centre, world units per CSS pixel) once a point has been dragged or
    /// the view zoomed or panned: the picture does not jump when a space-mapping drag grows or
    /// shrinks the domain, and undo and redo give back exactly the pictures they were. `None`
    /// fits the domain; opening another model, a new grid and the F key go back to that.
    fixed: Option<(DVec2, f64)>,
    /// The editor's [`Editor::opened`] and [`Editor::drags`] when this view last looked.
    seen: (u64, u64),
    /// Viewport size in CSS pixels.
    size: DVec2,
    /// Device pixels per CSS pixel.
    dpr: f64,
    /// Where the pointer went down for a drag this view began, in CSS pixels.
    press: Option<DVec2>,
    /// The box to fit instead of the editor's domain: a 2D model of many solids' bounds with the
    /// open part's domain.
    scene: Option<(DVec2, DVec2)>,
    /// The editor's solid's coordinates to the view's (the transforms above a part of a 2D model
    /// of many solids; identity otherwise).
    placement: DAffine2,
    /// Esc has cleared the selection: the next Tab leaves the view instead of walking the points.
    releasing: bool,
    /// Whether the zero contour of `S_ξ` alone, unclipped, is drawn (dashed) beside the solid's.
    unclipped: bool,
    /// A volume's true section drawn instead of its control slice: where its plane lies across
    /// the slice's axis, from 0 (the box's low face) to 1.
    section: Option<f64>,
}

impl Default for View2 {
    fn default() -> Self {
        Self::new()
    }
}

impl View2 {
    /// A 640×480 view that fits the domain.
    #[must_use]
    pub fn new() -> Self {
        Self {
            fixed: None,
            seen: (0, 0),
            size: DVec2::new(640.0, 480.0),
            dpr: 1.0,
            press: None,
            releasing: false,
            scene: None,
            placement: DAffine2::IDENTITY,
            unclipped: false,
            section: None,
        }
    }

    /// Draws a volume's true section by the plane at `at` (0 to 1 across the box, along the
    /// control slice's axis) instead of the slice, or the slice again (`None`). The picture is
    /// fitted again when the section comes or goes.
    pub fn set_section(&mut self, at: Option<f64>) {
        let at = at.map(|t| {
            if t.is_finite() {
                t.clamp(0.0, 1.0)
            } else {
                0.5
            }
        });
        if at.is_some() != self.section.is_some() {
            self.fixed = None;
        }
        self.section = at;
    }

    /// See [`Self::set_section`].
    #[must_use]
    pub fn section(&self) -> Option<f64> {
        self.section
    }

    /// Draws the zero contour of `S_ξ` alone, unclipped and dashed, beside the solid's (or not):
    /// what the clipping cuts away, as the first paper's Figs. 3 and 5 show it.
    pub fn set_unclipped(&mut self, on: bool) {
        self.unclipped = on;
    }

    /// Whether the unclipped contour is drawn.
    #[must_use]
    pub fn unclipped(&self) -> bool {
        self.unclipped
    }

    /// Places the editor's solid in the view by `placement` (its coordinates to the view's): its
    /// net is drawn and picked there, and a space drag moves its points by the pointer's motion
    /// taken back into its coordinates.
    pub fn set_placement(&mut self, placement: DAffine2) {
        self.placement = placement;
    }

    /// The CSS pixel of the editor's solid's point `p` (in its own coordinates).
    #[must_use]
    pub fn part_to_screen(&self, editor: &Editor, p: DVec2) -> DVec2 {
        self.to_screen(editor, self.placement.transform_point2(p))
    }

    /// Fits `scene` instead of the editor's domain (`None`: the domain again); a view held still
    /// since a drag stays as it is.
    pub fn set_scene(&mut self, scene: Option<(DVec2, DVec2)>) {
        self.scene = scene;
    }

    /// Catches up with the editor: fits the domain again after another model was opened, and
    /// holds the picture still from the first drag since (begun in any view). Call before drawing.
    pub fn sync(&mut self, editor: &Editor) {
        let (opened, drags) = (editor.opened(), editor.drags());
        if opened != self.seen.0 {
            self.fixed = None;
        }
        if drags != self.seen.1 && self.fixed.is_none() {
            let (min, max) = self.view_box(editor);
            self.fixed = Some(((min + max) * 0.5, (max.x - min.x) / self.size.x));
        }
        self.seen = (opened, drags);
    }

    /// Sets the viewport size in CSS pixels and the device pixel ratio; sizes below 1 become 1.
    pub fn resize(&mut self, width: f64, height: f64, dpr: f64) {
        let ok = |x: f64, d: f64| if x.is_finite() && x >= 1.0 { x } else { d };
        self.size = DVec2::new(ok(width, 1.0), ok(height, 1.0));
        self.dpr = if dpr.is_finite() && dpr > 0.0 {
            dpr.clamp(0.25, 8.0)
        } else {
            1.0
        };
    }

    /// The viewport size in CSS pixels.
    #[must_use]
    pub fn size(&self) -> DVec2 {
        self.size
    }

    /// Device pixels per CSS pixel.
    #[must_use]
    pub fn dpr(&self) -> f64 {
        self.dpr
    }

    /// The target size in device pixels.
    #[must_use]
    pub fn device_size(&self) -> (u32, u32) {
        let d = (self.size * self.dpr).round().max(DVec2::ONE);
        (d.x as u32, d.y as u32)
    }

    /// The world box shown: the domain with a margin, widened to the viewport's aspect ratio (or
    /// the view held still, zoomed or panned).
    #[must_use]
    pub fn view_box(&self, editor: &Editor) -> (DVec2, DVec2) {
        let (centre, scale) = self.held(editor);
        let half = self.size * scale * 0.5;
        (centre - half, centre + half)
    }

    /// The fitted view: the domain's (or the scene's) centre, and the world units per CSS pixel
    /// that show it with a margin, whichever way the viewport is longer.
    fn fitted(&self, editor: &Editor) -> (DVec2, f64) {
        let (min, max) = self.scene.unwrap_or_else(|| editor.solid().domain());
        let extent = (max - min).max_element();
        let half = (max - min) * 0.5 + DVec2::splat(extent * MARGIN);
        // World units per CSS pixel: the larger of the two needs, so the box fits both ways.
        ((min + max) * 0.5, (2.0 * half / self.size).max_element())
    }

    /// The view shown: held still, or fitted.
    fn held(&self, editor: &Editor) -> (DVec2, f64) {
        self.fixed.unwrap_or_else(|| self.fitted(editor))
    }

    /// How many times the picture is magnified from the fitted one (1 when fitted).
    #[must_use]
    pub fn zoom(&self, editor: &Editor) -> f64 {
        self.fitted(editor).1 / self.held(editor).1
    }

    /// Holds the view still with world point `w` under CSS pixel `q` at `scale` world units per
    /// CSS pixel, the zoom kept within [`MIN_ZOOM`]…[`MAX_ZOOM`] of the fitted view and the
    /// centre within [`PAN_REACH`] viewports of it. Returns whether the view changed.
    fn place(&mut self, editor: &Editor, w: DVec2, q: DVec2, scale: f64) -> bool {
        let (fitted_centre, fitted_scale) = self.fitted(editor);
        if !(fitted_scale.is_finite() && fitted_scale > 0.0) {
            return false;
        }
        let scale = scale.clamp(fitted_scale / MAX_ZOOM, fitted_scale / MIN_ZOOM);
        let from_centre = DVec2::new(q.x - self.size.x * 0.5, self.size.y * 0.5 - q.y);
        // Finite inputs give a finite centre or an infinite one, never NaN; the clamp takes both.
        let reach = self.size * fitted_scale * PAN_REACH;
        let centre = (w - from_centre * scale).clamp(fitted_centre - reach, fitted_centre + reach);
        if !(centre.is_finite() && scale.is_finite()) || self.fixed == Some((centre, scale)) {
            return false;
        }
        self.fixed = Some((centre, scale));
        true
    }

    /// A CSS pixel kept within a few viewports of this one: pointers that wandered off (a finger
    /// dragged past the canvas) still count, and no product of pixels and scales overflows.
    fn near(&self, q: DVec2) -> DVec2 {
        q.clamp(-4.0 * self.size, 5.0 * self.size)
    }

    /// Zooms about CSS pixel `q` by a wheel `delta_y` (positive: out): the world point under `q`
    /// stays under it, as in maps. Refused during this view's drag and for a delta that is zero or
    /// not a number. Returns whether the view changed.
    pub fn zoom_at(&mut self, editor: &Editor, q: DVec2, delta_y: f64) -> bool {
        if self.press.is_some() || !q.is_finite() || !delta_y.is_finite() || delta_y == 0.0 {
            return false;
        }
        self.sync(editor);
        let q = self.near(q);
        let w = self.to_world(editor, q);
        let factor = (delta_y * ZOOM_PER_WHEEL).clamp(-1.0, 1.0).exp();
        self.place(editor, w, q, self.held(editor).1 * factor)
    }

    /// Two fingers moved: the world point under `centre` (their midpoint before, in CSS pixels)
    /// goes to `centre + pan` (their midpoint now), magnified by `scale` (their spread now over
    /// their spread before). Refused during this view's drag and for values that are not numbers
    /// or a `scale` that is not positive. Returns whether the view changed.
    pub fn pinch(&mut self, editor: &Editor, centre: DVec2, scale: f64, pan: DVec2) -> bool {
        if self.press.is_some()
            || !centre.is_finite()
            || !pan.is_finite()
            || !scale.is_finite()
            || scale <= 0.0
        {
            return false;
        }
        self.sync(editor);
        let from = self.near(centre);
        let w = self.to_world(editor, from);
        let scale = scale.clamp(1.0 / PINCH_STEP, PINCH_STEP);
        self.place(
            editor,
            w,
            self.near(from + pan),
            self.held(editor).1 / scale,
        )
    }

    /// Pans by `delta` CSS pixels (the picture follows the pointer). Returns whether the view
    /// changed.
    pub fn pan(&mut self, editor: &Editor, delta: DVec2) -> bool {
        self.pinch(editor, self.size * 0.5, 1.0, delta)
    }

    /// CSS pixel (y down, origin top-left) of a world point.
    #[must_use]
    pub fn to_screen(&self, editor: &Editor, p: DVec2) -> DVec2 {
        let (min, max) = self.view_box(editor);
        let t = (p - min) / (max - min);
        DVec2::new(t.x, 1.0 - t.y) * self.size
    }

    /// World point under a CSS pixel.
    #[must_use]
    pub fn to_world(&self, editor: &Editor, q: DVec2) -> DVec2 {
        let (min, max) = self.view_box(editor);
        let t = q / self.size;
        min + DVec2::new(t.x, 1.0 - t.y) * (max - min)
    }

    /// `f` at the world point under a CSS pixel.
    #[must_use]
    pub fn probe(&self, editor: &Editor, q: DVec2) -> f64 {
        editor.f(self.to_world(editor, q))
    }

    /// The control point whose disc is under the CSS pixel `q`, nearest first.
    #[must_use]
    pub fn pick(&self, editor: &Editor, q: DVec2) -> Option<usize> {
        editor
            .solid()
            .net()
            .points()
            .iter()
            .enumerate()
            .map(|(k, p)| (k, self.part_to_screen(editor, p.truncate()).distance(q)))
            .filter(|&(_, d)| d <= PICK_RADIUS)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// Pointer pressed at CSS pixel `q`: selects the point under it and starts dragging it, in the
    /// editor's mode, or the other one when `other_mode` (the modifier key) is held. Returns whether
    /// a point was grabbed (a press on empty space keeps the selection).
    pub fn pointer_down(&mut self, editor: &mut Editor, q: DVec2, other_mode: bool) -> bool {
        self.releasing = false;
        self.sync(editor);
        let Some(k) = self.pick(editor, q) else {
            return false;
        };
        let mode = if other_mode {
            editor.mode().other()
        } else {
            editor.mode()
        };
        editor.begin_drag(k, mode);
        self.sync(editor);
        self.press = editor.dragging().then_some(q);
        true
    }

    /// Pointer moved to CSS pixel `q`: while dragging in function mode, up raises ξ and down lowers
    /// it; in space mode the point follows the pointer. Returns whether the solid changed.
    pub fn pointer_move(&mut self, editor: &mut Editor, q: DVec2) -> bool {
        self.sync(editor);
        let (Some(start), Some((point, mode))) = (self.press, editor.drag_start()) else {
            return false;
        };
        match mode {
            Mode::Function => editor.drag_to(None, Some(point.z + (start.y - q.y) * XI_PER_PIXEL)),
            Mode::Space => {
                let moved = self.to_world(editor, q) - self.to_world(editor, start);
                let xy = point.truncate() + self.placement.matrix2.inverse() * moved;
                editor.drag_to(Some(xy), None)
            }
        }
    }

    /// Pointer released or cancelled: ends the drag (one undo step if it changed the net).
    pub fn pointer_up(&mut self, editor: &mut Editor) {
        self.press = None;
        editor.end_drag();
    }

    /// Cancels this view's drag, putting the point back as Esc does (a second finger came down:
    /// the gesture is a pinch, not an edit). Returns whether there was a drag.
    pub fn cancel_drag(&mut self, editor: &mut Editor) -> bool {
        if self.press.take().is_none() || !editor.dragging() {
            return false;
        }
        editor.cancel();
        true
    }

    /// Fits the view to the domain again (the F key): the zoom and the pan are undone.
    pub fn fit_view(&mut self) {
        self.fixed = None;
    }

    /// The wheel at CSS pixel `q`: over the selected point, or with `xi` held (the Alt key),
    /// changes its ξ ([`Editor::wheel`]); elsewhere zooms about `q` ([`Self::zoom_at`]), so that a
    /// user zooming never edits the model. Returns whether the solid changed.
    pub fn wheel(&mut self, editor: &mut Editor, q: DVec2, delta_y: f64, xi: bool) -> bool {
        let over = editor
            .selected_point()
            .is_some_and(|p| self.part_to_screen(editor, p.truncate()).distance(q) <= PICK_RADIUS);
        if xi || over {
            return editor.wheel(delta_y);
        }
        self.zoom_at(editor, q, delta_y);
        false
    }

    /// A key pressed while the view has focus (`key` as in `KeyboardEvent.key`). Returns whether the
    /// view used it (the page then prevents the browser's default). Tab and Shift+Tab walk through
    /// the points and let focus leave the view after the last (first) one, as a composite widget
    /// does; Esc then Tab leaves at once (as in a code editor, whose Tab indents).
    pub fn key(&mut self, editor: &mut Editor, key: &str, shift: bool) -> bool {
        if matches!(key, "Shift" | "Control" | "Alt" | "Meta") {
            return false; // the modifier of a Shift+Tab to come: Esc still lets it leave
        }
        let releasing = core::mem::take(&mut self.releasing);
        if key == "Tab" && releasing {
            return false;
        }
        let [n, m] = editor.solid().degree();
        let step = if shift {
            XI_KEY_STEP * 0.1
        } else {
            XI_KEY_STEP
        };
        match key {
            "Tab" => editor.select_next(shift),
            "ArrowLeft" | "ArrowRight" | "ArrowUp" | "ArrowDown" => {
                // The first arrow press selects the middle point; the next ones walk the grid.
                let Some((i, j)) = editor.selected() else {
                    editor.select(Some((n / 2, m / 2)));
                    return true;
                };
                let (i, j) = match key {
                    "ArrowLeft" => (i.saturating_sub(1), j),
                    "ArrowRight" => ((i + 1).min(n), j),
                    "ArrowDown" => (i, j.saturating_sub(1)),
                    _ => (i, (j + 1).min(m)),
                };
                editor.select(Some((i, j)));
                true
            }
            "PageUp" | "+" | "=" => editor.nudge(step),
            "PageDown" | "-" | "_" => editor.nudge(-step),
            "Escape" => {
                // Esc during a drag puts the point back; otherwise it clears the selection, and the
                // next Tab leaves the view.
                self.releasing = !editor.dragging();
                self.press = None;
                editor.cancel();
                true
            }
            "m" | "M" => {
                editor.set_mode(editor.mode().other());
                true
            }
            "f" | "F" => {
                self.fit_view();
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::diverging;
    use crate::editor::{Editor, MAX_POINTS_PER_SIDE};
    use crate::frame2d::{FieldImage, Frame, frame, outline};
    use bezsolid_core::{Axis, Solid2};
    use core::f64::consts::FRAC_PI_2;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The editor with its 2D view, composed as the page composes them; the editor's own methods
    /// through `Deref`.
    struct Pair {
        e: Editor,
        v: View2,
    }

    impl core::ops::Deref for Pair {
        type Target = Editor;
        fn deref(&self) -> &Editor {
            &self.e
        }
    }

    impl core::ops::DerefMut for Pair {
        fn deref_mut(&mut self) -> &mut Editor {
            &mut self.e
        }
    }

    impl Pair {
        fn to_screen(&self, p: DVec2) -> DVec2 {
            self.v.to_screen(&self.e, p)
        }
        fn to_world(&self, q: DVec2) -> DVec2 {
            self.v.to_world(&self.e, q)
        }
        fn view_box(&self) -> (DVec2, DVec2) {
            self.v.view_box(&self.e)
        }
        fn device_size(&self) -> (u32, u32) {
            self.v.device_size()
        }
        fn pointer_down(&mut self, q: DVec2, other_mode: bool) -> bool {
            self.v.pointer_down(&mut self.e, q, other_mode)
        }
        fn pointer_move(&mut self, q: DVec2) -> bool {
            self.v.pointer_move(&mut self.e, q)
        }
        fn pointer_up(&mut self) {
            self.v.pointer_up(&mut self.e);
        }
        /// The wheel with the modifier that changes ξ anywhere.
        fn wheel(&mut self, delta_y: f64) -> bool {
            self.v.wheel(&mut self.e, DVec2::ZERO, delta_y, true)
        }
        fn wheel_at(&mut self, q: DVec2, delta_y: f64) -> bool {
            self.v.wheel(&mut self.e, q, delta_y, false)
        }
        fn key(&mut self, key: &str, shift: bool) -> bool {
            self.v.key(&mut self.e, key, shift)
        }
        fn frame(&mut self) -> Frame {
            self.v.sync(&self.e);
            frame(&self.e, &self.v)
        }
    }

    fn view() -> Pair {
        let mut v = View2::new();
        v.resize(800.0, 600.0, 2.0);
        Pair {
            e: Editor::new(Solid2::fig9()),
            v,
        }
    }

    #[test]
    fn view_screen_and_world_round_trip_and_keep_aspect() {
        let v = view();
        let p = DVec2::new(0.3, 0.7);
        assert!((v.to_world(v.to_screen(p)) - p).length() < 1e-12);
        // Isotropic: a unit square in the world is a square on screen.
        let a = v.to_screen(DVec2::ZERO);
        let b = v.to_screen(DVec2::ONE);
        assert!(((b.x - a.x) - (a.y - b.y)).abs() < 1e-9);
        // The domain's centre is the viewport's centre.
        assert!((v.to_screen(DVec2::splat(0.5)) - DVec2::new(400.0, 300.0)).length() < 1e-9);
        assert_eq!(v.device_size(), (1600, 1200));
    }

    #[test]
    fn view_click_selects_and_drag_up_raises_xi() {
        let mut v = view();
        let centre = v.to_screen(DVec2::splat(0.5));
        let press = centre + DVec2::new(3.0, -2.0);
        assert!(v.pointer_down(press, false));
        assert_eq!(v.selected(), Some((1, 1)));
        let before = v.selected_xi().unwrap();
        let f_before = v.solid().f(DVec2::new(0.5, 0.25));
        assert!(v.pointer_move(press + DVec2::new(5.0, -60.0)));
        assert!((v.selected_xi().unwrap() - (before + 60.0 * XI_PER_PIXEL)).abs() < 1e-12);
        assert!(
            v.solid().f(DVec2::new(0.5, 0.25)) > f_before,
            "raising the centre grows the solid"
        );
        v.pointer_up();
        assert!(!v.pointer_move(centre));
        // A click on empty space keeps the selection.
        assert!(!v.pointer_down(DVec2::new(1.0, 1.0), false));
        assert_eq!(v.selected(), Some((1, 1)));
    }

    #[test]
    fn view_wheel_up_raises_selected_xi() {
        let mut v = view();
        assert!(!v.wheel(-100.0), "nothing selected");
        v.select(Some((0, 2)));
        let before = v.selected_xi().unwrap();
        assert!(v.wheel(-100.0));
        assert!((v.selected_xi().unwrap() - before - 0.1).abs() < 1e-12);
        assert!(!v.wheel(f64::NAN));
        // Over the selected point, without the modifier: ξ too, and the view stays.
        let at = v.to_screen(DVec2::new(0.0, 1.0)) + DVec2::new(5.0, -5.0);
        let shown = v.view_box();
        assert!(v.wheel_at(at, -100.0));
        assert!((v.selected_xi().unwrap() - before - 0.2).abs() < 1e-12);
        assert_eq!(v.view_box(), shown);
    }

    #[test]
    fn wheel_over_empty_space_zooms_about_the_pointer_and_keeps_the_model() {
        let mut v = view();
        v.select(Some((1, 1)));
        let model = v.solid().clone();
        let q = DVec2::new(130.0, 420.0);
        let under = v.to_world(q);
        assert!(!v.wheel_at(q, -300.0), "the solid did not change");
        assert_eq!(v.solid(), &model);
        assert!(!v.can_undo(), "a zoom is no undo step");
        assert!(
            (v.v.zoom(&v.e) - 0.3f64.exp()).abs() < 1e-12,
            "wheel up zooms in"
        );
        assert!(
            (v.to_world(q) - under).length() < 1e-12,
            "the point under the pointer stays"
        );
        // Wheel down zooms back out about another point, which stays too.
        let r = DVec2::new(700.0, 80.0);
        let under = v.to_world(r);
        assert!(!v.wheel_at(r, 300.0));
        assert!((v.v.zoom(&v.e) - 1.0).abs() < 1e-12);
        assert!((v.to_world(r) - under).length() < 1e-12);
        // A drag after a zoom holds the zoomed picture still.
        let shown = v.view_box();
        let centre = v.to_screen(DVec2::splat(0.5));
        assert!(v.pointer_down(centre, false));
        assert!(
            !v.wheel_at(DVec2::new(5.0, 5.0), -100.0),
            "no zoom mid-drag"
        );
        assert_eq!(v.view_box(), shown);
        v.pointer_up();
        assert_eq!(v.view_box(), shown);
        // F fits again: the zoom is gone.
        v.wheel_at(DVec2::new(5.0, 5.0), -500.0);
        assert!(v.v.zoom(&v.e) > 1.5);
        assert!(v.key("f", false));
        assert!((v.v.zoom(&v.e) - 1.0).abs() < 1e-12);
        assert!((v.to_screen(DVec2::splat(0.5)) - DVec2::new(400.0, 300.0)).length() < 1e-9);
    }

    #[test]
    fn zoom_is_clamped_and_never_makes_a_non_finite_view() {
        let mut v = view();
        let q = DVec2::new(10.0, 590.0);
        for _ in 0..100 {
            v.wheel_at(q, -1e9);
        }
        assert!(
            (v.v.zoom(&v.e) - MAX_ZOOM).abs() < 1e-9,
            "{}",
            v.v.zoom(&v.e)
        );
        for _ in 0..100 {
            v.wheel_at(q, 1e9);
        }
        assert!(
            (v.v.zoom(&v.e) - MIN_ZOOM).abs() < 1e-12,
            "{}",
            v.v.zoom(&v.e)
        );
        let shown = v.view_box();
        for bad in [0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!v.v.zoom_at(&v.e, q, bad));
        }
        assert!(!v.v.zoom_at(&v.e, DVec2::new(f64::NAN, 1.0), -100.0));
        assert_eq!(v.view_box(), shown);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(!v.v.pinch(&v.e, q, bad, DVec2::ONE), "scale {bad}");
        }
        assert!(!v.v.pinch(&v.e, q, 1.0, DVec2::new(f64::NAN, 0.0)));
        // Wild but finite input: pointers far away, huge pans and spreads, tiny and huge zooms.
        for (k, big) in [1e9, -1e9, 1e300, -1e300, f64::MAX, 1e-300]
            .into_iter()
            .enumerate()
        {
            let far = DVec2::new(big, -big);
            v.v.zoom_at(&v.e, far, big);
            v.v.pinch(&v.e, far, big.abs(), far);
            v.v.pinch(&v.e, q, 1.0 / big.abs(), -far);
            v.v.pan(&v.e, DVec2::splat(big));
            let (min, max) = v.view_box();
            assert!(
                min.is_finite() && max.is_finite() && max.x > min.x,
                "step {k}"
            );
            let z = v.v.zoom(&v.e);
            assert!(
                (MIN_ZOOM * 0.999..=MAX_ZOOM * 1.001).contains(&z),
                "zoom {z}"
            );
            assert!(v.to_world(q).is_finite() && v.to_screen(DVec2::ZERO).is_finite());
        }
        // Panned as far as it goes, F still brings the domain back.
        assert!(v.key("F", false));
        assert!((v.to_screen(DVec2::splat(0.5)) - DVec2::new(400.0, 300.0)).length() < 1e-9);
    }

    #[test]
    fn a_pinch_zooms_about_the_fingers_and_pans_with_them() {
        let mut v = view();
        let model = v.solid().clone();
        let mid = DVec2::new(300.0, 250.0);
        let under = v.to_world(mid);
        let pan = DVec2::new(40.0, -15.0);
        assert!(v.v.pinch(&v.e, mid, 2.0, pan));
        assert!(
            (v.v.zoom(&v.e) - 2.0).abs() < 1e-12,
            "fingers apart magnify"
        );
        assert!(
            (v.to_world(mid + pan) - under).length() < 1e-12,
            "the point between the fingers follows them"
        );
        // A pan alone: the picture follows the pointer.
        let p = v.to_screen(DVec2::splat(0.5));
        assert!(v.v.pan(&v.e, DVec2::new(-25.0, 10.0)));
        assert!((v.to_screen(DVec2::splat(0.5)) - (p + DVec2::new(-25.0, 10.0))).length() < 1e-9);
        assert!((v.v.zoom(&v.e) - 2.0).abs() < 1e-12);
        assert_eq!(v.solid(), &model);
        assert!(!v.can_undo());
        // Picking follows the zoomed picture.
        let corner = v.to_screen(DVec2::ONE);
        assert!(v.pointer_down(corner + DVec2::new(3.0, 3.0), false));
        assert_eq!(v.selected(), Some((2, 2)));
        assert!(!v.v.pinch(&v.e, mid, 2.0, pan), "no pinch mid-drag");
        v.pointer_up();
    }

    #[test]
    fn a_zoom_composes_with_a_placed_part() {
        let mut v = view();
        let placement =
            DAffine2::from_scale_angle_translation(DVec2::splat(0.5), 0.3, DVec2::new(0.2, -0.1));
        v.v.set_placement(placement);
        let local = DVec2::new(1.0, 0.0);
        let q = v.v.part_to_screen(&v.e, local);
        assert!(!v.wheel_at(q, -400.0), "nothing selected: a zoom");
        v.v.pinch(&v.e, q, 1.5, DVec2::ZERO);
        assert!(
            (v.v.part_to_screen(&v.e, local) - q).length() < 1e-9,
            "the part's point under the fingers stays: {} vs {q}",
            v.v.part_to_screen(&v.e, local)
        );
        // The placed point is picked where it is drawn, and the wheel over it when selected is ξ.
        assert!(v.pointer_down(q, false));
        assert_eq!(v.selected(), Some((2, 0)));
        v.pointer_up();
        let z = v.v.zoom(&v.e);
        assert!(v.wheel_at(q, -100.0));
        assert_eq!(v.v.zoom(&v.e), z);
    }

    #[test]
    fn a_second_finger_cancels_a_drag_back_to_where_it_began() {
        let mut v = view();
        let centre = v.to_screen(DVec2::splat(0.5));
        assert!(!v.v.cancel_drag(&mut v.e), "no drag");
        assert!(v.pointer_down(centre, false));
        assert!(v.pointer_move(centre - DVec2::new(0.0, 40.0)));
        assert!(v.v.cancel_drag(&mut v.e));
        assert!(!v.dragging());
        assert_eq!(v.solid(), &Solid2::fig9());
        assert!(!v.can_undo(), "a cancelled drag is no step");
        assert_eq!(v.selected(), Some((1, 1)), "the point stays selected");
        assert!(
            v.v.pinch(&v.e, centre, 1.5, DVec2::ZERO),
            "the pinch goes on"
        );
        v.pointer_up();
        assert!(!v.can_undo());
    }

    #[test]
    fn view_keys_walk_the_grid_and_release_focus() {
        let mut v = view();
        assert!(v.key("Tab", false));
        assert_eq!(v.selected(), Some((0, 0)));
        for _ in 0..8 {
            assert!(v.key("Tab", false));
        }
        assert_eq!(v.selected(), Some((2, 2)));
        assert!(!v.key("Tab", false), "focus leaves after the last point");
        assert!(v.key("ArrowLeft", false));
        assert!(v.key("ArrowDown", false));
        assert_eq!(v.selected(), Some((1, 1)));
        assert!(v.key("Escape", false));
        assert!(v.key("ArrowRight", false));
        assert_eq!(
            v.selected(),
            Some((1, 1)),
            "the first arrow selects the middle point"
        );
        assert!(v.key("ArrowRight", false));
        assert_eq!(v.selected(), Some((2, 1)));
        assert!(v.key("ArrowLeft", false));
        let xi = v.selected_xi().unwrap();
        assert!(v.key("PageUp", false));
        assert!(v.key("-", true));
        assert!((v.selected_xi().unwrap() - (xi + 0.1 - 0.01)).abs() < 1e-12);
        assert!(v.key("Escape", false));
        assert_eq!(v.selected(), None);
        assert!(!v.key("q", false));
        // Esc, then Tab: focus leaves at once, and the next Tab (focus back) walks again.
        assert!(v.key("Tab", false));
        assert_eq!(v.selected(), Some((0, 0)));
        assert!(v.key("Escape", false));
        assert!(!v.key("Tab", false), "Esc then Tab leaves the view");
        assert!(v.key("Tab", false));
        assert!(v.key("Escape", false));
        assert!(!v.key("Shift", true));
        assert!(!v.key("Tab", true), "Esc then Shift+Tab leaves too");
        assert!(v.key("Tab", true));
        assert_eq!(v.selected(), Some((2, 2)));
        // Another key between Esc and Tab keeps Tab walking.
        assert!(v.key("Escape", false));
        assert!(v.key("ArrowLeft", false));
        assert!(v.key("Tab", false));
    }

    #[test]
    fn view_rejects_non_finite_xi() {
        let mut v = view();
        assert!(v.set_selected_xi(1.0).is_err(), "nothing selected");
        v.select(Some((1, 1)));
        let before = v.selected_xi();
        assert!(v.set_selected_xi(f64::NAN).is_err());
        assert_eq!(v.selected_xi(), before);
        // ξ far past the model's size is refused, saying the bound; near it is taken.
        let limit = v.xi_limit();
        let message = v.set_selected_xi(1e9).unwrap_err().message().to_owned();
        assert!(
            message.contains("too far") && message.contains(&limit.to_string()),
            "{message}"
        );
        assert_eq!(v.selected_xi(), before);
        v.set_selected_xi(-limit).unwrap();
        assert!(!v.nudge(-0.1), "keys stop at the bound");
        assert!(!v.wheel(100.0), "and so does the wheel");
        assert_eq!(v.selected_xi(), Some(-limit));
        assert!(v.nudge(0.1), "back towards 0 is taken");
        // A model whose ξ is already far past the bound (a file, a link) opens, and its points
        // come back by keys and the wheel.
        let mut far =
            Editor::new(Solid2::regular([2, 2], DVec2::ZERO, DVec2::ONE, |_| 2e4).unwrap());
        far.select(Some((1, 1)));
        assert!(far.nudge(-0.1) && far.wheel(100.0));
        assert!(!far.nudge(0.2), "but not further out");
        assert!(far.set_selected_xi(3e4).is_err());
        v.select(Some((3, 0)));
        assert_eq!(v.selected(), None, "outside the grid");
    }

    #[test]
    fn frame_field_is_red_inside_blue_outside_with_one_contour() {
        let mut v = view();
        let frame = v.frame();
        let FieldImage {
            width,
            height,
            rgba,
        } = &frame.field;
        assert_eq!(rgba.len(), (*width * *height * 4) as usize);
        let at = |q: DVec2| {
            let x = (q.x / 800.0 * f64::from(*width)) as usize;
            let y = (q.y / 600.0 * f64::from(*height)) as usize;
            let k = (y * *width as usize + x) * 4;
            [rgba[k], rgba[k + 1], rgba[k + 2]]
        };
        let inside = at(v.to_screen(DVec2::splat(0.5)));
        assert!(inside[0] > 200 && inside[2] < 120, "red inside: {inside:?}");
        let outside = at(v.to_screen(DVec2::new(-0.12, -0.12)));
        assert!(
            outside[2] > 180 && outside[0] < 100,
            "blue outside: {outside:?}"
        );
        let corner = at(v.to_screen(DVec2::new(0.05, 0.05)));
        assert!(
            corner[2] > corner[0] + 20,
            "bluish in the square's corner: {corner:?}"
        );
        assert_eq!(frame.contours.len(), 1);
        assert!(frame.contours[0].closed);
        assert!(frame.range.0 < 0.0 && frame.range.1 > 0.0);
        assert!(!frame.shapes.is_empty() && frame.shapes.len().is_multiple_of(3));
        assert!(
            frame
                .shapes
                .iter()
                .all(|s| s.position.iter().all(|c| c.abs() <= 1.5))
        );
    }

    #[test]
    fn a_drag_is_one_undo_step_and_redo_reapplies_it() {
        let mut v = view();
        let original = v.solid().clone();
        assert!(!v.can_undo() && !v.undo());
        let centre = v.to_screen(DVec2::splat(0.5));
        assert!(v.pointer_down(centre, false));
        for dy in 1..=30 {
            v.pointer_move(centre - DVec2::new(0.0, f64::from(dy) * 2.0));
        }
        assert!(!v.can_undo(), "no undo in the middle of a drag");
        v.pointer_up();
        let dragged = v.solid().clone();
        assert_ne!(dragged, original);
        assert!(v.undo());
        assert_eq!(v.solid(), &original, "one step undoes the whole drag");
        assert!(!v.undo());
        assert!(v.redo());
        assert_eq!(v.solid(), &dragged);
        assert!(!v.redo());
        // A click that does not move the point is no step.
        assert!(v.pointer_down(centre, false));
        v.pointer_up();
        assert!(v.undo());
        assert_eq!(v.solid(), &original);
        // A new edit clears the redo stack.
        v.select(Some((0, 0)));
        assert!(v.key("PageUp", false));
        assert!(!v.can_redo());
    }

    #[test]
    fn a_placed_solid_is_picked_and_dragged_where_it_is_drawn() {
        let mut v = view();
        // Turned a quarter, doubled and moved, as a part under a transform of a 2D model.
        let placement =
            DAffine2::from_scale_angle_translation(DVec2::splat(2.0), FRAC_PI_2, DVec2::X);
        v.v.set_placement(placement);
        v.set_mode(Mode::Space);
        let local = DVec2::new(1.0, 1.0);
        let corner = v.v.part_to_screen(&v.e, local);
        assert!(v.pointer_down(corner, false));
        let target = corner + DVec2::new(40.0, -25.0);
        assert!(v.pointer_move(target));
        let p = v.selected_point().unwrap().truncate();
        assert!(
            (v.v.part_to_screen(&v.e, p) - target).length() < 1e-9,
            "the placed point is under the pointer"
        );
        v.pointer_up();
    }

    #[test]
    fn space_drag_moves_the_point_under_the_pointer_and_the_outline_follows() {
        let mut v = view();
        v.set_mode(Mode::Space);
        let corner = v.to_screen(DVec2::new(1.0, 1.0));
        let outline_before = outline(v.solid().net());
        assert!(v.pointer_down(corner, false));
        let target = corner + DVec2::new(40.0, -25.0);
        assert!(v.pointer_move(target));
        // The view holds still during the drag, so the point is under the pointer.
        let p = v.selected_point().unwrap();
        assert!((v.to_screen(p.truncate()) - target).length() < 1e-9);
        assert!(
            v.solid().inverse().is_some(),
            "a moved corner is a space mapping"
        );
        v.pointer_up();
        assert!(
            (v.to_screen(p.truncate()) - target).length() < 1e-9,
            "the view stays put after the drop"
        );
        let outline_after = outline(v.solid().net());
        assert_ne!(outline_before[1], outline_after[1]);
        assert_eq!(
            outline_after[1].last(),
            Some(&p.truncate()),
            "S(1, 1) is the moved corner"
        );
        assert_eq!(v.selected_xi(), Some(-1.0), "ξ unchanged by a space drag");
        // The modifier key gives the other mode: ξ up, the point stays.
        let at = v.to_screen(p.truncate());
        assert!(v.pointer_down(at, true));
        assert!(v.pointer_move(at - DVec2::new(0.0, 30.0)));
        v.pointer_up();
        assert_eq!(v.selected_point().unwrap().truncate(), p.truncate());
        assert!((v.selected_xi().unwrap() - (-1.0 + 30.0 * XI_PER_PIXEL)).abs() < 1e-12);
        assert!(v.undo() && v.undo());
        assert_eq!(v.solid(), &Solid2::fig9());
        assert!(
            v.solid().inverse().is_none(),
            "back to the exact regular grid"
        );
        // Esc during a drag puts the point back.
        assert!(v.pointer_down(corner, false));
        assert!(v.pointer_move(corner + DVec2::new(10.0, 10.0)));
        assert!(v.key("Escape", false));
        assert!(!v.dragging());
        assert_eq!(v.solid(), &Solid2::fig9());
        assert!(!v.can_undo() && v.can_redo(), "a cancelled drag is no step");
        // F fits the view to the domain again.
        v.select(Some((2, 2)));
        v.set_selected_xy(3.0, 3.0).unwrap();
        let before = v.view_box();
        assert!(v.key("f", false));
        let (min, max) = v.view_box();
        assert_ne!((min, max), before);
        assert!(max.x > 3.0 && max.y > 3.0 && min.x < 0.0);
    }

    #[test]
    fn wheel_turns_and_typed_values_on_one_point_are_one_step() {
        let mut v = view();
        v.select(Some((1, 1)));
        for _ in 0..5 {
            assert!(v.wheel(-100.0));
        }
        assert!((v.selected_xi().unwrap() - 1.5).abs() < 1e-12);
        for x in [0.5, 0.55, 0.6] {
            v.set_selected_xy(x, 0.5).unwrap();
        }
        assert!(v.set_selected_xy(f64::NAN, 0.5).is_err());
        assert_eq!(v.selected_point().unwrap().x, 0.6);
        assert!(v.undo());
        assert_eq!(v.selected_point().unwrap().x, 0.5, "typing is one step");
        assert!(v.undo());
        assert_eq!(v.solid(), &Solid2::fig9(), "the wheel turns are one step");
    }

    #[test]
    fn elevation_keeps_the_shape_and_reset_gives_a_flat_grid() {
        let mut v = view();
        let probes = [
            DVec2::new(0.3, 0.4),
            DVec2::new(0.5, 0.5),
            DVec2::new(0.9, 0.1),
        ];
        let before: Vec<f64> = probes.iter().map(|&p| v.solid().f(p)).collect();
        v.elevate(Axis::U).unwrap();
        v.elevate(Axis::V).unwrap();
        assert_eq!(v.solid().degree(), [3, 3]);
        for (&p, f) in probes.iter().zip(&before) {
            assert!((v.solid().f(p) - f).abs() < 1e-12);
        }
        assert!(v.elevate(Axis::W).is_err());
        v.select(Some((3, 3)));
        v.reset_grid(2, 5).unwrap();
        assert_eq!(v.solid().degree(), [1, 4]);
        assert_eq!(v.selected(), None, "P33 is not in a 2×5 grid");
        v.reset_grid(4, 5).unwrap();
        // A dome: a solid in the middle of the domain, outside at its corners.
        let (min, max) = v.solid().domain();
        assert!(v.solid().f((min + max) / 2.0) > 0.05);
        assert!(v.solid().f(min + (max - min) * 0.05) < 0.0);
        assert_eq!(v.solid().net().points()[0].z, -0.5);
        v.reset_grid(2, 5).unwrap();
        assert!(v.reset_grid(1, 4).is_err() && v.reset_grid(2, 17).is_err());
        for _ in 0..(MAX_POINTS_PER_SIDE - 2) {
            v.elevate(Axis::U).unwrap();
        }
        assert!(
            v.elevate(Axis::U)
                .unwrap_err()
                .message()
                .contains("at most")
        );
        assert_eq!(v.solid().degree()[0], MAX_POINTS_PER_SIDE - 1);
        while v.undo() {}
        assert_eq!(v.solid(), &Solid2::fig9());
    }

    #[test]
    fn opening_a_model_is_an_undo_step() {
        let mut v = view();
        v.select(Some((2, 2)));
        let other = Solid2::regular([1, 1], DVec2::ZERO, DVec2::new(2.0, 1.0), |[i, j]| {
            (i + j) as f64 - 0.5
        })
        .unwrap();
        v.set_solid(other.clone());
        assert_eq!(v.solid(), &other);
        assert_eq!(v.selected(), None);
        assert!(v.undo());
        assert_eq!(v.solid(), &Solid2::fig9());
        assert!(v.key("m", false));
        assert_eq!(v.mode(), Mode::Space);
    }

    #[test]
    fn a_space_mapped_frame_draws_the_moved_solid() {
        let mut v = view();
        v.select(Some((1, 1)));
        v.set_selected_xy(0.65, 0.6).unwrap();
        assert!(v.solid().inverse().is_some_and(|m| m.injective()));
        let frame = v.frame();
        assert_eq!(frame.contours.len(), 1);
        assert!(frame.contours[0].closed);
        // Contour vertices are on f = 0 of the moved solid.
        for p in &frame.contours[0].points {
            assert!(v.solid().f(*p).abs() < 1e-6, "f = {}", v.solid().f(*p));
        }
        // The mesh: red where the solid is, drawn before the overlay.
        let inside = v.to_screen(DVec2::new(0.6, 0.55));
        let ndc = [
            (inside.x / 800.0 * 2.0 - 1.0) as f32,
            (1.0 - inside.y / 600.0 * 2.0) as f32,
        ];
        let near = frame
            .shapes
            .iter()
            .filter(|s| {
                (s.position[0] - ndc[0]).abs() < 0.01 && (s.position[1] - ndc[1]).abs() < 0.01
            })
            .collect::<Vec<_>>();
        assert!(!near.is_empty());
        assert!(near.iter().all(|s| s.color[0] > s.color[2]), "red inside");
        assert!(frame.range.0 < 0.0 && frame.range.1 > 0.0);
    }

    #[test]
    fn a_volume_is_edited_through_its_slices_with_one_history() {
        use bezsolid_core::model::ModelSolid;
        use bezsolid_core::presets::Preset;
        let ModelSolid::Volume(blob) = Preset::Blob.solid() else {
            unreachable!()
        };
        let mut v = view();
        v.set_volume(blob.clone());
        assert_eq!(v.slice(), Some((Axis::W, 1)));
        assert_eq!(v.solid().degree(), [2, 2]);
        // The middle w slice of the blob: its centre is the volume's centre point, ξ = 1.
        v.select(Some((1, 1)));
        assert_eq!(v.selected_xi(), Some(1.0));
        v.set_selected_xi(0.4).unwrap();
        assert_eq!(v.volume().unwrap().xi([1, 1, 1]), Some(0.4));
        // A space edit in the slice moves the volume's point in x and y (z kept).
        v.set_selected_xy(0.1, -0.2).unwrap();
        let p = v.volume().unwrap().net()[[1, 1, 1]];
        assert_eq!((p.x, p.y, p.z, p.w), (0.1, -0.2, 0.0, 0.4));
        assert!(v.volume().unwrap().inverse().is_some());
        // Another slice: across u, index 0 (points (y, z, ξ)).
        v.set_slice(Axis::U, 0).unwrap();
        assert_eq!(v.solid().net()[[0, 0]], DVec3::new(-1.0, -1.0, -1.0));
        assert!(v.set_slice(Axis::U, 3).is_err());
        // A 3D drag of a volume point: one step; the slice follows.
        let before = v.volume().unwrap().clone();
        v.begin_volume_drag(0);
        assert!(v.drag_volume_to(None, Some(0.5)));
        assert_eq!(v.solid().net()[[0, 0]].z, 0.5);
        v.pointer_up();
        assert!(v.undo());
        assert_eq!(v.volume().unwrap(), &before);
        assert!(v.undo(), "typed ξ, x and y of one point are one step");
        assert_eq!(v.volume().unwrap(), &blob);
        assert!(v.undo(), "back to the patch");
        assert!(v.volume().is_none());
        assert_eq!(v.solid(), &Solid2::fig9());
        assert!(v.redo());
        assert_eq!(v.volume().unwrap(), &blob);
        // Elevation of a volume keeps f; one step.
        let probe = DVec3::new(0.2, -0.3, 0.1);
        let f = v.volume().unwrap().f(probe);
        v.elevate(Axis::W).unwrap();
        assert_eq!(v.volume().unwrap().degree(), [2, 2, 3]);
        assert!((v.volume().unwrap().f(probe) - f).abs() < 1e-12);
        assert!(v.undo());
        assert_eq!(v.volume().unwrap(), &blob);
        // A new flat volume over the blob's box.
        v.new_volume(2, 3, 4).unwrap();
        assert_eq!(v.volume().unwrap().degree(), [1, 2, 3]);
        assert_eq!(v.volume().unwrap().domain(), blob.domain());
        assert!(v.new_volume(1, 3, 3).is_err());
        assert!(v.undo());
        assert_eq!(v.volume().unwrap(), &blob);
        // A new patch from a volume: over its box in x and y.
        v.reset_grid(3, 3).unwrap();
        assert!(v.volume().is_none());
        assert_eq!(v.solid().domain(), (DVec2::splat(-1.0), DVec2::ONE));
        assert!(v.undo());
        assert_eq!(v.volume().unwrap(), &blob);
    }

    #[test]
    fn diverging_scale_ends_and_middle() {
        assert_eq!(diverging(0.0), [0.97, 0.97, 0.97, 1.0]);
        let blue = diverging(-1.0);
        let red = diverging(5.0);
        assert!(blue[2] > blue[0] && red[0] > red[2]);
        assert_eq!(diverging(f64::NAN), diverging(0.0));
    }
}
