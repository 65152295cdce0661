//! A running stage's progress bars, behind a trait so that core draws
//! nothing itself. The runner lends a [`ProgressSink`] that draws bars on a
//! terminal (indicatif, in hypercontact-runner); a context without one
//! (tests, library use) shows nothing. Stage code sees only
//! [`crate::Context::progress`], [`Progress`] and [`crate::Context::note`],
//! so a new way of showing progress changes no stage.

/// Where a context shows its progress bars and notes.
pub trait ProgressSink: Send + Sync {
    /// A new bar over `len` steps of stage `stage`, labelled `what`.
    fn bar(&self, stage: &str, len: u64, what: &str) -> Box<dyn Bar>;

    /// Shows a note of stage `stage`. The context records every note
    /// itself, shown or not.
    fn note(&self, stage: &str, message: &str);
}

/// One bar a [`ProgressSink`] shows; stage code holds it as a
/// [`Progress`].
pub trait Bar: Send + Sync {
    fn inc(&self, n: u64);
    fn set_position(&self, pos: u64);
    fn set_message(&self, what: &str);
    /// The stage is done with the bar: it disappears. Called once.
    fn finish(&self);
}

/// A progress bar; share it by reference across worker threads (it is
/// `Sync`). It disappears when dropped.
pub struct Progress(Option<Box<dyn Bar>>);

impl Progress {
    /// A bar drawn by a sink.
    pub(crate) fn shown(bar: Box<dyn Bar>) -> Self {
        Progress(Some(bar))
    }

    /// A bar nobody sees (no sink).
    pub(crate) fn hidden() -> Self {
        Progress(None)
    }

    pub fn inc(&self, n: u64) {
        if let Some(bar) = &self.0 {
            bar.inc(n);
        }
    }

    pub fn set_position(&self, pos: u64) {
        if let Some(bar) = &self.0 {
            bar.set_position(pos);
        }
    }

    pub fn set_message(&self, what: &str) {
        if let Some(bar) = &self.0 {
            bar.set_message(what);
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.0 {
            bar.finish();
        }
    }
}
