//! Reading a model file's `solid` without holding more of it than it may be.
//!
//! serde's derive reads an internally tagged enum (`"kind": …` among the fields) by first copying
//! the whole object into a generic tree, whatever its size: a free-form model of a million
//! triangles took 20 times its text in memory before any cap was checked. Here the solid is read
//! field by field into its kind's types as soon as `kind` is known (writers put it first), and a
//! mesh's lists are counted while they are read ([`positions`], [`triangles`]): past
//! [`MAX_VERTICES`] or [`MAX_TRIANGLES`] the file is refused at that element. Fields that come
//! before `kind` are kept as [`Value`]s (bounded by [`MAX_KEPT_VALUES`]) and read once it comes.
//!
//! What opens is what the derive opened (a test reads many solids both ways): the same fields,
//! the same defaults, unknown fields ignored, and the sequence form `["patch", degree, points]`.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::marker::PhantomData;

use serde::de::value::{MapDeserializer, SeqDeserializer};
use serde::de::{
    self, DeserializeSeed, Deserializer, IgnoredAny, IntoDeserializer, MapAccess, SeqAccess,
    Unexpected, Visitor,
};
use serde::{Deserialize, forward_to_deserialize_any};

use super::{CoordAxis, EscOperand, Rotation, SolidSpec};
use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES};

/// The `kind` names, in variant order.
const KINDS: &[&str] = &[
    "patch",
    "volume",
    "esc",
    "plasm",
    "circle",
    "sphere",
    "rectangle",
    "box",
    "cylinder",
    "torus",
    "halfplane",
    "halfspace",
    "union",
    "intersection",
    "difference",
    "blend_union",
    "blend_intersection",
    "morph",
    "transform",
    "part",
    "piecewise",
    "hyperfun",
];

/// The most values kept from the fields before `kind` (every number, string and list counts one):
/// enough for the largest valid solid, two meshes at both caps, each vertex and triangle a list of
/// three numbers (4 values), with room for the small fields.
pub(crate) const MAX_KEPT_VALUES: usize = 2 * 4 * (MAX_VERTICES + MAX_TRIANGLES) + (1 << 16);

/// A mesh's `positions`, refused past [`MAX_VERTICES`].
pub(super) fn positions<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 3]>, D::Error> {
    d.deserialize_seq(Capped::new(MAX_VERTICES, "vertices"))
}

/// A piecewise solid's `points`, refused past [`crate::piecewise::MAX_POINTS`].
fn piecewise_points<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
    d.deserialize_seq(Capped {
        holder: "a piecewise solid",
        taker: "a piecewise solid",
        ..Capped::new(crate::piecewise::MAX_POINTS, "control points")
    })
}

/// A mesh's `triangles`, refused past [`MAX_TRIANGLES`].
pub(super) fn triangles<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[u32; 3]>, D::Error> {
    d.deserialize_seq(Capped::new(MAX_TRIANGLES, "triangles"))
}

/// A list of at most `max` elements, read one at a time.
struct Capped<T> {
    max: usize,
    what: &'static str,
    /// What holds the list, and what takes at most `max` of them, for the message.
    holder: &'static str,
    taker: &'static str,
    element: PhantomData<T>,
}

impl<T> Capped<T> {
    fn new(max: usize, what: &'static str) -> Self {
        Self {
            max,
            what,
            holder: "a mesh",
            taker: "a free-form model",
            element: PhantomData,
        }
    }

    fn too_many<E: de::Error>(&self) -> E {
        E::custom(format_args!(
            "{} has more than {} {} (the most {} takes)",
            self.holder, self.max, self.what, self.taker
        ))
    }
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for Capped<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a list of at most {} {}", self.max, self.what)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        // A format that states the length (postcard) is refused before any element is read.
        if seq.size_hint().is_some_and(|n| n > self.max) {
            return Err(self.too_many());
        }
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
        while let Some(element) = seq.next_element()? {
            if out.len() == self.max {
                return Err(self.too_many());
            }
            out.push(element);
        }
        Ok(out)
    }
}

