//! `bezsolid contour MODEL --res N -o OUT.svg [--accuracy A] [--box X0,Y0,X1,Y1] [--stats]`: the
//! zero contour of a patch solid, or of a 2D tree of many solids (within its bounds, or within the
//! box); with `--section x=C` (or `y=`, `z=`), the true section of a 3D model by that plane. With
//! `--stats` (and then `-o` may be left out) the area and perimeter inside the contour are printed
//! on stdout.

use anyhow::{Context, Result, bail};

use crate::args;
use bezsolid_core::contour::{Measure, Polyline, solid_contour};
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::ModelSolid;
use bezsolid_core::tree::{ModelTree, TreeMeshError};
use glam::DVec2;

/// The largest `--res`: 4096² samples is already 16 M evaluations.
const MAX_RES: usize = 4096;

/// `bezsolid contour`'s arguments.
#[derive(clap::Args)]
pub(crate) struct ContourArgs {
    #[command(flatten)]
    model: args::Model,
    /// The SVG file. May be left out with --stats.
    #[arg(short = 'o', long = "output", value_name = "OUT.svg")]
    output: Option<String>,
    /// Cells per side of the sampled square [default: 256; 2 to 4096].
    #[arg(long, value_name = "N")]
    res: Option<usize>,
    /// Vertices are refined until |f| <= A [default: 1e-9].
    #[arg(long, value_name = "A")]
    accuracy: Option<f64>,
    /// The box a tree is drawn within; needed by one that may be unbounded (a half-plane). With
    /// --section, X0,Y0,Z0,X1,Y1,Z1.
    #[arg(long = "box", value_name = "X0,Y0,X1,Y1")]
    region: Option<String>,
    /// The true section of a 3D model by the plane x=C, y=C or z=C, in the plane's coordinates.
    #[arg(long, value_name = "x=C|y=C|z=C")]
    section: Option<String>,
    /// Print `area: A` and `perimeter: P` of the region the contour bounds on stdout.
    #[arg(long)]
    stats: bool,
}

pub(crate) fn run(args: &ContourArgs) -> Result<()> {
    let model = args
        .model
        .get("contour", "bezsolid contour MODEL --res N -o OUT.svg")?;
    let res = args.res.unwrap_or(256);
    let out = Output {
        path: match args.output.as_deref() {
            Some(out) => Some(out),
            None if args.stats => None,
            None => Some(args::required("contour", None::<&str>, "-o OUT.svg")?),
        },
        stats: args.stats,
        res,
    };
    let accuracy = args.accuracy.unwrap_or(1e-9);
    if !(2..=MAX_RES).contains(&res) {
        bail!("--res {res} is outside 2..={MAX_RES}");
    }
    if !(accuracy.is_finite() && accuracy > 0.0) {
        bail!("--accuracy must be a positive number");
    }
    let file = match crate::open(model)? {
        crate::Opened::Program(program, bounds) => {
            return hyperfun_section(args, model, &program, bounds, res, accuracy, &out);
        }
        crate::Opened::Model(file) => file,
    };
    if let Some(plane) = args.section.as_deref() {
        return section(args, model, &file, plane, res, accuracy, &out);
    }
    if file.solid.is_tree() {
        let region = args::bounds::<2>("--box", args.region.as_deref())?;
        let ModelTree::Plane(tree) = file.to_tree().with_context(|| crate::describe(model))? else {
            bail!("contour draws 2D models; for a 3D tree use `bezsolid mesh`");
        };
        let lines = match tree.contour(res, accuracy, region) {
            Err(TreeMeshError::Unbounded) => bail!(
                "{}: the model may be unbounded (a half-plane, a morph past 0..1 or a blend of a \
                 space-mapped solid): draw it within --box X0,Y0,X1,Y1",
                crate::describe(model)
            ),
            other => other.with_context(|| crate::describe(model))?,
        };
        let (lo, hi) = region
            .or(tree.bounds())
            .map_or((DVec2::ZERO, DVec2::ONE), |(lo, hi)| {
                (DVec2::from_array(lo), DVec2::from_array(hi))
            });
        return out.write(&lines, lo, hi, "");
    }
    let ModelSolid::Patch(solid) = file.to_solid().with_context(|| crate::describe(model))? else {
        bail!("contour draws patch (2D) models; for a volume use `bezsolid mesh`");
    };
    let (lo, hi) = solid.domain();
    let lines = solid_contour(&solid, res, accuracy);
    crate::warn_exhausted(solid.exhausted());
    out.write(&lines, lo, hi, "")
}

/// Where the contour goes: the SVG file, the measurements on stdout, or both.
struct Output<'a> {
    path: Option<&'a str>,
    stats: bool,
    /// Cells per side of what was sampled (the SVG's margin is one of them).
    res: usize,
}

