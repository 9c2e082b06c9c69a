//! `cargo xtask pack [--out DIR]`: the tools' module as a package for node, a folder that
//! `npm install DIR` takes: the module built as the web build builds it, its glue from
//! wasm-bindgen for node (a module for `require`, loaded synchronously, that `import` takes too), the
//! TypeScript declarations wasm-bindgen writes beside it, a `package.json` and the README of
//! `crates/web/npm/`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde_json::{Value, json};

use crate::build::{Bindgen, cdylib};
use crate::recipe::Recipe;
use crate::setup;
use crate::util::{human, timed};

/// The recipe's module with the headless functions.
const TOOLS_MODULE: &str = "bezsolid_web";

/// The package's name, and the stem of its files (`bezsolid.js`, `bezsolid_bg.wasm`, …).
const NAME: &str = "bezsolid";

/// The package's README, as committed.
const README: &str = "crates/web/npm/README.md";

/// wasm-bindgen's target: glue for `require` that reads and instantiates the module synchronously
/// when it is first loaded. Node's ES modules import it too, with named exports (node finds the
/// `exports.name = …` assignments), so one file serves both and the module is instantiated once
/// however a program loads it.
const TARGET: &str = "nodejs";

/// The file that marks a folder as one pack wrote, and may clear (it is not in the package's
/// `files`, so `npm install` leaves it behind).
const MARK: &str = ".packed-by-cargo-xtask";

/// The default folder, under the workspace (git-ignored).
pub(crate) fn default_out(workspace: &Path) -> PathBuf {
    workspace.join("pkg")
}

/// Builds the package into `out`, replacing what an earlier pack left there; refuses a folder
/// that holds anything else.
pub(crate) fn pack(workspace: &Path, out: &Path) -> Result<()> {
    let (result, took) = timed(|| write_package(workspace, out));
    result?;
    eprintln!(
        "- packed {NAME} in {} ({}): `npm install {}`",
        out.display(),
        human(took),
        out.display()
    );
    Ok(())
}

fn write_package(workspace: &Path, out: &Path) -> Result<()> {
    let recipe = Recipe::load(workspace)?;
    let module = recipe
        .modules
        .iter()
        .find(|m| m.name == TOOLS_MODULE)
        .with_context(|| format!("wasm-pack.toml has no [[module]] named {TOOLS_MODULE}"))?;
    empty_folder(out)?;
    setup::wasm_target()?;
    let bind = Bindgen::new(workspace, &recipe)?;
    eprintln!(
        "- module {} (features {}) for node",
        module.name,
        module.features.join(", ")
    );
    let artifact = cdylib(workspace, &recipe, module)?;
    let (bindgen, optimised) = bind.run(&artifact, TARGET, NAME, out)?;
    let kb = |b: u64| format!("{:.0} KB", b as f64 / 1000.0);
    eprintln!(
        "- {NAME}_bg.wasm: {} after wasm-bindgen{}",
        kb(bindgen),
        optimised.map_or(String::new(), |o| format!(", {} after wasm-opt", kb(o)))
    );
    for file in [format!("{NAME}.js"), format!("{NAME}.d.ts")] {
        if !out.join(&file).is_file() {
            bail!("wasm-bindgen wrote no {file} in {}", out.display());
        }
    }
    std::fs::copy(workspace.join(README), out.join("README.md"))
        .with_context(|| format!("copying {README}"))?;
    let (version, license) = workspace_package(workspace)?;
    let mut files = Vec::new();
    for entry in std::fs::read_dir(out)? {
        let name = entry?.file_name().to_string_lossy().into_owned();
        if name != "package.json" && name != MARK {
            files.push(name);
        }
    }
    files.sort();
    std::fs::write(
        out.join("package.json"),
        manifest(&version, &license, &files),
    )?;
    Ok(())
}