/// A solid's kind: the value of `kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Patch,
    Volume,
    Esc,
    Plasm,
    Piecewise,
    Hyperfun,
    /// A node of a tree other than a Bézier leaf: its index in [`KINDS`].
    Node(usize),
}

impl<'de> Deserialize<'de> for Kind {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        impl Visitor<'_> for KindVisitor {
            type Value = Kind;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("variant identifier")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Kind, E> {
                match v {
                    "patch" => Ok(Kind::Patch),
                    "volume" => Ok(Kind::Volume),
                    "esc" => Ok(Kind::Esc),
                    "plasm" => Ok(Kind::Plasm),
                    "piecewise" => Ok(Kind::Piecewise),
                    "hyperfun" => Ok(Kind::Hyperfun),
                    _ => KINDS
                        .iter()
                        .position(|&k| k == v)
                        .map(Kind::Node)
                        .ok_or_else(|| E::unknown_variant(v, KINDS)),
                }
            }
            fn visit_bytes<E: de::Error>(self, v: &[u8]) -> Result<Kind, E> {
                match core::str::from_utf8(v) {
                    Ok(s) => self.visit_str(s),
                    Err(_) => Err(E::invalid_value(Unexpected::Bytes(v), &self)),
                }
            }
        }
        d.deserialize_identifier(KindVisitor)
    }
}

/// A key of the solid's object.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Key {
    Kind,
    Degree,
    Points,
    Operation,
    Operands,
    Expression,
    Script,
    Cells,
    Program,
    /// A HyperFun program's `box`.
    Box,
    /// A field of a tree's node: its index in [`NODE_KEYS`].
    Node(usize),
    /// A field no kind has (ignored, as serde ignores unknown fields).
    Other,
}

/// The fields of a tree's nodes (other than the Bézier leaves'), in [`NodeFields`]' order.
const NODE_KEYS: &[&str] = &[
    "center",
    "radius",
    "min",
    "max",
    "axis",
    "major",
    "minor",
    "normal",
    "offset",
    "of",
    "a0",
    "a1",
    "a2",
    "t",
    "solid",
    "translate",
    "rotate",
    "scale",
    "name",
    "hidden",
];

impl Key {
    fn name(self) -> &'static str {
        match self {
            Self::Kind => "kind",
            Self::Degree => "degree",
            Self::Points => "points",
            Self::Operation => "operation",
            Self::Operands => "operands",
            Self::Expression => "expression",
            Self::Script => "script",
            Self::Cells => "cells",
            Self::Program => "program",
            Self::Box => "box",
            Self::Node(i) => NODE_KEYS[i],
            Self::Other => "",
        }
    }
}

impl<'de> Deserialize<'de> for Key {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KeyVisitor;
        impl Visitor<'_> for KeyVisitor {
            type Value = Key;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a field name")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Key, E> {
                Ok(match v {
                    "kind" => Key::Kind,
                    "degree" => Key::Degree,
                    "points" => Key::Points,
                    "operation" => Key::Operation,
                    "operands" => Key::Operands,
                    "expression" => Key::Expression,
                    "script" => Key::Script,
                    "cells" => Key::Cells,
                    "program" => Key::Program,
                    "box" => Key::Box,
                    _ => NODE_KEYS
                        .iter()
                        .position(|&k| k == v)
                        .map_or(Key::Other, Key::Node),
                })
            }
            fn visit_bytes<E: de::Error>(self, v: &[u8]) -> Result<Key, E> {
                Ok(core::str::from_utf8(v)
                    .map_or(Key::Other, |s| self.visit_str::<E>(s).unwrap_or(Key::Other)))
            }
            fn visit_u64<E: de::Error>(self, _: u64) -> Result<Key, E> {
                Ok(Key::Other)
            }
        }
        d.deserialize_identifier(KeyVisitor)
    }
}

