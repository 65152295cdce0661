//! Where a run's time went, from its `provenance.json`: every stage by its
//! time in this run, the totals per kind, the run's wall time and peak
//! memory. What `hypercontact timings RUN_DIR` and `run --timings` print,
//! so a figure such as "the paper pipeline cold in N s" can be rerun and
//! checked by anyone.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::hash::canonical_json;
use crate::plan::PlannedStage;
use crate::provenance::{CacheUse, Provenance};

/// Stage times recorded by earlier runs (each record's `compute_s`, the
/// time of the computation that made the entry), for the ETAs of
/// [`crate::eta`]: looked up by kind and cache key (the same computation),
/// else by kind and parameters (the same work on other inputs: another
/// sample, another variant's upstream), taking the longest such record.
#[derive(Clone, Debug, Default)]
pub struct History {
    by_key: BTreeMap<(String, String), f64>,
    by_params: BTreeMap<(String, String), f64>,
}

impl History {
    /// Adds every stage of a run's record.
    pub fn add(&mut self, provenance: &Provenance) {
        for record in provenance.stages.values() {
            self.add_stage(&record.kind, &record.key, &record.params, record.compute_s);
        }
    }

    /// Adds one computation's time.
    pub fn add_stage(&mut self, kind: &str, key: &str, params: &serde_json::Value, seconds: f64) {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return;
        }
        self.by_key
            .insert((kind.to_owned(), key.to_owned()), seconds);
        let slot = (self.by_params)
            .entry((kind.to_owned(), canonical_json(params)))
            .or_insert(seconds);
        *slot = slot.max(seconds);
    }

    /// This history with a run's record added (if there is one).
    pub fn with(mut self, provenance: Option<&Provenance>) -> Self {
        if let Some(p) = provenance {
            self.add(p);
        }
        self
    }

    /// The recorded time of a planned stage's computation: its own entry's
    /// (a forced stage), else by key, else by parameters.
    pub fn seconds(&self, planned: &PlannedStage) -> Option<f64> {
        RunHistory::new(self, None).seconds(planned)
    }
}

/// The times one run goes by: the record in its own folder over the
/// history handed to it, read through without copying the latter (a
/// study hands each variant the times of every variant before it, and a
/// copy per variant would make the study quadratic in its variants).
pub struct RunHistory<'a> {
    below: &'a History,
    own: History,
}

impl<'a> RunHistory<'a> {
    /// `below` with the run's previous record (if any) over it.
    pub fn new(below: &'a History, previous: Option<&Provenance>) -> Self {
        Self {
            below,
            own: History::default().with(previous),
        }
    }

    /// As [`History::seconds`] on `below` with the record added: by key the
    /// record's time wins, by parameters the longer.
    pub fn seconds(&self, planned: &PlannedStage) -> Option<f64> {
        if let Some(m) = &planned.manifest {
            return Some(m.compute_s);
        }
        let key = (planned.kind.clone(), planned.key.clone());
        let by_key = |h: &History| h.by_key.get(&key).copied();
        if let Some(s) = by_key(&self.own).or_else(|| by_key(self.below)) {
            return Some(s);
        }
        let alike = (planned.kind.clone(), canonical_json(&planned.params));
        let by_params = |h: &History| h.by_params.get(&alike).copied();
        match (by_params(&self.own), by_params(self.below)) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }
}

/// One stage's line: name, kind, what the run did, seconds in this run.
struct Line<'a> {
    stage: &'a str,
    kind: &'a str,
    status: &'static str,
    seconds: f64,
}

fn lines(provenance: &Provenance) -> Vec<Line<'_>> {
    let mut lines: Vec<Line> = provenance
        .stages
        .iter()
        .filter_map(|(stage, r)| {
            let status = match r.cache {
                CacheUse::Miss if r.job.is_some() => "ran (job)",
                CacheUse::Miss => "ran",
                CacheUse::Forced => "forced",
                CacheUse::Hit => "cached",
                CacheUse::Skipped => return None,
            };
            // A cluster job's own compute time; here, the wall time in
            // this run (for a cached stage, its loading).
            let seconds = if r.job.is_some() {
                r.compute_s
            } else {
                r.wall_s
            };
            Some(Line {
                stage,
                kind: &r.kind,
                status,
                seconds,
            })
        })
        .collect();
    // A failed stage's time is part of where the run's time went.
    lines.extend(provenance.failed.iter().map(|(stage, f)| Line {
        stage,
        kind: &f.kind,
        status: "FAILED",
        seconds: f.wall_s,
    }));
    // Longest first; ties by name, so the table is the same every time.
    lines.sort_by(|a, b| b.seconds.total_cmp(&a.seconds).then(a.stage.cmp(b.stage)));
    lines
}

