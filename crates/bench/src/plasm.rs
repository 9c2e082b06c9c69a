//! The PLaSM cases: each of the paper's examples run whole (parse, evaluate, MAP), and
//! Script 4.4's surface sampled on a grid three ways: by the interpreter's `MAP`, by `core::blend`'s
//! closures (the same transfinite blend, compiled), and as the equal tensor-product patch.

use bezsolid_core::BezierCurve;
use bezsolid_core::blend::{self, Fun, Handle, patch_from_curves};
use bezsolid_plasm::{Interp, scripts};
use glam::DVec3;

use crate::{Clock, Row, time};

/// Script 4.4's curves.
fn curves() -> Vec<Vec<[f64; 3]>> {
    vec![
        vec![[0., 0., 0.], [10., 0., 0.]],
        vec![[0., 2., 0.], [8., 3., 0.], [9., 2., 0.]],
        vec![[0., 4., 1.], [7., 5., -1.], [8., 5., 1.], [12., 4., 0.]],
        vec![[0., 6., 0.], [9., 6., 3.], [10., 6., -1.]],
    ]
}

/// The cases.
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 500.0 };
    let mut rows = Vec::new();
    for e in scripts::EXAMPLES {
        let source = e.source();
        let (ms, runs, (cells, steps)) = time(clock, budget, || {
            let run = Interp::new().run(&source);
            assert!(run.error.is_none(), "example {} runs", e.id);
            let cells: usize = run
                .shown
                .iter()
                .filter_map(|s| s.value.as_pol())
                .map(bezsolid_plasm::Complex::cell_count)
                .sum();
            (cells, run.steps)
        });
        rows.push(Row {
            case: "plasm: run a paper example (parse, evaluate, MAP)".into(),
            who: format!("bezsolid: Script {}", e.id),
            n: cells,
            ms,
            runs,
            extra: cells as f64,
            note: format!("{steps} steps"),
        });
    }
    let sizes: &[usize] = if quick { &[20] } else { &[20, 100] };
    let defs = [scripts::S4_2.text, scripts::S4_3.text, scripts::S4_4.text].concat();
    for &n in sizes {
        let case = "plasm: Script 4.4's surface on an n × n grid of vertices";
        let points = ((n + 1) * (n + 1)) as f64;
        // The interpreter: the script's own MAP, at n.
        let script = format!("{defs}\nMAP:Surf1:(Intervals:1:{n} * Intervals:1:{n});\n");
        let mut interp = Interp::new();
        let (ms, runs, _) = time(clock, budget, || {
            let run = interp.run(&script);
            assert!(run.error.is_none());
            run.shown.len()
        });
        rows.push(Row {
            case: case.into(),
            who: "bezsolid: PLaSM interpreter (the whole script)".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: String::new(),
        });
        // core::blend: Bezier:S1 per curve, then Bezier:S2 of the curves, as closures.
        let handles: Vec<Handle> = curves()
            .iter()
            .map(|c| {
                let hs: Vec<Handle> = c.iter().map(|p| Handle::point(p)).collect();
                Handle::Map(blend::bezier(&Fun::select(0), &hs).unwrap_or_default())
            })
            .collect();
        let surface = blend::bezier(&Fun::select(1), &handles).unwrap_or_default();
        let ts: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
        let (ms, runs, _) = time(clock, budget, || {
            let mut acc = 0.0;
            for &u in &ts {
                for &v in &ts {
                    acc += blend::eval(&surface, &[u, v])[2];
                }
            }
            acc
        });
        rows.push(Row {
            case: case.into(),
            who: "core::blend closures".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: String::new(),
        });
        // The tensor patch: the curves elevated to degree 3.
        let cubic: Vec<BezierCurve<DVec3>> = curves()
            .iter()
            .map(|c| {
                let mut curve =
                    BezierCurve::try_new(c.iter().map(|p| DVec3::from_array(*p)).collect())
                        .unwrap_or_else(|_| unreachable!("a valid curve"));
                while curve.degree() < 3 {
                    curve = curve
                        .elevate()
                        .unwrap_or_else(|_| unreachable!("degree 3 is allowed"));
                }
                curve
            })
            .collect();
        let patch = patch_from_curves(&cubic).unwrap_or_else(|_| unreachable!("equal degrees"));
        let (ms, runs, _) = time(clock, budget, || patch.eval_grid([&ts, &ts]).len());
        rows.push(Row {
            case: case.into(),
            who: "tensor patch, eval_grid".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: String::new(),
        });
    }
    rows
}