/// The fields of one kind read so far.
enum Fields {
    Patch {
        degree: Option<[usize; 2]>,
        points: Option<Vec<[f64; 3]>>,
    },
    Volume {
        degree: Option<[usize; 3]>,
        points: Option<Vec<[f64; 4]>>,
    },
    Esc {
        operation: Option<Option<String>>,
        expression: Option<Option<String>>,
        operands: Option<Vec<EscOperand>>,
    },
    Plasm {
        script: Option<String>,
    },
    Piecewise {
        cells: Option<Vec<usize>>,
        degree: Option<Vec<usize>>,
        points: Option<Vec<Vec<f64>>>,
    },
    Hyperfun {
        program: Option<String>,
        bounds: Option<Option<[[f64; 3]; 2]>>,
    },
    /// A tree's node: its kind's index in [`KINDS`] and its fields.
    Node(usize, alloc::boxed::Box<NodeFields>),
}

/// The fields a tree's node may have, each read as it comes and checked for its kind at the end.
#[derive(Default)]
struct NodeFields {
    center: Option<Vec<f64>>,
    radius: Option<f64>,
    min: Option<Vec<f64>>,
    max: Option<Vec<f64>>,
    axis: Option<CoordAxis>,
    major: Option<f64>,
    minor: Option<f64>,
    normal: Option<Vec<f64>>,
    offset: Option<f64>,
    of: Option<Vec<SolidSpec>>,
    a0: Option<f64>,
    a1: Option<f64>,
    a2: Option<f64>,
    t: Option<f64>,
    solid: Option<alloc::boxed::Box<SolidSpec>>,
    translate: Option<Vec<f64>>,
    rotate: Option<Rotation>,
    scale: Option<Vec<f64>>,
    name: Option<String>,
    hidden: Option<bool>,
}

impl NodeFields {
    /// Reads the value of field `index` ([`NODE_KEYS`]).
    fn fill<'de, D: Deserializer<'de>>(&mut self, index: usize, d: D) -> Result<(), D::Error> {
        let key = Key::Node(index);
        match index {
            0 => fill(&mut self.center, key, d),
            1 => fill(&mut self.radius, key, d),
            2 => fill(&mut self.min, key, d),
            3 => fill(&mut self.max, key, d),
            4 => fill(&mut self.axis, key, d),
            5 => fill(&mut self.major, key, d),
            6 => fill(&mut self.minor, key, d),
            7 => fill(&mut self.normal, key, d),
            8 => fill(&mut self.offset, key, d),
            9 => fill(&mut self.of, key, d),
            10 => fill(&mut self.a0, key, d),
            11 => fill(&mut self.a1, key, d),
            12 => fill(&mut self.a2, key, d),
            13 => fill(&mut self.t, key, d),
            14 => fill(&mut self.solid, key, d),
            15 => fill(&mut self.translate, key, d),
            16 => fill(&mut self.rotate, key, d),
            17 => fill(&mut self.scale, key, d),
            18 => fill(&mut self.name, key, d),
            _ => fill(&mut self.hidden, key, d),
        }
    }

