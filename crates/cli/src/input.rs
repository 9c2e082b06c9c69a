//! Reading input with a cap that holds whatever the input is: a file, a pipe, a FIFO or a device.
//!
//! The size a file system reports is 0 for a pipe or `/dev/zero`, so a cap checked against it
//! holds for regular files only. Every reader here reads through [`Capped`] instead: at most
//! `cap + 1` bytes ([`Read::take`]), and reading the byte past the cap is an error that says so
//! ([`TooLarge`]). Whole files come from [`read_bytes`] and [`read_text`]; a file parsed line by line
//! (points) from [`open`], whose [`Lines`] hold one line at a time.

use std::fmt;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Take};

use anyhow::{Result, anyhow};

/// The largest model file read (a degree-16 volume with long decimals is well under 1 MiB).
pub(crate) const MAX_MODEL_BYTES: u64 = 16 << 20;

/// The largest points file read (CSV for `eval` and `esc`). Points are read a line at a time, so
/// this bounds the memory a line without an end (`/dev/zero`) takes; it holds about 4 million 3D
/// points written with all 17 digits (63 bytes a line), and the 10 million of the points cap when
/// they are written with 6 digits or so.
pub(crate) const MAX_POINTS_BYTES: u64 = 256 << 20;

/// An input passed its cap.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct TooLarge {
    /// The path as given.
    pub(crate) path: String,
    /// What it was read as, e.g. "model file".
    pub(crate) what: &'static str,
    /// The cap, in bytes.
    pub(crate) cap: u64,
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Self { path, what, cap } = self;
        write!(f, "{path} is too large: a {what} is at most ")?;
        match *cap {
            c if c > 0 && c % (1 << 20) == 0 => write!(f, "{} MiB", c >> 20),
            c if c > 0 && c % (1 << 10) == 0 => write!(f, "{} KiB", c >> 10),
            c => write!(f, "{c} bytes"),
        }
    }
}

impl std::error::Error for TooLarge {}

/// A reader that gives at most `cap` bytes and fails with [`TooLarge`] on the byte after them.
pub(crate) struct Capped<R> {
    inner: Take<R>,
    error: TooLarge,
}

impl<R: Read> Capped<R> {
    /// `inner`, capped at `cap` bytes; `path` and `what` are for the message.
    pub(crate) fn new(inner: R, path: &str, what: &'static str, cap: u64) -> Self {
        Self {
            inner: inner.take(cap.saturating_add(1)),
            error: TooLarge {
                path: path.into(),
                what,
                cap,
            },
        }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        // The limit is cap + 1: at 0, the byte past the cap has been read.
        if n > 0 && self.inner.limit() == 0 {
            return Err(io::Error::other(self.error.clone()));
        }
        Ok(n)
    }
}

/// The error of reading `path`: the cap's own message, or the system's after `cannot read PATH`.
pub(crate) fn read_error(path: &str, e: io::Error) -> anyhow::Error {
    match e
        .get_ref()
        .and_then(|inner| inner.downcast_ref::<TooLarge>())
    {
        Some(too_large) => anyhow!(too_large.clone()),
        None => anyhow!("cannot read {path}: {e}"),
    }
}

/// How many bytes to make room for next in a buffer that holds `len` bytes of an input capped at
/// `cap`: double, as `Vec` grows, but never past `cap + 1` in all, so that an input as long as its
/// cap (`/dev/zero`) takes its cap in memory, not twice that.
fn room(len: usize, cap: u64) -> usize {
    let left = usize::try_from(cap)
        .unwrap_or(usize::MAX)
        .saturating_add(1)
        .saturating_sub(len);
    len.max(1 << 16).min(left).max(1)
}

/// The lines of a capped input, one at a time (see [`open`]).
pub(crate) struct Lines {
    reader: BufReader<Capped<File>>,
    path: String,
    cap: u64,
    /// The bytes of the lines given so far.
    read: u64,
    /// The file's length, when it is a regular file.
    len: Option<u64>,
}

impl Lines {
    /// The next line, with its `\n` if it has one, into `line` (whatever it held is dropped);
    /// false at the end of the input. `line` grows as [`read_bytes`] does: a line as long as the
    /// cap takes the cap in memory.
    ///
    /// # Errors
    ///
    /// When the input cannot be read, or goes past its cap.
    pub(crate) fn next_into(&mut self, line: &mut Vec<u8>) -> Result<bool> {
        line.clear();
        loop {
            let room = room(line.len(), self.cap);
            line.reserve_exact(room);
            let n = (&mut self.reader)
                .take(room as u64)
                .read_until(b'\n', line)
                .map_err(|e| read_error(&self.path, e))?;
            self.read += n as u64;
            if n == 0 || line.last() == Some(&b'\n') {
                return Ok(!line.is_empty());
            }
        }
    }

    /// The bytes read so far, and the input's length where it is known (a regular file's, not a
    /// pipe's).
    pub(crate) fn progress(&self) -> (u64, Option<u64>) {
        (self.read, self.len)
    }
}

