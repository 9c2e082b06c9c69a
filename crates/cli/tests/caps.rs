//! Input caps hold whatever the input is: a regular file, a pipe, a FIFO or a device. Each reader
//! reads at most its cap and one byte more, and refuses with a one-line message; a regression that
//! reads on fails under the run's memory limit or its time limit, and does not hang.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use std::time::Duration;

use common::{Feed, bezsolid_bounded, one_line_error, out_path, scratch};

/// Far more than reading a cap's worth of bytes takes, even on a busy machine.
const LIMIT: Duration = Duration::from_secs(60);

/// Runs `args` with 1 GiB of address space and expects the one-line refusal that `says`.
fn refused(args: &[&str], feed: Feed, says: &str) {
    let out = bezsolid_bounded(args, feed, 1024, LIMIT);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = one_line_error(&out);
    assert!(line.contains(says), "{args:?}: {line}");
}

#[test]
fn endless_devices_are_refused_at_the_cap() {
    let pts = scratch("p.csv", "0,0,0\n");
    let pts = pts.to_str().unwrap();
    for (args, says) in [
        (
            vec!["link", "/dev/zero"],
            "/dev/zero is too large: a model file is at most 16 MiB",
        ),
        (
            vec!["eval", "/dev/zero", "--points", pts],
            "/dev/zero is too large: a model file is at most 16 MiB",
        ),
        (
            vec!["eval", "preset:fig9", "--points", "/dev/zero"],
            "/dev/zero is too large: a points file is at most 256 MiB",
        ),
        (
            vec!["esc", "classify", "/dev/zero", "--points", pts],
            "/dev/zero is too large: a mesh file is at most 128 MiB",
        ),
        (
            vec!["esc", "classify", "example:torus", "--points", "/dev/zero"],
            "/dev/zero is too large: a points file is at most 256 MiB",
        ),
        (
            vec!["plasm", "/dev/zero"],
            "/dev/zero is too large: a model file is at most 16 MiB",
        ),
        (
            vec!["link", "/dev/urandom"],
            "/dev/urandom is too large: a model file is at most 16 MiB",
        ),
    ] {
        refused(&args, Feed::Nothing, says);
    }
}

#[test]
fn endless_pipes_are_refused_at_the_cap() {
    // Valid lines, so that only the cap can stop them: comments for the points, a JSON string
    // that never closes for the model.
    refused(
        &["eval", "preset:fig9", "--points", "/dev/stdin"],
        Feed::Endless(b"# a comment line that is skipped\n"),
        "/dev/stdin is too large: a points file is at most 256 MiB",
    );
    refused(
        &["link", "/dev/stdin"],
        Feed::Endless(b"{\"format\": \"bezsolid\", \"solid\": \"long"),
        "/dev/stdin is too large: a model file is at most 16 MiB",
    );
}

#[test]
fn endless_fifos_are_refused_at_the_cap() {
    let fifo = out_path("endless.psm");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let path = fifo.clone();
    // The writer opens the FIFO (which waits for the reader) and writes until the reader is gone.
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        let mut w = std::fs::OpenOptions::new().write(true).open(path).unwrap();
        while w.write_all(b"1 + 1;\n").is_ok() {}
    });
    refused(
        &["plasm", fifo.to_str().unwrap()],
        Feed::Nothing,
        "endless.psm is too large: a script is at most 256 KiB",
    );
    writer.join().unwrap();
}

#[test]
fn regular_files_past_the_cap_are_refused() {
    // Sparse: no disk is used for the zeros.
    let big = out_path("big.obj");
    std::fs::File::create(&big)
        .unwrap()
        .set_len((128 << 20) + 1)
        .unwrap();
    let pts = scratch("q.csv", "0,0,0\n");
    refused(
        &[
            "esc",
            "classify",
            big.to_str().unwrap(),
            "--points",
            pts.to_str().unwrap(),
        ],
        Feed::Nothing,
        "big.obj is too large: a mesh file is at most 128 MiB",
    );
    let model = out_path("big.bsolid.json");
    std::fs::File::create(&model)
        .unwrap()
        .set_len((16 << 20) + 1)
        .unwrap();
    refused(
        &["link", model.to_str().unwrap()],
        Feed::Nothing,
        "big.bsolid.json is too large: a model file is at most 16 MiB",
    );
}

#[test]
fn free_form_models_are_refused_by_their_counts_in_little_memory() {
    // A million triangles in a model file of 8 MB (under its 16 MiB cap): reading it whole took
    // about 200 MB before the count was checked; now the list is refused at its 200001st
    // triangle, within 48 MiB of address space.
    let triangles = vec!["[0,1,2]"; 1_000_000].join(",");
    let model = scratch(
        "million.bsolid.json",
        &format!(
            r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "esc", "operands": [
               {{"mesh": {{"positions": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [{triangles}]}}}}]}}}}"#
        ),
    );
    let pts = scratch("r.csv", "0,0,0\n");
    for args in [
        vec![
            "esc",
            "classify",
            model.to_str().unwrap(),
            "--points",
            pts.to_str().unwrap(),
        ],
        vec!["link", model.to_str().unwrap()],
        vec!["mesh", model.to_str().unwrap(), "-o", "never.stl"],
    ] {
        let out = bezsolid_bounded(&args, Feed::Nothing, 48, LIMIT);
        let line = one_line_error(&out);
        assert!(
            line.contains(
                "is not a valid model file: a mesh has more than 200000 triangles (the most a \
                 free-form model takes)"
            ),
            "{args:?}: {line}"
        );
    }
    assert!(!std::path::Path::new("never.stl").exists());
}
