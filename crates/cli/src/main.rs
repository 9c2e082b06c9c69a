//! `bezsolid`: the command line of bezsolid (DESIGN §5).
//!
//! `bezsolid eval` evaluates a model's defining function, `contour` writes the zero contour of a patch
//! model as SVG, `mesh` the closed boundary mesh of a volume model as STL, OBJ or PLY, and `hf` either
//! as HyperFun; `link` and `bench` come with later work and answer with a clear error until then.
//! Errors go to stderr with a non-zero exit; bad input never panics.

mod args;
mod contour;
mod eval;
mod hf;
mod mesh;

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use bezsolid_core::model::{ModelFile, ModelSolid};
use bezsolid_core::presets::Preset;

const USAGE: &str = "usage: bezsolid <command> [options]

commands (DESIGN §5):
  eval MODEL --points FILE.csv [-o OUT.csv]
                                   f and the number of preimages per point: CSV x,y[,z],f,preimages
  contour MODEL [--res N] -o OUT.svg [--accuracy A]
                                   zero contours of a patch solid (N cells per side, default
                                   256; vertices refined to |f| <= A, default 1e-9)
  mesh MODEL [--res N] -o OUT.{stl,obj,ply} [--accuracy A]
                                   closed boundary mesh of a volume solid (N cells along the
                                   longest side, default 64; vertices refined to |f| <= A,
                                   default 1e-9)
  hf MODEL -o OUT.hf               HyperFun export (the explicit Bernstein sum)
  link MODEL                       print the share link                (not in this build yet)
  bench                            benchmarks                          (not in this build yet)

MODEL is a model file (.bsolid.json) or a preset: preset:fig9, preset:blob, preset:ring,
preset:fish.

options:
  -h, --help       this text
  -V, --version    the version
";

/// The largest model file read (a degree-16 volume with long decimals is well under 1 MiB).
const MAX_MODEL_BYTES: u64 = 16 << 20;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        None => {
            eprint!("{USAGE}");
            ExitCode::from(2)
        }
        Some("-h" | "--help" | "help") => {
            print!("{USAGE}");
            ExitCode::SUCCESS
        }
        Some("-V" | "--version") => {
            println!("bezsolid {}", env!("CARGO_PKG_VERSION"));
            ExitCode::SUCCESS
        }
        Some("eval") => report(eval::run(&args[1..])),
        Some("contour") => report(contour::run(&args[1..])),
        Some("mesh") => report(mesh::run(&args[1..])),
        Some("hf") => report(hf::run(&args[1..])),
        Some(cmd @ ("link" | "bench")) => {
            eprintln!("bezsolid: `{cmd}` is not available in this build yet");
            ExitCode::FAILURE
        }
        Some(other) => {
            eprintln!("bezsolid: unknown command `{other}`\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}

fn report(result: Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bezsolid: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Reads and validates a model file, or names a preset (`preset:NAME`).
pub(crate) fn load_model(arg: &str) -> Result<ModelSolid> {
    if let Some(name) = arg.strip_prefix("preset:") {
        let names: Vec<&str> = Preset::ALL.iter().map(|p| p.name()).collect();
        return Preset::from_name(name)
            .map(Preset::solid)
            .with_context(|| format!("no preset `{name}`; the presets are {}", names.join(", ")));
    }
    if arg.contains("#v1.") {
        bail!("share links are not supported by this build yet; pass a model file");
    }
    let path = Path::new(arg);
    let size = std::fs::metadata(path)
        .with_context(|| format!("cannot read {arg}"))?
        .len();
    if size > MAX_MODEL_BYTES {
        bail!("{arg} is {size} bytes; a model file is at most {MAX_MODEL_BYTES}");
    }
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {arg}"))?;
    let file: ModelFile =
        serde_json::from_str(&text).with_context(|| format!("{arg} is not a valid model file"))?;
    file.to_solid().with_context(|| arg.to_string())
}
