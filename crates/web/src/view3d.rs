//! The 3D view of a patch solid, as plain Rust: the surface `(x, y, ξ)` coloured by ξ, the plane
//! ξ = 0 and the control points as spheres (the first paper's Fig. 6 and Fig. 9); an orbit camera
//! with the conventions of three.js `OrbitControls` (left drag orbits, right or Shift drag pans, the
//! wheel zooms); picking by ray against the spheres; and drags of a sphere along its vertical line
//! (function mapping, ξ) or in its horizontal plane (space mapping, x and y), which go through the
//! editor ([`Editor`]) so that the two views share one model and one undo history.
//!
//! World space is z-up: `(x, y, h·ξ)`, where the height scale `h` is set when the view fits the
//! model (half the domain's larger side per unit of ξ) and held still while editing.

use bezsolid_core::contour::solid_contour;
use bezsolid_core::mesh::Share;
use bezsolid_core::model::{ModelFile, SolidSpec};
use bezsolid_core::{Axis, Solid3};
use glam::{DAffine3, DVec2, DVec3, DVec4};

use crate::camera::{Camera, OrbitView};
use crate::color::{Rgba, SELECT_COLOR, diverging};
use crate::editor::{Editor, Mode};
use crate::scene::{MeshVertex, Refined, Scene, float_vertices, next_generation};
use crate::view2d::XI_PER_PIXEL;

mod geometry;
mod scene;
mod section;
mod whole;

pub use geometry::{
    capped, mesh_floats, stack_segments, stack_share_segments, stack_vertices, surface_floats,
    surface_mesh, surface_share_floats,
};
use geometry::{plane_hit, xi_range};
pub(crate) use geometry::{prism, sphere};
pub use section::SectionPlane;
pub use whole::{Handle, SCALE_PER_PIXEL, TURN_PER_PIXEL, Whole};

/// Cells per side of the surface mesh.
const SURFACE_CELLS: usize = 48;
/// A sphere's radius as a fraction of the domain's larger side.
const SPHERE_RADIUS: f64 = 0.022;

const PLANE_COLOR: Rgba = [0.55, 0.58, 0.64, 0.28];
const GUIDE_COLOR: Rgba = [0.25, 0.27, 0.32, 1.0];
const NET_COLOR: Rgba = [0.35, 0.37, 0.42, 1.0];
const SURFACE_COLOR: Rgba = [0.86, 0.62, 0.42, 1.0];
const CONTOUR_COLOR: Rgba = [0.1, 0.1, 0.12, 1.0];
const SLICE_COLOR: Rgba = [1.0, 0.62, 0.0, 0.16];
/// The true section's plane: translucent violet, apart from the slice's orange.
const SECTION_COLOR: Rgba = [0.45, 0.3, 0.85, 0.22];
/// Its frame, which a drag moves along the plane's axis.
const SECTION_EDGE_COLOR: Rgba = [0.45, 0.3, 0.85, 1.0];
/// The polygonization's resolution at rest, by default (cells along the longest side).
pub const DEFAULT_RESOLUTION: usize = 64;
/// The most cells along the longest side the page meshes at.
pub const MAX_RESOLUTION: usize = 160;
/// Cells along the longest side while a point is being dragged.
const COARSE_RESOLUTION: usize = 24;
/// The low bits of a surface's key that count the cap's changes ([`View3::surface_key`]).
const CAP_BITS: u32 = 20;
/// Cells per side of each slice's contour in the stack.
const STACK_CELLS: usize = 48;

/// A drag of a control point (the camera's gestures are the [`OrbitView`]'s).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Gesture {
    /// A control point: the mode, and the offset from the grab point to the point's centre.
    Point(Mode, DVec3),
    /// A control point of a volume: the mode, where the pointer went down, the point then, and the
    /// offset from the grab point (on the plane through it facing the camera) to its centre.
    VolumePoint(Mode, DVec2, DVec4, DVec3),
    /// A handle of the selection: which, where the pointer went down, the handle's centre then,
    /// and the offset from the grab point to it.
    Handle(Handle, DVec2, DVec3, DVec3),
    /// The true section's plane, moved along its axis: where it was and the grab point on it.
    Plane(f64, DVec3),
}

/// The contour stack of a volume's slices across one axis, for one revision of the model.
#[derive(Clone, Debug)]
struct StackCache {
    revision: u64,
    axis: Axis,
    stack: Vec<MeshVertex>,
    segments: usize,
}

/// What a scene's triangles depend on (everything but the camera).
#[derive(Clone, Copy, Debug, PartialEq)]
struct GeometryKey {
    revision: u64,
    selected: Option<(usize, usize)>,
    slice: Option<(Axis, usize)>,
    surface: Option<(u64, usize)>,
    stack: Option<(u64, Axis)>,
    height: u64,
    whole: u64,
    /// The section plane's axis and where it lies (its bits).
    section: Option<(usize, u64)>,
}

/// A scene's triangles for one [`GeometryKey`], and the size of what they show.
#[derive(Clone, Debug)]
struct Geometry {
    key: GeometryKey,
    generation: u64,
    opaque: Vec<MeshVertex>,
    translucent: Vec<MeshVertex>,
    extent: f64,
}

