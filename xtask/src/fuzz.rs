//! `cargo xtask fuzz [--seconds N] [TARGET…]`: the fuzz campaigns of `fuzz/` (cargo-fuzz, nightly),
//! one target after another from its seeds and the corpus earlier runs grew, with a report per
//! target and every crash or timeout shown with where to file it.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{Context, Result, bail};

use crate::util::{human, output, run};

/// The cargo-fuzz release the campaigns are run with (`cargo install --locked`).
const CARGO_FUZZ: &str = "0.13.2";

/// The toolchain cargo-fuzz needs (libFuzzer's instrumentation is a nightly flag).
const NIGHTLY: &str = "nightly";

/// The default length of each target's campaign, in seconds.
pub(crate) const DEFAULT_SECONDS: u64 = 60;

/// libFuzzer's limit on one input (`-timeout`), in seconds. The decoders answer in microseconds,
/// so 10 s is a hang. The geometry targets build the inverse map and the atlas of a net of degree
/// up to 16 and evaluate, contour or mesh it, within the work budgets the product holds every query
/// to: up to a few tenths of a second in an optimised build, several seconds instrumented on a
/// shared two-core machine; 30 s is past any budget, so a hang.
fn timeout(target: &str) -> u32 {
    match target {
        "eval" | "contour" | "mesh" | "tree" => 30,
        _ => 10,
    }
}

/// What one campaign did, from libFuzzer's final statistics and the files it left.
struct Report {
    target: String,
    runs: u64,
    per_second: u64,
    seconds: f64,
    /// The corpus as libFuzzer last printed it: inputs and size (`1989/443Kb`), or the files left
    /// in the corpus folder (which also keeps inputs that smaller ones replaced).
    corpus: String,
    findings: Vec<PathBuf>,
    log: PathBuf,
}

/// A `cargo` of the rustup proxy with `+nightly`, whatever toolchain runs the xtask: `$CARGO` is
/// the stable binary itself, which takes no `+toolchain`.
fn nightly_cargo() -> Command {
    let mut cmd = Command::new("cargo");
    cmd.arg(format!("+{NIGHTLY}"))
        .env_remove("RUSTUP_TOOLCHAIN");
    cmd
}

/// The nightly toolchain and cargo-fuzz at [`CARGO_FUZZ`], installed when missing.
fn setup() -> Result<()> {
    if output(nightly_cargo().arg("--version")).is_none() {
        eprintln!("- installing the {NIGHTLY} toolchain (minimal profile) for cargo-fuzz");
        run(Command::new("rustup").args([
            "toolchain",
            "install",
            NIGHTLY,
            "--profile",
            "minimal",
        ]))?;
    }
    let installed = output(nightly_cargo().args(["fuzz", "--version"]));
    if installed.is_some_and(|v| v.split_whitespace().nth(1) == Some(CARGO_FUZZ)) {
        return Ok(());
    }
    eprintln!("- installing cargo-fuzz {CARGO_FUZZ} (a minute or two)");
    run(crate::util::cargo().args([
        "install",
        "cargo-fuzz",
        "--version",
        CARGO_FUZZ,
        "--locked",
        "--force",
    ]))
}

/// The targets of `fuzz/Cargo.toml`, in its order.
fn targets(fuzz: &Path) -> Result<Vec<String>> {
    let text =
        std::fs::read_to_string(fuzz.join("Cargo.toml")).context("reading fuzz/Cargo.toml")?;
    let manifest: toml::Table = text.parse().context("fuzz/Cargo.toml is not TOML")?;
    let bins = manifest
        .get("bin")
        .and_then(toml::Value::as_array)
        .context("fuzz/Cargo.toml has no [[bin]]")?;
    bins.iter()
        .map(|b| {
            b.get("name")
                .and_then(toml::Value::as_str)
                .map(str::to_owned)
                .context("a [[bin]] of fuzz/Cargo.toml has no name")
        })
        .collect()
}

/// The files of a folder (none if it does not exist).
fn files(dir: &Path) -> BTreeSet<PathBuf> {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default()
}

/// The number after `name:` in libFuzzer's final statistics (`stat::name: N`).
fn stat(log: &str, name: &str) -> Option<u64> {
    let key = format!("stat::{name}:");
    log.lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix(&key))
        .and_then(|v| v.trim().parse().ok())
}

/// `cargo xtask fuzz`: every target named (all when none is) for `seconds` each.
pub(crate) fn all(workspace: &Path, seconds: u64, wanted: &[String]) -> Result<()> {
    let fuzz = workspace.join("fuzz");
    let known = targets(&fuzz)?;
    for t in wanted {
        if !known.contains(t) {
            bail!("no fuzz target {t}; the targets are {}", known.join(", "));
        }
    }
    let chosen: Vec<String> = if wanted.is_empty() {
        known
    } else {
        wanted.to_vec()
    };
    setup()?;
    // One build for all targets (they share every dependency). No sanitizer: the code is safe Rust
    // (`unsafe_code` is forbidden in the workspace), and without ASan a campaign runs about twice
    // as many inputs; panics, overflowing stacks, hangs and memory blow-ups are caught all the same.
    run(nightly_cargo()
        .current_dir(&fuzz)
        .args(["fuzz", "build", "--sanitizer", "none"]))?;
    let mut reports = Vec::new();
    for target in &chosen {
        reports.push(campaign(&fuzz, target, seconds)?);
    }
    print!("{}", summary(&reports, workspace));
    let found: usize = reports.iter().map(|r| r.findings.len()).sum();
    if found > 0 {
        bail!("{found} finding(s): see above");
    }
    Ok(())
}

