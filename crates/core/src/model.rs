//! The model file (DESIGN §5): the document a user saves, shares and hands to the command line.
//!
//! ```json
//! { "format": "bezsolid", "version": 1,
//!   "solid": { "kind": "patch", "degree": [2, 2], "points": [[0.0, 0.0, -1.0], …] } }
//! ```
//!
//! - `kind: "patch"`: `degree [n, m]`, points `[x, y, ξ]`, `P_ij` at `i·(m + 1) + j`.
//! - `kind: "volume"`: `degree [n, m, l]`, points `[x, y, z, ξ]`, `P_ijk` at `(i·(m + 1) + j)·(l + 1) + k`.
//! - `kind: "esc"` (free-form): `operands`, one or two of `{ "example": "torus",
//!   "offset": [x, y, z] }` or `{ "mesh": { "positions": [[x, y, z], …], "triangles": [[a, b, c],
//!   …] }, "offset": … }`, and with two an `operation`: `union`, `intersection` or `difference`.
//!   A mesh holds at most [`MAX_VERTICES`] positions and [`MAX_TRIANGLES`] triangles: a reader
//!   refuses a longer list while reading it, before the rest of the file is read.
//! - `kind: "plasm"` (scripts): `script`, the text of a PLaSM script (at most
//!   [`MAX_SCRIPT_BYTES`]); what it draws is what the script's top-level expressions give.
//!
//! There is no separate box: a regular grid is recognised from the points. Readers ignore fields they
//! do not know (later kinds add fields) and reject an unknown version. With the `serde` feature the
//! types derive `Serialize` and `Deserialize` in exactly this shape.

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
/// The longest script a model file may hold, in bytes.
pub const MAX_SCRIPT_BYTES: usize = 256 * 1024;
/// The model file version this build writes and reads.
pub const VERSION: u32 = 1;

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
    /// A free-form solid: one or two solids bounded by the PN triangles of closed
    /// triangle meshes, combined by `operation` when there are two.
    Esc {
        /// `union`, `intersection` or `difference`; absent for one operand.
        #[cfg_attr(
            feature = "serde",
            serde(default, skip_serializing_if = "Option::is_none")
        )]
        operation: Option<String>,
        /// The solids, in order (`A`, then `B`).
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

    /// Whether this is a kind only a tree of many solids has: a primitive, an operation or a
    /// transform (a single patch or volume is also a tree, of one leaf, but reads as itself).
    #[must_use]
    pub fn is_tree(&self) -> bool {
        !matches!(
            self,
            Self::Patch { .. } | Self::Volume { .. } | Self::Esc { .. } | Self::Plasm { .. }
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

/// One solid of a free-form model: a built-in example or a triangle mesh, moved by `offset`.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EscOperand {
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
    /// Added to every vertex.
    #[cfg_attr(feature = "serde", serde(default))]
    pub offset: [f64; 3],
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

    /// The model file of a free-form model.
    #[must_use]
    pub fn from_esc(operation: Option<Op>, operands: Vec<EscOperand>) -> Self {
        Self::new(SolidSpec::Esc {
            operation: operation.map(|o| o.name().into()),
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
        let (operation, operands) = match &self.solid {
            SolidSpec::Esc {
                operation,
                operands,
            } => (operation, operands),
            SolidSpec::Plasm { .. } => {
                return Err(ModelError::Kind(
                    "this is a PLaSM script, not a free-form model",
                ));
            }
            _ => {
                return Err(ModelError::Kind(
                    "this is a Bézier solid, not a free-form model",
                ));
            }
        };
        let op = match operation {
            None => None,
            Some(name) => Some(Op::from_name(name).ok_or_else(|| {
                ModelError::Esc(format!(
                    "unknown operation {name:?}: use union, intersection or difference"
                ))
            })?),
        };
        let want = if op.is_some() { 2 } else { 1 };
        if operands.len() != want {
            return Err(ModelError::Esc(format!(
                "{} operand(s) with {}: expected {want}",
                operands.len(),
                operation.as_deref().unwrap_or("no operation")
            )));
        }
        // Every operand's counts before any operand is built.
        for (i, o) in operands.iter().enumerate() {
            if let Err(TooMany { what, count, max }) = o.check_counts() {
                return Err(ModelError::MeshTooLarge {
                    operand: i + 1,
                    what,
                    count,
                    max,
                });
            }
        }
        let solids = operands
            .iter()
            .enumerate()
            .map(|(i, o)| {
                o.to_solid()
                    .map_err(|e| ModelError::Esc(format!("operand {}: {e}", i + 1)))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let expr = match op {
            None => Expr::Solid(0),
            Some(op) => Expr::binary(op, Expr::Solid(0), Expr::Solid(1)),
        };
        Ok(Boolean { solids, expr })
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
            mesh: None,
            offset,
        }
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
        let offset = DVec3::from_array(self.offset);
        if !offset.is_finite() || offset.abs().max_element() > 1e9 {
            return Err("the offset must be finite numbers of at most 1e9".into());
        }
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
                        .map(|&p| DVec3::from_array(p) + offset)
                        .collect(),
                    normals: None,
                    triangles: spec.triangles.clone(),
                };
                return from_raw(&raw).map_err(|e| e.to_string());
            }
            _ => return Err("give either an example or a mesh".into()),
        };
        for p in &mut mesh.positions {
            *p += offset;
        }
        Ok(mesh)
    }

    /// The operand's [`EscSolid`].
    ///
    /// # Errors
    ///
    /// As [`EscOperand::to_mesh`], and a mesh that cannot be a chain.
    pub fn to_solid(&self) -> Result<EscSolid, String> {
        EscSolid::new(&self.to_mesh()?).map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensor::PatchError;
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
    fn free_form_meshes_past_the_count_caps_are_refused_before_anything_is_built() {
        let mesh = |positions: usize, triangles: usize| EscOperand {
            example: None,
            mesh: Some(MeshSpec {
                positions: alloc::vec![[0.0; 3]; positions],
                triangles: alloc::vec![[0, 1, 2]; triangles],
            }),
            offset: [0.0; 3],
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
}
