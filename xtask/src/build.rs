//! The web build: for each module of the recipe, cargo for wasm32 with its features,
//! wasm-bindgen into the recipe's out-dir, then wasm-opt; then the modules' hashed names.

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
    let bindgen_dir = setup::wasm_bindgen(workspace)?;
    let wasm_opt = recipe
        .wasm_opt
        .as_ref()
        .and_then(|args| setup::wasm_opt(workspace).map(|bin| (bin, args)));
    let mut built = Vec::new();
    let mut hashed = Vec::new();
    for module in &recipe.modules {
        eprintln!(
            "- module {} (features {})",
            module.name,
            module.features.join(", ")
        );
        let artifact = cdylib(workspace, recipe, module)?;
        run(Command::new(bindgen_dir.join("wasm-bindgen"))
            .arg(&artifact)
            .args([
                "--target",
                &recipe.bindgen_target,
                "--out-name",
                &module.name,
                "--out-dir",
            ])
            .arg(&recipe.out_dir))?;
        let wasm = recipe.out_dir.join(format!("{}_bg.wasm", module.name));
        let bindgen = size(&wasm)?;
        let mut optimised = None;
        if let Some((bin, args)) = &wasm_opt {
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

fn size(p: &Path) -> Result<u64> {
    std::fs::metadata(p)
        .map(|m| m.len())
        .with_context(|| p.display().to_string())
}

/// Builds the crate with `module`'s features alone and returns the path cargo reports for its
/// `.wasm` (every build writes it again, fresh or not: read it before the next build).
fn cdylib(workspace: &Path, recipe: &Recipe, module: &Module) -> Result<PathBuf> {
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
