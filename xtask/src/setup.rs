//! Bringing a bare machine up to what the build and the tests need. Every step checks first and only
//! installs what is missing, so a second run costs almost nothing.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

use crate::util::{cargo, locked_version, output, run};

pub(crate) const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// Adds the wasm32 target with rustup when it is missing.
pub(crate) fn wasm_target() -> Result<()> {
    let installed = output(Command::new("rustup").args(["target", "list", "--installed"]));
    match installed {
        Some(list) if list.lines().any(|l| l.trim() == WASM_TARGET) => Ok(()),
        Some(_) => {
            eprintln!("- adding the {WASM_TARGET} target");
            run(Command::new("rustup").args(["target", "add", WASM_TARGET]))
        }
        None => {
            // No rustup: trust the toolchain if it can build for the target, which the build will tell.
            eprintln!("- rustup not found; assuming the toolchain has {WASM_TARGET}");
            Ok(())
        }
    }
}

/// rustfmt and clippy, which a minimal rustup profile leaves out.
pub(crate) fn rust_components() -> Result<()> {
    let have = |args: &[&str]| output(cargo().args(args)).is_some();
    if have(&["fmt", "--version"]) && have(&["clippy", "--version"]) {
        return Ok(());
    }
    eprintln!("- adding the rustfmt and clippy components");
    run(Command::new("rustup").args(["component", "add", "rustfmt", "clippy"]))
}

/// node and npm for the browser suite and wasm-opt, from Debian when missing.
pub(crate) fn node() -> Result<()> {
    let works = |bin: &str| output(Command::new(bin).arg("--version")).is_some();
    if works("node") && works("npm") {
        return Ok(());
    }
    apt_install(&["nodejs", "npm"])?;
    if !(works("node") && works("npm")) {
        bail!("node and npm are still missing after installing Debian's nodejs and npm");
    }
    Ok(())
}

fn cargo_bin_dir() -> PathBuf {
    let home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(std::env::var_os("HOME").unwrap_or_else(|| ".".into())).join(".cargo")
        });
    home.join("bin")
}

/// The wasm-bindgen CLI at exactly the version of the `wasm-bindgen` crate in Cargo.lock (the CLI
/// refuses modules from any other version). Returns the folder holding `wasm-bindgen` and
/// `wasm-bindgen-test-runner`.
pub(crate) fn wasm_bindgen(workspace: &Path) -> Result<PathBuf> {
    let version = locked_version(workspace, "wasm-bindgen")?;
    let dir = cargo_bin_dir();
    let installed = |dir: &Path| {
        output(Command::new(dir.join("wasm-bindgen")).arg("--version"))
            .is_some_and(|v| v.split_whitespace().nth(1) == Some(version.as_str()))
            && dir.join("wasm-bindgen-test-runner").exists()
    };
    if installed(&dir) {
        return Ok(dir);
    }
    eprintln!("- installing wasm-bindgen-cli {version} (the version in Cargo.lock; a few minutes)");
    let install = |locked: bool| {
        let mut cmd = cargo();
        cmd.args([
            "install",
            "wasm-bindgen-cli",
            "--version",
            &version,
            "--force",
        ]);
        if locked {
            cmd.arg("--locked");
        }
        run(&mut cmd)
    };
    // --locked first (the CLI's own tested dependency set); when the registry no longer offers one of
    // those exact versions, resolve afresh.
    if let Err(e) = install(true) {
        eprintln!("- `cargo install --locked` failed ({e:#}); retrying with fresh resolution");
        install(false)?;
    }
    if !installed(&dir) {
        bail!(
            "wasm-bindgen {version} is still not in {} after installing it",
            dir.display()
        );
    }
    Ok(dir)
}

/// A working `wasm-opt` from npm binaryen (xtask/npm's lockfile), or `None` with a warning.
pub(crate) fn wasm_opt(workspace: &Path) -> Option<PathBuf> {
    if let Err(e) = node() {
        eprintln!("warning: no node for npm binaryen ({e:#}); the modules are left unoptimised");
        return None;
    }
    let dir = workspace.join("xtask/npm");
    let bin = dir.join("node_modules/.bin/wasm-opt");
    let works = |bin: &Path| output(Command::new(bin).arg("--version")).is_some();
    if !works(&bin) {
        eprintln!("- installing npm binaryen for wasm-opt (xtask/npm)");
        if let Err(e) = npm_ci(&dir) {
            eprintln!("warning: no working wasm-opt ({e:#}); the modules are left unoptimised");
            return None;
        }
    }
    if works(&bin) {
        Some(bin)
    } else {
        eprintln!(
            "warning: {} does not run; the modules are left unoptimised",
            bin.display()
        );
        None
    }
}

/// `npm ci` in `dir`, from its committed package-lock.json.
pub(crate) fn npm_ci(dir: &Path) -> Result<()> {
    run(Command::new("npm")
        .args(["ci", "--no-audit", "--no-fund", "--loglevel=error"])
        .current_dir(dir))
    .with_context(|| format!("npm ci in {}", dir.display()))
}

/// Debian chromium, chromium-driver and mesa-vulkan-drivers (lavapipe/SwiftShader paths for WebGPU),
/// installed with apt-get when missing.
pub(crate) fn browser_packages() -> Result<()> {
    const PACKAGES: [&str; 3] = ["chromium", "chromium-driver", "mesa-vulkan-drivers"];
    let missing: Vec<&str> = PACKAGES
        .into_iter()
        .filter(|p| {
            !output(Command::new("dpkg-query").args(["-W", "-f=${Status}", p]))
                .is_some_and(|s| s.contains("install ok installed"))
        })
        .collect();
    if missing.is_empty() && Path::new("/usr/bin/chromium").exists() {
        return Ok(());
    }
    apt_install(&missing)?;
    if !Path::new("/usr/bin/chromium").exists() {
        bail!(
            "/usr/bin/chromium is missing after installing {}",
            missing.join(" ")
        );
    }
    Ok(())
}

/// `apt-get install` as root (or through passwordless sudo), non-interactively.
fn apt_install(packages: &[&str]) -> Result<()> {
    eprintln!("- installing {} with apt-get", packages.join(" "));
    let root = output(Command::new("id").arg("-u")).is_some_and(|u| u.trim() == "0");
    let apt = |args: &[&str]| {
        let mut cmd = if root {
            Command::new("apt-get")
        } else {
            let mut c = Command::new("sudo");
            c.args(["-n", "apt-get"]);
            c
        };
        cmd.args(args).env("DEBIAN_FRONTEND", "noninteractive");
        run(&mut cmd)
    };
    apt(&["update", "-qq"]).context("apt-get update (needs root or passwordless sudo)")?;
    let mut args = vec!["install", "-y", "-qq"];
    args.extend(packages);
    apt(&args)
}
