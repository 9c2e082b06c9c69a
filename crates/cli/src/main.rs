//! `bezsolid`: the command line of bezsolid (DESIGN §5).
//!
//! `bezsolid eval` evaluates a model's defining function, `contour` writes the zero contour of a 2D
//! model as SVG, `mesh` the closed boundary mesh of a 3D model as STL, OBJ, PLY, 3MF or GLB (a model is one
//! patch or volume, or a tree of many solids), and `hf` either
//! as HyperFun, and `link` prints the share link of a model; `esc` classifies points against
//! solids bounded by PN triangles over triangle meshes, and their Booleans; `plasm` runs a PLaSM
//! script and writes what it draws; `completions` writes shell completions; `bench` is `cargo
//! xtask bench` for now. Every command has `--help` with examples (clap); long meshes and
//! evaluations show a progress bar when stderr is a terminal.
//! Wherever a command takes a MODEL, a share link (the whole URL or its fragment) works too.
//! Errors go to stderr with a non-zero exit, in the words they have always had; bad input never
//! panics.

mod args;
mod contour;
mod esc;
mod eval;
mod hf;
mod input;
mod link;
mod mesh;
mod output;
mod plasm;
mod progress;

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use bezsolid_core::hyperfun::read::Program;
use bezsolid_core::model::{MAX_SCRIPT_BYTES, ModelFile, ModelSolid, SolidSpec};
use bezsolid_core::presets::Preset;
use clap::error::ErrorKind;
use clap::{CommandFactory, FromArgMatches, Parser};

/// The command line. Each command's options are in its module; its help and examples here.
#[derive(Parser)]
#[command(
    name = "bezsolid",
    version,
    about = "Evaluate, draw and export solids defined by Bézier patches and volumes (extended space \
             mapping), free-form solids over triangle meshes, and PLaSM scripts.",
    after_help = MORE,
    arg_required_else_help = true
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Subcommand)]
enum Command {
    /// The defining function f and the number of preimages at each point of a CSV file.
    #[command(
        long_about = "The defining function f and the number of preimages at each point: CSV \
                      x,y[,z],f,preimages, one row per point of FILE.csv (one point a line, at \
                      most 256 MiB and 10 million points). Rows are written as points are read, \
                      and a bad line stops the output there. A model may be one patch or volume, \
                      or a tree of many solids.",
        after_help = "Examples:\n  bezsolid eval preset:fig9 --points points.csv -o values.csv\n  \
                      bezsolid eval model.bsolid.json --points points.csv --inverse paper"
    )]
    Eval(eval::EvalArgs),
    /// The zero contour of a 2D model as SVG, or the true section of a 3D model by a plane.
    #[command(
        long_about = "The zero contour of a patch solid, a piecewise patch or a 2D tree as SVG; \
                      with --section, the true section of a 3D model by that plane, drawn in the \
                      plane's coordinates. With --stats, the area and perimeter of the region the \
                      contour bounds (exact for the contour).",
        after_help = "Examples:\n  bezsolid contour preset:fig9 -o fig9.svg\n  \
                      bezsolid contour preset:fish --res 512 --stats\n  \
                      bezsolid contour preset:blob --section z=0.25 -o section.svg"
    )]
    Contour(contour::ContourArgs),
    /// The closed boundary mesh of a 3D model as STL, OBJ, PLY, 3MF or GLB.
    #[command(
        long_about = "The closed boundary mesh of a volume solid, a piecewise volume, a 3D tree \
                      or a free-form model's result, as STL, OBJ or PLY, as 3MF for slicers (in \
                      millimetres, Z up) or as GLB (glTF 2.0) for viewers (in metres, +Y up). \
                      With --stats, the mesh's volume, area and bounding box on stdout (exact \
                      for the mesh, by the divergence theorem).",
        after_help = "Examples:\n  bezsolid mesh preset:blob -o blob.stl\n  \
                      bezsolid mesh preset:chair --res 128 -o chair.3mf\n  \
                      bezsolid mesh 'http://127.0.0.1:8080/#v1.…' -o shared.glb\n  \
                      bezsolid mesh preset:ring --stats"
    )]
    Mesh(mesh::MeshArgs),
    /// HyperFun code of any model.
    #[command(
        long_about = "HyperFun code of any model: the explicit Bernstein sum (a space-mapped \
                      solid with its inverse map), a piecewise solid's cells chosen by `if`s, a \
                      tree with HyperFun's set operations, blends and primitives. A 2D model is a \
                      prism along z, or with --height the extrusion 0 <= z <= H.",
        after_help = "Examples:\n  bezsolid hf preset:blob -o blob.hf\n  \
                      bezsolid hf preset:fig9 --height 0.2 -o fig9.hf"
    )]
    Hf(hf::HfArgs),
    #[command(about = "The share link of a model: the page's address and #v1.<model>")]
    #[command(after_help = "Examples:\n  bezsolid link preset:blob\n  \
                            bezsolid link model.bsolid.json --base https://example.org/bezsolid/")]
    Link(link::LinkArgs),
    /// Point-in-solid and Booleans of free-form solids bounded by PN triangles over closed meshes.
    #[command(
        long_about = "Point-in-solid and Booleans of the solids bounded by the PN triangles of \
                      closed triangle meshes (OBJ or STL), of built-in examples, or of free-form \
                      model files and links: one 0 or 1 per point.",
        after_help = "Examples:\n  bezsolid esc classify example:torus --points points.csv\n  \
                      bezsolid esc bool example:icosphere difference example:torus --points points.csv\n  \
                      bezsolid esc expr '!(A|B)-C' A=a.obj B=example:torus C=c.stl --points points.csv"
    )]
    Esc(esc::EscArgs),
    /// Run a PLaSM script and write what it draws.
    #[command(
        long_about = "Run a PLaSM script (the third paper's language) and write what its \
                      top-level expressions draw: OBJ with faces, lines and points, or the \
                      triangles as STL or PLY; without -o, print the value of each top-level \
                      expression.",
        after_help = "Examples:\n  bezsolid plasm example:4.4 -o surface.obj\n  \
                      bezsolid plasm script.psm"
    )]
    Plasm(plasm::PlasmArgs),
    /// Shell completions for bezsolid, on stdout.
    #[command(
        after_help = "Examples:\n  bezsolid completions bash > ~/.local/share/bash-completion/completions/bezsolid\n  \
                      bezsolid completions zsh > ~/.zfunc/_bezsolid\n  \
                      bezsolid completions fish > ~/.config/fish/completions/bezsolid.fish"
    )]
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Benchmarks: run `cargo xtask bench` in the repository.
    #[command(hide = true)]
    Bench,
}

