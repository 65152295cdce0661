//! `hypercontact stages`: every stage kind with its parameters (defaults and
//! units), inputs and output schemas.

use anyhow::{Result, bail};
use hypercontact_core::{DynStage, Registry};
use serde_json::{Value, json};

pub fn print(registry: &Registry, kind: Option<&str>, as_json: bool) -> Result<()> {
    let stages: Vec<&std::sync::Arc<dyn DynStage>> = match kind {
        Some(k) => match registry.get(k) {
            Some(s) => vec![s],
            None => bail!(
                "unknown stage kind `{k}` (known: {})",
                registry.kinds().collect::<Vec<_>>().join(", ")
            ),
        },
        None => registry.iter().collect(),
    };
    let text = if as_json {
        let all: Vec<Value> = stages.iter().map(|s| describe_json(s.as_ref())).collect();
        serde_json::to_string_pretty(&all)? + "\n"
    } else {
        stages
            .iter()
            .map(|s| describe_text(s.as_ref(), kind.is_some()))
            .collect()
    };
    // A closed pipe (`| head`) is not an error worth a panic.
    match std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

fn default_text(defaults: &Value, name: &str) -> String {
    match defaults.get(name) {
        None | Some(Value::Null) => "-".into(),
        Some(Value::String(s)) if s.is_empty() => "(required)".into(),
        Some(Value::Number(n)) if n.as_f64() == Some(0.0) && name.ends_with("_m") => {
            "(required)".into()
        }
        Some(v) => v.to_string(),
    }
}

pub fn describe_text(stage: &dyn DynStage, full: bool) -> String {
    let info = stage.info();
    let defaults = stage.default_params();
    let mut out = format!("{} (v{}) — {}\n", info.kind, info.version, info.summary);
    if full && !info.doc.is_empty() {
        for line in wrap(info.doc, 88) {
            out.push_str(&format!("  {line}\n"));
        }
    }
    if !info.params.is_empty() {
        out.push_str("  params:\n");
        for p in info.params {
            let unit = if p.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", p.unit)
            };
            out.push_str(&format!(
                "    {:<22} = {:<14}{unit}  {}\n",
                p.name,
                default_text(&defaults, p.name),
                p.doc
            ));
        }
    }
    if !info.inputs.is_empty() {
        out.push_str("  inputs:\n");
        for i in info.inputs {
            out.push_str(&format!(
                "    {:<22} {} ({:?})  {}\n",
                i.name, i.kind, i.arity, i.doc
            ));
            for c in i.columns {
                out.push_str(&format!("      needs {:<18} {}\n", c.name, c.dtype));
            }
        }
    }
    out.push_str("  outputs:\n");
    for o in info.outputs {
        out.push_str(&format!("    {:<22} {}  {}\n", o.name, o.kind, o.doc));
        for c in o.columns {
            let unit = if c.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", c.unit)
            };
            out.push_str(&format!(
                "      {:<20} {}{unit}  {}\n",
                c.name, c.dtype, c.doc
            ));
        }
    }
    out.push('\n');
    out
}

fn describe_json(stage: &dyn DynStage) -> Value {
    let info = stage.info();
    let defaults = stage.default_params();
    json!({
        "kind": info.kind,
        "version": info.version,
        "summary": info.summary,
        "doc": info.doc,
        "params": info.params.iter().map(|p| json!({
            "name": p.name, "unit": p.unit, "doc": p.doc,
            "default": defaults.get(p.name).cloned().unwrap_or(Value::Null),
        })).collect::<Vec<_>>(),
        "inputs": info.inputs.iter().map(|i| json!({
            "name": i.name, "kind": i.kind, "arity": i.arity, "doc": i.doc,
            "columns": i.columns,
        })).collect::<Vec<_>>(),
        "outputs": info.outputs.iter().map(|o| json!({
            "name": o.name, "kind": o.kind, "doc": o.doc, "columns": o.columns,
        })).collect::<Vec<_>>(),
    })
}

fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    /// Every documented parameter exists in the defaults and every default
    /// is documented, so `stages` never drifts from the code.
    #[test]
    fn every_parameter_is_documented() {
        let registry = hypercontact::registry();
        for stage in registry.iter() {
            let info = stage.info();
            let defaults = stage.default_params();
            let keys: Vec<&String> = defaults
                .as_object()
                .map(|o| o.keys().collect())
                .unwrap_or_default();
            for k in &keys {
                assert!(
                    info.params.iter().any(|p| p.name == k.as_str()),
                    "{}: parameter `{k}` is not documented",
                    info.kind
                );
            }
            for p in info.params {
                assert!(
                    keys.iter().any(|k| k.as_str() == p.name),
                    "{}: `{}` documented but absent",
                    info.kind,
                    p.name
                );
            }
        }
    }
}
