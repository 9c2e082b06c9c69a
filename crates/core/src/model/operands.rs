//! A free-form model's operands and expression: their names, the expression they say, and each
//! operand's placement, mesh and solid.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use glam::DVec3;

use crate::esc::bool::{Expr, Op};
use crate::esc::chain::EscSolid;
use crate::esc::examples::Example;
use crate::mesh::Mesh;
use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES, RawMesh, from_raw};

use super::error::TooMany;
use super::{
    EscOperand, FILE_CREASE_ANGLE, MAX_NAME_CHARS, MAX_OFFSET, MAX_OPERANDS, MAX_SCALE, ModelError,
};

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
pub(super) fn default_names(operands: &[EscOperand]) -> Vec<String> {
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
    pub(super) fn check_counts(&self) -> Result<(), TooMany> {
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