/// The 3D view's state: the camera with its viewport, the height scale, and the drag of a control
/// point under way.
#[derive(Clone, Debug)]
pub struct View3 {
    orbit: OrbitView,
    /// World z per unit of ξ.
    height: f64,
    gesture: Option<Gesture>,
    /// A volume's surface: cells along the longest side at rest, and whether to mesh coarsely now
    /// (while a point moves).
    resolution: usize,
    coarse: bool,
    surface: Refined,
    stack: Option<StackCache>,
    /// The fine surface and the contour stack are made elsewhere (a Web Worker) and handed in with
    /// [`Self::set_surface`] and [`Self::set_stack`]; until they come, a coarse surface and the
    /// previous stack are drawn.
    external: bool,
    /// The contour stack wanted from elsewhere: `(revision, axis)`.
    stack_request: Option<(u64, Axis)>,
    geometry: Option<Geometry>,
    /// A model of many solids around the editor's part, and a count of its changes.
    whole: Option<Whole>,
    whole_generation: u64,
    /// What a handle's drag asks for since it began, not yet taken ([`Self::take_handle`]).
    handle_drag: Option<(Handle, DVec3)>,
    /// The plane the surface is cut at, `(axis, at)`: the solid is kept where `p[axis] ≤ at`
    /// and the cut face closed ([`capped`]).
    cap: Option<(usize, f64)>,
    /// A count of the cap's changes: with the model's revision, the key a surface is made for.
    cap_generation: u64,
    /// The true section's plane, drawn and dragged along its axis while the section is on.
    section: Option<SectionPlane>,
    /// Where a drag of the plane asks it to be since the last call ([`Self::take_section_drag`]).
    section_drag: Option<f64>,
}

impl View3 {
    /// A view that frames `editor`'s model.
    #[must_use]
    pub fn new(editor: &Editor) -> Self {
        let mut v = Self {
            orbit: OrbitView::default(),
            height: 1.0,
            gesture: None,
            resolution: DEFAULT_RESOLUTION,
            coarse: false,
            surface: Refined::default(),
            stack: None,
            external: false,
            stack_request: None,
            geometry: None,
            whole: None,
            whole_generation: 0,
            handle_drag: None,
            cap: None,
            cap_generation: 0,
            section: None,
            section_drag: None,
        };
        v.fit(editor);
        v
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        self.orbit.camera()
    }

    /// Cuts the surface at a plane, `(axis, at)`: the solid where `p[axis] ≤ at`, the cut face
    /// closed; `None` draws it whole. A new cap asks for a new surface.
    pub fn set_cap(&mut self, cap: Option<(usize, f64)>) {
        if cap != self.cap {
            self.cap = cap;
            self.cap_generation += 1;
        }
    }

    /// The plane the surface is cut at.
    #[must_use]
    pub fn cap(&self) -> Option<(usize, f64)> {
        self.cap
    }

    /// The key a surface is made for: the model's revision and the cap's generation, so that a
    /// surface made before either changed is not taken after.
    #[must_use]
    pub fn surface_key(&self, editor: &Editor) -> u64 {
        (editor.revision() << CAP_BITS) | (self.cap_generation & ((1 << CAP_BITS) - 1))
    }

    /// Sets the viewport size in CSS pixels (sizes below 1 become 1). Until the camera is moved,
    /// a new shape of viewport frames the model again.
    pub fn resize(&mut self, editor: &Editor, width: f64, height: f64) {
        let moved = self.orbit.moved();
        self.orbit.resize(width, height, (DVec3::ZERO, DVec3::ONE));
        if !moved {
            self.fit(editor);
        }
    }

    /// Frames the model again (the height scale too): after opening another model, or on request.
    pub fn fit(&mut self, editor: &Editor) {
        if let Some(whole) = &self.whole {
            // The surface drawn, where it is the model's as it is (the bounds of a blend are
            // loose).
            let drawn = self
                .surface
                .drawn()
                .filter(|m| m.revision == self.surface_key(editor))
                .and_then(|m| {
                    let (lo, hi) = m.vertices.iter().fold(
                        (DVec3::INFINITY, DVec3::NEG_INFINITY),
                        |(lo, hi), v| {
                            let p = glam::Vec3::from_array(v.position).as_dvec3();
                            (lo.min(p), hi.max(p))
                        },
                    );
                    (lo.cmple(hi).all()).then_some((lo, hi))
                });
            if let Some((min, max)) = drawn.or(whole.bounds) {
                // A margin for the selection's handles, which stand out of its frame.
                let pad = DVec3::splat((max - min).max_element() * 0.12);
                self.orbit.fit_box(min - pad, max + pad);
            }
            return;
        }
        if let Some(volume) = editor.volume() {
            let (min, max) = volume.domain();
            self.orbit.fit_box(min, max);
            return;
        }
        let (min, max) = editor.solid().domain();
        let extent = (max - min).max_element().max(1e-9);
        self.height = 0.5 * extent;
        let (lo, hi) = xi_range(editor);
        self.orbit.fit_box(
            DVec3::new(min.x, min.y, (lo * self.height).min(0.0)),
            DVec3::new(max.x, max.y, (hi * self.height).max(0.0)),
        );
    }

    /// World position of control point `p = (x, y, ξ)`.
    fn world(&self, p: DVec3) -> DVec3 {
        DVec3::new(p.x, p.y, p.z * self.height)
    }

    fn radius(editor: &Editor) -> f64 {
        let extent = match editor.volume() {
            Some(v) => (v.domain().1 - v.domain().0).max_element(),
            None => (editor.solid().domain().1 - editor.solid().domain().0).max_element(),
        };
        extent * SPHERE_RADIUS
    }

    /// A control point's sphere's radius as drawn: scaled with the part's placement.
    fn point_radius(&self, editor: &Editor) -> f64 {
        Self::radius(editor)
            * self
                .placement()
                .matrix3
                .determinant()
                .abs()
                .cbrt()
                .max(1e-9)
    }

    /// Forgets the surface drawn (another model was opened: it is not the new one's).
    pub fn forget_surface(&mut self) {
        self.surface.clear();
    }

    /// The world positions of the control points' spheres (the volume's or the patch's).
    fn centres(&self, editor: &Editor) -> Vec<DVec3> {
        if self.whole.as_ref().is_some_and(|w| !w.part) {
            return Vec::new();
        }
        let map = self.placement();
        match editor.volume() {
            Some(v) => v
                .net()
                .points()
                .iter()
                .map(|p| map.transform_point3(p.truncate()))
                .collect(),
            None => editor
                .solid()
                .net()
                .points()
                .iter()
                .map(|&p| self.world(p))
                .collect(),
        }
    }

