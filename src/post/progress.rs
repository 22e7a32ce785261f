//! Stage progress on stderr: a spinner on a terminal, plain lines otherwise.

use crate::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// Shows each pipeline stage as it runs.
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

    fn finish(&mut self, stage: &'static str, seconds: f64) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        if !self.quiet {
            eprintln!("  {stage:<14} {seconds:>9.3} s");
        }
    }
}
