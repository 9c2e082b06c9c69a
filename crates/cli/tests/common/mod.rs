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

/// The error message of a run that failed: it must have failed, said `bezsolid: …` on one line of
/// stderr, and said no phrase of 12 or more characters twice (a cause printed by an error and by
/// its source). Gives the line without `bezsolid: `.
pub(crate) fn one_line_error(out: &Output) -> String {
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    assert!(!out.status.success(), "it succeeded; stderr: {err}");
    assert!(
        err.ends_with('\n') && err.matches('\n').count() == 1,
        "not one line: {err:?}"
    );
    let line = err
        .trim_end()
        .strip_prefix("bezsolid: ")
        .unwrap_or_else(|| panic!("not a bezsolid error: {err:?}"));
    if let Some(phrase) = repeated_phrase(line, 12) {
        panic!("{phrase:?} is said twice in {line:?}");
    }
    line.to_string()
}

/// The first run of `len` characters of `text` that occurs again after it, if any.
pub(crate) fn repeated_phrase(text: &str, len: usize) -> Option<&str> {
    let starts: Vec<usize> = text.char_indices().map(|(i, _)| i).collect();
    starts.iter().enumerate().find_map(|(k, &i)| {
        let end = starts.get(k + len).copied().or_else(|| {
            // The last window ends at the end of the text.
            (k + len == starts.len()).then_some(text.len())
        })?;
        let phrase = &text[i..end];
        text[end..].contains(phrase).then_some(phrase)
    })
}
