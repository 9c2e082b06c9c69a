//! The names the page passes for the modeler's choices. Each is a `#[wasm_bindgen]` enum, so the
//! generated TypeScript lists what a call takes (`"function" | "space"`, `"obj" | "stl" | "ply"`, …)
//! and the glue turns it into the domain's type here, in one place.
//!
//! A string enum that JavaScript fills with any other string arrives as a hidden `__Invalid`
//! variant (wasm-bindgen's encoding), so every conversion below is a `TryFrom` whose error names
//! the strings that are taken. The axis is a numeric enum (the page numbers axes 0, 1, 2), which
//! the glue checks itself: any other number throws before the call runs.

// wasm-bindgen adds the hidden variant and a `from_js_value` to each string enum, undocumented.
#![allow(missing_docs)]

use bezsolid_core::Axis;
use bezsolid_core::esc::{Example, Op};
use bezsolid_core::mesh::Format;
use wasm_bindgen::prelude::*;

use crate::editor::Mode;
use crate::error::Error;
use crate::freeform::Display;

/// What a drag in the 2D view moves: a control point's defining value (`"function"`) or the point
/// in space (`"space"`, the inverse mapping).
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragMode {
    Function = "function",
    Space = "space",
}

impl TryFrom<DragMode> for Mode {
    type Error = Error;

    fn try_from(mode: DragMode) -> Result<Self, Error> {
        match mode {
            DragMode::Function => Ok(Self::Function),
            DragMode::Space => Ok(Self::Space),
            _ => Err(Error::new(
                "unknown drag mode: use \"function\" or \"space\"",
            )),
        }
    }
}

/// A parameter axis of a net: 0 (u), 1 (v), 2 (w; volumes only).
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamAxis {
    /// The first parameter.
    U = 0,
    /// The second parameter.
    V = 1,
    /// The third parameter (volumes only).
    W = 2,
}

impl From<ParamAxis> for Axis {
    fn from(axis: ParamAxis) -> Self {
        match axis {
            ParamAxis::U => Self::U,
            ParamAxis::V => Self::V,
            ParamAxis::W => Self::W,
        }
    }
}

/// A mesh file format: `"obj"`, `"stl"` or `"ply"`.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Obj = "obj",
    Stl = "stl",
    Ply = "ply",
}

impl TryFrom<MeshFormat> for Format {
    type Error = Error;

    fn try_from(format: MeshFormat) -> Result<Self, Error> {
        match format {
            MeshFormat::Obj => Ok(Self::Obj),
            MeshFormat::Stl => Ok(Self::Stl),
            MeshFormat::Ply => Ok(Self::Ply),
            _ => Err(Error::new(
                "unknown mesh format: use \"obj\", \"stl\" or \"ply\"",
            )),
        }
    }
}

/// The Free-form mode's operation on solids A and B, or `"none"` for A alone.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    Union = "union",
    Intersection = "intersection",
    Difference = "difference",
    None = "none",
}

impl Operation {
    /// The operation, `None` for A alone.
    pub(super) fn op(self) -> Result<Option<Op>, Error> {
        match self {
            Self::Union => Ok(Some(Op::Union)),
            Self::Intersection => Ok(Some(Op::Intersection)),
            Self::Difference => Ok(Some(Op::Difference)),
            Self::None => Ok(None),
            _ => Err(Error::new(
                "unknown operation: use \"union\", \"intersection\", \"difference\" or \"none\"",
            )),
        }
    }

    /// The name of `op`, `None` for A alone.
    pub(super) fn of(op: Option<Op>) -> Self {
        match op {
            Some(Op::Union) => Self::Union,
            Some(Op::Intersection) => Self::Intersection,
            Some(Op::Difference) => Self::Difference,
            None => Self::None,
        }
    }
}

/// What the Free-form view shows: the result, the paper's point mesh, or the operands.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FreeFormDisplay {
    Result = "result",
    Points = "points",
    Operands = "operands",
}

impl TryFrom<FreeFormDisplay> for Display {
    type Error = Error;

    fn try_from(display: FreeFormDisplay) -> Result<Self, Error> {
        match display {
            FreeFormDisplay::Result => Ok(Self::Result),
            FreeFormDisplay::Points => Ok(Self::Points),
            FreeFormDisplay::Operands => Ok(Self::Operands),
            _ => Err(Error::new(
                "unknown display: use \"result\", \"points\" or \"operands\"",
            )),
        }
    }
}

/// A built-in free-form solid.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FreeFormExample {
    Icosphere = "icosphere",
    Torus = "torus",
    Blob = "blob",
}

impl TryFrom<FreeFormExample> for Example {
    type Error = Error;

    fn try_from(example: FreeFormExample) -> Result<Self, Error> {
        match example {
            FreeFormExample::Icosphere => Ok(Self::Icosphere),
            FreeFormExample::Torus => Ok(Self::Torus),
            FreeFormExample::Blob => Ok(Self::Blob),
            _ => Err(Error::new(
                "unknown example: use \"icosphere\", \"torus\" or \"blob\"",
            )),
        }
    }
}

/// Which graphics API a view asks for: `"auto"` (WebGPU where the browser has it, else WebGL2),
/// `"webgpu"` or `"webgl2"`.
#[wasm_bindgen]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Auto = "auto",
    Webgpu = "webgpu",
    Webgl2 = "webgl2",
}

impl TryFrom<Backend> for wgpu::Backends {
    type Error = Error;

    fn try_from(backend: Backend) -> Result<Self, Error> {
        match backend {
            Backend::Auto => Ok(Self::BROWSER_WEBGPU | Self::GL),
            Backend::Webgpu => Ok(Self::BROWSER_WEBGPU),
            Backend::Webgl2 => Ok(Self::GL),
            _ => Err(Error::new(
                "unknown graphics backend: use \"auto\", \"webgpu\" or \"webgl2\"",
            )),
        }
    }
}
