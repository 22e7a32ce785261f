//! Stage timing and progress: the [`Progress`] events every long stage reports, the
//! [`Clock`] that times a stage and records a [`StageTiming`], and [`StageProgress`], the
//! terminal reporter the command-line program uses.
//!
//! Progress never decides a run: a reporter that cannot print drops the message.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write as _};
use std::time::{Duration, Instant};

/// Wall time of one pipeline stage.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StageTiming {
    /// Stage name.
    pub stage: &'static str,
    /// Seconds.
    pub seconds: f64,
}

/// Receives stage start/finish events (the CLI shows them as progress).
pub trait Progress {
    /// A part of the run begins whose stages belong together (one body of several, one
    /// method of a comparison); `label` names it.
    fn section(&mut self, _label: &str) {}
    /// A stage begins.
    fn start(&mut self, _stage: &'static str) {}
    /// The running stage has done `done` of `total` units of countable work (condensation
    /// columns, Lemke pivots, load increments).
    fn advance(&mut self, _done: usize, _total: usize) {}
    /// A stage ended after `seconds`.
    fn finish(&mut self, _stage: &'static str, _seconds: f64) {}
}

/// A [`Progress`] that ignores everything.
pub struct Silent;
impl Progress for Silent {}

/// Times stages, reports them to a [`Progress`] and keeps their [`StageTiming`]s.
pub struct Clock<'a> {
    progress: &'a mut dyn Progress,
    /// The stages timed so far, in order.
    pub timings: Vec<StageTiming>,
}

impl<'a> Clock<'a> {
    /// A clock that continues `timings` (empty for a new run).
    pub fn new(progress: &'a mut dyn Progress, timings: Vec<StageTiming>) -> Self {
        Self { progress, timings }
    }

    /// Runs `f` as the stage `stage`.
    pub fn run<T>(&mut self, stage: &'static str, f: impl FnOnce() -> T) -> T {
        self.run_counted(stage, |_| f())
    }

    /// Runs `f` as the stage `stage`, handing it a callback for `(done, total)` progress.
    pub fn run_counted<T>(
        &mut self,
        stage: &'static str,
        f: impl FnOnce(&mut dyn FnMut(usize, usize)) -> T,
    ) -> T {
        self.progress.start(stage);
        let t0 = Instant::now();
        let progress = &mut *self.progress;
        let out = f(&mut |done, total| progress.advance(done, total));
        let seconds = t0.elapsed().as_secs_f64();
        self.progress.finish(stage, seconds);
        self.timings.push(StageTiming { stage, seconds });
        out
    }
}

/// Shows each pipeline stage on stderr as it runs: a spinner on a terminal, one line per
/// finished stage otherwise.
pub struct StageProgress {
    quiet: bool,
    bar: Option<ProgressBar>,
}

impl StageProgress {
    /// A reporter; `quiet` silences it.
    pub fn new(quiet: bool) -> Self {
        Self { quiet, bar: None }
    }
}

impl Progress for StageProgress {
    fn section(&mut self, label: &str) {
        if !self.quiet {
            let _ = writeln!(std::io::stderr(), "{label}:");
        }
    }

    fn start(&mut self, stage: &'static str) {
        if self.quiet || !std::io::stderr().is_terminal() {
            return;
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} [{elapsed_precise}]") {
            bar.set_style(style);
        }
        bar.set_message(stage);
        bar.enable_steady_tick(Duration::from_millis(120));
        self.bar = Some(bar);
    }

    fn advance(&mut self, done: usize, total: usize) {
        let Some(bar) = &self.bar else { return };
        if bar.length().is_none() {
            let template = "{msg} [{bar:30}] {percent:>3}% ({pos}/{len}) [{elapsed_precise}]";
            if let Ok(style) = ProgressStyle::with_template(template) {
                bar.set_style(style.progress_chars("=> "));
            }
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    }

    fn finish(&mut self, stage: &'static str, seconds: f64) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        if !self.quiet {
            // A failing stderr never decides the run.
            let _ = writeln!(std::io::stderr(), "  {stage:<18} {seconds:>9.3} s");
        }
    }
}