/// `out` made and empty, and marked as pack's: a new folder, an empty one, or one an earlier pack
/// wrote (it holds the mark), removed first.
fn empty_folder(out: &Path) -> Result<()> {
    if out.exists() {
        let empty = std::fs::read_dir(out)
            .with_context(|| format!("reading {}", out.display()))?
            .next()
            .is_none();
        if !empty {
            if !out.join(MARK).is_file() {
                bail!(
                    "{} holds files that are not a {NAME} package; choose another --out",
                    out.display()
                );
            }
            std::fs::remove_dir_all(out).with_context(|| format!("clearing {}", out.display()))?;
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    std::fs::write(out.join(MARK), "").with_context(|| format!("marking {}", out.display()))
}

/// `[workspace.package] version` of the workspace's Cargo.toml.
fn workspace_package(workspace: &Path) -> Result<(String, String)> {
    let path = workspace.join("Cargo.toml");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let table: toml::Table = text
        .parse()
        .with_context(|| format!("parsing {}", path.display()))?;
    let field = |name: &str| {
        table
            .get("workspace")
            .and_then(|w| w.get("package"))
            .and_then(|p| p.get(name))
            .and_then(toml::Value::as_str)
            .map(str::to_owned)
            .with_context(|| format!("{}: no [workspace.package] {name}", path.display()))
    };
    Ok((field("version")?, field("license")?))
}

/// The package's `package.json`, its keys in the order people read them (`exports` conditions
/// are tried in order: `types` must come first).
fn manifest(version: &str, license: &str, files: &[String]) -> String {
    let js = json!(format!("./{NAME}.js"));
    let types = json!(format!("./{NAME}.d.ts"));
    // serde_json's maps sort their keys, so the objects are written by hand, one key a line.
    let exports = format!(
        "{{\n    \".\": {{\n      \"types\": {types},\n      \"import\": {js},\n      \
         \"require\": {js}\n    }},\n    \"./package.json\": \"./package.json\"\n  }}"
    );
    let description = "Bézier solids without a page or a GPU: a bezsolid model file or share link \
                       to STL, OBJ, PLY, 3MF or GLB meshes, contour SVG and measurements \
                       (WebAssembly)";
    // Indented as the object's values: a nested line starts two spaces further in.
    let pretty = |v: Value| {
        serde_json::to_string_pretty(&v)
            .unwrap_or_default()
            .replace('\n', "\n  ")
    };
    let fields = [
        ("name", pretty(json!(NAME))),
        ("version", pretty(json!(version))),
        ("description", pretty(json!(description))),
        ("license", pretty(json!(license))),
        ("type", pretty(json!("commonjs"))),
        ("main", pretty(js)),
        ("types", pretty(types)),
        ("exports", exports),
        ("files", pretty(json!(files))),
        ("engines", pretty(json!({"node": ">=18"}))),
    ];
    let lines: Vec<String> = fields
        .iter()
        .map(|(key, value)| format!("  {}: {value}", json!(key)))
        .collect();
    format!("{{\n{}\n}}\n", lines.join(",\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_parses_with_types_first() {
        let files = ["README.md".to_owned(), "bezsolid.js".to_owned()];
        let text = manifest("1.2.3", "MIT OR Apache-2.0", &files);
        let p: Value = serde_json::from_str(&text).expect("package.json is JSON");
        assert_eq!(p["name"], "bezsolid");
        assert_eq!(p["version"], "1.2.3");
        assert_eq!(p["license"], "MIT OR Apache-2.0");
        assert_eq!(p["main"], "./bezsolid.js");
        assert_eq!(p["exports"]["."]["require"], "./bezsolid.js");
        assert_eq!(p["files"], json!(files));
        // Condition order is meaning: TypeScript takes the first that matches.
        let dot = text.find("\".\"").expect("a \".\" export");
        let conditions: Vec<usize> = ["\"types\"", "\"import\"", "\"require\""]
            .iter()
            .map(|c| dot + text[dot..].find(c).expect("each condition"))
            .collect();
        assert!(conditions.is_sorted(), "{text}");
    }

    #[test]
    fn version_and_license_of_the_workspace_read() {
        let ws = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .expect("xtask sits in the workspace");
        let (v, license) = workspace_package(ws).expect("a version and a license");
        assert_eq!(v.split('.').count(), 3, "{v}");
        assert!(license.contains("MIT"), "{license}");
    }
}
