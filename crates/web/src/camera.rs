//! The orbit camera every 3D view contains: [`Camera`] (where it looks from, its projection and its
//! rays) and [`OrbitView`] (a camera with its viewport and the orbit, pan and zoom gestures, with
//! the conventions of three.js `OrbitControls`: left drag orbits, right or Shift drag pans, the
//! wheel zooms, two fingers zoom and pan).

use glam::{DVec2, DVec3};

use crate::scene::{MeshVertex, Scene};

/// Orbit: radians per CSS pixel of drag, as `OrbitControls` (a full turn per view height).
const ORBIT_PER_PIXEL: f64 = core::f64::consts::TAU;
/// Zoom: the distance is multiplied by `exp(deltaY · ZOOM_PER_WHEEL)` (a notch of 100 is ×1.105).
const ZOOM_PER_WHEEL: f64 = 0.001;
/// The camera's vertical field of view.
const FOV_Y: f64 = 0.75;
/// Pitch stays inside ±(π/2 − this), as `OrbitControls` keeps the pole out of reach.
const POLE_MARGIN: f64 = 0.01;
/// The most one pinch step changes the distance (a jump of the fingers' spread is not a zoom).
const PINCH_STEP: f64 = 5.0;
/// The eye's distance to the target stays within these.
const DISTANCE: (f64, f64) = (1e-6, 1e9);

/// An orbit camera around a target, z up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The point looked at and orbited.
    pub target: DVec3,
    /// Distance from the target to the eye.
    pub distance: f64,
    /// Angle around z, from +x.
    pub yaw: f64,
    /// Angle above the xy plane.
    pub pitch: f64,
}

impl Camera {
    /// A camera that frames the box `[min, max]` from the front right, above, in a viewport of
    /// `aspect` (width / height).
    #[must_use]
    pub fn fit(min: DVec3, max: DVec3, aspect: f64) -> Self {
        let radius = ((max - min).length() * 0.5).max(1e-9);
        // The narrower of the two fields of view must hold the box's bounding sphere.
        let half_x = ((FOV_Y * 0.5).tan() * aspect.clamp(0.05, 20.0)).atan();
        let half = half_x.min(FOV_Y * 0.5);
        Self {
            target: (min + max) * 0.5,
            distance: radius / half.sin() * 1.02,
            yaw: -1.1,
            pitch: 0.55,
        }
    }

    /// The eye's position.
    #[must_use]
    pub fn eye(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + DVec3::new(cp * cy, cp * sy, sp) * self.distance
    }

