//! `cargo xtask bench [--quick]`: the benchmark suite natively (with the peers, in the same process)
//! and as wasm in node, then the page's input-to-drawn figures in headless Chromium, and
//! BENCHMARKS.md with all of them and the ratios. `--page`: the page's figures alone, in place.

mod report;
mod targets;

use std::fmt::Write as _;
use std::net::TcpListener;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};
use serde_json::Value;

use crate::recipe::Recipe;
use crate::util::{cargo, run};
use crate::{build, serve, setup};

/// One row as the bench binary prints it.
struct Row {
    case: String,
    who: String,
    n: u64,
    ms: f64,
    runs: u64,
    extra: f64,
    note: String,
}

fn rows(json: &str, origin: &str) -> Result<Vec<Row>> {
    let value: Value = serde_json::from_str(json.trim())
        .with_context(|| format!("the {origin} benchmarks did not print JSON"))?;
    let Some(list) = value.as_array() else {
        bail!("the {origin} benchmarks printed no list");
    };
    list.iter()
        .map(|r| {
            Ok(Row {
                case: r["case"].as_str().context("case")?.to_owned(),
                who: r["who"].as_str().context("who")?.to_owned(),
                n: r["n"].as_u64().context("n")?,
                ms: r["ms"].as_f64().context("ms")?,
                runs: r["runs"].as_u64().context("runs")?,
                extra: r["extra"].as_f64().context("extra")?,
                note: r["note"].as_str().unwrap_or_default().to_owned(),
            })
        })
        .collect()
}

