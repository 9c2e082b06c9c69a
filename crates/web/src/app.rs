//! The contour view as plain Rust: the solid, the selected control point, the view transform, drags,
//! wheel and keys; and the [`Frame`] it draws, as data (a field image and coloured triangles), so that
//! everything but the GPU upload is tested natively.

use bezsolid_core::contour::{Grid2, Polyline, contour, sheet_contour, solid_contour};
use bezsolid_core::rfunc::clip2;
use bezsolid_core::{Axis, Patch, Solid2, Solid3, SolidError, Volume};
use glam::{DVec2, DVec3, DVec4};

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
/// The most undo steps kept (a 16×16 net is 6 KB, so this is at most a few MB).
pub const HISTORY_LIMIT: usize = 500;
/// The most control points per side of a patch in the editor (degree 15).
pub const MAX_POINTS_PER_SIDE: usize = 16;
/// Cells per side of the parameter-space mesh that draws a space mapping's field (mapped forward).
const MAPPED_MESH_CELLS: usize = 96;
/// Cells per side of the parameter square in which a space mapping's contour is traced.
const MAPPED_CONTOUR_CELLS: usize = 192;
/// Samples along each boundary curve of the domain's outline.
const OUTLINE_SAMPLES: usize = 64;

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
    /// The net may fold: the contour shows the zero lines of every sheet (see
    /// [`ContourView::frame`]).
    pub folded: bool,
}

/// What dragging a control point changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Function mapping: up and down change ξ.
    Function,
    /// Space mapping: the point follows the pointer in the plane.
    Space,
}

impl Mode {
    /// The other mode (what the modifier key gives during a drag).
    #[must_use]
    pub fn other(self) -> Self {
        match self {
            Self::Function => Self::Space,
            Self::Space => Self::Function,
        }
    }
}

#[derive(Clone, Debug)]
struct Drag {
    index: usize,
    mode: Mode,
    /// Where the pointer went down, in CSS pixels.
    start: DVec2,
    /// The point when the drag began.
    start_point: DVec3,
    /// The model before the drag: one undo step when the drag changed it.
    before: Net,
}

/// A model's control net, as the undo history keeps it.
#[derive(Clone, Debug, PartialEq)]
enum Net {
    Patch(Patch<DVec3>),
    Volume(Volume<DVec4>),
}

/// A volume model: the solid, and the slice of its control net that the patch editor shows (the
/// paper's cross-section chooser, Fig. 11).
#[derive(Clone, Debug)]
struct VolumeDoc {
    solid: Solid3,
    axis: Axis,
    index: usize,
}

/// What kind of edit an undo step records: consecutive wheel turns or number entries on one point
/// are one step; everything else is a step of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    Wheel(usize),
    Input(usize),
    Other,
}

