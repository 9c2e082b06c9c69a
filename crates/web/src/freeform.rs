//! The Free-form mode as plain Rust: one or two solids bounded by PN triangles over
//! triangle meshes (built-in examples or imported files), a Boolean operation, and what the 3D view
//! shows of them: the result's surface, the paper's point mesh with the points the last term of the
//! chain removes marked red (Figs. 12–17), or the operands' PN surfaces.
//!
//! The model is a free-form model file (`kind: "esc"`), so it saves, opens and shares as the
//! Bézier models do. The fine surface of the result is meshed elsewhere (a Web Worker, through
//! [`FreeForm::surface_request`] and [`FreeForm::set_surface`]); until it comes a coarse one is
//! drawn.

use bezsolid_core::esc::Boolean;
use bezsolid_core::esc::EscSolid;
use bezsolid_core::esc::Example;
use bezsolid_core::esc::{Expr, Op};
use bezsolid_core::mesh::Mesh;
use bezsolid_core::model::{EscOperand, MeshSpec, ModelFile, SolidSpec};
use glam::DVec3;

use crate::camera::{Camera, OrbitView};
use crate::color::Rgba;
use crate::error::Error;
use crate::history::{History, Weighed};
use crate::scene::{MeshVertex, Refined, Scene, float_vertices, next_generation};
use crate::view3d::mesh_floats;

/// The result's surface while the fine one is being made (cells along the longest side).
pub const COARSE_RESOLUTION: usize = 16;
/// The result's surface at rest, by default.
pub const DEFAULT_RESOLUTION: usize = 64;
/// The most triangles of the trimmed result drawn at rest (more patches draw coarser).
pub const VIEW_TRIANGLES: usize = 600_000;
/// The most triangles of the operands' faint surfaces.
pub const GHOST_TRIANGLES: usize = 150_000;
/// Points along the longest side of the point mesh, as the paper's Fig. 19 (25 × 25 × 25).
pub const POINT_MESH: usize = 25;

const RESULT_COLOR: Rgba = [0.42, 0.62, 0.86, 1.0];
const A_COLOR: Rgba = [0.42, 0.62, 0.86, 1.0];
const B_COLOR: Rgba = [0.92, 0.6, 0.32, 1.0];
const GHOST_ALPHA: f32 = 0.1;
const INSIDE_COLOR: Rgba = [0.3, 0.34, 0.42, 1.0];
const MARKED_COLOR: Rgba = [0.9, 0.12, 0.1, 1.0];

/// What the 3D view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Display {
    /// The result's surface, with the operands' surfaces faintly.
    Result,
    /// The paper's intermediate point mesh: the partial chain's points, red where the last term
    /// removes them.
    Points,
    /// The operands' PN surfaces.
    Operands,
}

/// What the triangles depend on: the revision, the display, and the surface's revision and
/// resolution.
type GeometryKey = (u64, Display, Option<(u64, usize)>);

/// The triangles for one key: key, generation, opaque, translucent.
type Geometry = (GeometryKey, u64, Vec<MeshVertex>, Vec<MeshVertex>);

/// The most bytes the Free-form mode's undo and redo steps keep (each holds the operands, an
/// imported mesh whole): past it the oldest steps go, the newest always stays.
pub const HISTORY_BYTES: usize = 64 << 20;

/// The scene as an undo step keeps it: the operands, their file names and the operation.
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    operands: Vec<EscOperand>,
    names: Vec<Option<String>>,
    operation: Option<Op>,
}

impl Weighed for Snapshot {
    fn bytes(&self) -> usize {
        self.operands
            .iter()
            .map(|o| {
                64 + o
                    .mesh
                    .as_ref()
                    .map_or(0, |m| 24 * m.positions.len() + 12 * m.triangles.len())
            })
            .sum::<usize>()
            + self.names.iter().flatten().map(String::len).sum::<usize>()
    }
}

