//! What the Free-form mode's 3D view draws: the triangles of each display (the result's surface,
//! the point mesh, the operands' PN surfaces), their colours, and the meshes and surfaces as
//! vertices.

use bezsolid_core::esc::Boolean;
use bezsolid_core::mesh::Mesh;
use glam::DVec3;

use super::{COARSE_RESOLUTION, Display, FreeForm, GHOST_TRIANGLES, POINT_MESH, VIEW_TRIANGLES};
use crate::color::Rgba;
use crate::scene::{MeshVertex, Scene, next_generation};
use crate::view3d::mesh_floats;

pub(super) const RESULT_COLOR: Rgba = [0.42, 0.62, 0.86, 1.0];
/// The operands' colours, in turn: A blue, B orange, then green, purple, teal, red.
const OPERAND_COLORS: [Rgba; 6] = [
    [0.42, 0.62, 0.86, 1.0],
    [0.92, 0.6, 0.32, 1.0],
    [0.4, 0.72, 0.42, 1.0],
    [0.66, 0.5, 0.82, 1.0],
    [0.3, 0.7, 0.7, 1.0],
    [0.85, 0.4, 0.45, 1.0],
];
const GHOST_ALPHA: f32 = 0.1;
const INSIDE_COLOR: Rgba = [0.3, 0.34, 0.42, 1.0];
const MARKED_COLOR: Rgba = [0.9, 0.12, 0.1, 1.0];

/// What the triangles depend on: the revision, the display, and the surface's revision and
/// resolution.
type GeometryKey = (u64, Display, Option<(u64, usize)>);

/// The triangles for one key: key, generation, opaque, translucent.
pub(super) type Geometry = (GeometryKey, u64, Vec<MeshVertex>, Vec<MeshVertex>);

impl FreeForm {
    /// Everything one redraw needs; the triangles are rebuilt only when the scene, the display or
    /// the surface changes.
    pub fn scene(&mut self) -> Scene<'_> {
        let shows_surface = self.display == Display::Result;
        if shows_surface {
            // A coarse surface now, the fine one from elsewhere.
            let boolean = &self.boolean;
            self.surface.update(
                self.revision,
                self.resolution,
                COARSE_RESOLUTION,
                true,
                |r| mesh_vertices(&boolean.surface(r), RESULT_COLOR),
            );
        }
        // Only the result display depends on the surface (its arrival redraws nothing else).
        let key = (
            self.revision,
            self.display,
            self.surface
                .drawn()
                .filter(|_| shows_surface)
                .map(|m| (m.revision, m.resolution)),
        );
        if self.geometry.as_ref().is_none_or(|g| g.0 != key) {
            let (opaque, translucent, counts) = self.build();
            if let Some((inside, marked)) = counts {
                self.point_counts = Some((self.revision, inside, marked));
            }
            self.generation = next_generation();
            self.geometry = Some((key, self.generation, opaque, translucent));
        }
        let (lo, hi) = self.extent_box();
        let extent = (hi - lo).length().max(1e-9);
        match &self.geometry {
            Some(g) => self.orbit.scene(&g.2, &g.3, g.1, extent),
            None => self.orbit.scene(&[], &[], 0, extent),
        }
    }

    /// The triangles of the current display, and the point mesh's counts when it is shown.
    fn build(&self) -> (Vec<MeshVertex>, Vec<MeshVertex>, Option<(usize, usize)>) {
        let mut opaque = Vec::new();
        let mut translucent = Vec::new();
        let mut counts = None;
        let ghost = |c: Rgba| [c[0], c[1], c[2], GHOST_ALPHA];
        let pn = |k: usize, color: Rgba, out: &mut Vec<MeshVertex>| {
            if let Some(s) = self.boolean.solids.get(k) {
                let level = tessellation_level(s.triangles().len(), 4, GHOST_TRIANGLES);
                out.extend(mesh_vertices(&s.surface().tessellate(level), color));
            }
        };
        let color = |k: usize| OPERAND_COLORS[k % OPERAND_COLORS.len()];
        let n = self.boolean.solids.len();
        match self.display {
            Display::Result => {
                if let Some(m) = self.surface.drawn() {
                    opaque.extend_from_slice(&m.vertices);
                }
                for k in 0..n {
                    pn(k, ghost(color(k)), &mut translucent);
                }
            }
            Display::Operands => {
                // A opaque, the others see-through so that what they overlap shows.
                pn(0, color(0), &mut opaque);
                for k in 1..n {
                    let c = color(k);
                    pn(k, [c[0], c[1], c[2], 0.55], &mut translucent);
                }
            }
            Display::Points => {
                let points = self.boolean.point_mesh(POINT_MESH);
                counts = Some((points.inside.len(), points.marked.len()));
                let r = points.step * 0.22;
                for p in &points.inside {
                    octahedron(&mut opaque, *p, r, INSIDE_COLOR);
                }
                for p in &points.marked {
                    octahedron(&mut opaque, *p, r * 1.15, MARKED_COLOR);
                }
            }
        }
        (opaque, translucent, counts)
    }

    /// Counts of the point mesh last drawn for this scene: `(in the result or partial chain,
    /// marked)`; `None` before it is drawn.
    #[must_use]
    pub fn point_counts(&self) -> Option<(usize, usize)> {
        self.point_counts
            .filter(|c| c.0 == self.revision)
            .map(|c| (c.1, c.2))
    }
}