/// The patch editor: the solid, the selected control point, the drag mode, undo and redo, and the
/// 2D contour view's transform, drags, wheel and keys.
#[derive(Clone, Debug)]
pub struct ContourView {
    solid: Solid2,
    selected: Option<usize>,
    drag: Option<Drag>,
    mode: Mode,
    /// The volume when the model is one; `solid` is then its selected slice.
    volume: Option<VolumeDoc>,
    /// A control point of the volume dragged in 3D, and the model before the drag.
    volume_drag: Option<(usize, Net)>,
    /// Counts changes of the model (for caches of what is drawn from it).
    revision: u64,
    undo: Vec<Net>,
    redo: Vec<Net>,
    last_step: Option<Step>,
    /// The view held still (centre, world units per CSS pixel) once a point has been dragged: the
    /// picture does not jump when a space-mapping drag grows or shrinks the domain, and undo and
    /// redo give back exactly the pictures they were. `None` fits the domain; opening another model,
    /// a new grid and the F key go back to that.
    fixed: Option<(DVec2, f64)>,
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
            mode: Mode::Function,
            volume: None,
            volume_drag: None,
            revision: 0,
            undo: Vec::new(),
            redo: Vec::new(),
            last_step: None,
            fixed: None,
            size: DVec2::new(640.0, 480.0),
            dpr: 1.0,
        }
    }

    /// The drag mode.
    #[must_use]
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Sets the drag mode (a drag under way keeps its own).
    pub fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
    }

    /// Replaces the model by a patch solid (a preset, an opened file or link): one undo step. The
    /// selection is kept where the new net has that point.
    pub fn set_solid(&mut self, solid: Solid2) {
        let before = self.net();
        self.drag = None;
        self.volume_drag = None;
        self.fixed = None;
        self.solid = solid;
        self.volume = None;
        self.changed_from(before, Step::Other);
        self.keep_selection_in_range();
    }

    /// Replaces the model by a volume solid: one undo step. The patch editor shows its middle
    /// slice across w.
    pub fn set_volume(&mut self, solid: Solid3) {
        let before = self.net();
        self.drag = None;
        self.volume_drag = None;
        self.fixed = None;
        let index = solid.degree()[2] / 2;
        self.volume = Some(VolumeDoc {
            solid,
            axis: Axis::W,
            index,
        });
        self.refresh_slice();
        self.changed_from(before, Step::Other);
        self.keep_selection_in_range();
    }

    /// The volume, when the model is one.
    #[must_use]
    pub fn volume(&self) -> Option<&Solid3> {
        self.volume.as_ref().map(|d| &d.solid)
    }

    /// The slice the patch editor shows, when the model is a volume: the axis it crosses and its
    /// index along it.
    #[must_use]
    pub fn slice(&self) -> Option<(Axis, usize)> {
        self.volume.as_ref().map(|d| (d.axis, d.index))
    }

    /// Opens another slice of the volume in the patch editor (not an undo step: the model is the
    /// same).
    ///
    /// # Errors
    ///
    /// When the model is a patch or `index` is past the net along `axis`.
    pub fn set_slice(&mut self, axis: Axis, index: usize) -> Result<(), String> {
        let doc = self
            .volume
            .as_mut()
            .ok_or("the model is a patch; it has no slices")?;
        let d = doc.solid.degree();
        let len = d[axis.index()] + 1;
        if index >= len {
            return Err(format!("the net has {len} slices across that axis"));
        }
        if self.drag.is_some() || self.volume_drag.is_some() {
            return Err("finish the drag first".into());
        }
        (doc.axis, doc.index) = (axis, index);
        self.fixed = None;
        self.refresh_slice();
        self.keep_selection_in_range();
        Ok(())
    }

    /// A number that changes whenever the model does.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The model's net, as the history keeps it.
    fn net(&self) -> Net {
        match &self.volume {
            Some(doc) => Net::Volume(doc.solid.net().clone()),
            None => Net::Patch(self.solid.net().clone()),
        }
    }

    /// Records `before` as an undo step if the model is no longer that.
    fn changed_from(&mut self, before: Net, step: Step) {
        if self.net() != before {
            self.revision += 1;
            self.record(before, step);
        }
    }

    /// The patch editor's solid from the volume's selected slice.
    fn refresh_slice(&mut self) {
        let Some(doc) = &self.volume else { return };
        if let Some(solid) = doc.solid.slice(doc.axis, doc.index) {
            self.solid = solid;
        }
    }

    /// Writes the edited slice back into the volume.
    fn write_back(&mut self) -> Result<(), String> {
        let Some(doc) = &mut self.volume else {
            return Ok(());
        };
        doc.solid
            .set_slice(doc.axis, doc.index, &self.solid)
            .map_err(|e| e.to_string())
    }

    fn keep_selection_in_range(&mut self) {
        if self.selected.is_some_and(|k| k >= self.count()) {
            self.selected = None;
        }
    }

    /// Applies an edit of the patch editor's solid as an undo step of kind `step` (written back into
    /// the volume when the model is one); a failed edit changes nothing.
    fn apply(
        &mut self,
        step: Step,
        edit: impl FnOnce(&mut Solid2) -> Result<(), SolidError>,
    ) -> Result<(), String> {
        let before = self.net();
        let old = self.solid.clone();
        edit(&mut self.solid).map_err(|e| e.to_string())?;
        if self.solid.net() != old.net() {
            if let Err(e) = self.write_back() {
                self.solid = old;
                return Err(e);
            }
            self.changed_from(before, step);
        }
        Ok(())
    }

    fn record(&mut self, before: Net, step: Step) {
        let coalesce = step != Step::Other && self.last_step == Some(step);
        if !coalesce {
            self.undo.push(before);
            if self.undo.len() > HISTORY_LIMIT {
                self.undo.remove(0);
            }
        }
        self.redo.clear();
        self.last_step = Some(step);
    }

    /// Forgets every undo and redo step (after restoring an autosaved model at start-up).
    pub fn forget_history(&mut self) {
        self.undo.clear();
        self.redo.clear();
        self.last_step = None;
    }

    fn busy(&self) -> bool {
        self.drag.is_some() || self.volume_drag.is_some()
    }

    /// Whether there is a step to undo.
    #[must_use]
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty() && !self.busy()
    }

    /// Whether there is an undone step to redo.
    #[must_use]
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty() && !self.busy()
    }

    /// Undoes the last step; returns whether there was one (never during a drag).
    pub fn undo(&mut self) -> bool {
        self.travel(true)
    }

    /// Redoes the last undone step; returns whether there was one.
    pub fn redo(&mut self) -> bool {
        self.travel(false)
    }

    /// Moves one step back (`undo`) or forward in the history: the net popped from one stack is
    /// restored and the current one pushed on the other.
    fn travel(&mut self, undo: bool) -> bool {
        if self.busy() {
            return false;
        }
        let popped = if undo {
            self.undo.pop()
        } else {
            self.redo.pop()
        };
        let Some(net) = popped else {
            return false;
        };
        let current = self.net();
        if self.restore(net) {
            if undo {
                self.redo.push(current);
            } else {
                self.undo.push(current);
            }
        }
        true
    }

    /// Puts back a net from the history (each was a valid solid when it was recorded). A volume
    /// keeps the slice shown where the net still has it.
    fn restore(&mut self, net: Net) -> bool {
        match net {
            Net::Patch(patch) => match Solid2::try_from_net(patch) {
                Ok(solid) => {
                    self.solid = solid;
                    self.volume = None;
                }
                Err(_) => return false,
            },
            Net::Volume(volume) => match Solid3::try_from_net(volume) {
                Ok(solid) => {
                    let (axis, index) = self.slice().unwrap_or((Axis::W, 0));
                    let d = solid.degree();
                    let top = d[axis.index()];
                    self.volume = Some(VolumeDoc {
                        solid,
                        axis,
                        index: index.min(top),
                    });
                    self.refresh_slice();
                }
                Err(_) => return false,
            },
        }
        self.revision += 1;
        self.last_step = None;
        self.keep_selection_in_range();
        true
    }

    /// Starts dragging control point `index` of the volume (flat, as in [`Volume::points`]) from
    /// another view: the patch editor opens the point's slice across the current axis and selects
    /// it there. The drag ends with [`Self::pointer_up`] as one undo step.
    pub fn begin_volume_drag(&mut self, index: usize) {
        let Some(doc) = &self.volume else { return };
        if index >= doc.solid.net().points().len() {
            return;
        }
        let Some(ijk) = doc.solid.net().multi_index(index) else {
            return;
        };
        let axis = doc.axis;
        let along = ijk[axis.index()];
        // The slice's two in-plane axes are numbered as the coordinates in its plane.
        let (lo, hi) = axis.others();
        let (p, q) = (ijk[lo.index()], ijk[hi.index()]);
        let before = self.net();
        if self.slice() != Some((axis, along)) {
            let _ = self.set_slice(axis, along);
        }
        self.selected = Some(p * (self.solid.degree()[1] + 1) + q);
        self.volume_drag = Some((index, before));
    }

    /// The control point of the volume dragged from another view.
    #[must_use]
    pub fn volume_dragged(&self) -> Option<usize> {
        self.volume_drag.as_ref().map(|(k, _)| *k)
    }

    /// During a volume drag: moves the point to `xyz` and/or sets its ξ. Returns whether the model
    /// changed.
    pub fn drag_volume_to(&mut self, xyz: Option<DVec3>, xi: Option<f64>) -> bool {
        let (Some((index, _)), Some(doc)) = (&self.volume_drag, &mut self.volume) else {
            return false;
        };
        let Some([i, j, k]) = doc.solid.net().multi_index(*index) else {
            return false;
        };
        let before = doc.solid.net().points()[*index];
        let ok = xi.is_none_or(|xi| doc.solid.set_xi([i, j, k], xi).is_ok())
            && xyz.is_none_or(|p| doc.solid.set_point([i, j, k], p).is_ok());
        let changed = ok && doc.solid.net().points()[*index] != before;
        if changed {
            self.revision += 1;
            self.refresh_slice();
        }
        changed
    }

    /// Raises the degree along `axis` (one more point per side there), keeping the shape.
    ///
    /// # Errors
    ///
    /// Past [`MAX_POINTS_PER_SIDE`] points, or for [`Axis::W`].
    pub fn elevate(&mut self, axis: Axis) -> Result<(), String> {
        if let Some(doc) = &self.volume {
            let d = doc.solid.degree();
            let side = d[axis.index()];
            if side + 1 >= MAX_POINTS_PER_SIDE {
                return Err(format!(
                    "the net has {} points along that axis already; the editor takes at most {MAX_POINTS_PER_SIDE}",
                    side + 1
                ));
            }
            let net = doc.solid.net().elevate(axis).map_err(|e| e.to_string())?;
            let solid = Solid3::try_from_net(net).map_err(|e| e.to_string())?;
            let before = self.net();
            if let Some(doc) = &mut self.volume {
                doc.solid = solid;
            }
            self.refresh_slice();
            self.changed_from(before, Step::Other);
            self.keep_selection_in_range();
            return Ok(());
        }
        let [n, m] = self.solid.degree();
        let side = match axis {
            Axis::U => n,
            Axis::V => m,
            Axis::W => return Err("a patch has no third axis".into()),
        };
        if side + 1 >= MAX_POINTS_PER_SIDE {
            return Err(format!(
                "the grid has {} points on that side already; the editor takes at most {MAX_POINTS_PER_SIDE}",
                side + 1
            ));
        }
        self.apply(Step::Other, |s| {
            *s = Solid2::try_from_net(s.net().elevate(axis)?)?;
            Ok(())
        })
    }

    /// A new flat patch of `nu × nv` points (2 to [`MAX_POINTS_PER_SIDE`]) over the current domain
    /// (a volume's box in x and y), at ξ = 0.25 everywhere (the paper's starting point for Fig. 9):
    /// the whole box is inside.
    ///
    /// # Errors
    ///
    /// For a size out of range.
    pub fn reset_grid(&mut self, nu: usize, nv: usize) -> Result<(), String> {
        for k in [nu, nv] {
            if !(2..=MAX_POINTS_PER_SIDE).contains(&k) {
                return Err(format!(
                    "a grid has 2 to {MAX_POINTS_PER_SIDE} points per side, not {k}"
                ));
            }
        }
        if let Some(v) = self.volume() {
            // From a volume: a new patch over its box's x, y extent.
            let (min, max) = v.domain();
            let patch = Solid2::regular(
                [nu - 1, nv - 1],
                min.truncate(),
                max.truncate(),
                |[_, _]| 0.25,
            )
            .map_err(|e| e.to_string())?;
            self.set_solid(patch);
            return Ok(());
        }
        let (min, max) = self.solid.domain();
        self.apply(Step::Other, |s| {
            *s = Solid2::regular([nu - 1, nv - 1], min, max, |[_, _]| 0.25)?;
            Ok(())
        })?;
        self.fixed = None;
        self.keep_selection_in_range();
        Ok(())
    }

    /// A new volume: a flat net of `nu × nv × nw` points (2 to [`MAX_POINTS_PER_SIDE`] each) at
    /// ξ = 0.25 (the whole box inside) over the current volume's box, or over the patch's domain
    /// times `[0, 1]`: one undo step.
    ///
    /// # Errors
    ///
    /// For a size out of range.
    pub fn new_volume(&mut self, nu: usize, nv: usize, nw: usize) -> Result<(), String> {
        for k in [nu, nv, nw] {
            if !(2..=MAX_POINTS_PER_SIDE).contains(&k) {
                return Err(format!(
                    "a net has 2 to {MAX_POINTS_PER_SIDE} points along each axis, not {k}"
                ));
            }
        }
        let (min, max) = match self.volume() {
            Some(v) => v.domain(),
            None => {
                let (a, b) = self.solid.domain();
                (a.extend(0.0), b.extend(1.0))
            }
        };
        let solid = Solid3::regular([nu - 1, nv - 1, nw - 1], min, max, |[_, _, _]| 0.25)
            .map_err(|e| e.to_string())?;
        self.set_volume(solid);
        Ok(())
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
        if let Some((centre, scale)) = self.fixed {
            let half = self.size * scale * 0.5;
            return (centre - half, centre + half);
        }
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
        self.solid.degree()[1] + 1
    }

    fn count(&self) -> usize {
        self.solid.net().points().len()
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
        let [n, m] = self.solid.degree();
        self.selected = ij
            .filter(|&(i, j)| i <= n && j <= m)
            .map(|(i, j)| i * (m + 1) + j);
    }

    /// ξ of the selected point.
    #[must_use]
    pub fn selected_xi(&self) -> Option<f64> {
        self.selected().and_then(|(i, j)| self.solid.xi([i, j]))
    }

    /// Sets ξ of the selected point.
    ///
    /// # Errors
    ///
    /// When nothing is selected or `xi` is not finite; nothing changes then.
    pub fn set_selected_xi(&mut self, xi: f64) -> Result<(), String> {
        let k = self.selected.ok_or("no control point is selected")?;
        let (i, j) = self.ij(k);
        self.apply(Step::Input(k), |s| s.set_xi([i, j], xi))
    }

    /// The selected control point `(x, y, ξ)`.
    #[must_use]
    pub fn selected_point(&self) -> Option<DVec3> {
        self.selected.map(|k| self.solid.net().points()[k])
    }

    /// Moves the selected point to `(x, y)` in the plane (space mapping, typed in).
    ///
    /// # Errors
    ///
    /// When nothing is selected or a coordinate is not finite; nothing changes then.
    pub fn set_selected_xy(&mut self, x: f64, y: f64) -> Result<(), String> {
        let k = self.selected.ok_or("no control point is selected")?;
        let (i, j) = self.ij(k);
        self.apply(Step::Input(k), |s| s.set_point([i, j], DVec2::new(x, y)))
    }

    /// The control point whose disc is under the CSS pixel `q`, nearest first.
    #[must_use]
    pub fn pick(&self, q: DVec2) -> Option<usize> {
        self.solid
            .net()
            .points()
            .iter()
            .enumerate()
            .map(|(k, p)| (k, self.to_screen(p.truncate()).distance(q)))
            .filter(|&(_, d)| d <= PICK_RADIUS)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// Pointer pressed at CSS pixel `q`: selects the point under it and starts dragging it, in the
    /// current mode, or the other one when `other_mode` (the modifier key) is held. Returns whether
    /// a point was grabbed (a press on empty space keeps the selection).
    pub fn pointer_down(&mut self, q: DVec2, other_mode: bool) -> bool {
        match self.pick(q) {
            Some(k) => {
                let mode = if other_mode {
                    self.mode.other()
                } else {
                    self.mode
                };
                self.begin_drag(k, mode);
                if let Some(drag) = &mut self.drag {
                    drag.start = q;
                }
                true
            }
            None => false,
        }
    }

    /// Starts dragging control point `index` (flat, as in [`Patch::points`]) in `mode`: it is
    /// selected, and the drag ends with [`Self::pointer_up`] as one undo step. For views other than
    /// this one, which move the point with [`Self::drag_to`].
    pub fn begin_drag(&mut self, index: usize, mode: Mode) {
        if index >= self.count() {
            return;
        }
        self.selected = Some(index);
        // The view holds still from now on: the point stays under the pointer even as the domain
        // it frames grows or shrinks.
        self.fix_view();
        self.drag = Some(Drag {
            index,
            mode,
            start: DVec2::ZERO,
            start_point: self.solid.net().points()[index],
            before: self.net(),
        });
    }

    /// The control point being dragged.
    #[must_use]
    pub fn dragged(&self) -> Option<usize> {
        self.drag.as_ref().map(|d| d.index)
    }

    /// During a drag: moves the point to `xy` in the plane and/or to `xi`. Returns whether the solid
    /// changed (a value it cannot take leaves it as it was).
    pub fn drag_to(&mut self, xy: Option<DVec2>, xi: Option<f64>) -> bool {
        let Some(drag) = &self.drag else { return false };
        let k = drag.index;
        let (i, j) = self.ij(k);
        let before = self.solid.net().points()[k];
        let ok = xi.is_none_or(|xi| self.solid.set_xi([i, j], xi).is_ok())
            && xy.is_none_or(|xy| self.solid.set_point([i, j], xy).is_ok());
        self.after_drag_move(ok && self.solid.net().points()[k] != before)
    }

    /// After a drag moved the slice's point: the volume follows; returns `changed`.
    fn after_drag_move(&mut self, changed: bool) -> bool {
        if changed {
            self.revision += 1;
            if self.write_back().is_err() {
                // The volume refused the net (it cannot, for values the patch took): put the slice
                // back as the volume has it.
                self.refresh_slice();
            }
        }
        changed
    }

    /// Pointer moved to CSS pixel `q`: while dragging in function mode, up raises ξ and down lowers
    /// it; in space mode the point follows the pointer. Returns whether the solid changed.
    pub fn pointer_move(&mut self, q: DVec2) -> bool {
        let Some(drag) = &self.drag else { return false };
        let (i, j) = self.ij(drag.index);
        let before = self.solid.net().points()[drag.index];
        let result = match drag.mode {
            Mode::Function => {
                let xi = drag.start_point.z + (drag.start.y - q.y) * XI_PER_PIXEL;
                self.solid.set_xi([i, j], xi)
            }
            Mode::Space => {
                let xy = drag.start_point.truncate() + self.to_world(q) - self.to_world(drag.start);
                self.solid.set_point([i, j], xy)
            }
        };
        let changed = result.is_ok() && self.solid.net().points()[drag.index] != before;
        self.after_drag_move(changed)
    }

    /// Pointer released or cancelled: ends the drag, which is one undo step if it changed the net.
    pub fn pointer_up(&mut self) {
        if let Some(drag) = self.drag.take() {
            self.changed_from_drag(drag.before);
        }
        if let Some((_, before)) = self.volume_drag.take() {
            self.changed_from_drag(before);
        }
    }

    fn changed_from_drag(&mut self, before: Net) {
        // The revision moved with every step of the drag; only the history is left to do.
        if self.net() != before {
            self.record(before, Step::Other);
        }
    }

    fn fix_view(&mut self) {
        if self.fixed.is_none() {
            let (min, max) = self.view_box();
            self.fixed = Some(((min + max) * 0.5, (max.x - min.x) / self.size.x));
        }
    }

    /// Fits the view to the domain again (the F key).
    pub fn fit_view(&mut self) {
        self.fixed = None;
    }

    /// Whether a drag is under way.
    #[must_use]
    pub fn dragging(&self) -> bool {
        self.drag.is_some()
    }

    /// Wheel over the view: changes ξ of the selected point (`deltaY < 0`, wheel up, raises it).
    /// Returns whether the solid changed.
    pub fn wheel(&mut self, delta_y: f64) -> bool {
        match (self.selected, self.selected_xi()) {
            (Some(k), Some(xi)) if delta_y.is_finite() && delta_y != 0.0 && self.drag.is_none() => {
                let (i, j) = self.ij(k);
                self.apply(Step::Wheel(k), |s| {
                    s.set_xi([i, j], xi - delta_y * XI_PER_WHEEL)
                })
                .is_ok()
            }
            _ => false,
        }
    }

    /// A key pressed while the view has focus (`key` as in `KeyboardEvent.key`). Returns whether the
    /// view used it (the page then prevents the browser's default). Tab and Shift+Tab walk through
    /// the points and let focus leave the view after the last (first) one, as a composite widget does.
    pub fn key(&mut self, key: &str, shift: bool) -> bool {
        let [n, m] = self.solid.degree();
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
                // Esc during a drag puts the point back; otherwise it clears the selection.
                if let Some(drag) = self.drag.take() {
                    self.restore(drag.before);
                } else if let Some((_, before)) = self.volume_drag.take() {
                    self.restore(before);
                } else {
                    self.selected = None;
                }
                true
            }
            "m" | "M" => {
                self.mode = self.mode.other();
                true
            }
            "f" | "F" => {
                self.fit_view();
                true
            }
            _ => false,
        }
    }

    fn nudge(&mut self, delta: f64) -> bool {
        match (self.selected, self.selected_xi()) {
            (Some(k), Some(xi)) if self.drag.is_none() => {
                let (i, j) = self.ij(k);
                self.apply(Step::Other, |s| s.set_xi([i, j], xi + delta))
                    .is_ok()
            }
            _ => false,
        }
    }

    /// Field samples `(w, h)` of the view with `long` along its longer side.
    fn field_size(&self, long: usize) -> (usize, usize) {
        let aspect = self.size.x / self.size.y;
        if aspect >= 1.0 {
            (long, ((long as f64 / aspect).round() as usize).max(2))
        } else {
            (((long as f64 * aspect).round() as usize).max(2), long)
        }
    }

    /// `f` sampled at the texel centres of a `w × h` image of the view (so the filtered texture and
    /// the contour agree), with the grid.
    fn sample_view(&self, w: usize, h: usize) -> (Grid2, Vec<f64>) {
        let (vmin, vmax) = self.view_box();
        let texel = (vmax - vmin) / DVec2::new(w as f64, h as f64);
        let grid = Grid2::new(vmin + texel * 0.5, vmax - texel * 0.5, w, h);
        let values = self.solid.f_grid([&grid.xs(), &grid.ys()]);
        (grid, values)
    }

    /// Builds the frame: samples the field over the view, colours it, traces the zero contour and
    /// lays out the control grid, the points and the selection ring. A space mapping is drawn in
    /// parameter space and mapped forward ([`Self::frame`] picks the path).
    #[must_use]
    pub fn frame(&self) -> Frame {
        if self.solid.inverse().is_some() {
            return self.frame_mapped();
        }
        let (w, h) = self.field_size(FIELD_SAMPLES);
        let (grid, values) = self.sample_view(w, h);
        let (xs, ys) = (grid.xs(), grid.ys());

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
        let field = field_image(w, h, &values, range);
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
            folded: false,
        }
    }

    /// The frame of a space mapping. The inverse map at every pixel would cost a Newton solve per
    /// pixel; instead a parameter-space mesh of the patch is mapped forward (`S(u, v)`, exact at its
    /// vertices) and coloured by the clipped `S_ξ`, drawn in increasing `f` so that where the net
    /// folds the larger value (the max over preimages) is on top. Outside the image `f` is negative
    /// everywhere; it is drawn flat full blue: proving that a point has no preimage takes Bézier
    /// clipping over the whole domain (40 ms for a coarse 96-pixel image of a 16×16 net, natively).
    /// The contour is traced in parameter space and mapped forward.
    ///
    /// Where the net may fold (no injectivity certificate) the exact contour would need the inverse
    /// map at every sample, seconds per frame at degree 15: the live view draws the zero lines of
    /// every sheet ([`sheet_contour`]) and [`Frame::folded`] says so. Exports use the exact `f`.
    fn frame_mapped(&self) -> Frame {
        let injective = self.solid.inverse().is_some_and(|m| m.injective());
        let (w, h) = (2, 2);
        let cells = MAPPED_MESH_CELLS;
        let ts: Vec<f64> = (0..=cells).map(|k| k as f64 / cells as f64).collect();
        let net = self.solid.net().eval_grid([&ts, &ts]);
        let side = cells + 1;
        let fs: Vec<f64> = net
            .iter()
            .enumerate()
            .map(|(k, p)| clip2(p.z, ts[k % side], ts[k / side]))
            .collect();
        let range = fs
            .iter()
            .fold((0.0f64, 0.0f64), |r, &v| (r.0.min(v), r.1.max(v)));
        let values = vec![range.0.min(-1e-300); w * h];
        let field = field_image(w, h, &values, range);

        let mut pen = Pen {
            out: Vec::with_capacity(cells * cells * 6),
            size: self.size,
            dpr: self.dpr,
        };
        let mut triangles: Vec<(f64, [usize; 3])> = Vec::with_capacity(cells * cells * 2);
        for b in 0..cells {
            for a in 0..cells {
                let k = b * side + a;
                for tri in [[k, k + 1, k + side + 1], [k, k + side + 1, k + side]] {
                    let top = tri.iter().map(|&i| fs[i]).fold(f64::NEG_INFINITY, f64::max);
                    triangles.push((top, tri));
                }
            }
        }
        triangles.sort_by(|a, b| a.0.total_cmp(&b.0));
        let colour = |v: f64| diverging(normalise(v, range));
        for (_, tri) in &triangles {
            for &i in tri {
                let q = self.to_screen(net[i].truncate());
                pen.out.push(ShapeVertex {
                    position: pen.ndc(q),
                    color: colour(fs[i]),
                });
            }
        }
        let magnitude = fs.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
        let accuracy = CONTOUR_ACCURACY * magnitude;
        let contours = if injective {
            solid_contour(&self.solid, MAPPED_CONTOUR_CELLS, accuracy)
        } else {
            sheet_contour(&self.solid, MAPPED_CONTOUR_CELLS, accuracy)
        };
        let mut shapes = pen.out;
        shapes.extend(self.shapes(&contours));
        Frame {
            field,
            shapes,
            contours,
            range,
            folded: !injective,
        }
    }

    /// The largest |ξ| of the control points: the ξ that colours a point full blue or red.
    #[must_use]
    pub fn xi_scale(&self) -> f64 {
        let m = self
            .solid
            .net()
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
        let patch = self.solid.net();
        // The domain's outline: the patch's four boundary curves (the box of a regular grid).
        for line in outline(patch) {
            for w in line.windows(2) {
                pen.segment(self.to_screen(w[0]), self.to_screen(w[1]), 1.25, BOX_COLOR);
            }
        }
        let [n, m] = self.solid.degree();
        let at = |i: usize, j: usize| self.to_screen(patch[[i, j]].truncate());
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

/// `v` on the colour scale's `[−1, 1]`: each sign scaled to its own extreme of `range`.
fn normalise(v: f64, range: (f64, f64)) -> f64 {
    if v >= 0.0 {
        v / range.1.max(1e-300)
    } else {
        v / -range.0.min(-1e-300)
    }
}

/// The `w × h` samples `values` (row-major from the bottom) as an image (row 0 at the top).
fn field_image(w: usize, h: usize, values: &[f64], range: (f64, f64)) -> FieldImage {
    let mut rgba = Vec::with_capacity(w * h * 4);
    for row in (0..h).rev() {
        for &v in &values[row * w..(row + 1) * w] {
            rgba.extend(diverging(normalise(v, range)).map(|c| (c * 255.0).round() as u8));
        }
    }
    FieldImage {
        width: w as u32,
        height: h as u32,
        rgba,
    }
}

/// The four boundary curves of a patch in the plane, `S(u, 0)`, `S(1, v)`, `S(u, 1)`, `S(0, v)`, as
/// polylines in world coordinates.
#[must_use]
pub fn outline(patch: &Patch<DVec3>) -> [Vec<DVec2>; 4] {
    let t = |k: usize| k as f64 / OUTLINE_SAMPLES as f64;
    let curve = |f: &dyn Fn(f64) -> (f64, f64)| -> Vec<DVec2> {
        (0..=OUTLINE_SAMPLES)
            .map(|k| {
                let (u, v) = f(t(k));
                patch.eval([u, v]).truncate()
            })
            .collect()
    };
    [
        curve(&|s| (s, 0.0)),
        curve(&|s| (1.0, s)),
        curve(&|s| (1.0 - s, 1.0)),
        curve(&|s| (0.0, 1.0 - s)),
    ]
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
        assert!(v.solid().net().points().iter().all(|p| p.z == 0.25));
        assert!(v.reset_grid(1, 4).is_err() && v.reset_grid(2, 17).is_err());
        for _ in 0..(MAX_POINTS_PER_SIDE - 2) {
            v.elevate(Axis::U).unwrap();
        }
        assert!(v.elevate(Axis::U).unwrap_err().contains("at most"));
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
