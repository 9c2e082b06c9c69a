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
//!   [`Expr::parse`]). An operand's `name` is optional: unnamed operands are `A`, `B`, `C`, … by
//!   position. An operand is placed by `offset`, and optionally `rotate` (`[rx, ry, rz]`, degrees)
//!   and `scale` (per axis, non-zero; a negative one mirrors): each point `p` goes to
//!   `offset + Rz·Ry·Rx·S·p`, as a tree's `transform` moves its solid. `crease` (degrees, 0 to 180)
//!   sets the angle between neighbouring faces past which an edge stays sharp; absent, it is 180
//!   (every edge rounded), as files written before creases were read.
//!   A mesh holds at most [`MAX_VERTICES`] positions and [`MAX_TRIANGLES`] triangles: a reader
//!   refuses a longer list while reading it, before the rest of the file is read.
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

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use glam::{DVec3, DVec4};

use alloc::format;
use alloc::string::ToString;

use crate::esc::bool::{Expr, Op};
use crate::esc::chain::EscSolid;
use crate::esc::draw::Boolean;
use crate::esc::examples::Example;
use crate::mesh::Mesh;
use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES, RawMesh, from_raw};
use crate::solid::{Solid2, Solid3, SolidError};
use crate::tensor::{Patch, Volume};

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

/// A model file.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ModelFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`] for this build.
    pub version: u32,
    /// The one solid of the model.
    pub solid: SolidSpec,
}