    /// The camera's right, up and backward (eye − target) unit vectors.
    fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let back = (self.eye() - self.target).normalize();
        let right = DVec3::Z.cross(back).normalize();
        let up = back.cross(right);
        (right, up, back)
    }

    /// Near and far planes that hold a scene of size `extent` around the target.
    fn clip_planes(&self, extent: f64) -> (f64, f64) {
        let near = (self.distance - extent * 2.0).max(self.distance * 1e-3);
        (near, self.distance + extent * 2.0)
    }

    /// Clip from world for a viewport of `aspect` (width / height), column-major.
    #[must_use]
    pub fn view_proj(&self, aspect: f64, extent: f64) -> [[f64; 4]; 4] {
        let (r, u, b) = self.basis();
        let e = self.eye();
        // View: rows are the camera axes; translation −axis·eye.
        let view = [
            [r.x, u.x, b.x, 0.0],
            [r.y, u.y, b.y, 0.0],
            [r.z, u.z, b.z, 0.0],
            [-r.dot(e), -u.dot(e), -b.dot(e), 1.0],
        ];
        let (near, far) = self.clip_planes(extent);
        let f = 1.0 / (FOV_Y * 0.5).tan();
        let a = aspect.max(1e-6);
        // Right-handed perspective to depth 0 (near) .. 1 (far).
        let proj = [
            [f / a, 0.0, 0.0, 0.0],
            [0.0, f, 0.0, 0.0],
            [0.0, 0.0, far / (near - far), -1.0],
            [0.0, 0.0, near * far / (near - far), 0.0],
        ];
        let mut out = [[0.0; 4]; 4];
        for (c, col) in out.iter_mut().enumerate() {
            for (r, x) in col.iter_mut().enumerate() {
                *x = (0..4).map(|k| proj[k][r] * view[c][k]).sum();
            }
        }
        out
    }

    /// The ray through CSS pixel `q` of a viewport of `size`: origin (the eye) and unit direction.
    #[must_use]
    pub fn ray(&self, q: DVec2, size: DVec2) -> (DVec3, DVec3) {
        let (r, u, b) = self.basis();
        let t = (FOV_Y * 0.5).tan();
        let ndc = DVec2::new(q.x / size.x * 2.0 - 1.0, 1.0 - q.y / size.y * 2.0);
        let dir = r * ndc.x * t * (size.x / size.y) + u * ndc.y * t - b;
        (self.eye(), dir.normalize())
    }

    /// Orbits by a pointer move of `delta` CSS pixels in a viewport `height` pixels tall: right
    /// turns the scene right, up tilts it towards the viewer.
    pub fn orbit(&mut self, delta: DVec2, height: f64) {
        let k = ORBIT_PER_PIXEL / height.max(1.0);
        self.yaw -= delta.x * k;
        let limit = core::f64::consts::FRAC_PI_2 - POLE_MARGIN;
        self.pitch = (self.pitch + delta.y * k).clamp(-limit, limit);
    }

    /// Pans so that the point under the pointer follows it.
    pub fn pan(&mut self, delta: DVec2, height: f64) {
        let (r, u, _) = self.basis();
        let per_pixel = 2.0 * self.distance * (FOV_Y * 0.5).tan() / height.max(1.0);
        self.target += (-r * delta.x + u * delta.y) * per_pixel;
    }

    /// Zooms by a wheel `delta_y` (positive: away).
    pub fn zoom(&mut self, delta_y: f64) {
        if delta_y.is_finite() {
            self.distance = (self.distance * (delta_y * ZOOM_PER_WHEEL).clamp(-1.0, 1.0).exp())
                .clamp(DISTANCE.0, DISTANCE.1);
        }
    }

    /// Two fingers moved: their spread grew by `scale` (the scene is magnified as much: the eye
    /// comes closer) and their midpoint moved by `delta` CSS pixels (the scene follows, as a pan).
    /// Values that are not numbers, and a `scale` that is not positive, change nothing; returns
    /// whether the camera moved.
    pub fn pinch(&mut self, scale: f64, delta: DVec2, height: f64) -> bool {
        if !(scale.is_finite() && scale > 0.0 && delta.is_finite()) {
            return false;
        }
        let scale = scale.clamp(1.0 / PINCH_STEP, PINCH_STEP);
        self.distance = (self.distance / scale).clamp(DISTANCE.0, DISTANCE.1);
        // At most a few viewports' worth of pan per step: finite whatever the fingers report.
        let reach = 4.0 * height.max(1.0);
        self.pan(
            delta.clamp(DVec2::splat(-reach), DVec2::splat(reach)),
            height,
        );
        true
    }
}

/// An orbit camera with its viewport and gesture, for the views whose only interaction is the
/// camera (the free-form and script views): left drag orbits, right or Shift drag pans, the
/// wheel zooms, and the view refits on resize until the camera is moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitView {
    camera: Camera,
    size: DVec2,
    /// Panning or orbiting, and the last pointer position.
    gesture: Option<(bool, DVec2)>,
    /// The user has moved the camera since it was last fitted.
    moved: bool,
}

impl Default for OrbitView {
    fn default() -> Self {
        Self {
            camera: Camera::fit(DVec3::splat(-1.0), DVec3::ONE, 1.0),
            size: DVec2::new(640.0, 480.0),
            gesture: None,
            moved: false,
        }
    }
}

impl OrbitView {
    /// Frames the box `[lo, hi]`; a flat box (a plane drawing at z = 0, its lines drawn as thin
    /// tubes: under 2% as deep as it is large) is seen from above, x to the right and y up.
    pub fn fit(&mut self, lo: DVec3, hi: DVec3) {
        self.fit_box(lo, hi);
        let size = hi - lo;
        if size.z <= 0.02 * size.length() {
            self.camera.yaw = -core::f64::consts::FRAC_PI_2;
            self.camera.pitch = core::f64::consts::FRAC_PI_2 - POLE_MARGIN;
        }
    }

    /// Frames the box `[lo, hi]` from the front right, above, however flat it is.
    pub fn fit_box(&mut self, lo: DVec3, hi: DVec3) {
        self.camera = Camera::fit(lo, hi, self.size.x / self.size.y.max(1.0));
        self.moved = false;
    }

    /// The viewport's size in CSS pixels (below 1, or not a number, becomes 1); refits to
    /// `[lo, hi]` unless the camera was moved.
    pub fn resize(&mut self, width: f64, height: f64, (lo, hi): (DVec3, DVec3)) {
        let ok = |x: f64| if x.is_finite() && x >= 1.0 { x } else { 1.0 };
        self.size = DVec2::new(ok(width), ok(height));
        if !self.moved {
            self.fit(lo, hi);
        }
    }

    /// The viewport's size in CSS pixels.
    #[must_use]
    pub fn size(&self) -> DVec2 {
        self.size
    }

