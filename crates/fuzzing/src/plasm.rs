//! The `plasm` target: the PLaSM parser and evaluator under their limits.

use std::fmt::Write as _;

use bezsolid_plasm::mesh::{Geometry, write_obj};
use bezsolid_plasm::{Complex, Interp, Limits, Span};

/// The step limit of a run here: a twentieth of [`Limits::default`]'s 20 M (about 50 ms instead of
/// a second in a release build), so that a campaign spends its time on many inputs rather than on
/// the few that run to the limit; every other limit is the default. The limits bound a run by
/// counting, so what a smaller budget cannot reach is more of the same work.
pub const PLASM_STEPS: u64 = 1_000_000;

/// The most points and cells of a run's results that are made into geometry and OBJ text here.
/// The writers take about 1.3 µs a cell, against some 0.03 µs a cell for a product of domains
/// that makes them (524 k cells: 14 ms to run, 1.3 s to draw and write), so past this a campaign
/// would spend its time writing; the writers' code is the same at every size.
const MAX_DRAWN: usize = 100_000;

/// Runs the bytes as a PLaSM script (invalid UTF-8 replaced by U+FFFD) with [`PLASM_STEPS`], and
/// checks the run.
///
/// - An error's place and every warning's are in the source: `start ≤ end ≤ len`, on character
///   boundaries, with the line and column (in characters, from 1) of `start`.
/// - Every point of every complex a top-level expression gives is finite (a result that is not a
///   finite number is an error of the run).
/// - The values print, and the complexes become the geometry and the OBJ text the page and the
///   command line make of them (up to 100,000 points and cells in all).
///
/// # Panics
///
/// On a bug: a broken promise above, or any panic (an overflow of the stack included) in the
/// parser, the evaluator or the writers.
pub fn plasm(data: &[u8]) {
    run_script(&String::from_utf8_lossy(data));
}

/// Runs a script as [`plasm()`] does.
pub(crate) fn run_script(src: &str) {
    let mut interp = Interp::with_limits(Limits {
        steps: PLASM_STEPS,
        ..Limits::default()
    });
    let run = interp.run(src);
    if let Some(e) = &run.error {
        check_span(src, e.span, &e.to_string());
    }
    for w in &run.warnings {
        check_span(src, w.span, &w.to_string());
    }
    let mut printed = String::new();
    for shown in &run.shown {
        check_span(src, shown.span, "a value");
        let _ = write!(printed, "{}", shown.value);
        printed.clear();
        if let Some(c) = shown.value.as_pol() {
            for i in 0..c.point_count() {
                assert!(
                    c.point(i).iter().all(|x| x.is_finite()),
                    "point {i} of a complex is not finite: {:?}",
                    c.point(i)
                );
            }
        }
    }
    let complexes: Vec<&Complex> = run.shown.iter().filter_map(|s| s.value.as_pol()).collect();
    let size: usize = complexes
        .iter()
        .map(|c| c.point_count() + c.cell_count())
        .sum();
    if size <= MAX_DRAWN {
        let geometry = Geometry::of(complexes.iter().copied());
        let _ = geometry.bounds();
        let _ = write_obj(complexes.iter().copied());
    }
}

/// `span` is a place in `src` whose line and column are those of its start.
fn check_span(src: &str, span: Span, what: &str) {
    let (start, end) = (span.start as usize, span.end as usize);
    assert!(
        start <= end && end <= src.len(),
        "{what}: span {start}..{end} is not in the {} bytes of source",
        src.len()
    );
    assert!(
        src.is_char_boundary(start) && src.is_char_boundary(end),
        "{what}: span {start}..{end} splits a character"
    );
    let before = &src[..start];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |i| i + 1)..]
        .chars()
        .count()
        + 1;
    assert_eq!(
        (span.line as usize, span.col as usize),
        (line, col),
        "{what}: the line and column are not those of byte {start}"
    );
}
