//! What the commands share in their arguments: the parser (clap, with the settings every command
//! keeps), the words of its refusals (the same as the command line has always said them), the
//! MODEL and required options, and the box option.

use anyhow::{Context, Result, bail};
use clap::error::{ContextKind, ContextValue, ErrorKind};

/// `cmd` with the settings the command line has always had, on it and on every subcommand: an
/// option given twice takes its last value, and an option's value may begin with `-`
/// (`--box -1,-1,-1,1,1,1`, `--height -1` refused by the command with its reason).
pub(crate) fn settle(cmd: clap::Command) -> clap::Command {
    cmd.args_override_self(true)
        .mut_args(|arg| {
            let takes_value = arg.get_action().takes_values();
            if takes_value && !arg.is_positional() {
                arg.allow_hyphen_values(true)
            } else {
                arg
            }
        })
        .mut_subcommands(settle)
}

/// A refusal of the parser: what to print after `bezsolid: ` on stderr, and the exit code.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct Refusal {
    pub(crate) message: String,
    pub(crate) code: u8,
}

/// The words of clap's refusal `e` of the arguments `raw` (after the program's name): an unknown
/// option, a stray argument, an option without its value or with a value that is not a number say
/// what they always said, with exit code 1; an unknown command says so with the usage, code 2.
/// Anything else is clap's own first sentence, code 1.
pub(crate) fn refusal(e: &clap::Error, raw: &[String], usage: &str) -> Refusal {
    let cmd = command_path(raw);
    let context = |kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.as_str()),
        _ => None,
    };
    // The argument as typed; for a value's error, clap's "--res <N>" names the option `--res`.
    let typed = context(ContextKind::InvalidArg).unwrap_or_default();
    let option = typed.split(' ').next().unwrap_or(typed);
    let unknown_command = |word: &str| Refusal {
        message: format!("unknown command `{word}`\n\n{usage}"),
        code: 2,
    };
    let message = match e.kind() {
        // Before the command, as the command.
        ErrorKind::InvalidSubcommand | ErrorKind::UnknownArgument if cmd.starts_with('-') => {
            return unknown_command(&cmd);
        }
        ErrorKind::InvalidSubcommand | ErrorKind::UnknownArgument if cmd == "esc" => format!(
            "esc: unknown command `{}`; usage: {}",
            context(ContextKind::InvalidSubcommand).unwrap_or(typed),
            crate::esc::USAGE
        ),
        ErrorKind::InvalidSubcommand => {
            return unknown_command(context(ContextKind::InvalidSubcommand).unwrap_or_default());
        }
        ErrorKind::UnknownArgument if typed.starts_with('-') && typed.len() > 1 => {
            format!("{cmd}: unknown option {typed}")
        }
        ErrorKind::UnknownArgument => format!("{cmd}: unexpected argument {typed}"),
        ErrorKind::InvalidValue if context(ContextKind::InvalidValue).is_none_or(str::is_empty) => {
            // Said as it was typed: `-o needs a value`.
            let typed = raw
                .last()
                .filter(|a| a.starts_with('-'))
                .map_or(option, String::as_str);
            format!("{typed} needs a value")
        }
        ErrorKind::ValueValidation => format!(
            "{option} {} is not a valid number here",
            context(ContextKind::InvalidValue).unwrap_or_default()
        ),
        _ if cmd.is_empty() => clap_sentence(e),
        _ => format!("{cmd}: {}", clap_sentence(e)),
    };
    Refusal { message, code: 1 }
}

/// The command the arguments name, as messages name it: `mesh`, or `esc classify`.
fn command_path(raw: &[String]) -> String {
    match raw {
        [esc, sub, ..] if esc == "esc" && ["classify", "bool", "expr"].contains(&sub.as_str()) => {
            format!("esc {sub}")
        }
        [cmd, ..] => cmd.clone(),
        [] => String::new(),
    }
}

/// clap's message for `e` in one sentence, without its `error: `, its usage and its tips.
fn clap_sentence(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let text = text.trim_start_matches("error: ");
    let text = text.split("\n\nUsage:").next().unwrap_or(text);
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| {
            !l.is_empty() && !l.starts_with("For more information") && !l.starts_with("tip:")
        })
        .collect();
    lines.join(" ")
}

/// The MODEL argument of the commands that take a model file, a share link or a preset.
#[derive(clap::Args)]
pub(crate) struct Model {
    /// The model: a model file, a share link, a HyperFun file bezsolid exported or a preset (see
    /// `bezsolid --help`).
    #[arg(value_name = "MODEL")]
    model: Option<String>,
}

impl Model {
    /// The model, which command `cmd` needs; `usage` is shown when it is missing.
    pub(crate) fn get(&self, cmd: &str, usage: &str) -> Result<&str> {
        model(cmd, self.model.as_deref(), usage)
    }
}

/// The MODEL argument of command `cmd`; `usage` is shown when it is missing.
pub(crate) fn model<'a>(cmd: &str, model: Option<&'a str>, usage: &str) -> Result<&'a str> {
    model.with_context(|| format!("{cmd}: which model? usage: {usage}"))
}

/// The value of an option of command `cmd` that must be given; `what` says what it is for.
pub(crate) fn required<T>(cmd: &str, value: Option<T>, what: &str) -> Result<T> {
    value.with_context(|| format!("{cmd}: {what} is required"))
}

/// The box `text` of option `name`, `x0,y0[,z0],x1,y1[,z1]` (`D` coordinates per corner), if given.
pub(crate) fn bounds<const D: usize>(
    name: &str,
    text: Option<&str>,
) -> Result<Option<([f64; D], [f64; D])>> {
    let Some(text) = text else {
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
