//! Which build of hypercontact produced a cache entry (#31, 4).
//!
//! A cache key holds a stage's kind, its hand-kept `version`, parameters
//! and upstream keys, but nothing of the code: a forgotten version bump lets
//! an entry made by older code be reused. Each entry's manifest therefore
//! names the build that made it (package version and a hash of the sources,
//! see the root `build.rs`), and `cache verify --producer` lists the entries
//! another build made. The identity stays out of keys and products, which
//! must be the same bytes from any build.

use std::sync::OnceLock;

/// What an entry whose manifest predates the field is listed as.
pub const UNKNOWN: &str = "unknown build";

static RUNNING: OnceLock<String> = OnceLock::new();

/// Names the running build; the binary calls this once at start. Later
/// calls keep the first name.
pub fn set_running(identity: &str) {
    let _ = RUNNING.set(identity.to_owned());
}

/// The running build: as set by the binary, else the library's version
/// with no source hash (a test or another program using the library).
pub fn running() -> &'static str {
    RUNNING.get_or_init(|| format!("{}+src.unknown", env!("CARGO_PKG_VERSION")))
}

/// How a recorded producer reads: the identity, or [`UNKNOWN`].
pub fn shown(recorded: Option<&str>) -> &str {
    recorded.unwrap_or(UNKNOWN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_producer_reads_as_unknown() {
        assert_eq!(shown(None), "unknown build");
        assert_eq!(shown(Some("0.1.0+src.00ff")), "0.1.0+src.00ff");
    }
}
