//! How a run shows its stages' progress on a terminal: core's
//! [`ProgressSink`] drawn with indicatif. Each stage's bars join the run's
//! `MultiProgress` under the overall bar; a note is printed above the bars,
//! or as a plain line on stderr when the bars are hidden (piped or CI runs,
//! where indicatif draws nothing). A quiet run lends no sink at all.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use hypercontact_core::progress::{Bar, ProgressSink};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};

use crate::eta::{self, Pace};
use crate::plan::{Plan, Reason};
use crate::timings::RunHistory;

/// The bars of one stage: under the run's `MultiProgress`, with the run's
/// label (a study's `variant 3/6`) and the stage's recorded time.
pub struct TerminalProgress<'a> {
    multi: &'a MultiProgress,
    label: Option<String>,
    /// An earlier run's time of this computation, seconds.
    recorded_s: Option<f64>,
    started: Instant,
}

impl<'a> TerminalProgress<'a> {
    /// A stage starting now.
    pub fn new(multi: &'a MultiProgress) -> Self {
        Self {
            multi,
            label: None,
            recorded_s: None,
            started: Instant::now(),
        }
    }

    /// Notes are prefixed with `label` (a study's variant).
    pub fn labelled(mut self, label: Option<&str>) -> Self {
        self.label = label.map(str::to_owned);
        self
    }

    /// The stage took `seconds` in an earlier run (see [`crate::timings::History`]).
    pub fn recorded(mut self, seconds: Option<f64>) -> Self {
        self.recorded_s = seconds;
        self
    }
}

impl ProgressSink for TerminalProgress<'_> {
    fn bar(&self, stage: &str, len: u64, what: &str) -> Box<dyn Bar> {
        Box::new(StageBar(self.stage_bar(stage, len, what)))
    }

    fn note(&self, stage: &str, message: &str) {
        let line = note_line(self.label.as_deref(), stage, message);
        if self.multi.is_hidden() {
            eprintln!("{}", line.trim_start());
        } else {
            let _ = self.multi.println(line);
        }
    }
}

/// A note as printed: in the bars' stage column, or after the variant.
fn note_line(label: Option<&str>, stage: &str, message: &str) -> String {
    match label {
        Some(label) => format!("{label}: {stage} {message}"),
        // The same column as the bars' stage names.
        None => format!("{stage:>14} {message}"),
    }
}

impl TerminalProgress<'_> {
    /// The indicatif bar of a stage, added under the run's bars.
    fn stage_bar(&self, stage: &str, len: u64, what: &str) -> ProgressBar {
        let bar = self.multi.add(ProgressBar::new(len));
        let tracker = StageEta {
            stage_started: self.started,
            recorded_s: self.recorded_s,
            samples: Vec::new(),
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix:>14.bold} {msg:<24} [{bar:30}] {human_pos}/{human_len} ({stage_eta})",
            )
            .expect("valid template")
            .with_key("stage_eta", tracker)
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

/// The `{stage_eta}` of a stage's bar: follows the steps as they come
/// (the pace of the latest ones) and writes [`eta::stage_eta`].
#[derive(Clone)]
struct StageEta {
    stage_started: Instant,
    recorded_s: Option<f64>,
    /// (seconds since the bar started, steps done), one per change.
    samples: Vec<(f64, u64)>,
}

/// Samples kept per bar: beyond, every other one is dropped (the pace of
/// the latest quarter needs only a rough record of the early steps).
const SAMPLES: usize = 1024;

impl indicatif::style::ProgressTracker for StageEta {
    fn clone_box(&self) -> Box<dyn indicatif::style::ProgressTracker> {
        Box::new(self.clone())
    }

    fn tick(&mut self, state: &ProgressState, _: Instant) {
        let pos = state.pos();
        match self.samples.last() {
            Some(&(_, last)) if last == pos => return,
            // A bar moved back: its steps start again.
            Some(&(_, last)) if last > pos => self.samples.clear(),
            _ => {}
        }
        if self.samples.len() >= SAMPLES {
            let mut k = 0;
            self.samples.retain(|_| {
                k += 1;
                k % 2 == 0
            });
        }
        self.samples.push((state.elapsed().as_secs_f64(), pos));
    }

    fn reset(&mut self, _: &ProgressState, _: Instant) {
        self.samples.clear();
    }

    fn write(&self, state: &ProgressState, w: &mut dyn std::fmt::Write) {
        let elapsed_s = state.elapsed().as_secs_f64();
        let pace = Pace {
            elapsed_s,
            done: state.pos(),
            total: state.len().unwrap_or(0),
            latest_s_per_step: eta::latest_s_per_step(&self.samples, elapsed_s),
        };
        let recorded_left_s =
            (self.recorded_s).map(|s| s - self.stage_started.elapsed().as_secs_f64());
        let _ = w.write_str(&eta::stage_eta(&pace, recorded_left_s));
    }
}

/// The bar of a whole run: stages done, the stage running, and the run's
/// ETA from the stages' recorded times (hidden when quiet).
pub struct RunBar {
    bar: ProgressBar,
    clock: Arc<Mutex<RunClock>>,
}

/// What the run's ETA is computed from, shared with its bar.
#[derive(Clone, Debug)]
struct RunClock {
    /// Expected seconds of each stage of the plan: 0 for a stage that does
    /// not compute, its recorded time for one that does, None unrecorded.
    expected_s: Vec<Option<f64>>,
    /// The stage running and when it started.
    current: usize,
    started: Instant,
}

