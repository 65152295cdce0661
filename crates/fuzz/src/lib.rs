//! What the property tests share (a dev-dependency only): one
//! configuration, so every fuzz test in CI is bounded and seeded alike, the
//! byte splice and edits the readers' tests mutate files with, and a run in
//! a pool of a given size for the tests that products are the same bits on
//! any thread count, and a run with a deadline.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// `cases` cases from a fixed seed (12) without failure files, so CI runs
/// the same bounded search every time; `PROPTEST_CASES` and
/// `PROPTEST_RNG_SEED` widen or move it.
pub fn config(cases: u32) -> Config {
    let defaults = Config::default();
    Config {
        cases: if std::env::var_os("PROPTEST_CASES").is_some() {
            defaults.cases
        } else {
            cases
        },
        rng_seed: match defaults.rng_seed {
            RngSeed::Random => RngSeed::Fixed(12),
            fixed => fixed,
        },
        failure_persistence: None,
        ..defaults
    }
}

/// `bytes` with each edit `(at, remove, insert)` applied in turn: `remove`
/// bytes from `at` (wrapped into the current length) replaced by `insert`.
pub fn splice(mut bytes: Vec<u8>, edits: &[(usize, usize, Vec<u8>)]) -> Vec<u8> {
    for (at, remove, insert) in edits {
        let at = at % (bytes.len() + 1);
        let end = (at + remove).min(bytes.len());
        bytes.splice(at..end, insert.iter().copied());
    }
    bytes
}

/// One to four [`splice`] edits of a binary file: mostly overwrites of 1–3
/// bytes (the length kept, so headers and offsets still point into the
/// file), sometimes a cut of up to 300 bytes or an insertion.
pub fn byte_edits() -> impl Strategy<Value = Vec<(usize, usize, Vec<u8>)>> {
    prop::collection::vec(
        prop_oneof![
            3 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..4))
                .prop_map(|(at, bytes)| (at, bytes.len(), bytes)),
            1 => (
                any::<usize>(),
                prop_oneof![Just(0usize), 1usize..4, 0usize..300],
                prop::collection::vec(any::<u8>(), 0..4),
            ),
        ],
        1..5,
    )
}

/// `run`'s result, computed on its own thread; panics if it takes longer
/// than `seconds` (a reader that never ends, as on `/dev/zero`, fails the
/// test instead of hanging it).
pub fn within<T: Send + 'static>(seconds: u64, run: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(run());
    });
    rx.recv_timeout(std::time::Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("did not end within {seconds} s"))
}

/// `run`'s result computed in a rayon pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, run: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a rayon pool of the requested size")
        .install(run)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splices_wrap_and_clip() {
        let b = b"abcdef".to_vec();
        assert_eq!(splice(b.clone(), &[(1, 2, b"X".to_vec())]), b"aXdef");
        assert_eq!(splice(b.clone(), &[(8, 0, b"Z".to_vec())]), b"aZbcdef");
        assert_eq!(splice(b, &[(4, 10, Vec::new())]), b"abcd");
        assert_eq!(config(7).cases, 7);
    }
}