/// A solid as the file spells it.
///
/// It is read field by field, not through serde's derive (which copies the whole object first):
/// a free-form model's meshes are counted while they are read and refused past [`MAX_TRIANGLES`]
/// triangles or [`MAX_VERTICES`] positions.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "lowercase"))]
pub enum SolidSpec {
    /// A 2D solid from a patch: points `[x, y, ξ]`.
    Patch {
        /// `[n, m]`.
        degree: [usize; 2],
        /// `(n + 1)(m + 1)` points, `P_ij` at `i·(m + 1) + j`.
        points: Vec<[f64; 3]>,
    },
    /// A 3D solid from a volume: points `[x, y, z, ξ]`.
    Volume {
        /// `[n, m, l]`.
        degree: [usize; 3],
        /// `(n + 1)(m + 1)(l + 1)` points, `P_ijk` at `(i·(m + 1) + j)·(l + 1) + k`.
        points: Vec<[f64; 4]>,
    },
    /// A free-form solid: solids bounded by the PN triangles of closed triangle meshes, combined
    /// by `operation` (two, or one for `complement`) or by `expression` (any number).
    Esc {
        /// `union`, `intersection` or `difference` of two operands, or `complement` of one; absent
        /// for one operand alone or with an `expression`.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        operation: Option<String>,
        /// A Boolean expression over the operands' names ([`Expr::parse`]), e.g. `(A | B) - C`.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        expression: Option<String>,
        /// The solids, in order (`A`, `B`, … unless named).
        operands: Vec<EscOperand>,
    },
    /// A PLaSM script, run by `bezsolid-plasm`.
    Plasm {
        /// The script's text.
        script: String,
    },
    /// A disc: `radius² − ‖p − center‖²` (2D trees).
    Circle {
        /// The centre.
        center: [f64; 2],
        /// The radius, positive.
        radius: f64,
    },
    /// A ball: `radius² − ‖p − center‖²` (3D trees).
    Sphere {
        /// The centre.
        center: [f64; 3],
        /// The radius, positive.
        radius: f64,
    },
    /// `s_x & s_y`, `s_i = (p_i − min_i)(max_i − p_i)` (2D trees).
    Rectangle {
        /// The lower corner.
        min: [f64; 2],
        /// The upper corner, above `min` on every axis.
        max: [f64; 2],
    },
    /// `s_x & s_y & s_z`, `s_i = (p_i − min_i)(max_i − p_i)` (3D trees).
    Box {
        /// The lower corner.
        min: [f64; 3],
        /// The upper corner, above `min` on every axis.
        max: [f64; 3],
    },
    /// An infinite cylinder: `radius²` less the squared distance from the line along `axis` through
    /// `center` (3D trees).
    Cylinder {
        /// A point of the axis line.
        center: [f64; 3],
        /// The line's direction.
        axis: CoordAxis,
        /// The radius, positive.
        radius: f64,
    },
    /// A torus around the line along `axis` through `center`:
    /// `minor² − (sqrt(a² + b²) − major)² − c²`, `c` along the axis, `a, b` across it (3D trees).
    Torus {
        /// The centre.
        center: [f64; 3],
        /// The axis of revolution.
        axis: CoordAxis,
        /// The distance from the axis to the tube's centre line, positive.
        major: f64,
        /// The tube's radius, positive.
        minor: f64,
    },
    /// `offset − normal · p` (2D trees).
    Halfplane {
        /// The outward normal, not zero.
        normal: [f64; 2],
        /// The offset.
        offset: f64,
    },
    /// `offset − normal · p` (3D trees).
    Halfspace {
        /// The outward normal, not zero.
        normal: [f64; 3],
        /// The offset.
        offset: f64,
    },
    /// `f1 | f2 | …` left to right.
    Union {
        /// Two or more nodes.
        of: Vec<SolidSpec>,
    },
    /// `f1 & f2 & …` left to right.
    Intersection {
        /// Two or more nodes.
        of: Vec<SolidSpec>,
    },
    /// `f1 & (−f2) & (−f3) …` left to right.
    Difference {
        /// Two or more nodes.
        of: Vec<SolidSpec>,
    },
    /// `(f1 | f2) + a0 / (1 + (f1/a1)² + (f2/a2)²)` (Pasko and Savchenko's blending union,
    /// HyperFun's `hfBlendUni`).
    #[cfg_attr(feature = "serde", serde(rename = "blend_union"))]
    BlendUnion {
        /// Two nodes.
        of: Vec<SolidSpec>,
        /// The blend's height.
        a0: f64,
        /// How far it reaches into the first operand, not zero.
        a1: f64,
        /// How far it reaches into the second operand, not zero.
        a2: f64,
    },
    /// `(f1 & f2) + a0 / (1 + (f1/a1)² + (f2/a2)²)` (HyperFun's `hfBlendInt`).
    #[cfg_attr(feature = "serde", serde(rename = "blend_intersection"))]
    BlendIntersection {
        /// Two nodes.
        of: Vec<SolidSpec>,
        /// The blend's height.
        a0: f64,
        /// How far it reaches into the first operand, not zero.
        a1: f64,
        /// How far it reaches into the second operand, not zero.
        a2: f64,
    },
    /// `(1 − t) f1 + t f2` (metamorphosis).
    Morph {
        /// Two nodes.
        of: Vec<SolidSpec>,
        /// The morph's parameter: 0 is the first node, 1 the second.
        t: f64,
    },
    /// The solid moved by `M = T · Rz · Ry · Rx · S`: `f(p) = f_solid(M⁻¹ p)`.
    Transform {
        /// The node moved.
        solid: alloc::boxed::Box<SolidSpec>,
        /// `T`: a 2D or 3D offset.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        translate: Option<Vec<f64>>,
        /// `R`, in degrees: one angle in 2D, `[rx, ry, rz]` in 3D.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        rotate: Option<Rotation>,
        /// `S`, per axis, no component zero.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        scale: Option<Vec<f64>>,
    },
    /// A named part: its solid as it is (`f = f_solid`), with a name for people and whether the
    /// modeler's views hide it. Evaluation, meshes and exports take the solid whole, hidden or not.
    Part {
        /// The solid named.
        solid: alloc::boxed::Box<SolidSpec>,
        /// The name, at most [`MAX_NAME_BYTES`] bytes (may be empty).
        name: String,
        /// Whether the views leave it out (absent: shown).
        #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "is_false"))]
        hidden: bool,
    },
    /// A piecewise solid ([`crate::piecewise`]): `cells` `[cu, cv]` (2D) or `[cu, cv, cw]` (3D)
    /// cells of `degree` `[n, m]` or `[n, m, l]` each, from one global net of
    /// `(cu·n + 1)(cv·m + 1)[(cw·l + 1)]` points `[x, y, ξ]` or `[x, y, z, ξ]`, indexed like a
    /// single net with those counts.
    Piecewise {
        /// The cells along each axis.
        cells: Vec<usize>,
        /// Each cell's degree.
        degree: Vec<usize>,
        /// The global net's points, the last axis fastest.
        points: Vec<Vec<f64>>,
    },
    /// A HyperFun program, read and evaluated as HyperFun's interpreter does
    /// ([`crate::hyperfun::read`]): its solid is `f > 0` within `box`.
    Hyperfun {
        /// The program's text.
        program: String,
        /// The box `[[x0, y0, z0], [x1, y1, z1]]` it is drawn and meshed in (a program has no
        /// bounds of its own); absent, [`DEFAULT_HYPERFUN_BOX`].
        #[cfg_attr(
            feature = "serde",
            serde(rename = "box", default, skip_serializing_if = "Option::is_none")
        )]
        bounds: Option<[[f64; 3]; 2]>,
    },
}

