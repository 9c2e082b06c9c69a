//! The web build: for each module of the recipe, cargo for wasm32 with its features,
//! wasm-bindgen into the recipe's out-dir, then wasm-opt; then the modules' hashed names. The
//! package for node (`cargo xtask pack`) makes one module with the same steps.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};

use crate::recipe::{Module, Recipe};
use crate::setup;
use crate::util::{cargo, run};

/// Sizes of one module, in bytes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sizes {
    pub(crate) bindgen: u64,
    pub(crate) optimised: Option<u64>,
    pub(crate) gzipped: u64,
    pub(crate) brotli: u64,
}

impl std::fmt::Display for Sizes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kb = |b: u64| format!("{:.0} KB", b as f64 / 1000.0);
        write!(f, "wasm after wasm-bindgen {}", kb(self.bindgen))?;
        if let Some(o) = self.optimised {
            write!(f, ", after wasm-opt {}", kb(o))?;
        }
        write!(
            f,
            ", gzipped {}, brotli {} (as served)",
            kb(self.gzipped),
            kb(self.brotli)
        )
    }
}

/// Builds every module of the recipe into its out-dir, then `assets.js` naming them by content;
/// returns each module's name and sizes.
pub(crate) fn web(workspace: &Path, recipe: &Recipe) -> Result<Vec<(String, Sizes)>> {
    setup::wasm_target()?;
    let bind = Bindgen::new(workspace, recipe)?;
    let mut built = Vec::new();
    let mut hashed = Vec::new();
    for module in &recipe.modules {
        eprintln!(
            "- module {} (features {})",
            module.name,
            module.features.join(", ")
        );
        let artifact = cdylib(workspace, recipe, module)?;
        let (bindgen, optimised) = bind.run(
            &artifact,
            &recipe.bindgen_target,
            &module.name,
            &recipe.out_dir,
        )?;
        let (name, travel) = crate::assets::publish(&recipe.out_dir, &module.name)?;
        let sizes = Sizes {
            bindgen,
            optimised,
            gzipped: travel.gzip,
            brotli: travel.brotli,
        };
        eprintln!("- {}: {sizes}", module.name);
        hashed.push((module.name.clone(), name));
        built.push((module.name.clone(), sizes));
    }
    crate::assets::write_manifest(&recipe.out_dir, &hashed)?;
    crate::assets::write_offline_list(&recipe.out_dir, &hashed)?;
    Ok(built)
}

/// wasm-bindgen at Cargo.lock's version, then wasm-opt with the recipe's arguments where the
/// recipe enables it and a working one can be had.
pub(crate) struct Bindgen<'a> {
    dir: PathBuf,
    wasm_opt: Option<(PathBuf, &'a [String])>,
}

impl<'a> Bindgen<'a> {
    /// Installs what is missing (setup's steps).
    pub(crate) fn new(workspace: &Path, recipe: &'a Recipe) -> Result<Self> {
        Ok(Self {
            dir: setup::wasm_bindgen(workspace)?,
            wasm_opt: recipe
                .wasm_opt
                .as_deref()
                .and_then(|args| setup::wasm_opt(workspace).map(|bin| (bin, args))),
        })
    }

    /// Writes the glue and the module `<name>_bg.wasm` of the cdylib `artifact` for `target` into
    /// `out_dir`, then optimises the module (keeping it as it is, with a warning, when wasm-opt
    /// fails); returns its size after wasm-bindgen and after wasm-opt.
    pub(crate) fn run(
        &self,
        artifact: &Path,
        target: &str,
        name: &str,
        out_dir: &Path,
    ) -> Result<(u64, Option<u64>)> {
        run(Command::new(self.dir.join("wasm-bindgen"))
            .arg(artifact)
            .args(["--target", target, "--out-name", name, "--out-dir"])
            .arg(out_dir))?;
        let wasm = out_dir.join(format!("{name}_bg.wasm"));
        let bindgen = size(&wasm)?;
        let mut optimised = None;
        if let Some((bin, args)) = &self.wasm_opt {
            let tmp = wasm.with_extension("opt.wasm");
            match run(Command::new(bin).arg(&wasm).args(*args).arg("-o").arg(&tmp)) {
                Ok(()) => {
                    std::fs::rename(&tmp, &wasm)?;
                    optimised = Some(size(&wasm)?);
                }
                Err(e) => {
                    let _ = std::fs::remove_file(&tmp);
                    eprintln!("warning: {e:#}; keeping the unoptimised module");
                }
            }
        }
        Ok((bindgen, optimised))
    }
}

fn size(p: &Path) -> Result<u64> {
    std::fs::metadata(p)
        .map(|m| m.len())
        .with_context(|| p.display().to_string())
}

/// Builds the crate with `module`'s features alone and returns the path cargo reports for its
/// `.wasm` (every build writes it again, fresh or not: read it before the next build).
pub(crate) fn cdylib(workspace: &Path, recipe: &Recipe, module: &Module) -> Result<PathBuf> {
    let mut cmd = cargo();
    cmd.current_dir(workspace)
        .args([
            "build",
            "--message-format=json-render-diagnostics",
            "--target",
            setup::WASM_TARGET,
            "--profile",
            &recipe.profile,
            "-p",
            &recipe.krate,
            "--no-default-features",
            "--features",
            &module.features.join(","),
        ])
        .stderr(Stdio::inherit());
    eprintln!(
        "  $ cargo build -p {} --features {}",
        recipe.krate,
        module.features.join(",")
    );
    let out = cmd.output().context("could not start cargo")?;
    if !out.status.success() {
        bail!("building {} failed ({})", module.name, out.status);
    }
    let target = recipe.krate.replace('-', "_");
    let mut found = None;
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if msg["reason"] == "compiler-artifact" && msg["target"]["name"] == target.as_str() {
            found = msg["filenames"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(serde_json::Value::as_str)
                .find(|f| f.ends_with(".wasm"))
                .map(PathBuf::from);
        }
    }
    found.with_context(|| format!("cargo named no .wasm for {}", module.name))
}