/// What the help says after the commands.
const MORE: &str = "MODEL is a model file (.bsolid.json: one patch or volume, or a tree of many \
solids: primitives, Bézier solids, set operations, blends, morphs and transforms), a share link \
(the whole URL or its #v1. fragment; quote it in the shell), a HyperFun file bezsolid exported \
(.hf: it carries its model; `eval`, and `mesh` and `contour --section` within --box, also take \
any HyperFun program, read as HyperFun reads it, and a model file or link of kind hyperfun, its \
box the default --box) or a \
preset: preset:fig9, \
preset:blob, preset:ring, preset:fish, and the zoo's preset:chair, preset:vase, preset:knot, \
preset:shell, preset:koi, preset:tooth. MESH, A and B are mesh files or built-in examples: \
example:icosphere, example:torus, example:blob, or free-form model files or links (`mesh` writes \
the surface of a free-form model's result); SOLID likewise. SCRIPT is a script file (.psm), a \
model file or link holding one, or one of the paper's examples: example:3.1, example:3.3, \
example:4.1, example:4.4, example:4.6, example:4.7, example:4.8, example:4.7-bezier-grid.

Inputs are read up to a cap, whatever they are (files, pipes, devices): a model file 16 MiB, a \
script file 256 KiB, a HyperFun file 32 MiB, a mesh file 128 MiB, a points file 256 MiB.

Run `bezsolid <command> --help` for a command's options and examples.";

/// The command line's parser, with the settings every command keeps ([`args::settle`]).
fn command() -> clap::Command {
    args::settle(Cli::command())
}

