//! The contour view as plain Rust: the solid, the selected control point, the view transform, drags,
//! wheel and keys; and the [`Frame`] it draws, as data (a field image and coloured triangles), so that
//! everything but the GPU upload is tested natively.

use bezsolid_core::Solid2;
use bezsolid_core::contour::{Grid2, Polyline, contour};
use glam::DVec2;

/// Radius of a drawn control point, in CSS pixels.
pub const POINT_RADIUS: f64 = 7.0;
/// How far from a control point's centre a click still picks it, in CSS pixels.
pub const PICK_RADIUS: f64 = 14.0;
/// ξ change per CSS pixel of vertical drag: 120 px move a point by one unit of ξ.
pub const XI_PER_PIXEL: f64 = 1.0 / 120.0;
/// ξ change per unit of wheel `deltaY` (a notch of 100 is 0.1; wheel up raises the point).
pub const XI_PER_WHEEL: f64 = 0.001;
/// ξ change per arrow-less key press (`PageUp`/`+`); a tenth of it with Shift.
pub const XI_KEY_STEP: f64 = 0.1;
/// Empty border around the domain box, as a fraction of its larger side.
const MARGIN: f64 = 0.14;
/// Samples of the field along the view's longer side (the texture is filtered up to the canvas).
const FIELD_SAMPLES: usize = 320;
/// Accuracy to which contour vertices are refined onto f = 0, relative to the largest |f| sampled.
pub const CONTOUR_ACCURACY: f64 = 1e-9;

/// An RGBA colour, components in `[0, 1]`, not premultiplied.
pub type Rgba = [f32; 4];

const CONTOUR_COLOR: Rgba = [0.06, 0.06, 0.08, 1.0];
const GRID_COLOR: Rgba = [0.18, 0.2, 0.24, 0.75];
const BOX_COLOR: Rgba = [0.3, 0.32, 0.36, 0.6];
const OUTLINE_COLOR: Rgba = [0.08, 0.08, 0.1, 1.0];
const SELECT_COLOR: Rgba = [1.0, 0.62, 0.0, 1.0];

/// The diverging colour scale of the field (the idea of the paper's Fig. 7): `t = −1` blue, `0`
/// white, `+1` red; `t` is clamped to `[−1, 1]`.
#[must_use]
pub fn diverging(t: f64) -> Rgba {
    const BLUE: [f64; 3] = [0.16, 0.36, 0.78];
    const WHITE: [f64; 3] = [0.97, 0.97, 0.97];
    const RED: [f64; 3] = [0.80, 0.16, 0.13];
    let t = if t.is_nan() { 0.0 } else { t.clamp(-1.0, 1.0) };
    let (end, s) = if t < 0.0 { (BLUE, -t) } else { (RED, t) };
    // A slight ease so that values near zero are visibly tinted.
    let s = s.powf(0.6);
    let c = |k: usize| (WHITE[k] + (end[k] - WHITE[k]) * s) as f32;
    [c(0), c(1), c(2), 1.0]
}

/// One vertex of the overlay geometry: a position in normalised device coordinates and a colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeVertex {
    /// x, y in `[−1, 1]`, y up.
    pub position: [f32; 2],
    /// Straight (not premultiplied) RGBA.
    pub color: Rgba,
}

impl ShapeVertex {
    /// Bytes of one vertex: 6 little-endian `f32`.
    pub const SIZE: usize = 24;

    /// Appends the vertex's bytes, in the layout of the shape pipeline (`float32x2`, `float32x4`).
    pub fn write(&self, out: &mut Vec<u8>) {
        for x in self.position.iter().chain(&self.color) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
}

/// The function field as an image covering the whole view: row 0 at the top, RGBA8.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldImage {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width · height · 4` bytes.
    pub rgba: Vec<u8>,
}

