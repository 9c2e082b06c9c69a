//! The 3D view's scene: the geometry of a patch or a volume, its caches, and the frame's
//! triangles.

use super::geometry::{
    model_vertices, net_rods, quad, sphere_detail, surface_vertices, volume_net, xi_range,
};
use super::*;

impl View3 {
    /// Builds the scene of `editor`'s model: the triangles come from the cache unless what they
    /// depend on changed; the camera is applied fresh.
    #[must_use]
    pub fn scene(&mut self, editor: &Editor) -> Scene<'_> {
        if self.whole.is_some() {
            let moving = self.coarse || editor.busy() || self.handle_dragged().is_some();
            let resolution = if moving {
                COARSE_RESOLUTION.min(self.resolution)
            } else {
                self.resolution
            };
            // The whole model's surface is made elsewhere only (it can be large); the one drawn
            // stays until the new one comes.
            if self.whole.as_ref().is_some_and(|w| w.shown) {
                self.surface.ask(self.surface_key(editor), resolution);
            } else {
                self.surface.clear();
            }
        } else if let Some(volume) = editor.volume() {
            self.update_volume_caches(editor, volume);
        }
        let key = GeometryKey {
            revision: editor.revision(),
            selected: editor.selected(),
            slice: editor.slice(),
            surface: self.surface.drawn().map(|m| (m.revision, m.resolution)),
            stack: self.stack.as_ref().map(|c| (c.revision, c.axis)),
            height: self.height.to_bits(),
            whole: self.whole_generation,
            section: self.section.map(|s| (s.axis, s.at.to_bits())),
        };
        if self.geometry.as_ref().is_none_or(|g| g.key != key) {
            let (mut opaque, mut translucent, extent) = match (&self.whole, editor.volume()) {
                (Some(whole), _) => self.whole_geometry(editor, whole),
                (None, Some(volume)) => self.volume_geometry(editor, volume),
                (None, None) => self.patch_geometry(editor),
            };
            if let Some(s) = self.section {
                translucent.extend(quad(s.corners(), SECTION_COLOR));
                let c = s.corners();
                let r = Self::radius(editor) * 0.25;
                for k in 0..4 {
                    prism(&mut opaque, c[k], c[(k + 1) % 4], r, SECTION_EDGE_COLOR);
                }
            }
            let generation = next_generation();
            self.geometry = Some(Geometry {
                key,
                generation,
                opaque,
                translucent,
                extent,
            });
        }
        match &self.geometry {
            Some(g) => self
                .orbit
                .scene(&g.opaque, &g.translucent, g.generation, g.extent),
            None => self.orbit.scene(&[], &[], 0, 1.0),
        }
    }

    /// A patch: the surface `(x, y, h·ξ)` coloured by ξ, the control points as spheres, the net as
    /// rods, and the plane ξ = 0.
    pub(super) fn patch_geometry(
        &self,
        editor: &Editor,
    ) -> (Vec<MeshVertex>, Vec<MeshVertex>, f64) {
        let solid = editor.solid();
        let patch = solid.net();
        let (lo, hi) = xi_range(editor);
        let scale = lo.abs().max(hi.abs()).max(1e-12);
        let mut opaque = Vec::new();

        // The surface over a parameter grid, normals from the grid's differences.
        let n = SURFACE_CELLS;
        let ts: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
        // A piecewise patch: each cell's polynomial over its share of the global parameter.
        let pts: Vec<DVec3> = match editor.piecewise2() {
            Some(pieces) => ts
                .iter()
                .flat_map(|&v| ts.iter().map(move |&u| [u, v]))
                .map(|t| self.world(pieces.eval(t)))
                .collect(),
            None => patch
                .eval_grid([&ts, &ts])
                .into_iter()
                .map(|p| self.world(p))
                .collect(),
        };
        let side = n + 1;
        let at = |a: usize, b: usize| pts[b * side + a];
        let normal = |a: usize, b: usize| {
            let du = at((a + 1).min(n), b) - at(a.saturating_sub(1), b);
            let dv = at(a, (b + 1).min(n)) - at(a, b.saturating_sub(1));
            du.cross(dv).normalize_or(DVec3::Z)
        };
        let vertex = |a: usize, b: usize| {
            let p = at(a, b);
            MeshVertex {
                position: p.as_vec3().to_array(),
                normal: normal(a, b).as_vec3().to_array(),
                color: diverging(p.z / self.height / scale),
            }
        };
        for b in 0..n {
            for a in 0..n {
                for (x, y) in [
                    (a, b),
                    (a + 1, b),
                    (a + 1, b + 1),
                    (a, b),
                    (a + 1, b + 1),
                    (a, b + 1),
                ] {
                    opaque.push(vertex(x, y));
                }
            }
        }

        // The control points as spheres coloured by ξ; the selected one orange on a guide line
        // down to the plane (the vertical it moves along in function mode).
        let r = Self::radius(editor);
        let [du, dv] = solid.degree();
        let selected = editor.selected().map(|(i, j)| i * (dv + 1) + j);
        let detail = sphere_detail(patch.points().len());
        for (k, p) in patch.points().iter().enumerate() {
            let c = self.world(*p);
            if selected == Some(k) {
                sphere(&mut opaque, c, r * 1.3, SELECT_COLOR, detail);
                prism(
                    &mut opaque,
                    DVec3::new(c.x, c.y, 0.0),
                    c,
                    r * 0.18,
                    GUIDE_COLOR,
                );
            } else {
                sphere(&mut opaque, c, r, diverging(p.z / scale), detail);
            }
        }
        net_rods(&mut opaque, (du, dv), |i, j| self.world(patch[[i, j]]), r);

        // The plane ξ = 0 over the domain with a margin.
        let (min, max) = solid.domain();
        let pad = (max - min).max_element() * 0.12;
        let (a, b) = (min - DVec2::splat(pad), max + DVec2::splat(pad));
        let translucent = quad(
            [
                DVec3::new(a.x, a.y, 0.0),
                DVec3::new(b.x, a.y, 0.0),
                DVec3::new(b.x, b.y, 0.0),
                DVec3::new(a.x, b.y, 0.0),
            ],
            PLANE_COLOR,
        );
        let extent = (max - min).max_element().max((hi - lo) * self.height) + pad;
        (opaque, translucent.to_vec(), extent)
    }

    /// Brings a volume's surface (remeshed only when the model or the resolution changed; a fine
    /// surface made elsewhere is asked for, with a coarse one drawn meanwhile) and its contour
    /// stack up to date.
    pub(super) fn update_volume_caches(&mut self, editor: &Editor, volume: &Solid3) {
        // A point moving in either view: the coarse surface, and nothing asked of the worker.
        let moving = self.coarse || editor.dragging();
        let resolution = if moving {
            COARSE_RESOLUTION.min(self.resolution)
        } else {
            self.resolution
        };
        let axis = editor.slice().map_or(Axis::W, |(a, _)| a);
        let revision = editor.revision();
        let cap = self.cap;
        // A piecewise volume is its cells' polynomials, not its global net read as one.
        let piecewise = editor.cells().is_some();
        self.surface.update(
            self.surface_key(editor),
            resolution,
            COARSE_RESOLUTION.min(resolution),
            self.external && !moving,
            |r| match cap {
                None if !piecewise => surface_vertices(volume, r),
                cap => model_vertices(editor, cap, r),
            },
        );
        if !self
            .stack
            .as_ref()
            .is_some_and(|c| c.revision == revision && c.axis == axis)
        {
            if self.external {
                // The previous stack across this axis stays drawn until the new one comes (a
                // folded net's slices cost seconds); one across another axis would mislead.
                if self.stack.as_ref().is_some_and(|c| c.axis != axis) {
                    self.stack = None;
                }
                if !moving {
                    self.stack_request = Some((revision, axis));
                }
            } else if !moving || self.stack.as_ref().is_none_or(|c| c.axis != axis) {
                let (data, _) = stack_segments(volume, axis, |_, _| {});
                self.stack = Some(StackCache {
                    revision,
                    axis,
                    stack: stack_vertices(volume, &data),
                    segments: data.len() / 6,
                });
            }
        }
    }

    /// A volume: its surface, the stack of its slices' zero contours, the control points as
    /// spheres coloured by ξ (the selected slice's larger), and the selected slice's net and plane.
    pub(super) fn volume_geometry(
        &self,
        editor: &Editor,
        volume: &Solid3,
    ) -> (Vec<MeshVertex>, Vec<MeshVertex>, f64) {
        let mut opaque: Vec<MeshVertex> = Vec::new();
        if let Some(m) = self.surface.drawn() {
            opaque.extend_from_slice(&m.vertices);
        }
        if let Some(c) = &self.stack {
            opaque.extend_from_slice(&c.stack);
        }
        let mut translucent = Vec::new();
        volume_net(
            editor,
            volume,
            DAffine3::IDENTITY,
            Self::radius(editor),
            (&mut opaque, &mut translucent),
        );
        let (min, max) = volume.domain();
        (opaque, translucent, (max - min).max_element() * 1.5)
    }
}
