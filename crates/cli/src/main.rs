//! `bezsolid`: the command line of bezsolid (DESIGN §5).
//!
//! This first slice knows its name and version; `eval`, `contour`, `mesh`, `hf` and `link` arrive with
//! the model file (issue 3 and after) and answer with a clear error until then.

use std::process::ExitCode;

const USAGE: &str = "usage: bezsolid <command> [options]

commands (DESIGN §5):
  eval MODEL --points FILE.csv     f and preimages per point
  contour MODEL --res N -o OUT.svg zero contours of a patch solid
  mesh MODEL --res N -o OUT.stl    polygonize a volume solid (stl, obj, ply)
  hf MODEL -o OUT.hf               HyperFun export
  link MODEL                       print the share link
  bench                            benchmarks

options:
  -h, --help       this text
  -V, --version    the version
";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        None | Some("-h" | "--help" | "help") => {
            print!("{USAGE}");
            if args.is_empty() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            }
        }
        Some("-V" | "--version") => {
            println!("bezsolid {}", env!("CARGO_PKG_VERSION"));
            ExitCode::SUCCESS
        }
        Some(cmd @ ("eval" | "contour" | "mesh" | "hf" | "link" | "bench")) => {
            eprintln!(
                "bezsolid: `{cmd}` is not available in this build yet (it comes with the model file)"
            );
            ExitCode::FAILURE
        }
        Some(other) => {
            eprintln!("bezsolid: unknown command `{other}`\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}
