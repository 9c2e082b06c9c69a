//! What a 3D view hands the renderer ([`Scene`]: cached triangles and a camera), and the one cache
//! of a surface drawn coarse now and fine once it comes from elsewhere ([`Refined`]), which the
//! Bézier volume view and the free-form view share.

use crate::color::Rgba;

/// One vertex of the 3D geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshVertex {
    /// World position.
    pub position: [f32; 3],
    /// Unit normal (the shading is two-sided).
    pub normal: [f32; 3],
    /// Straight RGBA.
    pub color: Rgba,
}

impl MeshVertex {
    /// Bytes of one vertex: 10 little-endian `f32`.
    pub const SIZE: usize = 40;

    /// Appends the vertex's bytes (`float32x3`, `float32x3`, `float32x4`).
    pub fn write(&self, out: &mut Vec<u8>) {
        for x in self.position.iter().chain(&self.normal).chain(&self.color) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
}

/// Everything one 3D redraw needs. The triangles are borrowed from the view's cache: they are
/// rebuilt only when the model, the selection, the slice or the surface changes, not when the camera
/// moves, and `generation` tells the renderer whether to upload them again.
#[derive(Clone, Debug)]
pub struct Scene<'a> {
    /// Opaque triangles (surface, spheres, guides), drawn first.
    pub opaque: &'a [MeshVertex],
    /// Translucent triangles (the plane ξ = 0), drawn last.
    pub translucent: &'a [MeshVertex],
    /// Changes whenever the triangles do.
    pub generation: u64,
    /// Clip from world, column-major (`wgpu`'s depth range 0 to 1).
    pub view_proj: [[f32; 4]; 4],
    /// The camera's position, for the headlight.
    pub eye: [f32; 3],
}

/// A number for a new set of triangles, never handed out before: the patch, volume and free-form
/// scenes draw on one renderer, which uploads the triangles again whenever the generation it
/// last drew changes, so their generations must not collide.
pub fn next_generation() -> u64 {
    static NEXT: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, core::sync::atomic::Ordering::Relaxed)
}

/// Triangles from six `f32` per vertex (position, normal), in one colour.
#[must_use]
pub fn float_vertices(data: &[f32], color: Rgba) -> Vec<MeshVertex> {
    data.chunks_exact(6)
        .map(|v| MeshVertex {
            position: [v[0], v[1], v[2]],
            normal: [v[3], v[4], v[5]],
            color,
        })
        .collect()
}

/// A surface made for one revision of what it shows, at one resolution.
#[derive(Clone, Debug)]
pub struct Made {
    /// The revision of the model it shows.
    pub revision: u64,
    /// The resolution it was made at.
    pub resolution: usize,
    /// Its triangles, three vertices each.
    pub vertices: Vec<MeshVertex>,
}

/// A surface drawn coarse now and fine once it comes from elsewhere (a Web Worker): the surface
/// drawn, and the fine one wanted. A surface made elsewhere is taken only for the revision it was
/// asked for: a newer edit supersedes it. While a new resolution is being made, the surface the
/// revision already has stays drawn.
#[derive(Clone, Debug, Default)]
pub struct Refined {
    made: Option<Made>,
    request: Option<(u64, usize)>,
}

impl Refined {
    /// Brings the surface to `revision` at `resolution`. With `elsewhere`, the fine surface is
    /// asked for ([`Self::take_request`]) and, if this revision has none yet, one is made here at
    /// `coarse`; otherwise it is made here at `resolution`. `make(resolution)` makes triangles.
    pub fn update(
        &mut self,
        revision: u64,
        resolution: usize,
        coarse: usize,
        elsewhere: bool,
        make: impl FnOnce(usize) -> Vec<MeshVertex>,
    ) {
        if self.has(revision, resolution) {
            return;
        }
        let local = if elsewhere {
            self.request = Some((revision, resolution));
            if self.made.as_ref().is_some_and(|m| m.revision == revision) {
                return;
            }
            coarse
        } else {
            resolution
        };
        if !self.has(revision, local) {
            self.made = Some(Made {
                revision,
                resolution: local,
                vertices: make(local),
            });
        }
    }

