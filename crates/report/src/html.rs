//! The HTML building blocks of `index.html`: the page shell (style sized for
//! A4 text width, no external resources), tables, number formatting and the
//! provenance section.

use std::collections::BTreeMap;

use hypercontact_core::{ColumnData, Table};
use serde_json::{Map, Value};

/// Escapes text for HTML element content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// `v` with `digits` significant digits, plain between 1e-4 and 1e7 and in
/// scientific notation outside; "n/a" for NaN and infinities.
pub fn fmt_sig(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-4..7).contains(&magnitude) {
        let s = format!("{:.*e}", digits.saturating_sub(1), v);
        // 1.230e-5 → 1.23e-5
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// A table with a header row; `None` cells render as "n/a".
pub fn simple_table(caption: &str, header: &[String], rows: &[Vec<String>]) -> String {
    anchored_table("", caption, header, rows)
}

/// [`simple_table`] with an anchor `id` (on the caption, or on the table
/// without one) that other sections link to; none when `id` is empty.
pub fn anchored_table(id: &str, caption: &str, header: &[String], rows: &[Vec<String>]) -> String {
    // The caption is a paragraph, not <caption>: a <caption> is only as
    // wide as its table and wraps word by word above narrow tables.
    let mut html = String::new();
    let mut anchor = (!id.is_empty()).then(|| format!(" id=\"{}\"", escape(id)));
    if !caption.is_empty() {
        html.push_str(&format!(
            "<p class=\"table-caption\"{}>{}</p>\n",
            anchor.take().unwrap_or_default(),
            escape(caption)
        ));
    }
    html.push_str(&format!("<table{}>\n", anchor.unwrap_or_default()));
    html.push_str("<thead><tr>");
    for h in header {
        html.push_str(&format!("<th>{h}</th>"));
    }
    html.push_str("</tr></thead>\n<tbody>\n");
    for row in rows {
        html.push_str("<tr>");
        for cell in row {
            html.push_str(&format!("<td>{cell}</td>"));
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody></table>\n");
    html
}

/// Any table, every column as it is (floats with 5 significant digits).
pub fn generic_table(caption: &str, table: &Table) -> String {
    let header: Vec<String> = table.column_names().iter().map(|n| escape(n)).collect();
    let rows: Vec<Vec<String>> = (0..table.n_rows())
        .map(|row| {
            table
                .columns()
                .iter()
                .map(|c| match &c.data {
                    ColumnData::F64(v) => fmt_sig(v[row], 5),
                    ColumnData::I64(v) => v[row].to_string(),
                    ColumnData::Str(v) => escape(&v[row]),
                })
                .collect()
        })
        .collect();
    simple_table(caption, &header, &rows)
}

/// Entries of a provenance record that change from run to run while the
/// results do not: wall and compute times. `provenance.json` keeps them; the
/// page leaves them out so that it is the same to the byte on every run.
const RUN_DEPENDENT_KEYS: [&str; 2] = ["compute_s", "wall_s"];

/// The record as the page shows it: without [`RUN_DEPENDENT_KEYS`], and with
/// each input file (`files_blake3`, path → hash, and the parameter that
/// names it) shown by its file name only: the folder it was read from
/// depends on where the pipeline was run from, and its content hash
/// already identifies it.
fn reproducible_record(record: &Value) -> Value {
    reproducible(record, &BTreeMap::new())
}

/// `value` made reproducible inside a record whose input files are shown
/// under the names in `shown_as` (path → name).
fn reproducible(value: &Value, shown_as: &BTreeMap<String, String>) -> Value {
    match value {
        Value::Object(object) => {
            let files = object.get("files_blake3").and_then(Value::as_object);
            let with_these;
            let shown_as = match files {
                Some(files) => {
                    with_these = shown_as
                        .clone()
                        .into_iter()
                        .chain(file_names(files))
                        .collect();
                    &with_these
                }
                None => shown_as,
            };
            Value::Object(
                object
                    .iter()
                    .filter(|(key, _)| !RUN_DEPENDENT_KEYS.contains(&key.as_str()))
                    .map(|(key, value)| {
                        let value = match (key.as_str(), files) {
                            ("files_blake3", Some(files)) => Value::Object(
                                files
                                    .iter()
                                    .map(|(path, hash)| (shown_as[path].clone(), hash.clone()))
                                    .collect(),
                            ),
                            _ => reproducible(value, shown_as),
                        };
                        (key.clone(), value)
                    })
                    .collect(),
            )
        }
        Value::Array(items) => Value::Array(
            items
                .iter()
                .map(|item| reproducible(item, shown_as))
                .collect(),
        ),
        Value::String(text) => Value::String(shown_as.get(text).unwrap_or(text).clone()),
        other => other.clone(),
    }
}

/// The name each input file is shown under: its file name; the second
/// file of one name (from another folder) is `name #2`, and so on.
fn file_names(files: &Map<String, Value>) -> Vec<(String, String)> {
    let mut names: Vec<(String, String)> = Vec::new();
    for path in files.keys() {
        let name = std::path::Path::new(path)
            .file_name()
            .map_or_else(|| path.clone(), |n| n.to_string_lossy().into_owned());
        let name = (1..)
            .map(|n| match n {
                1 => name.clone(),
                n => format!("{name} #{n}"),
            })
            .find(|candidate| names.iter().all(|(_, taken)| taken != candidate))
            .expect("an unused name among unboundedly many");
        names.push((path.clone(), name));
    }
    names
}

/// The provenance section at the bottom of the page, folded: a
/// `<details>` element whose summary counts the stages behind the report,
/// with one line per stage (name, kind and version, cache-key prefix) and,
/// unfolded further, the record the runner hands the stage (versions,
/// parameters, keys, input-file hashes of every upstream stage, without
/// what differs from run to run), or a placeholder when the report is
/// rendered outside a run.
///
/// Whether a stage ran or came from the cache, and its wall time, differ
/// from run to run while the page is the same bytes on every run (it is a
/// cached product), so the page points to `provenance.json` and
/// `hypercontact timings` for them instead of showing them.
pub fn provenance_section(provenance: Option<&serde_json::Value>) -> String {
    let mut html = String::from("<section id=\"provenance\">\n<h2>Provenance</h2>\n");
    let Some(value) = provenance.map(reproducible_record) else {
        html.push_str(
            "<p class=\"note\">No provenance record was passed to the report stage \
             (versions, parameters and input hashes of the run). The runner's \
             record of this run lists them, with its timings.</p>\n</section>\n",
        );
        return html;
    };
    let upstream = value.get("upstream").and_then(|u| u.as_object());
    let count = upstream.map_or(0, |u| u.len());
    html.push_str(&format!(
        "<details class=\"provenance\">\n<summary>{count} stage{} behind this report{}</summary>\n",
        if count == 1 { "" } else { "s" },
        match value.get("pipeline").and_then(|p| p.as_str()) {
            Some(name) => format!(" (pipeline <code>{}</code>)", escape(name)),
            None => String::new(),
        }
    ));
    if let Some(upstream) = upstream {
        html.push_str(&stage_lines(upstream));
    }
    html.push_str(
        "<p class=\"note\">Whether each stage ran or came from the cache, and its wall time, \
         are in the run's <code>provenance.json</code> (<code>hypercontact timings \
         runs/&lt;name&gt;</code>): they change from run to run, and this page does not.</p>\n",
    );
    if let Some(object) = value.as_object() {
        let scalars: Vec<Vec<String>> = object
            .iter()
            .filter(|(_, v)| !v.is_object() && !v.is_array())
            .map(|(k, v)| {
                let text = match v {
                    serde_json::Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                vec![escape(k), escape(&text)]
            })
            .collect();
        if !scalars.is_empty() {
            html.push_str(&simple_table(
                "",
                &["item".to_owned(), "value".to_owned()],
                &scalars,
            ));
        }
    }
    if let Some(upstream) = upstream {
        html.push_str(&upstream_table(upstream));
    }
    let pretty = serde_json::to_string_pretty(&value).unwrap_or_else(|_| value.to_string());
    html.push_str(&format!(
        "<details><summary>Full record (JSON)</summary>\n<pre>{}</pre>\n</details>\n",
        escape(&pretty)
    ));
    html.push_str("</details>\n</section>\n");
    html
}

/// One line per upstream stage: `name · kind vN · key 0123456789ab`.
fn stage_lines(upstream: &serde_json::Map<String, serde_json::Value>) -> String {
    let text = |v: Option<&serde_json::Value>| match v {
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
        None => String::new(),
    };
    let mut html = String::from("<ul class=\"stage-lines\">\n");
    for (name, r) in upstream {
        let key = text(r.get("key"));
        html.push_str(&format!(
            "<li><code>{}</code> · {} v{} · key <code>{}</code></li>\n",
            escape(name),
            escape(&text(r.get("kind"))),
            escape(&text(r.get("version"))),
            escape(&key.chars().take(12).collect::<String>())
        ));
    }
    html.push_str("</ul>\n");
    html
}

/// One row per upstream stage: what made the numbers on this page.
fn upstream_table(upstream: &serde_json::Map<String, serde_json::Value>) -> String {
    let text = |v: Option<&serde_json::Value>| match v {
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
        None => String::new(),
    };
    let rows: Vec<Vec<String>> = upstream
        .iter()
        .map(|(name, r)| {
            let key = text(r.get("key"));
            let files = r
                .get("files_blake3")
                .and_then(|f| f.as_object())
                .map(|f| {
                    f.iter()
                        .map(|(path, hash)| {
                            let hash = text(Some(hash));
                            format!("{path} ({})", &hash[..hash.len().min(12)])
                        })
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default();
            vec![
                escape(name),
                escape(&format!(
                    "{} v{}",
                    text(r.get("kind")),
                    text(r.get("version"))
                )),
                format!("<code>{}</code>", escape(&key[..key.len().min(12)])),
                escape(&text(r.get("params"))),
                escape(&files),
            ]
        })
        .collect();
    let header = [
        "stage",
        "kind",
        "cache key",
        "parameters",
        "input files (BLAKE3)",
    ]
    .map(str::to_owned);
    simple_table("Stages behind this report", &header, &rows)
}

/// The page around `body`: inline style only, sized for reading and
/// printing at A4 width.
pub fn page(title: &str, body: &str) -> String {
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
  body {{ font-family: "DejaVu Sans", Arial, sans-serif; font-size: 10.5pt; line-height: 1.45;
         max-width: 180mm; margin: 12mm auto; padding: 0 6mm; color: #111; }}
  h1 {{ font-size: 16pt; margin-bottom: 0.2em; }}
  h2 {{ font-size: 13pt; border-bottom: 1px solid #bbb; padding-bottom: 2px; margin-top: 1.8em; }}
  figure {{ margin: 1.2em 0; page-break-inside: avoid; }}
  figure svg {{ width: 100%; height: auto; display: block; }}
  figcaption {{ font-size: 9.5pt; margin-top: 0.4em; }}
  table {{ border-collapse: collapse; margin: 0.8em 0; font-size: 9pt;
          border-top: 1.5px solid #000; border-bottom: 1.5px solid #000; }}
  .table-caption {{ font-weight: bold; margin: 1.2em 0 0.2em 0; font-size: 9.5pt; }}
  table {{ margin-top: 0.2em; }}
  th {{ border-bottom: 1px solid #000; text-align: right; padding: 3px 8px; }}
  td {{ text-align: right; padding: 2px 8px; font-variant-numeric: tabular-nums; }}
  th:first-child, td:first-child {{ text-align: left; }}
  .note {{ color: #555; font-size: 9.5pt; }}
  .skipped {{ background: #f6f6f6; border-left: 3px solid #999; padding: 4px 10px; }}
  #provenance td {{ text-align: left; overflow-wrap: anywhere; font-size: 8pt; vertical-align: top; }}
  #provenance summary {{ cursor: pointer; font-weight: bold; }}
  #provenance ul.stage-lines {{ font-size: 9pt; padding-left: 1.2em; margin: 0.5em 0; }}
  pre {{ font-size: 8pt; white-space: pre-wrap; background: #f6f6f6; padding: 6px; }}
  @media print {{ body {{ margin: 0 auto; }} h2 {{ page-break-after: avoid; }} }}
</style>
</head>
<body>
{body}
</body>
</html>
"#,
        title = escape(title),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits() {
        assert_eq!(fmt_sig(5025.77e6 / 1e6, 6), "5025.77");
        assert_eq!(fmt_sig(1.79, 3), "1.79");
        assert_eq!(fmt_sig(0.000123456, 3), "0.000123");
        assert_eq!(fmt_sig(1.5e-9, 3), "1.5e-9");
        assert_eq!(fmt_sig(-0.0488, 3), "-0.0488");
        assert_eq!(fmt_sig(2.0, 4), "2");
        assert_eq!(fmt_sig(f64::NAN, 3), "n/a");
        assert_eq!(fmt_sig(12345678.0, 3), "1.23e7");
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn provenance_placeholder_and_record() {
        assert!(provenance_section(None).contains("No provenance record"));
        let record = serde_json::json!({"version": "0.1.0", "stages": {"fit": {"ms": 12}}});
        let html = provenance_section(Some(&record));
        assert!(html.contains("<td>version</td><td>0.1.0</td>"), "{html}");
        assert!(html.contains("&quot;ms&quot;: 12"), "{html}");
    }

    /// The runner's record for one upstream stage, as computed in `folder`
    /// in `compute_s` seconds.
    fn record(folder: &str, compute_s: f64) -> serde_json::Value {
        serde_json::json!({
            "pipeline": "quick",
            "key": "a1b2c3",
            "wall_s": compute_s * 3.0,
            "upstream": {
                "fit": {
                    "kind": "material-fit",
                    "version": 1,
                    "key": "0123456789abcdef",
                    "params": {"model": "ogden-6", "csv": format!("{folder}/data/tensile.csv")},
                    "files_blake3": {
                        format!("{folder}/data/tensile.csv"): "77aa",
                        format!("{folder}/other/tensile.csv"): "88bb99cc",
                    },
                    "compute_s": compute_s,
                }
            }
        })
    }

    /// Folded: everything after the heading is inside one `<details>`,
    /// whose summary counts the stages, with one line per stage giving its
    /// kind, version and the first 12 characters of its key.
    #[test]
    fn provenance_is_folded_with_a_line_per_stage() {
        let mut record = record("/data", 0.5);
        record["upstream"]["t1"] = serde_json::json!({
            "kind": "surface", "version": 5, "key": "fedcba9876543210ff", "params": {},
        });
        let html = provenance_section(Some(&record));
        let body = &html[html.find("</h2>\n").unwrap() + 6..];
        assert!(
            body.starts_with(
                "<details class=\"provenance\">\n<summary>2 stages behind \
                                  this report (pipeline <code>quick</code>)</summary>"
            ),
            "{body}"
        );
        assert!(body.ends_with("</details>\n</section>\n"), "{body}");
        let lines: Vec<&str> = body.lines().filter(|l| l.starts_with("<li>")).collect();
        assert_eq!(
            lines,
            [
                "<li><code>fit</code> · material-fit v1 · key <code>0123456789ab</code></li>",
                "<li><code>t1</code> · surface v5 · key <code>fedcba987654</code></li>",
            ]
        );
        // The full table and record are still there, one level further in.
        assert!(body.contains("<td>fit</td>") && body.contains("Full record (JSON)"));
        assert_eq!(body.matches("<details").count(), 2);
        assert_eq!(body.matches("</details>").count(), 2);
    }

    #[test]
    fn provenance_section_is_the_same_for_any_timing_and_folder() {
        let first = provenance_section(Some(&record("/tmp/.tmpAbC123", 0.23)));
        let second = provenance_section(Some(&record("/home/me/study", 1.5)));
        assert_eq!(first, second);
        assert!(
            !first.contains("compute") && !first.contains("wall_s"),
            "{first}"
        );
        assert!(
            !first.contains("/tmp") && !first.contains("0.23"),
            "{first}"
        );
        // The files stay identified by name and content hash.
        assert!(first.contains("tensile.csv (77aa)"), "{first}");
        assert!(first.contains("tensile.csv #2 (88bb99cc)"), "{first}");
        // The parameter naming the file shows the same name.
        assert!(
            first.contains("&quot;csv&quot;:&quot;tensile.csv&quot;"),
            "{first}"
        );
        assert!(first.contains("<td>fit</td>"), "{first}");
    }
}