/// The longest name of a [`SolidSpec::Part`], in bytes.
pub const MAX_NAME_BYTES: usize = 256;

#[cfg(feature = "serde")]
#[allow(clippy::trivially_copy_pass_by_ref)] // serde's `skip_serializing_if` passes a reference
fn is_false(b: &bool) -> bool {
    !*b
}

impl SolidSpec {
    /// A tree node's children, in order: an operation's `of`, a transform's or a part's `solid`;
    /// none for a leaf.
    #[must_use]
    pub fn children(&self) -> &[SolidSpec] {
        match self {
            Self::Union { of }
            | Self::Intersection { of }
            | Self::Difference { of }
            | Self::BlendUnion { of, .. }
            | Self::BlendIntersection { of, .. }
            | Self::Morph { of, .. } => of,
            Self::Transform { solid, .. } | Self::Part { solid, .. } => {
                core::slice::from_ref(&**solid)
            }
            _ => &[],
        }
    }

    /// An operation's operands (`of`), to change in place; `None` for a leaf or a transform.
    pub fn operands_mut(&mut self) -> Option<&mut Vec<SolidSpec>> {
        match self {
            Self::Union { of }
            | Self::Intersection { of }
            | Self::Difference { of }
            | Self::BlendUnion { of, .. }
            | Self::BlendIntersection { of, .. }
            | Self::Morph { of, .. } => Some(of),
            _ => None,
        }
    }

    /// Child `i` ([`SolidSpec::children`]), to change in place.
    pub fn child_mut(&mut self, i: usize) -> Option<&mut SolidSpec> {
        match self {
            Self::Transform { solid, .. } | Self::Part { solid, .. } => {
                (i == 0).then_some(&mut **solid)
            }
            _ => self.operands_mut()?.get_mut(i),
        }
    }

    /// The spec of a piecewise solid ([`SolidSpec::Piecewise`]).
    #[must_use]
    pub fn from_piecewise<const D: usize>(solid: &crate::piecewise::Piecewise<D>) -> Self
    where
        crate::dim::Dim<D>: crate::dim::Dimension<D>,
    {
        use crate::dim::{Dim, Dimension};
        Self::Piecewise {
            cells: solid.cells().to_vec(),
            degree: solid.degree().to_vec(),
            points: solid
                .points()
                .iter()
                .map(|&c| {
                    let (x, xi) = Dim::<D>::split(c);
                    x.into_iter().chain([xi]).collect()
                })
                .collect(),
        }
    }

    /// The piecewise solid of `D` dimensions this spec is: a [`SolidSpec::Piecewise`], or a
    /// single patch or volume as one of one cell ([`crate::piecewise::Piecewise::from_solid`]);
    /// `None` for another kind or dimension.
    #[must_use]
    pub fn to_piecewise<const D: usize>(
        &self,
    ) -> Option<Result<crate::piecewise::Piecewise<D>, crate::piecewise::PiecewiseError>>
    where
        crate::dim::Dim<D>: crate::dim::Dimension<D>,
    {
        let single = |degree: &[usize], points: Vec<Vec<f64>>| {
            (degree.len() == D).then(|| crate::tree::piecewise::<D>(&[1; D], degree, &points))
        };
        match self {
            Self::Piecewise {
                cells,
                degree,
                points,
            } => (cells.len() == D).then(|| crate::tree::piecewise::<D>(cells, degree, points)),
            Self::Patch { degree, points } => {
                single(degree, points.iter().map(|p| p.to_vec()).collect())
            }
            Self::Volume { degree, points } => {
                single(degree, points.iter().map(|p| p.to_vec()).collect())
            }
            _ => None,
        }
    }

    /// Whether this is a kind only a tree of many solids has: a primitive, an operation or a
    /// transform (a single patch or volume is also a tree, of one leaf, but reads as itself).
    #[must_use]
    pub fn is_tree(&self) -> bool {
        !matches!(
            self,
            Self::Patch { .. }
                | Self::Volume { .. }
                | Self::Esc { .. }
                | Self::Plasm { .. }
                | Self::Hyperfun { .. }
        )
    }
}

