//! How a run shows its stages' progress on a terminal: core's
//! [`ProgressSink`] drawn with indicatif. Each stage's bars join the run's
//! `MultiProgress` under the overall bar; a note is printed above the bars,
//! or as a plain line on stderr when the bars are hidden (piped or CI runs,
//! where indicatif draws nothing). A quiet run lends no sink at all.

use std::time::Duration;

use hypercontact_core::progress::{Bar, ProgressSink};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

/// The run's bars: every stage's under one `MultiProgress`.
pub struct TerminalProgress<'a>(pub &'a MultiProgress);

impl ProgressSink for TerminalProgress<'_> {
    fn bar(&self, stage: &str, len: u64, what: &str) -> Box<dyn Bar> {
        Box::new(StageBar(self.stage_bar(stage, len, what)))
    }

    fn note(&self, stage: &str, message: &str) {
        // The same column as the bars' stage names.
        let line = format!("{stage:>14} {message}");
        if self.0.is_hidden() {
            eprintln!("{}", line.trim_start());
        } else {
            let _ = self.0.println(line);
        }
    }
}

impl TerminalProgress<'_> {
    /// The indicatif bar of a stage, added under the run's bars.
    fn stage_bar(&self, stage: &str, len: u64, what: &str) -> ProgressBar {
        let bar = self.0.add(ProgressBar::new(len));
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix:>14.bold} {msg:<24} [{bar:30}] {human_pos}/{human_len} ({eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        // Redrawn while a long step runs, so the ETA stays current between
        // increments.
        bar.enable_steady_tick(Duration::from_millis(200));
        bar.set_prefix(stage.to_owned());
        bar.set_message(what.to_owned());
        bar
    }
}

/// One stage's indicatif bar.
struct StageBar(ProgressBar);

impl Bar for StageBar {
    fn inc(&self, n: u64) {
        self.0.inc(n);
    }

    fn set_position(&self, pos: u64) {
        self.0.set_position(pos);
    }

    fn set_message(&self, what: &str) {
        self.0.set_message(what.to_owned());
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use indicatif::ProgressDrawTarget;

    /// A stage's progress reaches an indicatif bar labelled with the stage
    /// and what it counts, and the bar is cleared when the stage is done.
    #[test]
    fn a_stage_bar_is_labelled_moved_and_cleared() {
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::hidden());
        let drawn = TerminalProgress(&multi).stage_bar("surf", 4, "stitch tiles");
        assert_eq!(
            (drawn.prefix(), drawn.message(), drawn.length()),
            ("surf".to_owned(), "stitch tiles".to_owned(), Some(4))
        );
        let bar = StageBar(drawn.clone());
        bar.inc(1);
        assert_eq!(drawn.position(), 1);
        bar.set_position(3);
        bar.set_message("filter");
        assert_eq!(
            (drawn.position(), drawn.message()),
            (3, "filter".to_owned())
        );
        assert!(!drawn.is_finished());
        bar.finish();
        assert!(drawn.is_finished());
    }
}
