//! Progress on the terminal: an indicatif bar per long stage of one painting (a counted bar
//! for the relaxation iterations, spinners for the rest), counted bars over the files of a
//! batch or the tiles of a contact sheet, and, with `-v`, a line of per-stage timings at the
//! end. Bars draw only when standard error is a terminal and not with `-q`;
//! the timings print whenever `-v` is given, so they reach logs as well.

use crate::progress::{Observer, Stage};
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::Mutex;
use std::time::Duration;

/// How chatty a command is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Verbosity {
    /// No bars (failures and errors still print).
    pub quiet: bool,
    /// Print per-stage timings.
    pub verbose: bool,
}

/// An [`Observer`] drawing one bar per stage and collecting timings.
pub struct StageBars {
    verbosity: Verbosity,
    current: Mutex<Option<ProgressBar>>,
    timings: Mutex<Vec<(Stage, Duration, Option<u64>)>>,
}

impl StageBars {
    /// Bars (unless quiet) and timings (when verbose).
    pub fn new(verbosity: Verbosity) -> Self {
        StageBars {
            verbosity,
            current: Mutex::new(None),
            timings: Mutex::new(Vec::new()),
        }
    }

    /// Prints the per-stage timings when verbose, as one line.
    pub fn print_timings(&self) {
        if !self.verbosity.verbose {
            return;
        }
        let timings = self.timings.lock().expect("timings");
        let total: Duration = timings.iter().map(|t| t.1).sum();
        let parts: Vec<String> = timings
            .iter()
            .map(|(stage, elapsed, steps)| {
                let steps = steps.map_or(String::new(), |n| format!(" ({n} it)"));
                format!("{} {:.3} s{steps}", stage.label(), elapsed.as_secs_f64())
            })
            .collect();
        eprintln!(
            "timings: {}; total {:.3} s",
            parts.join(", "),
            total.as_secs_f64()
        );
    }
}

/// A bar counting `total` `things` (tiles, files) with elapsed time and ETA, titled `prefix`;
/// hidden when `quiet` (and, as every bar, off a terminal).
pub fn counted(total: usize, prefix: &str, things: &str, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let template = format!(
        "{{prefix}} [{{bar:32}}] {{pos}}/{{len}} {things}, {{elapsed}} elapsed, ETA {{eta}}"
    );
    let bar = ProgressBar::new(total as u64).with_style(
        ProgressStyle::with_template(&template)
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(prefix.to_string());
    bar
}

fn bar_for(stage: Stage, total: Option<u64>) -> ProgressBar {
    let bar = match total {
        Some(n) => ProgressBar::new(n).with_style(
            ProgressStyle::with_template(
                "{prefix:>10} [{bar:32}] {pos}/{len} iterations {elapsed}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        ),
        None => ProgressBar::new_spinner().with_style(
            ProgressStyle::with_template("{prefix:>10} {spinner} {elapsed}")
                .expect("valid template"),
        ),
    };
    bar.set_prefix(stage.label());
    if !bar.is_hidden() {
        bar.enable_steady_tick(Duration::from_millis(120));
    }
    bar
}

impl Observer for StageBars {
    fn begin(&self, stage: Stage, total: Option<u64>) {
        if self.verbosity.quiet {
            return;
        }
        let mut current = self.current.lock().expect("bar");
        if let Some(old) = current.take() {
            old.finish_and_clear();
        }
        *current = Some(bar_for(stage, total));
    }

    fn advance(&self, _stage: Stage, done: u64) {
        if let Some(bar) = self.current.lock().expect("bar").as_ref() {
            bar.set_position(done);
        }
    }

    fn end(&self, stage: Stage, elapsed: Duration, steps: Option<u64>) {
        if let Some(bar) = self.current.lock().expect("bar").take() {
            bar.finish_and_clear();
        }
        self.timings
            .lock()
            .expect("timings")
            .push((stage, elapsed, steps));
    }
}
