//! `bezsolid link MODEL [--base URL]`: the share link of a model (DESIGN §5).

use anyhow::{Context, Result, bail};
use bezsolid_core::model::SolidSpec;

use crate::args;

/// The page that `cargo xtask serve` serves.
const DEFAULT_BASE: &str = "http://127.0.0.1:8080/";

/// `bezsolid link`'s arguments.
#[derive(clap::Args)]
pub(crate) struct LinkArgs {
    #[command(flatten)]
    model: args::Model,
    #[arg(
        long,
        value_name = "URL",
        help = "The page's address the link starts with [default: http://127.0.0.1:8080/, the \
                page of `cargo xtask serve`]"
    )]
    base: Option<String>,
}

pub(crate) fn run(args: &LinkArgs) -> Result<()> {
    let model = args.model.get("link", "bezsolid link MODEL [--base URL]")?;
    let base = args.base.as_deref().unwrap_or(DEFAULT_BASE);
    if base.contains('#') {
        bail!("link: --base {base} already has a fragment ('#')");
    }
    let file = crate::load_file(model)?;
    // Validate as every reader will, so that a link printed here always opens.
    match file.solid {
        SolidSpec::Esc { .. } => file.to_boolean().map(drop),
        SolidSpec::Plasm { .. } => file.to_script().map(drop),
        SolidSpec::Hyperfun { .. } => file.to_hyperfun().map(drop),
        // One patch or volume, or a tree of many solids.
        _ => file.to_tree().map(drop),
    }
    .with_context(|| crate::describe(model))?;
    println!("{base}{}", bezsolid_core::link::encode(&file)?);
    Ok(())
}
