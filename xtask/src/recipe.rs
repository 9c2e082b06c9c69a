//! `wasm-pack.toml`: the web packaging recipe (its top comment says what each key does).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use toml::{Table, Value};

/// One module the build writes: the crate with `features` (and no others), named `name`.
#[derive(Debug, Clone)]
pub(crate) struct Module {
    pub(crate) name: String,
    pub(crate) features: Vec<String>,
}

/// The recipe, with paths resolved against the workspace root.
#[derive(Debug, Clone)]
pub(crate) struct Recipe {
    pub(crate) krate: String,
    pub(crate) profile: String,
    pub(crate) bindgen_target: String,
    pub(crate) out_dir: PathBuf,
    pub(crate) modules: Vec<Module>,
    pub(crate) wasm_opt: Option<Vec<String>>,
    pub(crate) root: PathBuf,
    pub(crate) address: String,
    pub(crate) port: u16,
}

impl Recipe {
    pub(crate) fn load(workspace: &Path) -> Result<Self> {
        let path = workspace.join("wasm-pack.toml");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        let table: Table = text
            .parse()
            .with_context(|| format!("parsing {}", path.display()))?;
        let section = |name: &str| -> Result<&Table> {
            table
                .get(name)
                .and_then(Value::as_table)
                .with_context(|| format!("{}: missing section [{name}]", path.display()))
        };
        let string = |t: &Table, key: &str| -> Result<String> {
            t.get(key)
                .and_then(Value::as_str)
                .map(str::to_owned)
                .with_context(|| format!("{}: missing string `{key}`", path.display()))
        };
        let package = section("package")?;
        let bindgen = section("bindgen")?;
        let opt = section("wasm-opt")?;
        let serve = section("serve")?;
        let wasm_opt = if opt.get("enabled").and_then(Value::as_bool).unwrap_or(false) {
            let args = opt
                .get("args")
                .and_then(Value::as_array)
                .context("[wasm-opt] needs `args`")?
                .iter()
                .map(|v| {
                    v.as_str()
                        .map(str::to_owned)
                        .context("[wasm-opt] args must be strings")
                })
                .collect::<Result<Vec<_>>>()?;
            Some(args)
        } else {
            None
        };
        let strings = |v: &Value, what: &str| -> Result<Vec<String>> {
            v.as_array()
                .with_context(|| format!("{}: `{what}` must be a list", path.display()))?
                .iter()
                .map(|x| {
                    x.as_str()
                        .map(str::to_owned)
                        .with_context(|| format!("{}: `{what}` must be strings", path.display()))
                })
                .collect()
        };
        let modules = table
            .get("module")
            .and_then(Value::as_array)
            .with_context(|| format!("{}: no [[module]]", path.display()))?
            .iter()
            .map(|m| {
                let m = m
                    .as_table()
                    .with_context(|| format!("{}: [[module]] is a table", path.display()))?;
                let features = m
                    .get("features")
                    .map_or(Ok(Vec::new()), |f| strings(f, "features"))?;
                Ok(Module {
                    name: string(m, "name")?,
                    features,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        if modules.is_empty() {
            bail!("{}: no [[module]]", path.display());
        }
        let port = serve
            .get("port")
            .and_then(Value::as_integer)
            .context("[serve] needs `port`")?;
        let Ok(port) = u16::try_from(port) else {
            bail!("[serve] port {port} is not a TCP port")
        };
        Ok(Self {
            krate: string(package, "crate")?,
            profile: string(package, "profile")?,
            bindgen_target: string(bindgen, "target")?,
            out_dir: workspace.join(string(bindgen, "out-dir")?),
            modules,
            wasm_opt,
            root: workspace.join(string(serve, "root")?),
            address: string(serve, "address")?,
            port,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recipe_of_the_repository_loads() {
        let ws = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .expect("xtask sits in the workspace");
        let r = Recipe::load(ws).expect("wasm-pack.toml parses");
        assert_eq!(r.krate, "bezsolid-web");
        assert_eq!(r.bindgen_target, "web");
        assert!(r.out_dir.ends_with("www/pkg"));
        assert!(
            r.wasm_opt
                .as_ref()
                .is_some_and(|a| a.iter().any(|x| x.starts_with("-O")))
        );
        assert_eq!(r.address, "127.0.0.1");
        let names: Vec<&str> = r.modules.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["bezsolid_page", "bezsolid_page_gl", "bezsolid_web"]);
        assert!(r.modules.iter().all(|m| !m.features.is_empty()));
    }
}
