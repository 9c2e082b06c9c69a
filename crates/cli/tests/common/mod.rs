//! Helpers shared by the CLI's integration tests: running the binary and a scratch folder per test
//! binary and process.

#![allow(dead_code)] // each test binary uses its own subset
#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::Duration;

/// Runs the `bezsolid` binary with `args`.
pub(crate) fn bezsolid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bezsolid"))
        .args(args)
        .output()
        .unwrap()
}

/// Runs the `bezsolid` binary with `args`, which must succeed (else the test fails with its
/// stderr).
pub(crate) fn succeed(args: &[&str]) -> Output {
    let out = bezsolid(args);
    assert!(
        out.status.success(),
        "bezsolid {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
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

/// What a bounded run gets on its stdin.
pub(crate) enum Feed {
    /// Nothing (stdin is `/dev/null`).
    Nothing,
    /// These bytes over and over, until it stops reading.
    Endless(&'static [u8]),
    /// These bytes, then the end.
    Once(Vec<u8>),
}

/// Runs the `bezsolid` binary with `args` under an address-space limit of `memory_mib` MiB
/// (`ulimit -v`: a reader that ignores its cap, or a command that holds what it should stream,
/// fails instead of taking the machine's memory), with `feed` on its stdin, and panics if it works
/// past `limit`.
///
/// The limit is of the processor time the command used (where the system says it, as Linux's
/// `/proc` does), not of the time on the clock: a budget of work, which other work on a shared
/// machine does not eat into. The clock still stops a command that waits forever, at ten times the
/// limit and a minute.
pub(crate) fn bezsolid_bounded(
    args: &[&str],
    feed: Feed,
    memory_mib: u64,
    limit: std::time::Duration,
) -> Output {
    use std::io::{Read, Write};
    use std::process::Stdio;
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {} && exec \"$0\" \"$@\"",
            memory_mib * 1024
        ))
        .arg(env!("CARGO_BIN_EXE_bezsolid"))
        .args(args)
        .stdin(if matches!(feed, Feed::Nothing) {
            Stdio::null()
        } else {
            Stdio::piped()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let feeder = child.stdin.take().map(|mut stdin| {
        std::thread::spawn(move || match feed {
            // Until the reader is gone (a broken pipe).
            Feed::Endless(chunk) => while stdin.write_all(chunk).is_ok() {},
            Feed::Once(bytes) => {
                let _ = stdin.write_all(&bytes);
            }
            Feed::Nothing => {}
        })
    });
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        let worked = cpu_time(child.id());
        let waited = start.elapsed();
        if worked.unwrap_or(waited) > limit || waited > limit * 10 + Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "bezsolid {args:?} still ran after {limit:?} (processor time {worked:?}, on the \
                 clock {waited:?})"
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    if let Some(feeder) = feeder {
        feeder.join().unwrap();
    }
    Output {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// The processor time (user and system) process `pid` has used so far, where `/proc` says it.
fn cpu_time(pid: u32) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command's name, which is bracketed and may hold spaces.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the line, in ticks of 1/100 s (USER_HZ).
    let ticks = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// A small deterministic generator (xorshift): the same inputs on every run.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// A number in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
