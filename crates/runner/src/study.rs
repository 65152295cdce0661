//! Studies: one pipeline over a list or grid of parameter values.
//!
//! Every variant (numbered 1 … N) is planned and run like a pipeline with
//! `--set` overrides, on the same cache, so stages a variant does not
//! change are computed once for all of them. The chosen table outputs of
//! all variants are gathered into one table each in the study's folder
//! (`runs/<name>/study/`), led by `variant` and the varied parameters
//! (`icm.model`, `trunc.levels`, ...), each entry's rows once.

use std::path::PathBuf;

use hypercontact_core::{ColumnData, Product, Table};
use indexmap::IndexMap;
use serde::Serialize;

use crate::exec::{RunError, RunOptions, RunReport, run};
use crate::pipeline::{Pipeline, PipelineError, StudySpec};
use crate::store;

/// One point of the study: `stage.param` → value.
pub type Variant = IndexMap<String, serde_json::Value>;

/// The variants of a study: every case (or one empty case) combined with
/// every point of the grid.
pub fn variants(spec: &StudySpec) -> Vec<Variant> {
    let mut out: Vec<Variant> = if spec.cases.is_empty() {
        vec![Variant::new()]
    } else {
        spec.cases.clone()
    };
    for (param, values) in &spec.grid {
        out = out
            .into_iter()
            .flat_map(|base| {
                values.iter().map(move |v| {
                    let mut next = base.clone();
                    next.insert(param.clone(), v.clone());
                    next
                })
            })
            .collect();
    }
    out
}

#[derive(Debug, Serialize)]
struct VariantRecord {
    /// The variant's number, 1 … N, as in its folder and the tables'
    /// `variant` column.
    index: usize,
    values: Variant,
    out_dir: String,
    computed: usize,
    cached: usize,
    /// Stages that failed, and stages not run because of them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    failed: Vec<String>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    not_run: Vec<String>,
}

/// What a study did.
#[derive(Debug)]
pub struct StudyReport {
    /// Every variant in order (variant `k` is `runs[k - 1]`).
    pub runs: Vec<(Variant, RunReport)>,
    /// Gathered tables: `stage.output` → file.
    pub tables: Vec<(String, PathBuf)>,
    /// The study's folder.
    pub dir: PathBuf,
}

/// The study folder of a pipeline when `--out` is not given:
/// `runs/<name>/study/`, apart from a single run's `runs/<name>/`.
pub fn default_dir(pipeline: &Pipeline) -> PathBuf {
    PathBuf::from("runs").join(&pipeline.name).join("study")
}

/// How the study's folder names variant `k` (1 … N).
fn variant_dir(study_dir: &std::path::Path, k: usize) -> PathBuf {
    study_dir.join("variants").join(format!("{k:03}"))
}

/// Runs every variant into `<out>/variants/<k>/` (k = 1 … N), with
/// `options.out_dir` the study's folder ([`default_dir`] by default), and
/// gathers the `collect:` tables there as `<out>/<stage>.<output>.parquet`
/// with `study.json`. Variants run on, past failed stages, unless
/// `options.keep_going` is off; failures make the result
/// [`RunError::StudyFailed`], after the tables of the variants that ran.
pub fn run_study(pipeline: &Pipeline, options: &RunOptions) -> Result<StudyReport, RunError> {
    let spec = study_spec(pipeline)?;
    let runs = run_variants(pipeline, options)?;
    let dir = options.out_dir.clone();
    if options.dry_run {
        return Ok(StudyReport {
            runs,
            tables: Vec::new(),
            dir,
        });
    }
    let cache = crate::exec::open_cache(&options.cache_dir)?;
    let mut tables = Vec::new();
    for target in &spec.collect {
        if let Some(path) = collect(pipeline, &spec, &runs, &cache, target, &dir)? {
            tables.push((target.clone(), path));
        }
    }
    write_record(&runs, &dir)?;
    let report = StudyReport { runs, tables, dir };
    if report.failed() {
        // The entries of temporary stages stay for the rerun that follows
        // the fix.
        return Err(RunError::StudyFailed(Box::new(report)));
    }
    for (_, run) in &report.runs {
        crate::exec::drop_temps(&run.plan, &cache)?;
    }
    Ok(report)
}

