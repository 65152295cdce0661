//! Studies: one pipeline over a list or grid of parameter values.
//!
//! Every variant is planned and run like a pipeline with `--set`
//! overrides, on the same cache, so stages a variant does not change are
//! computed once for all of them. The chosen table outputs of all variants
//! are gathered into one table each, with the varied parameters as leading
//! columns (`icm.model`, `trunc.levels`, ...).

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
    index: usize,
    values: Variant,
    out_dir: String,
    computed: usize,
    cached: usize,
}

/// What a study did.
#[derive(Debug)]
pub struct StudyReport {
    pub runs: Vec<(Variant, RunReport)>,
    /// Gathered tables: `stage.output` → file.
    pub tables: Vec<(String, PathBuf)>,
}

/// Runs every variant; variant `k` exports to `<out>/variants/<k>/`, and the
/// gathered tables land as `<out>/<stage>.<output>.parquet`.
pub fn run_study(pipeline: &Pipeline, options: &RunOptions) -> Result<StudyReport, RunError> {
    let spec = study_spec(pipeline)?;
    let mut runs = Vec::new();
    // Entries a cluster job computed count as the work of the first
    // variant that reads them; later variants find them cached.
    let mut unclaimed = options.remote.clone();
    for (k, (variant, p)) in variant_pipelines(pipeline)?.into_iter().enumerate() {
        let mut o = options.clone();
        o.out_dir = options.out_dir.join("variants").join(format!("{k:03}"));
        o.overrides = variant.iter().map(|(p, v)| format!("{p}={v}")).collect();
        // Variants may share a temporary entry: drop them after the last.
        o.keep_temps = true;
        o.remote = unclaimed.clone();
        let report = run(&p, &o)?;
        for s in &report.plan.stages {
            unclaimed.remove(&s.key);
        }
        runs.push((variant, report));
    }
    if options.dry_run {
        return Ok(StudyReport {
            runs,
            tables: Vec::new(),
        });
    }

    let cache = crate::exec::open_cache(&options.cache_dir)?;
    let mut tables = Vec::new();
    for target in &spec.collect {
        let (stage, output) = target.split_once('.').expect("checked above");
        let mut gathered = Table::new();
        for (variant, report) in &runs {
            let key = &report
                .plan
                .stage(stage)
                .expect("collect names a pipeline stage")
                .key;
            let crate::cache::EntryState::Valid(manifest) = cache.check(key) else {
                return Err(PipelineError::new(
                    &pipeline.file,
                    format!("study.collect `{target}`: the entry vanished from the cache"),
                )
                .into());
            };
            let record = &manifest.outputs[output];
            let Product::Table(table) = store::read_product(&cache.entry_dir(key), output, record)?
            else {
                unreachable!("checked to be a table output");
            };
            let tagged = table.with_constants(&constants(&spec, variant));
            gathered.append(&tagged).map_err(|e| {
                PipelineError::new(&pipeline.file, format!("study.collect `{target}`: {e}"))
            })?;
        }
        let path = options.out_dir.join(format!("{stage}.{output}.parquet"));
        // The varied parameters' columns are not declared: they go unlisted.
        let columns = pipeline
            .stage(stage)
            .and_then(|decl| decl.stage.info().output(output))
            .map_or(&[][..], |spec| spec.columns);
        let mut bytes = Vec::new();
        hypercontact_io::write_parquet_described(&gathered, columns, &mut bytes).map_err(|e| {
            PipelineError::new(&pipeline.file, format!("study.collect `{target}`: {e}"))
        })?;
        crate::write_atomic(&path, &bytes).map_err(|cause| RunError::Output {
            path: path.clone(),
            cause,
        })?;
        tables.push((target.clone(), path));
    }
    let records: Vec<VariantRecord> = runs
        .iter()
        .enumerate()
        .map(|(index, (values, report))| VariantRecord {
            index,
            values: values.clone(),
            out_dir: options
                .out_dir
                .join("variants")
                .join(format!("{index:03}"))
                .display()
                .to_string(),
            computed: report.computed(),
            cached: report.hits(),
        })
        .collect();
    for (_, report) in &runs {
        crate::exec::drop_temps(&report.plan, &cache)?;
    }
    let json = serde_json::to_vec_pretty(&records).expect("records serialise");
    let study_json = options.out_dir.join("study.json");
    crate::write_atomic(&study_json, &json).map_err(|cause| RunError::Output {
        path: study_json,
        cause,
    })?;
    Ok(StudyReport { runs, tables })
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
    let mut out = Vec::new();
    for (k, variant) in variants(&spec).into_iter().enumerate() {
        let mut p = pipeline.clone();
        for (path, value) in &variant {
            let origin = format!("study variant {k} ({path} = {value})");
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

/// The varied parameters of one variant as a one-row table. A parameter
/// whose values are all numbers becomes a number column, otherwise text.
fn constants(spec: &StudySpec, variant: &Variant) -> Table {
    let mut table = Table::new();
    let names: Vec<&String> = spec
        .cases
        .iter()
        .flat_map(|c| c.keys())
        .chain(spec.grid.keys())
        .fold(Vec::new(), |mut acc, k| {
            if !acc.contains(&k) {
                acc.push(k);
            }
            acc
        });
    for name in names {
        let all_values: Vec<&serde_json::Value> = spec
            .cases
            .iter()
            .filter_map(|c| c.get(name))
            .chain(spec.grid.get(name).into_iter().flatten())
            .collect();
        let value = variant.get(name).unwrap_or(&serde_json::Value::Null);
        let data = if all_values.iter().all(|v| v.is_i64()) {
            ColumnData::I64(vec![value.as_i64().unwrap_or_default()])
        } else if all_values.iter().all(|v| v.is_number()) {
            ColumnData::F64(vec![value.as_f64().unwrap_or(f64::NAN)])
        } else {
            ColumnData::Str(vec![match value {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            }])
        };
        table.push(name, data);
    }
    table
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
        let c = constants(&spec, &v[0]);
        assert_eq!(c.str("t.levels").unwrap(), ["100"]);
    }
}
