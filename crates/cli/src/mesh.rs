//! `bezsolid mesh MODEL [--res N] -o OUT.{stl,obj,ply} [--accuracy A]`: the closed boundary mesh of a
//! volume solid.

use anyhow::{Context, Result, bail};
use bezsolid_core::mesh::{MAX_RESOLUTION, obj, ply, stl};
use bezsolid_core::model::ModelSolid;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let mut model = None;
    let mut res = 64usize;
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
            s if s.starts_with('-') && s.len() > 1 => bail!("mesh: unknown option {s}"),
            s if model.is_none() => model = Some(s),
            s => bail!("mesh: unexpected argument {s}"),
        }
    }
    let model =
        model.context("mesh: which model? usage: bezsolid mesh MODEL --res N -o OUT.stl")?;
    let out = out.context("mesh: -o OUT.stl, OUT.obj or OUT.ply is required")?;
    let ext = std::path::Path::new(out)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let Some(ext @ ("stl" | "obj" | "ply")) = ext.as_deref() else {
        bail!("mesh: {out} should end in .stl, .obj or .ply");
    };
    if !(1..=MAX_RESOLUTION).contains(&res) {
        bail!("--res {res} is outside 1..={MAX_RESOLUTION}");
    }
    let ModelSolid::Volume(solid) = crate::load_model(model)? else {
        bail!("mesh polygonizes volume (3D) models; for a patch use `bezsolid contour`");
    };
    let mesh = solid.polygonize(res, accuracy)?;
    let bytes = match ext {
        "stl" => stl::write_stl(&mesh),
        "obj" => obj::write_obj(&mesh).into_bytes(),
        _ => ply::write_ply(&mesh),
    };
    std::fs::write(out, bytes).with_context(|| format!("cannot write {out}"))?;
    eprintln!(
        "bezsolid: {} triangles, {} vertices written to {out}",
        mesh.triangle_count(),
        mesh.positions.len()
    );
    Ok(())
}
