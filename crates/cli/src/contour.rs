//! `bezsolid contour MODEL --res N -o OUT.svg [--accuracy A]`: the zero contour of a patch solid.

use anyhow::{Context, Result, bail};

use crate::args::Args;
use bezsolid_core::contour::{Grid2, contour};
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::ModelSolid;
use glam::DVec2;

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
    // One cell of margin: f is negative outside the box, so every contour closes inside the grid.
    let cell = (hi - lo) / res as f64;
    let grid = Grid2::new(lo - cell, hi + cell, res + 3, res + 3);
    let values = solid.f_grid(&grid.xs(), &grid.ys());
    let lines = contour(&grid, &values, |p: DVec2| solid.f(p), accuracy);
    std::fs::write(out, contours_svg(&lines, lo - cell, hi + cell))
        .with_context(|| format!("cannot write {out}"))?;
    eprintln!("bezsolid: {} contour pieces written to {out}", lines.len());
    Ok(())
}
