//! The readers and writers of a [`ModelFile`]: `from_*` and `to_solid`, `to_script`, `to_hyperfun`,
//! `to_boolean`.

use alloc::format;
use alloc::vec::Vec;

use glam::{DVec3, DVec4};

use crate::esc::bool::{Expr, Op};
use crate::esc::draw::Boolean;
use crate::solid::{Solid2, Solid3, SolidError};
use crate::tensor::{Patch, Volume};

use super::error::TooMany;
use super::operands::default_names;
use super::{
    COMPLEMENT, DEFAULT_HYPERFUN_BOX, EscOperand, FORMAT, MAX_SCRIPT_BYTES, MAX_TOTAL_TRIANGLES,
    ModelError, ModelFile, SolidSpec, VERSION, esc_expr,
};

/// A validated solid of a model.
#[derive(Clone, Debug, PartialEq)]
pub enum ModelSolid {
    /// From a patch.
    Patch(Solid2),
    /// From a volume.
    Volume(Solid3),
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

    pub(super) fn new(solid: SolidSpec) -> Self {
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
    /// operands' names ([`operand_names`](super::operand_names)).
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
