//! The `model` target: model files of every kind, read as JSON, validated and built.

use bezsolid_core::link::{self, LinkError};
use bezsolid_core::model::{
    EscOperand, FORMAT, MeshSpec, ModelFile, ModelSolid, SolidSpec, VERSION,
};
use bezsolid_core::tree::ModelTree;

/// Reads the bytes as a model file (JSON), and checks what reads.
///
/// What reads must write back to JSON that reads to the same model, bit for bit; be built as its
/// kind says: a patch or volume solid ([`ModelFile::to_solid`], which must give back its own
/// file), a free-form model ([`ModelFile::to_boolean`]: the meshes validated and made into chains)
/// or a script ([`ModelFile::to_script`], then run as the `plasm` target runs it); and travel
/// through a share link (when it fits in one), which carries the solid but not the header: a valid
/// solid unchanged, an invalid one still invalid.
///
/// # Panics
///
/// On a bug: a failed round trip, a solid that does not give back its file, or any panic in the
/// reader, the validation, the builders or the script's run.
pub fn model(data: &[u8]) {
    let Ok(file) = serde_json::from_slice::<ModelFile>(data) else {
        return;
    };
    let json = serde_json::to_string(&file).expect("a model file that reads writes back");
    let back: ModelFile = serde_json::from_str(&json)
        .unwrap_or_else(|e| panic!("a written model file does not read ({e}): {json}"));
    assert!(
        same_file(&back, &file),
        "JSON round trip changed the model:\n{json}"
    );
    let valid = check_model(&file);
    let header = file.format == FORMAT && file.version == VERSION;
    let solid_valid = if header {
        valid
    } else {
        check_model(&ModelFile {
            format: FORMAT.into(),
            version: VERSION,
            solid: file.solid.clone(),
        })
    };
    match link::encode(&file) {
        Ok(text) => {
            let back = link::decode_file(&text)
                .unwrap_or_else(|e| panic!("the model's link does not open ({e}): {text}"));
            // An invalid solid may come back spelt otherwise (an unknown name as "unknown", a
            // missing mesh as an empty one).
            if solid_valid {
                assert!(
                    same_solid(&back.solid, &file.solid),
                    "the model's link opens to another model:\n{back:?}"
                );
            } else {
                assert!(
                    !check_model(&back),
                    "an invalid model is valid through its link:\n{back:?}"
                );
            }
        }
        Err(LinkError::TooLong { .. }) => {}
        // A tree that breaks a rule a link's layout holds to (a free-form model inside it, a blend
        // of three nodes, too many nodes) is refused by the encoder as by validation.
        Err(LinkError::Model(_)) if file.to_tree().is_err() => {}
        Err(e) => panic!("a model that reads does not encode: {e}"),
    }
}

/// Builds a model file as its kind says, checking what the builders promise; whether it is valid
/// (a Bézier solid, a free-form model or a script that [`ModelFile`] accepts).
pub(crate) fn check_model(file: &ModelFile) -> bool {
    let mut valid = false;
    if let Ok(solid) = file.to_solid() {
        let again = match &solid {
            ModelSolid::Patch(s) => ModelFile::from_solid2(s),
            ModelSolid::Volume(s) => ModelFile::from_solid3(s),
        };
        assert!(
            same_file(&again, file),
            "a solid does not give back its model file:\n{again:?}\nfrom\n{file:?}"
        );
        valid = true;
    }
    if let Ok(boolean) = file.to_boolean() {
        assert!(
            matches!(file.solid, SolidSpec::Esc { .. }),
            "a free-form model from another kind"
        );
        for solid in &boolean.solids {
            let (lo, hi) = solid.bounds();
            assert!(
                lo.is_finite() && hi.is_finite() && lo.cmple(hi).all(),
                "a free-form solid's bounds {lo} .. {hi}"
            );
        }
        // The expression is written back as the same expression, whatever form the file had.
        if let SolidSpec::Esc { operands, .. } = &file.solid {
            let again = ModelFile::from_esc_expr(&boolean.expr, operands.clone());
            let expr = again.to_boolean().map(|b| b.expr);
            assert_eq!(expr.as_ref(), Ok(&boolean.expr), "{again:?}");
            let mut stats = bezsolid_core::esc::Stats::default();
            let v = boolean.value(glam::DVec3::new(0.1, -0.2, 0.3), &mut stats);
            assert!(
                v == 0 || v == 1,
                "a normal chain's value is 0 or 1, not {v}"
            );
        }
        valid = true;
    }
    if let Ok(tree) = file.to_tree() {
        // Evaluation of any valid tree is total: a number at every point (NaN only from a net
        // whose values overflow, which validation refuses).
        let probe = |tree_f: &dyn Fn([f64; 3]) -> f64| {
            for p in [[0.0, 0.0, 0.0], [0.5, -0.25, 1.0], [1e3, -1e3, 1e-3]] {
                let _ = tree_f(p);
            }
        };
        match &tree {
            ModelTree::Plane(t) => {
                probe(&|p| t.f(glam::DVec2::new(p[0], p[1])));
                // A bounded tree contours (an unbounded one says so), coarsely.
                if t.bounds().is_some() {
                    t.contour(8, 1e-9, None)
                        .expect("a bounded 2D tree contours");
                }
            }
            ModelTree::Space(t) => {
                probe(&|p| t.f(glam::DVec3::from_array(p)));
                // A bounded tree meshes closed, coarsely; any tree meshes within a box.
                // A solid finer than so coarse a grid says so, with an inside point.
                if let Some((lo, hi)) = t.bounds() {
                    let mesh = match t.polygonize(6, 1e-9, None) {
                        Err(bezsolid_core::tree::TreeMeshError::Lost { at, .. }) => {
                            assert!(t.f(glam::DVec3::from_array(at)) > 0.0, "lost at {at:?}");
                            None
                        }
                        other => Some(other.expect("a bounded tree meshes")),
                    };
                    let finite = lo
                        .iter()
                        .chain(&hi)
                        .all(|v| v.is_finite() && v.abs() < 1e12);
                    if let Some(mesh) = mesh.filter(|_| finite) {
                        assert!(
                            mesh.check_closed_manifold().is_ok(),
                            "a tree's mesh is not closed"
                        );
                    }
                }
                let _ = t.polygonize(4, 1e-9, Some(([-1.0; 3], [1.0; 3])));
            }
        }
        valid = true;
    }
    if let Ok(script) = file.to_script() {
        crate::plasm::run_script(script);
        valid = true;
    }
    valid
}