/// Runs the variants in order, each labelled `variant k/N` on the bars and
/// notes, each knowing the stage times of those before it (for ETAs) and
/// the entries that failed in them (not computed again).
fn run_variants(
    pipeline: &Pipeline,
    options: &RunOptions,
) -> Result<Vec<(Variant, RunReport)>, RunError> {
    let variants = variant_pipelines(pipeline)?;
    let n = variants.len();
    let mut runs = Vec::with_capacity(n);
    // Entries a cluster job computed count as the work of the first
    // variant that reads them; later variants find them cached. What
    // grows from variant to variant (the times, the failures) is moved
    // into each variant's options and back, never copied: a copy per
    // variant would make a study quadratic in its variants.
    let mut unclaimed = options.remote.clone();
    let mut history = options.history.clone();
    let mut failed = options.known_failures.clone();
    let base = RunOptions {
        remote: Default::default(),
        history: Default::default(),
        known_failures: Default::default(),
        ..options.clone()
    };
    for (i, (variant, p)) in variants.into_iter().enumerate() {
        let k = i + 1;
        let mut o = base.clone();
        o.out_dir = variant_dir(&options.out_dir, k);
        o.overrides = variant.iter().map(|(p, v)| format!("{p}={v}")).collect();
        // Variants may share a temporary entry: drop them after the last.
        o.keep_temps = true;
        o.remote = std::mem::take(&mut unclaimed);
        o.label = Some(format!("variant {k}/{n}"));
        o.history = std::mem::take(&mut history);
        o.known_failures = std::mem::take(&mut failed);
        let result = run(&p, &o);
        (unclaimed, history, failed) = (o.remote, o.history, o.known_failures);
        let report = match result {
            Ok(report) => report,
            Err(RunError::Failed(report)) if options.keep_going => *report,
            Err(e) => return Err(e),
        };
        for s in &report.plan.stages {
            unclaimed.remove(&s.key);
        }
        history.add(&report.provenance);
        for f in &report.failures {
            failed.insert(f.key.clone(), f.cause.clone());
        }
        runs.push((variant, report));
    }
    Ok(runs)
}

impl StudyReport {
    /// Whether a stage of some variant failed.
    pub fn failed(&self) -> bool {
        self.runs.iter().any(|(_, r)| !r.failures.is_empty())
    }

    /// Each variant that had failures, with them: the error of a study
    /// that kept going.
    pub fn failure_text(&self) -> String {
        let n = self.runs.len();
        let mut text = String::new();
        for (i, (_, run)) in self.runs.iter().enumerate() {
            if run.failures.is_empty() {
                continue;
            }
            if !text.is_empty() {
                text.push('\n');
            }
            text.push_str(&format!("variant {}/{n}: {}", i + 1, run.failure_text()));
        }
        text
    }

    /// The study's plan as `--dry-run` prints it: each variant's stages,
    /// where an entry an earlier variant computes shows as `shared` (it is
    /// computed once, by that variant), then the totals.
    pub fn describe(&self) -> String {
        use std::collections::{HashMap, HashSet};
        let n = self.runs.len();
        let mut first_by: HashMap<&str, usize> = HashMap::new();
        // Per entry a variant runs: how many variants plan it (each
        // variant counted once), so `shared` is one pass over the plans.
        let mut planned_by: HashMap<&str, usize> = HashMap::new();
        let mut cached: HashSet<&str> = HashSet::new();
        let mut out = String::new();
        for (i, (variant, run)) in self.runs.iter().enumerate() {
            let values: Vec<String> = variant.iter().map(|(p, v)| format!("{p}={v}")).collect();
            out.push_str(&format!("variant {}/{n}: {}\n", i + 1, values.join(" ")));
            out.push_str(&run.plan.describe_with(&|s| {
                if !s.runs {
                    return None;
                }
                (first_by.get(s.key.as_str())).map(|&k| format!("computed once, by variant {k}"))
            }));
            let keys: HashSet<&str> = run.plan.stages.iter().map(|s| s.key.as_str()).collect();
            for key in keys {
                *planned_by.entry(key).or_default() += 1;
            }
            for s in &run.plan.stages {
                if s.runs {
                    first_by.entry(s.key.as_str()).or_insert(i + 1);
                }
                if s.reason == crate::plan::Reason::Cached {
                    cached.insert(s.key.as_str());
                }
            }
        }
        let shared = (first_by.keys())
            .filter(|key| planned_by.get(*key).is_some_and(|&count| count > 1))
            .count();
        out.push_str(&format!(
            "study: {} entries to compute ({shared} of them shared by several variants), {} cached\n",
            first_by.len(),
            cached.len()
        ));
        out
    }
}

