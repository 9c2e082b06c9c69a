//! The arguments every command takes: one MODEL and `--name value` options (`-o` is `--output`).

use std::str::FromStr;

use anyhow::{Context, Result, bail};

/// A command's parsed arguments.
pub(crate) struct Args<'a> {
    cmd: &'static str,
    model: Option<&'a str>,
    values: Vec<(&'static str, &'a str)>,
    flags: Vec<&'static str>,
}

impl<'a> Args<'a> {
    /// Parses `args` for command `cmd`, which takes the options named in `options` (each with a
    /// value). Unknown options and a second positional argument are errors.
    pub(crate) fn parse(
        cmd: &'static str,
        args: &'a [String],
        options: &[&'static str],
    ) -> Result<Self> {
        Self::parse_with_flags(cmd, args, options, &[])
    }

    /// [`Args::parse`] for a command that also takes the options named in `flags`, which take
    /// no value ([`Args::flag`]).
    pub(crate) fn parse_with_flags(
        cmd: &'static str,
        args: &'a [String],
        options: &[&'static str],
        flags: &[&'static str],
    ) -> Result<Self> {
        let mut parsed = Self {
            cmd,
            model: None,
            values: Vec::new(),
            flags: Vec::new(),
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let name = if a == "-o" { "--output" } else { a.as_str() };
            if let Some(&flag) = flags.iter().find(|&&f| f == name) {
                parsed.flags.push(flag);
            } else if let Some(&option) = options.iter().find(|&&o| o == name) {
                let value = it.next().with_context(|| format!("{a} needs a value"))?;
                parsed.values.push((option, value));
            } else if a.starts_with('-') && a.len() > 1 {
                bail!("{cmd}: unknown option {a}");
            } else if parsed.model.is_none() {
                parsed.model = Some(a);
            } else {
                bail!("{cmd}: unexpected argument {a}");
            }
        }
        Ok(parsed)
    }

    /// The MODEL argument; `usage` is shown when it is missing.
    pub(crate) fn model(&self, usage: &str) -> Result<&'a str> {
        self.model
            .with_context(|| format!("{}: which model? usage: {usage}", self.cmd))
    }

    /// Whether the flag `name` was given.
    pub(crate) fn flag(&self, name: &str) -> bool {
        self.flags.contains(&name)
    }

    /// The value of option `name` (the last one given), if any.
    pub(crate) fn value(&self, name: &str) -> Option<&'a str> {
        self.values
            .iter()
            .rev()
            .find(|(n, _)| *n == name)
            .map(|&(_, v)| v)
    }

    /// The value of option `name`, which must be given; `what` says what it is for.
    pub(crate) fn required(&self, name: &str, what: &str) -> Result<&'a str> {
        self.value(name)
            .with_context(|| format!("{}: {what} is required", self.cmd))
    }

    /// Option `name` parsed as a number, `default` when absent.
    pub(crate) fn number<T: FromStr>(&self, name: &str, default: T) -> Result<T> {
        match self.value(name) {
            None => Ok(default),
            Some(v) => v
                .parse()
                .ok()
                .with_context(|| format!("{name} {v} is not a valid number here")),
        }
    }

    /// The box of option `name`, `x0,y0[,z0],x1,y1[,z1]` (`D` coordinates per corner), if given.
    pub(crate) fn bounds<const D: usize>(
        &self,
        name: &str,
    ) -> Result<Option<([f64; D], [f64; D])>> {
        let Some(text) = self.value(name) else {
            return Ok(None);
        };
        let usage = || {
            let corner = ["x", "y", "z"][..D].join(",");
            format!(
                "{name} takes {} numbers: {corner} of the low corner, then of the high",
                2 * D
            )
        };
        let numbers = text
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| anyhow::anyhow!("{}: {text:?}", usage()))?;
        if numbers.len() != 2 * D {
            bail!("{}: {text:?}", usage());
        }
        let lo = core::array::from_fn(|i| numbers[i]);
        let hi = core::array::from_fn(|i| numbers[D + i]);
        if (0..D).any(|i| !(lo[i].is_finite() && hi[i].is_finite() && lo[i] < hi[i])) {
            bail!("{name}: every coordinate must be finite, the low corner's below the high one's");
        }
        Ok(Some((lo, hi)))
    }
}
