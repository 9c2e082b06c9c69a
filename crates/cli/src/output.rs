//! Where a command writes rows as it makes them: a buffered `-o` file or stdout.

use std::fmt;
use std::fs::File;
use std::io::{self, BufWriter, Write};

use anyhow::{Result, anyhow};

/// A buffered output that names itself in its errors.
pub(crate) struct Sink {
    out: BufWriter<Box<dyn Write>>,
    name: String,
    stdout: bool,
}

impl Sink {
    /// The file `path` (created, or truncated), or stdout without one.
    ///
    /// # Errors
    ///
    /// When the file cannot be created.
    pub(crate) fn create(path: Option<&str>) -> Result<Self> {
        let (out, name): (Box<dyn Write>, _) = match path {
            Some(path) => (
                Box::new(File::create(path).map_err(|e| anyhow!("cannot write {path}: {e}"))?),
                path.to_string(),
            ),
            None => (Box::new(io::stdout().lock()), "stdout".to_string()),
        };
        Ok(Self {
            out: BufWriter::with_capacity(1 << 16, out),
            name,
            stdout: path.is_none(),
        })
    }

    /// Whether this is stdout.
    pub(crate) fn is_stdout(&self) -> bool {
        self.stdout
    }

    /// Writes `args`.
    ///
    /// # Errors
    ///
    /// When the output cannot be written (a full disk, a closed pipe).
    pub(crate) fn write(&mut self, args: fmt::Arguments<'_>) -> Result<()> {
        self.out
            .write_fmt(args)
            .map_err(|e| anyhow!("cannot write {}: {e}", self.name))
    }

    /// Writes what is buffered.
    ///
    /// # Errors
    ///
    /// As [`Sink::write`].
    pub(crate) fn finish(mut self) -> Result<()> {
        self.out
            .flush()
            .map_err(|e| anyhow!("cannot write {}: {e}", self.name))
    }
}
