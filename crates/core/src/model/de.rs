//! Reading a model file's `solid` without holding more of it than it may be.
//!
//! serde's derive reads an internally tagged enum (`"kind": …` among the fields) by first copying
//! the whole object into a generic tree, whatever its size: a free-form model of a million
//! triangles took 20 times its text in memory before any cap was checked. Here the solid is read
//! field by field into its kind's types as soon as `kind` is known (writers put it first), and a
//! mesh's lists are counted while they are read ([`positions`], [`triangles`]): past
//! [`MAX_VERTICES`](crate::mesh::MAX_VERTICES) or [`MAX_TRIANGLES`](crate::mesh::MAX_TRIANGLES)
//! the file is refused at that element. Fields that come before `kind` are kept as [`Value`]s
//! (bounded by [`MAX_KEPT_VALUES`]) and read once it comes.
//!
//! What opens is what the derive opened (a test reads many solids both ways): the same fields,
//! the same defaults, unknown fields ignored, and the sequence form `["patch", degree, points]`.
//!
//! Submodules: `keys` (the `kind` names and field keys), `fields` (the fields of a kind read so
//! far, checked and built at the end), `lists` (lists capped while read) and `value` (the values
//! kept from before `kind` and read again).

use alloc::vec::Vec;
use core::fmt;

use serde::Deserialize;
use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

use super::SolidSpec;

mod fields;
mod keys;
mod lists;
mod value;

use fields::{Field, Fields};
use keys::{KINDS, Key, Kind};
use lists::piecewise_points;
pub(super) use lists::{positions, triangles};
use value::{Keep, MAX_KEPT_VALUES, Value, ValueDeserializer};

impl<'de> Deserialize<'de> for SolidSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SolidVisitor)
    }
}

struct SolidVisitor;

impl<'de> Visitor<'de> for SolidVisitor {
    type Value = SolidSpec;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a solid: an object with a \"kind\"")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SolidSpec, A::Error> {
        let mut fields: Option<Fields> = None;
        // The fields before `kind`, and how many more values may be kept.
        let mut kept: Vec<(Key, Value)> = Vec::new();
        let mut budget = MAX_KEPT_VALUES;
        while let Some(key) = map.next_key::<Key>()? {
            match (&mut fields, key) {
                (Some(_), Key::Kind) => return Err(de::Error::duplicate_field("kind")),
                (None, Key::Kind) => {
                    let mut read = Fields::new(map.next_value::<Kind>()?);
                    for (key, value) in kept.drain(..) {
                        Field {
                            fields: &mut read,
                            key,
                        }
                        .deserialize(ValueDeserializer::<A::Error>::new(value))?;
                    }
                    fields = Some(read);
                }
                (Some(read), key) => map.next_value_seed(Field { fields: read, key })?,
                (None, Key::Other) => map.next_value::<IgnoredAny>().map(drop)?,
                (None, key) => {
                    let value = map.next_value_seed(Keep {
                        budget: &mut budget,
                    })?;
                    kept.push((key, value));
                }
            }
        }
        fields
            .ok_or_else(|| de::Error::missing_field("kind"))?
            .finish()
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SolidSpec, A::Error> {
        // The sequence form: the kind, then the fields in declaration order.
        let kind: Kind = element(&mut seq, 0)?;
        let solid = match kind {
            Kind::Patch => SolidSpec::Patch {
                degree: element(&mut seq, 1)?,
                points: element(&mut seq, 2)?,
            },
            Kind::Volume => SolidSpec::Volume {
                degree: element(&mut seq, 1)?,
                points: element(&mut seq, 2)?,
            },
            // The layout of files before expressions, which are read after the operands.
            Kind::Esc => {
                // `#[serde(default)]`: absent at the end, it is none.
                let operation = seq.next_element()?.unwrap_or_default();
                let operands = element(&mut seq, 2)?;
                let expression = seq.next_element()?.unwrap_or_default();
                SolidSpec::Esc {
                    operation,
                    expression,
                    operands,
                }
            }
            Kind::Plasm => SolidSpec::Plasm {
                script: element(&mut seq, 1)?,
            },
            Kind::Piecewise => SolidSpec::Piecewise {
                cells: element(&mut seq, 1)?,
                degree: element(&mut seq, 2)?,
                points: seq.next_element_seed(PiecewisePoints)?.ok_or_else(|| {
                    de::Error::invalid_length(3, &"a kind and the fields of that kind")
                })?,
            },
            Kind::Hyperfun => SolidSpec::Hyperfun {
                program: element(&mut seq, 1)?,
                // `#[serde(default)]`: absent at the end, there is none.
                bounds: seq.next_element()?.unwrap_or_default(),
            },
            Kind::Node(kind) => {
                return Err(de::Error::custom(format_args!(
                    "a \"{}\" node is written as an object with a \"kind\"",
                    KINDS[kind]
                )));
            }
        };
        if seq.next_element::<IgnoredAny>()?.is_some() {
            return Err(de::Error::custom(
                "the solid has more elements than the fields of its kind",
            ));
        }
        Ok(solid)
    }
}