/// Gathers `target` (`stage.output`) of every variant into one table at
/// `<dir>/<stage>.<output>.parquet`: one block of rows per entry (variants
/// sharing the entry, because the stage does not depend on what differs
/// between them, give it once), led by `variant` and the varied
/// parameters (see [`entry_tags`]). Variants in which the stage failed or
/// was not run give no rows; with none left, no table (None).
fn collect(
    pipeline: &Pipeline,
    spec: &StudySpec,
    runs: &[(Variant, RunReport)],
    cache: &crate::cache::Cache,
    target: &str,
    dir: &std::path::Path,
) -> Result<Option<PathBuf>, RunError> {
    let (stage, output) = target.split_once('.').expect("checked above");
    let err = |message: String| -> RunError {
        PipelineError::new(
            &pipeline.file,
            format!("study.collect `{target}`: {message}"),
        )
        .into()
    };
    let keys: Vec<Option<String>> = (runs.iter())
        .map(|(_, r)| {
            let missing = r.failures.iter().any(|f| f.stage == stage)
                || r.blocked.iter().any(|b| b.stage == stage);
            let planned = r.plan.stage(stage).expect("collect names a pipeline stage");
            (!missing).then(|| planned.key.clone())
        })
        .collect();
    let groups = shared_entries(&keys);
    if groups.is_empty() {
        return Ok(None);
    }
    let variants: Vec<&Variant> = runs.iter().map(|(v, _)| v).collect();
    let tags = entry_tags(spec, &variants, &groups);
    let mut gathered = Table::new();
    for (group, tag) in groups.iter().zip(&tags) {
        let key = keys[group[0]].as_deref().expect("grouped keys are present");
        let crate::cache::EntryState::Valid(manifest) = cache.check(key) else {
            return Err(err("the entry vanished from the cache".to_owned()));
        };
        let record = &manifest.outputs[output];
        let Product::Table(table) = store::read_product(&cache.entry_dir(key), output, record)?
        else {
            unreachable!("checked to be a table output");
        };
        (gathered.append(&table.with_constants(tag))).map_err(|e| err(e.to_string()))?;
    }
    let path = dir.join(format!("{stage}.{output}.parquet"));
    // `variant` and the varied parameters' columns are not declared: they
    // go unlisted.
    let columns = pipeline
        .stage(stage)
        .and_then(|decl| decl.stage.info().output(output))
        .map_or(&[][..], |spec| spec.columns);
    let mut bytes = Vec::new();
    hypercontact_io::write_parquet_described(&gathered, columns, &mut bytes)
        .map_err(|e| err(e.to_string()))?;
    crate::write_atomic(&path, &bytes).map_err(|cause| RunError::Output {
        path: path.clone(),
        cause,
    })?;
    Ok(Some(path))
}

/// `study.json`: each variant's number, values, folder and counts.
fn write_record(runs: &[(Variant, RunReport)], dir: &std::path::Path) -> Result<(), RunError> {
    let records: Vec<VariantRecord> = (runs.iter().enumerate())
        .map(|(i, (values, report))| VariantRecord {
            index: i + 1,
            values: values.clone(),
            out_dir: variant_dir(dir, i + 1).display().to_string(),
            computed: report.computed(),
            cached: report.hits(),
            failed: report.failures.iter().map(|f| f.stage.clone()).collect(),
            not_run: report.blocked.iter().map(|b| b.stage.clone()).collect(),
        })
        .collect();
    let json = serde_json::to_vec_pretty(&records).expect("records serialise");
    let study_json = dir.join("study.json");
    crate::write_atomic(&study_json, &json).map_err(|cause| RunError::Output {
        path: study_json,
        cause,
    })
}

