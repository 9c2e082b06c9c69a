//! Why a model file was refused: [`ModelError`] and its message.

use alloc::string::String;
use core::fmt;

use crate::solid::SolidError;

use super::{FORMAT, MAX_SCRIPT_BYTES, VERSION};

/// Why a model file was refused.
///
/// Its message says the inner error's too (the page shows `to_string()` alone), so
/// [`source`](core::error::Error::source) gives none: a chain printed link by link (`anyhow`'s
/// `{:#}`) says each cause once, as the Rust API guidelines ask (C-GOOD-ERR: one or the other).
#[derive(Clone, Debug, PartialEq)]
pub enum ModelError {
    /// `format` is not [`FORMAT`].
    Format(String),
    /// `version` is not one this build reads.
    Version(u32),
    /// The solid is invalid.
    Solid(SolidError),
    /// A free-form model where a Bézier solid is wanted, or the other way round.
    Kind(&'static str),
    /// A free-form model that cannot be built: what is wrong.
    Esc(String),
    /// A script past [`MAX_SCRIPT_BYTES`]: its length.
    ScriptTooLong(usize),
    /// A HyperFun program past [`MAX_SOURCE_BYTES`](crate::hyperfun::read::MAX_SOURCE_BYTES):
    /// its length.
    ProgramTooLong(usize),
    /// A HyperFun program's box that is not finite or is empty on an axis (its low coordinate
    /// not below its high one): the box.
    BadBox([[f64; 3]; 2]),
    /// A tree of many solids that breaks a rule: the node's path and what is wrong.
    Tree(crate::tree::TreeError),
    /// A free-form model's mesh past a count cap, found before anything is built.
    MeshTooLarge {
        /// The operand, from 1.
        operand: usize,
        /// `"triangles"` ([`MAX_TRIANGLES`](crate::mesh::MAX_TRIANGLES)) or `"vertices"`
        /// ([`MAX_VERTICES`](crate::mesh::MAX_VERTICES)).
        what: &'static str,
        /// How many the mesh has.
        count: usize,
        /// The cap.
        max: usize,
    },
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Format(s) => write!(
                f,
                "not a bezsolid model (format is {s:?}, expected {FORMAT:?})"
            ),
            Self::Version(v) => {
                write!(
                    f,
                    "model file version {v} is not supported (this build reads version {VERSION})"
                )
            }
            Self::Solid(e) => write!(f, "invalid solid: {e}"),
            Self::Kind(why) => f.write_str(why),
            Self::Esc(why) => write!(f, "invalid free-form model: {why}"),
            Self::Tree(e) => write!(f, "invalid model: {e}"),
            Self::ScriptTooLong(len) => write!(
                f,
                "the script is {len} bytes; a model file holds at most {MAX_SCRIPT_BYTES}"
            ),
            Self::ProgramTooLong(len) => write!(
                f,
                "the HyperFun program is {len} bytes; a model file holds at most {}",
                crate::hyperfun::read::MAX_SOURCE_BYTES
            ),
            Self::BadBox([lo, hi]) => write!(
                f,
                "the HyperFun program's box [{lo:?}, {hi:?}] is refused: its coordinates must \
                 be finite, each low one below the high one"
            ),
            Self::MeshTooLarge {
                operand,
                what,
                count,
                max,
            } => write!(
                f,
                "invalid free-form model: operand {operand}: {}",
                TooMany {
                    what,
                    count: *count,
                    max: *max
                }
            ),
        }
    }
}

impl core::error::Error for ModelError {}

impl From<SolidError> for ModelError {
    fn from(e: SolidError) -> Self {
        Self::Solid(e)
    }
}

/// A mesh's count past its cap.
pub(super) struct TooMany {
    pub(super) what: &'static str,
    pub(super) count: usize,
    pub(super) max: usize,
}

impl fmt::Display for TooMany {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Self { what, count, max } = self;
        write!(
            f,
            "the mesh has {count} {what}, more than the {max} a free-form model takes"
        )
    }
}