/// A coordinate axis of space, as a cylinder or a torus names its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum CoordAxis {
    /// `x`.
    X,
    /// `y`.
    Y,
    /// `z`.
    Z,
}

impl CoordAxis {
    /// 0, 1 or 2.
    #[must_use]
    pub const fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }
}

/// A transform's rotation in degrees: one angle (2D, about the origin, counter-clockwise) or
/// `[rx, ry, rz]` about the axes (3D, applied x first).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
pub enum Rotation {
    /// A 2D rotation.
    Angle(f64),
    /// A 3D rotation.
    Angles([f64; 3]),
}

/// One solid of a free-form model: a built-in example or a triangle mesh, placed by `offset`,
/// `rotate` and `scale`.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EscOperand {
    /// Its name in an `expression` ([`is_name`](crate::esc::bool::is_name)); unnamed operands
    /// are `A`, `B`, `C`, … by position.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub name: Option<String>,
    /// The name of a built-in example (`icosphere`, `torus`, `blob`).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub example: Option<String>,
    /// Or a closed triangle mesh, triangles counter-clockwise seen from outside.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub mesh: Option<MeshSpec>,
    /// Added to every vertex (after `scale` and `rotate`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub offset: [f64; 3],
    /// Rotation about the axes in degrees, `[rx, ry, rz]`, applied x first (`Rz·Ry·Rx`).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub rotate: Option<[f64; 3]>,
    /// Scale along each axis, applied first; non-zero, a negative one mirrors.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub scale: Option<[f64; 3]>,
    /// The angle in degrees between neighbouring faces' normals past which their edge is a crease
    /// that stays sharp (0 to 180; 180 keeps none). Absent, it is [`FILE_CREASE_ANGLE`] (180:
    /// every edge rounded), what files written before creases meant, so that they keep their
    /// numbers; the page writes the angle it uses for an imported mesh
    /// ([`DEFAULT_CREASE_ANGLE`](crate::esc::DEFAULT_CREASE_ANGLE) unless changed).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub crease: Option<f64>,
}

/// A triangle mesh in a model file: at most [`MAX_VERTICES`] positions and [`MAX_TRIANGLES`]
/// triangles (a reader refuses a longer list at the first element past its cap).
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MeshSpec {
    /// Vertex positions.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "de::positions"))]
    pub positions: Vec<[f64; 3]>,
    /// Vertex indices, three per triangle, from 0.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "de::triangles"))]
    pub triangles: Vec<[u32; 3]>,
}

/// A validated solid of a model.
#[derive(Clone, Debug, PartialEq)]
pub enum ModelSolid {
    /// From a patch.
    Patch(Solid2),
    /// From a volume.
    Volume(Solid3),
}

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
        /// `"triangles"` ([`MAX_TRIANGLES`]) or `"vertices"` ([`MAX_VERTICES`]).
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

impl ModelFile {
    /// The model file of a patch solid.
    #[must_use]
    pub fn from_solid2(solid: &Solid2) -> Self {
        let [n, m] = solid.degree();
        let points = solid.net().points().iter().map(|p| p.to_array()).collect();
        Self::new(SolidSpec::Patch {
            degree: [n, m],
            points,
        })
    }

    /// The model file of a volume solid.
    #[must_use]
    pub fn from_solid3(solid: &Solid3) -> Self {
        let [n, m, l] = solid.degree();
        let points = solid.net().points().iter().map(|p| p.to_array()).collect();
        Self::new(SolidSpec::Volume {
            degree: [n, m, l],
            points,
        })
    }

    /// The model file of any solid: a tree, or one of the single kinds.
    #[must_use]
    pub fn from_spec(solid: SolidSpec) -> Self {
        Self::new(solid)
    }

