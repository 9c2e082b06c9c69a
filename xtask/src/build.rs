//! The web build: cargo for wasm32, wasm-bindgen into the recipe's out-dir, then wasm-opt.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};

use crate::recipe::Recipe;
use crate::setup;
use crate::util::{cargo, run};

/// Sizes of the page's module, in bytes.
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

/// Builds the page's module into the recipe's out-dir.
pub(crate) fn web(workspace: &Path, recipe: &Recipe) -> Result<Sizes> {
    setup::wasm_target()?;
    let bindgen_dir = setup::wasm_bindgen(workspace)?;
    run(cargo().current_dir(workspace).args([
        "build",
        "--target",
        setup::WASM_TARGET,
        "--profile",
        &recipe.profile,
        "-p",
        &recipe.krate,
    ]))?;
    let artifact = recipe.artifact(workspace);
    run(Command::new(bindgen_dir.join("wasm-bindgen"))
        .arg(&artifact)
        .args([
            "--target",
            &recipe.bindgen_target,
            "--out-name",
            &recipe.out_name,
            "--out-dir",
        ])
        .arg(&recipe.out_dir))?;
    let wasm = recipe.out_dir.join(format!("{}_bg.wasm", recipe.out_name));
    let size = |p: &Path| {
        std::fs::metadata(p)
            .map(|m| m.len())
            .with_context(|| p.display().to_string())
    };
    let bindgen = size(&wasm)?;
    let mut optimised = None;
    if let Some(args) = &recipe.wasm_opt
        && let Some(bin) = setup::wasm_opt(workspace)
    {
        let tmp = wasm.with_extension("opt.wasm");
        match run(Command::new(bin).arg(&wasm).args(args).arg("-o").arg(&tmp)) {
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
    let travel = crate::assets::publish(&recipe.out_dir, &recipe.out_name)?;
    let sizes = Sizes {
        bindgen,
        optimised,
        gzipped: travel.gzip,
        brotli: travel.brotli,
    };
    eprintln!("- {sizes}");
    Ok(sizes)
}
