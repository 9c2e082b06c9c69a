//! HyperFun exports evaluated: each space-mapped preset's export (its inverse map written in
//! HyperFun's loops) run by the strict reader at random points of the box around its net, beside
//! bezsolid's own evaluation of the solid at the same points. The export's target is a millisecond
//! a point in HyperFun's interpreter; the reader counts the same operations.

use bezsolid_core::Solid3;
use bezsolid_core::hyperfun::read::Program;
use bezsolid_core::hyperfun::solid3_hf;
use bezsolid_core::inverse::Method;
use bezsolid_core::model::ModelSolid;
use bezsolid_core::presets::Preset;
use glam::DVec3;

use crate::{Clock, Row, time};

/// The case's name.
pub const CASE: &str = "HyperFun export of a space-mapped preset, evaluated at random points";

/// The box around a solid's net, grown by a tenth on each side.
fn net_box(solid: &Solid3) -> (DVec3, DVec3) {
    let (lo, hi) = solid
        .net()
        .points()
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.truncate()), hi.max(p.truncate()))
        });
    let grow = (hi - lo) * 0.1;
    (lo - grow, hi + grow)
}

/// The cases.
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 500.0 };
    let count = if quick { 50 } else { 400 };
    let mut rows = Vec::new();
    for preset in Preset::ALL {
        let ModelSolid::Volume(solid) = preset.solid() else {
            continue;
        };
        if !solid.is_space_mapped() {
            continue;
        }
        let Ok(text) = solid3_hf(&solid) else {
            continue;
        };
        let Ok(program) = Program::parse(&text) else {
            continue;
        };
        let (lo, hi) = net_box(&solid);
        // A fixed sequence of points (a small linear congruential generator).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut unit = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let points: Vec<DVec3> = (0..count)
            .map(|_| lo + (hi - lo) * DVec3::new(unit(), unit(), unit()))
            .collect();
        let mut run = program.evaluator();
        let (ms, runs, ops) = time(clock, budget, || {
            let mut ops = 0u64;
            for p in &points {
                if run.eval(&p.to_array(), &[]).is_ok() {
                    ops += run.operations();
                }
            }
            ops
        });
        rows.push(Row {
            case: CASE.into(),
            who: format!("bezsolid: the strict HyperFun reader, {}", preset.name()),
            n: count,
            ms,
            runs,
            extra: count as f64 / (ms / 1000.0),
            note: format!(
                "{:.0} reader operations a point; {} bytes of HyperFun",
                ops as f64 / count as f64,
                text.len()
            ),
        });
        solid.plan(count);
        let (ms, runs, _) = time(clock, budget, || {
            points
                .iter()
                .map(|&p| solid.evaluate(p, Method::Fast).f)
                .sum::<f64>()
        });
        rows.push(Row {
            case: CASE.into(),
            who: format!("bezsolid: eval, {}", preset.name()),
            n: count,
            ms,
            runs,
            extra: count as f64 / (ms / 1000.0),
            note: String::new(),
        });
    }
    rows
}
