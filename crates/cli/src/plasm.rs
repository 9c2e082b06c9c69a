//! `bezsolid plasm SCRIPT [-o OUT.{obj,stl,ply}]`: runs a PLaSM script (the third paper's language) and writes what
//! its top-level expressions draw.

use anyhow::{Context, Result, bail};
use bezsolid_core::mesh::Format;
use bezsolid_plasm::mesh::export;
use bezsolid_plasm::{Complex, Interp, scripts};

use crate::args;

const USAGE: &str = "bezsolid plasm SCRIPT [-o OUT.obj]";

/// `bezsolid plasm`'s arguments.
#[derive(clap::Args)]
pub(crate) struct PlasmArgs {
    /// The script: a .psm file, a model file or share link holding one, or example:ID.
    #[arg(value_name = "SCRIPT")]
    script: Option<String>,
    /// Where the drawing goes: .obj (faces, lines and points), .stl or .ply (the triangles).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<String>,
}

pub(crate) fn run(args: &PlasmArgs) -> Result<()> {
    let arg = args::model("plasm", args.script.as_deref(), USAGE)?;
    let script = load(arg)?;
    let mut interp = Interp::new();
    let run = interp.run(&script);
    for w in &run.warnings {
        eprintln!("bezsolid: warning: {w}");
    }
    let name = crate::describe(arg);
    let out = args.output.as_deref();
    // Values are printed as a console would: all of them, or with -o those that are not drawn.
    for s in &run.shown {
        if out.is_none() || s.value.as_pol().is_none() {
            println!("line {}: {}", s.span.line, s.value);
        }
    }
    if let Some(e) = &run.error {
        bail!("{name}: {e}");
    }
    let complexes: Vec<&Complex> = run.shown.iter().filter_map(|s| s.value.as_pol()).collect();
    let Some(out) = out else {
        return Ok(());
    };
    if complexes.is_empty() {
        bail!("plasm: {name} draws nothing (no top-level expression gives a complex)");
    }
    let Some(format) = Format::of_path(out) else {
        bail!("plasm: {out} should end in .obj, .stl or .ply");
    };
    let Ok(bytes) = export(complexes.iter().copied(), format) else {
        bail!("plasm: {name} draws no triangles (only curves or points): write an .obj");
    };
    std::fs::write(out, bytes).with_context(|| format!("cannot write {out}"))?;
    let cells: usize = complexes.iter().map(|c| c.cell_count()).sum();
    eprintln!(
        "bezsolid: {} complexes, {cells} cells written to {out} ({} steps)",
        complexes.len(),
        run.steps
    );
    Ok(())
}

/// The script named by `arg`: `example:ID` (the paper's, e.g. `example:4.4`), a script file, or
/// a model file or share link holding a script.
fn load(arg: &str) -> Result<String> {
    if let Some(id) = arg.strip_prefix("example:") {
        let ids: Vec<&str> = scripts::EXAMPLES.iter().map(|e| e.id).collect();
        return scripts::example(id)
            .map(scripts::Example::source)
            .with_context(|| format!("no example `{id}`; the examples are {}", ids.join(", ")));
    }
    let file = crate::load_file(arg)?;
    Ok(file
        .to_script()
        .with_context(|| crate::describe(arg))?
        .to_string())
}
