//! `bezsolid eval MODEL --points FILE.csv [-o OUT.csv]`.

use std::fmt::Write as _;

use anyhow::{Context, Result, bail};

use crate::args::Args;
use bezsolid_core::inverse::Method;
use bezsolid_core::model::ModelSolid;
use glam::{DVec2, DVec3};

/// The most points one call evaluates.
const MAX_POINTS: usize = 10_000_000;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let args = Args::parse("eval", args, &["--points", "--output"])?;
    let model = args.model("bezsolid eval MODEL --points FILE.csv")?;
    let points = args.required("--points", "--points FILE.csv")?;
    let out = args.value("--output");
    let solid = crate::load_model(model)?;
    let dim = match solid {
        ModelSolid::Patch(_) => 2,
        ModelSolid::Volume(_) => 3,
    };
    let text = crate::input::read_text(points, crate::input::MAX_POINTS_BYTES, "points file")?;
    let coords = parse_points(&text, dim).with_context(|| points.to_string())?;
    let csv = evaluate(&solid, &coords);
    match out {
        Some(path) => std::fs::write(path, csv).with_context(|| format!("cannot write {path}"))?,
        None => print!("{csv}"),
    }
    Ok(())
}

/// Points of `dim` coordinates, one per line, comma-separated. Blank lines and `#` comments are
/// skipped; a first line that is not numbers is taken as a header.
pub(crate) fn parse_points(text: &str, dim: usize) -> Result<Vec<Vec<f64>>> {
    let mut out = Vec::new();
    let mut first = true;
    for (no, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed: Result<Vec<f64>, _> = fields.iter().map(|f| f.parse::<f64>()).collect();
        let Ok(values) = parsed else {
            if first {
                first = false;
                continue;
            }
            bail!("line {}: not {dim} numbers: {line:?}", no + 1);
        };
        first = false;
        if values.len() != dim {
            bail!(
                "line {}: expected {dim} coordinates, found {}",
                no + 1,
                values.len()
            );
        }
        if !values.iter().all(|v| v.is_finite()) {
            bail!("line {}: coordinates must be finite numbers", no + 1);
        }
        if out.len() == MAX_POINTS {
            bail!("more than {MAX_POINTS} points");
        }
        out.push(values);
    }
    Ok(out)
}

/// The CSV: a header, then `x,y[,z],f,preimages` per point. On a regular grid the map is a scaling,
/// so a point has one preimage inside the (closed) domain box and none outside; a space mapping
/// counts the parameter points in the closed unit box that map to it (several where it folds).
fn evaluate(solid: &ModelSolid, points: &[Vec<f64>]) -> String {
    let mut csv = String::new();
    match solid {
        ModelSolid::Patch(s) => {
            csv.push_str("x,y,f,preimages\n");
            for p in points {
                let v = s.evaluate(DVec2::new(p[0], p[1]), Method::Fast);
                let _ = writeln!(csv, "{},{},{},{}", p[0], p[1], v.f, v.preimages);
            }
        }
        ModelSolid::Volume(s) => {
            csv.push_str("x,y,z,f,preimages\n");
            for p in points {
                let v = s.evaluate(DVec3::new(p[0], p[1], p[2]), Method::Fast);
                let _ = writeln!(csv, "{},{},{},{},{}", p[0], p[1], p[2], v.f, v.preimages);
            }
        }
    }
    csv
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_parse_with_header_comments_and_errors() {
        let pts = parse_points("x,y\n# c\n0.5, 0.25\n\n1,2\n", 2).unwrap();
        assert_eq!(pts, vec![vec![0.5, 0.25], vec![1.0, 2.0]]);
        assert!(parse_points("1,2,3\n", 2).is_err());
        assert!(parse_points("1,2\nx,y\n", 2).is_err());
        assert!(parse_points("1,NaN\n", 2).is_err());
        assert!(parse_points("1,inf\n", 2).is_err());
    }
}