    fn new(solid: SolidSpec) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            solid,
        }
    }

    /// Checks the header and builds the solid.
    ///
    /// # Errors
    ///
    /// [`ModelError`] for another format or version, or an invalid control net (wrong count, degree
    /// outside 1..=16, non-finite or huge values, an empty box, or moved control points, which need
    /// the inverse map of a later version).
    pub fn to_solid(&self) -> Result<ModelSolid, ModelError> {
        self.check_header()?;
        Ok(match &self.solid {
            SolidSpec::Patch { degree, points } => {
                let pts = points.iter().map(|&p| DVec3::from_array(p)).collect();
                let patch = Patch::try_new(*degree, pts).map_err(SolidError::from)?;
                ModelSolid::Patch(Solid2::try_from_net(patch)?)
            }
            SolidSpec::Volume { degree, points } => {
                let pts = points.iter().map(|&p| DVec4::from_array(p)).collect();
                let volume = Volume::try_new(*degree, pts).map_err(SolidError::from)?;
                ModelSolid::Volume(Solid3::try_from_net(volume)?)
            }
            SolidSpec::Esc { .. } => {
                return Err(ModelError::Kind(
                    "this is a free-form model (meshes and Booleans), not a Bézier solid",
                ));
            }
            SolidSpec::Plasm { .. } => {
                return Err(ModelError::Kind(
                    "this is a PLaSM script (run it with `bezsolid plasm`), not a Bézier solid",
                ));
            }
            SolidSpec::Piecewise { .. } => {
                return Err(ModelError::Kind(
                    "this is a piecewise solid (cells of one net), not a single Bézier solid",
                ));
            }
            SolidSpec::Hyperfun { .. } => return Err(ModelError::Kind(HYPERFUN_NOT_BEZIER)),
            _ => {
                return Err(ModelError::Kind(
                    "this is a model of many solids (a tree of primitives, Bézier solids and \
                     operations), not one Bézier solid",
                ));
            }
        })
    }

    pub(crate) fn check_header(&self) -> Result<(), ModelError> {
        if self.format != FORMAT {
            return Err(ModelError::Format(self.format.clone()));
        }
        if self.version != VERSION {
            return Err(ModelError::Version(self.version));
        }
        Ok(())
    }

    /// The model file of a PLaSM script.
    #[must_use]
    pub fn from_plasm(script: &str) -> Self {
        Self::new(SolidSpec::Plasm {
            script: script.into(),
        })
    }

    /// Checks the header and gives the script of a PLaSM model.
    ///
    /// # Errors
    ///
    /// [`ModelError`] for another format or version, another kind ([`ModelError::Kind`]), or a
    /// script past [`MAX_SCRIPT_BYTES`].
    pub fn to_script(&self) -> Result<&str, ModelError> {
        self.check_header()?;
        let SolidSpec::Plasm { script } = &self.solid else {
            return Err(ModelError::Kind("this model is not a PLaSM script"));
        };
        if script.len() > MAX_SCRIPT_BYTES {
            return Err(ModelError::ScriptTooLong(script.len()));
        }
        Ok(script)
    }

    /// The model file of a HyperFun program drawn and meshed within `bounds`
    /// (`[[x0, y0, z0], [x1, y1, z1]]`; `None` writes no box: [`DEFAULT_HYPERFUN_BOX`]).
    #[must_use]
    pub fn from_hyperfun(program: &str, bounds: Option<[[f64; 3]; 2]>) -> Self {
        Self::new(SolidSpec::Hyperfun {
            program: program.into(),
            bounds,
        })
    }

    /// Checks the header and gives the program of a HyperFun model and its box
    /// ([`DEFAULT_HYPERFUN_BOX`] where the file gives none). The program is not parsed here
    /// ([`Program::parse`](crate::hyperfun::read::Program::parse) does that).
    ///
    /// # Errors
    ///
    /// [`ModelError`] for another format or version, another kind ([`ModelError::Kind`]), a
    /// program past [`MAX_SOURCE_BYTES`](crate::hyperfun::read::MAX_SOURCE_BYTES)
    /// ([`ModelError::ProgramTooLong`]), or a box that is not finite or is empty on an axis
    /// ([`ModelError::BadBox`]).
    pub fn to_hyperfun(&self) -> Result<(&str, [[f64; 3]; 2]), ModelError> {
        self.check_header()?;
        let SolidSpec::Hyperfun { program, bounds } = &self.solid else {
            return Err(ModelError::Kind("this model is not a HyperFun program"));
        };
        if program.len() > crate::hyperfun::read::MAX_SOURCE_BYTES {
            return Err(ModelError::ProgramTooLong(program.len()));
        }
        let bounds = bounds.unwrap_or(DEFAULT_HYPERFUN_BOX);
        let [lo, hi] = bounds;
        // Each side finite: its corners and its length (a box of ±1e308 has no step to mesh by).
        if (0..3).any(|i| !((hi[i] - lo[i]).is_finite() && lo[i] < hi[i])) {
            return Err(ModelError::BadBox(bounds));
        }
        Ok((program, bounds))
    }

    /// The model file of a free-form model.
    #[must_use]
    pub fn from_esc(operation: Option<Op>, operands: Vec<EscOperand>) -> Self {
        Self::new(SolidSpec::Esc {
            operation: operation.map(|o| o.name().into()),
            expression: None,
            operands,
        })
    }

    /// The model file of a free-form model whose operands combine by `expr` (solid `i` is
    /// `operands[i]`). It is written in the shortest form that says it: one operand alone, an
    /// `operation` of two operands in order or a `complement` of one, else an `expression` over the
    /// operands' names ([`operand_names`]).
    #[must_use]
    pub fn from_esc_expr(expr: &Expr, operands: Vec<EscOperand>) -> Self {
        let named = operands.iter().any(|o| o.name.is_some());
        let (operation, expression) = match (expr, operands.len()) {
            (Expr::Solid(0), 1) => (None, None),
            (Expr::Complement(a), 1) if **a == Expr::Solid(0) => (Some(COMPLEMENT.into()), None),
            (Expr::Binary(op, a, b), 2)
                if !named && **a == Expr::Solid(0) && **b == Expr::Solid(1) =>
            {
                (Some(op.name().into()), None)
            }
            _ => {
                let names = default_names(&operands);
                (None, Some(expr.text(&names)))
            }
        };
        Self::new(SolidSpec::Esc {
            operation,
            expression,
            operands,
        })
    }

    /// Checks the header and builds a free-form model: its solids and the expression over them
    /// (solid 0, or `0 op 1`).
    ///
    /// # Errors
    ///
    /// [`ModelError`] for another format or version, a Bézier solid ([`ModelError::Kind`]), or a
    /// free-form model that cannot be built ([`ModelError::Esc`]: an unknown example or operation,
    /// the wrong number of operands, an offset that is not finite, or a mesh that is not a closed
    /// solid).
    pub fn to_boolean(&self) -> Result<Boolean, ModelError> {
        self.check_header()?;
        let (operation, expression, operands) = match &self.solid {
            SolidSpec::Esc {
                operation,
                expression,
                operands,
            } => (operation, expression, operands),
            SolidSpec::Plasm { .. } => {
                return Err(ModelError::Kind(
                    "this is a PLaSM script, not a free-form model",
                ));
            }
            SolidSpec::Hyperfun { .. } => {
                return Err(ModelError::Kind(
                    "this is a HyperFun program, not a free-form model",
                ));
            }
            _ => {
                return Err(ModelError::Kind(
                    "this is a Bézier solid, not a free-form model",
                ));
            }
        };
        let expr = esc_expr(operation.as_deref(), expression.as_deref(), operands)?;
        // Every operand's counts before any operand is built.
        let mut total = 0;
        for (i, o) in operands.iter().enumerate() {
            if let Err(TooMany { what, count, max }) = o.check_counts() {
                return Err(ModelError::MeshTooLarge {
                    operand: i + 1,
                    what,
                    count,
                    max,
                });
            }
            total += o.mesh.as_ref().map_or(0, |m| m.triangles.len());
        }
        if total > MAX_TOTAL_TRIANGLES {
            return Err(ModelError::Esc(format!(
                "the meshes have {total} triangles together, more than the \
                 {MAX_TOTAL_TRIANGLES} a free-form model takes"
            )));
        }
        let solids = operands
            .iter()
            .enumerate()
            .map(|(i, o)| {
                o.to_solid()
                    .map_err(|e| ModelError::Esc(format!("operand {}: {e}", i + 1)))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Boolean { solids, expr })
    }
}