fn stdout_of(cmd: &mut Command) -> Result<String> {
    eprintln!("  $ {cmd:?}");
    let out = cmd.output().context("could not start the benchmark")?;
    if !out.status.success() {
        bail!(
            "the benchmark failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Where the page's figures begin in BENCHMARKS.md (they run to its end).
const PAGE_HEADING: &str = "## The page: input to drawn";

/// Builds and serves the page, runs `tests/latency.mjs` in headless Chromium (WebGL2 on `SwiftShader`)
/// and returns its section of BENCHMARKS.md: drags in the page, one move a frame and under a
/// continuous stream of moves.
fn page_latency(workspace: &Path) -> Result<String> {
    setup::browser_packages()?;
    setup::node()?;
    let tests = workspace.join("tests");
    setup::npm_ci(&tests)?;
    let recipe = Recipe::load(workspace)?;
    build::web(workspace, &recipe)?;
    let listener =
        TcpListener::bind((recipe.address.as_str(), 0)).context("binding a loopback port")?;
    let url = format!("http://{}/", listener.local_addr()?);
    let server = serve::Server::start(listener, recipe.root.clone())?;
    // The first load on each path (the page's module is built for WebGPU alone and with WebGL2),
    // then the drags on WebGL2.
    let load = stdout_of(
        Command::new("node")
            .args(["latency.mjs", "webgpu", "--load"])
            .current_dir(&tests)
            .env("BEZSOLID_URL", &url),
    );
    let lines = stdout_of(
        Command::new("node")
            .args(["latency.mjs", "webgl2"])
            .current_dir(&tests)
            .env("BEZSOLID_URL", &url),
    );
    server.stop();
    let lines = format!("{}\n{}", load?, lines?);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{PAGE_HEADING}\n\n`tests/latency.mjs` in headless Chromium (WebGPU on Vulkan SwiftShader for the first \
         load of the WebGPU build, WebGL2 on SwiftShader for the rest: the GPU is the CPU), 1400 × 800, served by the xtask's server on loopback (so the network \
         costs nothing here: the bytes are what a real network would carry). First the page's \
         load: navigation to the first frame drawn, and what was fetched before it, with an \
         empty cache and again with the modules cached under their content-hashed names (the page \
         fetches one page module, for WebGPU alone or with WebGL2, chosen before the download; the \
         workers fetch the tools' module after the first frame). Then \
         a control point dragged by real pointer events, first one \
         move a frame, then a stream of moves sent as fast as the browser takes them. \
         \"input→drawn\" is the page's own figure: from the oldest move a frame applies to the \
         end of that frame. The page applies the newest move once a frame and drops the others; \
         under a stream the moves applied and the frames drawn are counted. Machine: {}.\n",
        machine().split(';').next().unwrap_or_default()
    );
    for line in lines.lines().filter(|l| !l.trim().is_empty()) {
        let _ = writeln!(s, "- {line}");
    }
    Ok(s)
}

/// `cargo xtask bench --page`: the page's figures alone, in place in BENCHMARKS.md.
pub(crate) fn page(workspace: &Path) -> Result<()> {
    let section = page_latency(workspace)?;
    let path = workspace.join("BENCHMARKS.md");
    let old = std::fs::read_to_string(&path).unwrap_or_default();
    let kept = old.find(PAGE_HEADING).map_or(old.as_str(), |at| &old[..at]);
    let text = format!(
        "{}
{section}",
        kept.trim_end()
    );
    std::fs::write(&path, text).context("writing BENCHMARKS.md")?;
    print!("{section}");
    eprintln!("wrote the page's figures in BENCHMARKS.md");
    Ok(())
}

pub(crate) fn all(workspace: &Path, quick: bool) -> Result<()> {
    let quick_arg: &[&str] = if quick { &["--quick"] } else { &[] };
    let native = stdout_of(
        cargo()
            .current_dir(workspace)
            .args([
                "run",
                "--release",
                "-p",
                "bezsolid-bench",
                "--features",
                "peers",
                "--bin",
            ])
            .args(["bezsolid-bench", "--"])
            .args(quick_arg),
    )?;
    let native = rows(&native, "native")?;

    setup::wasm_target()?;
    setup::node()?;
    let bindgen = setup::wasm_bindgen(workspace)?;
    let out_dir = bench_module(workspace, &bindgen, "target", "target/bench-wasm", None)?;
    let script = format!(
        "process.stdout.write(require({:?}).run({quick}))",
        out_dir.join("bezsolid_bench.js")
    );
    let mut wasm = rows(
        &stdout_of(Command::new("node").args(["-e", &script]))?,
        "wasm",
    )?;
    // The page's way to every core: workers making the drawn surface in shares (node's worker
    // threads, the same module).
    wasm.extend(rows(
        &stdout_of(
            Command::new("node")
                .arg(workspace.join("crates/bench/workers.js"))
                .arg(out_dir.join("bezsolid_bench.js"))
                .arg(quick.to_string()),
        )?,
        "wasm workers",
    )?);

    // The grid evaluation again, from the same code built without SIMD (its own target directory:
    // other flags would rebuild the other's artifacts each time).
    let scalar_dir = bench_module(
        workspace,
        &bindgen,
        "target/no-simd",
        "target/bench-wasm-no-simd",
        Some("-C target-feature=-simd128"),
    )?;
    let script = format!(
        "process.stdout.write(require({:?}).run_eval({quick}))",
        scalar_dir.join("bezsolid_bench.js")
    );
    let scalar = rows(
        &stdout_of(Command::new("node").args(["-e", &script]))?,
        "wasm without SIMD",
    )?;

    let mut text = report::report(
        &Measured {
            native: &native,
            wasm: &wasm,
            scalar: &scalar,
        },
        quick,
    );
    let page = page_latency(workspace).unwrap_or_else(|e| {
        format!(
            "{PAGE_HEADING}

Not measured on this machine: {e:#}
"
        )
    });
    let _ = write!(
        text,
        "
{page}"
    );
    if quick {
        print!("{text}");
        eprintln!("(--quick: BENCHMARKS.md left as it is)");
    } else {
        std::fs::write(workspace.join("BENCHMARKS.md"), &text).context("writing BENCHMARKS.md")?;
        print!("{text}");
        eprintln!("wrote BENCHMARKS.md");
    }
    Ok(())
}

/// The benchmarks' wasm module built into `target_dir` (with `rustflags` in place of the
/// configured ones where given) and made a node package in `out_dir`, which it returns.
fn bench_module(
    workspace: &Path,
    bindgen: &Path,
    target_dir: &str,
    out_dir: &str,
    rustflags: Option<&str>,
) -> Result<std::path::PathBuf> {
    let mut build = cargo();
    build.current_dir(workspace).args([
        "build",
        "--release",
        "--target",
        setup::WASM_TARGET,
        "-p",
        "bezsolid-bench",
        "--lib",
        "--target-dir",
        target_dir,
    ]);
    if let Some(flags) = rustflags {
        build.env("RUSTFLAGS", flags);
    }
    run(&mut build)?;
    let out_dir = workspace.join(out_dir);
    run(Command::new(bindgen.join("wasm-bindgen"))
        .arg(
            workspace
                .join(target_dir)
                .join(setup::WASM_TARGET)
                .join("release/bezsolid_bench.wasm"),
        )
        .args(["--target", "nodejs", "--out-dir"])
        .arg(&out_dir))?;
    Ok(out_dir)
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, std::num::NonZero::get);
    let node = Command::new("node")
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
        .unwrap_or_default();
    format!("{cpu}, {cores} cores; one thread is used. Node {node} for wasm.")
}

/// The rows of the report: native, wasm (the modules as served, with SIMD), and wasm without SIMD
/// (grid evaluation alone, the same code built without it).
struct Measured<'a> {
    native: &'a [Row],
    wasm: &'a [Row],
    scalar: &'a [Row],
}
