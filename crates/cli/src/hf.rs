//! `bezsolid hf MODEL -o OUT.hf [--height H]`: HyperFun export of any patch or volume (a regular one
//! as the explicit Bernstein sum, a space-mapped one with its inverse map written in HyperFun), or
//! of a tree of many solids; a 2D model is a prism along z, or with `--height` the extrusion from
//! z = 0 to z = H.

use anyhow::{Context, Result, bail};

use crate::args;
use bezsolid_core::hyperfun::{extruded, solid2_hf, solid3_hf, tree_hf};
use bezsolid_core::model::ModelSolid;

/// `bezsolid hf`'s arguments.
#[derive(clap::Args)]
pub(crate) struct HfArgs {
    #[command(flatten)]
    model: args::Model,
    /// The HyperFun file.
    #[arg(short = 'o', long = "output", value_name = "OUT.hf")]
    output: Option<String>,
    /// A 2D model extruded from z = 0 to z = H (without it, a prism along z).
    #[arg(long, value_name = "H")]
    height: Option<String>,
}

pub(crate) fn run(args: &HfArgs) -> Result<()> {
    let model = args.model.get("hf", "bezsolid hf MODEL -o OUT.hf")?;
    let out = args::required("hf", args.output.as_deref(), "-o OUT.hf")?;
    let file = crate::load_file(model)?;
    let text = if file.solid.is_tree() {
        tree_hf(&file).with_context(|| crate::describe(model))?
    } else {
        match file.to_solid().with_context(|| crate::describe(model))? {
            ModelSolid::Patch(s) => solid2_hf(&s),
            ModelSolid::Volume(s) => solid3_hf(&s),
        }?
    };
    let text = match args.height.as_deref() {
        None => text,
        Some(h) => {
            // Parsed here, so that refusals quote it as typed.
            let Ok(height) = h.parse::<f64>() else {
                bail!("--height {h} is not a valid number here");
            };
            if !(height.is_finite() && height > 0.0) {
                bail!("--height {h}: the extrusion's height is a positive number");
            }
            match extruded(&text, height) {
                Some(slab) => slab,
                None => bail!("--height extrudes 2D models; {model} is a 3D model"),
            }
        }
    };
    std::fs::write(out, text).with_context(|| format!("cannot write {out}"))?;
    eprintln!("bezsolid: HyperFun model written to {out}");
    Ok(())
}
