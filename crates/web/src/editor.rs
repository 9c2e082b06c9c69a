//! The editor: the model (a patch solid, or a volume solid edited through one slice at a time),
//! the selected control point, the drag mode, the drag under way and the undo history. Every view
//! edits the model through it: the 2D contour view ([`crate::view2d`]), the 3D view
//! ([`crate::view3d`]) and the exports ([`crate::document`]) take an [`Editor`], so the views share
//! one model and one history, and none knows of another.

use std::collections::VecDeque;

use bezsolid_core::model::{ModelSolid, SolidSpec};
use bezsolid_core::piecewise::{Piecewise2, Piecewise3};
use bezsolid_core::{Axis, Patch, Solid2, Solid3, SolidError, Volume};
use glam::{DVec2, DVec3, DVec4};

use crate::error::Error;

/// ξ change per unit of wheel `deltaY` (a notch of 100 is 0.1; wheel up raises the point).
pub const XI_PER_WHEEL: f64 = 0.001;
/// ξ change per arrow-less key press (`PageUp`/`+`); a tenth of it with Shift.
pub const XI_KEY_STEP: f64 = 0.1;
/// The most undo steps kept (a 16×16 net is 6 KB, so this is at most a few MB).
pub const HISTORY_LIMIT: usize = 500;
/// The most control points per side of a patch in the editor (degree 15).
pub const MAX_POINTS_PER_SIDE: usize = 16;

/// How far ξ of a control point may go, in multiples of the longest side of the model's domain
/// ([`Editor::xi_limit`]).
pub const XI_PER_EXTENT: f64 = 100.0;

/// ξ of the point `index` of a new regular net of `degree`: the Bézier coefficients of the dome
/// `ξ(u) = 1/4 − 3/4 · mean over the axes of (2u − 1)²` (exact: a quadratic has coefficients at
/// any degree from 2), which is 1/4 in the middle of the box and −1/2 at its corners, so that a new
/// patch or volume is a solid in the middle of its box (a disc or ball) and every point's ξ
/// matters. An axis of two points cannot bend and is left out; a net of two points along every
/// axis is inside everywhere (ξ = 1/4).
#[must_use]
pub fn dome<const D: usize>(index: [usize; D], degree: [usize; D]) -> f64 {
    let mut sum = 0.0;
    let mut axes = 0;
    for (&i, &n) in index.iter().zip(&degree) {
        if n >= 2 {
            // (2u − 1)² = 4u² − 4u + 1, with u and u² of coefficients i/n and i(i − 1)/(n(n − 1)).
            let (i, n) = (i as f64, n as f64);
            sum += 4.0 * i * (i - 1.0) / (n * (n - 1.0)) - 4.0 * i / n + 1.0;
            axes += 1;
        }
    }
    if axes == 0 {
        return 0.25;
    }
    0.25 - 0.75 * sum / f64::from(axes)
}

/// `plain`, a patch's or a volume's spec, as the piecewise solid of `cells` where there are cells.
#[must_use]
pub fn piecewise_spec(cells: Option<&Cells>, plain: SolidSpec) -> SolidSpec {
    let Some(cells) = cells else { return plain };
    let points = match plain {
        SolidSpec::Patch { points, .. } => points.iter().map(|p| p.to_vec()).collect(),
        SolidSpec::Volume { points, .. } => points.iter().map(|p| p.to_vec()).collect(),
        other => return other,
    };
    SolidSpec::Piecewise {
        cells: cells.count.clone(),
        degree: cells.degree.clone(),
        points,
    }
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

/// A drag of a control point of the patch editor's solid.
#[derive(Clone, Debug)]
struct Drag {
    index: usize,
    mode: Mode,
    /// The point when the drag began.
    start_point: DVec3,
    /// The model before the drag: one undo step when the drag changed it.
    before: Net,
}

/// A model's control net, as the undo history keeps it, with the cells it is cut into when the
/// model is piecewise.
#[derive(Clone, Debug, PartialEq)]
enum Net {
    Patch(Patch<DVec3>, Option<Cells>),
    Volume(Volume<DVec4>, Option<Cells>),
}

/// The cells of a piecewise model ([`bezsolid_core::piecewise`]) whose global net the editor
/// holds as one net (the patch's, or the volume's): every view edits it as one, so a dragged
/// point that cells share moves in each of them. What the editor's solid evaluates to is the
/// piecewise solid's `f` ([`Editor::f`], [`Editor::piecewise2`], [`Editor::piecewise3`]).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Cells {
    /// The cells along each axis (u, v[, w]).
    pub count: Vec<usize>,
    /// Each cell's degree along each axis.
    pub degree: Vec<usize>,
}