    /// The node of kind `kind` ([`KINDS`]), or the first of its fields that is missing or of the
    /// wrong length.
    fn finish<E: de::Error>(self, kind: usize) -> Result<SolidSpec, E> {
        fn need<T, E: de::Error>(v: Option<T>, name: &'static str) -> Result<T, E> {
            v.ok_or_else(|| E::missing_field(name))
        }
        fn array<const N: usize, E: de::Error>(
            v: Option<Vec<f64>>,
            name: &'static str,
        ) -> Result<[f64; N], E> {
            let v = need::<_, E>(v, name)?;
            <[f64; N]>::try_from(v.as_slice()).map_err(|_| {
                E::custom(format_args!(
                    "\"{name}\" has {} numbers; this kind takes {N}",
                    v.len()
                ))
            })
        }
        let f = self;
        Ok(match KINDS[kind] {
            "circle" => SolidSpec::Circle {
                center: array(f.center, "center")?,
                radius: need(f.radius, "radius")?,
            },
            "sphere" => SolidSpec::Sphere {
                center: array(f.center, "center")?,
                radius: need(f.radius, "radius")?,
            },
            "rectangle" => SolidSpec::Rectangle {
                min: array(f.min, "min")?,
                max: array(f.max, "max")?,
            },
            "box" => SolidSpec::Box {
                min: array(f.min, "min")?,
                max: array(f.max, "max")?,
            },
            "cylinder" => SolidSpec::Cylinder {
                center: array(f.center, "center")?,
                axis: need(f.axis, "axis")?,
                radius: need(f.radius, "radius")?,
            },
            "torus" => SolidSpec::Torus {
                center: array(f.center, "center")?,
                axis: need(f.axis, "axis")?,
                major: need(f.major, "major")?,
                minor: need(f.minor, "minor")?,
            },
            "halfplane" => SolidSpec::Halfplane {
                normal: array(f.normal, "normal")?,
                offset: need(f.offset, "offset")?,
            },
            "halfspace" => SolidSpec::Halfspace {
                normal: array(f.normal, "normal")?,
                offset: need(f.offset, "offset")?,
            },
            "union" => SolidSpec::Union {
                of: need(f.of, "of")?,
            },
            "intersection" => SolidSpec::Intersection {
                of: need(f.of, "of")?,
            },
            "difference" => SolidSpec::Difference {
                of: need(f.of, "of")?,
            },
            "blend_union" => SolidSpec::BlendUnion {
                of: need(f.of, "of")?,
                a0: need(f.a0, "a0")?,
                a1: need(f.a1, "a1")?,
                a2: need(f.a2, "a2")?,
            },
            "blend_intersection" => SolidSpec::BlendIntersection {
                of: need(f.of, "of")?,
                a0: need(f.a0, "a0")?,
                a1: need(f.a1, "a1")?,
                a2: need(f.a2, "a2")?,
            },
            "morph" => SolidSpec::Morph {
                of: need(f.of, "of")?,
                t: need(f.t, "t")?,
            },
            "transform" => SolidSpec::Transform {
                solid: need(f.solid, "solid")?,
                translate: f.translate,
                rotate: f.rotate,
                scale: f.scale,
            },
            _ => SolidSpec::Part {
                solid: need(f.solid, "solid")?,
                name: need(f.name, "name")?,
                hidden: f.hidden.unwrap_or(false),
            },
        })
    }
}

impl Fields {
    fn new(kind: Kind) -> Self {
        match kind {
            Kind::Patch => Self::Patch {
                degree: None,
                points: None,
            },
            Kind::Volume => Self::Volume {
                degree: None,
                points: None,
            },
            Kind::Esc => Self::Esc {
                operation: None,
                expression: None,
                operands: None,
            },
            Kind::Plasm => Self::Plasm { script: None },
            Kind::Piecewise => Self::Piecewise {
                cells: None,
                degree: None,
                points: None,
            },
            Kind::Hyperfun => Self::Hyperfun {
                program: None,
                bounds: None,
            },
            Kind::Node(kind) => Self::Node(kind, alloc::boxed::Box::default()),
        }
    }