/// Whether two model files are the same bit for bit (`==` on `f64` takes −0 for 0 and no NaN for
/// itself).
pub(crate) fn same_file(a: &ModelFile, b: &ModelFile) -> bool {
    a.format == b.format && a.version == b.version && same_solid(&a.solid, &b.solid)
}

fn bits<const N: usize>(a: &[[f64; N]], b: &[[f64; N]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.iter().zip(q).all(|(x, y)| x.to_bits() == y.to_bits()))
}

pub(crate) fn same_solid(a: &SolidSpec, b: &SolidSpec) -> bool {
    match (a, b) {
        (
            SolidSpec::Patch { degree, points },
            SolidSpec::Patch {
                degree: d,
                points: p,
            },
        ) => degree == d && bits(points, p),
        (
            SolidSpec::Volume { degree, points },
            SolidSpec::Volume {
                degree: d,
                points: p,
            },
        ) => degree == d && bits(points, p),
        (
            SolidSpec::Esc {
                operation,
                expression,
                operands,
            },
            SolidSpec::Esc {
                operation: o,
                expression: e,
                operands: ops,
            },
        ) => {
            operation == o
                && expression == e
                && operands.len() == ops.len()
                && operands.iter().zip(ops).all(|(x, y)| same_operand(x, y))
        }
        (SolidSpec::Plasm { script }, SolidSpec::Plasm { script: s }) => script == s,
        // Trees: `Debug` writes every number so that it reads back to the same bits (−0 as
        // `-0.0`), and every field.
        (
            SolidSpec::Patch { .. }
            | SolidSpec::Volume { .. }
            | SolidSpec::Esc { .. }
            | SolidSpec::Plasm { .. },
            _,
        ) => false,
        _ => format!("{a:?}") == format!("{b:?}"),
    }
}

fn same_operand(a: &EscOperand, b: &EscOperand) -> bool {
    let same_mesh =
        |x: &MeshSpec, y: &MeshSpec| x.triangles == y.triangles && bits(&x.positions, &y.positions);
    let bits_of = |x: Option<[f64; 3]>| x.map(|v| v.map(f64::to_bits));
    a.example == b.example
        && a.name == b.name
        && bits(&[a.offset], &[b.offset])
        && bits_of(a.rotate) == bits_of(b.rotate)
        && bits_of(a.scale) == bits_of(b.scale)
        && a.crease.map(f64::to_bits) == b.crease.map(f64::to_bits)
        && match (&a.mesh, &b.mesh) {
            (None, None) => true,
            (Some(x), Some(y)) => same_mesh(x, y),
            _ => false,
        }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_file_tells_negative_zero_and_nan_apart() {
        let patch = |x: f64| ModelFile {
            format: "bezsolid".into(),
            version: 1,
            solid: SolidSpec::Patch {
                degree: [1, 1],
                points: vec![[x, 0.0, 0.0]; 4],
            },
        };
        assert!(same_file(&patch(f64::NAN), &patch(f64::NAN)));
        assert!(!same_file(&patch(0.0), &patch(-0.0)));
        assert!(same_file(&patch(0.5), &patch(0.5)));
        assert!(!same_file(&patch(0.5), &ModelFile::from_plasm("1;")));
    }
}