    /// The CSS pixel where control point `index`'s sphere centre is drawn (`None` behind the eye).
    #[must_use]
    pub fn screen_of(&self, editor: &Editor, index: usize) -> Option<DVec2> {
        self.orbit.screen_of(*self.centres(editor).get(index)?)
    }

    /// The control point whose sphere the ray through CSS pixel `q` meets first.
    #[must_use]
    pub fn pick(&self, editor: &Editor, q: DVec2) -> Option<usize> {
        let (o, d) = self.orbit.ray(q);
        // Picking is a little more generous than the drawn sphere.
        let r = self.point_radius(editor) * 1.6;
        self.centres(editor)
            .into_iter()
            .enumerate()
            .filter_map(|(k, p)| {
                let c = p - o;
                let t = c.dot(d);
                let miss = c.length_squared() - t * t;
                (t > 0.0 && miss <= r * r).then(|| (k, t - (r * r - miss).sqrt()))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// Pointer pressed at CSS pixel `q`: `pan` (right button or Shift on empty space) pans; on a
    /// sphere the point is grabbed (in the editor's mode, the other with `other_mode`); elsewhere the
    /// camera orbits. Returns whether a control point was grabbed.
    pub fn pointer_down(
        &mut self,
        editor: &mut Editor,
        q: DVec2,
        pan: bool,
        other_mode: bool,
    ) -> bool {
        if !pan && let Some((handle, centre)) = self.pick_handle(q) {
            let (o, d) = self.orbit.ray(q);
            let grab = plane_hit(o, d, centre, self.back()).unwrap_or(centre);
            self.gesture = Some(Gesture::Handle(handle, q, centre, centre - grab));
            self.handle_drag = None;
            return true;
        }
        if !pan && let Some(k) = self.pick(editor, q) {
            let mode = if other_mode {
                editor.mode().other()
            } else {
                editor.mode()
            };
            if let Some(volume) = editor.volume() {
                let p = volume.net().points()[k];
                let (o, d) = self.orbit.ray(q);
                let back = self.back();
                let at = self.placement().transform_point3(p.truncate());
                let grab = plane_hit(o, d, at, back).unwrap_or(at);
                editor.begin_volume_drag(k);
                self.gesture = Some(Gesture::VolumePoint(mode, q, p, at - grab));
                return true;
            }
            let centre = self.world(editor.solid().net().points()[k]);
            let grab = self.grab_point(centre, mode, q).unwrap_or(centre);
            editor.begin_drag(k, mode);
            self.gesture = Some(Gesture::Point(mode, centre - grab));
            return true;
        }
        if !pan && let Some(s) = self.section {
            let (o, d) = self.orbit.ray(q);
            if let Some(grab) = s.hit(o, d) {
                self.gesture = Some(Gesture::Plane(s.at, grab));
                self.section_drag = None;
                return false;
            }
        }
        self.orbit.pointer_down(q, pan || other_mode);
        false
    }

    /// Where the pointer ray meets the constraint of a drag through `centre`: the vertical line
    /// (function mode) or the horizontal plane (space mode).
    fn grab_point(&self, centre: DVec3, mode: Mode, q: DVec2) -> Option<DVec3> {
        let (o, d) = self.orbit.ray(q);
        match mode {
            Mode::Space => {
                if d.z.abs() < 1e-9 {
                    return None;
                }
                let t = (centre.z - o.z) / d.z;
                (t > 0.0).then(|| o + d * t)
            }
            Mode::Function => {
                // The point of the line centre + s·z closest to the ray.
                let w = o - centre;
                let b = d.z;
                let denom = 1.0 - b * b;
                if denom < 1e-9 {
                    return None;
                }
                let s = (w.z - b * d.dot(w)) / denom;
                Some(centre + DVec3::Z * s)
            }
        }
    }

    /// Pointer moved to CSS pixel `q`. Returns whether anything changed (camera or model).
    pub fn pointer_move(&mut self, editor: &mut Editor, q: DVec2) -> bool {
        match self.gesture {
            None => self.orbit.pointer_move(q),
            Some(Gesture::Plane(start, grab)) => {
                let Some(s) = self.section else {
                    return false;
                };
                // The point of the line through the grab point along the axis nearest the ray.
                let (o, d) = self.orbit.ray(q);
                let w = o - grab;
                let b = d[s.axis];
                let denom = 1.0 - b * b;
                if denom < 1e-9 {
                    // Looking along the axis: the ray says nothing about where along it.
                    return false;
                }
                let along = (w[s.axis] - b * d.dot(w)) / denom;
                let at = (start + along).clamp(s.lo[s.axis], s.hi[s.axis]);
                self.section_drag = Some(at);
                true
            }
            Some(Gesture::Handle(handle, start, centre, offset)) => {
                let amount = match handle {
                    Handle::Move => {
                        let (o, d) = self.orbit.ray(q);
                        match plane_hit(o, d, centre, self.back()) {
                            Some(hit) => hit + offset - centre,
                            None => return false,
                        }
                    }
                    Handle::Turn => DVec3::new((q.x - start.x) * TURN_PER_PIXEL, 0.0, 0.0),
                    Handle::Scale => {
                        DVec3::new(((start.y - q.y) * SCALE_PER_PIXEL).exp(), 0.0, 0.0)
                    }
                };
                self.handle_drag = Some((handle, amount));
                true
            }
            Some(Gesture::VolumePoint(mode, start, p, offset)) => match mode {
                Mode::Function => {
                    editor.drag_volume_to(None, Some(p.w + (start.y - q.y) * XI_PER_PIXEL))
                }
                Mode::Space => {
                    let (o, d) = self.orbit.ray(q);
                    let map = self.placement();
                    let at = map.transform_point3(p.truncate());
                    match plane_hit(o, d, at, self.back()) {
                        Some(hit) => editor.drag_volume_to(
                            Some(map.inverse().transform_point3(hit + offset)),
                            None,
                        ),
                        None => false,
                    }
                }
            },
            Some(Gesture::Point(mode, offset)) => {
                let Some(k) = editor.dragged() else {
                    self.gesture = None;
                    return false;
                };
                let centre = self.world(editor.solid().net().points()[k]);
                let Some(hit) = self.grab_point(centre, mode, q) else {
                    return false;
                };
                let to = hit + offset;
                match mode {
                    Mode::Function => editor.drag_to(None, Some(to.z / self.height)),
                    Mode::Space => editor.drag_to(Some(to.truncate()), None),
                }
            }
        }
    }

    /// Pointer released: ends the gesture (a point drag is one undo step).
    pub fn pointer_up(&mut self, editor: &mut Editor) {
        if matches!(
            self.gesture,
            Some(Gesture::Point(..) | Gesture::VolumePoint(..))
        ) {
            editor.end_drag();
        }
        self.gesture = None;
        self.orbit.pointer_up();
    }

    /// Whether a gesture is under way.
    #[must_use]
    pub fn busy(&self) -> bool {
        self.gesture.is_some() || self.orbit.busy()
    }

    /// The wheel: zooms.
    pub fn wheel(&mut self, delta_y: f64) {
        self.orbit.wheel(delta_y);
    }

    /// Two fingers: zoom by their spread's `scale` and pan by their midpoint's `delta` CSS pixels
    /// ([`crate::camera::Camera::pinch`]). Refused while a point or a handle is dragged (cancel
    /// it first); returns whether the camera moved.
    pub fn pinch(&mut self, scale: f64, delta: DVec2) -> bool {
        if self.gesture.is_some() {
            return false;
        }
        self.orbit.pinch(scale, delta)
    }

    /// Cancels the gesture under way (a second finger came down: the gesture is a pinch): a
    /// point's drag puts the point back as Esc does, an orbit or a pan stops where it is. A
    /// handle's drag is its owner's to end ([`crate::parts::Parts::end_handle`]); here it only
    /// stops.
    pub fn cancel(&mut self, editor: &mut Editor) {
        if matches!(
            self.gesture,
            Some(Gesture::Point(..) | Gesture::VolumePoint(..))
        ) && editor.busy()
        {
            editor.cancel();
        }
        self.gesture = None;
        self.handle_drag = None;
        self.orbit.pointer_up();
    }

    /// The camera's backward unit vector (eye − target): the normal of the plane a volume's point
    /// is dragged in.
    fn back(&self) -> DVec3 {
        let camera = self.orbit.camera();
        (camera.eye() - camera.target).normalize()
    }

    /// Sets the volume surface's resolution at rest (cells along the longest side, 8 to
    /// [`MAX_RESOLUTION`]); returns the value taken.
    pub fn set_resolution(&mut self, resolution: usize) -> usize {
        self.resolution = resolution.clamp(8, MAX_RESOLUTION);
        self.resolution
    }

    /// The volume surface's resolution at rest.
    #[must_use]
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// Meshes coarsely (while a point moves) or at the resolution set (at rest).
    pub fn set_coarse(&mut self, coarse: bool) {
        self.coarse = coarse;
    }

    /// The triangle count of the volume's surface last drawn and the resolution it was made at.
    #[must_use]
    pub fn surface_info(&self) -> Option<(usize, usize)> {
        self.surface
            .drawn()
            .map(|m| (m.vertices.len() / 3, m.resolution))
    }

    /// Whether the surface drawn is of `editor`'s model as it is now.
    #[must_use]
    pub fn surface_is_current(&self, editor: &Editor) -> bool {
        self.surface.info(self.surface_key(editor)).is_some()
    }

    /// Whether the fine surface and the contour stack are made elsewhere (see
    /// [`Self::set_surface`] and [`Self::set_stack`]).
    pub fn set_external_surface(&mut self, external: bool) {
        self.external = external;
    }

    /// The contour stack wanted from elsewhere since the last call: `(revision, axis)`. It is
    /// asked for at rest only (not while a point is being dragged).
    pub fn take_stack_request(&mut self) -> Option<(u64, Axis)> {
        self.stack_request.take()
    }

    /// Hands in a contour stack made elsewhere ([`stack_segments`]) for model `revision` across
    /// `axis`: six `f64` per segment (its two ends). A stack for an older revision or another axis
    /// is dropped (a newer edit supersedes it); returns whether it was taken.
    pub fn set_stack(&mut self, editor: &Editor, revision: u64, axis: Axis, data: &[f64]) -> bool {
        let Some(volume) = editor.volume() else {
            return false;
        };
        let current = editor.slice().map_or(Axis::W, |(a, _)| a);
        if revision != editor.revision() || axis != current || !data.len().is_multiple_of(6) {
            return false;
        }
        self.stack = Some(StackCache {
            revision,
            axis,
            stack: stack_vertices(volume, data),
            segments: data.len() / 6,
        });
        true
    }

    /// The contour stack drawn now: its segments, and whether it is of the model as it is (not
    /// the previous one, drawn while the new one is being made); `None` when none is drawn.
    #[must_use]
    pub fn stack_info(&self, editor: &Editor) -> Option<(usize, bool)> {
        self.stack.as_ref().map(|c| {
            let axis = editor.slice().map_or(Axis::W, |(a, _)| a);
            (
                c.segments,
                c.revision == editor.revision() && c.axis == axis,
            )
        })
    }

    /// The fine surface wanted from elsewhere since the last call: `(revision, resolution)`.
    pub fn take_request(&mut self) -> Option<(u64, usize)> {
        self.surface.take_request()
    }

    /// Hands in a surface made elsewhere for model `revision` at `resolution`: `data` holds six
    /// `f32` per vertex (position, normal), three vertices per triangle. A surface for an older
    /// revision is dropped (a newer edit supersedes it); returns whether it was taken.
    pub fn set_surface(
        &mut self,
        editor: &Editor,
        revision: u64,
        resolution: usize,
        data: &[f32],
    ) -> bool {
        if (editor.volume().is_none() && self.whole.is_none()) || !data.len().is_multiple_of(18) {
            return false;
        }
        let vertices = float_vertices(data, SURFACE_COLOR);
        let current = self.surface_key(editor);
        if self.whole.is_some() {
            self.surface
                .hand_in_newer(revision, current, resolution, vertices)
        } else {
            self.surface
                .hand_in(revision, current, resolution, vertices)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::geometry::{SPHERE_TRIANGLES, sphere_detail};
    use super::*;
    use bezsolid_core::Solid2;

    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn setup() -> (Editor, View3) {
        let editor = Editor::new(Solid2::fig9());
        let mut view = View3::new(&editor);
        view.resize(&editor, 800.0, 600.0);
        (editor, view)
    }

    /// Where world point `p` lands, in CSS pixels.
    fn project(view: &View3, p: DVec3) -> DVec2 {
        let m = view.camera().view_proj(800.0 / 600.0, 2.0);
        let clip: [f64; 4] =
            core::array::from_fn(|r| (0..3).map(|c| m[c][r] * p[c]).sum::<f64>() + m[3][r]);
        let ndc = DVec2::new(clip[0] / clip[3], clip[1] / clip[3]);
        DVec2::new((ndc.x + 1.0) * 400.0, (1.0 - ndc.y) * 300.0)
    }

    #[test]
    fn rays_go_through_the_pixels_points_project_to() {
        let (_, view) = setup();
        for p in [
            DVec3::ZERO,
            DVec3::new(1.0, 0.3, 0.4),
            DVec3::new(0.5, 1.0, -0.5),
        ] {
            let q = project(&view, p);
            let (o, d) = view.orbit.ray(q);
            let miss = (p - o).cross(d).length();
            assert!(miss < 1e-9, "{p}: {miss}");
        }
        // Depth in 0..1 with the target in between.
        let m = view.camera().view_proj(800.0 / 600.0, 2.0);
        let t = view.camera().target;
        let z: f64 = (0..3).map(|c| m[c][2] * t[c]).sum::<f64>() + m[3][2];
        let w: f64 = (0..3).map(|c| m[c][3] * t[c]).sum::<f64>() + m[3][3];
        assert!((0.0..1.0).contains(&(z / w)));
    }

    #[test]
    fn a_sphere_is_picked_and_dragged_along_its_vertical_in_function_mode() {
        let (mut editor, mut view) = setup();
        let centre = DVec3::new(0.5, 0.5, 1.0 * view.height);
        let q = project(&view, centre);
        assert!((view.screen_of(&editor, 4).unwrap() - q).length() < 1e-9);
        assert_eq!(view.pick(&editor, q), Some(4));
        assert!(view.pointer_down(&mut editor, q, false, false));
        assert_eq!(editor.selected(), Some((1, 1)));
        // Up on the screen raises ξ; the point stays where it is in x, y.
        let target = project(&view, centre + DVec3::Z * 0.25 * view.height);
        assert!(view.pointer_move(&mut editor, target));
        view.pointer_up(&mut editor);
        let p = editor.selected_point().unwrap();
        assert!((p.z - 1.25).abs() < 1e-6, "ξ = {}", p.z);
        assert_eq!((p.x, p.y), (0.5, 0.5));
        assert!(editor.undo(), "one undo step");
        assert_eq!(editor.solid(), &Solid2::fig9());
    }

    #[test]
    fn space_mode_moves_the_sphere_in_its_plane() {
        let (mut editor, mut view) = setup();
        editor.set_mode(Mode::Space);
        let corner = DVec3::new(1.0, 1.0, -view.height);
        let q = project(&view, corner);
        assert!(view.pointer_down(&mut editor, q, false, false));
        let to = project(&view, corner + DVec3::new(0.2, 0.1, 0.0));
        assert!(view.pointer_move(&mut editor, to));
        view.pointer_up(&mut editor);
        let p = editor.selected_point().unwrap();
        assert!((p - DVec3::new(1.2, 1.1, -1.0)).length() < 1e-6, "{p}");
        assert!(editor.solid().inverse().is_some());
    }

    #[test]
    fn empty_space_orbits_pans_and_zooms_the_camera() {
        let (mut editor, mut view) = setup();
        let before = *view.camera();
        assert!(!view.pointer_down(&mut editor, DVec2::new(5.0, 5.0), false, false));
        assert!(view.pointer_move(&mut editor, DVec2::new(105.0, 5.0)));
        view.pointer_up(&mut editor);
        assert!(
            (view.camera().yaw - (before.yaw - core::f64::consts::TAU * 100.0 / 600.0)).abs()
                < 1e-12
        );
        assert_eq!(view.camera().distance, before.distance);
        assert!(!view.pointer_down(&mut editor, DVec2::new(5.0, 5.0), true, false));
        view.pointer_move(&mut editor, DVec2::new(5.0, 50.0));
        view.pointer_up(&mut editor);
        assert_ne!(view.camera().target, before.target);
        view.wheel(100.0);
        assert!(view.camera().distance > before.distance);
        // The pitch never reaches the pole.
        view.pointer_down(&mut editor, DVec2::new(5.0, 5.0), false, false);
        view.pointer_move(&mut editor, DVec2::new(5.0, 5000.0));
        assert!(view.camera().pitch < core::f64::consts::FRAC_PI_2);
        view.pointer_up(&mut editor);
        assert_eq!(editor.solid(), &Solid2::fig9(), "the camera never edits");
        assert!(!editor.can_undo());
        view.fit(&editor);
        assert_eq!(view.camera().distance, before.distance);
    }

    #[test]
    fn two_fingers_zoom_and_pan_and_cancel_a_point_drag() {
        let (mut editor, mut view) = setup();
        let before = *view.camera();
        assert!(view.pinch(2.0, DVec2::new(30.0, 0.0)));
        assert!((view.camera().distance - before.distance / 2.0).abs() < 1e-12);
        assert_ne!(
            view.camera().target,
            before.target,
            "the midpoint's move pans"
        );
        assert!(!view.pinch(f64::NAN, DVec2::ZERO) && !view.pinch(0.0, DVec2::ZERO));
        // A second finger on a point's drag: the point goes back, no undo step, then the pinch.
        let at = view.screen_of(&editor, 4).unwrap();
        assert!(view.pointer_down(&mut editor, at, false, false));
        assert!(view.pointer_move(&mut editor, at - DVec2::new(0.0, 40.0)));
        assert_ne!(editor.solid(), &Solid2::fig9());
        assert!(!view.pinch(1.5, DVec2::ZERO), "not during a drag");
        view.cancel(&mut editor);
        assert!(!view.busy() && !editor.busy());
        assert_eq!(editor.solid(), &Solid2::fig9());
        assert!(!editor.can_undo());
        assert_eq!(editor.selected(), Some((1, 1)), "the point stays selected");
        assert!(view.pinch(1.5, DVec2::ZERO));
        // An orbit cancelled stops; nothing is deselected.
        view.pointer_down(&mut editor, DVec2::new(5.0, 5.0), false, false);
        view.cancel(&mut editor);
        assert!(!view.busy());
        assert_eq!(editor.selected(), Some((1, 1)));
    }

    #[test]
    fn the_scene_has_the_surface_spheres_and_plane() {
        let (mut editor, mut view) = setup();
        let height = view.height;
        let scene = view.scene(&editor);
        assert!(scene.opaque.len() > SURFACE_CELLS * SURFACE_CELLS * 6);
        assert_eq!(scene.opaque.len() % 3, 0);
        assert_eq!(scene.translucent.len(), 6);
        assert!(
            scene
                .opaque
                .iter()
                .all(|v| v.position.iter().all(|x| x.is_finite()))
        );
        // The surface's highest vertex is the centre, at h·ξ with ξ = S_ξ(1/2, 1/2).
        let top = scene.opaque[..SURFACE_CELLS * SURFACE_CELLS * 6]
            .iter()
            .map(|v| v.position[2])
            .fold(f32::MIN, f32::max);
        let expected = editor.solid().net().eval([0.5, 0.5]).z * height;
        assert!(
            (f64::from(top) - expected).abs() < 1e-3,
            "{top} vs {expected}"
        );
        let (generation, matrix) = (scene.generation, scene.view_proj);
        assert!(view.surface_info().is_none(), "no volume, no surface");
        // Moving the camera keeps the triangles (no new generation to upload); an edit or a new
        // selection makes new ones.
        view.wheel(100.0);
        view.orbit.pointer_down(DVec2::new(100.0, 100.0), false);
        view.orbit.pointer_move(DVec2::new(130.0, 110.0));
        view.orbit.pointer_up();
        let moved = view.scene(&editor);
        assert_eq!(moved.generation, generation);
        assert_ne!(moved.view_proj, matrix, "the camera moved");
        editor.select(Some((0, 0)));
        assert_ne!(view.scene(&editor).generation, generation);
        let selected = view.scene(&editor).generation;
        editor.set_selected_xi(0.5).unwrap();
        assert_ne!(view.scene(&editor).generation, selected);
    }

    /// A piecewise patch's surface is its cells' polynomials over the global parameter, not the
    /// global net read as one patch.
    #[test]
    fn a_piecewise_patch_is_drawn_cell_by_cell() {
        let (mut editor, mut view) = setup();
        let mut parts = crate::parts::Parts::of_editor(&mut editor).unwrap();
        parts.add_cell(0, &mut editor).unwrap();
        let pieces = editor.piecewise2().unwrap();
        let height = view.height;
        let scene = view.scene(&editor);
        // The vertex over the middle of the edge the cells share (t = (1/2, 1/2), a grid point).
        let t = [0.5, 0.5];
        let p = pieces.eval(t);
        let z = scene.opaque[..SURFACE_CELLS * SURFACE_CELLS * 6]
            .iter()
            .find(|v| {
                (f64::from(v.position[0]) - p.x).abs() < 1e-5
                    && (f64::from(v.position[1]) - p.y).abs() < 1e-5
            })
            .map(|v| f64::from(v.position[2]))
            .unwrap();
        assert!((z - p.z * height).abs() < 1e-4, "{z} vs {}", p.z * height);
        let single = editor.solid().net().eval(t).z * height;
        assert!((z - single).abs() > 1e-2, "not the global net as one patch");
    }

    /// A piecewise volume's surface, drawn while the fine one is made elsewhere, lies on the
    /// piecewise solid's boundary: its cells' polynomials, not its global net read as one.
    #[test]
    fn a_piecewise_volume_is_drawn_cell_by_cell() {
        let (_, mut editor, mut view) = blob_elsewhere();
        let mut parts = crate::parts::Parts::of_editor(&mut editor).unwrap();
        parts.add_cell(0, &mut editor).unwrap();
        let pieces = editor.piecewise3().unwrap();
        let _ = view.scene(&editor);
        let drawn = view.surface.drawn().unwrap();
        assert_eq!(drawn.revision, view.surface_key(&editor));
        assert!(drawn.vertices.len() > 300, "{}", drawn.vertices.len());
        let worst = |f: &dyn Fn(DVec3) -> f64| {
            drawn
                .vertices
                .iter()
                .map(|v| f(DVec3::from_array(v.position.map(f64::from))).abs())
                .fold(0.0, f64::max)
        };
        assert!(
            worst(&|p| pieces.f(p)) < 1e-5,
            "{}",
            worst(&|p| pieces.f(p))
        );
        // The global net read as one volume is another solid.
        let single = editor.volume().unwrap().clone();
        let as_one = surface_mesh(&single, COARSE_RESOLUTION).unwrap();
        let off = as_one
            .positions
            .iter()
            .map(|&p| pieces.f(p).abs())
            .fold(0.0, f64::max);
        assert!(off > 1e-3, "{off}");
    }

    /// The blob volume in a view whose fine surface is made elsewhere, its scene drawn once.
    fn blob_elsewhere() -> (Solid3, Editor, View3) {
        use bezsolid_core::model::ModelSolid;
        use bezsolid_core::presets::Preset;
        let ModelSolid::Volume(blob) = Preset::Blob.solid() else {
            unreachable!()
        };
        let (mut editor, mut view) = setup();
        editor.set_volume(blob.clone());
        view.set_external_surface(true);
        let _ = view.scene(&editor);
        (blob, editor, view)
    }

    /// The true section's plane is drawn (translucent, with its frame), and a drag on its frame
    /// moves it along its axis within the box; a drag in its middle orbits the camera.
    #[test]
    fn the_section_plane_is_drawn_and_its_frame_drags_it_along_its_axis() {
        use bezsolid_core::model::ModelSolid;
        use bezsolid_core::presets::Preset;
        let ModelSolid::Volume(blob) = Preset::Blob.solid() else {
            unreachable!()
        };
        let (mut editor, mut view) = setup();
        editor.set_volume(blob.clone());
        view.fit(&editor);
        let (lo, hi) = blob.domain();
        view.set_section_plane(Some(SectionPlane {
            axis: 2,
            at: 0.0,
            lo,
            hi,
        }));
        let scene = view.scene(&editor);
        assert!(
            scene
                .translucent
                .iter()
                .any(|v| v.color == SECTION_COLOR && v.position[2] == 0.0)
        );
        let revision = editor.revision();
        // Inside the frame, between the control points: the camera orbits.
        let middle = project(&view, DVec3::new(0.5, -0.5, 0.0));
        assert!(!view.pointer_down(&mut editor, middle, false, false));
        assert!(!view.section_dragged());
        view.pointer_up(&mut editor);
        // Its frame, on the edge x = lo between two control points: the plane is grabbed and
        // follows upwards.
        let edge = project(&view, DVec3::new(lo.x, 0.5, 0.0));
        assert!(view.over_section(edge));
        assert!(!view.pointer_down(&mut editor, edge, false, false));
        assert!(view.section_dragged());
        assert!(view.pointer_move(&mut editor, edge - DVec2::new(0.0, 40.0)));
        let up = view.take_section_drag().unwrap();
        assert!(up > 0.05 && up <= hi.z, "{up}");
        // Down: below the middle; far down or up, held at the box's faces.
        assert!(view.pointer_move(&mut editor, edge + DVec2::new(0.0, 60.0)));
        assert!(view.take_section_drag().unwrap() < -0.1);
        assert!(view.pointer_move(&mut editor, edge + DVec2::new(0.0, 300.0)));
        assert_eq!(view.take_section_drag(), Some(lo.z));
        assert!(view.pointer_move(&mut editor, edge - DVec2::new(0.0, 600.0)));
        assert_eq!(view.take_section_drag(), Some(hi.z));
        view.pointer_up(&mut editor);
        assert!(!view.section_dragged());
        assert_eq!(editor.revision(), revision, "the model is not edited");
    }

    /// A cap cuts the surface at its plane and closes it there (the cut face's vertices lie on
    /// the plane, its normals across it); a new cap asks for a new surface and one made for the
    /// old cap is not taken; without it the surface is whole again.
    #[test]
    fn a_cap_cuts_the_surface_at_its_plane_and_asks_for_a_new_one() {
        let (blob, editor, mut view) = blob_elsewhere();
        let (before, _) = view.take_request().unwrap();
        let highest = |view: &View3| {
            let m = view.surface.drawn().unwrap();
            m.vertices
                .iter()
                .map(|v| v.position[2])
                .fold(f32::NEG_INFINITY, f32::max)
        };
        assert!(highest(&view) > 0.5, "the whole blob reaches up");
        view.set_cap(Some((2, 0.25)));
        let _ = view.scene(&editor);
        let (after, wanted) = view.take_request().unwrap();
        assert_ne!(after, before);
        assert_eq!(after, view.surface_key(&editor));
        // The coarse surface drawn meanwhile is cut: nothing above the plane, a face on it.
        assert!(highest(&view) <= 0.25 + 1e-6, "{}", highest(&view));
        let m = view.surface.drawn().unwrap();
        let on_plane: Vec<_> = m
            .vertices
            .iter()
            .filter(|v| (v.position[2] - 0.25).abs() < 1e-5)
            .collect();
        assert!(on_plane.len() > 30, "{}", on_plane.len());
        assert!(on_plane.iter().any(|v| v.normal[2] > 0.99));
        // A surface made for the key before the cap is not taken.
        let data = surface_floats(&blob, wanted);
        assert!(!view.set_surface(&editor, before, wanted, &data));
        // The same cap again asks for nothing new; no cap asks for the whole surface.
        view.set_cap(Some((2, 0.25)));
        assert_eq!(view.surface_key(&editor), after);
        view.set_cap(None);
        let _ = view.scene(&editor);
        assert!(view.take_request().is_some());
        assert!(highest(&view) > 0.5);
    }

    #[test]
    fn a_surface_made_elsewhere_replaces_the_coarse_one_for_its_revision_only() {
        let (blob, mut editor, mut view) = blob_elsewhere();
        let (coarse, res) = view.surface_info().unwrap();
        assert_eq!(res, COARSE_RESOLUTION);
        let (revision, wanted) = view.take_request().unwrap();
        assert_eq!(
            (revision, wanted),
            (view.surface_key(&editor), DEFAULT_RESOLUTION)
        );
        assert!(view.take_request().is_none());
        let data = surface_floats(&blob, wanted);
        // A surface for an older revision is dropped.
        assert!(!view.set_surface(&editor, revision.wrapping_sub(1), wanted, &data));
        assert!(view.set_surface(&editor, revision, wanted, &data));
        let _ = view.scene(&editor);
        let (fine, res) = view.surface_info().unwrap();
        assert_eq!(res, DEFAULT_RESOLUTION);
        assert!(fine > coarse);
        assert_eq!(fine, surface_mesh(&blob, wanted).unwrap().triangles.len());
        assert!(view.take_request().is_none(), "nothing more to ask for");
        // Local meshing (no worker) makes the fine surface at once.
        view.set_external_surface(false);
        editor.select(Some((1, 1)));
        editor.set_selected_xi(0.7).unwrap();
        let _ = view.scene(&editor);
        assert_eq!(view.surface_info().unwrap().1, DEFAULT_RESOLUTION);
    }

    #[test]
    fn a_stack_made_elsewhere_is_the_stack_made_here_and_only_for_its_revision() {
        use bezsolid_core::model::ModelSolid;
        use bezsolid_core::presets::Preset;
        let ModelSolid::Volume(fish) = Preset::Fish.solid() else {
            unreachable!()
        };
        // Here: the stack is made while the scene is built.
        let (mut editor, mut here) = setup();
        editor.set_volume(fish.clone());
        let _ = here.scene(&editor);
        let (segments, current) = here.stack_info(&editor).unwrap();
        assert!(segments > 50 && current, "{segments}");
        let local = here.stack.clone().unwrap().stack;
        // Elsewhere: asked for at rest, once, and drawn when handed in for this revision.
        let mut there = View3::new(&editor);
        there.resize(&editor, 800.0, 600.0);
        there.set_external_surface(true);
        let _ = there.scene(&editor);
        assert!(
            there.stack_info(&editor).is_none(),
            "nothing drawn before it comes"
        );
        let (revision, axis) = there.take_stack_request().unwrap();
        assert_eq!((revision, axis), (editor.revision(), Axis::W));
        let mut calls = Vec::new();
        let (data, approximate) =
            stack_segments(&fish, axis, |done, total| calls.push((done, total)));
        assert_eq!(approximate, 0, "the fish is exact");
        assert_eq!(
            calls,
            (1..=3).map(|k| (k, 3)).collect::<Vec<_>>(),
            "one call a slice"
        );
        assert!(!there.set_stack(&editor, revision.wrapping_sub(1), axis, &data));
        assert!(
            !there.set_stack(&editor, revision, Axis::U, &data),
            "another axis"
        );
        let before = there.scene(&editor).opaque.len();
        assert_eq!(
            there.take_stack_request(),
            Some((revision, axis)),
            "asked for while it is not there"
        );
        assert!(there.set_stack(&editor, revision, axis, &data));
        assert_eq!(there.stack.as_ref().unwrap().stack, local, "the same rods");
        // It is drawn as soon as it comes (nothing else changed: the scene is built again).
        assert_eq!(there.scene(&editor).opaque.len(), before + local.len());
        assert!(
            there.take_stack_request().is_none(),
            "nothing more to ask for"
        );
        // An edit: the previous stack stays drawn, and the new one is asked for at rest only.
        editor.select(Some((1, 1)));
        editor.set_selected_xi(0.9).unwrap();
        there.set_coarse(true);
        let _ = there.scene(&editor);
        assert_eq!(there.stack_info(&editor), Some((segments, false)));
        assert!(
            there.take_stack_request().is_none(),
            "not while a point moves"
        );
        there.set_coarse(false);
        let _ = there.scene(&editor);
        assert_eq!(
            there.take_stack_request(),
            Some((editor.revision(), Axis::W))
        );
        // A drag of a slice's point in the 2D view: nothing is asked of the worker until it ends.
        let _ = there.take_request();
        editor.begin_drag(4, Mode::Function);
        assert!(editor.drag_to(None, Some(0.3)));
        let _ = there.scene(&editor);
        assert!(there.take_stack_request().is_none() && there.take_request().is_none());
        assert_eq!(there.surface_info().unwrap().1, COARSE_RESOLUTION);
        editor.end_drag();
        let _ = there.scene(&editor);
        assert_eq!(
            there.take_stack_request(),
            Some((editor.revision(), Axis::W))
        );
        assert_eq!(
            there.take_request(),
            Some((there.surface_key(&editor), DEFAULT_RESOLUTION))
        );
        // Another axis: the stack across the old one is no longer drawn.
        editor.set_slice(Axis::U, 0).unwrap();
        let _ = there.scene(&editor);
        assert!(there.stack_info(&editor).is_none());
    }

    #[test]
    fn many_control_points_are_drawn_with_coarser_spheres_within_the_budget() {
        assert_eq!(
            sphere_detail(16 * 16),
            (8, 12),
            "a patch keeps round spheres"
        );
        assert_eq!(sphere_detail(7 * 7 * 3), (8, 12));
        let (rings, segments) = sphere_detail(17 * 17 * 17);
        assert!(17 * 17 * 17 * rings * segments * 2 <= SPHERE_TRIANGLES);
        let mut out = Vec::new();
        sphere(&mut out, DVec3::ZERO, 1.0, SELECT_COLOR, (rings, segments));
        assert_eq!(out.len(), rings * segments * 6);
        assert!(out.iter().all(|v| {
            let p = glam::Vec3::from_array(v.position);
            (p.length() - 1.0).abs() < 1e-6 && p.dot(glam::Vec3::from_array(v.normal)) > 0.99
        }));
        // A degree-16 volume's scene: the spheres within the budget.
        let (mut editor, mut view) = setup();
        editor.set_volume(
            Solid3::regular([16, 16, 16], DVec3::ZERO, DVec3::ONE, |[_, _, _]| 0.25).unwrap(),
        );
        let scene = view.scene(&editor);
        assert!(
            scene.opaque.len() < SPHERE_TRIANGLES * 3 + 200_000,
            "{}",
            scene.opaque.len()
        );
    }
}
