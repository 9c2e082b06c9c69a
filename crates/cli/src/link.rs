//! `bezsolid link MODEL [--base URL]`: the share link of a model (DESIGN §5).

use anyhow::{Context, Result, bail};
use bezsolid_core::model::SolidSpec;

use crate::args::Args;

/// The page that `cargo xtask serve` serves.
const DEFAULT_BASE: &str = "http://127.0.0.1:8080/";

pub(crate) fn run(args: &[String]) -> Result<()> {
    let args = Args::parse("link", args, &["--base"])?;
    let model = args.model("bezsolid link MODEL [--base URL]")?;
    let base = args.value("--base").unwrap_or(DEFAULT_BASE);
    if base.contains('#') {
        bail!("link: --base {base} already has a fragment ('#')");
    }
    let file = crate::load_file(model)?;
    // Validate as every reader will, so that a link printed here always opens.
    match file.solid {
        SolidSpec::Esc { .. } => file.to_boolean().map(drop),
        SolidSpec::Plasm { .. } => file.to_script().map(drop),
        // One patch or volume, or a tree of many solids.
        _ => file.to_tree().map(drop),
    }
    .with_context(|| crate::describe(model))?;
    println!("{base}{}", bezsolid_core::link::encode(&file)?);
    Ok(())
}
