//! A model of many solids in the page: the [`Outline`] of its tree, the one undo history of every
//! change to it, and the Bézier part whose control points the 2D and 3D editors edit.
//!
//! The [`Editor`] holds the open Bézier part (the selected node, when it is a patch or a volume)
//! as it holds a model of one solid, so its views and drags work unchanged; [`Parts::sync`] writes
//! what the editor changed back into the tree as one undo step when a drag or an entry ends, and
//! [`Parts::file`] gives the whole tree with the part as the editor has it now (during a drag too,
//! for the live surface). Undo and redo step through the tree's history, edits of a part included:
//! the editor's own history is not used while a tree is open.

use bezsolid_core::model::{ModelFile, Rotation, SolidSpec};
use bezsolid_core::piecewise::{Piecewise, PiecewiseError};
use bezsolid_core::tree::ModelTree;
use glam::{DAffine2, DAffine3, DMat3, DVec3};

use crate::document;
use crate::editor::{Editor, MAX_PIECEWISE_POINTS};
use crate::history::{History, Weighed};

use crate::error::Error;
use crate::outline::{NewNode, NodePath, Outline, Wrap};
use crate::view3d::Handle;

mod handles;
mod history;
mod placement;

pub use history::HISTORY_BYTES;
use placement::{linear, transform_numbers};

/// The tree and its selection, as the history keeps them.
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    root: SolidSpec,
    selected: NodePath,
}

/// A model of many solids, its history and the part open in the editor (see the module
/// documentation).
#[derive(Clone, Debug)]
pub struct Parts {
    outline: Outline,
    /// The steps to undo and redo (within [`HISTORY_BYTES`]).
    history: History<Snapshot>,
    /// The editor's [`Editor::recorded`] when the part's last edit was written back as a step:
    /// an edit the editor merged into that step (another wheel notch on the same point) is
    /// written back into it too.
    sync_recorded: Option<u64>,
    /// The field last set, on which node: consecutive settings of it (a slider's moves) are one
    /// undo step.
    last_set: Option<(NodePath, String)>,
    /// The Bézier part in the editor: its path.
    open: Option<NodePath>,
    /// The editor's revision last written back (or loaded).
    synced: u64,
    /// A drag of the selection's handle under way.
    gesture: Option<HandleGesture>,
}

/// A drag of a handle: the model before it (one undo step for the whole drag), and the
/// transform's numbers and its parent's map to space when it began.
#[derive(Clone, Debug)]
struct HandleGesture {
    before: Snapshot,
    translate: DVec3,
    rotate: [f64; 3],
    scale: DVec3,
    parent: DAffine3,
    /// The point a turn or a scale keeps still: the centre of the transform's solid, in its
    /// coordinates.
    pivot: DVec3,
}

/// The node's spec of the editor's model.
fn editor_spec(editor: &Editor) -> SolidSpec {
    document::model_file(editor).solid
}

fn is_bezier(spec: &SolidSpec) -> bool {
    document::editable(spec)
}

/// The names of the parameter axes.
const AXES: [&str; 3] = ["u", "v", "w"];

/// `spec` (a patch, a volume or a piecewise one of `D` axes) with a cell more or less along
/// `axis`; one cell along every axis is written as the single patch or volume it is.
fn cells_changed<const D: usize>(
    spec: &SolidSpec,
    axis: usize,
    add: bool,
) -> Result<SolidSpec, Error>
where
    bezsolid_core::Dim<D>: bezsolid_core::Dimension<D>,
    Piecewise<D>: Cellular,
{
    let bad = |e: PiecewiseError| Error::new(e.to_string());
    let solid = spec
        .to_piecewise::<D>()
        .ok_or_else(|| Error::new("the part is not a Bézier patch or volume"))?
        .map_err(bad)?;
    if axis >= D {
        return Err(Error::new(format!(
            "the part has no axis {}",
            AXES.get(axis).unwrap_or(&"?")
        )));
    }
    if !add && solid.cells()[axis] == 1 {
        return Err(Error::new(format!(
            "the part has one cell along {}: there is none to remove",
            AXES[axis]
        )));
    }
    let changed = if add {
        solid.with_cell_added(axis)
    } else {
        solid.with_cell_removed(axis)
    }
    .map_err(bad)?;
    Ok(changed
        .single_spec()
        .unwrap_or_else(|| SolidSpec::from_piecewise(&changed)))
}

/// What a piecewise solid of one cell along every axis is as a single one.
trait Cellular {
    /// The spec of the single patch or volume, where the solid has one cell.
    fn single_spec(&self) -> Option<SolidSpec>;
}

impl Cellular for Piecewise<2> {
    fn single_spec(&self) -> Option<SolidSpec> {
        (self.cells() == [1, 1])
            .then(|| self.part([0, 0]).map(|s| ModelFile::from_solid2(s).solid))?
    }
}

impl Cellular for Piecewise<3> {
    fn single_spec(&self) -> Option<SolidSpec> {
        (self.cells() == [1, 1, 1]).then(|| {
            self.part([0, 0, 0])
                .map(|s| ModelFile::from_solid3(s).solid)
        })?
    }
}