/// `path` opened to be read a line at a time, at most `cap` bytes of it (`what` names it in the
/// message).
///
/// # Errors
///
/// When the file cannot be opened.
pub(crate) fn open(path: &str, cap: u64, what: &'static str) -> Result<Lines> {
    let file = File::open(path).map_err(|e| read_error(path, e))?;
    let len = file
        .metadata()
        .ok()
        .filter(std::fs::Metadata::is_file)
        .map(|m| m.len());
    Ok(Lines {
        reader: BufReader::new(Capped::new(file, path, what, cap)),
        path: path.into(),
        cap,
        read: 0,
        len,
    })
}

/// All bytes of `path`, refused past `cap` (`what` names it in the message).
///
/// # Errors
///
/// When it cannot be read, or it is longer than `cap`.
pub(crate) fn read_bytes(path: &str, cap: u64, what: &'static str) -> Result<Vec<u8>> {
    let file = File::open(path).map_err(|e| read_error(path, e))?;
    let mut reader = Capped::new(file, path, what, cap);
    let mut bytes = Vec::new();
    loop {
        let room = room(bytes.len(), cap);
        bytes.reserve_exact(room);
        let n = (&mut reader)
            .take(room as u64)
            .read_to_end(&mut bytes)
            .map_err(|e| read_error(path, e))?;
        if n < room {
            return Ok(bytes);
        }
    }
}

/// All of `path` as UTF-8 text, refused past `cap` (`what` names it in the message).
///
/// # Errors
///
/// As [`read_bytes`], and when the text is not UTF-8.
pub(crate) fn read_text(path: &str, cap: u64, what: &'static str) -> Result<String> {
    String::from_utf8(read_bytes(path, cap, what)?)
        .map_err(|_| anyhow!("cannot read {path}: stream did not contain valid UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(data: &[u8], cap: u64) -> io::Result<Vec<u8>> {
        let mut out = Vec::new();
        Capped::new(data, "in", "test", cap).read_to_end(&mut out)?;
        Ok(out)
    }

    #[test]
    fn capped_reads_up_to_the_cap_and_refuses_one_byte_more() {
        assert_eq!(read_all(b"", 0).unwrap(), b"");
        assert_eq!(read_all(b"abc", 3).unwrap(), b"abc");
        assert_eq!(read_all(b"abc", 4).unwrap(), b"abc");
        for (data, cap) in [(&b"abcd"[..], 3), (b"a", 0)] {
            let e = read_all(data, cap).unwrap_err();
            let message = read_error("in", e).to_string();
            assert_eq!(
                message,
                format!("in is too large: a test is at most {cap} bytes")
            );
        }
        // An endless input stops at the cap.
        let mut out = Vec::new();
        let e = Capped::new(io::repeat(0), "zero", "model file", 16 << 20)
            .read_to_end(&mut out)
            .unwrap_err();
        assert!(out.len() <= (16 << 20) + 1);
        assert_eq!(
            read_error("zero", e).to_string(),
            "zero is too large: a model file is at most 16 MiB"
        );
    }

    #[test]
    fn lines_come_one_at_a_time_up_to_the_cap() {
        let path = std::env::temp_dir().join(format!("bezsolid-lines-{}", std::process::id()));
        std::fs::write(&path, "ab\n\nc\r\nlast").unwrap();
        let path = path.to_str().unwrap();
        let mut line = Vec::new();
        let mut got = Vec::new();
        let mut lines = open(path, 12, "test").unwrap();
        while lines.next_into(&mut line).unwrap() {
            got.push(String::from_utf8(line.clone()).unwrap());
        }
        assert_eq!(got, ["ab\n", "\n", "c\r\n", "last"]);
        // Exactly the cap is read; one byte more is not.
        let mut lines = open(path, 11, "test").unwrap();
        for _ in 0..4 {
            assert!(lines.next_into(&mut line).unwrap());
        }
        assert!(!lines.next_into(&mut line).unwrap());
        // One byte short: refused when a read reaches the byte past the cap (through the buffer,
        // before the last line comes).
        let mut lines = open(path, 10, "test").unwrap();
        let mut read = 0;
        let e = loop {
            match lines.next_into(&mut line) {
                Ok(more) => assert!(more, "it ended without the error"),
                Err(e) => break e,
            }
            read += 1;
        };
        assert!(read < 4);
        assert_eq!(
            e.to_string(),
            format!("{path} is too large: a test is at most 10 bytes")
        );
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn other_read_errors_name_the_path() {
        let e = read_bytes("/no/such/dir/file", 10, "test").unwrap_err();
        assert!(
            e.to_string().starts_with("cannot read /no/such/dir/file: "),
            "{e}"
        );
        assert_eq!(
            TooLarge {
                path: "p".into(),
                what: "script",
                cap: 256 << 10
            }
            .to_string(),
            "p is too large: a script is at most 256 KiB"
        );
    }
}
