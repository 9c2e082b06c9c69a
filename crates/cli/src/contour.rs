//! `bezsolid contour MODEL --res N -o OUT.svg [--accuracy A]`: the zero contour of a patch solid.

use anyhow::{Context, Result, bail};

use crate::args::Args;
use bezsolid_core::contour::solid_contour;
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::ModelSolid;

/// The largest `--res`: 4096² samples is already 16 M evaluations.
const MAX_RES: usize = 4096;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let args = Args::parse("contour", args, &["--res", "--accuracy", "--output"])?;
    let model = args.model("bezsolid contour MODEL --res N -o OUT.svg")?;
    let out = args.required("--output", "-o OUT.svg")?;
    let res: usize = args.number("--res", 256)?;
    let accuracy: f64 = args.number("--accuracy", 1e-9)?;
    if !(2..=MAX_RES).contains(&res) {
        bail!("--res {res} is outside 2..={MAX_RES}");
    }
    if !(accuracy.is_finite() && accuracy > 0.0) {
        bail!("--accuracy must be a positive number");
    }
    let ModelSolid::Patch(solid) = crate::load_model(model)? else {
        bail!("contour draws patch (2D) models; for a volume use `bezsolid mesh`");
    };
    let (lo, hi) = solid.domain();
    let cell = (hi - lo) / res as f64;
    let lines = solid_contour(&solid, res, accuracy);
    std::fs::write(out, contours_svg(&lines, lo - cell, hi + cell))
        .with_context(|| format!("cannot write {out}"))?;
    eprintln!("bezsolid: {} contour pieces written to {out}", lines.len());
    crate::warn_exhausted(solid.exhausted());
    Ok(())
}