    /// The ray through CSS pixel `q`: origin (the eye) and unit direction.
    #[must_use]
    pub fn ray(&self, q: DVec2) -> (DVec3, DVec3) {
        self.camera.ray(q, self.size)
    }

    /// The CSS pixel where world point `p` is drawn (`None` behind the eye).
    #[must_use]
    pub fn screen_of(&self, p: DVec3) -> Option<DVec2> {
        let m = self.camera.view_proj(self.size.x / self.size.y, 1.0);
        let clip: [f64; 4] =
            core::array::from_fn(|r| (0..3).map(|c| m[c][r] * p[c]).sum::<f64>() + m[3][r]);
        (clip[3] > 0.0).then(|| {
            let ndc = DVec2::new(clip[0] / clip[3], clip[1] / clip[3]);
            DVec2::new((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5) * self.size
        })
    }

    /// Whether an orbit or pan is under way.
    #[must_use]
    pub fn busy(&self) -> bool {
        self.gesture.is_some()
    }

    /// Whether the user moved the camera since it was last fitted.
    #[must_use]
    pub fn moved(&self) -> bool {
        self.moved
    }

    /// Pointer pressed: orbit, or pan with `pan`.
    pub fn pointer_down(&mut self, q: DVec2, pan: bool) {
        self.gesture = Some((pan, q));
    }

    /// Pointer moved; returns whether the camera moved.
    pub fn pointer_move(&mut self, q: DVec2) -> bool {
        let Some((pan, last)) = self.gesture else {
            return false;
        };
        if pan {
            self.camera.pan(q - last, self.size.y);
        } else {
            self.camera.orbit(q - last, self.size.y);
        }
        self.gesture = Some((pan, q));
        self.moved = true;
        true
    }

    /// Pointer released.
    pub fn pointer_up(&mut self) {
        self.gesture = None;
    }

    /// The wheel: zooms.
    pub fn wheel(&mut self, delta_y: f64) {
        self.camera.zoom(delta_y);
        self.moved = true;
    }

    /// Two fingers: zoom by their spread's `scale` and pan by their midpoint's `delta` CSS pixels
    /// ([`Camera::pinch`]); an orbit or pan under way ends. Returns whether the camera moved.
    pub fn pinch(&mut self, scale: f64, delta: DVec2) -> bool {
        self.gesture = None;
        let moved = self.camera.pinch(scale, delta, self.size.y);
        self.moved |= moved;
        moved
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// A scene of cached triangles seen from here, for a model of size `extent`.
    #[must_use]
    pub fn scene<'a>(
        &self,
        opaque: &'a [MeshVertex],
        translucent: &'a [MeshVertex],
        generation: u64,
        extent: f64,
    ) -> Scene<'a> {
        let m = self.camera.view_proj(self.size.x / self.size.y, extent);
        Scene {
            opaque,
            translucent,
            generation,
            view_proj: m.map(|c| c.map(|x| x as f32)),
            eye: self.camera.eye().as_vec3().to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_pinch_zooms_by_the_spread_and_pans_by_the_midpoint() {
        let mut v = OrbitView::default();
        v.resize(400.0, 300.0, (DVec3::splat(-1.0), DVec3::ONE));
        let before = *v.camera();
        let target = v.screen_of(before.target).unwrap();
        assert!(v.pinch(2.0, DVec2::new(20.0, -10.0)));
        assert!(v.moved());
        assert!((v.camera().distance - before.distance / 2.0).abs() < 1e-12);
        // The target was at the centre; it follows the fingers' midpoint.
        let now = v.screen_of(before.target).unwrap();
        assert!(
            (now - (target + DVec2::new(20.0, -10.0))).length() < 1e-6,
            "{now}"
        );
        // Nothing that is not a number, or not positive, moves it; wild values stay finite.
        let kept = *v.camera();
        for bad in [f64::NAN, 0.0, -2.0, f64::INFINITY] {
            assert!(!v.pinch(bad, DVec2::ZERO));
        }
        assert!(!v.pinch(1.0, DVec2::new(f64::NAN, 0.0)));
        assert_eq!(*v.camera(), kept);
        for big in [1e9, 1e-9, 1e300, 1e-300, f64::MAX] {
            v.pinch(big, DVec2::splat(big));
            v.pinch(1.0 / big, DVec2::splat(-big));
            let c = v.camera();
            assert!(c.target.is_finite() && c.distance.is_finite() && c.distance > 0.0);
        }
    }

    #[test]
    fn a_pinch_ends_an_orbit() {
        let mut v = OrbitView::default();
        v.pointer_down(DVec2::new(10.0, 10.0), false);
        assert!(v.busy());
        v.pinch(1.2, DVec2::ZERO);
        assert!(!v.busy());
        assert!(!v.pointer_move(DVec2::new(50.0, 10.0)));
    }
}
