//! `bezsolid`: the command line of bezsolid (DESIGN §5).
//!
//! `bezsolid eval` evaluates a model's defining function, `contour` writes the zero contour of a 2D
//! model as SVG, `mesh` the closed boundary mesh of a 3D model as STL, OBJ, PLY, 3MF or GLB (a model is one
//! patch or volume, or a tree of many solids), and `hf` either
//! as HyperFun, and `link` prints the share link of a model; `esc` classifies points against
//! solids bounded by PN triangles over triangle meshes, and their Booleans; `plasm` runs a PLaSM
//! script and writes what it draws; `bench` is `cargo xtask bench` for now.
//! Wherever a command takes a MODEL, a share link (the whole URL or its fragment) works too.
//! Errors go to stderr with a non-zero exit; bad input never panics.

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

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use bezsolid_core::model::{MAX_SCRIPT_BYTES, ModelFile, ModelSolid};
use bezsolid_core::presets::Preset;

const USAGE: &str = "usage: bezsolid <command> [options]

commands (DESIGN §5):
  eval MODEL --points FILE.csv [-o OUT.csv] [--inverse paper|clip|fast]
                                   f and the number of preimages per point: CSV x,y[,z],f,preimages
                                   (FILE.csv: one point a line, at most 256 MiB and 10 million
                                   points; rows are written as points are read, and a bad line
                                   stops the output there; moved points are inverted by
                                   the paper's spline guess and Bézier clipping, by clipping
                                   over the whole domain, or by seeded Newton, the default)
  contour MODEL [--res N] -o OUT.svg [--accuracy A] [--box X0,Y0,X1,Y1]
          [--section x=C|y=C|z=C] [--stats]
                                   zero contours of a patch solid, a piecewise patch or a 2D
                                   tree (N cells per side, default 256; vertices refined to
                                   |f| <= A, default 1e-9; a tree that may be unbounded needs
                                   --box); with --section, the true section of a 3D model by
                                   that plane, in the plane's coordinates (--box X0,Y0,Z0,X1,
                                   Y1,Z1 for one that may be unbounded); --stats prints
                                   `area: A` and `perimeter: P` of the region the contour
                                   bounds on stdout (exact for the contour; -o may be left out)
  mesh MODEL [--res N] -o OUT.{stl,obj,ply,3mf,glb} [--accuracy A]
       [--box X0,Y0,Z0,X1,Y1,Z1] [--threads T] [--stats]
                                   closed boundary mesh of a volume solid, a piecewise volume
                                   or a 3D tree (N cells along the longest side, default 64;
                                   vertices refined to |f| <= A, default 1e-9; a tree that may
                                   be unbounded, such as a half-space, needs --box, and is cut
                                   by it; meshed on T threads, default every core: the same
                                   mesh as on one); --stats prints `volume: V`, `area: A` and
                                   `bbox: X0 Y0 Z0 X1 Y1 Z1` of the mesh on stdout (exact for
                                   the mesh, by the divergence theorem; -o may be left out);
                                   3MF for slicers in millimetres, Z up; GLB (glTF 2.0) for
                                   viewers in metres, +Y up
  hf MODEL -o OUT.hf [--height H]  HyperFun export (the explicit Bernstein sum; a piecewise
                                   solid's cells chosen by `if`s; a tree with HyperFun's set
                                   operations, blends and primitives); a 2D model is a prism
                                   along z, or with --height the extrusion 0 <= z <= H
  link MODEL [--base URL]          print the share link: URL (default http://127.0.0.1:8080/,
                                   the page of `cargo xtask serve`) + #v1.<model>
  esc classify MESH --points FILE.csv [-o OUT]
                                   point-in-solid for the solid bounded by the PN triangles of
                                   a closed triangle mesh (OBJ or STL): one 0 or 1 per point
  esc bool A OP B --points FILE.csv [-o OUT]
                                   the same for A OP B, OP one of union, intersection,
                                   difference; `esc bool complement A` for A's complement
  esc expr \"EXPR\" NAME=SOLID... --points FILE.csv [-o OUT]
                                   the same for an expression of many solids: names, | union,
                                   & intersection, - difference, ! complement, brackets (!
                                   binds tightest, then &, then | and - left to right), e.g.
                                   esc expr \"!(A|B)-C\" A=a.obj B=example:torus C=c.stl
                                   (esc commands take --crease DEG: an edge whose faces turn
                                   by more than DEG degrees stays sharp; default 50, 180
                                   rounds every edge)
  plasm SCRIPT [-o OUT.{obj,stl,ply}]
                                   run a PLaSM script (the third paper's language) and write
                                   what its top-level expressions draw: OBJ with faces, lines
                                   and points, or the triangles as STL or PLY; without -o, print
                                   the value of each top-level expression
  bench                            benchmarks                          (run `cargo xtask bench`)

MODEL is a model file (.bsolid.json: one patch or volume, or a tree of many solids: primitives,
Bézier solids, set operations, blends, morphs and transforms, DESIGN §5), a share link (the whole URL or its #v1. fragment; quote it
in the shell) or a preset: preset:fig9, preset:blob, preset:ring, preset:fish, and the zoo's preset:chair,
preset:vase, preset:knot, preset:shell, preset:koi, preset:tooth. MESH, A and B are mesh files or
built-in examples: example:icosphere, example:torus, example:blob, or free-form model files or
links (`mesh` writes the surface of a free-form model's result); SOLID likewise. SCRIPT is a script file (.psm),
a model file or link holding one, or one of the paper's examples: example:3.1, example:3.3,
example:4.1, example:4.4, example:4.6, example:4.7, example:4.8,
example:4.7-bezier-grid.

Inputs are read up to a cap, whatever they are (files, pipes, devices): a model file 16 MiB, a
script file 256 KiB, a mesh file 128 MiB, a points file 256 MiB.

options:
  -h, --help       this text
  -V, --version    the version
";

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
        Some("link") => report(link::run(&args[1..])),
        Some("esc") => report(esc::run(&args[1..])),
        Some("plasm") => report(plasm::run(&args[1..])),
        Some("bench") => {
            eprintln!(
                "bezsolid: `bench` is not in this build; run `cargo xtask bench` in the repository"
            );
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
    let text = input::read_text(arg, input::MAX_MODEL_BYTES, "model file")?;
    serde_json::from_str(&text).with_context(|| format!("{arg} is not a valid model file"))
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