/// The pipeline's study, its `collect:` targets checked.
fn study_spec(pipeline: &Pipeline) -> Result<StudySpec, RunError> {
    let spec = pipeline.study.clone().ok_or_else(|| {
        PipelineError::new(&pipeline.file, "the pipeline has no `study:` section")
    })?;
    for (i, target) in spec.collect.iter().enumerate() {
        let at = pipeline.locate(&["study".to_owned(), "collect".to_owned(), i.to_string()]);
        let err = |message: String| PipelineError::new(&pipeline.file, message).located(at);
        let (stage, output) = target
            .split_once('.')
            .ok_or_else(|| err(format!("study.collect `{target}`: expected STAGE.OUTPUT")))?;
        let decl = pipeline
            .stage(stage)
            .ok_or_else(|| err(format!("study.collect `{target}`: no stage `{stage}`")))?;
        if decl.temp {
            return Err(err(format!(
                "study.collect `{target}`: `{stage}` is temporary (`temp: true`), its entries are \
                 dropped; collect a stage that reads it, or make it permanent"
            ))
            .into());
        }
        match decl.stage.info().output(output) {
            Some(o) if o.kind == hypercontact_core::ProductKind::Table => {}
            _ => {
                return Err(err(format!(
                    "study.collect `{target}`: `{stage}` has no table output `{output}`"
                ))
                .into());
            }
        }
    }
    Ok(spec)
}

/// Every variant of the pipeline's study with the pipeline it runs (its
/// values set, each error placed where the study gives the value).
pub fn variant_pipelines(pipeline: &Pipeline) -> Result<Vec<(Variant, Pipeline)>, RunError> {
    let spec = study_spec(pipeline)?;
    // Each variant is a plain pipeline: without the study, a copy costs
    // the stages only (the grid's values stay with the study's pipeline).
    let mut base = pipeline.clone();
    base.study = None;
    let variants = variants(&spec);
    let mut out = Vec::with_capacity(variants.len());
    for (k, variant) in variants.into_iter().enumerate() {
        let mut p = base.clone();
        for (path, value) in &variant {
            let origin = format!("study variant {} ({path} = {value})", k + 1);
            p.set_value(path, value.clone(), &origin).map_err(|e| {
                // A value of the grid is reported where the grid gives it.
                let at = pipeline.locate(&["study", "grid", path.as_str()]);
                if e.line.is_none() { e.located(at) } else { e }
            })?;
        }
        out.push((variant, p));
    }
    Ok(out)
}

/// The variants (indices into `keys`) grouped by the entry they have of
/// a collected stage, in order of first appearance; a variant without one
/// (None: the stage failed there) is in no group.
fn shared_entries(keys: &[Option<String>]) -> Vec<Vec<usize>> {
    let mut group_of: std::collections::HashMap<&str, usize> = Default::default();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, key) in keys.iter().enumerate() {
        let Some(key) = key.as_deref() else {
            continue;
        };
        let g = *group_of.entry(key).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
    }
    groups
}

/// The leading columns of each group's rows, as a one-row table per
/// group: `variant`, the number (1 … N) of the group's first variant, and
/// one column per varied parameter (`stage.param`), in the study's order.
/// A group's value of a parameter is the one all its variants share; where
/// they differ, the entry does not depend on it and the value is `*`. A
/// parameter no entry depends on gets no column; one every entry has a
/// value of is a number column when all its values are integers (or all
/// numbers), else text, as is one with a `*`.
fn entry_tags(spec: &StudySpec, variants: &[&Variant], groups: &[Vec<usize>]) -> Vec<Table> {
    const MISSING: serde_json::Value = serde_json::Value::Null;
    let names = varied_names(spec);
    let mut tags: Vec<Table> = (groups.iter())
        .map(|g| Table::new().with("variant", vec![g[0] as i64 + 1]))
        .collect();
    for name in names {
        let column: Vec<Option<&serde_json::Value>> = (groups.iter())
            .map(|g| {
                let value = |i: usize| variants[i].get(name).unwrap_or(&MISSING);
                let first = value(g[0]);
                g.iter().all(|&i| value(i) == first).then_some(first)
            })
            .collect();
        if column.iter().all(Option::is_none) {
            continue;
        }
        let every =
            |test: fn(&serde_json::Value) -> bool| column.iter().all(|v| v.is_some_and(test));
        let (ints, numbers) = (
            every(serde_json::Value::is_i64),
            every(serde_json::Value::is_number),
        );
        for (tag, value) in tags.iter_mut().zip(&column) {
            let data = if ints {
                ColumnData::I64(vec![value.and_then(|v| v.as_i64()).unwrap_or_default()])
            } else if numbers {
                ColumnData::F64(vec![value.and_then(|v| v.as_f64()).unwrap_or(f64::NAN)])
            } else {
                ColumnData::Str(vec![match value {
                    None => "*".to_owned(),
                    Some(serde_json::Value::String(s)) => s.clone(),
                    Some(other) => other.to_string(),
                }])
            };
            tag.push(name, data);
        }
    }
    tags
}

