//! A progress bar on stderr for work that may take seconds: a mesh of a net that folds, of a tree
//! at a fine resolution or of a free-form result, and many points evaluated.
//!
//! It is drawn only when stderr is a terminal, and only once the work has run for
//! [`SHOWN_AFTER`], so that quick commands print nothing more; in a pipe or a file (a log, a test)
//! it is never drawn. It is cleared when the work ends, leaving the lines the command prints.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long work runs before its bar is drawn.
pub(crate) const SHOWN_AFTER: Duration = Duration::from_millis(400);

/// The progress of one piece of work.
pub(crate) struct Progress {
    bar: ProgressBar,
    start: Instant,
    /// Whether the bar may be drawn at all (stderr is a terminal).
    terminal: bool,
    shown: bool,
}

impl Progress {
    /// The progress of `what` ("meshing"), to be drawn if stderr is a terminal; not when the
    /// command writes its rows on stdout (`rows_on_stdout`) and that is the terminal too, where
    /// the bar would be drawn over them.
    pub(crate) fn new(what: &'static str, rows_on_stdout: bool) -> Self {
        let terminal =
            std::io::stderr().is_terminal() && !(rows_on_stdout && std::io::stdout().is_terminal());
        Self::with_terminal(what, terminal)
    }

    /// Whether the bar may be drawn: work that costs something to report its progress (a mesh
    /// made in rounds) need not, when it is not.
    pub(crate) fn live(&self) -> bool {
        self.terminal
    }

    fn with_terminal(what: &'static str, terminal: bool) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_message(what);
        Self {
            bar,
            start: Instant::now(),
            terminal,
            shown: false,
        }
    }

    /// `done` of `total` steps are done (the work's own steps: layers, cells, bytes).
    pub(crate) fn steps(&mut self, done: usize, total: usize) {
        self.at(done as u64, Some(total as u64));
    }

    /// `done` units are done, of `total` when it is known; without a total they are bytes (of a
    /// pipe, whose length is not known).
    pub(crate) fn at(&mut self, done: u64, total: Option<u64>) {
        if self.bar.length() != total {
            match total {
                Some(total) => self.bar.set_length(total),
                None => self.bar.unset_length(),
            }
        }
        self.bar.set_position(done);
        if self.terminal && !self.shown && self.start.elapsed() >= SHOWN_AFTER {
            self.shown = true;
            let template = if total.is_some() {
                "{msg} [{bar:32}] {percent:>3}% {elapsed} (about {eta} left)"
            } else {
                "{spinner} {msg}: {binary_bytes} read, {elapsed}"
            };
            if let Ok(style) = ProgressStyle::with_template(template) {
                self.bar.set_style(style.progress_chars("=> "));
            }
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.bar.enable_steady_tick(Duration::from_millis(120));
        }
    }

    /// The work is done: the bar is cleared (before anything else is printed on stderr). A
    /// progress dropped on an error clears its bar too.
    pub(crate) fn finish(self) {
        drop(self);
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bar_is_drawn_on_a_terminal_after_a_while_and_never_elsewhere() {
        let mut piped = Progress::with_terminal("meshing", false);
        assert!(!piped.live());
        let mut terminal = Progress::with_terminal("meshing", true);
        piped.steps(1, 10);
        terminal.steps(1, 10);
        // Quick work draws nothing.
        assert!(!piped.shown && !terminal.shown);
        std::thread::sleep(SHOWN_AFTER);
        piped.steps(2, 10);
        terminal.steps(2, 10);
        assert!(!piped.shown);
        assert!(terminal.shown);
        assert_eq!(terminal.bar.position(), 2);
        assert_eq!(terminal.bar.length(), Some(10));
        terminal.at(5, None);
        assert_eq!(terminal.bar.length(), None);
        piped.finish();
        terminal.finish();
    }
}