/// The Free-form mode's document, view and camera.
#[derive(Clone, Debug)]
pub struct FreeForm {
    operands: Vec<EscOperand>,
    /// The file names of imported meshes, by operand (`None` for a built-in example, which is
    /// named by the operand itself).
    names: Vec<Option<String>>,
    operation: Option<Op>,
    display: Display,
    resolution: usize,
    boolean: Boolean,
    revision: u64,
    /// The result's surface: coarse now, fine from elsewhere.
    surface: Refined,
    orbit: OrbitView,
    geometry: Option<Geometry>,
    /// The point mesh's counts `(inside, marked)` for a revision.
    point_counts: Option<(u64, usize, usize)>,
    generation: u64,
    /// The steps to undo and redo: every change of an operand, its place or the operation.
    history: History<Snapshot>,
}

impl Default for FreeForm {
    fn default() -> Self {
        Self::new()
    }
}

impl FreeForm {
    /// The default scene: the blob minus a torus through it.
    #[must_use]
    pub fn new() -> Self {
        let operands = vec![
            EscOperand::example(Example::Blob, [0.0; 3]),
            EscOperand::example(Example::Torus, [0.0, 0.0, 0.35]),
        ];
        let file = ModelFile::from_esc(Some(Op::Difference), operands);
        let mut f = Self {
            operands: Vec::new(),
            names: Vec::new(),
            operation: None,
            display: Display::Result,
            resolution: DEFAULT_RESOLUTION,
            boolean: Boolean {
                solids: Vec::new(),
                expr: Expr::Solid(0),
            },
            revision: 0,
            surface: Refined::default(),
            orbit: OrbitView::default(),
            geometry: None,
            point_counts: None,
            generation: 0,
            history: History::new(HISTORY_BYTES),
        };
        f.open(&file)
            .unwrap_or_else(|_| unreachable!("the default scene is valid"));
        f.history.clear();
        f
    }

    /// The model file of the scene.
    #[must_use]
    pub fn model_file(&self) -> ModelFile {
        ModelFile::from_esc(self.operation, self.operands.clone())
    }

