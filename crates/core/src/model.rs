//! The model file (DESIGN §5): the document a user saves, shares and hands to the command line.
//!
//! ```json
//! { "format": "bezsolid", "version": 1,
//!   "solid": { "kind": "patch", "degree": [2, 2], "points": [[0.0, 0.0, -1.0], …] } }
//! ```
//!
//! - `kind: "patch"`: `degree [n, m]`, points `[x, y, ξ]`, `P_ij` at `i·(m + 1) + j`.
//! - `kind: "volume"`: `degree [n, m, l]`, points `[x, y, z, ξ]`, `P_ijk` at `(i·(m + 1) + j)·(l + 1) + k`.
//! - `kind: "esc"` (free-form): `operands`, each `{ "example": "torus", "offset": [x, y, z] }` or
//!   `{ "mesh": { "positions": [[x, y, z], …], "triangles": [[a, b, c], …] }, "offset": … }`, and
//!   how they combine: one operand alone; two with an `operation` (`union`, `intersection` or
//!   `difference`); one with the `operation` `complement`; or any number (up to
//!   [`MAX_OPERANDS`]) with an `expression` over their names, e.g. `"(A | B) - !C"` (the syntax of
//!   [`Expr::parse`](crate::esc::bool::Expr::parse)). An operand's `name` is optional: unnamed
//!   operands are `A`, `B`, `C`, … by position. An operand is placed by `offset`, and optionally
//!   `rotate` (`[rx, ry, rz]`, degrees) and `scale` (per axis, non-zero; a negative one mirrors):
//!   each point `p` goes to
//!   `offset + Rz·Ry·Rx·S·p`, as a tree's `transform` moves its solid. `crease` (degrees, 0 to 180)
//!   sets the angle between neighbouring faces past which an edge stays sharp; absent, it is 180
//!   (every edge rounded), as files written before creases were read.
//!   A mesh holds at most [`MAX_VERTICES`](crate::mesh::MAX_VERTICES) positions and
//!   [`MAX_TRIANGLES`] triangles: a reader refuses a longer list while reading it, before the rest
//!   of the file is read.
//! - `kind: "plasm"` (scripts): `script`, the text of a PLaSM script (at most
//!   [`MAX_SCRIPT_BYTES`]); what it draws is what the script's top-level expressions give.
//! - `kind: "hyperfun"` (HyperFun programs): `program`, the text of a HyperFun program (at most
//!   [`MAX_SOURCE_BYTES`](crate::hyperfun::read::MAX_SOURCE_BYTES)), read and evaluated as
//!   HyperFun's interpreter does ([`crate::hyperfun::read`]); its solid is `f > 0`. A program has
//!   no bounds of its own: `box`, `[[x0, y0, z0], [x1, y1, z1]]` (finite, each low coordinate
//!   below the high one), is the box it is drawn and meshed in; absent, it is
//!   [`DEFAULT_HYPERFUN_BOX`], `[-10, 10]³` as HyperFun's polygonizer takes by default. In a
//!   tree of many solids (3D) such a node is a leaf: `program & box`, the R-conjunction of the
//!   program's value and the box's (as a `box` node's), the program's solid within its box.
//!
//! A patch or volume has no separate box: a regular grid is recognised from the points. Readers
//! ignore fields they do not know (later kinds add fields) and reject an unknown version. With the
//! `serde` feature the types derive `Serialize` and `Deserialize` in exactly this shape.
//!
//! Submodules: `spec` (the types a file is spelled in: [`ModelFile`], [`SolidSpec`] and its
//! parts), `error` ([`ModelError`]), `read` (the `from_*` writers and `to_*` readers of a
//! [`ModelFile`], and [`ModelSolid`]), `operands` (a free-form model's operand names, expression,
//! placement and meshes) and, with `serde`, `de` (the deserializer of a [`SolidSpec`]).

mod error;
mod operands;
mod read;
mod spec;

pub use error::ModelError;
pub use operands::{COMPLEMENT, esc_expr, operand_names};
pub(crate) use read::HYPERFUN_ALONE;
pub use read::ModelSolid;
pub use spec::{CoordAxis, EscOperand, MAX_NAME_BYTES, MeshSpec, ModelFile, Rotation, SolidSpec};