    /// The solid, or the first field (in declaration order) that is missing.
    fn finish<E: de::Error>(self) -> Result<SolidSpec, E> {
        let missing = |key: Key| E::missing_field(key.name());
        Ok(match self {
            Self::Patch { degree, points } => SolidSpec::Patch {
                degree: degree.ok_or_else(|| missing(Key::Degree))?,
                points: points.ok_or_else(|| missing(Key::Points))?,
            },
            Self::Volume { degree, points } => SolidSpec::Volume {
                degree: degree.ok_or_else(|| missing(Key::Degree))?,
                points: points.ok_or_else(|| missing(Key::Points))?,
            },
            Self::Esc {
                operation,
                expression,
                operands,
            } => SolidSpec::Esc {
                operation: operation.unwrap_or_default(),
                expression: expression.unwrap_or_default(),
                operands: operands.ok_or_else(|| missing(Key::Operands))?,
            },
            Self::Plasm { script } => SolidSpec::Plasm {
                script: script.ok_or_else(|| missing(Key::Script))?,
            },
            Self::Piecewise {
                cells,
                degree,
                points,
            } => SolidSpec::Piecewise {
                cells: cells.ok_or_else(|| missing(Key::Cells))?,
                degree: degree.ok_or_else(|| missing(Key::Degree))?,
                points: points.ok_or_else(|| missing(Key::Points))?,
            },
            Self::Hyperfun { program, bounds } => SolidSpec::Hyperfun {
                program: program.ok_or_else(|| missing(Key::Program))?,
                bounds: bounds.unwrap_or_default(),
            },
            Self::Node(kind, fields) => fields.finish(kind)?,
        })
    }
}

/// Reads the value of `key` into its slot of `fields`, or skips it where this kind has no such
/// field.
struct Field<'a> {
    fields: &'a mut Fields,
    key: Key,
}

/// Reads a value of type `T` into an empty `slot`; a second value for it is an error.
fn fill<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    slot: &mut Option<T>,
    key: Key,
    d: D,
) -> Result<(), D::Error> {
    if slot.is_some() {
        return Err(de::Error::duplicate_field(key.name()));
    }
    *slot = Some(T::deserialize(d)?);
    Ok(())
}

impl<'de> DeserializeSeed<'de> for Field<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let key = self.key;
        match (self.fields, key) {
            (Fields::Patch { degree, .. }, Key::Degree) => fill(degree, key, d),
            (Fields::Patch { points, .. }, Key::Points) => fill(points, key, d),
            (Fields::Volume { degree, .. }, Key::Degree) => fill(degree, key, d),
            (Fields::Volume { points, .. }, Key::Points) => fill(points, key, d),
            (Fields::Esc { operation, .. }, Key::Operation) => fill(operation, key, d),
            (Fields::Esc { operands, .. }, Key::Operands) => fill(operands, key, d),
            (Fields::Esc { expression, .. }, Key::Expression) => fill(expression, key, d),
            (Fields::Plasm { script }, Key::Script) => fill(script, key, d),
            (Fields::Piecewise { cells, .. }, Key::Cells) => fill(cells, key, d),
            (Fields::Hyperfun { program, .. }, Key::Program) => fill(program, key, d),
            (Fields::Hyperfun { bounds, .. }, Key::Box) => fill(bounds, key, d),
            (Fields::Piecewise { degree, .. }, Key::Degree) => fill(degree, key, d),
            (Fields::Piecewise { points, .. }, Key::Points) => {
                if points.is_some() {
                    return Err(de::Error::duplicate_field("points"));
                }
                *points = Some(piecewise_points(d)?);
                Ok(())
            }
            // `name` and `hidden` are a part's: on other kinds they are ignored, as any field no
            // kind has (what files written before parts may hold).
            (Fields::Node(kind, _), Key::Node(index))
                if matches!(NODE_KEYS[index], "name" | "hidden") && KINDS[*kind] != "part" =>
            {
                d.deserialize_ignored_any(IgnoredAny).map(drop)
            }
            (Fields::Node(_, fields), Key::Node(index)) => fields.fill(index, d),
            _ => IgnoredAny::deserialize(d).map(drop),
        }
    }
}

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

/// A value kept until the solid's kind is known: what a self-describing format (JSON) gives.
enum Value {
    Unit,
    Bool(bool),
    U64(u64),
    I64(i64),
    F64(f64),
    Str(Box<str>),
    Bytes(Box<[u8]>),
    Seq(Box<[Value]>),
    Map(Box<[(Value, Value)]>),
}