/// A mesh as triangle-list vertices of one colour.
#[must_use]
pub fn mesh_vertices(mesh: &Mesh, color: Rgba) -> Vec<MeshVertex> {
    let mut out = Vec::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        for &i in t {
            out.push(MeshVertex {
                position: mesh.positions[i as usize].as_vec3().to_array(),
                normal: mesh.normals[i as usize].as_vec3().to_array(),
                color,
            });
        }
    }
    out
}

/// The result's surface as the page draws it at rest, for the resolution setting `resolution`
/// (cells along the longest side of an exported mesh): the solids' PN surfaces, each patch split
/// into `(resolution / 16)²` triangles and trimmed along the others
/// ([`Boolean::trimmed_surface`]), as six `f32` per vertex, three vertices per triangle (what the
/// worker hands to [`FreeForm::set_surface`]). Crisper than a mesh of the same cost: the
/// intersection curves are followed, not cut across by grid cells.
#[must_use]
pub fn surface_floats(boolean: &Boolean, resolution: usize) -> Vec<f32> {
    let patches = boolean.solids.iter().map(|s| s.triangles().len()).sum();
    let level = tessellation_level(patches, (resolution / 16).clamp(1, 10), VIEW_TRIANGLES);
    mesh_floats(&boolean.trimmed_surface(level))
}

/// Triangles per patch edge: `wanted`, or fewer so that `patches · level²` stays within
/// `budget` (at least 1): a 200 k-triangle import is drawn with one triangle per patch, not 16.
#[must_use]
pub fn tessellation_level(patches: usize, wanted: usize, budget: usize) -> usize {
    let fit = (budget as f64 / patches.max(1) as f64).sqrt() as usize;
    wanted.min(fit).max(1)
}

/// A small octahedron (a point of the point mesh).
pub(crate) fn octahedron(out: &mut Vec<MeshVertex>, c: DVec3, r: f64, color: Rgba) {
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let a = axes[0] * sx;
                let b = axes[1] * sy;
                let z = axes[2] * sz;
                // Counter-clockwise seen from outside.
                let (p, q) = if sx * sy * sz > 0.0 { (a, b) } else { (b, a) };
                let n = (p + q + z).normalize();
                for v in [p, q, z] {
                    out.push(MeshVertex {
                        position: (c + v * r).as_vec3().to_array(),
                        normal: n.as_vec3().to_array(),
                        color,
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::freeform::DEFAULT_RESOLUTION;
    use bezsolid_core::esc::Op;

    #[test]
    fn the_default_scene_draws_every_display() {
        let mut f = FreeForm::new();
        for d in [Display::Result, Display::Points, Display::Operands] {
            f.set_display(d);
            let scene = f.scene();
            assert!(!scene.opaque.is_empty(), "{d:?}");
        }
        // The coarse surface is drawn and the fine one requested.
        assert_eq!(f.surface_info().map(|s| s.1), Some(COARSE_RESOLUTION));
        let (revision, resolution) = f.surface_request().expect("a request");
        assert_eq!(resolution, DEFAULT_RESOLUTION);
        let fine = surface_floats(f.boolean(), resolution);
        assert!(f.set_surface(revision, resolution, &fine));
        assert_eq!(f.surface_info().map(|s| s.1), Some(DEFAULT_RESOLUTION));
        // A stale surface is refused.
        f.set_operation(Some(Op::Union)).unwrap();
        assert!(!f.set_surface(revision, resolution, &fine));
    }

    #[test]
    fn big_meshes_are_drawn_coarser() {
        assert_eq!(tessellation_level(5120, 4, VIEW_TRIANGLES), 4);
        assert_eq!(tessellation_level(200_000, 4, VIEW_TRIANGLES), 1);
        assert_eq!(tessellation_level(60_000, 4, VIEW_TRIANGLES), 3);
        assert_eq!(tessellation_level(0, 4, VIEW_TRIANGLES), 4);
    }
}
