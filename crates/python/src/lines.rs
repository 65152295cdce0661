//! Progress as plain text lines, for where bars cannot be drawn: a Jupyter
//! notebook shows what Python writes to `sys.stderr`, but not a terminal's
//! cursor movements (and not the process's own stderr at all). Each bar
//! says where it is when it starts, at most once per interval while it
//! moves, and when it finishes; notes pass through. The module hands it a
//! writer that calls back into Python.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use hypercontact_core::progress::{Bar, ProgressSink};

/// Where the lines go.
pub type Writer = Arc<dyn Fn(&str) + Send + Sync>;

/// A [`ProgressSink`] writing throttled lines.
pub struct LineProgress {
    writer: Writer,
    interval: Duration,
}

impl LineProgress {
    pub fn new(writer: Writer, interval: Duration) -> Self {
        Self { writer, interval }
    }
}

impl ProgressSink for LineProgress {
    fn bar(&self, stage: &str, len: u64, what: &str) -> Box<dyn Bar> {
        let bar = LineBar {
            writer: self.writer.clone(),
            interval: self.interval,
            stage: stage.to_owned(),
            len,
            pos: AtomicU64::new(0),
            state: Mutex::new(State {
                what: what.to_owned(),
                started: Instant::now(),
                last_line: None,
            }),
        };
        bar.say(0, true);
        Box::new(bar)
    }

    fn note(&self, stage: &str, message: &str) {
        // Warnings reach Python as warnings (the module raises them from
        // the returned notes); a line would say them twice.
        if !message.starts_with("warning:") {
            (self.writer)(&format!("{stage}: {message}\n"));
        }
    }
}

struct State {
    what: String,
    started: Instant,
    last_line: Option<Instant>,
}

struct LineBar {
    writer: Writer,
    interval: Duration,
    stage: String,
    len: u64,
    pos: AtomicU64,
    state: Mutex<State>,
}

impl LineBar {
    /// Writes the bar's line if `force`d or an interval has passed.
    fn say(&self, pos: u64, force: bool) {
        let mut state = self.state.lock().unwrap_or_else(|p| p.into_inner());
        let now = Instant::now();
        let due = state
            .last_line
            .is_none_or(|last| now.duration_since(last) >= self.interval);
        if !(force || due) {
            return;
        }
        state.last_line = Some(now);
        let elapsed_s = now.duration_since(state.started).as_secs_f64();
        let line = format!(
            "{}: {} {pos}/{} ({elapsed_s:.1} s)\n",
            self.stage, state.what, self.len
        );
        drop(state);
        (self.writer)(&line);
    }
}

impl Bar for LineBar {
    fn inc(&self, n: u64) {
        let pos = self.pos.fetch_add(n, Ordering::Relaxed) + n;
        self.say(pos, false);
    }

    fn set_position(&self, pos: u64) {
        self.pos.store(pos, Ordering::Relaxed);
        self.say(pos, false);
    }

    fn set_message(&self, what: &str) {
        self.state.lock().unwrap_or_else(|p| p.into_inner()).what = what.to_owned();
    }

    fn finish(&self) {
        self.say(self.pos.load(Ordering::Relaxed), true);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collecting() -> (Writer, Arc<Mutex<Vec<String>>>) {
        let lines = Arc::new(Mutex::new(Vec::new()));
        let sink = lines.clone();
        let writer: Writer = Arc::new(move |s: &str| sink.lock().unwrap().push(s.to_owned()));
        (writer, lines)
    }

    #[test]
    fn a_bar_says_its_start_its_end_and_nothing_between_within_an_interval() {
        let (writer, lines) = collecting();
        let progress = LineProgress::new(writer, Duration::from_secs(3600));
        let bar = progress.bar("bem", 40, "load steps");
        for _ in 0..40 {
            bar.inc(1);
        }
        bar.finish();
        progress.note("bem", "40 steps");
        progress.note("bem", "warning: said by Python instead");
        let lines = lines.lock().unwrap();
        assert_eq!(lines.len(), 3, "{lines:?}");
        assert!(
            lines[0].starts_with("bem: load steps 0/40 ("),
            "{}",
            lines[0]
        );
        assert!(
            lines[1].starts_with("bem: load steps 40/40 ("),
            "{}",
            lines[1]
        );
        assert_eq!(lines[2], "bem: 40 steps\n");
    }

    #[test]
    fn with_no_interval_every_move_is_a_line() {
        let (writer, lines) = collecting();
        let progress = LineProgress::new(writer, Duration::ZERO);
        let bar = progress.bar("fem", 3, "steps");
        bar.set_position(2);
        bar.set_message("newton");
        bar.inc(1);
        let lines = lines.lock().unwrap();
        assert_eq!(lines.len(), 3, "{lines:?}");
        assert!(lines[2].starts_with("fem: newton 3/3 ("), "{}", lines[2]);
    }
}