impl Parts {
    /// The parts of `root`: the first Bézier part (depth first) is selected and opened in
    /// `editor`, or else the root is selected.
    ///
    /// # Errors
    ///
    /// A tree that breaks a rule of DESIGN §5.
    pub fn new(root: SolidSpec, editor: &mut Editor) -> Result<Self, Error> {
        let outline = Self::outline_of(root)?;
        let mut parts = Self {
            outline,
            history: History::new(HISTORY_BYTES),
            last_set: None,
            sync_recorded: None,
            open: None,
            synced: editor.revision(),
            gesture: None,
        };
        parts.reload(editor)?;
        Ok(parts)
    }

    /// The outline of `root` with its first Bézier part (depth first) selected, or its root.
    fn outline_of(root: SolidSpec) -> Result<Outline, Error> {
        let mut outline = Outline::new(root)?;
        if let Some(row) = outline.rows().into_iter().find(|r| r.bezier) {
            outline.select(&row.path)?;
        }
        Ok(outline)
    }

    /// The editor's model of one solid as a tree of one part, selected and open.
    ///
    /// # Errors
    ///
    /// None for a model the editor holds; the type is [`Parts::new`]'s.
    pub fn of_editor(editor: &mut Editor) -> Result<Self, Error> {
        // The editor's undo steps become the tree's (opening the part forgets the editor's).
        let history = editor.undo_specs();
        let mut parts = Self::new(editor_spec(editor), editor)?;
        for root in history {
            parts.history.push(Snapshot {
                root,
                selected: Vec::new(),
            });
        }
        Ok(parts)
    }

    /// The outline (the tree as last written back, and the selection).
    #[must_use]
    pub fn outline(&self) -> &Outline {
        &self.outline
    }

    /// The path of the part open in the editor.
    #[must_use]
    pub fn open(&self) -> Option<&[usize]> {
        self.open.as_deref()
    }

    /// The tree with the open part as `editor` has it now (during a drag too).
    #[must_use]
    pub fn root(&self, editor: &Editor) -> SolidSpec {
        let mut o = self.outline.clone();
        if let Some(path) = &self.open {
            // The editor's part is a valid node of the tree's dimension: this cannot fail.
            let _ = o.replace(path, editor_spec(editor));
        }
        o.root().clone()
    }

    /// What the views show of the tree (see [`Self::root`]): the tree without its hidden parts
    /// (an operation keeps the operands left, a blend or a morph left with one is that one);
    /// `None` when everything is hidden.
    #[must_use]
    pub fn shown(&self, editor: &Editor) -> Option<SolidSpec> {
        fn strip(spec: SolidSpec) -> Option<SolidSpec> {
            match spec {
                SolidSpec::Part { hidden: true, .. } => None,
                SolidSpec::Part { solid, name, .. } => strip(*solid).map(|s| SolidSpec::Part {
                    solid: Box::new(s),
                    name,
                    hidden: false,
                }),
                SolidSpec::Transform {
                    solid,
                    translate,
                    rotate,
                    scale,
                } => strip(*solid).map(|s| SolidSpec::Transform {
                    solid: Box::new(s),
                    translate,
                    rotate,
                    scale,
                }),
                mut spec => {
                    let difference = matches!(spec, SolidSpec::Difference { .. });
                    let Some(of) = spec.operands_mut() else {
                        return Some(spec);
                    };
                    let all = of.len();
                    let kept: Vec<Option<SolidSpec>> =
                        core::mem::take(of).into_iter().map(strip).collect();
                    // A difference without what it cuts from is nothing (not its cutters).
                    if difference && kept.first().is_some_and(Option::is_none) {
                        return None;
                    }
                    let kept: Vec<SolidSpec> = kept.into_iter().flatten().collect();
                    match kept.len() {
                        0 => None,
                        1 if all > 1 => kept.into_iter().next(),
                        _ => {
                            *spec.operands_mut()? = kept;
                            Some(spec)
                        }
                    }
                }
            }
        }
        // The tree is at most 32 deep (checked), so the recursion is bounded.
        strip(self.root(editor))
    }

    /// Renames the selection ([`Outline::rename`]). One undo step.
    ///
    /// # Errors
    ///
    /// A name past the cap.
    pub fn rename(&mut self, name: &str, editor: &mut Editor) -> Result<(), Error> {
        self.edit(editor, |o| o.rename(name))
    }

