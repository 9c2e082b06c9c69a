//! The true section's plane in the 3D view: where it lies, and its drag along its axis.

use super::geometry::plane_hit;
use super::*;

/// The true section's plane as the 3D view shows it: across `axis` at `at`, over the box
/// `lo`…`hi` of the other two axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionPlane {
    /// 0 = x, 1 = y, 2 = z.
    pub axis: usize,
    /// Where it lies along the axis.
    pub at: f64,
    /// The model's box: the plane's extent, and the range it moves in.
    pub lo: DVec3,
    /// See `lo`.
    pub hi: DVec3,
}

impl SectionPlane {
    /// Its four corners, in order around it.
    pub(super) fn corners(&self) -> [DVec3; 4] {
        let (a, b) = match self.axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let corner = |i: bool, j: bool| {
            let mut p = self.lo;
            p[self.axis] = self.at;
            p[a] = if i { self.hi[a] } else { self.lo[a] };
            p[b] = if j { self.hi[b] } else { self.lo[b] };
            p
        };
        [
            corner(false, false),
            corner(true, false),
            corner(true, true),
            corner(false, true),
        ]
    }

    /// Where the ray `o + t·d` meets the plane's frame: the band along its edges, a tenth of
    /// its extent wide on either side of them (the middle is left to orbiting the camera).
    pub(super) fn hit(&self, o: DVec3, d: DVec3) -> Option<DVec3> {
        let mut n = DVec3::ZERO;
        n[self.axis] = 1.0;
        let mut p = self.lo;
        p[self.axis] = self.at;
        let hit = plane_hit(o, d, p, n)?;
        let mut near_edge = false;
        for k in (0..3).filter(|&k| k != self.axis) {
            let t = (hit[k] - self.lo[k]) / (self.hi[k] - self.lo[k]).max(f64::MIN_POSITIVE);
            if !(-RIM..=1.0 + RIM).contains(&t) {
                return None;
            }
            near_edge |= !(RIM..=1.0 - RIM).contains(&t);
        }
        near_edge.then_some(hit)
    }
}

/// The width of the section plane's frame that a drag grabs, as a fraction of its extent.
pub(super) const RIM: f64 = 0.1;

impl View3 {
    /// Shows the true section's plane (`None`: no section), which a drag on it moves along its
    /// axis within the box.
    pub fn set_section_plane(&mut self, plane: Option<SectionPlane>) {
        self.section = plane;
    }

    /// Where a drag of the section's plane asks it to be, since the last call.
    pub fn take_section_drag(&mut self) -> Option<f64> {
        self.section_drag.take()
    }

    /// Whether the section's plane is being dragged.
    #[must_use]
    pub fn section_dragged(&self) -> bool {
        matches!(self.gesture, Some(Gesture::Plane(..)))
    }

    /// Whether the ray through CSS pixel `q` meets the section's plane.
    #[must_use]
    pub fn over_section(&self, q: DVec2) -> bool {
        let (o, d) = self.orbit.ray(q);
        self.section.and_then(|s| s.hit(o, d)).is_some()
    }

    /// The CSS pixel of the section plane's point at fractions `(s, t)` of its extent along its
    /// two other axes in order (`(0.5, 0.5)` its centre, `0` or `1` on its frame); `None` with no
    /// section (or behind the eye).
    #[must_use]
    pub fn section_screen(&self, s: f64, t: f64) -> Option<DVec2> {
        let plane = self.section?;
        let c = plane.corners();
        // Corners in order: (lo, lo), (hi, lo), (hi, hi), (lo, hi) of the two other axes.
        let p = c[0] + (c[1] - c[0]) * s + (c[3] - c[0]) * t;
        self.orbit.screen_of(p)
    }
}
