//! The spec types: [`ModelFile`], [`SolidSpec`] and the parts a solid is spelled in.

use alloc::string::String;
use alloc::vec::Vec;

#[cfg(feature = "serde")]
use super::de;

/// A model file.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ModelFile {
    /// Always [`FORMAT`](super::FORMAT).
    pub format: String,
    /// [`VERSION`](super::VERSION) for this build.
    pub version: u32,
    /// The one solid of the model.
    pub solid: SolidSpec,
}

/// A solid as the file spells it.
///
/// It is read field by field, not through serde's derive (which copies the whole object first):
/// a free-form model's meshes are counted while they are read and refused past
/// [`MAX_TRIANGLES`](crate::mesh::MAX_TRIANGLES) triangles or
/// [`MAX_VERTICES`](crate::mesh::MAX_VERTICES) positions.
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
        /// A Boolean expression over the operands' names
        /// ([`Expr::parse`](crate::esc::bool::Expr::parse)), e.g. `(A | B) - C`.
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
        /// bounds of its own); absent, [`DEFAULT_HYPERFUN_BOX`](super::DEFAULT_HYPERFUN_BOX).
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
    /// that stays sharp (0 to 180; 180 keeps none). Absent, it is
    /// [`FILE_CREASE_ANGLE`](super::FILE_CREASE_ANGLE) (180: every edge rounded), what files
    /// written before creases meant, so that they keep their numbers; the page writes the angle it
    /// uses for an imported mesh
    /// ([`DEFAULT_CREASE_ANGLE`](crate::esc::DEFAULT_CREASE_ANGLE) unless changed).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub crease: Option<f64>,
}

/// A triangle mesh in a model file: at most [`MAX_VERTICES`](crate::mesh::MAX_VERTICES)
/// positions and [`MAX_TRIANGLES`](crate::mesh::MAX_TRIANGLES) triangles (a reader refuses a
/// longer list at the first element past its cap).
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
