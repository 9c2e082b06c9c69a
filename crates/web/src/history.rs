//! Undo and redo of whole states: a model of many solids' tree, the Free-form mode's scene.
//!
//! Each step keeps the state as it was before a change, with its size in bytes; the oldest steps go
//! past [`HISTORY_LIMIT`] steps or a byte budget (the newest always stays), so an imported mesh of
//! millions of triangles cannot fill the page's memory however often it is moved.

use crate::editor::HISTORY_LIMIT;

/// A state the history can keep: its size in bytes (about: its numbers and a little more).
pub trait Weighed {
    /// About how many bytes the state holds.
    fn bytes(&self) -> usize;
}

/// The steps to undo and redo of states `T`, within `budget` bytes.
#[derive(Clone, Debug)]
pub struct History<T> {
    undo: Vec<(T, usize)>,
    redo: Vec<(T, usize)>,
    budget: usize,
}

impl<T: Weighed> History<T> {
    /// An empty history that keeps at most `budget` bytes of steps (and at least the newest).
    #[must_use]
    pub fn new(budget: usize) -> Self {
        Self {
            undo: Vec::new(),
            redo: Vec::new(),
            budget,
        }
    }

    /// Keeps `before` (the state before a change just made) as the newest undo step; the steps
    /// undone before are gone.
    pub fn push(&mut self, before: T) {
        self.redo.clear();
        self.keep(before);
    }

    /// Keeps `before` as the newest undo step, dropping the oldest past the caps.
    fn keep(&mut self, before: T) {
        let size = before.bytes();
        self.undo.push((before, size));
        let mut total: usize = self.undo.iter().chain(&self.redo).map(|(_, b)| b).sum();
        let mut drop = 0;
        while self.undo.len() - drop > 1
            && (self.undo.len() - drop > HISTORY_LIMIT || total > self.budget)
        {
            total -= self.undo[drop].1;
            drop += 1;
        }
        self.undo.drain(..drop);
    }

    /// The state to go back to from `now` (which becomes a step to redo), if there is one.
    pub fn undo(&mut self, now: T) -> Option<T> {
        let (before, _) = self.undo.pop()?;
        let size = now.bytes();
        self.redo.push((now, size));
        Some(before)
    }

    /// The state to go forward to from `now` (which becomes a step to undo), if there is one.
    pub fn redo(&mut self, now: T) -> Option<T> {
        let (after, _) = self.redo.pop()?;
        self.keep(now);
        Some(after)
    }

    /// Whether there is a step to undo.
    #[must_use]
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether there is an undone step to redo.
    #[must_use]
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Forgets every step.
    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }

    /// The bytes the steps hold.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.undo.iter().chain(&self.redo).map(|(_, b)| b).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[derive(Clone, Debug, PartialEq)]
    struct State(u32, usize);

    impl Weighed for State {
        fn bytes(&self) -> usize {
            self.1
        }
    }

    #[test]
    fn undo_and_redo_walk_the_steps_and_a_new_change_drops_the_redo() {
        let mut h = History::new(1000);
        assert!(!h.can_undo());
        h.push(State(0, 1));
        h.push(State(1, 1));
        assert_eq!(h.undo(State(2, 1)), Some(State(1, 1)));
        assert_eq!(h.undo(State(1, 1)), Some(State(0, 1)));
        assert_eq!(h.undo(State(0, 1)), None, "nothing before the first");
        assert!(h.can_redo());
        assert_eq!(h.redo(State(0, 1)), Some(State(1, 1)));
        h.push(State(1, 1));
        assert!(!h.can_redo(), "a new change drops what was undone");
    }

    #[test]
    fn the_oldest_steps_go_past_the_byte_budget_and_the_newest_stays() {
        let mut h = History::new(100);
        for k in 0..10 {
            h.push(State(k, 30));
        }
        assert!(h.bytes() <= 100, "{}", h.bytes());
        assert_eq!(h.undo(State(10, 30)), Some(State(9, 30)));
        let mut huge = History::new(100);
        huge.push(State(0, 1_000));
        assert_eq!(
            huge.undo(State(1, 1)),
            Some(State(0, 1_000)),
            "the newest stays"
        );
        let mut many = History::new(usize::MAX);
        for k in 0..(HISTORY_LIMIT as u32 + 20) {
            many.push(State(k, 1));
        }
        assert_eq!(many.bytes(), HISTORY_LIMIT);
    }
}