/// A piecewise solid's `points` as an element of a sequence.
struct PiecewisePoints;

impl<'de> DeserializeSeed<'de> for PiecewisePoints {
    type Value = Vec<Vec<f64>>;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        piecewise_points(d)
    }
}

/// Element `index` of a sequence-form solid, which must be there.
fn element<'de, A: SeqAccess<'de>, T: Deserialize<'de>>(
    seq: &mut A,
    index: usize,
) -> Result<T, A::Error> {
    seq.next_element()?
        .ok_or_else(|| de::Error::invalid_length(index, &"a kind and the fields of that kind"))
}

#[cfg(test)]
mod tests {
    use super::super::EscOperand;
    use super::*;
    use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES};

    use crate::model::MeshSpec;
    use alloc::format;
    use alloc::string::String;
    use alloc::string::ToString;
    use alloc::vec;
    use alloc::vec::Vec;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The solid as serde's derive read it before this reader.
    #[derive(Deserialize)]
    #[serde(tag = "kind", rename_all = "lowercase")]
    enum Derived {
        Patch {
            degree: [usize; 2],
            points: Vec<[f64; 3]>,
        },
        Volume {
            degree: [usize; 3],
            points: Vec<[f64; 4]>,
        },
        Esc {
            #[serde(default)]
            operation: Option<String>,
            operands: Vec<EscOperand>,
        },
        Plasm {
            script: String,
        },
        Hyperfun {
            program: String,
            #[serde(default, rename = "box")]
            bounds: Option<[[f64; 3]; 2]>,
        },
    }

    impl From<Derived> for SolidSpec {
        fn from(d: Derived) -> Self {
            match d {
                Derived::Patch { degree, points } => Self::Patch { degree, points },
                Derived::Volume { degree, points } => Self::Volume { degree, points },
                Derived::Esc {
                    operation,
                    operands,
                } => Self::Esc {
                    operation,
                    expression: None,
                    operands,
                },
                Derived::Plasm { script } => Self::Plasm { script },
                Derived::Hyperfun { program, bounds } => Self::Hyperfun { program, bounds },
            }
        }
    }

    #[test]
    fn solids_read_as_the_derive_read_them() {
        let patch =
            r#""degree": [1, 1], "points": [[0, 0, 1], [0, 1, 1], [1, 0, -0.0], [1, 1, 1e-300]]"#;
        let volume = r#""degree": [1, 1, 1], "points": [[0,0,0,1],[0,0,1,1],[0,1,0,1],[0,1,1,1],
            [1,0,0,1],[1,0,1,1],[1,1,0,1],[1,1,1,-2.5]]"#;
        let esc = r#""operation": "union", "operands": [{"example": "torus"},
            {"mesh": {"positions": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]]},
             "offset": [1, 2, 3]}]"#;
        let mut cases: Vec<String> = Vec::new();
        for (kind, fields) in [
            ("patch", patch),
            ("volume", volume),
            ("esc", esc),
            ("plasm", r#""script": "1 + 1;""#),
            (
                "hyperfun",
                r#""program": "m(x[3], a[1]) { m = 1 - x[1]^2; }", "box": [[-1, -2, -3], [1, 2, 3.5]]"#,
            ),
            ("hyperfun", r#""program": "m(x[3], a[1]) { m = 1; }""#),
        ] {
            let k = format!(r#""kind": "{kind}""#);
            // `kind` first (as written), last, in the middle of other fields, as an index.
            cases.push(format!("{{{k}, {fields}}}"));
            cases.push(format!("{{{fields}, {k}}}"));
            cases.push(format!(
                r#"{{"x": [1, {{"y": null}}], {fields}, "z": true, {k}}}"#
            ));
            cases.push(format!(r#"{{"note": "a", {k}, {fields}, "other": [[]]}}"#));
            let index = KINDS.iter().position(|&n| n == kind).unwrap_or(9);
            cases.push(format!(r#"{{"kind": {index}, {fields}}}"#));
            // Fields of other kinds, well or badly typed, before and after `kind`.
            cases.push(format!(
                r#"{{"script": 5, "points": "no", {k}, "operands": 1, "degree": {{}}, {fields}}}"#
            ));
            cases.push(format!(
                r#"{{{k}, "operation": [1], "script": null, {fields}}}"#
            ));
            // Twice the same field or kind; no kind.
            cases.push(format!("{{{k}, {fields}, {fields}}}"));
            cases.push(format!("{{{fields}, {k}, {fields}}}"));
            cases.push(format!("{{{k}, {fields}, {k}}}"));
            cases.push(format!("{{{fields}}}"));
        }
        for extra in [
            // Missing fields, defaults, wrong types and lengths.
            r#"{"kind": "patch", "degree": [1, 1]}"#,
            r#"{"kind": "patch", "points": []}"#,
            r#"{"kind": "esc", "operands": []}"#,
            r#"{"kind": "esc", "operation": null, "operands": []}"#,
            r#"{"operation": null, "kind": "esc", "operands": []}"#,
            r#"{"kind": "esc"}"#,
            r#"{"kind": "plasm"}"#,
            r#"{"kind": "patch", "degree": [1.5, 1], "points": []}"#,
            r#"{"kind": "patch", "degree": [1, 1, 1], "points": []}"#,
            r#"{"kind": "patch", "degree": [1, 1], "points": [[0, 0, 0, 0]]}"#,
            r#"{"degree": [1, -1], "kind": "patch", "points": []}"#,
            r#"{"kind": "volume", "degree": [1, 1, 1], "points": [[0, 0, 0]]}"#,
            r#"{"kind": "esc", "operands": [{"mesh": {"positions": [], "triangles": [[0, 1]]}}]}"#,
            r#"{"kind": "esc", "operands": [{"mesh": {"positions": [[0, 0, 0]]}}]}"#,
            r#"{"operands": [{"mesh": {"positions": [], "triangles": []}}], "kind": "esc"}"#,
            r#"{"kind": "plasm", "script": 5}"#,
            r#"{"script": ["a"], "kind": "plasm"}"#,
            r#"{"kind": "hyperfun"}"#,
            r#"{"kind": "hyperfun", "box": [[0, 0, 0], [1, 1, 1]]}"#,
            r#"{"kind": "hyperfun", "program": 5}"#,
            r#"{"kind": "hyperfun", "program": "", "box": null}"#,
            r#"{"box": null, "kind": "hyperfun", "program": ""}"#,
            r#"{"kind": "hyperfun", "program": "", "box": [[0, 0], [1, 1]]}"#,
            r#"{"kind": "hyperfun", "program": "", "box": [[0, 0, 0]]}"#,
            r#"{"kind": "hyperfun", "program": "", "box": [[0, 0, 0], [1, 1, "1"]]}"#,
            r#"{"kind": "hyperfun", "program": "", "box": "no"}"#,
            r#"{"box": [[0, 0, 0], [1, 1, 1], [2, 2, 2]], "kind": "hyperfun", "program": ""}"#,
            r#"{"kind": "hyperfun", "program": "", "box": [[0, 0, 0], [1, 1, 1]], "box": null}"#,
            // Kinds that do not exist.
            r#"{"kind": "teapot", "script": ""}"#,
            r#"{"kind": 4, "script": ""}"#,
            r#"{"kind": -1, "script": ""}"#,
            r#"{"kind": null, "script": ""}"#,
            r#"{"kind": ["plasm"], "script": ""}"#,
            r#"{"kind": "Patch", "degree": [1, 1], "points": []}"#,
            // The sequence form, whole, short and long.
            r#"["patch", [1, 1], [[0, 0, 1], [0, 1, 1], [1, 0, 1], [1, 1, 1]]]"#,
            r#"["patch", [1, 1]]"#,
            r#"["plasm", "1;"]"#,
            r#"["plasm", "1;", 2]"#,
            r#"["plasm"]"#,
            r#"["hyperfun", "m(x[3], a[1]) { m = 1; }"]"#,
            r#"["hyperfun", "", [[0, 0, 0], [1, 1, 1]]]"#,
            r#"["hyperfun", "", null]"#,
            r#"["hyperfun", "", [[0, 0, 0], [1, 1, 1]], 3]"#,
            r#"["hyperfun", "", [[0, 0], [1, 1]]]"#,
            r#"["hyperfun"]"#,
            r#"["esc", "union", []]"#,
            r#"["esc", null, []]"#,
            r#"["esc", []]"#,
            r#"["esc"]"#,
            r#"[]"#,
            r#"[3, "1;"]"#,
            // Not a solid at all.
            "{}",
            "null",
            "5",
            r#""patch""#,
        ] {
            cases.push(extra.to_string());
        }
        for case in cases {
            let ours = serde_json::from_str::<SolidSpec>(&case);
            let derived = serde_json::from_str::<Derived>(&case).map(SolidSpec::from);
            match (ours, derived) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a, b, "{case}");
                    // Bit for bit: -0.0 stays negative.
                    assert_eq!(format!("{a:?}"), format!("{b:?}"), "{case}");
                }
                (Err(_), Err(_)) => {}
                (a, b) => panic!("{case}: ours {a:?}, the derive's {b:?}"),
            }
        }
    }

    /// A free-form model of one mesh of `triangles` triangles, `kind` first or last.
    fn esc_json(triangles: usize, kind_first: bool) -> String {
        let list = vec!["[0,1,2]"; triangles].join(",");
        let fields = format!(
            r#""operands": [{{"mesh": {{"positions": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [{list}]}}}}]"#
        );
        if kind_first {
            format!(r#"{{"kind": "esc", {fields}}}"#)
        } else {
            format!(r#"{{{fields}, "kind": "esc"}}"#)
        }
    }

    #[test]
    fn meshes_past_the_caps_are_refused_while_they_are_read() {
        for kind_first in [true, false] {
            let at_cap = serde_json::from_str::<SolidSpec>(&esc_json(MAX_TRIANGLES, kind_first));
            let Ok(SolidSpec::Esc { operands, .. }) = at_cap else {
                panic!("{at_cap:?}");
            };
            assert_eq!(
                operands[0].mesh.as_ref().map(|m| m.triangles.len()),
                Some(MAX_TRIANGLES)
            );
            let e = serde_json::from_str::<SolidSpec>(&esc_json(MAX_TRIANGLES + 1, kind_first))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(&format!(
                    "a mesh has more than {MAX_TRIANGLES} triangles (the most a free-form model takes)"
                )),
                "{e}"
            );
        }
        let positions = format!(
            r#"{{"positions": [{}], "triangles": []}}"#,
            vec!["[0,0,0]"; MAX_VERTICES + 1].join(",")
        );
        let e = serde_json::from_str::<MeshSpec>(&positions)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("more than {MAX_VERTICES} vertices")),
            "{e}"
        );
        // A format that states a list's length first is refused before the elements are read:
        // postcard, no positions, then MAX_TRIANGLES + 1 triangles and a byte for each (postcard
        // states a length only where that many bytes follow), too few for their 3 indices.
        #[cfg(feature = "link")]
        {
            let mut bytes = vec![0];
            bytes.extend(postcard::to_allocvec(&(MAX_TRIANGLES + 1)).unwrap());
            bytes.resize(bytes.len() + MAX_TRIANGLES + 1, 0);
            let e = postcard::from_bytes::<MeshSpec>(&bytes).unwrap_err();
            // Reading them one at a time would run out of bytes instead.
            assert_eq!(e, postcard::Error::SerdeDeCustom);
        }
    }

    #[test]
    fn fields_before_the_kind_are_kept_up_to_a_bound() {
        // Numbers in a field before `kind`: one more than the bound is refused, whatever field.
        let json = |n: usize| {
            format!(
                r#"{{"script": [{}], "kind": "patch"}}"#,
                vec!["0"; n].join(",")
            )
        };
        let e = serde_json::from_str::<SolidSpec>(&json(MAX_KEPT_VALUES))
            .unwrap_err()
            .to_string();
        assert!(e.contains("write \"kind\" first"), "{e}");
        // Within it, the field is read and the solid's own errors come.
        let e = serde_json::from_str::<SolidSpec>(&json(10))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing field `degree`"), "{e}");
    }
}
