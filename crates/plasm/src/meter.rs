//! The memory meter: the bytes that values hold, counted as they are built and credited as they
//! are dropped, so that a run can be held to a budget of memory as the step limit holds it to a
//! budget of work.
//!
//! What is counted is the heap storage of the values, in the sizes that Rust asks the allocator
//! for, plus [`BLOCK`] bytes for each block that it gives (its header and rounding): a sequence
//! is its `Rc` (two counts and the vector's header) and its items' capacity, 16 bytes each; a
//! function is its `Rc` and the capacity of its arguments; a complex is its `Rc`, its
//! coordinates (8 bytes each) and its point indices (4 bytes each). Numbers and truth values live
//! inside the items that hold them. The interpreter adds, for as long as it holds them, the
//! buffers that it fills while the script runs (the results of `AA` or of `CONS` on their way,
//! the parameters and `WHERE` slots of the calls under way, `MAP`'s points and compiled map).
//!
//! Not counted: the parsed script (bounded by the source limit), and copies that a built-in
//! makes and drops before the script takes another step (the numbers of `+:<…>`, the point of
//! `IsPoint`), each at most a sequence's worth (1 M items).
//!
//! The count is per thread (values hold `Rc`s, so they never leave their thread), and a run
//! measures what it holds against the count at its start: what earlier runs left alive is not
//! its own, and what it frees of theirs is credited to it.

use std::cell::Cell;

thread_local! {
    /// Bytes held now by the values of this thread, charged and not yet credited.
    static LIVE: Cell<i64> = const { Cell::new(0) };
}

/// Bytes held now by the values (and the interpreter's buffers) of this thread.
pub(crate) fn live() -> i64 {
    LIVE.with(Cell::get)
}

/// Counts `bytes` as held.
pub(crate) fn charge(bytes: usize) {
    if bytes > 0 {
        LIVE.with(|l| l.set(l.get() + bytes as i64));
    }
}

/// Counts `bytes` as given back.
pub(crate) fn credit(bytes: usize) {
    if bytes > 0 {
        LIVE.with(|l| l.set(l.get() - bytes as i64));
    }
}

/// What an allocator adds to each block it gives, counted with the block: a header and the
/// rounding up to its alignment, 8 to 16 bytes in glibc's `malloc` and in `dlmalloc` (Rust's
/// allocator on wasm32). Small blocks are most of many a script's memory: a sequence of one item
/// asks for blocks of 40 and 16 bytes, and glibc gives 48 and 32.
pub(crate) const BLOCK: usize = 2 * size_of::<usize>();

/// Bytes of a heap block of a `T` behind an `Rc`: the strong and weak counts, and the `T`.
pub(crate) const fn rc_bytes<T>() -> usize {
    BLOCK + 2 * size_of::<usize>() + size_of::<T>()
}

/// Bytes of a vector's buffer of `capacity` items of `T` (none for no items: an empty vector
/// has no block).
pub(crate) const fn buffer_bytes<T>(capacity: usize) -> usize {
    if capacity == 0 {
        0
    } else {
        BLOCK.saturating_add(capacity.saturating_mul(size_of::<T>()))
    }
}

/// A charge held for as long as it lives, and credited when it is dropped: the bytes of a buffer
/// that is not (yet) a value, or of a complex.
#[derive(Debug, Default)]
pub(crate) struct Charge(usize);

impl Charge {
    /// Charges `bytes`.
    pub(crate) fn new(bytes: usize) -> Charge {
        charge(bytes);
        Charge(bytes)
    }

    /// Holds `bytes` from now on instead of what it held.
    pub(crate) fn set(&mut self, bytes: usize) {
        charge(bytes);
        credit(self.0);
        self.0 = bytes;
    }
}

impl Clone for Charge {
    /// A copy of what it counts is counted again.
    fn clone(&self) -> Charge {
        Charge::new(self.0)
    }
}

impl Drop for Charge {
    fn drop(&mut self) {
        credit(self.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charge_is_credited_when_dropped_and_copies_count_again() {
        let start = live();
        let mut a = Charge::new(100);
        assert_eq!(live() - start, 100);
        let b = a.clone();
        assert_eq!(live() - start, 200);
        a.set(40);
        assert_eq!(live() - start, 140);
        drop(b);
        drop(a);
        assert_eq!(live(), start);
    }
}