impl RunBar {
    /// The bar of a run of `plan`, under `multi` (none when quiet), its
    /// prefix `label` (a study's `variant 3/6`) or `stages`.
    pub fn new(
        multi: Option<&MultiProgress>,
        plan: &Plan,
        history: &RunHistory,
        label: Option<&str>,
    ) -> Self {
        let expected_s = (plan.stages.iter())
            .map(|s| match s.runs && s.reason != Reason::Cached {
                true => history.seconds(s),
                false => Some(0.0),
            })
            .collect();
        let clock = Arc::new(Mutex::new(RunClock {
            expected_s,
            current: 0,
            started: Instant::now(),
        }));
        let Some(multi) = multi else {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
            return Self { bar, clock };
        };
        let bar = multi.add(ProgressBar::new(plan.stages.len() as u64));
        let shared = clock.clone();
        let run_eta = move |_: &ProgressState, w: &mut dyn std::fmt::Write| {
            if let Ok(clock) = shared.lock() {
                let text = clock.eta();
                if !text.is_empty() {
                    let _ = write!(w, "  (run {text})");
                }
            }
        };
        bar.set_style(
            ProgressStyle::with_template("{prefix:>14.bold} [{bar:30}] {pos}/{len} {msg}{run_eta}")
                .expect("valid template")
                .with_key("run_eta", run_eta)
                .progress_chars("=> "),
        );
        bar.set_prefix(label.unwrap_or("stages").to_owned());
        bar.enable_steady_tick(Duration::from_millis(500));
        Self { bar, clock }
    }

    /// Stage `index` of the plan, `name`, starts.
    pub fn start(&self, index: usize, name: &str) {
        if let Ok(mut clock) = self.clock.lock() {
            clock.current = index;
            clock.started = Instant::now();
        }
        self.bar.set_message(name.to_owned());
    }

    /// Stage `index` is done (or was not run).
    pub fn done(&self, index: usize) {
        if let Ok(mut clock) = self.clock.lock()
            && let Some(slot) = clock.expected_s.get_mut(index)
        {
            *slot = Some(0.0);
        }
        self.bar.inc(1);
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// The text after the stage name, for tests.
    #[cfg(test)]
    fn eta(&self) -> String {
        self.clock.lock().map(|c| c.eta()).unwrap_or_default()
    }
}

impl RunClock {
    fn eta(&self) -> String {
        let current = (self.expected_s.get(self.current).copied().flatten())
            .map(|s| s - self.started.elapsed().as_secs_f64());
        let later = self.expected_s.get(self.current + 1..).unwrap_or(&[]);
        eta::run_eta(current, later)
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
    use crate::timings::History;

    /// A stage's progress reaches an indicatif bar labelled with the stage
    /// and what it counts, and the bar is cleared when the stage is done.
    #[test]
    fn a_stage_bar_is_labelled_moved_and_cleared() {
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::hidden());
        let drawn = TerminalProgress::new(&multi).stage_bar("surf", 4, "stitch tiles");
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

    fn planned(name: &str, reason: Reason) -> crate::plan::PlannedStage {
        crate::plan::PlannedStage {
            name: name.to_owned(),
            kind: "bem".to_owned(),
            version: 1,
            key: format!("key-{name}"),
            params: serde_json::json!({ "steps": name.len() }),
            files: Default::default(),
            inputs: Vec::new(),
            runs: reason != Reason::Cached,
            reason,
            temp: false,
            manifest: None,
        }
    }

    /// The run's bar carries the study's `variant i/N` and the run's ETA:
    /// the recorded times of the stages still to compute, a lower bound
    /// while one of them has none; a cached stage costs nothing.
    #[test]
    fn the_run_bar_is_labelled_and_adds_the_recorded_times() {
        let plan = Plan {
            stages: vec![
                planned("a", Reason::Cached),
                planned("bb", Reason::New),
                planned("ccc", Reason::New),
            ],
        };
        let mut history = History::default();
        history.add_stage("bem", "key-bb", &serde_json::json!({}), 40.0);
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::hidden());
        let bar = RunBar::new(
            Some(&multi),
            &plan,
            &RunHistory::new(&history, None),
            Some("variant 2/6"),
        );
        assert_eq!(bar.bar.prefix(), "variant 2/6");
        bar.start(0, "a");
        assert_eq!(bar.eta(), "ETA ≥ 40s", "`ccc` was never timed");
        bar.done(0);
        bar.start(1, "bb");
        assert_eq!(bar.bar.message(), "bb");
        // `ccc` ran before with the same parameters, on other inputs.
        let mut history = History::default();
        history.add_stage("bem", "key-bb", &serde_json::json!({}), 40.0);
        history.add_stage("bem", "other", &serde_json::json!({ "steps": 3 }), 19.5);
        let bar = RunBar::new(Some(&multi), &plan, &RunHistory::new(&history, None), None);
        assert_eq!(bar.bar.prefix(), "stages");
        bar.start(1, "bb");
        assert_eq!(bar.eta(), "ETA 1m00s");
        bar.done(1);
        bar.start(2, "ccc");
        assert_eq!(bar.eta(), "ETA 20s");
        let quiet = RunBar::new(
            None,
            &plan,
            &RunHistory::new(&History::default(), None),
            None,
        );
        assert_eq!(quiet.eta(), "");
    }

    #[test]
    fn a_note_in_a_study_names_its_variant() {
        assert_eq!(
            note_line(Some("variant 3/6"), "report", "skipped fig2"),
            "variant 3/6: report skipped fig2"
        );
        assert_eq!(
            note_line(None, "report", "skipped fig2"),
            "        report skipped fig2"
        );
    }
}
