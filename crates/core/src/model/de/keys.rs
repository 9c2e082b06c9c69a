//! The solid's keys and kinds: the names of `kind` and of the fields, read as identifiers.

use core::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, Unexpected, Visitor};

/// The `kind` names, in variant order.
pub(super) const KINDS: &[&str] = &[
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

/// A solid's kind: the value of `kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
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
pub(super) enum Key {
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

/// The fields of a tree's nodes (other than the Bézier leaves'), in
/// [`NodeFields`](super::fields::NodeFields)' order.
pub(super) const NODE_KEYS: &[&str] = &[
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
    pub(super) fn name(self) -> &'static str {
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