impl Output<'_> {
    /// Writes `lines`, drawn over `[lo, hi]`, as SVG and says so (`what` names a section), and
    /// prints their measurements with `--stats`.
    fn write(&self, lines: &[Polyline], lo: DVec2, hi: DVec2, what: &str) -> Result<()> {
        let measure = Measure::of(lines);
        if let Some(out) = self.path {
            let cell = (hi - lo) / self.res as f64;
            std::fs::write(out, contours_svg(lines, lo - cell, hi + cell))
                .with_context(|| format!("cannot write {out}"))?;
            eprintln!(
                "bezsolid: {what}{} contour pieces{} written to {out}",
                lines.len(),
                if what.is_empty() {
                    String::new()
                } else {
                    format!(", area {:.6},", measure.area)
                }
            );
        }
        if self.stats {
            println!("area: {}", measure.area);
            println!("perimeter: {}", measure.perimeter);
            eprintln!(
                "bezsolid: measured on the contour at --res {} (exact for its polylines; a finer \
                 --res comes nearer the solid)",
                self.res
            );
            if measure.open > 0 {
                eprintln!(
                    "bezsolid: warning: {} open contour pieces end on the sampled box and bound \
                     nothing; they are left out of the area and perimeter (a larger --box closes \
                     them)",
                    measure.open
                );
            }
        }
        Ok(())
    }
}

/// The plane of `--section x=C` (or `y=`, `z=`): its axis and coordinate.
fn parse_plane(plane: &str) -> Result<(usize, f64)> {
    let parsed = plane.split_once('=').and_then(|(name, at)| {
        let axis = ["x", "y", "z"].iter().position(|a| *a == name.trim())?;
        let at: f64 = at.trim().parse().ok().filter(|v: &f64| v.is_finite())?;
        Some((axis, at))
    });
    parsed.ok_or_else(|| {
        anyhow::anyhow!("--section {plane}: a plane is x=C, y=C or z=C with C a finite number")
    })
}

/// `--section x=C` of a HyperFun program (not a bezsolid export), within the box it needs (a
/// program has no bounds of its own: `--box`, else the box its model file gives, `default`): its
/// zero contour in the plane, as HyperFun evaluates it.
fn hyperfun_section(
    args: &ContourArgs,
    path: &str,
    program: &bezsolid_core::hyperfun::read::Program,
    default: Option<([f64; 3], [f64; 3])>,
    res: usize,
    accuracy: f64,
    out: &Output<'_>,
) -> Result<()> {
    use glam::DVec3;
    let path = crate::describe(path);
    let Some(plane) = args.section.as_deref() else {
        bail!(
            "{path}: a HyperFun program is 3D: draw its section with --section x=C, y=C or z=C{}",
            if default.is_some() {
                ""
            } else {
                " within --box X0,Y0,Z0,X1,Y1,Z1"
            }
        );
    };
    let (axis, at) = parse_plane(plane)?;
    let Some((lo, hi)) = args::bounds::<3>("--box", args.region.as_deref())?.or(default) else {
        bail!(
            "{path}: a HyperFun program has no bounds of its own: cut it within \
             --box X0,Y0,Z0,X1,Y1,Z1"
        );
    };
    let (lo, hi) = (DVec3::from_array(lo), DVec3::from_array(hi));
    let lines = bezsolid_core::hyperfun::field::section(program, axis, at, lo, hi, res, accuracy)
        .map_err(|e| anyhow::anyhow!("{path}: {e}"))?;
    let [a, b] = bezsolid_core::tree::plane_axes(axis);
    let (lo, hi) = (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b]));
    out.write(&lines, lo, hi, &format!("the section {plane}: "))
}

/// `--section x=C`: the true section of a 3D model (a volume, a piecewise volume or a 3D tree) by
/// the plane, drawn in the plane's coordinates (`y, z` across x, `x, z` across y, `x, y` across z).
fn section(
    args: &ContourArgs,
    model: &str,
    file: &bezsolid_core::model::ModelFile,
    plane: &str,
    res: usize,
    accuracy: f64,
    out: &Output<'_>,
) -> Result<()> {
    let (axis, at) = parse_plane(plane)?;
    let region = args::bounds::<3>("--box", args.region.as_deref())?;
    let ModelTree::Space(tree) = file.to_tree().with_context(|| crate::describe(model))? else {
        bail!("--section cuts 3D models; this is a 2D model: draw its contour without it");
    };
    let lines = match tree.section(axis, at, res, accuracy, region) {
        Err(TreeMeshError::Unbounded) => bail!(
            "{}: the model may be unbounded (a half-space, a cylinder, a morph past 0..1 or a \
             blend of a space-mapped solid): cut it within --box X0,Y0,Z0,X1,Y1,Z1",
            crate::describe(model)
        ),
        other => other.with_context(|| crate::describe(model))?,
    };
    let [a, b] = bezsolid_core::tree::plane_axes(axis);
    let (lo, hi) = region
        .or(tree.bounds())
        .map_or((DVec2::ZERO, DVec2::ONE), |(lo, hi)| {
            (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b]))
        });
    out.write(&lines, lo, hi, &format!("the section {plane}: "))
}