    /// Hides the selection from the views or shows it again ([`Outline::toggle_hidden`]). One
    /// undo step.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn toggle_hidden(&mut self, editor: &mut Editor) -> Result<(), Error> {
        self.edit(editor, Outline::toggle_hidden)
    }

    /// The model file of the whole tree (see [`Self::root`]).
    #[must_use]
    pub fn file(&self, editor: &Editor) -> ModelFile {
        ModelFile::from_spec(self.root(editor))
    }

    /// The checked tree (see [`Self::root`]).
    ///
    /// # Errors
    ///
    /// None in practice: every tree the outline holds was checked.
    pub fn tree(&self, editor: &Editor) -> Result<ModelTree, Error> {
        Ok(self.file(editor).to_tree()?)
    }

    /// Writes what the editor changed in the open part back into the tree, as one undo step,
    /// unless a drag is under way. Call it after anything that may edit the part.
    pub fn sync(&mut self, editor: &Editor) {
        if editor.revision() == self.synced || editor.busy() {
            return;
        }
        self.synced = editor.revision();
        let Some(path) = self.open.clone() else {
            return;
        };
        let spec = editor_spec(editor);
        if self.outline.node(&path) == Some(&spec) {
            return;
        }
        let before = self.snapshot();
        if self.outline.replace(&path, spec).is_ok() {
            self.last_set = None;
            let merged = self.sync_recorded == Some(editor.recorded());
            if !merged {
                self.push(before);
            }
            self.sync_recorded = Some(editor.recorded());
        }
    }

    /// Opens the selected node in the editor when it is a Bézier part (and it is not open as it
    /// is already); bumps the editor's revision so that what is drawn of the tree follows.
    fn reload(&mut self, editor: &mut Editor) -> Result<(), Error> {
        let selected = self.outline.through_parts(self.outline.selected());
        let node = self.outline.node(&selected).cloned();
        match node {
            Some(spec) if is_bezier(&spec) => {
                let same =
                    self.open.as_deref() == Some(&selected[..]) && editor_spec(editor) == spec;
                if !same {
                    document::open_spec(editor, spec)?;
                }
                self.open = Some(selected);
            }
            _ => self.open = None,
        }
        editor.forget_history();
        editor.touch();
        self.synced = editor.revision();
        Ok(())
    }

    /// Applies `edit` to the outline as one undo step (the open part written back first), then
    /// opens the selection.
    fn edit(
        &mut self,
        editor: &mut Editor,
        edit: impl FnOnce(&mut Outline) -> Result<(), Error>,
    ) -> Result<(), Error> {
        self.sync(editor);
        let before = self.snapshot();
        edit(&mut self.outline)?;
        self.last_set = None;
        self.push(before);
        self.reload(editor)
    }

    /// Replaces the whole model by `root` (an opened file, link or preset; one undo step).
    ///
    /// # Errors
    ///
    /// A tree that breaks a rule: nothing changes.
    pub fn replace_root(&mut self, root: SolidSpec, editor: &mut Editor) -> Result<(), Error> {
        let outline = Self::outline_of(root)?;
        self.edit(editor, |o| {
            *o = outline;
            Ok(())
        })
    }

    /// Replaces the open Bézier part by `node` (a new grid; one undo step); a name around it
    /// stays.
    ///
    /// # Errors
    ///
    /// No part open, or a node of the other dimension in a tree of more: nothing changes.
    pub fn replace_open(&mut self, node: SolidSpec, editor: &mut Editor) -> Result<(), Error> {
        let path = self
            .open
            .clone()
            .ok_or_else(|| Error::new("select a Bézier part to replace it with a new grid"))?;
        self.edit(editor, |o| o.replace(&path, node))
    }

    /// The program and box of the selected part if it is a HyperFun program.
    #[must_use]
    pub fn selected_hyperfun(&self) -> Option<(String, [[f64; 3]; 2])> {
        match self.outline.selected_leaf()?.1 {
            SolidSpec::Hyperfun { program, bounds } => Some((
                program.clone(),
                bounds.unwrap_or(bezsolid_core::model::DEFAULT_HYPERFUN_BOX),
            )),
            _ => None,
        }
    }

    /// Puts `program` in `bounds` in place of the selected HyperFun part (one undo step).
    ///
    /// # Errors
    ///
    /// A selection that is no HyperFun part, or a program the tree refuses (HyperFun's error at
    /// its line): nothing changes.
    pub fn set_hyperfun(
        &mut self,
        program: &str,
        bounds: [[f64; 3]; 2],
        editor: &mut Editor,
    ) -> Result<(), Error> {
        let (path, node) = self.outline.selected_leaf().ok_or("nothing is selected")?;
        if !matches!(node, SolidSpec::Hyperfun { .. }) {
            return Err(
                "select a HyperFun part under Parts to put the program in its place".into(),
            );
        }
        let node = SolidSpec::Hyperfun {
            program: program.into(),
            bounds: Some(bounds),
        };
        self.edit(editor, |o| o.replace(&path, node))
    }

    /// Selects the node at `path` (not an undo step).
    ///
    /// # Errors
    ///
    /// No such node.
    pub fn select(&mut self, path: &[usize], editor: &mut Editor) -> Result<(), Error> {
        self.sync(editor);
        self.outline.select(path)?;
        self.last_set = None;
        self.reload(editor)
    }

    /// Adds a node of `kind` beside the selection ([`Outline::add`]), at the right of the
    /// selection's bounds.
    ///
    /// # Errors
    ///
    /// A kind of the other dimension, or a tree past the caps.
    pub fn add(&mut self, kind: NewNode, editor: &mut Editor) -> Result<(), Error> {
        let at = self.beside(editor);
        self.edit(editor, |o| o.add(kind, at))
    }

    /// Puts `op` around the selection ([`Outline::wrap`]).
    ///
    /// # Errors
    ///
    /// A tree past the caps.
    pub fn wrap(&mut self, op: Wrap, editor: &mut Editor) -> Result<(), Error> {
        let at = self.beside(editor);
        self.edit(editor, |o| o.wrap(op, at))
    }

    /// Removes the selection ([`Outline::remove`]).
    ///
    /// # Errors
    ///
    /// For the root.
    pub fn remove(&mut self, editor: &mut Editor) -> Result<(), Error> {
        self.edit(editor, Outline::remove)
    }

    /// Moves the selection `by` places among its siblings ([`Outline::reorder`]).
    ///
    /// # Errors
    ///
    /// See [`Outline::reorder`].
    pub fn reorder(&mut self, by: isize, editor: &mut Editor) -> Result<(), Error> {
        self.edit(editor, |o| o.reorder(by))
    }

    /// Sets a number of the selection ([`Outline::set`]); settings of one field of one node in a
    /// row (a slider's moves) are one undo step.
    ///
    /// # Errors
    ///
    /// A field the node lacks, or a value the tree's rules refuse: nothing changes.
    pub fn set(&mut self, field: &str, value: f64, editor: &mut Editor) -> Result<(), Error> {
        self.sync(editor);
        let key = (self.outline.selected().to_vec(), field.to_owned());
        let before = self.snapshot();
        self.outline.set(field, value)?;
        if self.snapshot() != before {
            if self.last_set.as_ref() != Some(&key) {
                self.push(before);
            }
            self.last_set = Some(key);
        }
        editor.touch();
        self.synced = editor.revision();
        Ok(())
    }

    /// Adds a cell along `axis` (0 = u) to the open part, after its last
    /// ([`Piecewise::with_cell_added`]: the last cells mirrored across their face); a single
    /// patch or volume becomes a piecewise one of two cells. One undo step.
    ///
    /// # Errors
    ///
    /// No part open, an axis the part lacks, or a net past what the editor takes
    /// ([`document::editable`]): nothing changes.
    pub fn add_cell(&mut self, axis: usize, editor: &mut Editor) -> Result<(), Error> {
        self.change_cells(axis, true, editor)
    }

    /// Removes the open part's last cell along `axis`; a piecewise solid left with one cell is a
    /// single patch or volume again. One undo step.
    ///
    /// # Errors
    ///
    /// No part open, or one cell along `axis`: nothing changes.
    pub fn remove_cell(&mut self, axis: usize, editor: &mut Editor) -> Result<(), Error> {
        self.change_cells(axis, false, editor)
    }

    fn change_cells(&mut self, axis: usize, add: bool, editor: &mut Editor) -> Result<(), Error> {
        self.sync(editor);
        let path = self
            .open
            .clone()
            .ok_or_else(|| Error::new("select a Bézier part to change its cells"))?;
        let spec = editor_spec(editor);
        let node = if editor.volume().is_some() {
            cells_changed::<3>(&spec, axis, add)?
        } else {
            cells_changed::<2>(&spec, axis, add)?
        };
        if !document::editable(&node) {
            return Err(Error::new(format!(
                "the net would have more than {MAX_PIECEWISE_POINTS} points along {}: the \
                 editor takes at most that many",
                AXES[axis]
            )));
        }
        self.edit(editor, |o| o.replace(&path, node))
    }

    /// What the outliner shows, as JSON: `dimension`, `selected` and `open` (paths), the
    /// selection's `name` and whether it is `hidden` (a named part's), `rows` (`path`, `depth`,
    /// `label`, `bezier`, `hidden`), `fields` of the selection (`name`, `value`), and `undo`,
    /// `redo`.
    #[must_use]
    pub fn to_json(&self) -> String {
        let rows: Vec<_> = self
            .outline
            .rows()
            .into_iter()
            .map(|r| {
                serde_json::json!({
                    "path": r.path, "depth": r.depth, "label": r.label, "bezier": r.bezier,
                    "hidden": r.hidden,
                })
            })
            .collect();
        let fields: Vec<_> = self
            .outline
            .fields()
            .into_iter()
            .map(|(name, value)| serde_json::json!({ "name": name, "value": value }))
            .collect();
        let (name, hidden) = match self.outline.node(self.outline.selected()) {
            Some(SolidSpec::Part { name, hidden, .. }) => (name.as_str(), *hidden),
            _ => ("", false),
        };
        serde_json::json!({
            "dimension": self.outline.dimension(),
            "name": name,
            "hidden": hidden,
            "selected": self.outline.selected(),
            "open": self.open,
            "rows": rows,
            "fields": fields,
            "undo": self.can_undo(),
            "redo": self.can_redo(),
        })
        .to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bezsolid_core::Solid3;
    use glam::DVec2;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn volume_editor() -> Editor {
        let mut e = Editor::new(bezsolid_core::Solid2::fig9());
        e.new_volume(4, 4, 4).unwrap();
        e.forget_history();
        e
    }

    /// The piecewise patch of `cells` quadratic cells over `[0, cells]` of the file, `ξ` a bump.
    fn piecewise_patch(cells: [usize; 2]) -> SolidSpec {
        let dims = cells.map(|c| 2 * c + 1);
        let points = (0..dims[0])
            .flat_map(|i| (0..dims[1]).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (x, y) = (i as f64 / 2.0, j as f64 / 2.0);
                vec![x, y, 0.3 - 0.1 * ((x - 0.8).powi(2) + (y - 0.5).powi(2))]
            })
            .collect();
        SolidSpec::Piecewise {
            cells: cells.to_vec(),
            degree: vec![2, 2],
            points,
        }
    }

    /// The page's path: a piecewise file opened as a model, its global net in the editor; a point
    /// on the face two cells share dragged (in space, then in ξ) moves in both cells, as one undo
    /// step; the views' `f` is the piecewise solid's.
    #[test]
    fn a_piecewise_net_is_edited_as_one_and_a_shared_point_moves_every_cell_that_holds_it() {
        let mut e = Editor::new(bezsolid_core::Solid2::fig9());
        let mut parts = Parts::new(piecewise_patch([2, 1]), &mut e).unwrap();
        assert_eq!(
            parts.open(),
            Some(&[][..]),
            "a piecewise part is opened for editing"
        );
        assert_eq!(e.solid().degree(), [4, 2], "the global net, 5 × 3 points");
        let cells = e.cells().cloned().unwrap();
        assert_eq!((cells.count, cells.degree), (vec![2, 1], vec![2, 2]));
        // Point (2, 1) lies on the face x = 1 that the two cells share.
        let index = 2 * 3 + 1;
        let cell = |parts: &Parts, e: &Editor, c: [usize; 2]| {
            let solid = parts.root(e).to_piecewise::<2>().unwrap().unwrap();
            solid.part(c).unwrap().net().clone()
        };
        e.begin_drag(index, crate::editor::Mode::Space);
        assert!(e.drag_to(Some(DVec2::new(1.1, 0.55)), Some(0.9)));
        e.end_drag();
        parts.sync(&e);
        let moved = glam::DVec3::new(1.1, 0.55, 0.9);
        assert_eq!(cell(&parts, &e, [0, 0]).points()[2 * 3 + 1], moved);
        assert_eq!(
            cell(&parts, &e, [1, 0]).points()[1],
            moved,
            "the same point of the next cell"
        );
        assert!(matches!(
            parts.outline().root(),
            SolidSpec::Piecewise { .. }
        ));
        // What the views evaluate is the piecewise solid, not the global net as one patch.
        let solid = parts.root(&e).to_piecewise::<2>().unwrap().unwrap();
        for p in [
            DVec2::new(1.05, 0.5),
            DVec2::new(0.3, 0.2),
            DVec2::new(1.9, 0.8),
        ] {
            assert_eq!(e.f(p), solid.f(p));
        }
        assert!(
            (e.f(DVec2::new(1.05, 0.5)) - e.solid().f(DVec2::new(1.05, 0.5))).abs() > 1e-6,
            "one patch of the global net is another solid"
        );
        assert!(parts.undo(&mut e));
        assert_eq!(parts.root(&e), piecewise_patch([2, 1]));
        assert!(
            e.cells().is_some(),
            "undo gives the piecewise part back, still piecewise"
        );
    }

    /// Cells added along an axis of a single patch, then of a piecewise volume; removed again
    /// down to the single solid; the caps say what they are.
    #[test]
    fn cells_are_added_along_an_axis_and_removed_within_the_editors_caps() {
        let mut e = Editor::new(bezsolid_core::Solid2::fig9());
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.add_cell(0, &mut e).unwrap();
        let SolidSpec::Piecewise { cells, degree, .. } = parts.root(&e) else {
            panic!("a patch with a cell added is piecewise");
        };
        assert_eq!((cells, degree), (vec![2, 1], vec![2, 2]));
        assert_eq!(e.solid().degree(), [4, 2]);
        // The new cell mirrors the first: f is symmetric about their face.
        let (lo, hi) = e.solid().domain();
        let mid = (lo.x + hi.x) / 2.0;
        for p in [DVec2::new(0.2, 0.3), DVec2::new(0.45, 0.8)] {
            let q = DVec2::new(2.0 * mid - p.x, p.y);
            assert!((e.f(p) - e.f(q)).abs() < 1e-12);
        }
        assert!(parts.remove_cell(1, &mut e).is_err(), "one cell along v");
        parts.remove_cell(0, &mut e).unwrap();
        assert_eq!(
            parts.root(&e),
            ModelFile::from_solid2(&bezsolid_core::Solid2::fig9()).solid,
            "one cell left: the single patch again"
        );
        assert!(e.cells().is_none());
        // Quadratic cells: eight fit the editor (17 points), a ninth does not.
        for _ in 0..7 {
            parts.add_cell(1, &mut e).unwrap();
        }
        let err = parts.add_cell(1, &mut e).unwrap_err();
        assert!(err.to_string().contains("points along v"), "{err}");
        assert!(parts.add_cell(2, &mut e).is_err(), "a patch has no w");
        // A volume's cells, and the slice the 2D view shows is piecewise across its plane.
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.add_cell(2, &mut e).unwrap();
        parts.add_cell(0, &mut e).unwrap();
        let volume = e.piecewise3().unwrap();
        assert_eq!(volume.cells(), [2, 1, 2]);
        e.set_slice(bezsolid_core::Axis::V, 1).unwrap();
        let slice = e.piecewise2().unwrap();
        assert_eq!(slice.cells(), [2, 2], "the cells of the xz plane");
        assert!(parts.undo(&mut e) && parts.undo(&mut e) && !parts.undo(&mut e));
        assert!(e.cells().is_none(), "two steps back: the single volume");
    }

    /// Built as the page builds it: a volume, parts added, a point of the volume dragged, a
    /// blend's setting moved like a slider; each change one undo step, undone and redone.
    #[test]
    fn a_hyperfun_part_is_added_read_and_replaced_in_one_undo_step() {
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        assert_eq!(parts.selected_hyperfun(), None);
        parts.add(NewNode::Hyperfun, &mut e).unwrap();
        let (program, [lo, hi]) = parts.selected_hyperfun().expect("the new part is selected");
        assert!(program.contains("hfBlendUni"));
        assert!((0..3).all(|i| lo[i] < hi[i]));
        // The tree evaluates it: inside at its centre.
        let ModelTree::Space(tree) = parts.tree(&e).unwrap() else {
            panic!("3D")
        };
        let centre = (DVec3::from_array(lo) + DVec3::from_array(hi)) / 2.0;
        assert!(tree.f(centre) > 0.0);
        // Named, it is still the selection's program; a new program replaces it, one step.
        parts.rename("ring", &mut e).unwrap();
        let bigger = program.replace("0.35", "0.5");
        parts.set_hyperfun(&bigger, [lo, hi], &mut e).unwrap();
        assert_eq!(parts.selected_hyperfun().unwrap().0, bigger);
        assert!(parts.undo(&mut e));
        assert_eq!(parts.selected_hyperfun().unwrap().0, program);
        // A program HyperFun refuses changes nothing.
        let err = parts
            .set_hyperfun("my_model(x[3], a[1]) { s = 1; }", [lo, hi], &mut e)
            .unwrap_err();
        assert!(err.to_string().contains("Left bracket expected"), "{err}");
        assert_eq!(parts.selected_hyperfun().unwrap().0, program);
        // Another selection is no HyperFun part.
        parts.select(&[0], &mut e).unwrap();
        assert!(parts.set_hyperfun(&program, [lo, hi], &mut e).is_err());
    }

    #[test]
    fn every_change_to_a_model_of_many_solids_is_one_undo_step() {
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        assert_eq!(parts.open(), Some(&[][..]));
        parts.add(NewNode::Sphere, &mut e).unwrap();
        parts.add(NewNode::Box, &mut e).unwrap();
        assert!(matches!(parts.outline().root(), SolidSpec::Union { of } if of.len() == 3));
        assert_eq!(parts.open(), None, "a sphere is not a Bézier part");
        // Open the volume and drag one of its points: one step, written back when the drag ends.
        parts.select(&[0], &mut e).unwrap();
        assert_eq!(parts.open(), Some(&[0][..]));
        let before = parts.outline().root().clone();
        e.begin_volume_drag(0);
        assert!(e.drag_volume_to(Some(DVec3::new(-0.3, -0.2, -0.1)), None));
        parts.sync(&e);
        assert_eq!(
            parts.outline().root(),
            &before,
            "not while the drag is under way"
        );
        assert_ne!(
            parts.root(&e),
            before,
            "but the whole tree follows the drag"
        );
        e.end_drag();
        parts.sync(&e);
        let dragged = parts.outline().root().clone();
        assert_ne!(dragged, before);
        // A blend around the box, its a0 moved in three settings: one step.
        parts.select(&[2], &mut e).unwrap();
        parts.wrap(Wrap::BlendUnion, &mut e).unwrap();
        for a0 in [0.2, 0.3, 0.4] {
            parts.set("a0", a0, &mut e).unwrap();
        }
        assert!(parts.set("a1", 0.0, &mut e).is_err(), "a1 = 0 is refused");
        let blended = parts.outline().root().clone();
        assert!(parts.undo(&mut e), "the a0 settings");
        assert!(parts.undo(&mut e), "the blend");
        assert_eq!(parts.outline().root(), &dragged);
        assert!(parts.undo(&mut e), "the drag");
        assert_eq!(parts.outline().root(), &before);
        assert!(parts.redo(&mut e) && parts.redo(&mut e) && parts.redo(&mut e));
        assert_eq!(parts.outline().root(), &blended);
        assert!(!parts.can_redo());
        // The tree the page meshes is the whole model.
        let ModelTree::Space(t) = parts.tree(&e).unwrap() else {
            panic!("3D")
        };
        assert_eq!(t.leaf_count(), 4);
        assert_eq!(t.bezier_count(), 1);
    }

    /// A sphere's handles: a move, a turn and a scale dragged, each one undo step; the first
    /// puts a transform around the sphere.
    #[test]
    fn handles_move_turn_and_scale_the_selection_one_step_each() {
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.add(NewNode::Sphere, &mut e).unwrap();
        let centre = |parts: &Parts, e: &Editor| {
            let (lo, hi) = parts.bounds_of(parts.outline().selected(), e).unwrap();
            0.5 * (lo + hi)
        };
        let c0 = centre(&parts, &e);
        parts.begin_handle(&mut e).unwrap();
        assert!(matches!(
            parts.outline().node(parts.outline().selected()),
            Some(SolidSpec::Transform { .. })
        ));
        for k in 1..=4 {
            parts.drag_handle(
                Handle::Move,
                DVec3::new(0.0, 0.0, 0.1 * f64::from(k)),
                &mut e,
            );
        }
        parts.end_handle();
        let c1 = centre(&parts, &e);
        assert!(
            (c1 - c0 - DVec3::new(0.0, 0.0, 0.4)).length() < 1e-9,
            "{c0} → {c1}"
        );
        // Scale it by 2 about its own origin, turn it a quarter: the transform's numbers.
        parts.begin_handle(&mut e).unwrap();
        parts.drag_handle(Handle::Scale, DVec3::new(2.0, 0.0, 0.0), &mut e);
        parts.drag_handle(Handle::Scale, DVec3::new(0.0, 0.0, 0.0), &mut e);
        parts.end_handle();
        parts.begin_handle(&mut e).unwrap();
        parts.drag_handle(Handle::Turn, DVec3::new(90.0, 0.0, 0.0), &mut e);
        parts.end_handle();
        let fields: Vec<(String, f64)> = parts.outline().fields();
        let get = |n: &str| fields.iter().find(|(f, _)| f == n).unwrap().1;
        assert_eq!(
            get("scale[0]"),
            2.0,
            "a zero scale was refused, the last good one kept"
        );
        assert_eq!(get("rotate[2]"), 90.0);
        // Turned and scaled about its centre, which stayed where the move put it.
        let c2 = centre(&parts, &e);
        assert!((c2 - c1).length() < 1e-9, "{c1} → {c2}");
        let (lo, hi) = parts.bounds_of(parts.outline().selected(), &e).unwrap();
        assert!(
            ((hi - lo).x - 1.6).abs() < 1e-9,
            "a sphere of radius 0.8 now"
        );
        // Three drags, three steps (the first with its new transform).
        for _ in 0..3 {
            assert!(parts.undo(&mut e));
        }
        assert!(matches!(
            parts.outline().node(&[1]),
            Some(SolidSpec::Sphere { .. })
        ));
    }

    /// What a review found: the editor's history carried over, wheel notches merged as the editor
    /// merges them, a value set to itself no step, a new grid of the other dimension for the root,
    /// a new grid keeping a name, parts added beside a moved one where it is, a named part's solid
    /// removed with its name.
    #[test]
    fn history_and_edits_keep_to_what_the_user_sees() {
        let mut e = Editor::new(bezsolid_core::Solid2::fig9());
        let original = editor_spec(&e);
        e.select(Some((1, 1)));
        e.nudge(0.1);
        e.select(Some((0, 0)));
        e.nudge(0.1);
        let mut parts = Parts::of_editor(&mut e).unwrap();
        assert!(
            parts.undo(&mut e) && parts.undo(&mut e),
            "the editor's two steps"
        );
        assert_eq!(parts.outline().root(), &original);
        assert!(!parts.can_undo());
        // Five wheel notches on one point: one step, as in the editor.
        e.select(Some((1, 1)));
        let before = parts.outline().root().clone();
        for _ in 0..5 {
            e.wheel(100.0);
            parts.sync(&e);
        }
        assert_ne!(parts.outline().root(), &before);
        assert!(parts.undo(&mut e));
        assert_eq!(parts.outline().root(), &before);
        assert!(!parts.can_undo());
        // A value set to itself is no step, and does not join the next setting to an older step.
        parts.add(NewNode::Sphere, &mut e).unwrap();
        parts.set("radius", 0.4, &mut e).unwrap();
        let with_sphere = parts.outline().root().clone();
        parts.set("radius", 0.5, &mut e).unwrap();
        assert!(parts.undo(&mut e));
        assert_eq!(parts.outline().root(), &with_sphere);
        // The sphere removed again, the patch is the root: a new volume replaces it, and the
        // model is 3D from then on.
        parts.remove(&mut e).unwrap();
        parts.select(&[], &mut e).unwrap();
        let mut scratch = e.clone();
        scratch.new_volume(3, 3, 3).unwrap();
        parts.replace_open(editor_spec(&scratch), &mut e).unwrap();
        assert_eq!(parts.outline().dimension(), 3);
        parts.add(NewNode::Torus, &mut e).unwrap();
        // A named volume given a new grid keeps its name.
        parts.select(&[0], &mut e).unwrap();
        parts.rename("hull", &mut e).unwrap();
        assert_eq!(parts.open(), Some(&[0, 0][..]));
        let mut scratch = e.clone();
        scratch.new_volume(2, 2, 2).unwrap();
        parts.replace_open(editor_spec(&scratch), &mut e).unwrap();
        assert!(
            matches!(parts.outline().node(&[0]), Some(SolidSpec::Part { name, .. }) if name == "hull")
        );
        // Deleting the named part's solid takes the part with it.
        parts.select(&[0, 0], &mut e).unwrap();
        parts.remove(&mut e).unwrap();
        assert!(matches!(parts.outline().root(), SolidSpec::Torus { .. }));
        // A part added beside a moved and scaled one lands beside it in space.
        parts.wrap(Wrap::Transform, &mut e).unwrap();
        parts.set("translate[0]", 5.0, &mut e).unwrap();
        parts.set("scale[0]", 2.0, &mut e).unwrap();
        let (lo, hi) = parts.bounds_of(&[], &e).unwrap();
        parts.select(&[0], &mut e).unwrap();
        parts.add(NewNode::Box, &mut e).unwrap();
        assert_eq!(
            parts.outline().selected(),
            [0, 1],
            "beside the torus, under its move"
        );
        let (blo, bhi) = parts.bounds_of(parts.outline().selected(), &e).unwrap();
        let gap = blo.x.max(lo.x) - bhi.x.min(hi.x);
        assert!(
            gap < 0.0,
            "the box ({blo}, {bhi}) touches the torus ({lo}, {hi})"
        );
    }

    /// Hidden parts are left out of what the views show, and only there.
    #[test]
    fn hidden_parts_leave_the_views_only() {
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.add(NewNode::Sphere, &mut e).unwrap();
        parts.add(NewNode::Box, &mut e).unwrap();
        parts.select(&[1], &mut e).unwrap();
        parts.toggle_hidden(&mut e).unwrap();
        let shown = parts.shown(&e).unwrap();
        assert!(matches!(&shown, SolidSpec::Union { of } if of.len() == 2));
        assert!(matches!(parts.outline().root(), SolidSpec::Union { of } if of.len() == 3));
        // The box blended with a second sphere, which is hidden: the box alone is shown there.
        parts.select(&[2], &mut e).unwrap();
        parts.wrap(Wrap::BlendUnion, &mut e).unwrap();
        parts.select(&[2, 1], &mut e).unwrap();
        parts.toggle_hidden(&mut e).unwrap();
        let Some(SolidSpec::Union { of }) = parts.shown(&e) else {
            panic!("a union")
        };
        assert!(matches!(of[1], SolidSpec::Box { .. }), "{of:?}");
        // A difference whose first operand is hidden shows nothing, not its cutters: the box is
        // all that is left to show.
        parts.select(&[0], &mut e).unwrap();
        parts.wrap(Wrap::Difference, &mut e).unwrap();
        parts.select(&[0, 0], &mut e).unwrap();
        parts.toggle_hidden(&mut e).unwrap();
        assert!(matches!(parts.shown(&e), Some(SolidSpec::Box { .. })));
        // Everything hidden: nothing shown; one undo shows the root again.
        parts.select(&[], &mut e).unwrap();
        parts.toggle_hidden(&mut e).unwrap();
        assert!(parts.shown(&e).is_none());
        assert!(parts.undo(&mut e));
        assert!(parts.shown(&e).is_some());
        // The file keeps every part, hidden or not.
        let ModelTree::Space(t) = parts.tree(&e).unwrap() else {
            panic!("3D")
        };
        assert_eq!(t.leaf_count(), 5);
    }

    /// A patch under a transform of a 2D model: the placement takes its points where the tree has
    /// them (the tree's f at the placed point is the patch's f at the point).
    #[test]
    fn a_patch_under_a_transform_is_placed_in_the_plane() {
        let mut e = Editor::new(bezsolid_core::Solid2::fig9());
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.wrap(Wrap::Transform, &mut e).unwrap();
        parts.set("translate[0]", 1.5, &mut e).unwrap();
        parts.set("rotate", 30.0, &mut e).unwrap();
        parts.set("scale[1]", -0.5, &mut e).unwrap();
        parts.select(&[0], &mut e).unwrap();
        assert_eq!(parts.open(), Some(&[0][..]));
        let map = parts.placement2(&[0]);
        let ModelTree::Plane(t) = parts.tree(&e).unwrap() else {
            panic!("2D")
        };
        for p in [glam::DVec2::new(0.5, 0.5), glam::DVec2::new(0.2, 0.9)] {
            let (a, b) = (t.f(map.transform_point2(p)), e.solid().f(p));
            assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{a} against {b}");
        }
    }

    #[test]
    fn a_part_under_a_transform_is_placed_and_framed_in_space() {
        let mut e = volume_editor();
        let mut parts = Parts::of_editor(&mut e).unwrap();
        parts.wrap(Wrap::Transform, &mut e).unwrap();
        parts.set("translate[0]", 2.0, &mut e).unwrap();
        parts.set("scale[2]", 3.0, &mut e).unwrap();
        parts.set("rotate[2]", 90.0, &mut e).unwrap();
        let map = parts.placement(&[0]);
        // (1, 0, 1) scaled to (1, 0, 3), turned about z to (0, 1, 3), moved to (2, 1, 3).
        let p = map.transform_point3(DVec3::new(1.0, 0.0, 1.0));
        assert!((p - DVec3::new(2.0, 1.0, 3.0)).length() < 1e-12, "{p}");
        // The transform's box in space holds the moved volume's points.
        let (lo, hi) = parts.bounds_of(&[], &e).unwrap();
        parts.select(&[0], &mut e).unwrap();
        let volume: &Solid3 = e.volume().unwrap();
        for q in volume.net().points() {
            let w = map.transform_point3(q.truncate());
            assert!(w.cmpge(lo - 1e-9).all() && w.cmple(hi + 1e-9).all(), "{w}");
        }
    }
}