/// Everything one redraw needs.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Drawn first, filtered to the whole target.
    pub field: FieldImage,
    /// Drawn over the field, as a triangle list with alpha blending.
    pub shapes: Vec<ShapeVertex>,
    /// The zero contour in world coordinates (what the black line shows).
    pub contours: Vec<Polyline>,
    /// The lowest and highest `f` sampled inside the domain box (full blue and full red; the
    /// legend's ends).
    pub range: (f64, f64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Drag {
    index: usize,
    start_y: f64,
    start_xi: f64,
}

/// The state of the 2D contour view of one patch solid.
#[derive(Clone, Debug)]
pub struct ContourView {
    solid: Solid2,
    selected: Option<usize>,
    drag: Option<Drag>,
    /// Viewport size in CSS pixels.
    size: DVec2,
    /// Device pixels per CSS pixel.
    dpr: f64,
}

impl ContourView {
    /// A view of `solid` in a 640×480 viewport, nothing selected.
    #[must_use]
    pub fn new(solid: Solid2) -> Self {
        Self {
            solid,
            selected: None,
            drag: None,
            size: DVec2::new(640.0, 480.0),
            dpr: 1.0,
        }
    }

    /// The solid shown.
    #[must_use]
    pub fn solid(&self) -> &Solid2 {
        &self.solid
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

    /// The target size in device pixels.
    #[must_use]
    pub fn device_size(&self) -> (u32, u32) {
        let d = (self.size * self.dpr).round().max(DVec2::ONE);
        (d.x as u32, d.y as u32)
    }

    /// The world box shown: the domain with a margin, widened to the viewport's aspect ratio.
    #[must_use]
    pub fn view_box(&self) -> (DVec2, DVec2) {
        let (min, max) = self.solid.domain();
        let centre = (min + max) * 0.5;
        let extent = (max - min).max_element();
        let half = (max - min) * 0.5 + DVec2::splat(extent * MARGIN);
        // World units per CSS pixel: the larger of the two needs, so the box fits both ways.
        let scale = (2.0 * half / self.size).max_element();
        let half = self.size * scale * 0.5;
        (centre - half, centre + half)
    }

    /// CSS pixel (y down, origin top-left) of a world point.
    #[must_use]
    pub fn to_screen(&self, p: DVec2) -> DVec2 {
        let (min, max) = self.view_box();
        let t = (p - min) / (max - min);
        DVec2::new(t.x, 1.0 - t.y) * self.size
    }

    /// World point under a CSS pixel.
    #[must_use]
    pub fn to_world(&self, q: DVec2) -> DVec2 {
        let (min, max) = self.view_box();
        let t = q / self.size;
        min + DVec2::new(t.x, 1.0 - t.y) * (max - min)
    }

    /// `f` at the world point under a CSS pixel.
    #[must_use]
    pub fn probe(&self, q: DVec2) -> f64 {
        self.solid.f(self.to_world(q))
    }

    fn columns(&self) -> usize {
        self.solid.degree().1 + 1
    }

    fn count(&self) -> usize {
        self.solid.patch().points().len()
    }

    fn ij(&self, index: usize) -> (usize, usize) {
        (index / self.columns(), index % self.columns())
    }

    /// The selected control point as `(i, j)`.
    #[must_use]
    pub fn selected(&self) -> Option<(usize, usize)> {
        self.selected.map(|k| self.ij(k))
    }

    /// Selects `P_ij` (or nothing); out-of-range indices select nothing.
    pub fn select(&mut self, ij: Option<(usize, usize)>) {
        let (n, m) = self.solid.degree();
        self.selected = ij
            .filter(|&(i, j)| i <= n && j <= m)
            .map(|(i, j)| i * (m + 1) + j);
    }

    /// ξ of the selected point.
    #[must_use]
    pub fn selected_xi(&self) -> Option<f64> {
        self.selected().map(|(i, j)| self.solid.xi(i, j))
    }

    /// Sets ξ of the selected point.
    ///
    /// # Errors
    ///
    /// When nothing is selected or `xi` is not finite; nothing changes then.
    pub fn set_selected_xi(&mut self, xi: f64) -> Result<(), String> {
        let (i, j) = self.selected().ok_or("no control point is selected")?;
        self.solid.set_xi(i, j, xi).map_err(|e| e.to_string())
    }

    /// The control point whose disc is under the CSS pixel `q`, nearest first.
    #[must_use]
    pub fn pick(&self, q: DVec2) -> Option<usize> {
        self.solid
            .patch()
            .points()
            .iter()
            .enumerate()
            .map(|(k, p)| (k, self.to_screen(p.truncate()).distance(q)))
            .filter(|&(_, d)| d <= PICK_RADIUS)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// Pointer pressed at CSS pixel `q`: selects the point under it and starts dragging it. Returns
    /// whether a point was grabbed (a press on empty space keeps the selection).
    pub fn pointer_down(&mut self, q: DVec2) -> bool {
        match self.pick(q) {
            Some(k) => {
                self.selected = Some(k);
                let (i, j) = self.ij(k);
                self.drag = Some(Drag {
                    index: k,
                    start_y: q.y,
                    start_xi: self.solid.xi(i, j),
                });
                true
            }
            None => false,
        }
    }

    /// Pointer moved to CSS pixel `q`: while dragging, up raises ξ and down lowers it. Returns
    /// whether the solid changed.
    pub fn pointer_move(&mut self, q: DVec2) -> bool {
        let Some(drag) = self.drag else { return false };
        let (i, j) = self.ij(drag.index);
        let xi = drag.start_xi + (drag.start_y - q.y) * XI_PER_PIXEL;
        self.solid.set_xi(i, j, xi).is_ok()
    }

    /// Pointer released or cancelled: ends the drag.
    pub fn pointer_up(&mut self) {
        self.drag = None;
    }

    /// Whether a drag is under way.
    #[must_use]
    pub fn dragging(&self) -> bool {
        self.drag.is_some()
    }

    /// Wheel over the view: changes ξ of the selected point (`deltaY < 0`, wheel up, raises it).
    /// Returns whether the solid changed.
    pub fn wheel(&mut self, delta_y: f64) -> bool {
        match self.selected_xi() {
            Some(xi) if delta_y.is_finite() && delta_y != 0.0 => {
                self.set_selected_xi(xi - delta_y * XI_PER_WHEEL).is_ok()
            }
            _ => false,
        }
    }

    /// A key pressed while the view has focus (`key` as in `KeyboardEvent.key`). Returns whether the
    /// view used it (the page then prevents the browser's default). Tab and Shift+Tab walk through
    /// the points and let focus leave the view after the last (first) one, as a composite widget does.
    pub fn key(&mut self, key: &str, shift: bool) -> bool {
        let (n, m) = self.solid.degree();
        let step = if shift {
            XI_KEY_STEP * 0.1
        } else {
            XI_KEY_STEP
        };
        match key {
            "Tab" => {
                let count = self.count();
                let next = match (self.selected, shift) {
                    (None, false) => Some(0),
                    (None, true) => Some(count - 1),
                    (Some(k), false) => (k + 1 < count).then_some(k + 1),
                    (Some(k), true) => k.checked_sub(1),
                };
                match next {
                    Some(k) => {
                        self.selected = Some(k);
                        true
                    }
                    None => false,
                }
            }
            "ArrowLeft" | "ArrowRight" | "ArrowUp" | "ArrowDown" => {
                // The first arrow press selects the middle point; the next ones walk the grid.
                let Some((i, j)) = self.selected() else {
                    self.select(Some((n / 2, m / 2)));
                    return true;
                };
                let (i, j) = match key {
                    "ArrowLeft" => (i.saturating_sub(1), j),
                    "ArrowRight" => ((i + 1).min(n), j),
                    "ArrowDown" => (i, j.saturating_sub(1)),
                    _ => (i, (j + 1).min(m)),
                };
                self.select(Some((i, j)));
                true
            }
            "PageUp" | "+" | "=" => self.nudge(step),
            "PageDown" | "-" | "_" => self.nudge(-step),
            "Escape" => {
                self.drag = None;
                self.selected = None;
                true
            }
            _ => false,
        }
    }

    fn nudge(&mut self, delta: f64) -> bool {
        match self.selected_xi() {
            Some(xi) => self.set_selected_xi(xi + delta).is_ok(),
            None => false,
        }
    }

    /// Builds the frame: samples the field over the view, colours it, traces the zero contour and
    /// lays out the control grid, the points and the selection ring.
    #[must_use]
    pub fn frame(&self) -> Frame {
        let (vmin, vmax) = self.view_box();
        let aspect = self.size.x / self.size.y;
        let (w, h) = if aspect >= 1.0 {
            (
                FIELD_SAMPLES,
                ((FIELD_SAMPLES as f64 / aspect).round() as usize).max(2),
            )
        } else {
            (
                ((FIELD_SAMPLES as f64 * aspect).round() as usize).max(2),
                FIELD_SAMPLES,
            )
        };
        // Samples at texel centres, so the filtered texture and the contour agree.
        let texel = (vmax - vmin) / DVec2::new(w as f64, h as f64);
        let grid = Grid2::new(vmin + texel * 0.5, vmax - texel * 0.5, w, h);
        let (xs, ys) = (grid.xs(), grid.ys());
        let values = self.solid.f_grid(&xs, &ys);

        // Each sign is scaled to its own extreme, so the whole blue-white-red range is in use and zero
        // stays white whatever the magnitudes.
        // The range is taken inside the domain box: outside it the clipping falls off steeply and
        // would wash out the interior; those samples clamp to full blue.
        let (dmin, dmax) = self.solid.domain();
        let mut range = (0.0f64, 0.0f64);
        for (b, &y) in ys.iter().enumerate() {
            for (a, &x) in xs.iter().enumerate() {
                if (dmin.x..=dmax.x).contains(&x) && (dmin.y..=dmax.y).contains(&y) {
                    let v = values[b * w + a];
                    range = (range.0.min(v), range.1.max(v));
                }
            }
        }
        let normalise = |v: f64| {
            if v >= 0.0 {
                v / range.1.max(1e-300)
            } else {
                v / -range.0.min(-1e-300)
            }
        };
        let mut rgba = Vec::with_capacity(w * h * 4);
        for row in (0..h).rev() {
            for &v in &values[row * w..(row + 1) * w] {
                rgba.extend(diverging(normalise(v)).map(|c| (c * 255.0).round() as u8));
            }
        }
        let field = FieldImage {
            width: w as u32,
            height: h as u32,
            rgba,
        };

        let magnitude = values.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
        let contours = contour(
            &grid,
            &values,
            |p| self.solid.f(p),
            CONTOUR_ACCURACY * magnitude,
        );
        let shapes = self.shapes(&contours);
        Frame {
            field,
            shapes,
            contours,
            range,
        }
    }

    /// The largest |ξ| of the control points: the ξ that colours a point full blue or red.
    #[must_use]
    pub fn xi_scale(&self) -> f64 {
        let m = self
            .solid
            .patch()
            .points()
            .iter()
            .map(|p| p.z.abs())
            .fold(0.0, f64::max);
        if m > 1e-12 { m } else { 1.0 }
    }

    fn shapes(&self, contours: &[Polyline]) -> Vec<ShapeVertex> {
        let scale = self.xi_scale();
        let mut pen = Pen {
            out: Vec::new(),
            size: self.size,
            dpr: self.dpr,
        };
        let (dmin, dmax) = self.solid.domain();
        let corners = [
            dmin,
            DVec2::new(dmax.x, dmin.y),
            dmax,
            DVec2::new(dmin.x, dmax.y),
        ];
        for k in 0..4 {
            pen.segment(
                self.to_screen(corners[k]),
                self.to_screen(corners[(k + 1) % 4]),
                1.0,
                BOX_COLOR,
            );
        }
        let (n, m) = self.solid.degree();
        let patch = self.solid.patch();
        let at = |i: usize, j: usize| self.to_screen(patch.point(i, j).truncate());
        for i in 0..=n {
            for j in 0..=m {
                if i < n {
                    pen.segment(at(i, j), at(i + 1, j), 1.5, GRID_COLOR);
                }
                if j < m {
                    pen.segment(at(i, j), at(i, j + 1), 1.5, GRID_COLOR);
                }
            }
        }
        for line in contours {
            let pts: Vec<DVec2> = line.points.iter().map(|&p| self.to_screen(p)).collect();
            let count = if line.closed {
                pts.len()
            } else {
                pts.len().saturating_sub(1)
            };
            for k in 0..count {
                pen.segment(pts[k], pts[(k + 1) % pts.len()], 2.5, CONTOUR_COLOR);
            }
            for &p in &pts {
                pen.disc(p, 1.25, CONTOUR_COLOR);
            }
        }
        for (k, p) in patch.points().iter().enumerate() {
            let q = self.to_screen(p.truncate());
            if self.selected == Some(k) {
                pen.disc(q, POINT_RADIUS + 5.0, SELECT_COLOR);
            }
            pen.disc(q, POINT_RADIUS + 1.5, OUTLINE_COLOR);
            pen.disc(q, POINT_RADIUS, diverging(p.z / scale));
        }
        pen.out
    }
}

/// Turns CSS-pixel strokes and discs into NDC triangles.
struct Pen {
    out: Vec<ShapeVertex>,
    size: DVec2,
    dpr: f64,
}

impl Pen {
    fn ndc(&self, q: DVec2) -> [f32; 2] {
        let t = q / self.size;
        [(t.x * 2.0 - 1.0) as f32, (1.0 - t.y * 2.0) as f32]
    }

    fn triangle(&mut self, a: DVec2, b: DVec2, c: DVec2, color: Rgba) {
        for p in [a, b, c] {
            self.out.push(ShapeVertex {
                position: self.ndc(p),
                color,
            });
        }
    }

    /// A straight stroke `width` CSS pixels wide (at least one device pixel).
    fn segment(&mut self, a: DVec2, b: DVec2, width: f64, color: Rgba) {
        let d = b - a;
        let len = d.length();
        if len <= 0.0 || !len.is_finite() {
            return;
        }
        let half = width.max(1.0 / self.dpr) * 0.5;
        let nrm = DVec2::new(-d.y, d.x) / len * half;
        self.triangle(a - nrm, b - nrm, b + nrm, color);
        self.triangle(a - nrm, b + nrm, a + nrm, color);
    }

    /// A filled disc, with enough sides to look round at its size.
    fn disc(&mut self, c: DVec2, r: f64, color: Rgba) {
        let sides = ((r * self.dpr * 2.0) as usize).clamp(6, 40);
        let at = |k: usize| {
            let a = core::f64::consts::TAU * k as f64 / sides as f64;
            c + DVec2::new(a.cos(), a.sin()) * r
        };
        for k in 0..sides {
            self.triangle(c, at(k), at(k + 1), color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn view() -> ContourView {
        let mut v = ContourView::new(Solid2::fig9());
        v.resize(800.0, 600.0, 2.0);
        v
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
        assert!(v.pointer_down(press));
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
        assert!(!v.pointer_down(DVec2::new(1.0, 1.0)));
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
    }

    #[test]
    fn view_rejects_non_finite_xi() {
        let mut v = view();
        assert!(v.set_selected_xi(1.0).is_err(), "nothing selected");
        v.select(Some((1, 1)));
        let before = v.selected_xi();
        assert!(v.set_selected_xi(f64::NAN).is_err());
        assert_eq!(v.selected_xi(), before);
        v.select(Some((3, 0)));
        assert_eq!(v.selected(), None, "outside the grid");
    }

    #[test]
    fn frame_field_is_red_inside_blue_outside_with_one_contour() {
        let v = view();
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
    fn diverging_scale_ends_and_middle() {
        assert_eq!(diverging(0.0), [0.97, 0.97, 0.97, 1.0]);
        let blue = diverging(-1.0);
        let red = diverging(5.0);
        assert!(blue[2] > blue[0] && red[0] > red[2]);
        assert_eq!(diverging(f64::NAN), diverging(0.0));
    }
}