    /// Whether the surface drawn is of `revision` at `resolution`.
    #[must_use]
    pub fn has(&self, revision: u64, resolution: usize) -> bool {
        self.made
            .as_ref()
            .is_some_and(|m| m.revision == revision && m.resolution == resolution)
    }

    /// Asks for the fine surface of `revision` at `resolution` (after an edit or a new
    /// resolution), unless it is drawn already.
    pub fn ask(&mut self, revision: u64, resolution: usize) {
        if !self.has(revision, resolution) {
            self.request = Some((revision, resolution));
        }
    }

    /// The fine surface wanted since the last call: `(revision, resolution)`.
    pub fn take_request(&mut self) -> Option<(u64, usize)> {
        self.request.take()
    }

    /// Hands in a surface made elsewhere for `revision` at `resolution`, taken only when
    /// `revision` is `current`; returns whether it was.
    pub fn hand_in(
        &mut self,
        revision: u64,
        current: u64,
        resolution: usize,
        vertices: Vec<MeshVertex>,
    ) -> bool {
        self.take(revision == current, revision, resolution, vertices)
    }

    /// Keeps `vertices` as the surface drawn when `wanted`; returns `wanted`.
    fn take(
        &mut self,
        wanted: bool,
        revision: u64,
        resolution: usize,
        vertices: Vec<MeshVertex>,
    ) -> bool {
        if wanted {
            self.made = Some(Made {
                revision,
                resolution,
                vertices,
            });
        }
        wanted
    }

    /// Hands in a surface made elsewhere for `revision` at `resolution`, taken when it is newer
    /// than the one drawn and not past `current` (a surface that follows a stream of edits: each
    /// one drawn is closer to the model); returns whether it was.
    pub fn hand_in_newer(
        &mut self,
        revision: u64,
        current: u64,
        resolution: usize,
        vertices: Vec<MeshVertex>,
    ) -> bool {
        let newer = self.made.as_ref().is_none_or(|m| {
            m.revision < revision || (m.revision == revision && m.resolution != resolution)
        });
        self.take(revision <= current && newer, revision, resolution, vertices)
    }

    /// The surface drawn now.
    #[must_use]
    pub fn drawn(&self) -> Option<&Made> {
        self.made.as_ref()
    }

    /// The triangles and resolution of the surface drawn, if it is of `revision`.
    #[must_use]
    pub fn info(&self, revision: u64) -> Option<(usize, usize)> {
        self.made
            .as_ref()
            .filter(|m| m.revision == revision)
            .map(|m| (m.vertices.len() / 3, m.resolution))
    }

    /// Forgets the surface and the request (another model).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tris(resolution: usize) -> Vec<MeshVertex> {
        let v = MeshVertex {
            position: [resolution as f32; 3],
            normal: [0.0, 0.0, 1.0],
            color: [1.0; 4],
        };
        vec![v; 3 * resolution]
    }

    #[test]
    fn coarse_now_fine_from_elsewhere_for_its_revision_only() {
        let mut r = Refined::default();
        r.update(1, 64, 24, true, tris);
        assert_eq!(r.info(1), Some((24, 24)));
        assert_eq!(r.take_request(), Some((1, 64)));
        assert_eq!(r.take_request(), None);
        // A surface for an older revision is dropped; the current one is taken.
        assert!(!r.hand_in(0, 1, 64, tris(64)));
        assert!(r.hand_in(1, 1, 64, tris(64)));
        assert_eq!(r.info(1), Some((64, 64)));
        r.update(1, 64, 24, true, |_| unreachable!("drawn already"));
        // A new resolution keeps the revision's surface drawn until it comes.
        r.update(1, 96, 24, true, |_| {
            unreachable!("this revision has a surface")
        });
        assert_eq!(r.info(1), Some((64, 64)));
        assert_eq!(r.take_request(), Some((1, 96)));
        // An edit: coarse again.
        r.update(2, 96, 24, true, tris);
        assert_eq!(r.info(2), Some((24, 24)));
        assert_eq!(r.info(1), None);
        assert_eq!(r.take_request(), Some((2, 96)));
        // Made here when nothing is made elsewhere.
        r.update(3, 40, 24, false, tris);
        assert_eq!(r.info(3), Some((40, 40)));
        assert_eq!(r.take_request(), None, "nothing asked of elsewhere");
    }
}
