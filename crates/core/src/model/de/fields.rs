//! The fields of one kind read so far ([`Fields`], a tree node's [`NodeFields`]), each read
//! into its slot as it comes, and checked and built into a [`SolidSpec`] at the end.

use alloc::string::String;
use alloc::vec::Vec;

use serde::Deserialize;
use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny};

use super::super::{CoordAxis, EscOperand, Rotation, SolidSpec};
use super::keys::{KINDS, Key, Kind, NODE_KEYS};
use super::lists::piecewise_points;

/// The fields of one kind read so far.
pub(super) enum Fields {
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
pub(super) struct NodeFields {
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
    pub(super) fn finish<E: de::Error>(self, kind: usize) -> Result<SolidSpec, E> {
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
    pub(super) fn new(kind: Kind) -> Self {
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
    pub(super) fn finish<E: de::Error>(self) -> Result<SolidSpec, E> {
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
pub(super) struct Field<'a> {
    pub(super) fields: &'a mut Fields,
    pub(super) key: Key,
}

/// Reads a value of type `T` into an empty `slot`; a second value for it is an error.
pub(super) fn fill<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
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
