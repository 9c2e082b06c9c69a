//! The memory budget of a run, measured by the allocator: every script in `tests/hostile` once
//! held hundreds of megabytes to gigabytes before the step limit stopped it (or, reserving room
//! for results in recursion, before the call limit did); now each ends with the memory limit's
//! error, at its place, having allocated at most the budget (256 MiB) and a little slack for
//! what a built-in copies and drops within a step. The paper's examples stay small, and a script
//! that builds and drops large values over and over, more than the budget in all, is not refused.

use std::sync::{Mutex, PoisonError};

use bezsolid_plasm::{ErrorKind, Interp, Run, scripts};
use peak_alloc::PeakAlloc;

#[global_allocator]
static ALLOC: PeakAlloc = PeakAlloc;

/// The allocator's counts are the process's: the tests that measure run one at a time.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const MIB: usize = 1 << 20;

/// The most a hostile script may allocate at once: the budget, and the slack of what is not
/// counted (a built-in's copies, the parsed script, the run's own records).
const MOST: usize = 300 * MIB;

/// Runs `src` on a fresh interpreter: the run, with its values dropped, and the most bytes
/// allocated at once beyond what was allocated before.
fn measured(src: &str) -> (Run, usize) {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(PoisonError::into_inner);
    let before = ALLOC.current_usage();
    ALLOC.reset_peak_usage();
    let mut run = Interp::new().run(src);
    let peak = ALLOC.peak_usage().saturating_sub(before);
    run.shown.clear();
    (run, peak)
}

/// A hostile script ends with the memory limit's error at `(line, column)` (where its budget
/// runs out), within [`MOST`] bytes.
fn refused(src: &str, line: u32, col: u32) {
    let (run, peak) = measured(src);
    let e = run.error.expect("the run fails");
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    assert!(
        e.message
            .starts_with("the script builds more than 256 MiB of values held at once")
            && e.message.contains("memory"),
        "{e}"
    );
    assert_eq!((e.span.line, e.span.col), (line, col), "{e}");
    assert!(
        peak < MOST,
        "{} MiB allocated at once, {} MiB counted",
        peak / MIB,
        run.memory / MIB as u64
    );
    assert!(run.memory <= 256 * MIB as u64);
}

macro_rules! hostile {
    ($($name:ident $file:literal ($line:literal, $col:literal),)*) => {$(
        #[test]
        fn $name() {
            refused(include_str!(concat!("hostile/", $file)), $line, $col);
        }
    )*};
}

hostile! {
    // 16 ranges of a million numbers (16 MB each) fit; the 17th does not.
    thirty_ranges_held_by_names "ranges.psm" (18, 12),
    thirty_ranges_in_one_sequence "ranges-in-a-sequence.psm" (2, 196),
    sequences_doubled_by_cat_then_copied "cat-doubling.psm" (27, 11),
    // A million pairs are 90 MB: the third DISTL does not fit.
    a_million_pairs_per_distl "distl.psm" (5, 10),
    a_million_sequences_per_trans "trans.psm" (5, 10),
    // A million points of 16 coordinates are 136 MB with their cells: one fits, not two.
    a_million_points_of_16_coordinates_per_map "map-16d.psm" (5, 10),
    products_of_32_coordinates "products-32d.psm" (4, 12),
    // Each level of the recursion reserved 16 MB for its results before the first came.
    cons_reserving_room_in_recursion "cons-recursion.psm" (2, 21),
    sum_reserving_room_in_recursion "lift-recursion.psm" (2, 21),
}

#[test]
fn the_papers_examples_stay_small() {
    for example in scripts::EXAMPLES {
        let (run, peak) = measured(&example.source());
        assert!(run.error.is_none(), "{}: {:?}", example.id, run.error);
        assert!(
            peak < 2 * MIB && run.memory < MIB as u64,
            "{}: {} KiB allocated at once, {} KiB counted",
            example.id,
            peak >> 10,
            run.memory >> 10
        );
    }
}

#[test]
fn memory_built_and_dropped_over_and_over_is_not_refused() {
    // Eight times a million pairs (90 MB), 720 MB in all, each dropped when counted.
    let src = "DEF pairs (n::IsNat) = LEN:(DISTL:<n, 1..1000000>);\n+:(AA:pairs:(1..8));";
    let (run, peak) = measured(src);
    assert!(run.error.is_none(), "{:?}", run.error);
    assert!(peak < MOST && run.memory < 128 * MIB as u64);
}
