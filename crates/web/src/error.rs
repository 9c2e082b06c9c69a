//! The one error type of the page's plain-Rust modules: a message for the person at the page.
//!
//! Every fallible function of [`crate::editor`], [`crate::document`], [`crate::freeform`] and
//! [`crate::script`] returns [`Error`]; the core's typed errors convert into it with `?`, and it
//! converts into wasm-bindgen's `JsError` with `?` in the glue (it implements
//! [`std::error::Error`]), so no call site spells out a conversion.

use std::fmt;

use bezsolid_core::esc::EscError;
use bezsolid_core::mesh::{MeshError, ReadError, UnknownFormat};
use bezsolid_core::model::ModelError;
use bezsolid_core::{PatchError, SolidError};

/// What went wrong, in words the page shows as they are.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error(String);

impl Error {
    /// An error saying `message`.
    #[must_use]
    pub fn new(message: impl Into<String>) -> Self {
        Self(message.into())
    }

    /// The message.
    #[must_use]
    pub fn message(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

impl From<String> for Error {
    fn from(message: String) -> Self {
        Self(message)
    }
}

impl From<&str> for Error {
    fn from(message: &str) -> Self {
        Self(message.into())
    }
}

macro_rules! from_display {
    ($($t:ty),*) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Self {
                Self(e.to_string())
            }
        }
    )*};
}
from_display!(
    SolidError,
    PatchError,
    ModelError,
    MeshError,
    ReadError,
    UnknownFormat,
    bezsolid_core::mesh::exchange::ExportError,
    EscError,
    bezsolid_core::hyperfun::TreeHfError,
    bezsolid_core::tree::TreeMeshError,
    bezsolid_core::link::LinkError,
    serde_json::Error
);
