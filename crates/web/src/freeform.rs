//! The Free-form mode as plain Rust: solids bounded by PN triangles over triangle meshes
//! (built-in examples or imported files), each placed by an offset, a rotation and a scale, a
//! Boolean expression over them (`(A | B) - !C`, [`Expr`]), and what the 3D view shows of them: the result's surface, the paper's point mesh with the points the last term of the
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
use bezsolid_core::model::{EscOperand, MAX_OPERANDS, MeshSpec, ModelFile, SolidSpec};
use glam::DVec3;

use crate::camera::{Camera, OrbitView};
use crate::error::Error;
use crate::history::{History, Weighed};
use crate::scene::{Refined, float_vertices};

mod drag;
mod draw;
mod file;
pub mod headless;

use drag::Moving;
pub(crate) use draw::octahedron;
use draw::{Geometry, RESULT_COLOR};
pub use draw::{mesh_vertices, surface_floats, tessellation_level};
pub use file::{is_free_form, model_json, read_file};

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

/// The most bytes the Free-form mode's undo and redo steps keep (each holds the operands, an
/// imported mesh whole): past it the oldest steps go, the newest always stays.
pub const HISTORY_BYTES: usize = 64 << 20;

/// How the operands combine, as the panel's operation menu says it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combine {
    /// Solid A alone.
    Alone,
    /// The operation over every operand, left to right (`A | B | C`).
    Binary(Op),
    /// A's complement, `!A`.
    Complement,
}