/// The timings table of a run.
pub fn table(provenance: &Provenance) -> String {
    let lines = lines(provenance);
    let in_stages_s: f64 = lines.iter().map(|l| l.seconds).sum();
    let share = |s: f64| {
        if in_stages_s > 0.0 {
            100.0 * s / in_stages_s
        } else {
            0.0
        }
    };
    let mut out = format!(
        "{:<28} {:<22} {:<10} {:>10} {:>7}\n",
        "stage", "kind", "status", "time s", "share"
    );
    for l in &lines {
        let _ = writeln!(
            out,
            "{:<28} {:<22} {:<10} {:>10.2} {:>6.1}%",
            l.stage,
            l.kind,
            l.status,
            l.seconds,
            share(l.seconds)
        );
    }
    let mut by_kind: BTreeMap<&str, (usize, f64)> = BTreeMap::new();
    for l in &lines {
        let entry = by_kind.entry(l.kind).or_default();
        entry.0 += 1;
        entry.1 += l.seconds;
    }
    let mut kinds: Vec<_> = by_kind.into_iter().collect();
    kinds.sort_by(|a, b| b.1.1.total_cmp(&a.1.1).then(a.0.cmp(b.0)));
    out.push_str("\nby kind:\n");
    for (kind, (count, seconds)) in kinds {
        let _ = writeln!(
            out,
            "  {kind:<22} {count:>3} × {:>9.2} s = {seconds:>10.2} s {:>6.1}%",
            seconds / count as f64,
            share(seconds)
        );
    }
    let failed = provenance.failed.len();
    let ran = (lines.iter())
        .filter(|l| l.status != "cached" && l.status != "FAILED")
        .count();
    let failed_text = match failed {
        0 => String::new(),
        n => format!(", {n} failed"),
    };
    let memory = match provenance.peak_rss_mb {
        // The record holds MiB (VmHWM's kB are KiB); the table says GB,
        // 10^9 bytes: 2 048 MiB is 2.15 GB, not "2.00 GB" as it said.
        Some(mib) => format!("; peak memory {:.2} GB", mib * 1_048_576.0 / 1e9),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "\n{} stages: {ran} computed, {} cached{failed_text}; {in_stages_s:.1} s in stages, run wall \
         {:.1} s{memory}",
        lines.len(),
        lines.len() - ran - failed,
        provenance.wall_s
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::provenance::StageRecord;

    fn record(kind: &str, cache: CacheUse, wall_s: f64) -> StageRecord {
        StageRecord {
            kind: kind.to_owned(),
            version: 1,
            key: String::new(),
            params: serde_json::Value::Null,
            files: BTreeMap::new(),
            inputs: BTreeMap::new(),
            outputs: BTreeMap::new(),
            cache,
            wall_s,
            compute_s: wall_s,
            temp: false,
            notes: Vec::new(),
            job: None,
            producer: None,
        }
    }

    #[test]
    fn stages_longest_first_with_kind_totals_and_the_run() {
        let mut stages = BTreeMap::new();
        stages.insert("a-bem".to_owned(), record("bem", CacheUse::Miss, 3.0));
        stages.insert("b-bem".to_owned(), record("bem", CacheUse::Miss, 1.0));
        stages.insert("fit".to_owned(), record("material-fit", CacheUse::Hit, 0.5));
        stages.insert("gone".to_owned(), record("icm", CacheUse::Skipped, 9.0));
        stages.insert("surf".to_owned(), record("surface", CacheUse::Forced, 5.5));
        let provenance = Provenance {
            pipeline: "p".to_owned(),
            pipeline_file: "p.yaml".to_owned(),
            pipeline_blake3: String::new(),
            hypercontact_version: String::new(),
            producer: None,
            overrides: Vec::new(),
            started_unix_s: 0,
            wall_s: 10.3,
            peak_rss_mb: Some(2048.0),
            stages,
            format: crate::provenance::PROVENANCE_FORMAT,
            failed: BTreeMap::new(),
        };
        let text = table(&provenance);
        let order: Vec<&str> = text
            .lines()
            .skip(1)
            .take_while(|l| !l.is_empty())
            .map(|l| l.split_whitespace().next().unwrap())
            .collect();
        assert_eq!(order, ["surf", "a-bem", "b-bem", "fit"]);
        assert!(
            text.contains(
                "surf                         surface                forced           5.50   55.0%"
            ),
            "{text}"
        );
        assert!(
            text.contains("  bem                      2 ×      2.00 s =       4.00 s   40.0%"),
            "{text}"
        );
        assert!(text.contains("4 stages: 3 computed, 1 cached; 10.0 s in stages, run wall 10.3 s; peak memory 2.15 GB"), "{text}");
        assert!(!text.contains("gone"));
    }

    /// A stage's recorded time: its own entry's, else the same key's,
    /// else the longest of the same kind and parameters.
    #[test]
    fn history_finds_a_stage_by_key_then_by_parameters() {
        let mut stages = BTreeMap::new();
        let mut bem = record("bem", CacheUse::Miss, 30.0);
        bem.key = "k1".to_owned();
        bem.params = serde_json::json!({ "steps": 40, "model": "linear" });
        stages.insert("t1-bem".to_owned(), bem.clone());
        bem.key = "k2".to_owned();
        bem.compute_s = 50.0;
        stages.insert("t2-bem".to_owned(), bem);
        let provenance = Provenance {
            pipeline: "p".to_owned(),
            pipeline_file: "p.yaml".to_owned(),
            pipeline_blake3: String::new(),
            hypercontact_version: String::new(),
            producer: None,
            overrides: Vec::new(),
            started_unix_s: 0,
            wall_s: 80.0,
            peak_rss_mb: None,
            stages,
            format: crate::provenance::PROVENANCE_FORMAT,
            failed: BTreeMap::new(),
        };
        let history = History::default().with(Some(&provenance));
        let mut planned = crate::plan::PlannedStage {
            name: "t1-bem".to_owned(),
            kind: "bem".to_owned(),
            version: 1,
            key: "k1".to_owned(),
            // Key order does not matter.
            params: serde_json::json!({ "model": "linear", "steps": 40 }),
            files: BTreeMap::new(),
            inputs: Vec::new(),
            runs: true,
            reason: crate::plan::Reason::New,
            temp: false,
            manifest: None,
        };
        assert_eq!(history.seconds(&planned), Some(30.0));
        planned.key = "k3".to_owned();
        assert_eq!(history.seconds(&planned), Some(50.0), "the longest alike");
        planned.params = serde_json::json!({ "model": "linear", "steps": 80 });
        assert_eq!(history.seconds(&planned), None);
        planned.kind = "icm".to_owned();
        planned.key = "k1".to_owned();
        assert_eq!(history.seconds(&planned), None, "another kind");
    }
}
