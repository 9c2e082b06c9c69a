//! `cargo xtask`: set-up, build, serve and test orchestration for bezsolid.
//!
//! - `cargo xtask serve [--port N]`: sets up a bare machine (wasm32 target, the wasm-bindgen CLI of
//!   Cargo.lock, npm binaryen for wasm-opt), builds the page as `wasm-pack.toml` says and serves `www/`
//!   on loopback.
//! - `cargo xtask test [--update-screenshot]`: fmt, clippy, native tests, docs, the `no_std` build, the
//!   wasm tests in node, the web build, the package for node and the modules headless in node, and
//!   the browser suite in headless chromium on both backends.
//! - `cargo xtask pack [--out DIR]`: the tools' module as a package for node in `DIR` (default
//!   `pkg/`): the module and its glue for node, the TypeScript declarations, `package.json` and a
//!   README whose example turns a share link into an STL file; `npm install DIR` takes it. The test
//!   run packs it too, and installs and runs it in node.
//! - `cargo xtask fuzz [--seconds N] [TARGET…]`: the fuzz campaigns of `fuzz/` (installs the nightly
//!   toolchain and cargo-fuzz when missing), N seconds per target, with a report per target.

mod assets;
mod bench;
mod build;
mod fuzz;
mod pack;
mod recipe;
mod serve;
mod setup;
mod test;
mod util;

use std::net::TcpListener;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};

const USAGE: &str = "usage: cargo xtask <command>

commands:
  serve [--port N]             set up, build the page and serve it (port also from BEZSOLID_PORT)
  test [--update-screenshot]   every check, in order, stopping at the first failure
  bench [--quick | --page]     benchmarks, native (with peers) and wasm in node, and the page's
                               input-to-drawn in headless Chromium; writes BENCHMARKS.md
                               (--page: only the page's figures, in place)
  pack [--out DIR]             the tools' module as a package for node (default DIR: pkg/),
                               for `npm install DIR`
  fuzz [--seconds N] [TARGET...]
                               fuzz campaigns (nightly, cargo-fuzz), N seconds per target (default 60),
                               every target when none is named; see FUZZING.md
";

fn workspace() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().map_or(manifest.clone(), PathBuf::from)
}

fn main() -> ExitCode {
    match real_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn real_main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let ws = workspace();
    match args.first().map(String::as_str) {
        Some("serve") => serve_command(&ws, &args[1..]),
        Some("test") => {
            let mut options = test::Options::default();
            for a in &args[1..] {
                match a.as_str() {
                    "--update-screenshot" => options.update_screenshot = true,
                    other => bail!("unknown option {other}\n\n{USAGE}"),
                }
            }
            test::all(&ws, &options)
        }
        Some("bench") => {
            let mut quick = false;
            let mut page = false;
            for a in &args[1..] {
                match a.as_str() {
                    "--quick" => quick = true,
                    "--page" => page = true,
                    other => bail!("unknown option {other}\n\n{USAGE}"),
                }
            }
            if page {
                bench::page(&ws)
            } else {
                bench::all(&ws, quick)
            }
        }
        Some("pack") => {
            let mut out = pack::default_out(&ws);
            let mut it = args[1..].iter();
            while let Some(a) = it.next() {
                match a.as_str() {
                    "--out" => {
                        let dir = it.next().context("--out needs a folder")?;
                        out = std::path::absolute(dir)
                            .with_context(|| format!("--out {dir} is not a path"))?;
                    }
                    other => bail!("unknown option {other}\n\n{USAGE}"),
                }
            }
            pack::pack(&ws, &out)
        }
        Some("fuzz") => {
            let mut seconds = fuzz::DEFAULT_SECONDS;
            let mut targets = Vec::new();
            let mut it = args[1..].iter();
            while let Some(a) = it.next() {
                match a.as_str() {
                    "--seconds" => {
                        let n = it.next().context("--seconds needs a number")?;
                        seconds =
                            n.parse().ok().filter(|&s| s > 0).with_context(|| {
                                format!("--seconds {n} is not a positive number")
                            })?;
                    }
                    other if other.starts_with('-') => bail!("unknown option {other}\n\n{USAGE}"),
                    target => targets.push(target.to_owned()),
                }
            }
            fuzz::all(&ws, seconds, &targets)
        }
        Some("-h" | "--help" | "help") => {
            print!("{USAGE}");
            Ok(())
        }
        Some(other) => bail!("unknown command {other}\n\n{USAGE}"),
        None => bail!("no command\n\n{USAGE}"),
    }
}

fn serve_command(ws: &std::path::Path, args: &[String]) -> Result<()> {
    let recipe = recipe::Recipe::load(ws)?;
    let mut port = match std::env::var("BEZSOLID_PORT") {
        Ok(p) => p
            .parse::<u16>()
            .with_context(|| format!("BEZSOLID_PORT={p} is not a port"))?,
        Err(_) => recipe.port,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--port" => {
                let p = it.next().context("--port needs a number")?;
                port = p
                    .parse()
                    .with_context(|| format!("--port {p} is not a port"))?;
            }
            other => bail!("unknown option {other}\n\n{USAGE}"),
        }
    }
    let (sizes, took) = util::timed(|| build::web(ws, &recipe));
    let sizes = sizes?;
    eprintln!("- built in {}", util::human(took));
    for (module, sizes) in &sizes {
        eprintln!("  {module}: {sizes}");
    }
    let listener = TcpListener::bind((recipe.address.as_str(), port)).with_context(|| {
        format!(
            "cannot listen on {}:{port}; is it in use? choose another with --port",
            recipe.address
        )
    })?;
    let addr = listener.local_addr()?;
    println!(
        "bezsolid: serving {} at http://{addr}/  (Ctrl+C stops)",
        recipe.root.display()
    );
    serve::serve(listener, recipe.root.clone());
    Ok(())
}