fn campaign(fuzz: &Path, target: &str, seconds: u64) -> Result<Report> {
    let corpus = fuzz.join("corpus").join(target);
    // Where `cargo fuzz run` has libFuzzer write crashes and timeouts.
    let artifacts = fuzz.join("artifacts").join(target);
    std::fs::create_dir_all(&corpus).context("creating the corpus folder")?;
    std::fs::create_dir_all(&artifacts).context("creating the artifacts folder")?;
    let before = files(&artifacts);
    let log = artifacts.join("last-run.log");
    eprintln!(
        "- fuzzing {target} for {seconds} s (log: {})",
        log.display()
    );
    let mut cmd = nightly_cargo();
    cmd.current_dir(fuzz)
        .args(["fuzz", "run", "--sanitizer", "none", target])
        .arg(&corpus)
        .arg(fuzz.join("seeds").join(target))
        .arg("--")
        .arg(format!("-max_total_time={seconds}"))
        .arg(format!("-timeout={}", timeout(target)))
        .arg("-rss_limit_mb=2048")
        .arg("-print_final_stats=1");
    let dict = fuzz.join("dicts").join(format!("{target}.dict"));
    if dict.exists() {
        cmd.arg(format!("-dict={}", dict.display()));
    }
    let file = std::fs::File::create(&log).context("creating the log")?;
    let started = Instant::now();
    let status = cmd
        .stdout(Stdio::null())
        .stderr(file)
        .status()
        .with_context(|| format!("could not start cargo fuzz run {target}"))?;
    let took = started.elapsed();
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    let findings: Vec<PathBuf> = files(&artifacts)
        .difference(&before)
        .filter(|p| p.file_name().is_some_and(|n| n != "last-run.log"))
        .cloned()
        .collect();
    let runs = stat(&text, "number_of_executed_units");
    if runs.is_none() && findings.is_empty() {
        let tail: Vec<&str> = text.lines().rev().take(20).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        bail!(
            "cargo fuzz run {target} ended ({status}) without statistics:\n{}",
            tail.join("\n")
        );
    }
    let corpus = last_corpus(&text).unwrap_or_else(|| {
        let left = files(&corpus);
        let bytes: u64 = left
            .iter()
            .filter_map(|p| p.metadata().ok())
            .map(|m| m.len())
            .sum();
        format!("{} files, {} KiB", left.len(), bytes.div_ceil(1024))
    });
    Ok(Report {
        target: target.to_owned(),
        runs: runs.unwrap_or(0),
        per_second: stat(&text, "average_exec_per_sec").unwrap_or(0),
        seconds: took.as_secs_f64(),
        corpus,
        findings,
        log,
    })
}

/// The last corpus libFuzzer reported (`corp: 1989/443Kb`), as "1989 inputs, 443 KB".
fn last_corpus(log: &str) -> Option<String> {
    let line = log.lines().rev().find(|l| l.contains(" corp: "))?;
    let (_, rest) = line.split_once(" corp: ")?;
    let (count, size) = rest.split_whitespace().next()?.split_once('/')?;
    let size = size.replace("Kb", " KB").replace("Mb", " MB");
    let size = size
        .strip_suffix('b')
        .map_or(size.clone(), |b| format!("{b} bytes"));
    Some(format!("{count} inputs, {size}"))
}

/// The panic message of a finding, from the log: the line after `panicked at` and the one after.
fn panic_message(log: &Path) -> String {
    let text = std::fs::read_to_string(log).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines
        .iter()
        .position(|l| l.contains("panicked at"))
        .map(|i| lines[i..(i + 3).min(lines.len())].join("\n    "))
        .or_else(|| {
            lines
                .iter()
                .find(|l| l.contains("ERROR: libFuzzer"))
                .map(|l| (*l).to_owned())
        })
        .unwrap_or_default()
}

/// The first bytes of a file, printable ASCII as it is and the rest as `\xNN`.
fn preview(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_default();
    let mut s: String = bytes
        .iter()
        .take(240)
        .map(|&b| match b {
            b' '..=b'~' if b != b'\\' => char::from(b).to_string(),
            b'\n' => "\\n".into(),
            _ => format!("\\x{b:02x}"),
        })
        .collect();
    if bytes.len() > 240 {
        let _ = write!(s, "… ({} bytes)", bytes.len());
    }
    s
}

fn summary(reports: &[Report], workspace: &Path) -> String {
    let mut s = String::from(
        "\n| target | executions | exec/s | duration | corpus | findings |\n|---|---:|---:|---:|---:|---|\n",
    );
    for r in reports {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.target,
            r.runs,
            r.per_second,
            human(std::time::Duration::from_secs_f64(r.seconds)),
            r.corpus,
            if r.findings.is_empty() {
                "none".to_owned()
            } else {
                r.findings.len().to_string()
            }
        );
    }
    for r in reports {
        for f in &r.findings {
            let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("finding");
            let kind = name.split('-').next().unwrap_or("crash");
            let shown = f.strip_prefix(workspace).unwrap_or(f);
            let _ = writeln!(
                s,
                "\n{} {kind}: {}\n  input: {}\n  {}\n  file it, named for what it finds, and replay it with the tests:\n    mv {} fuzz/regressions/{}/<what-it-found>",
                r.target,
                shown.display(),
                preview(f),
                panic_message(&r.log),
                shown.display(),
                r.target,
            );
        }
    }
    s
}
