//! The names the page passes for the modeler's choices. Each is a `#[wasm_bindgen]` enum, so the
//! generated TypeScript lists what a call takes (`"function" | "space"`, `"obj" | "stl" | "ply"`, …)
//! and the glue turns it into the domain's type here, in one place.
//!
//! A string enum that JavaScript fills with any other string arrives as a hidden `__Invalid`
//! variant (wasm-bindgen's encoding), so every conversion is a `TryFrom` whose error names the
//! strings that are taken. The axis is a numeric enum (the page numbers axes 0, 1, 2), which the
//! glue checks itself: any other number throws before the call runs.

// wasm-bindgen adds the hidden variant and a `from_js_value` to each string enum, undocumented.
#![allow(missing_docs)]

use bezsolid_core::Axis;
use bezsolid_core::esc::{Example, Op};
use bezsolid_core::mesh::exchange::ExportFormat;
use wasm_bindgen::prelude::*;

use crate::editor::Mode;
use crate::error::Error;
use crate::freeform::{Combine, Display};
use crate::outline::{NewNode, Wrap};

/// The error for a string that is none of `names`: "unknown mesh format: use "obj", "stl" or "ply"".
fn unknown(what: &str, names: &[&str]) -> Error {
    let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
    let list = match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    Error::new(format!("unknown {what}: use {list}"))
}

/// String enums for the page and their conversions: `Name => DomainType, "what it is" { Variant =
/// "string" => domain value, … }`.
macro_rules! page_names {
    ($(
        $(#[$meta:meta])*
        $name:ident => $domain:ty, $what:literal {
            $($variant:ident = $text:literal => $value:expr,)+
        }
    )+) => {$(
        $(#[$meta])*
        #[wasm_bindgen]
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name {
            $($variant = $text,)+
        }

        impl $name {
            /// The page's name for it.
            #[allow(dead_code)] // not every enum is named back to the page
            pub(crate) fn text(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)+
                    _ => "",
                }
            }
        }

        impl TryFrom<$name> for $domain {
            type Error = Error;

            fn try_from(name: $name) -> Result<Self, Error> {
                match name {
                    $($name::$variant => Ok($value),)+
                    _ => Err(unknown($what, &[$($text),+])),
                }
            }
        }
    )+};
}

page_names! {
    /// What a drag in the 2D view moves: a control point's defining value (`"function"`) or the
    /// point in space (`"space"`, the inverse mapping).
    DragMode => Mode, "drag mode" {
        Function = "function" => Mode::Function,
        Space = "space" => Mode::Space,
    }

    // A plain string, not a doc comment: wasm-bindgen copies a string enum's doc into the
    // TypeScript declarations (the package for node ships them) as its literal's text, and a doc
    // comment's literal is a raw string (`r"…"`).
    #[doc = " A mesh file format: `stl` (binary), `obj`, `ply`, `3mf` or `glb`."]
    MeshFormat => ExportFormat, "mesh format" {
        Obj = "obj" => ExportFormat::Obj,
        Stl = "stl" => ExportFormat::Stl,
        Ply = "ply" => ExportFormat::Ply,
        ThreeMf = "3mf" => ExportFormat::ThreeMf,
        Glb = "glb" => ExportFormat::Glb,
    }

    /// How the Free-form mode's solids combine: an operation over all of them, A's complement, or
    /// `"none"` for A alone.
    Operation => Combine, "operation" {
        Union = "union" => Combine::Binary(Op::Union),
        Intersection = "intersection" => Combine::Binary(Op::Intersection),
        Difference = "difference" => Combine::Binary(Op::Difference),
        Complement = "complement" => Combine::Complement,
        None = "none" => Combine::Alone,
    }

    /// What the Free-form view shows: the result, the paper's point mesh, or the operands.
    FreeFormDisplay => Display, "display" {
        Result = "result" => Display::Result,
        Points = "points" => Display::Points,
        Operands = "operands" => Display::Operands,
    }

    /// A built-in free-form solid.
    FreeFormExample => Example, "example" {
        Icosphere = "icosphere" => Example::Icosphere,
        Torus = "torus" => Example::Torus,
        Blob = "blob" => Example::Blob,
    }

    /// A part the outliner adds to a model of many solids: a primitive of the model's dimension
    /// (`"sphere"` is a circle in 2D, `"box"` a rectangle, `"half"` a half-plane or half-space) or
    /// a regular Bézier patch or volume (`"bezier"`).
    PartKind => NewNode, "part" {
        Sphere = "sphere" => NewNode::Sphere,
        Box = "box" => NewNode::Box,
        Cylinder = "cylinder" => NewNode::Cylinder,
        Torus = "torus" => NewNode::Torus,
        Half = "half" => NewNode::Half,
        Bezier = "bezier" => NewNode::Bezier,
        Hyperfun = "hyperfun" => NewNode::Hyperfun,
    }

    /// An operation the outliner puts around the selected part.
    PartOperation => Wrap, "operation" {
        Union = "union" => Wrap::Union,
        Intersection = "intersection" => Wrap::Intersection,
        Difference = "difference" => Wrap::Difference,
        BlendUnion = "blend_union" => Wrap::BlendUnion,
        BlendIntersection = "blend_intersection" => Wrap::BlendIntersection,
        Morph = "morph" => Wrap::Morph,
        Transform = "transform" => Wrap::Transform,
    }

}

#[cfg(feature = "page")]
page_names! {
    /// Which graphics API a view asks for: `"auto"` (WebGPU where the browser has it, else
    /// WebGL2), `"webgpu"` or `"webgl2"`.
    Backend => wgpu::Backends, "graphics backend" {
        Auto = "auto" => wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL,
        Webgpu = "webgpu" => wgpu::Backends::BROWSER_WEBGPU,
        Webgl2 = "webgl2" => wgpu::Backends::GL,
    }
}

impl From<Combine> for Operation {
    fn from(c: Combine) -> Self {
        match c {
            Combine::Binary(Op::Union) => Self::Union,
            Combine::Binary(Op::Intersection) => Self::Intersection,
            Combine::Binary(Op::Difference) => Self::Difference,
            Combine::Complement => Self::Complement,
            Combine::Alone => Self::None,
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
