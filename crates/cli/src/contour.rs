//! `bezsolid contour MODEL --res N -o OUT.svg [--accuracy A]`: the zero contour of a patch solid.

use anyhow::{Context, Result, bail};
use bezsolid_core::contour::{Grid2, contour};
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::ModelSolid;
use glam::DVec2;

/// The largest `--res`: 4096² samples is already 16 M evaluations.
const MAX_RES: usize = 4096;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let mut model = None;
    let mut res = 256usize;
    let mut out = None;
    let mut accuracy: f64 = 1e-9;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--res" => {
                let v = it.next().context("--res needs a number")?;
                res = v
                    .parse()
                    .with_context(|| format!("--res {v} is not a whole number"))?;
            }
            "--accuracy" => {
                let v = it.next().context("--accuracy needs a number")?;
                accuracy = v
                    .parse()
                    .with_context(|| format!("--accuracy {v} is not a number"))?;
            }
            "-o" | "--output" => out = Some(it.next().context("-o needs a file")?),
            s if s.starts_with('-') && s.len() > 1 => bail!("contour: unknown option {s}"),
            s if model.is_none() => model = Some(s),
            s => bail!("contour: unexpected argument {s}"),
        }
    }
    let model =
        model.context("contour: which model? usage: bezsolid contour MODEL --res N -o OUT.svg")?;
    let out = out.context("contour: -o OUT.svg is required")?;
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