fn main() -> ExitCode {
    let raw: Vec<String> = std::env::args().skip(1).collect();
    let matches = match command()
        .try_get_matches_from(std::iter::once("bezsolid".into()).chain(raw.iter().cloned()))
    {
        Ok(matches) => matches,
        Err(e) if !e.use_stderr() => {
            // --help and --version, on stdout.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            return ExitCode::from(2);
        }
        Err(e) => {
            let usage = command().render_help();
            let refusal = args::refusal(&e, &raw, &usage.to_string());
            eprintln!("bezsolid: {}", refusal.message);
            return ExitCode::from(refusal.code);
        }
    };
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => {
            eprintln!("bezsolid: {e}");
            return ExitCode::FAILURE;
        }
    };
    match cli.command {
        Command::Eval(a) => report(eval::run(&a)),
        Command::Contour(a) => report(contour::run(&a)),
        Command::Mesh(a) => report(mesh::run(&a)),
        Command::Hf(a) => report(hf::run(&a)),
        Command::Link(a) => report(link::run(&a)),
        Command::Esc(a) => report(esc::run(&a)),
        Command::Plasm(a) => report(plasm::run(&a)),
        Command::Completions { shell } => {
            // Written whole, so that a closed pipe is an error here, not a panic in the generator.
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut command(), "bezsolid", &mut script);
            report(
                std::io::Write::write_all(&mut std::io::stdout().lock(), &script)
                    .map_err(|e| anyhow::anyhow!("cannot write stdout: {e}")),
            )
        }
        Command::Bench => {
            eprintln!(
                "bezsolid: `bench` is not in this build; run `cargo xtask bench` in the repository"
            );
            ExitCode::FAILURE
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

/// Says on stderr that `count` evaluations of `f` ran out of their work budget (a net that folds
/// over itself very many times), so that a drawing made of them may miss pieces.
pub(crate) fn warn_exhausted(count: usize) {
    if count > 0 {
        eprintln!(
            "bezsolid: warning: the net folds over itself so often that {count} evaluations \
             reached the work limit of a query; pieces of the drawing may be missing"
        );
    }
}

/// How messages name the model `arg`: its path, or for a link (too long to quote) what it is.
pub(crate) fn describe(arg: &str) -> String {
    if is_link(arg) {
        "the share link's model".into()
    } else {
        arg.into()
    }
}

/// The model file named by `arg` (a path, a share link or a preset), not yet validated. A PLaSM
/// script file (`.psm`) is read as the model file holding it.
pub(crate) fn load_file(arg: &str) -> Result<ModelFile> {
    if let Some(name) = arg.strip_prefix("preset:") {
        return Ok(match preset(name)?.solid() {
            ModelSolid::Patch(s) => ModelFile::from_solid2(&s),
            ModelSolid::Volume(s) => ModelFile::from_solid3(&s),
        });
    }
    if is_link(arg) {
        // Every link error says that it is about the link.
        return Ok(bezsolid_core::link::decode_file(arg)?);
    }
    if Path::new(arg)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("psm"))
    {
        let cap = MAX_SCRIPT_BYTES as u64;
        return Ok(ModelFile::from_plasm(&input::read_text(
            arg, cap, "script",
        )?));
    }
    if is_hyperfun(arg) {
        let text = read_hyperfun(arg)?;
        return carried(arg, &text).unwrap_or_else(|| {
            anyhow::bail!(
                "{arg} is a HyperFun program that carries no bezsolid model (bezsolid's exports \
                 carry theirs, unless it was too large): `bezsolid eval` evaluates it as HyperFun \
                 reads it"
            )
        });
    }
    let text = input::read_text(arg, input::MAX_MODEL_BYTES, "model file")?;
    serde_json::from_str(&text).with_context(|| format!("{arg} is not a valid model file"))
}

/// The bezsolid model the text of the HyperFun file `arg` carries; `None` where it carries none.
fn carried(arg: &str, text: &str) -> Option<Result<ModelFile>> {
    Some(bezsolid_core::hyperfun::model_of(text)?.map_err(|e| {
        anyhow::anyhow!("{arg}: the bezsolid model this HyperFun file carries does not open: {e}")
    }))
}

/// Whether `arg` names a HyperFun file (`.hf`).
pub(crate) fn is_hyperfun(arg: &str) -> bool {
    !is_link(arg)
        && Path::new(arg)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("hf"))
}

/// A MODEL of the commands that take a HyperFun program too (`eval`, `mesh`, `contour`).
pub(crate) enum Opened {
    /// A HyperFun program, parsed: that of a HyperFun file that carries no bezsolid model (no
    /// box: `None`), or of a model file or link of kind `hyperfun`, with its box (the file's, or
    /// the default box where it gives none).
    Program(Program, Option<([f64; 3], [f64; 3])>),
    /// Any other model ([`load_file`]), the model a bezsolid export carries included; not yet
    /// validated.
    Model(ModelFile),
}

/// Opens `arg` as [`load_file`] does, where a HyperFun program may stand for a model; the file is
/// read once.
pub(crate) fn open(arg: &str) -> Result<Opened> {
    let file = if is_hyperfun(arg) {
        let text = read_hyperfun(arg)?;
        match carried(arg, &text) {
            Some(file) => file?,
            None => {
                return Program::parse(&text)
                    .map(|program| Opened::Program(program, None))
                    .map_err(|e| anyhow::anyhow!("{arg}: {e}"));
            }
        }
    } else {
        load_file(arg)?
    };
    if !matches!(file.solid, SolidSpec::Hyperfun { .. }) {
        return Ok(Opened::Model(file));
    }
    let (text, [lo, hi]) = file.to_hyperfun().with_context(|| describe(arg))?;
    let program = Program::parse(text).map_err(|e| anyhow::anyhow!("{}: {e}", describe(arg)))?;
    Ok(Opened::Program(program, Some((lo, hi))))
}

/// The text of the HyperFun file `arg`, within the reader's cap.
fn read_hyperfun(arg: &str) -> Result<String> {
    let cap = bezsolid_core::hyperfun::read::MAX_SOURCE_BYTES as u64;
    input::read_text(arg, cap, "HyperFun file")
}

fn preset(name: &str) -> Result<Preset> {
    let names: Vec<&str> = Preset::ALL.iter().map(|p| p.name()).collect();
    Preset::from_name(name)
        .with_context(|| format!("no preset `{name}`; the presets are {}", names.join(", ")))
}

/// Whether `arg` is a share link rather than a path: it has a fragment, is a web address, or is a
/// bare `v<N>.` fragment that names no file.
pub(crate) fn is_link(arg: &str) -> bool {
    arg.contains('#')
        || arg.starts_with("http://")
        || arg.starts_with("https://")
        || (arg.starts_with('v')
            && arg[1..]
                .split_once('.')
                .is_some_and(|(n, _)| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
            && !Path::new(arg).exists())
}
