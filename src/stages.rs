//! `hypercontact stages`: every stage kind with its parameters (defaults and
//! units), inputs and output schemas.

use anyhow::{Result, bail};
use hypercontact_core::param::TypeDoc;
use hypercontact_core::{DynStage, ParamSpec, Registry};
use serde_json::Value;

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
        let all: Vec<Value> = stages
            .iter()
            .map(|s| hypercontact::describe_json(s.as_ref()))
            .collect();
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

/// The default as the text shows it: the YAML/JSON value, `(required)`,
/// or `-` for an optional parameter without one.
fn default_text(p: &ParamSpec) -> String {
    match &p.default {
        _ if p.required => "(required)".into(),
        None | Some(Value::Null) => "-".into(),
        Some(v) => v.to_string(),
    }
}

/// What follows the doc: the choices, the range, the kind of value when it
/// is not a plain number, text or flag.
fn constraints(p: &ParamSpec) -> String {
    let mut parts = Vec::new();
    // An optional parameter shows `-` as its default; its type is the inner one.
    let ty = match &p.ty {
        TypeDoc::Optional(inner) => inner.as_ref(),
        ty => ty,
    };
    match ty {
        TypeDoc::Number | TypeDoc::Integer | TypeDoc::Bool | TypeDoc::Text => {}
        TypeDoc::Struct(_) => {}
        other => parts.push(other.to_string()),
    }
    if let Some(range) = &p.range {
        parts.push(range.to_string());
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({})", parts.join("; "))
    }
}

fn param_lines(out: &mut String, specs: &[ParamSpec], prefix: &str, full: bool) {
    for p in specs {
        let name = if prefix.is_empty() {
            p.name.to_owned()
        } else {
            format!("{prefix}.{}", p.name)
        };
        if let TypeDoc::Struct(fields) = &p.ty {
            out.push_str(&format!("    {name:<22}   {}\n", p.doc));
            param_lines(out, fields, &name, full);
            continue;
        }
        let unit = if p.unit.is_empty() {
            String::new()
        } else {
            format!(" [{}]", p.unit)
        };
        out.push_str(&format!(
            "    {name:<22} = {:<14}{unit}  {}{}\n",
            default_text(p),
            p.doc,
            constraints(p)
        ));
        let choices = match &p.ty {
            TypeDoc::Choice(c) => Some(*c),
            TypeDoc::Optional(inner) => match &**inner {
                TypeDoc::Choice(c) => Some(*c),
                _ => None,
            },
            _ => None,
        };
        if full && let Some(choices) = choices {
            for c in choices.iter().filter(|c| !c.doc.is_empty()) {
                out.push_str(&format!("      {:<20}   {}\n", c.name, c.doc));
            }
        }
    }
}

pub fn describe_text(stage: &dyn DynStage, full: bool) -> String {
    let info = stage.info();
    let specs = stage.params_spec();
    let mut out = format!("{} (v{}) — {}\n", info.kind, info.version, info.summary);
    if full && !info.doc.is_empty() {
        for line in wrap(info.doc, 88) {
            out.push_str(&format!("  {line}\n"));
        }
    }
    if !specs.is_empty() {
        out.push_str("  params:\n");
        param_lines(&mut out, &specs, "", full);
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
    if full {
        let r = stage.resources();
        out.push_str(&format!(
            "  slurm job (--executor slurm): cpus {}, mem {} MiB, time {} min\n",
            r.cpus, r.mem_mb, r.time_min
        ));
    }
    out.push('\n');
    out
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
    use super::*;

    /// What `hypercontact stages` prints, and each kind in full, pinned: a
    /// change of any declaration shows up in review.
    #[test]
    fn stage_descriptions_are_pinned() {
        let registry = hypercontact::registry();
        let summary: String = registry
            .iter()
            .map(|s| describe_text(s.as_ref(), false))
            .collect();
        insta::assert_snapshot!("stages", summary);
        let full: String = registry
            .iter()
            .map(|s| describe_text(s.as_ref(), true))
            .collect();
        insta::assert_snapshot!("stages_full", full);
    }

    /// Every parameter of every kind is documented, and every required one
    /// is required by its declaration (no faked zero defaults).
    #[test]
    fn every_parameter_is_documented() {
        let registry = hypercontact::registry();
        for stage in registry.iter() {
            for p in stage.params_spec() {
                assert!(
                    !p.doc.is_empty(),
                    "{}: parameter `{}` has no doc comment",
                    stage.info().kind,
                    p.name
                );
                assert!(
                    p.required || p.default.is_some() || matches!(p.ty, TypeDoc::Optional(_)),
                    "{}: `{}` is neither required, defaulted nor optional",
                    stage.info().kind,
                    p.name
                );
            }
        }
    }
}