/// How the readers of Bézier solids and trees refuse a HyperFun program.
pub(crate) const HYPERFUN_NOT_BEZIER: &str = "this is a HyperFun program (draw it in the HyperFun \
     mode, or mesh it with `bezsolid mesh`), not a Bézier solid";

/// How the reader of trees refuses a HyperFun program alone (a tree may hold one as a leaf).
pub(crate) const HYPERFUN_ALONE: &str = "this is a HyperFun program, a model of its own (draw it \
     in the HyperFun mode, or mesh it with `bezsolid mesh`), not a model of many solids; put it \
     in one (a union, a transform, …) to combine it with other solids";

/// The `operation` of a free-form model of one operand that takes its complement.
pub const COMPLEMENT: &str = "complement";

/// The names of a free-form model's operands: each one's `name`, or `A`, `B`, `C`, … by position.
///
/// # Errors
///
/// [`ModelError::Esc`] for more than [`MAX_OPERANDS`] operands, a name that is not a name
/// ([`is_name`](crate::esc::bool::is_name)) or is longer than [`MAX_NAME_CHARS`], or two
/// operands of the same name.
pub fn operand_names(operands: &[EscOperand]) -> Result<Vec<String>, ModelError> {
    if operands.len() > MAX_OPERANDS {
        return Err(ModelError::Esc(format!(
            "{} operands; a free-form model has at most {MAX_OPERANDS}",
            operands.len()
        )));
    }
    let names = default_names(operands);
    for (i, name) in names.iter().enumerate() {
        if !crate::esc::bool::is_name(name) || name.chars().count() > MAX_NAME_CHARS {
            return Err(ModelError::Esc(format!(
                "operand {}: {name:?} is not a name (a letter or _, then letters, digits or _; \
                 at most {MAX_NAME_CHARS})",
                i + 1
            )));
        }
        if let Some(j) = names[..i].iter().position(|n| n == name) {
            return Err(ModelError::Esc(format!(
                "operands {} and {} are both named {name:?}",
                j + 1,
                i + 1
            )));
        }
    }
    Ok(names)
}