    /// Opens a free-form model file.
    ///
    /// # Errors
    ///
    /// What is wrong with it (the scene is kept).
    pub fn open(&mut self, file: &ModelFile) -> Result<(), Error> {
        let boolean = file.to_boolean().map_err(Error::from)?;
        let SolidSpec::Esc {
            operation,
            operands,
        } = &file.solid
        else {
            return Err("not a free-form model".into());
        };
        let before = self.snapshot();
        self.operation = operation.as_deref().and_then(Op::from_name);
        self.operands = operands.clone();
        self.names = vec![None; operands.len()];
        self.boolean = boolean;
        self.changed();
        self.fit();
        self.record(before);
        Ok(())
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            operands: self.operands.clone(),
            names: self.names.clone(),
            operation: self.operation,
        }
    }

    /// Keeps `before` as an undo step if the scene is no longer that.
    fn record(&mut self, before: Snapshot) {
        if before.operands != self.operands
            || before.operation != self.operation
            || before.names != self.names
        {
            self.history.push(before);
        }
    }

    /// Undoes the last change of an operand, its place or the operation; returns whether there
    /// was one.
    pub fn undo(&mut self) -> bool {
        self.step(true)
    }

    /// Redoes the last undone change; returns whether there was one.
    pub fn redo(&mut self) -> bool {
        self.step(false)
    }

    fn step(&mut self, back: bool) -> bool {
        let now = self.snapshot();
        let Some(to) = (if back {
            self.history.undo(now)
        } else {
            self.history.redo(now)
        }) else {
            return false;
        };
        // A step was a scene that was built: it builds again.
        if self.apply(to.operands, to.operation).is_ok() {
            self.names = to.names;
        }
        true
    }

    /// Whether there is a change to undo.
    #[must_use]
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone change to redo.
    #[must_use]
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Forgets every undo and redo step (after restoring an autosaved scene at start-up).
    pub fn forget_history(&mut self) {
        self.history.clear();
    }

    fn changed(&mut self) {
        self.revision += 1;
        self.surface.ask(self.revision, self.resolution);
    }

    /// Rebuilds the solids from a changed operand list; on failure the scene stays as it was.
    fn apply(&mut self, operands: Vec<EscOperand>, operation: Option<Op>) -> Result<(), Error> {
        // Solids whose operand is unchanged are kept (moved, not rebuilt or copied): changing the
        // operation rebuilds nothing. On an error they are put back.
        let mut old: Vec<Option<EscSolid>> = core::mem::take(&mut self.boolean.solids)
            .into_iter()
            .map(Some)
            .collect();
        let mut solids = Vec::with_capacity(operands.len());
        for (i, o) in operands.iter().enumerate() {
            let kept = if self.operands.get(i) == Some(o) {
                old.get_mut(i).and_then(Option::take)
            } else {
                None
            };
            match kept.map_or_else(|| o.to_solid(), Ok) {
                Ok(s) => solids.push(s),
                Err(e) => {
                    // Back where they were: each taken solid is at its own index.
                    for (k, s) in solids.into_iter().enumerate() {
                        if self.operands.get(k) == operands.get(k) {
                            old[k] = Some(s);
                        }
                    }
                    self.boolean.solids = old.into_iter().flatten().collect();
                    return Err(Error::new(format!("operand {}: {e}", i + 1)));
                }
            }
        }
        let expr = match operation {
            None if operands.len() == 1 => Expr::Solid(0),
            Some(op) if operands.len() == 2 => Expr::binary(op, Expr::Solid(0), Expr::Solid(1)),
            _ => return Err("an operation needs two solids, and one solid no operation".into()),
        };
        let boolean = Boolean { solids, expr };
        // A replaced or dropped operand's file name goes with it; a moved one keeps it.
        fn shape(o: Option<&EscOperand>) -> Option<(&Option<String>, &Option<MeshSpec>)> {
            o.map(|o| (&o.example, &o.mesh))
        }
        for (k, name) in self.names.iter_mut().enumerate() {
            if shape(self.operands.get(k)) != shape(operands.get(k)) {
                *name = None;
            }
        }
        self.names.resize(operands.len(), None);
        self.operands = operands;
        self.operation = operation;
        self.boolean = boolean;
        self.changed();
        Ok(())
    }

    /// Operand `slot` (0 for A, 1 for B) becomes a built-in example, keeping its offset.
    ///
    /// # Errors
    ///
    /// An unknown slot.
    pub fn set_example(&mut self, slot: usize, example: Example) -> Result<(), Error> {
        let offset = self.operands.get(slot).map_or([0.0; 3], |o| o.offset);
        self.replace(slot, example.name(), EscOperand::example(example, offset))
    }

    /// Operand `slot` becomes an imported mesh (read by [`bezsolid_core::mesh::read`]), named `name`.
    ///
    /// # Errors
    ///
    /// An unknown slot, or a mesh that cannot bound a solid.
    pub fn set_mesh(&mut self, slot: usize, name: &str, mesh: &Mesh) -> Result<(), Error> {
        let op = EscOperand {
            example: None,
            mesh: Some(MeshSpec {
                positions: mesh.positions.iter().map(|p| p.to_array()).collect(),
                triangles: mesh.triangles.clone(),
            }),
            offset: [0.0; 3],
        };
        self.replace(slot, name, op)?;
        self.fit();
        Ok(())
    }

    /// Operand `slot` becomes `op`, named `name`; a new B comes with a union.
    fn replace(&mut self, slot: usize, name: &str, op: EscOperand) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        match slot {
            _ if slot < operands.len() => operands[slot] = op,
            1 if operands.len() == 1 => operands.push(op),
            _ => return Err(Error::new(format!("no operand {}", slot + 1))),
        }
        let operation = self
            .operation
            .or((operands.len() == 2).then_some(Op::Union));
        let before = self.snapshot();
        self.apply(operands, operation)?;
        self.set_name(slot, name);
        self.record(before);
        Ok(())
    }

    fn set_name(&mut self, slot: usize, name: &str) {
        self.names.resize(self.operands.len(), None);
        if let Some(n) = self.names.get_mut(slot) {
            *n = self.operands[slot].mesh.is_some().then(|| name.into());
        }
    }

    /// Moves operand `slot` to `offset` (from its file position).
    ///
    /// # Errors
    ///
    /// An unknown slot or an offset that is not finite.
    pub fn set_offset(&mut self, slot: usize, offset: [f64; 3]) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        let o = operands
            .get_mut(slot)
            .ok_or_else(|| Error::new(format!("no operand {}", slot + 1)))?;
        o.offset = offset;
        let before = self.snapshot();
        self.apply(operands, self.operation)?;
        self.record(before);
        Ok(())
    }

    /// The operation on A and B, or `None` for solid A alone (a new B is a torus).
    ///
    /// # Errors
    ///
    /// When the new model cannot be built.
    pub fn set_operation(&mut self, operation: Option<Op>) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        match operation {
            None => operands.truncate(1),
            Some(_) if operands.len() == 1 => {
                operands.push(EscOperand::example(Example::Torus, [0.0, 0.0, 0.35]));
            }
            Some(_) => {}
        }
        let before = self.snapshot();
        self.apply(operands, operation)?;
        self.record(before);
        Ok(())
    }

    /// Changes whenever the scene does.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The operation on A and B, or `None` for solid A alone.
    #[must_use]
    pub fn operation(&self) -> Option<Op> {
        self.operation
    }

    /// Operand `slot`: its name (an example's, or the imported file's) and offset.
    #[must_use]
    pub fn operand(&self, slot: usize) -> Option<(String, [f64; 3], bool)> {
        let o = self.operands.get(slot)?;
        let name = match (&o.example, self.names.get(slot)) {
            (Some(example), _) => example.clone(),
            (None, Some(Some(file))) => file.clone(),
            (None, _) => "imported mesh".into(),
        };
        Some((name, o.offset, o.example.is_some()))
    }

    /// The solids and expression.
    #[must_use]
    pub fn boolean(&self) -> &Boolean {
        &self.boolean
    }

    /// Sets what the view shows.
    pub fn set_display(&mut self, display: Display) {
        self.display = display;
    }

    /// The resolution of the result's surface at rest (8 to 160); returns the value taken.
    pub fn set_resolution(&mut self, resolution: usize) -> usize {
        self.resolution = resolution.clamp(8, bezsolid_core::esc::draw::MAX_RESOLUTION);
        self.surface.ask(self.revision, self.resolution);
        self.resolution
    }

    /// The resolution at rest.
    #[must_use]
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// The fine surface wanted: `(revision, resolution)`, once.
    pub fn surface_request(&mut self) -> Option<(u64, usize)> {
        self.surface.take_request()
    }

    /// The fine surface for `revision` at `resolution` as six `f32` per vertex (position, normal),
    /// three vertices per triangle; ignored when the scene has changed since. Returns whether it
    /// was taken.
    pub fn set_surface(&mut self, revision: u64, resolution: usize, data: &[f32]) -> bool {
        if !data.len().is_multiple_of(18) {
            return false;
        }
        self.surface.hand_in(
            revision,
            self.revision,
            resolution,
            float_vertices(data, RESULT_COLOR),
        )
    }

    /// The triangles and resolution of the result's surface drawn now.
    #[must_use]
    pub fn surface_info(&self) -> Option<(usize, usize)> {
        self.surface.info(self.revision)
    }

    /// Frames the scene.
    pub fn fit(&mut self) {
        let (lo, hi) = self.extent_box();
        self.orbit.fit(lo, hi);
    }

    fn extent_box(&self) -> (DVec3, DVec3) {
        self.boolean.scene_bounds()
    }

    /// The viewport's size in CSS pixels.
    pub fn resize(&mut self, width: f64, height: f64) {
        let bounds = self.extent_box();
        self.orbit.resize(width, height, bounds);
    }

    /// The camera and its gestures.
    pub fn orbit(&mut self) -> &mut OrbitView {
        &mut self.orbit
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        self.orbit.camera()
    }

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
        match self.display {
            Display::Result => {
                if let Some(m) = self.surface.drawn() {
                    opaque.extend_from_slice(&m.vertices);
                }
                pn(0, ghost(A_COLOR), &mut translucent);
                pn(1, ghost(B_COLOR), &mut translucent);
            }
            Display::Operands => {
                pn(0, A_COLOR, &mut opaque);
                pn(
                    1,
                    [B_COLOR[0], B_COLOR[1], B_COLOR[2], 0.55],
                    &mut translucent,
                );
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

/// The model file in `text`: JSON, or a share link (a whole URL or its fragment).
///
/// # Errors
///
/// What is wrong with it.
pub fn read_file(text: &str) -> Result<ModelFile, Error> {
    if text.len() > crate::document::MAX_MODEL_BYTES {
        return Err(Error::new(format!(
            "the file is {} bytes; a model file is at most {}",
            text.len(),
            crate::document::MAX_MODEL_BYTES
        )));
    }
    if text.trim_start().starts_with('{') {
        serde_json::from_str(text)
            .map_err(|e| Error::new(format!("not a bezsolid model file: {e}")))
    } else {
        bezsolid_core::link::decode_file(text.trim()).map_err(Error::from)
    }
}

/// The text of a free-form model file: indented, or compact when an operand is a mesh.
#[must_use]
pub fn model_json(file: &ModelFile) -> String {
    let has_mesh = matches!(&file.solid, SolidSpec::Esc { operands, .. }
        if operands.iter().any(|o| o.mesh.is_some()));
    if has_mesh {
        serde_json::to_string(file)
    } else {
        serde_json::to_string_pretty(file)
    }
    .unwrap_or_default()
}

/// Whether `text` (a model file or link) holds a free-form model.
#[must_use]
pub fn is_free_form(text: &str) -> bool {
    read_file(text).is_ok_and(|f| matches!(f.solid, SolidSpec::Esc { .. }))
}

/// The page's free-form work without a page (the worker's jobs, and node).
pub mod headless {
    use super::read_file;
    use crate::error::Error;
    use bezsolid_core::mesh::Format;

    /// The largest resolution of a headless surface or mesh.
    pub const MAX_RESOLUTION: usize = bezsolid_core::esc::draw::MAX_RESOLUTION;

    fn boolean(text: &str, resolution: usize) -> Result<bezsolid_core::esc::Boolean, Error> {
        if !(2..=MAX_RESOLUTION).contains(&resolution) {
            return Err(Error::new(format!(
                "resolution {resolution} is outside 2..={MAX_RESOLUTION}"
            )));
        }
        read_file(text)?.to_boolean().map_err(Error::from)
    }

    /// The result's surface of a free-form model or link, as [`super::surface_floats`].
    ///
    /// # Errors
    ///
    /// What is wrong with the input or the resolution (2 to 160).
    pub fn surface(text: &str, resolution: usize) -> Result<Vec<f32>, Error> {
        Ok(super::surface_floats(
            &boolean(text, resolution)?,
            resolution,
        ))
    }

    /// A mesh file of the result's surface.
    ///
    /// # Errors
    ///
    /// As [`surface`], or an empty result.
    pub fn mesh(text: &str, format: Format, resolution: usize) -> Result<Vec<u8>, Error> {
        mesh_in_steps(text, format, resolution, |_, _| {})
    }

    /// [`mesh`], calling `progress(done, total)` after each layer of the result's samples and at
    /// the end ([`bezsolid_core::esc::Boolean::surface_in_steps`]).
    ///
    /// # Errors
    ///
    /// As [`mesh`].
    pub fn mesh_in_steps(
        text: &str,
        format: Format,
        resolution: usize,
        progress: impl FnMut(usize, usize),
    ) -> Result<Vec<u8>, Error> {
        let mesh = boolean(text, resolution)?.surface_in_steps(resolution, progress);
        if mesh.triangles.is_empty() {
            return Err("the result is empty: there is no surface to export".into());
        }
        Ok(format.write(&mesh))
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
    use bezsolid_core::mesh::Format;
    use glam::DVec2;

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
    fn edits_round_trip_through_the_model_file_and_bad_ones_keep_the_scene() {
        let mut f = FreeForm::new();
        f.set_example(0, Example::Icosphere).unwrap();
        f.set_offset(1, [0.5, 0.0, 0.0]).unwrap();
        f.set_operation(Some(Op::Intersection)).unwrap();
        let file = f.model_file();
        let mut g = FreeForm::new();
        g.open(&file).unwrap();
        assert_eq!(g.model_file(), file);
        assert_eq!(g.operation(), Some(Op::Intersection));
        let before = f.model_file();
        assert!(f.set_example(2, Example::Blob).is_err(), "no third operand");
        assert!(f.set_offset(1, [f64::NAN, 0.0, 0.0]).is_err());
        let open = bezsolid_core::esc::examples::icosphere(1);
        let mut broken = open.clone();
        broken.triangles.pop();
        assert!(f.set_mesh(1, "broken.obj", &broken).is_err());
        assert_eq!(f.model_file(), before);
        assert_eq!(f.boolean().solids.len(), 2, "the solids are kept");
        assert!(f.boolean().solids[0].contains(DVec3::ZERO));
        // A good mesh is taken, named by its file.
        f.set_mesh(1, "ball.obj", &open).unwrap();
        assert_eq!(f.operand(1).map(|o| o.0), Some("ball.obj".into()));
        // One operand alone.
        f.set_operation(None).unwrap();
        assert_eq!(f.boolean().solids.len(), 1);
    }

    #[test]
    fn headless_surfaces_and_meshes_of_files_and_links() {
        let f = FreeForm::new();
        let json = serde_json::to_string(&f.model_file()).unwrap();
        let link = bezsolid_core::link::encode(&f.model_file()).unwrap();
        assert!(is_free_form(&json) && is_free_form(&link));
        assert!(!is_free_form("{}"));
        let a = headless::surface(&json, 16).unwrap();
        assert_eq!(a, headless::surface(&link, 16).unwrap());
        assert!(a.len() > 18 * 100);
        // The export is the closed mesh of the same resolution.
        let stl = headless::mesh(&link, Format::Stl, 16).unwrap();
        let closed = f.boolean().surface(16);
        closed.check_closed_manifold().unwrap();
        assert_eq!(stl.len(), 84 + 50 * closed.triangles.len());
        assert!(headless::mesh(&link, Format::Stl, 1000).is_err());
        assert!(headless::surface(&link, 1000).is_err());
        assert!(headless::surface("#v1.garbage", 16).is_err());
    }

    #[test]
    fn model_files_with_meshes_are_compact_and_read_back() {
        let mut f = FreeForm::new();
        assert!(model_json(&f.model_file()).contains('\n'));
        f.set_mesh(1, "ball.obj", &bezsolid_core::esc::examples::icosphere(2))
            .unwrap();
        let text = model_json(&f.model_file());
        assert!(!text.contains('\n'));
        assert_eq!(read_file(&text).unwrap(), f.model_file());
    }

    #[test]
    fn operand_names_follow_the_operands() {
        let mut f = FreeForm::new();
        f.set_example(1, Example::Icosphere).unwrap();
        f.set_operation(None).unwrap();
        f.set_operation(Some(Op::Union)).unwrap();
        assert_eq!(f.operand(1).map(|o| o.0), Some("torus".into()));
        f.set_mesh(1, "ball.obj", &bezsolid_core::esc::examples::icosphere(1))
            .unwrap();
        assert_eq!(f.operand(1).map(|o| o.0), Some("ball.obj".into()));
        f.set_offset(1, [0.1, 0.0, 0.0]).unwrap();
        assert_eq!(
            f.operand(1).map(|o| o.0),
            Some("ball.obj".into()),
            "a moved mesh keeps its name"
        );
        f.set_example(1, Example::Blob).unwrap();
        assert_eq!(
            f.operand(1).map(|o| (o.0, o.2)),
            Some(("blob".into(), true))
        );
        // Opening a file names its meshes plainly.
        f.set_mesh(0, "ball.obj", &bezsolid_core::esc::examples::icosphere(1))
            .unwrap();
        let file = f.model_file();
        f.open(&file).unwrap();
        assert_eq!(f.operand(0).map(|o| o.0), Some("imported mesh".into()));
    }

    #[test]
    fn every_change_is_one_undo_step_and_redo_gives_it_back() {
        let mut f = FreeForm::new();
        let start = f.model_file();
        assert!(!f.can_undo());
        f.set_operation(Some(Op::Intersection)).unwrap();
        f.set_offset(1, [0.2, 0.0, 0.0]).unwrap();
        f.set_mesh(0, "ball.obj", &bezsolid_core::esc::examples::icosphere(1))
            .unwrap();
        let last = f.model_file();
        // A refused change is no step.
        assert!(f.set_offset(1, [f64::NAN, 0.0, 0.0]).is_err());
        let revision = f.revision();
        assert!(f.undo());
        assert!(f.revision() > revision, "the scene is built again");
        assert_eq!(f.operand(0).map(|o| o.0), Some("blob".into()));
        assert!(f.undo());
        assert_eq!(f.operand(1).map(|o| o.1), Some([0.0, 0.0, 0.35]));
        assert!(f.undo());
        assert_eq!(f.model_file(), start);
        assert!(!f.undo());
        assert!(f.redo() && f.redo() && f.redo());
        assert_eq!(f.model_file(), last);
        assert_eq!(
            f.operand(0).map(|o| o.0),
            Some("ball.obj".into()),
            "the name comes back"
        );
        assert!(!f.redo());
        // Opening a file is a step too; the history can be forgotten.
        f.open(&start).unwrap();
        assert!(f.undo());
        assert_eq!(f.model_file(), last);
        f.forget_history();
        assert!(!f.can_undo() && !f.can_redo());
    }

    #[test]
    fn big_meshes_are_drawn_coarser() {
        assert_eq!(tessellation_level(5120, 4, VIEW_TRIANGLES), 4);
        assert_eq!(tessellation_level(200_000, 4, VIEW_TRIANGLES), 1);
        assert_eq!(tessellation_level(60_000, 4, VIEW_TRIANGLES), 3);
        assert_eq!(tessellation_level(0, 4, VIEW_TRIANGLES), 4);
    }

    #[test]
    fn the_camera_orbits_pans_and_zooms() {
        let mut f = FreeForm::new();
        let start = *f.camera();
        f.orbit().pointer_down(DVec2::new(10.0, 10.0), false);
        assert!(f.orbit().pointer_move(DVec2::new(40.0, 10.0)));
        f.orbit().pointer_up();
        assert_ne!(f.camera().yaw, start.yaw);
        f.orbit().wheel(100.0);
        assert!(f.camera().distance > start.distance);
        f.fit();
        assert_eq!(*f.camera(), start);
    }
}
