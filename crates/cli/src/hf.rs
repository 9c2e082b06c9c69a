//! `bezsolid hf MODEL -o OUT.hf`: HyperFun export.

use anyhow::{Context, Result, bail};
use bezsolid_core::hyperfun::{solid2_hf, solid3_hf};
use bezsolid_core::model::ModelSolid;

pub(crate) fn run(args: &[String]) -> Result<()> {
    let mut model = None;
    let mut out = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "-o" | "--output" => out = Some(it.next().context("-o needs a file")?),
            s if s.starts_with('-') && s.len() > 1 => bail!("hf: unknown option {s}"),
            s if model.is_none() => model = Some(s),
            s => bail!("hf: unexpected argument {s}"),
        }
    }
    let model = model.context("hf: which model? usage: bezsolid hf MODEL -o OUT.hf")?;
    let out = out.context("hf: -o OUT.hf is required")?;
    let text = match crate::load_model(model)? {
        ModelSolid::Patch(s) => solid2_hf(&s),
        ModelSolid::Volume(s) => solid3_hf(&s),
    };
    std::fs::write(out, text).with_context(|| format!("cannot write {out}"))?;
    eprintln!("bezsolid: HyperFun model written to {out}");
    Ok(())
}
