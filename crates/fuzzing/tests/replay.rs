//! Replays the campaigns' seeds and findings on stable Rust, in every `cargo test --workspace`:
//! each file of `fuzz/seeds/<target>/` and `fuzz/regressions/<target>/` through its target, each
//! within a time budget.
//!
//! A finding whose fix is still to come is listed in `fuzz/regressions/OPEN` (`target/file`, then
//! `panic` or `hang`, then what it finds). An open panic must still panic, so that its fix is
//! noticed and its line removed, which makes it a regression like the others; an open hang is not
//! run (nothing in a test can stop it).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use bezsolid_fuzzing::{TARGETS, target};

/// The most one input may take here (a debug build of the workspace; campaigns run optimised
/// builds under libFuzzer's `-timeout`, which is far shorter).
const BUDGET: Duration = Duration::from_secs(10);

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// The files of `dir`, sorted, or none if it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.expect("a readable folder").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// How an open finding fails.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Open {
    Panic,
    Hang,
}

/// The open findings: `target/file` and how each fails.
fn open_findings(fuzz: &Path) -> Vec<(String, Open)> {
    let text = std::fs::read_to_string(fuzz.join("regressions/OPEN")).unwrap_or_default();
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            let mut words = l.split_whitespace();
            let file = words.next().unwrap_or_default().to_owned();
            let how = match words.next() {
                Some("panic") => Open::Panic,
                Some("hang") => Open::Hang,
                other => panic!("fuzz/regressions/OPEN: {l:?}: {other:?} is not panic or hang"),
            };
            (file, how)
        })
        .collect()
}

#[test]
fn replay_seeds_and_regressions_within_budget() {
    let fuzz = fuzz_dir();
    // Every folder names a target, so that an input filed under a misspelt name is not skipped.
    for kind in ["seeds", "regressions"] {
        for entry in std::fs::read_dir(fuzz.join(kind)).expect("fuzz/ has seeds and regressions") {
            let path = entry.expect("a readable folder").path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            assert!(
                !path.is_dir() || target(name).is_some(),
                "{} is not a target's folder",
                path.display()
            );
        }
    }
    let open = open_findings(&fuzz);
    for (file, _) in &open {
        assert!(
            fuzz.join("regressions").join(file).is_file(),
            "fuzz/regressions/OPEN lists {file}, which is not in fuzz/regressions"
        );
    }
    let mut counts = Vec::new();
    let mut open_run = 0;
    let started = Instant::now();
    for &(name, run) in TARGETS {
        let seeds = files(&fuzz.join("seeds").join(name));
        assert!(!seeds.is_empty(), "no seeds for {name}");
        let regressions = files(&fuzz.join("regressions").join(name));
        for path in seeds.iter().chain(&regressions) {
            let listed = path
                .file_name()
                .and_then(|n| n.to_str())
                .map(|n| format!("{name}/{n}"));
            let how = open
                .iter()
                .find(|(f, _)| Some(f) == listed.as_ref())
                .map(|&(_, how)| how);
            let data = std::fs::read(path).expect("a readable input");
            match how {
                None => {
                    let t = Instant::now();
                    run(&data);
                    let took = t.elapsed();
                    assert!(
                        took <= BUDGET,
                        "{} took {took:?}, past the budget of {BUDGET:?}",
                        path.display()
                    );
                }
                Some(Open::Panic) => {
                    // Quietly: the message is printed on one line below, without a backtrace.
                    let hook = std::panic::take_hook();
                    std::panic::set_hook(Box::new(|_| {}));
                    let result = catch_unwind(AssertUnwindSafe(|| run(&data)));
                    std::panic::set_hook(hook);
                    let Err(payload) = result else {
                        panic!(
                            "{} no longer fails: remove its line from fuzz/regressions/OPEN",
                            path.display()
                        );
                    };
                    let message = payload
                        .downcast_ref::<String>()
                        .map(String::as_str)
                        .or_else(|| payload.downcast_ref::<&str>().copied())
                        .unwrap_or("");
                    let first = message.lines().next().unwrap_or("");
                    println!("open: {} still panics: {first}", path.display());
                    open_run += 1;
                }
                Some(Open::Hang) => {}
            }
        }
        counts.push((name, seeds.len(), regressions.len()));
    }
    let hangs = open.iter().filter(|(_, h)| *h == Open::Hang).count();
    let total: usize = counts.iter().map(|(_, s, r)| s + r).sum::<usize>() - hangs;
    let each: Vec<String> = counts
        .iter()
        .map(|(name, s, r)| format!("{name} {s}+{r}"))
        .collect();
    println!(
        "replayed {total} inputs in {:?} (seeds+regressions: {}); open findings: {open_run} still \
         panic, {hangs} hangs not run",
        started.elapsed(),
        each.join(", "),
    );
}