/// The scene as an undo step keeps it: the operands, their file names and the expression.
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    operands: Vec<EscOperand>,
    names: Vec<Option<String>>,
    expr: Expr,
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
    /// The steps to undo and redo: every change of an operand, its place or the expression.
    history: History<Snapshot>,
    /// A drag that moves an operand: the operand, where it was, the plane it moves in (a point
    /// and the view's direction) and the point of the plane first under the pointer.
    moving: Option<Moving>,
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
            moving: None,
        };
        f.open(&file)
            .unwrap_or_else(|_| unreachable!("the default scene is valid"));
        f.history.clear();
        f
    }

    /// The model file of the scene.
    #[must_use]
    pub fn model_file(&self) -> ModelFile {
        ModelFile::from_esc_expr(&self.boolean.expr, self.operands.clone())
    }

    /// Opens a free-form model file.
    ///
    /// # Errors
    ///
    /// What is wrong with it (the scene is kept).
    pub fn open(&mut self, file: &ModelFile) -> Result<(), Error> {
        let boolean = file.to_boolean().map_err(Error::from)?;
        let SolidSpec::Esc { operands, .. } = &file.solid else {
            return Err("not a free-form model".into());
        };
        let before = self.snapshot();
        self.moving = None;
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
            expr: self.boolean.expr.clone(),
        }
    }

    /// Keeps `before` as an undo step if the scene is no longer that.
    fn record(&mut self, before: Snapshot) {
        if before.operands != self.operands
            || before.expr != self.boolean.expr
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
        self.moving = None;
        // A step was a scene that was built: it builds again.
        if self.apply(to.operands, to.expr).is_ok() {
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
    fn apply(&mut self, operands: Vec<EscOperand>, expr: Expr) -> Result<(), Error> {
        if operands.is_empty() || operands.len() > MAX_OPERANDS {
            return Err(Error::new(format!(
                "a free-form model has 1 to {MAX_OPERANDS} solids"
            )));
        }
        if expr.arity() > operands.len() {
            return Err("the expression names a solid that is not there".into());
        }
        bezsolid_core::model::operand_names(&operands).map_err(Error::from)?;
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
            crease: Some(bezsolid_core::esc::DEFAULT_CREASE_ANGLE),
            mesh: Some(MeshSpec {
                positions: mesh.positions.iter().map(|p| p.to_array()).collect(),
                triangles: mesh.triangles.clone(),
            }),
            offset: [0.0; 3],
            ..EscOperand::default()
        };
        self.replace(slot, name, op)?;
        self.fit();
        Ok(())
    }

    /// Operand `slot` becomes `op` (keeping its name in the expression and its placement), named
    /// `name`; a new operand just past the last joins the result's union.
    fn replace(&mut self, slot: usize, name: &str, op: EscOperand) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        let mut expr = self.boolean.expr.clone();
        let count = operands.len();
        match operands.get_mut(slot) {
            Some(old) => {
                *old = EscOperand {
                    name: old.name.take(),
                    rotate: old.rotate,
                    scale: old.scale,
                    crease: old.crease.or(op.crease),
                    ..op
                };
            }
            None if slot == count => {
                operands.push(op);
                expr = Expr::binary(Op::Union, expr, Expr::Solid(slot));
            }
            None => return Err(Error::new(format!("no operand {}", slot + 1))),
        }
        let before = self.snapshot();
        self.apply(operands, expr)?;
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
        let (_, rotate, scale) = self.placement(slot).ok_or_else(|| no_operand(slot))?;
        self.set_placement(slot, offset, rotate, scale)
    }

    /// Places operand `slot`: each point `p` of its mesh goes to `offset + Rz·Ry·Rx·S·p`, with
    /// `rotate` in degrees about x, y, z and `scale` per axis (non-zero; negative mirrors).
    ///
    /// # Errors
    ///
    /// An unknown slot, or numbers the model file refuses (the scene is kept).
    pub fn set_placement(
        &mut self,
        slot: usize,
        offset: [f64; 3],
        rotate: [f64; 3],
        scale: [f64; 3],
    ) -> Result<(), Error> {
        let before = self.snapshot();
        self.place(slot, offset, rotate, scale)?;
        self.record(before);
        Ok(())
    }

    fn place(
        &mut self,
        slot: usize,
        offset: [f64; 3],
        rotate: [f64; 3],
        scale: [f64; 3],
    ) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        let o = operands.get_mut(slot).ok_or_else(|| no_operand(slot))?;
        o.offset = offset;
        o.rotate = (rotate != [0.0; 3]).then_some(rotate);
        o.scale = (scale != [1.0; 3]).then_some(scale);
        if operands == self.operands {
            return Ok(());
        }
        self.apply(operands, self.boolean.expr.clone())
    }

    /// Operand `slot`'s crease angle: an edge whose faces' normals differ by more than `degrees`
    /// stays sharp (0 to 180; 180 rounds every edge).
    ///
    /// # Errors
    ///
    /// An unknown slot or an angle outside 0 to 180 (the scene is kept).
    pub fn set_crease(&mut self, slot: usize, degrees: f64) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        let o = operands.get_mut(slot).ok_or_else(|| no_operand(slot))?;
        o.crease = Some(degrees);
        if operands == self.operands {
            return Ok(());
        }
        let before = self.snapshot();
        self.apply(operands, self.boolean.expr.clone())?;
        self.record(before);
        Ok(())
    }

    /// Operand `slot`'s crease angle in degrees.
    #[must_use]
    pub fn crease(&self, slot: usize) -> Option<f64> {
        let o = self.operands.get(slot)?;
        Some(o.crease.unwrap_or(bezsolid_core::model::FILE_CREASE_ANGLE))
    }

    /// Operand `slot`'s placement: offset, rotation (degrees) and scale.
    #[must_use]
    pub fn placement(&self, slot: usize) -> Option<([f64; 3], [f64; 3], [f64; 3])> {
        let o = self.operands.get(slot)?;
        Some((
            o.offset,
            o.rotate.unwrap_or([0.0; 3]),
            o.scale.unwrap_or([1.0; 3]),
        ))
    }

    /// How the operands combine: A alone (the others go), an operation over all of them left to
    /// right (with A alone, a torus B comes), or A's complement (the others go).
    ///
    /// # Errors
    ///
    /// When the new model cannot be built.
    pub fn set_combine(&mut self, combine: Combine) -> Result<(), Error> {
        let mut operands = self.operands.clone();
        let expr = match combine {
            Combine::Alone | Combine::Complement => {
                operands.truncate(1);
                if combine == Combine::Alone {
                    Expr::Solid(0)
                } else {
                    Expr::complement(Expr::Solid(0))
                }
            }
            Combine::Binary(op) => {
                if operands.len() == 1 {
                    operands.push(EscOperand::example(Example::Torus, [0.0, 0.0, 0.35]));
                }
                (1..operands.len()).fold(Expr::Solid(0), |e, i| Expr::binary(op, e, Expr::Solid(i)))
            }
        };
        let before = self.snapshot();
        self.apply(operands, expr)?;
        self.record(before);
        Ok(())
    }

    /// [`FreeForm::set_combine`] of an operation on A and B, or `None` for A alone.
    ///
    /// # Errors
    ///
    /// When the new model cannot be built.
    pub fn set_operation(&mut self, operation: Option<Op>) -> Result<(), Error> {
        self.set_combine(operation.map_or(Combine::Alone, Combine::Binary))
    }

    /// How the operands combine, when the menu can say it (`None`: another expression).
    #[must_use]
    pub fn combine(&self) -> Option<Combine> {
        let n = self.operands.len();
        match &self.boolean.expr {
            Expr::Solid(0) if n == 1 => Some(Combine::Alone),
            Expr::Complement(a) if n == 1 && **a == Expr::Solid(0) => Some(Combine::Complement),
            e @ Expr::Binary(op, ..) if n >= 2 => {
                let fold = (1..n).fold(Expr::Solid(0), |e, i| Expr::binary(*op, e, Expr::Solid(i)));
                (*e == fold).then_some(Combine::Binary(*op))
            }
            _ => None,
        }
    }

    /// The expression over the operands' names (`A`, `B`, … unless a file named them).
    #[must_use]
    pub fn expression(&self) -> String {
        self.boolean.expr.text(&self.letters())
    }

    /// The operands' names in the expression.
    #[must_use]
    pub fn letters(&self) -> Vec<String> {
        bezsolid_core::model::operand_names(&self.operands).unwrap_or_default()
    }

    /// Combines the operands by the expression `text` (`|` union, `&` intersection, `-`
    /// difference, `!` complement, brackets, over the operands' names).
    ///
    /// # Errors
    ///
    /// What is wrong with the text, with its place (the scene is kept).
    pub fn set_expression(&mut self, text: &str) -> Result<(), Error> {
        let expr = Expr::parse(text, &self.letters()).map_err(|e| Error::new(e.to_string()))?;
        if expr == self.boolean.expr {
            return Ok(());
        }
        let before = self.snapshot();
        self.apply(self.operands.clone(), expr)?;
        self.record(before);
        Ok(())
    }

    /// Adds a built-in example as a new operand beside the scene, joining the result's union;
    /// returns its slot.
    ///
    /// # Errors
    ///
    /// Past [`MAX_OPERANDS`] operands.
    pub fn add_operand(&mut self, example: Example) -> Result<usize, Error> {
        if self.operands.len() >= MAX_OPERANDS {
            return Err(Error::new(format!(
                "a free-form model has at most {MAX_OPERANDS} solids"
            )));
        }
        let (lo, hi) = self.extent_box();
        let at = if lo.is_finite() && hi.is_finite() {
            DVec3::new(hi.x + 0.5, (lo.y + hi.y) / 2.0, (lo.z + hi.z) / 2.0)
        } else {
            DVec3::ZERO
        };
        let slot = self.operands.len();
        self.replace(
            slot,
            example.name(),
            EscOperand::example(example, at.to_array()),
        )?;
        // Beside the scene may be outside the view: the view takes in the new scene.
        self.fit();
        Ok(slot)
    }

    /// Removes operand `slot`: the expression loses it (an operation with it becomes its other
    /// operand, a complement of it goes too) and names the later operands anew.
    ///
    /// # Errors
    ///
    /// An unknown slot, or the last operand.
    pub fn remove_operand(&mut self, slot: usize) -> Result<(), Error> {
        if slot >= self.operands.len() {
            return Err(no_operand(slot));
        }
        if self.operands.len() == 1 {
            return Err("the model needs a solid: this is the last one".into());
        }
        let expr = without(&self.boolean.expr, slot).unwrap_or(Expr::Solid(0));
        let mut operands = self.operands.clone();
        operands.remove(slot);
        let before = self.snapshot();
        self.names.remove(slot);
        if let Err(e) = self.apply(operands, expr) {
            self.names.insert(slot, None);
            return Err(e);
        }
        self.record(before);
        Ok(())
    }

    /// The number of operands.
    #[must_use]
    pub fn operand_count(&self) -> usize {
        self.operands.len()
    }

    /// Changes whenever the scene does.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
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
}