impl Cells {
    /// The cells of the plane of two axes (a volume's slice across the third).
    fn plane(&self, a: Axis, b: Axis) -> Option<Self> {
        let pick = |x: &[usize]| Some(vec![*x.get(a.index())?, *x.get(b.index())?]);
        Some(Self {
            count: pick(&self.count)?,
            degree: pick(&self.degree)?,
        })
    }
}

/// The most control points along an axis of a piecewise net the editor holds: its global net is
/// a net of one degree up to [`bezsolid_core::MAX_DEGREE`] (five cubic cells, eight quadratic).
pub const MAX_PIECEWISE_POINTS: usize = bezsolid_core::MAX_DEGREE + 1;

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

/// The model, the selection, the drag mode, the drag under way and the history (see the module
/// documentation).
#[derive(Clone, Debug)]
pub struct Editor {
    /// The patch solid edited: the model, or the volume's selected slice.
    solid: Solid2,
    selected: Option<usize>,
    drag: Option<Drag>,
    mode: Mode,
    /// The volume when the model is one; `solid` is then its selected slice.
    volume: Option<VolumeDoc>,
    /// The cells when the model is piecewise: the patch's or the volume's net is the global one.
    cells: Option<Cells>,
    /// A control point of the volume dragged in 3D, and the model before the drag.
    volume_drag: Option<(usize, Net)>,
    /// Counts changes of the model (for caches of what is drawn from it).
    revision: u64,
    undo: VecDeque<Net>,
    redo: VecDeque<Net>,
    last_step: Option<Step>,
    /// See [`Editor::opened`] and [`Editor::drags`].
    opened: u64,
    drags: u64,
    /// See [`Editor::recorded`].
    recorded: u64,
}

