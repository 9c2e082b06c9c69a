//! The one undo history of a model of many solids: its snapshots, their weight, and the steps
//! back and forth through them.

use super::*;

/// The most bytes the undo and redo steps of a model of many solids keep (each step holds the
/// whole tree): past it the oldest steps go, the newest always stays.
pub const HISTORY_BYTES: usize = 64 << 20;

impl Weighed for Snapshot {
    fn bytes(&self) -> usize {
        spec_bytes(&self.root)
    }
}

/// About how many bytes `spec` takes: its numbers, and a little per node.
pub(super) fn spec_bytes(spec: &SolidSpec) -> usize {
    let mut bytes = 0;
    let mut todo = vec![spec];
    while let Some(s) = todo.pop() {
        bytes += 64
            + match s {
                SolidSpec::Patch { points, .. } => 24 * points.len(),
                SolidSpec::Volume { points, .. } => 32 * points.len(),
                SolidSpec::Piecewise { points, .. } => {
                    points.iter().map(|p| 24 + 8 * p.len()).sum()
                }
                SolidSpec::Part { name, .. } => name.len(),
                SolidSpec::Hyperfun { program, .. } => program.len(),
                _ => 0,
            };
        todo.extend(s.children());
    }
    bytes
}

impl Parts {
    pub(super) fn snapshot(&self) -> Snapshot {
        Snapshot {
            root: self.outline.root().clone(),
            selected: self.outline.selected().to_vec(),
        }
    }

    pub(super) fn push(&mut self, before: Snapshot) {
        if self.snapshot() == before {
            return;
        }
        self.history.push(before);
        self.sync_recorded = None;
    }

    /// Forgets every undo and redo step (after restoring an autosaved model at start-up).
    pub fn forget_history(&mut self) {
        self.history.clear();
        self.last_set = None;
    }

    /// Whether there is a step to undo.
    #[must_use]
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone step to redo.
    #[must_use]
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Undoes the last step (a drag of a part's point, an added node, a slider's setting, …);
    /// returns whether there was one.
    pub fn undo(&mut self, editor: &mut Editor) -> bool {
        self.step(editor, true)
    }

    /// Redoes the last undone step; returns whether there was one.
    pub fn redo(&mut self, editor: &mut Editor) -> bool {
        self.step(editor, false)
    }

    pub(super) fn step(&mut self, editor: &mut Editor, back: bool) -> bool {
        if editor.busy() || self.gesture.is_some() {
            return false;
        }
        self.sync(editor);
        let now = self.snapshot();
        let Some(snapshot) = (if back {
            self.history.undo(now)
        } else {
            self.history.redo(now)
        }) else {
            return false;
        };
        self.sync_recorded = None;
        // A snapshot was a checked tree.
        if let Ok(mut o) = Outline::new(snapshot.root) {
            let _ = o.select(&snapshot.selected);
            self.outline = o;
        }
        self.last_set = None;
        self.open = None;
        let _ = self.reload(editor);
        true
    }
}
