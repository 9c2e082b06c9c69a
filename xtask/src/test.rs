//! `cargo xtask test`: every check in order, stopping at the first failure, with a summary.

use std::net::TcpListener;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

use anyhow::{Context, Result, bail};

use crate::recipe::Recipe;
use crate::util::{cargo, human, run, timed};
use crate::{build, pack, serve, setup};

/// Options of `cargo xtask test`.
#[derive(Debug, Default)]
pub(crate) struct Options {
    /// Copy the WebGL2 screenshot the browser suite takes to docs/screenshot.png.
    pub(crate) update_screenshot: bool,
}

type Step<'a> = (&'static str, Box<dyn FnOnce() -> Result<()> + 'a>);

pub(crate) fn all(workspace: &Path, options: &Options) -> Result<()> {
    let recipe = Recipe::load(workspace)?;
    let ws = workspace;
    let cargo_in = move || {
        let mut c = cargo();
        c.current_dir(ws);
        c
    };
    let steps: Vec<Step<'_>> = vec![
        (
            "cargo fmt --check",
            Box::new(move || {
                setup::rust_components()?;
                run(cargo_in().args(["fmt", "--all", "--", "--check"]))
            }),
        ),
        (
            "clippy (native and wasm32, warnings denied)",
            Box::new(move || {
                setup::wasm_target()?;
                run(cargo_in().args([
                    "clippy",
                    "--workspace",
                    "--all-targets",
                    "--",
                    "-D",
                    "warnings",
                ]))?;
                run(cargo_in().args([
                    "clippy",
                    "-p",
                    "bezsolid-core",
                    "-p",
                    "bezsolid-web",
                    "--all-targets",
                    "--target",
                    setup::WASM_TARGET,
                    "--",
                    "-D",
                    "warnings",
                ]))?;
                // The page's module without WebGL2, and the tools' module, as the web build makes them.
                for features in ["page", "tools"] {
                    run(cargo_in().args([
                        "clippy",
                        "-p",
                        "bezsolid-web",
                        "--no-default-features",
                        "--features",
                        features,
                        "--target",
                        setup::WASM_TARGET,
                        "--",
                        "-D",
                        "warnings",
                    ]))?;
                }
                Ok(())
            }),
        ),
        (
            "native tests",
            Box::new(move || run(cargo_in().args(["test", "--workspace"]))),
        ),
        (
            "docs (warnings denied)",
            Box::new(move || {
                run(cargo_in()
                    .args(["doc", "--workspace", "--no-deps"])
                    .env("RUSTDOCFLAGS", "-D warnings"))
            }),
        ),
        (
            "core is no_std (wasm32, no default features, with the link codec)",
            Box::new(move || {
                run(cargo_in().args([
                    "build",
                    "-p",
                    "bezsolid-core",
                    "--no-default-features",
                    "--features",
                    "link",
                    "--target",
                    setup::WASM_TARGET,
                ]))
            }),
        ),
        (
            "core and web tests in node (wasm-bindgen-test-runner)",
            Box::new(move || {
                let bin = setup::wasm_bindgen(ws)?;
                run(cargo_in()
                    .args([
                        "test",
                        "--target",
                        setup::WASM_TARGET,
                        "-p",
                        "bezsolid-core",
                        "-p",
                        "bezsolid-web",
                    ])
                    .env(
                        "CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER",
                        bin.join("wasm-bindgen-test-runner"),
                    ))
            }),
        ),
        (
            "web build",
            Box::new(|| build::web(workspace, &recipe).map(|_| ())),
        ),
        (
            "the package for node, and the tools' and the page's modules headless in node (tests/node)",
            Box::new(move || {
                setup::node()?;
                // The package the node tests install (the web build's cdylib again: cargo is fresh).
                pack::pack(ws, &pack::default_out(ws))?;
                // The node tests use npm packages too (the glTF validator), from the committed lockfile.
                setup::npm_ci(&ws.join("tests"))?;
                run(Command::new("node")
                    .args(["--test", "--test-concurrency=1", "node/"])
                    .current_dir(ws.join("tests")))
            }),
        ),
        (
            "browser suite (WebGL2 and WebGPU)",
            Box::new(move || browser_suite(ws, options)),
        ),
    ];

    let total = steps.len();
    let mut done: Vec<(&str, Duration, bool)> = Vec::new();
    let mut failure = None;
    for (name, step) in steps {
        eprintln!("\n== {name}");
        let (result, took) = timed(step);
        done.push((name, took, result.is_ok()));
        if let Err(e) = result {
            failure = Some(e);
            break;
        }
    }
    eprintln!("\n== summary");
    for (name, took, ok) in &done {
        eprintln!(
            "  {:<6} {:>8}  {name}",
            if *ok { "ok" } else { "FAILED" },
            human(*took)
        );
    }
    let passed = done.iter().filter(|d| d.2).count();
    let failed = done.len() - passed;
    if done.len() < total {
        eprintln!("  ({} steps not run)", total - done.len());
    }
    println!("steps: {passed} passed, {failed} failed");
    match failure {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The four flags under which headless Debian chromium gives a WebGPU adapter that really draws
/// (TOOLCHAIN.md); the test harness adds them for the WebGPU run.
pub(crate) const WEBGPU_FLAGS: [&str; 4] = [
    "--enable-unsafe-webgpu",
    "--enable-features=Vulkan",
    "--use-vulkan=swiftshader",
    "--use-angle=swiftshader",
];

fn browser_suite(workspace: &Path, options: &Options) -> Result<()> {
    setup::browser_packages()?;
    setup::node()?;
    let tests = workspace.join("tests");
    setup::npm_ci(&tests)?;
    let recipe = Recipe::load(workspace)?;
    let listener =
        TcpListener::bind((recipe.address.as_str(), 0)).context("binding a loopback port")?;
    let url = format!("http://{}/", listener.local_addr()?);
    let server = serve::Server::start(listener, recipe.root.clone())?;
    let mut files: Vec<_> = std::fs::read_dir(tests.join("e2e"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(".test.mjs"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no tests/e2e/*.test.mjs");
    }
    let artifacts = workspace.join("target/e2e");
    std::fs::create_dir_all(&artifacts)?;
    let runtime = artifacts.join("xdg-runtime");
    std::fs::create_dir_all(&runtime)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700))?;
    }
    let runs = ["webgl2", "webgpu"].map(|backend| {
        eprintln!("-- {backend} at {url}");
        run(Command::new("node")
            .arg("--test")
            .arg("--test-concurrency=1")
            .args(&files)
            .current_dir(&tests)
            .env("BEZSOLID_URL", &url)
            .env("BEZSOLID_BACKEND", backend)
            .env("BEZSOLID_ARTIFACTS", &artifacts)
            .env("BEZSOLID_WEBGPU_FLAGS", WEBGPU_FLAGS.join(" "))
            .env("XDG_RUNTIME_DIR", &runtime))
    });
    server.stop();
    for r in runs {
        r?;
    }
    if options.update_screenshot {
        let shot = artifacts.join("webgl2/modeler.png");
        let dest = workspace.join("docs/screenshot.png");
        std::fs::create_dir_all(workspace.join("docs"))?;
        std::fs::copy(&shot, &dest).with_context(|| format!("copying {}", shot.display()))?;
        eprintln!("- updated {}", dest.display());
    }
    Ok(())
}