fn no_operand(slot: usize) -> Error {
    Error::new(format!("no operand {}", slot + 1))
}

/// `expr` without solid `slot`, the later solids numbered one lower: an operation with it becomes
/// its other operand, a complement of it goes too; `None` when nothing is left.
fn without(expr: &Expr, slot: usize) -> Option<Expr> {
    match expr {
        Expr::Solid(i) if *i == slot => None,
        Expr::Solid(i) => Some(Expr::Solid(if *i > slot { i - 1 } else { *i })),
        Expr::Complement(a) => without(a, slot).map(Expr::complement),
        Expr::Binary(op, a, b) => match (without(a, slot), without(b, slot)) {
            (Some(a), Some(b)) => Some(Expr::binary(*op, a, b)),
            (a, b) => a.or(b),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

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
        assert_eq!(g.combine(), Some(Combine::Binary(Op::Intersection)));
        let before = f.model_file();
        assert!(
            f.set_example(3, Example::Blob).is_err(),
            "no fourth operand"
        );
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

    #[test]
    fn expressions_of_many_solids_are_edited_saved_and_undone() {
        let mut f = FreeForm::new();
        assert_eq!(f.expression(), "A - B");
        assert_eq!(f.combine(), Some(Combine::Binary(Op::Difference)));
        let c = f.add_operand(Example::Icosphere).unwrap();
        assert_eq!((c, f.operand_count()), (2, 3));
        assert_eq!(f.expression(), "A - B | C", "a new solid joins the union");
        assert_eq!(f.combine(), None);
        f.set_expression("!(A | C) & B").unwrap();
        assert_eq!(f.expression(), "!(A | C) & B");
        // A bad text says where, and keeps the scene.
        let e = f.set_expression("A | D").unwrap_err().to_string();
        assert!(e.contains("\"D\"") && e.contains("character 5"), "{e}");
        assert!(f.set_expression("(A").is_err());
        assert_eq!(f.expression(), "!(A | C) & B");
        // The file says the expression; it opens to the same scene.
        let file = f.model_file();
        assert!(
            matches!(&file.solid, SolidSpec::Esc { expression: Some(t), .. } if t == "!(A | C) & B")
        );
        let mut g = FreeForm::new();
        g.open(&file).unwrap();
        assert_eq!(g.expression(), f.expression());
        let link = bezsolid_core::link::encode(&file).unwrap();
        g.open(&read_file(&link).unwrap()).unwrap();
        assert_eq!(g.model_file(), file);
        // The result is the expression's, at points.
        let mut stats = bezsolid_core::esc::Stats::default();
        let q = DVec3::new(0.0, 0.0, 0.35);
        let v = |i: usize, stats: &mut bezsolid_core::esc::Stats| {
            i32::from(f.boolean().solids[i].value(q, stats) == 1)
        };
        let (a, b, c) = (v(0, &mut stats), v(1, &mut stats), v(2, &mut stats));
        let want = (1 - (a + c - a * c)) * b;
        assert_eq!(f.boolean().value(q, &mut stats), want);
        // Removing B: the intersection with it becomes its other side.
        f.remove_operand(1).unwrap();
        assert_eq!(f.expression(), "!(A | B)");
        assert_eq!(f.operand_count(), 2);
        assert!(f.undo());
        assert_eq!(f.expression(), "!(A | C) & B");
        assert!(f.undo() && f.undo());
        assert_eq!(f.expression(), "A - B");
        // The menu's operations go over every solid; complement takes A alone.
        f.add_operand(Example::Blob).unwrap();
        f.set_combine(Combine::Binary(Op::Intersection)).unwrap();
        assert_eq!(f.expression(), "A & B & C");
        f.set_combine(Combine::Complement).unwrap();
        assert_eq!((f.expression(), f.operand_count()), ("!A".into(), 1));
        assert!(f.boolean().value(DVec3::splat(9.0), &mut stats) == 1);
        assert!(f.remove_operand(0).is_err(), "the last solid stays");
    }

    #[test]
    fn an_imported_cube_keeps_its_edges_unless_its_crease_angle_rounds_them() {
        let cube = bezsolid_core::mesh::read(
            b"v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
              f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\n\
              f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n",
        )
        .unwrap();
        let mut f = FreeForm::new();
        f.set_mesh(0, "cube.obj", &cube).unwrap();
        f.set_combine(Combine::Alone).unwrap();
        let mut stats = bezsolid_core::esc::Stats::default();
        let q = DVec3::new(1.2, 0.0, 0.0);
        assert_eq!(f.boolean().value(q, &mut stats), 0);
        assert_eq!(f.crease(0), Some(bezsolid_core::esc::DEFAULT_CREASE_ANGLE));
        f.set_crease(0, 180.0).unwrap();
        assert_eq!(
            f.boolean().value(q, &mut stats),
            1,
            "rounded, the faces bulge"
        );
        assert!(f.set_crease(0, 181.0).is_err());
        assert_eq!(f.crease(0), Some(180.0));
        assert!(f.undo());
        assert_eq!(f.boolean().value(q, &mut stats), 0);
    }
}