impl Editor {
    /// An editor of `solid`, nothing selected, no history.
    #[must_use]
    pub fn new(solid: Solid2) -> Self {
        Self {
            solid,
            selected: None,
            drag: None,
            mode: Mode::Function,
            volume: None,
            cells: None,
            volume_drag: None,
            revision: 0,
            undo: VecDeque::new(),
            redo: VecDeque::new(),
            last_step: None,
            opened: 0,
            drags: 0,
            recorded: 0,
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
        self.replace(ModelSolid::Patch(solid), None);
    }

    /// Replaces the model by a volume solid: one undo step. The patch editor shows its middle
    /// slice across w.
    pub fn set_volume(&mut self, solid: Solid3) {
        self.replace(ModelSolid::Volume(solid), None);
    }

    /// Replaces the model by a piecewise one: `net` is its global net (a patch's or a volume's)
    /// cut into `cells`; one undo step. A volume's middle slice across w is shown.
    ///
    /// # Errors
    ///
    /// When the net's point counts are not the cells' (`count·degree + 1` along each axis) or
    /// the cells are of another dimension; nothing changes then.
    pub fn set_piecewise(&mut self, net: ModelSolid, cells: Cells) -> Result<(), Error> {
        let dims = match &net {
            ModelSolid::Patch(s) => s.net().dims().to_vec(),
            ModelSolid::Volume(v) => v.net().dims().to_vec(),
        };
        let fits = cells.count.len() == dims.len()
            && cells.degree.len() == dims.len()
            && (0..dims.len()).all(|a| cells.count[a] * cells.degree[a] + 1 == dims[a]);
        if !fits {
            return Err(Error::new(format!(
                "a net of {dims:?} points is not {:?} cells of degree {:?}",
                cells.count, cells.degree
            )));
        }
        self.replace(net, Some(cells));
        Ok(())
    }

    fn replace(&mut self, model: ModelSolid, cells: Option<Cells>) {
        let before = self.net();
        self.drag = None;
        self.volume_drag = None;
        self.opened += 1;
        match model {
            ModelSolid::Patch(solid) => {
                self.solid = solid;
                self.volume = None;
            }
            ModelSolid::Volume(solid) => {
                let index = solid.degree()[2] / 2;
                self.volume = Some(VolumeDoc {
                    solid,
                    axis: Axis::W,
                    index,
                });
                self.refresh_slice();
            }
        }
        self.cells = cells;
        self.changed_from(before, Step::Other);
        self.keep_selection_in_range();
    }

    /// The cells, when the model is piecewise.
    #[must_use]
    pub fn cells(&self) -> Option<&Cells> {
        self.cells.as_ref()
    }

    /// The 2D solid shown (the patch, or the volume's slice) as the piecewise solid it is, when
    /// the model is piecewise (a slice of a piecewise volume is a piecewise patch of the cells of
    /// its plane).
    #[must_use]
    pub fn piecewise2(&self) -> Option<Piecewise2> {
        let cells = match self.slice() {
            Some((axis, _)) => {
                let (a, b) = axis.others();
                self.cells.as_ref()?.plane(a, b)?
            }
            None => self.cells.clone()?,
        };
        Piecewise2::new(
            cells.count.try_into().ok()?,
            cells.degree.try_into().ok()?,
            self.solid.net().points().to_vec(),
        )
        .ok()
    }

    /// The piecewise volume, when the model is one.
    #[must_use]
    pub fn piecewise3(&self) -> Option<Piecewise3> {
        let cells = self.cells.clone()?;
        Piecewise3::new(
            cells.count.try_into().ok()?,
            cells.degree.try_into().ok()?,
            self.volume()?.net().points().to_vec(),
        )
        .ok()
    }

    /// `f` of the 2D solid shown at `p`: the patch's or the slice's, piecewise where the model is.
    #[must_use]
    pub fn f(&self, p: DVec2) -> f64 {
        match self.piecewise2() {
            Some(solid) => solid.f(p),
            None => self.solid.f(p),
        }
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
    pub fn set_slice(&mut self, axis: Axis, index: usize) -> Result<(), Error> {
        let doc = self
            .volume
            .as_mut()
            .ok_or("the model is a patch; it has no slices")?;
        let d = doc.solid.degree();
        let len = d[axis.index()] + 1;
        if index >= len {
            return Err(Error::new(format!(
                "the net has {len} slices across that axis"
            )));
        }
        if self.drag.is_some() || self.volume_drag.is_some() {
            return Err("finish the drag first".into());
        }
        (doc.axis, doc.index) = (axis, index);
        self.opened += 1;
        self.refresh_slice();
        self.keep_selection_in_range();
        Ok(())
    }

    /// A number that changes whenever the model does.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Marks the model changed from outside (a model of many solids changed around the part the
    /// editor holds): what is drawn of it is made again.
    pub fn touch(&mut self) {
        self.revision += 1;
    }

    /// The model's net, as the history keeps it.
    fn net(&self) -> Net {
        let cells = self.cells.clone();
        match &self.volume {
            Some(doc) => Net::Volume(doc.solid.net().clone(), cells),
            None => Net::Patch(self.solid.net().clone(), cells),
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
    fn write_back(&mut self) -> Result<(), Error> {
        let Some(doc) = &mut self.volume else {
            return Ok(());
        };
        doc.solid
            .set_slice(doc.axis, doc.index, &self.solid)
            .map_err(Error::from)
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
    ) -> Result<(), Error> {
        let before = self.net();
        let old = self.solid.clone();
        edit(&mut self.solid).map_err(Error::from)?;
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
            self.recorded += 1;
            self.undo.push_back(before);
            if self.undo.len() > HISTORY_LIMIT {
                self.undo.pop_front();
            }
        }
        self.redo.clear();
        self.last_step = Some(step);
    }

    /// How many undo steps have been recorded (an edit merged into the last step, a wheel turn or
    /// a typed number on the same point, adds none): a model of many solids takes its own steps
    /// from the editor's part by it.
    #[must_use]
    pub fn recorded(&self) -> u64 {
        self.recorded
    }

    /// The models of the undo steps, oldest first, as the model file spells a solid (what a model
    /// of many solids made from this one keeps as its history).
    #[must_use]
    pub fn undo_specs(&self) -> Vec<SolidSpec> {
        self.undo
            .iter()
            .map(|net| match net {
                Net::Patch(p, cells) => piecewise_spec(
                    cells.as_ref(),
                    SolidSpec::Patch {
                        degree: p.degree(),
                        points: p.points().iter().map(|q| q.to_array()).collect(),
                    },
                ),
                Net::Volume(v, cells) => piecewise_spec(
                    cells.as_ref(),
                    SolidSpec::Volume {
                        degree: v.degree(),
                        points: v.points().iter().map(|q| q.to_array()).collect(),
                    },
                ),
            })
            .collect()
    }

    /// Forgets every undo and redo step (after restoring an autosaved model at start-up).
    pub fn forget_history(&mut self) {
        self.undo.clear();
        self.redo.clear();
        self.last_step = None;
    }

    /// Whether a drag of a control point is under way (in either view).
    #[must_use]
    pub fn busy(&self) -> bool {
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
            self.undo.pop_back()
        } else {
            self.redo.pop_back()
        };
        let Some(net) = popped else {
            return false;
        };
        let current = self.net();
        if self.restore(net) {
            if undo {
                self.redo.push_back(current);
            } else {
                self.undo.push_back(current);
            }
        }
        true
    }

    /// Puts back a net from the history (each was a valid solid when it was recorded). A volume
    /// keeps the slice shown where the net still has it.
    fn restore(&mut self, net: Net) -> bool {
        match net {
            Net::Patch(patch, cells) => match Solid2::try_from_net(patch) {
                Ok(solid) => {
                    self.solid = solid;
                    self.volume = None;
                    self.cells = cells;
                }
                Err(_) => return false,
            },
            Net::Volume(volume, cells) => match Solid3::try_from_net(volume) {
                Ok(solid) => {
                    let (axis, index) = self.slice().unwrap_or((Axis::W, 0));
                    let d = solid.degree();
                    let top = d[axis.index()];
                    self.volume = Some(VolumeDoc {
                        solid,
                        axis,
                        index: index.min(top),
                    });
                    self.cells = cells;
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
    /// it there. The drag ends with [`Self::end_drag`] as one undo step.
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
    pub fn elevate(&mut self, axis: Axis) -> Result<(), Error> {
        if self.cells.is_some() {
            return Err(
                "a piecewise net's cells keep their degree: add cells along an axis instead".into(),
            );
        }
        if let Some(doc) = &self.volume {
            let d = doc.solid.degree();
            let side = d[axis.index()];
            if side + 1 >= MAX_POINTS_PER_SIDE {
                return Err(Error::new(format!(
                    "the net has {} points along that axis already; the editor takes at most {MAX_POINTS_PER_SIDE}",
                    side + 1
                )));
            }
            let net = doc.solid.net().elevate(axis).map_err(Error::from)?;
            let solid = Solid3::try_from_net(net).map_err(Error::from)?;
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
            return Err(Error::new(format!(
                "the grid has {} points on that side already; the editor takes at most {MAX_POINTS_PER_SIDE}",
                side + 1
            )));
        }
        self.apply(Step::Other, |s| {
            *s = Solid2::try_from_net(s.net().elevate(axis)?)?;
            Ok(())
        })
    }

    /// A new patch of `nu × nv` points (2 to [`MAX_POINTS_PER_SIDE`]) on a regular grid over the
    /// current domain (a volume's box in x and y), its ξ a [`dome`]: a solid in the middle of the
    /// domain, so that moving any point shows at once.
    ///
    /// # Errors
    ///
    /// For a size out of range.
    pub fn reset_grid(&mut self, nu: usize, nv: usize) -> Result<(), Error> {
        for k in [nu, nv] {
            if !(2..=MAX_POINTS_PER_SIDE).contains(&k) {
                return Err(Error::new(format!(
                    "a grid has 2 to {MAX_POINTS_PER_SIDE} points per side, not {k}"
                )));
            }
        }
        if let Some(v) = self.volume() {
            // From a volume: a new patch over its box's x, y extent.
            let (min, max) = v.domain();
            let patch = Solid2::regular([nu - 1, nv - 1], min.truncate(), max.truncate(), |ij| {
                dome(ij, [nu - 1, nv - 1])
            })
            .map_err(Error::from)?;
            self.set_solid(patch);
            return Ok(());
        }
        let (min, max) = self.solid.domain();
        if self.cells.is_some() {
            // From a piecewise patch: a single patch over its domain.
            let patch =
                Solid2::regular([nu - 1, nv - 1], min, max, |ij| dome(ij, [nu - 1, nv - 1]))
                    .map_err(Error::from)?;
            self.set_solid(patch);
            return Ok(());
        }
        self.apply(Step::Other, |s| {
            *s = Solid2::regular([nu - 1, nv - 1], min, max, |ij| dome(ij, [nu - 1, nv - 1]))?;
            Ok(())
        })?;
        self.opened += 1;
        self.keep_selection_in_range();
        Ok(())
    }

    /// A new volume: a regular net of `nu × nv × nw` points (2 to [`MAX_POINTS_PER_SIDE`] each)
    /// whose ξ is a [`dome`] (a solid ball in the middle of the box) over the current volume's box,
    /// or over the patch's domain times `[0, 1]`: one undo step.
    ///
    /// # Errors
    ///
    /// For a size out of range.
    pub fn new_volume(&mut self, nu: usize, nv: usize, nw: usize) -> Result<(), Error> {
        for k in [nu, nv, nw] {
            if !(2..=MAX_POINTS_PER_SIDE).contains(&k) {
                return Err(Error::new(format!(
                    "a net has 2 to {MAX_POINTS_PER_SIDE} points along each axis, not {k}"
                )));
            }
        }
        let (min, max) = match self.volume() {
            Some(v) => v.domain(),
            None => {
                let (a, b) = self.solid.domain();
                (a.extend(0.0), b.extend(1.0))
            }
        };
        let degree = [nu - 1, nv - 1, nw - 1];
        let solid =
            Solid3::regular(degree, min, max, |ijk| dome(ijk, degree)).map_err(Error::from)?;
        self.set_volume(solid);
        Ok(())
    }

    /// The solid shown.
    #[must_use]
    pub fn solid(&self) -> &Solid2 {
        &self.solid
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
    pub fn set_selected_xi(&mut self, xi: f64) -> Result<(), Error> {
        let k = self.selected.ok_or("no control point is selected")?;
        let (i, j) = self.ij(k);
        self.check_xi(xi)?;
        self.apply(Step::Input(k), |s| s.set_xi([i, j], xi))
    }

    /// The largest |ξ| a control point takes: [`XI_PER_EXTENT`] times the model's extent (its
    /// domain's longest side). ξ far past the domain's size is a slip of the keyboard (1e9 for
    /// 1e-9), and would squash every other value to nothing in the views' colours.
    #[must_use]
    pub fn xi_limit(&self) -> f64 {
        let extent = match self.volume() {
            Some(v) => {
                let (min, max) = v.domain();
                (max - min).max_element()
            }
            None => {
                let (min, max) = self.solid.domain();
                (max - min).max_element()
            }
        };
        XI_PER_EXTENT * extent.max(0.01)
    }

    /// Refuses `xi` for the selected point when it is past [`Self::xi_limit`] and further out than
    /// the point's ξ now: a value past the bound (from a file, a link, a drag in 3D) can always be
    /// brought back.
    fn check_xi(&self, xi: f64) -> Result<(), Error> {
        let limit = self.xi_limit();
        let now = self.selected_xi().map_or(0.0, f64::abs);
        if xi.abs() > limit && xi.abs() > now {
            return Err(Error::new(format!(
                "ξ = {xi} is too far from the model: ξ stays within ±{limit} ({XI_PER_EXTENT} times the longest side of its domain)"
            )));
        }
        Ok(())
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
    pub fn set_selected_xy(&mut self, x: f64, y: f64) -> Result<(), Error> {
        let k = self.selected.ok_or("no control point is selected")?;
        let (i, j) = self.ij(k);
        self.apply(Step::Input(k), |s| s.set_point([i, j], DVec2::new(x, y)))
    }

    /// Starts dragging control point `index` of the patch editor's solid (flat, as in
    /// [`bezsolid_core::Tensor::points`]) in `mode`: it is selected, the views hold still from now
    /// on ([`Self::drags`]), the point moves with [`Self::drag_to`], and the drag ends with
    /// [`Self::end_drag`] as one undo step.
    pub fn begin_drag(&mut self, index: usize, mode: Mode) {
        if index >= self.count() {
            return;
        }
        self.selected = Some(index);
        self.drags += 1;
        self.drag = Some(Drag {
            index,
            mode,
            start_point: self.solid.net().points()[index],
            before: self.net(),
        });
    }

    /// The point being dragged as it was when the drag began `(x, y, ξ)`, and the drag's mode.
    #[must_use]
    pub fn drag_start(&self) -> Option<(DVec3, Mode)> {
        self.drag.as_ref().map(|d| (d.start_point, d.mode))
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

    /// Ends the drag (the pointer was released or cancelled): one undo step if it changed the net.
    pub fn end_drag(&mut self) {
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

    /// Whether a drag is under way.
    #[must_use]
    pub fn dragging(&self) -> bool {
        self.drag.is_some()
    }

    /// The wheel: changes ξ of the selected point (`deltaY < 0`, wheel up, raises it); turns on
    /// one point are one undo step. Returns whether the solid changed.
    pub fn wheel(&mut self, delta_y: f64) -> bool {
        match (self.selected, self.selected_xi()) {
            (Some(k), Some(xi)) if delta_y.is_finite() && delta_y != 0.0 && self.drag.is_none() => {
                let (i, j) = self.ij(k);
                let xi = xi - delta_y * XI_PER_WHEEL;
                self.check_xi(xi).is_ok()
                    && self.apply(Step::Wheel(k), |s| s.set_xi([i, j], xi)).is_ok()
            }
            _ => false,
        }
    }

    /// Raises ξ of the selected point by `delta` (a key press): one undo step. Returns whether the
    /// solid changed.
    pub fn nudge(&mut self, delta: f64) -> bool {
        match (self.selected, self.selected_xi()) {
            (Some(k), Some(xi)) if self.drag.is_none() && self.check_xi(xi + delta).is_ok() => {
                let (i, j) = self.ij(k);
                self.apply(Step::Other, |s| s.set_xi([i, j], xi + delta))
                    .is_ok()
            }
            _ => false,
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

    /// Counts the times the model was replaced (opened, a new grid, another slice): a 2D view fits
    /// the domain again when it changes.
    #[must_use]
    pub fn opened(&self) -> u64 {
        self.opened
    }

    /// Counts the drags begun: a 2D view holds still from the first drag after it was fitted, so
    /// that the point stays under the pointer even as the domain grows or shrinks, and undo and
    /// redo give back exactly the pictures they were.
    #[must_use]
    pub fn drags(&self) -> u64 {
        self.drags
    }

    /// Selects the next control point (the previous with `back`), or none past the last (first):
    /// Tab and Shift+Tab. Returns whether a point is selected.
    pub fn select_next(&mut self, back: bool) -> bool {
        let count = self.count();
        let next = match (self.selected, back) {
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

    /// Esc: a drag under way is undone (the point goes back); otherwise the selection is cleared.
    pub fn cancel(&mut self) {
        if let Some(drag) = self.drag.take() {
            self.restore(drag.before);
        } else if let Some((_, before)) = self.volume_drag.take() {
            self.restore(before);
        } else {
            self.selected = None;
        }
    }
}
