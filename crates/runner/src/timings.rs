//! Where a run's time went, from its `provenance.json`: every stage by its
//! time in this run, the totals per kind, the run's wall time and peak
//! memory. What `hypercontact timings RUN_DIR` and `run --timings` print,
//! so a figure such as "the paper pipeline cold in N s" can be rerun and
//! checked by anyone.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::provenance::{CacheUse, Provenance};

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
    let ran = lines.iter().filter(|l| l.status != "cached").count();
    let memory = match provenance.peak_rss_mb {
        Some(mb) => format!("; peak memory {:.2} GB", mb / 1024.0),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "\n{} stages: {ran} computed, {} cached; {in_stages_s:.1} s in stages, run wall {:.1} s{memory}",
        lines.len(),
        lines.len() - ran,
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
        assert!(text.contains("4 stages: 3 computed, 1 cached; 10.0 s in stages, run wall 10.3 s; peak memory 2.00 GB"), "{text}");
        assert!(!text.contains("gone"));
    }
}
