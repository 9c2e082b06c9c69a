//! Every preset's export read by the strict reader ([`super::read`], HyperFun's grammar and
//! evaluation) agrees with `eval` at random points in and around the solid, within a bounded
//! work per point.

use glam::{DVec2, DVec3};

use super::read::Program;
use super::{solid2_hf, solid3_hf};
use crate::model::ModelSolid;
use crate::presets::Preset;
use crate::testutil::Rng;

/// The most operations of the reader a point of a preset's export may take on average: under a
/// millisecond in HyperFun's own interpreter, which took 3.3–3.7 ns per operation of this reader
/// on these files (the chair: 195,000 operations, 0.68 ms a point; the knot: 51,000, 0.17 ms).
const MOST_OPERATIONS: u64 = 250_000;

#[test]
fn every_preset_exports_what_hyperfun_reads_and_evaluates_as_eval() {
    let mut rng = Rng::new(42);
    for preset in Preset::ALL {
        let solid = preset.solid();
        let text = match &solid {
            ModelSolid::Patch(s) => solid2_hf(s),
            ModelSolid::Volume(s) => solid3_hf(s),
        }
        .unwrap();
        let program = Program::parse(&text)
            .unwrap_or_else(|e| panic!("{preset:?}: HyperFun refuses its export: {e}"));
        let mut run = program.evaluator();
        let (lo, hi) = match &solid {
            ModelSolid::Patch(s) => {
                let (lo, hi) = net_box(s);
                (
                    DVec3::new(lo[0], lo[1], -1.0),
                    DVec3::new(hi[0], hi[1], 1.0),
                )
            }
            ModelSolid::Volume(s) => {
                let (lo, hi) = net_box(s);
                (DVec3::from_array(lo), DVec3::from_array(hi))
            }
        };
        let (mut operations, mut apart) = (0, 0);
        const POINTS: usize = 300;
        for _ in 0..POINTS {
            let t = DVec3::new(
                rng.range(-0.3, 1.3),
                rng.range(-0.3, 1.3),
                rng.range(-0.3, 1.3),
            );
            let p = lo + (hi - lo) * t;
            let got = run
                .eval(&p.to_array(), &[])
                .unwrap_or_else(|e| panic!("{preset:?} at {p}: {e}"));
            operations += run.operations();
            let want = match &solid {
                ModelSolid::Patch(s) => s.f(DVec2::new(p.x, p.y)),
                ModelSolid::Volume(s) => s.f(p),
            };
            if (got - want).abs() <= 1e-9 * want.abs().max(1.0) {
                continue;
            }
            // Outside the image, where the continuation's root sits far past the box, its
            // polynomial's terms cancel: Newton may settle there under one rounding and not the
            // other, which then takes the spline guess. Both are negative.
            assert!(
                got < 0.0 && want < 0.0,
                "{preset:?} at {p}: HyperFun {got}, eval {want}"
            );
            apart += 1;
        }
        assert!(
            apart * 50 <= POINTS,
            "{preset:?}: {apart} of {POINTS} points apart"
        );
        let mean = operations / POINTS as u64;
        assert!(
            mean <= MOST_OPERATIONS,
            "{preset:?}: {mean} operations a point, more than {MOST_OPERATIONS}"
        );
    }
}

/// The box of a solid's control points (which holds the solid).
fn net_box<const D: usize>(s: &crate::solid::Solid<D>) -> ([f64; D], [f64; D])
where
    crate::dim::Dim<D>: crate::dim::Dimension<D>,
{
    use crate::dim::{Dim, Dimension};
    s.net().points().iter().fold(
        ([f64::INFINITY; D], [f64::NEG_INFINITY; D]),
        |(mut lo, mut hi), &c| {
            let (x, _) = Dim::<D>::split(c);
            for k in 0..D {
                lo[k] = lo[k].min(x[k]);
                hi[k] = hi[k].max(x[k]);
            }
            (lo, hi)
        },
    )
}

#[cfg(feature = "link")]
#[test]
fn an_export_carries_its_model_back_exactly() {
    use crate::model::ModelFile;
    for preset in Preset::ALL {
        let (text, file) = match preset.solid() {
            ModelSolid::Patch(s) => (solid2_hf(&s).unwrap(), ModelFile::from_solid2(&s)),
            ModelSolid::Volume(s) => (solid3_hf(&s).unwrap(), ModelFile::from_solid3(&s)),
        };
        let back = super::model_of(&text)
            .unwrap_or_else(|| panic!("{preset:?}: no model carried"))
            .unwrap();
        assert_eq!(back, file, "{preset:?}");
        // HyperFun takes the comments: each within its scanner's 256 characters.
        assert!(
            text.lines()
                .filter(|l| l.trim_start().starts_with("--"))
                .all(|l| l.len() < 256),
            "{preset:?}"
        );
        Program::parse(&text).unwrap();
    }
    // A file written for HyperFun carries none; a carried link edited by hand is an error.
    assert!(super::model_of("my_model(x[3], a[1]) { my_model = 1; }").is_none());
    let text = solid3_hf(&match Preset::Blob.solid() {
        ModelSolid::Volume(s) => s,
        ModelSolid::Patch(_) => unreachable!(),
    })
    .unwrap();
    // The link cut short: its last characters dropped.
    let last = text
        .lines()
        .rfind(|l| l.starts_with(super::MODEL_MARK))
        .unwrap();
    let broken = text.replacen(last, &last[..last.len() - 6], 1);
    assert!(super::model_of(&broken).unwrap().is_err());
}