/// Each operand's name or letter, unchecked.
fn default_names(operands: &[EscOperand]) -> Vec<String> {
    operands
        .iter()
        .enumerate()
        .map(|(i, o)| match &o.name {
            Some(name) => name.clone(),
            None => letter(i),
        })
        .collect()
}

/// `A` … `Z`, then `S27`, `S28`, … (past [`MAX_OPERANDS`], for messages only).
fn letter(i: usize) -> String {
    match u8::try_from(i).ok().filter(|&i| i < 26) {
        Some(i) => char::from(b'A' + i).to_string(),
        None => format!("S{}", i + 1),
    }
}

/// The expression a free-form model's `operation`, `expression` and operands say.
///
/// # Errors
///
/// [`ModelError::Esc`]: both or an unknown operation, the wrong number of operands for it, bad
/// names ([`operand_names`]), or an expression that does not parse.
pub fn esc_expr(
    operation: Option<&str>,
    expression: Option<&str>,
    operands: &[EscOperand],
) -> Result<Expr, ModelError> {
    let names = operand_names(operands)?;
    let count = |want: usize, what: &str| {
        if operands.len() == want {
            Ok(())
        } else {
            Err(ModelError::Esc(format!(
                "{} operand(s) with {what}: expected {want}",
                operands.len()
            )))
        }
    };
    match (operation, expression) {
        (Some(_), Some(_)) => Err(ModelError::Esc(
            "give an operation or an expression, not both".into(),
        )),
        (None, Some(text)) => {
            if operands.is_empty() {
                return Err(ModelError::Esc("an expression needs operands".into()));
            }
            Expr::parse(text, &names).map_err(|e| ModelError::Esc(format!("expression: {e}")))
        }
        (Some(COMPLEMENT), None) => {
            count(1, COMPLEMENT)?;
            Ok(Expr::complement(Expr::Solid(0)))
        }
        (Some(name), None) => {
            let op = Op::from_name(name).ok_or_else(|| {
                ModelError::Esc(format!(
                    "unknown operation {name:?}: use union, intersection, difference or complement"
                ))
            })?;
            count(2, name)?;
            Ok(Expr::binary(op, Expr::Solid(0), Expr::Solid(1)))
        }
        (None, None) => {
            count(1, "no operation")?;
            Ok(Expr::Solid(0))
        }
    }
}

/// A mesh's count past its cap.
struct TooMany {
    what: &'static str,
    count: usize,
    max: usize,
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

impl EscOperand {
    /// A built-in example, moved by `offset`.
    #[must_use]
    pub fn example(example: Example, offset: [f64; 3]) -> Self {
        Self {
            example: Some(example.name().into()),
            offset,
            ..Self::default()
        }
    }

