//! BENCHMARKS.md's text from the rows: the heading and the machine, the targets (unless
//! `--quick`), one table per case, and the notes.

use std::fmt::Write as _;

use super::{Measured, machine, targets};

pub(super) fn report(measured: &Measured<'_>, quick: bool) -> String {
    let Measured {
        native,
        wasm,
        scalar,
    } = *measured;
    let mut s = String::new();
    let _ = writeln!(s, "# Benchmarks\n");
    let _ = writeln!(
        s,
        "Written by `cargo xtask bench`{}; every figure below comes from one run of it, native and wasm \
         (in node) on the same machine, peers in the same process as ours. Times are medians of \
         repeated runs (`runs`). Machine: {}\n",
        if quick { " --quick" } else { "" },
        machine()
    );
    let _ = writeln!(
        s,
        "The solid is a degree-(4, 4, 4) volume over [0, 1]³: a ball with rippled control values \
         (`bezsolid_bench::bench_solid`). `n` is samples per axis for evaluation and cells per axis \
         for meshing.\n"
    );
    if !quick {
        targets::meshing_targets(&mut s, native, wasm, scalar);
        targets::space_mapping_targets(&mut s, native, wasm);
        targets::folded_targets(&mut s, native);
        targets::free_form_targets(&mut s, native, wasm);
        targets::plasm_section(&mut s, native, wasm);
        targets::tree_targets(&mut s, native, wasm);
    }
    let mut cases: Vec<&str> = Vec::new();
    for r in native {
        if !cases.contains(&r.case.as_str()) {
            cases.push(&r.case);
        }
    }
    for case in cases {
        let eval = case.contains("grid evaluation")
            || case.starts_with("inverse map")
            || case.starts_with("point-in-solid")
            || case.starts_with("plasm: Script 4.4")
            || case.starts_with("HyperFun export");
        let _ = writeln!(s, "## {case}\n");
        let extra = if case.starts_with("point-in-solid") {
            "queries/s"
        } else if case.starts_with("point mesh") {
            "points"
        } else if eval {
            "points/s"
        } else if case.starts_with("contour") {
            "vertices"
        } else if case.starts_with("plasm: run") {
            "cells made"
        } else if case.starts_with("build the inverse map") {
            "certified injective (1 = yes)"
        } else {
            "triangles"
        };
        let _ = writeln!(
            s,
            "| who | n | native ms | wasm ms | wasm / native | {extra} | vs bezsolid native | runs |"
        );
        let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|");
        for r in native.iter().filter(|r| r.case == case) {
            let ours = native
                .iter()
                .find(|o| o.case == case && o.n == r.n && o.who.starts_with("bezsolid"));
            let w = wasm
                .iter()
                .find(|o| o.case == case && o.n == r.n && o.who == r.who);
            let (wasm_ms, ratio) = w.map_or(("–".to_owned(), "–".to_owned()), |w| {
                (format!("{:.2}", w.ms), format!("{:.2}×", w.ms / r.ms))
            });
            let versus = match ours {
                Some(o) if !r.who.starts_with("bezsolid") => {
                    format!("{:.2}× our time", r.ms / o.ms)
                }
                _ => "–".to_owned(),
            };
            let extra = if eval && r.extra < 1e7 {
                format!("{:.3} M", r.extra / 1e6)
            } else if eval {
                format!("{:.0} M", r.extra / 1e6)
            } else {
                format!("{:.0}", r.extra)
            };
            let _ = writeln!(
                s,
                "| {} | {} | {:.2} | {wasm_ms} | {ratio} | {extra} | {versus} | {} |",
                r.who, r.n, r.ms, r.runs
            );
        }
        let _ = writeln!(s);
        for r in native
            .iter()
            .filter(|r| r.case == case && !r.note.is_empty())
        {
            let _ = writeln!(s, "- {} (native, n = {}): {}", r.who, r.n, r.note);
            if let Some(w) = wasm
                .iter()
                .find(|w| w.case == case && w.who == r.who && w.n == r.n && w.note != r.note)
            {
                let _ = writeln!(s, "- {} (wasm, n = {}): {}", w.who, w.n, w.note);
            }
        }
        if native.iter().any(|r| r.case == case && !r.note.is_empty()) {
            let _ = writeln!(s);
        }
    }
    let _ = writeln!(
        s,
        "Notes: fidget meshes adaptively (its octree merges cells where the fit allows), so its triangle \
         counts are not comparable with a uniform mesher's; compare time at equal resolution. Its times \
         include evaluating the polynomial, so compare them with our `polygonize` rows. \
         fast-surface-nets meshes the same f32 copy of the array our meshing step reads. Peers run \
         natively only."
    );
    s
}