/// Reads a [`Value`], counting each against `budget`.
struct Keep<'a> {
    budget: &'a mut usize,
}

impl Keep<'_> {
    fn count<E: de::Error>(&mut self) -> Result<(), E> {
        *self.budget = self.budget.checked_sub(1).ok_or_else(|| {
            E::custom(format_args!(
                "the solid's fields before its \"kind\" hold more than {MAX_KEPT_VALUES} values \
                 (write \"kind\" first)"
            ))
        })?;
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for Keep<'_> {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Keep<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("any value")
    }

    fn visit_bool<E: de::Error>(mut self, v: bool) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Bool(v))
    }

    fn visit_i64<E: de::Error>(mut self, v: i64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::I64(v))
    }

    fn visit_u64<E: de::Error>(mut self, v: u64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::U64(v))
    }

    fn visit_f64<E: de::Error>(mut self, v: f64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::F64(v))
    }

    fn visit_str<E: de::Error>(mut self, v: &str) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Str(v.into()))
    }

    fn visit_bytes<E: de::Error>(mut self, v: &[u8]) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Bytes(v.into()))
    }

    fn visit_unit<E: de::Error>(mut self) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Unit)
    }

    fn visit_none<E: de::Error>(self) -> Result<Value, E> {
        self.visit_unit()
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }

    fn visit_seq<A: SeqAccess<'de>>(mut self, mut seq: A) -> Result<Value, A::Error> {
        self.count()?;
        let mut out = Vec::new();
        while let Some(v) = seq.next_element_seed(Keep {
            budget: self.budget,
        })? {
            out.push(v);
        }
        Ok(Value::Seq(out.into_boxed_slice()))
    }

    fn visit_map<A: MapAccess<'de>>(mut self, mut map: A) -> Result<Value, A::Error> {
        self.count()?;
        let mut out = Vec::new();
        while let Some(k) = map.next_key_seed(Keep {
            budget: self.budget,
        })? {
            let v = map.next_value_seed(Keep {
                budget: self.budget,
            })?;
            out.push((k, v));
        }
        Ok(Value::Map(out.into_boxed_slice()))
    }
}

/// Reads a kept [`Value`] as any type, with the error type of the file's deserializer.
struct ValueDeserializer<E> {
    value: Value,
    error: PhantomData<E>,
}

impl<E> ValueDeserializer<E> {
    fn new(value: Value) -> Self {
        Self {
            value,
            error: PhantomData,
        }
    }
}

impl<'de, E: de::Error> IntoDeserializer<'de, E> for Value {
    type Deserializer = ValueDeserializer<E>;

    fn into_deserializer(self) -> ValueDeserializer<E> {
        ValueDeserializer::new(self)
    }
}

impl<'de, E: de::Error> Deserializer<'de> for ValueDeserializer<E> {
    type Error = E;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        match self.value {
            Value::Unit => visitor.visit_unit(),
            Value::Bool(v) => visitor.visit_bool(v),
            Value::U64(v) => visitor.visit_u64(v),
            Value::I64(v) => visitor.visit_i64(v),
            Value::F64(v) => visitor.visit_f64(v),
            Value::Str(v) => visitor.visit_string(v.into()),
            Value::Bytes(v) => visitor.visit_byte_buf(v.into()),
            Value::Seq(v) => {
                let mut seq = SeqDeserializer::new(v.into_vec().into_iter());
                let out = visitor.visit_seq(&mut seq)?;
                seq.end()?;
                Ok(out)
            }
            Value::Map(v) => {
                let mut map = MapDeserializer::new(v.into_vec().into_iter());
                let out = visitor.visit_map(&mut map)?;
                map.end()?;
                Ok(out)
            }
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        match self.value {
            Value::Unit => visitor.visit_none(),
            _ => visitor.visit_some(self),
        }
    }

    forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MeshSpec;
    use alloc::format;
    use alloc::string::ToString;
    use alloc::vec;
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
