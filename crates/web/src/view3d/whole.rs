//! A model of many solids in the 3D view: the [`Whole`] around the open part, the selection's
//! handles and frame, and the whole model's geometry.

use super::geometry::volume_net;
use super::*;

/// A model of many solids around the part the editor holds: the 3D view then draws the whole
/// model's surface (made elsewhere, see [`View3::set_surface`]), the open part's control points
/// placed in space, and the selection's box.
#[derive(Clone, Debug, PartialEq)]
pub struct Whole {
    /// The open part's coordinates to space (the transforms above it).
    pub placement: DAffine3,
    /// Whether a Bézier volume is open in the editor (its control points drawn and dragged).
    pub part: bool,
    /// The selection's box in space, drawn as a frame.
    pub frame: Option<(DVec3, DVec3)>,
    /// The whole model's box: what the view frames.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Whether anything of the model is shown (not every part hidden): its surface is drawn.
    pub shown: bool,
    /// Whether the selection has handles (a part or an operation, not a Bézier part whose points
    /// are dragged instead): dragged, they move, turn and scale it.
    pub handles: bool,
}

/// A handle of the selection in a model of many solids, and what dragging it does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handle {
    /// Above the frame: moves the selection in the plane facing the camera.
    Move,
    /// On the frame's +x face: sideways turns the selection about z.
    Turn,
    /// At the frame's top corner: up grows the selection, down shrinks it.
    Scale,
}

/// Degrees of turn per CSS pixel of a [`Handle::Turn`] drag.
pub const TURN_PER_PIXEL: f64 = 0.5;

/// Scale factor per CSS pixel of a [`Handle::Scale`] drag, as an exponent (`e^(0.005 · 100)`
/// ≈ 1.65 for 100 pixels up).
pub const SCALE_PER_PIXEL: f64 = 0.005;

pub(super) const HANDLE_COLORS: [Rgba; 3] = [
    [1.0, 0.62, 0.0, 1.0],
    [0.16, 0.36, 0.78, 1.0],
    [0.18, 0.62, 0.3, 1.0],
];

/// The colour of the selection's frame in a model of many solids.
pub(super) const FRAME_COLOR: Rgba = [1.0, 0.62, 0.0, 1.0];

impl View3 {
    /// Puts the view in a model of many solids (`Some`), or back to a model of one (`None`).
    pub fn set_whole(&mut self, whole: Option<Whole>) {
        if self.whole != whole {
            if self.whole.is_none() || whole.is_none() {
                self.surface.clear();
                self.stack = None;
            }
            self.whole = whole;
            self.whole_generation += 1;
        }
    }

    /// The model of many solids the view is in.
    #[must_use]
    pub fn whole(&self) -> Option<&Whole> {
        self.whole.as_ref()
    }

    /// The selection's handles: which, where, and the radius drawn.
    pub(super) fn handles(&self) -> Vec<(Handle, DVec3, f64)> {
        let Some(Whole {
            handles: true,
            frame: Some((lo, hi)),
            bounds,
            ..
        }) = &self.whole
        else {
            return Vec::new();
        };
        let (lo, hi) = (*lo, *hi);
        if !(hi - lo).is_finite() {
            return Vec::new();
        }
        let extent = bounds.map_or((hi - lo).max_element(), |(a, b)| (b - a).max_element());
        let r = (extent * 0.025).max(1e-9);
        let c = 0.5 * (lo + hi);
        // Outside the frame, where the solid cannot cover them: above it, at its +x side and
        // past its top corner.
        vec![
            (Handle::Move, DVec3::new(c.x, c.y, hi.z + 3.0 * r), r * 1.2),
            (Handle::Turn, DVec3::new(hi.x + 3.0 * r, c.y, c.z), r),
            (Handle::Scale, hi + DVec3::splat(2.0 * r), r),
        ]
    }

    /// The handle the ray through CSS pixel `q` meets first.
    pub(super) fn pick_handle(&self, q: DVec2) -> Option<(Handle, DVec3)> {
        let (o, d) = self.orbit.ray(q);
        self.handles()
            .into_iter()
            .filter_map(|(h, c, r)| {
                let r = r * 1.4;
                let v = c - o;
                let t = v.dot(d);
                let miss = v.length_squared() - t * t;
                (t > 0.0 && miss <= r * r).then_some((h, c, t))
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(h, c, _)| (h, c))
    }

    /// Whether a handle of the selection is under CSS pixel `q`.
    #[must_use]
    pub fn over_handle(&self, q: DVec2) -> bool {
        self.pick_handle(q).is_some()
    }

    /// The CSS pixel of a handle's centre (`None` when the selection has none, or behind the
    /// eye).
    #[must_use]
    pub fn handle_screen(&self, handle: Handle) -> Option<DVec2> {
        let (_, c, _) = self.handles().into_iter().find(|(h, ..)| *h == handle)?;
        self.orbit.screen_of(c)
    }

    /// What the handle being dragged asks for since the drag began: the move in space
    /// ([`Handle::Move`]), the turn in degrees (`x` of [`Handle::Turn`]) or the scale factor (`x`
    /// of [`Handle::Scale`]); `None` when nothing new.
    pub fn take_handle(&mut self) -> Option<(Handle, DVec3)> {
        self.handle_drag.take()
    }

    /// The handle being dragged.
    #[must_use]
    pub fn handle_dragged(&self) -> Option<Handle> {
        match self.gesture {
            Some(Gesture::Handle(h, ..)) => Some(h),
            _ => None,
        }
    }

    /// The open part's coordinates to space.
    pub(super) fn placement(&self) -> DAffine3 {
        self.whole
            .as_ref()
            .map_or(DAffine3::IDENTITY, |w| w.placement)
    }

    /// A model of many solids: its surface, the open part's control points and its slice's net
    /// placed in space, and the selection's box as a frame.
    pub(super) fn whole_geometry(
        &self,
        editor: &Editor,
        whole: &Whole,
    ) -> (Vec<MeshVertex>, Vec<MeshVertex>, f64) {
        let mut opaque: Vec<MeshVertex> = Vec::new();
        if let Some(m) = self.surface.drawn() {
            opaque.extend_from_slice(&m.vertices);
        }
        let extent = whole
            .bounds
            .map_or(2.0, |(min, max)| (max - min).max_element().max(1e-9) * 1.5);
        let mut translucent = Vec::new();
        if let (true, Some(volume)) = (whole.part, editor.volume()) {
            volume_net(
                editor,
                volume,
                whole.placement,
                self.point_radius(editor),
                (&mut opaque, &mut translucent),
            );
        }
        for (k, (_, c, r)) in self.handles().into_iter().enumerate() {
            sphere(&mut opaque, c, r, HANDLE_COLORS[k], (10, 16));
        }
        if let Some((lo, hi)) = whole.frame {
            let r = extent * 0.002;
            let corner = |c: usize| {
                DVec3::new(
                    if c & 1 == 0 { lo.x } else { hi.x },
                    if c & 2 == 0 { lo.y } else { hi.y },
                    if c & 4 == 0 { lo.z } else { hi.z },
                )
            };
            for c in 0..8 {
                for bit in [1, 2, 4] {
                    if c & bit == 0 {
                        prism(&mut opaque, corner(c), corner(c | bit), r, FRAME_COLOR);
                    }
                }
            }
        }
        (opaque, translucent, extent)
    }
}