    /// The placement: the linear part `Rz·Ry·Rx·S` and the offset.
    ///
    /// # Errors
    ///
    /// In words: an offset past [`MAX_OFFSET`], an angle that is not finite, a scale that is zero,
    /// not finite, or past [`MAX_SCALE`] (or its inverse).
    pub fn placement(&self) -> Result<(glam::DMat3, DVec3), String> {
        let offset = DVec3::from_array(self.offset);
        if !offset.is_finite() || offset.abs().max_element() > MAX_OFFSET {
            return Err(format!(
                "the offset must be finite numbers of at most {MAX_OFFSET:e}"
            ));
        }
        let mut linear = glam::DMat3::IDENTITY;
        if let Some(scale) = self.scale {
            if let Some(s) = scale
                .iter()
                .find(|s| !(s.is_finite() && (1.0 / MAX_SCALE..=MAX_SCALE).contains(&s.abs())))
            {
                return Err(format!(
                    "the scale {s} is refused: each axis's must be non-zero, finite, and between \
                     {:e} and {MAX_SCALE:e} in size",
                    1.0 / MAX_SCALE
                ));
            }
            linear = glam::DMat3::from_diagonal(DVec3::from_array(scale));
        }
        if let Some(angles) = self.rotate {
            if angles.iter().any(|a| !a.is_finite() || a.abs() > 1e6) {
                return Err("the rotation must be finite angles of at most 1e6 degrees".into());
            }
            let rows = crate::tree::rotation3(angles);
            linear = glam::DMat3::from_cols_array_2d(&rows).transpose() * linear;
        }
        Ok((linear, offset))
    }

    /// Whether its mesh, if it has one, is within [`MAX_VERTICES`] positions and
    /// [`MAX_TRIANGLES`] triangles.
    fn check_counts(&self) -> Result<(), TooMany> {
        let Some(mesh) = &self.mesh else {
            return Ok(());
        };
        for (what, count, max) in [
            ("triangles", mesh.triangles.len(), MAX_TRIANGLES),
            ("vertices", mesh.positions.len(), MAX_VERTICES),
        ] {
            if count > max {
                return Err(TooMany { what, count, max });
            }
        }
        Ok(())
    }

    /// The operand's mesh (the example's or its own), moved, welded, validated and with normals.
    ///
    /// # Errors
    ///
    /// What is wrong with it, in words; a mesh past the count caps is refused before anything is
    /// copied.
    pub fn to_mesh(&self) -> Result<Mesh, String> {
        self.check_counts().map_err(|e| e.to_string())?;
        let (linear, offset) = self.placement()?;
        let mirrored = linear.determinant() < 0.0;
        let mut mesh = match (&self.example, &self.mesh) {
            (Some(name), None) => Example::from_name(name)
                .ok_or_else(|| {
                    format!("no example {name:?}; the examples are icosphere, torus and blob")
                })?
                .mesh(),
            (None, Some(spec)) => {
                // Moved before it is checked, so that the checks see the mesh as it is used.
                let raw = RawMesh {
                    positions: spec
                        .positions
                        .iter()
                        .map(|&p| linear * DVec3::from_array(p) + offset)
                        .collect(),
                    normals: None,
                    triangles: if mirrored {
                        spec.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
                    } else {
                        spec.triangles.clone()
                    },
                };
                return from_raw(&raw).map_err(|e| e.to_string());
            }
            _ => return Err("give either an example or a mesh".into()),
        };
        for p in &mut mesh.positions {
            *p = linear * *p + offset;
        }
        if linear != glam::DMat3::IDENTITY {
            // Normals go by the inverse transpose; a mirror turns the triangles over.
            let normal = linear.inverse().transpose();
            for n in &mut mesh.normals {
                *n = (normal * *n).normalize_or_zero();
            }
            if mirrored {
                for t in &mut mesh.triangles {
                    t.swap(1, 2);
                }
            }
        }
        Ok(mesh)
    }

    /// The operand's [`EscSolid`].
    ///
    /// # Errors
    ///
    /// As [`EscOperand::to_mesh`], and a mesh that cannot be a chain.
    pub fn to_solid(&self) -> Result<EscSolid, String> {
        let crease = self.crease.unwrap_or(FILE_CREASE_ANGLE);
        if !crate::esc::pn::valid_crease_angle(crease) {
            return Err(crate::esc::EscError::CreaseAngle { degrees: crease }.to_string());
        }
        EscSolid::with_crease_angle(&self.to_mesh()?, crease).map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
