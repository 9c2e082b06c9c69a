//! Helpers shared by the CLI's integration tests: running the binary and a scratch folder per test
//! binary and process.

#![allow(dead_code)] // each test binary uses its own subset
#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `bezsolid` binary with `args`.
pub(crate) fn bezsolid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bezsolid"))
        .args(args)
        .output()
        .unwrap()
}

/// The path of `name` in this test binary's scratch folder (created).
pub(crate) fn out_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "bezsolid-{}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Writes `contents` to `name` in the scratch folder and returns its path.
pub(crate) fn scratch(name: &str, contents: &str) -> PathBuf {
    let path = out_path(name);
    std::fs::write(&path, contents).unwrap();
    path
}