use crate::mesh::MAX_TRIANGLES;

#[cfg(feature = "serde")]
mod de;

/// The value of the `format` field.
pub const FORMAT: &str = "bezsolid";
/// The crease angle of a free-form operand whose file says none: 180°, no creases, as every file
/// written before creases was read.
pub const FILE_CREASE_ANGLE: f64 = 180.0;
/// The most operands a free-form model has.
pub const MAX_OPERANDS: usize = 26;
/// The most triangles of all a free-form model's meshes together (two meshes at the cap of one).
pub const MAX_TOTAL_TRIANGLES: usize = 2 * MAX_TRIANGLES;
/// The longest name of an operand, in characters.
pub const MAX_NAME_CHARS: usize = 32;
/// The farthest a free-form operand is moved, on any axis.
pub const MAX_OFFSET: f64 = 1e9;
/// The largest scale of a free-form operand, and the inverse of the smallest.
pub const MAX_SCALE: f64 = 1e6;
/// The longest script a model file may hold, in bytes.
pub const MAX_SCRIPT_BYTES: usize = 256 * 1024;
/// The model file version this build writes and reads.
pub const VERSION: u32 = 1;
/// The box of a HyperFun program whose model file gives none (`[[x0, y0, z0], [x1, y1, z1]]`):
/// `[-10, 10]³`, the default box of HyperFun's polygonizer.
pub const DEFAULT_HYPERFUN_BOX: [[f64; 3]; 2] = [[-10.0; 3], [10.0; 3]];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::esc::bool::{Expr, Op};
    use alloc::format;
    use alloc::string::ToString;
    use alloc::vec::Vec;
    use glam::DVec3;

    use crate::esc::examples::Example;

    use crate::mesh::MAX_VERTICES;
    use crate::solid::{Solid2, Solid3, SolidError};

    use crate::tensor::PatchError;
    use alloc::vec;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn model_round_trips_solids() {
        let s2 = Solid2::fig9();
        assert_eq!(
            ModelFile::from_solid2(&s2).to_solid(),
            Ok(ModelSolid::Patch(s2))
        );
        let s3 = Solid3::regular([1, 2, 1], DVec3::ZERO, DVec3::ONE, |[i, j, k]| {
            (i + j + k) as f64 - 1.5
        })
        .unwrap();
        assert_eq!(
            ModelFile::from_solid3(&s3).to_solid(),
            Ok(ModelSolid::Volume(s3))
        );
    }

    #[test]
    fn hyperfun_programs_round_trip_through_json_with_and_without_a_box() {
        let program = "my_model(x[3], a[1]) {\n  my_model = 1 - x[1]^2; -- \"é\"\n}\n";
        let plain = ModelFile::from_hyperfun(program, None);
        let json = serde_json::to_string(&plain).unwrap();
        assert!(
            json.contains(r#""kind":"hyperfun","program":"#) && !json.contains("box"),
            "{json}"
        );
        let back: ModelFile = serde_json::from_str(&json).unwrap();
        assert_eq!(back, plain);
        assert_eq!(back.to_hyperfun(), Ok((program, DEFAULT_HYPERFUN_BOX)));
        let bounds = [[-1.0, -2.5, 0.0], [1.0, 2.5, 3.0]];
        let boxed = ModelFile::from_hyperfun(program, Some(bounds));
        let json = serde_json::to_string(&boxed).unwrap();
        assert!(
            json.contains(r#""box":[[-1.0,-2.5,0.0],[1.0,2.5,3.0]]"#),
            "{json}"
        );
        let back: ModelFile = serde_json::from_str(&json).unwrap();
        assert_eq!(back, boxed);
        assert_eq!(back.to_hyperfun(), Ok((program, bounds)));
        // As a person writes it: the box before the kind, integers, other fields ignored.
        let file: ModelFile = serde_json::from_str(
            r#"{"format": "bezsolid", "version": 1, "solid": {"box": [[0, 0, 0], [1, 2, 3]],
                "note": 1, "kind": "hyperfun", "program": "m(x[3], a[1]) { m = 1; }"}}"#,
        )
        .unwrap();
        assert_eq!(
            file.to_hyperfun(),
            Ok(("m(x[3], a[1]) { m = 1; }", [[0.0; 3], [1.0, 2.0, 3.0]]))
        );
        // Not a Bézier solid, a tree, a free-form model or a script, and said so.
        for e in [
            file.to_solid().unwrap_err(),
            file.to_tree().unwrap_err(),
            file.to_boolean().unwrap_err(),
        ] {
            assert!(e.to_string().contains("HyperFun program"), "{e}");
        }
        assert!(
            file.to_solid()
                .unwrap_err()
                .to_string()
                .contains("bezsolid mesh")
        );
        assert_eq!(
            file.to_script(),
            Err(ModelError::Kind("this model is not a PLaSM script"))
        );
        assert_eq!(
            ModelFile::from_plasm("1;").to_hyperfun(),
            Err(ModelError::Kind("this model is not a HyperFun program"))
        );
        assert!(!file.solid.is_tree());
        // Inside a tree it is a leaf.
        let tree = ModelFile::from_spec(SolidSpec::Union {
            of: vec![
                SolidSpec::Sphere {
                    center: [0.0; 3],
                    radius: 1.0,
                },
                file.solid.clone(),
            ],
        });
        assert!(tree.solid.is_tree());
        assert!(tree.to_tree().is_ok());
    }

    #[test]
    fn hyperfun_programs_with_a_bad_box_or_a_wrong_field_type_are_refused() {
        let read = |solid: &str| {
            serde_json::from_str::<ModelFile>(&format!(
                r#"{{"format": "bezsolid", "version": 1, "solid": {solid}}}"#
            ))
        };
        for (solid, says) in [
            (r#"{"kind": "hyperfun", "program": 5}"#, "expected a string"),
            (r#"{"kind": "hyperfun"}"#, "missing field `program`"),
            (
                r#"{"kind": "hyperfun", "program": "", "box": [[0, 0], [1, 1]]}"#,
                "array of length 3",
            ),
            (
                r#"{"kind": "hyperfun", "program": "", "box": [0, 0, 0, 1, 1, 1]}"#,
                "expected an array",
            ),
            (
                r#"{"kind": "hyperfun", "program": "", "box": "[-1, 1]"}"#,
                "expected an array",
            ),
        ] {
            let e = read(solid).unwrap_err().to_string();
            assert!(e.contains(says), "{solid}: {e}");
        }
        for (bounds, inverted) in [
            ("[[0, 0, 0], [1, 1, 0]]", true),
            ("[[0, 2, 0], [1, 1, 1]]", true),
            ("[[0, 0, 0], [1, 1, 1e999]]", false),
        ] {
            let solid = format!(r#"{{"kind": "hyperfun", "program": "", "box": {bounds}}}"#);
            match read(&solid) {
                Ok(file) => {
                    let e = file.to_hyperfun().unwrap_err();
                    assert!(matches!(e, ModelError::BadBox(_)), "{e:?}");
                    assert!(e.to_string().contains("low one below the high one"), "{e}");
                }
                // JSON has no infinite numbers: serde_json refuses one out of range.
                Err(e) => assert!(!inverted, "{solid}: {e}"),
            }
        }
        let e = ModelFile::from_hyperfun("", Some([[0.0; 3], [f64::NAN; 3]]))
            .to_hyperfun()
            .unwrap_err();
        assert!(matches!(e, ModelError::BadBox(_)), "{e:?}");
        // The header first.
        let mut file = ModelFile::from_hyperfun("", Some([[1.0; 3], [0.0; 3]]));
        file.version = 2;
        assert_eq!(file.to_hyperfun(), Err(ModelError::Version(2)));
    }

    #[test]
    fn free_form_meshes_past_the_count_caps_are_refused_before_anything_is_built() {
        let mesh = |positions: usize, triangles: usize| EscOperand {
            example: None,
            mesh: Some(MeshSpec {
                positions: alloc::vec![[0.0; 3]; positions],
                triangles: alloc::vec![[0, 1, 2]; triangles],
            }),
            offset: [0.0; 3],
            ..EscOperand::default()
        };
        let one = ModelFile::from_esc(None, alloc::vec![mesh(3, MAX_TRIANGLES + 1)]);
        let err = one.to_boolean().err();
        assert_eq!(
            err,
            Some(ModelError::MeshTooLarge {
                operand: 1,
                what: "triangles",
                count: MAX_TRIANGLES + 1,
                max: MAX_TRIANGLES
            })
        );
        assert_eq!(
            err.map(|e| e.to_string()).unwrap_or_default(),
            "invalid free-form model: operand 1: the mesh has 200001 triangles, more than the \
             200000 a free-form model takes"
        );
        // The second operand's counts are checked before the first operand is built.
        let two = ModelFile::from_esc(
            Some(Op::Union),
            alloc::vec![
                EscOperand::example(Example::Torus, [0.0; 3]),
                mesh(MAX_VERTICES + 1, 1),
            ],
        );
        assert_eq!(
            two.to_boolean().err(),
            Some(ModelError::MeshTooLarge {
                operand: 2,
                what: "vertices",
                count: MAX_VERTICES + 1,
                max: MAX_VERTICES
            })
        );
        // An operand on its own (the page builds them one at a time) says the same in words.
        let err = mesh(3, MAX_TRIANGLES + 1).to_mesh().unwrap_err();
        assert!(err.starts_with("the mesh has 200001 triangles"), "{err}");
        // At the caps the counts pass, and the mesh is judged as a mesh.
        let at_caps = ModelFile::from_esc(None, alloc::vec![mesh(MAX_VERTICES, 1)]);
        assert!(matches!(at_caps.to_boolean(), Err(ModelError::Esc(_))));
    }

    #[test]
    fn model_rejects_bad_header_and_nets() {
        let mut m = ModelFile::from_solid2(&Solid2::fig9());
        m.version = 2;
        assert_eq!(m.to_solid(), Err(ModelError::Version(2)));
        m.version = 1;
        m.format = "other".into();
        assert!(matches!(m.to_solid(), Err(ModelError::Format(_))));
        let short = ModelFile::new(SolidSpec::Patch {
            degree: [2, 2],
            points: alloc::vec![[0.0; 3]; 8],
        });
        assert_eq!(
            short.to_solid(),
            Err(ModelError::Solid(SolidError::Patch(
                PatchError::PointCount {
                    expected: 9,
                    got: 8
                }
            )))
        );
    }

    /// A cube `[−1, 1]³` as a model file's mesh, triangles counter-clockwise from outside.
    fn cube() -> MeshSpec {
        let (positions, triangles) = crate::testutil::box_mesh(DVec3::splat(-1.0), DVec3::ONE, 0);
        MeshSpec {
            positions: positions.iter().map(|p| p.to_array()).collect(),
            triangles,
        }
    }

    fn esc(
        operation: Option<&str>,
        expression: Option<&str>,
        operands: Vec<EscOperand>,
    ) -> ModelFile {
        ModelFile::from_spec(SolidSpec::Esc {
            operation: operation.map(Into::into),
            expression: expression.map(Into::into),
            operands,
        })
    }

    #[test]
    fn free_form_expressions_name_operands_by_letter_or_name() {
        let ex = |e: Example, x: f64| EscOperand::example(e, [x, 0.0, 0.0]);
        let three = vec![
            ex(Example::Icosphere, 0.0),
            ex(Example::Icosphere, 3.0),
            EscOperand {
                name: Some("far".into()),
                ..ex(Example::Icosphere, 6.0)
            },
        ];
        let b = esc(None, Some("A | B | far"), three.clone())
            .to_boolean()
            .unwrap();
        let mut stats = crate::esc::Stats::default();
        for x in [0.0, 3.0, 6.0] {
            assert_eq!(b.value(DVec3::new(x, 0.0, 0.0), &mut stats), 1);
        }
        assert_eq!(b.value(DVec3::new(1.5, 0.0, 0.0), &mut stats), 0);
        let b = esc(None, Some("!(A | far)"), three.clone())
            .to_boolean()
            .unwrap();
        assert_eq!(b.value(DVec3::ZERO, &mut stats), 0);
        assert_eq!(b.value(DVec3::new(3.0, 0.0, 0.0), &mut stats), 1);
        assert_eq!(b.value(DVec3::new(1.5, 0.0, 0.0), &mut stats), 1);
        // The file's text survives JSON.
        let file = esc(None, Some("(A|B) - far"), three.clone());
        let json = serde_json::to_string(&file).unwrap();
        assert!(json.contains(r#""expression":"(A|B) - far""#), "{json}");
        assert_eq!(serde_json::from_str::<ModelFile>(&json).unwrap(), file);
        // from_esc_expr writes the shortest form.
        let e = Expr::parse("A - B", &["A", "B"]).unwrap();
        let two = ModelFile::from_esc_expr(&e, three[..2].to_vec());
        assert!(
            matches!(&two.solid, SolidSpec::Esc { operation: Some(o), expression: None, .. } if o == "difference")
        );
        let e = Expr::parse("!A", &["A"]).unwrap();
        let not = ModelFile::from_esc_expr(&e, three[..1].to_vec());
        assert!(matches!(&not.solid, SolidSpec::Esc { operation: Some(o), .. } if o == COMPLEMENT));
        let e = Expr::parse("B - A", &["A", "B"]).unwrap();
        let swapped = ModelFile::from_esc_expr(&e, three[..2].to_vec());
        assert!(
            matches!(&swapped.solid, SolidSpec::Esc { expression: Some(t), .. } if t == "B - A")
        );
        assert_eq!(swapped.to_boolean().unwrap().expr, e);
    }

    #[test]
    fn free_form_models_that_say_too_much_or_too_little_are_refused() {
        let ball = || EscOperand::example(Example::Icosphere, [0.0; 3]);
        let named = |n: &str| EscOperand {
            name: Some(n.into()),
            ..ball()
        };
        let refused = |f: ModelFile, says: &str| {
            let e = f.to_boolean().unwrap_err().to_string();
            assert!(e.contains(says), "{e:?} should say {says:?}");
        };
        refused(
            esc(Some("union"), Some("A|B"), vec![ball(), ball()]),
            "not both",
        );
        refused(
            esc(None, Some("A|C"), vec![ball(), ball()]),
            "no solid is named \"C\"",
        );
        refused(esc(None, Some("A|"), vec![ball(), ball()]), "character 3");
        refused(esc(None, Some("A"), vec![]), "needs operands");
        refused(
            esc(Some("complement"), None, vec![ball(), ball()]),
            "expected 1",
        );
        refused(esc(Some("xor"), None, vec![ball(), ball()]), "complement");
        refused(
            esc(None, Some("A|B"), vec![named("B"), ball()]),
            "both named \"B\"",
        );
        refused(esc(None, Some("A"), vec![named("1x")]), "not a name");
        refused(
            esc(None, Some("A"), vec![ball(); MAX_OPERANDS + 1]),
            "at most 26",
        );
        let bad = |o: EscOperand| esc(None, None, vec![o]);
        refused(
            bad(EscOperand {
                scale: Some([1.0, 0.0, 1.0]),
                ..ball()
            }),
            "scale 0",
        );
        refused(
            bad(EscOperand {
                scale: Some([f64::NAN, 1.0, 1.0]),
                ..ball()
            }),
            "scale",
        );
        refused(
            bad(EscOperand {
                rotate: Some([f64::INFINITY, 0.0, 0.0]),
                ..ball()
            }),
            "rotation",
        );
        refused(
            bad(EscOperand {
                crease: Some(200.0),
                ..ball()
            }),
            "not 200",
        );
    }

    #[test]
    fn free_form_operands_are_rotated_scaled_and_mirrored() {
        let mut stats = crate::esc::Stats::default();
        let inside = |o: EscOperand, p: [f64; 3], stats: &mut crate::esc::Stats| {
            esc(None, None, vec![o])
                .to_boolean()
                .unwrap()
                .value(DVec3::from_array(p), stats)
                == 1
        };
        let cube = EscOperand {
            mesh: Some(cube()),
            ..EscOperand::default()
        };
        // Stretched along x to [−2, 2], then turned a quarter about z: along y.
        let long = EscOperand {
            scale: Some([2.0, 1.0, 1.0]),
            rotate: Some([0.0, 0.0, 90.0]),
            offset: [0.0, 0.0, 5.0],
            ..cube.clone()
        };
        assert!(inside(long.clone(), [0.0, 1.8, 5.0], &mut stats));
        assert!(!inside(long.clone(), [1.8, 0.0, 5.0], &mut stats));
        assert!(!inside(long, [0.0, 0.0, 0.0], &mut stats));
        // A mirror keeps the solid a solid (its triangles turned over), for meshes and examples.
        let mirrored = EscOperand {
            scale: Some([-1.0, 0.5, 1.0]),
            crease: Some(crate::esc::DEFAULT_CREASE_ANGLE),
            ..cube
        };
        assert!(inside(mirrored.clone(), [0.9, 0.4, 0.0], &mut stats));
        assert!(!inside(mirrored.clone(), [0.0, 0.55, 0.0], &mut stats));
        // Its edges are creases, kept sharp at the page's angle; 180 rounds them, and so does a
        // file that says no angle, as files written before creases did.
        assert!(!inside(mirrored.clone(), [1.02, 0.0, 0.0], &mut stats));
        let round = EscOperand {
            crease: Some(180.0),
            ..mirrored.clone()
        };
        assert!(inside(round, [1.02, 0.0, 0.0], &mut stats));
        let old = EscOperand {
            crease: None,
            ..mirrored
        };
        assert!(inside(old, [1.02, 0.0, 0.0], &mut stats));
        let ball = EscOperand {
            scale: Some([-2.0, 1.0, 1.0]),
            rotate: Some([0.0, 90.0, 0.0]),
            ..EscOperand::example(Example::Icosphere, [0.0; 3])
        };
        // x stretched to ±2, then turned about y: x goes to −z.
        assert!(inside(ball.clone(), [0.0, 0.0, 1.8], &mut stats));
        assert!(!inside(ball.clone(), [1.8, 0.0, 0.0], &mut stats));
        let mesh = ball.to_mesh().unwrap();
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            // The ellipsoid's outward normal: the gradient of x² + y² + (z/2)².
            let g = DVec3::new(p.x, p.y, p.z / 4.0).normalize();
            assert!(n.dot(g) > 0.99, "normal {n} at {p}");
        }
    }

    #[test]
    fn free_form_expressions_agree_with_ray_parity_on_the_pn_surfaces() {
        let file = esc(
            None,
            Some("!(A | wing) - C & A | (B & !C)"),
            vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand {
                    rotate: Some([0.0, 70.0, 20.0]),
                    scale: Some([0.8, 0.8, 1.4]),
                    ..EscOperand::example(Example::Torus, [0.2, 0.0, 0.3])
                },
                EscOperand {
                    scale: Some([0.6, -0.5, 0.7]),
                    ..EscOperand::example(Example::Icosphere, [0.4, 0.2, -0.1])
                },
                EscOperand {
                    name: Some("wing".into()),
                    mesh: Some(cube()),
                    scale: Some([0.3, 1.2, 0.3]),
                    ..EscOperand::default()
                },
            ],
        );
        let boolean = file.to_boolean().unwrap();
        let (lo, hi) = boolean.scene_bounds();
        let mut stats = crate::esc::Stats::default();
        let mut seen = Vec::new();
        let mut seed = 11_u64;
        let mut unit = move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1_u64 << 53) as f64
        };
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..400 {
            let q = lo + (hi - lo) * DVec3::new(unit(), unit(), unit());
            let parity = boolean
                .expr
                .value(&mut |i| boolean.solids[i].parity_value(q, &mut stats, &mut seen));
            let chain = boolean.value(q, &mut stats);
            assert_eq!(chain, parity, "at {q}");
            if chain == 1 {
                inside += 1;
            } else {
                outside += 1;
            }
        }
        assert!(
            inside > 40 && outside > 40,
            "{inside} inside, {outside} outside"
        );
    }
}