/// The varied parameters: the cases' keys, then the grid's, each once.
fn varied_names(spec: &StudySpec) -> Vec<&String> {
    spec.cases
        .iter()
        .flat_map(|c| c.keys())
        .chain(spec.grid.keys())
        .fold(Vec::new(), |mut acc, k| {
            if !acc.contains(&k) {
                acc.push(k);
            }
            acc
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn grid_times_cases() {
        let mut spec = StudySpec::default();
        spec.grid.insert("a.x".into(), vec![json!(1), json!(2)]);
        spec.grid
            .insert("b.y".into(), vec![json!("p"), json!("q"), json!("r")]);
        let v = variants(&spec);
        assert_eq!(v.len(), 6);
        assert_eq!(v[5]["a.x"], json!(2));
        assert_eq!(v[5]["b.y"], json!("r"));
        spec.cases = vec![IndexMap::from([("c.z".to_owned(), json!(true))]); 2];
        assert_eq!(variants(&spec).len(), 12);
    }

    #[test]
    fn mixed_values_become_text_columns() {
        let mut spec = StudySpec::default();
        spec.grid
            .insert("t.levels".into(), vec![json!(100), json!("all")]);
        let v = variants(&spec);
        let all: Vec<&Variant> = v.iter().collect();
        let tags = entry_tags(&spec, &all, &[vec![0], vec![1]]);
        assert_eq!(tags[0].str("t.levels").unwrap(), ["100"]);
        assert_eq!(tags[1].str("t.levels").unwrap(), ["all"]);
        assert_eq!(tags[1].i64("variant").unwrap(), [2]);
    }

    /// A 2 × 2 grid whose collected stage depends on `a.x` only: variants
    /// 1 and 2 share an entry, 3 and 4 another. The rows come once per
    /// entry, under the first variant, with `a.x` and without `b.y`; a
    /// stage that depends on neither comes once, with neither.
    #[test]
    fn an_entry_shared_by_variants_is_tagged_once_with_what_it_depends_on() {
        let mut spec = StudySpec::default();
        spec.grid.insert("a.x".into(), vec![json!(1), json!(2)]);
        spec.grid.insert("b.y".into(), vec![json!("p"), json!("q")]);
        let v = variants(&spec);
        let all: Vec<&Variant> = v.iter().collect();
        let keys: Vec<Option<String>> = ["k1", "k1", "k2", "k2"]
            .iter()
            .map(|k| Some(k.to_string()))
            .collect();
        let groups = shared_entries(&keys);
        assert_eq!(groups, [vec![0, 1], vec![2, 3]]);
        let tags = entry_tags(&spec, &all, &groups);
        assert_eq!(tags[0].column_names(), ["variant", "a.x"]);
        assert_eq!(
            (
                tags[0].i64("variant").unwrap(),
                tags[1].i64("variant").unwrap()
            ),
            (&[1][..], &[3][..])
        );
        assert_eq!(tags[1].i64("a.x").unwrap(), [2]);

        let one = shared_entries(&[Some("k".into()), Some("k".into()), None, Some("k".into())]);
        assert_eq!(one, [vec![0, 1, 3]]);
        let tags = entry_tags(&spec, &all, &one);
        assert_eq!(tags[0].column_names(), ["variant"]);

        // Depends on b.y only where a.x = 2: a text column with `*` where
        // the entry is the same for every b.y.
        let keys: Vec<Option<String>> = ["k1", "k1", "k2", "k3"]
            .iter()
            .map(|k| Some(k.to_string()))
            .collect();
        let groups = shared_entries(&keys);
        let tags = entry_tags(&spec, &all, &groups);
        let b: Vec<&str> = tags
            .iter()
            .map(|t| t.str("b.y").unwrap()[0].as_str())
            .collect();
        assert_eq!(b, ["*", "p", "q"]);
        assert!(tags.iter().all(|t| t.i64("a.x").is_ok()));
    }
}
