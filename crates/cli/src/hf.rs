//! `bezsolid hf MODEL -o OUT.hf`: HyperFun export of a regular patch or volume, or of a tree of many
//! solids (its regular Bézier leaves as the explicit Bernstein sum).

use anyhow::{Context, Result};

use crate::args::Args;
use bezsolid_core::hyperfun::{solid2_hf, solid3_hf, tree_hf};
use bezsolid_core::model::ModelSolid;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let args = Args::parse("hf", args, &["--output"])?;
    let model = args.model("bezsolid hf MODEL -o OUT.hf")?;
    let out = args.required("--output", "-o OUT.hf")?;
    let file = crate::load_file(model)?;
    let text = if file.solid.is_tree() {
        tree_hf(&file).with_context(|| crate::describe(model))?
    } else {
        match file.to_solid().with_context(|| crate::describe(model))? {
            ModelSolid::Patch(s) => solid2_hf(&s),
            ModelSolid::Volume(s) => solid3_hf(&s),
        }?
    };
    std::fs::write(out, text).with_context(|| format!("cannot write {out}"))?;
    eprintln!("bezsolid: HyperFun model written to {out}");
    Ok(())
}
