//! What an editor knows about `hypercontact.stages`: the type stub
//! `python/hypercontact/stages.pyi` and the docstring of each generated
//! function, both written from the stage declarations (parameters with
//! their types, defaults, units and docs; inputs; outputs), so a new kind
//! or parameter needs no Python. The committed stub is checked against this
//! generator by `tests/stubs.rs`, which rewrites it when asked.

use std::fmt::Write as _;

use hypercontact_core::param::TypeDoc;
use hypercontact_core::{Arity, DynStage, ParamSpec, ProductKind, Registry};
use serde_json::Value;

/// Keywords every generated function takes besides the stage's own
/// parameters and inputs; no stage may declare these names.
pub const RESERVED: [&str; 2] = ["out_dir", "progress"];

/// The Python attribute of a kind: hyphens as underscores, a keyword with a
/// trailing underscore (as `hypercontact.stages` names them).
pub fn attribute(kind: &str) -> String {
    let name = kind.replace('-', "_");
    const KEYWORDS: [&str; 35] = [
        "False", "None", "True", "and", "as", "assert", "async", "await", "break", "class",
        "continue", "def", "del", "elif", "else", "except", "finally", "for", "from", "global",
        "if", "import", "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise", "return",
        "try", "while", "with", "yield",
    ];
    if KEYWORDS.contains(&name.as_str()) {
        name + "_"
    } else {
        name
    }
}

/// A Python string literal of `text` (double quotes; UTF-8 kept as it is).
fn py_str(text: &str) -> String {
    format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The Python type a parameter of this declared type takes.
fn param_type(ty: &TypeDoc) -> String {
    match ty {
        TypeDoc::Number => "float".to_owned(),
        TypeDoc::Integer => "int".to_owned(),
        TypeDoc::Bool => "bool".to_owned(),
        TypeDoc::Text => "str".to_owned(),
        TypeDoc::Path => "Union[str, PathLike[str]]".to_owned(),
        TypeDoc::Choice(choices) => format!(
            "Literal[{}]",
            choices
                .iter()
                .map(|c| py_str(c.name))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        TypeDoc::Optional(inner) => format!("Optional[{}]", param_type(inner)),
        TypeDoc::List(inner) | TypeDoc::Array(_, inner) => {
            format!("Sequence[{}]", param_type(inner))
        }
        TypeDoc::Map(inner) => format!("Mapping[str, {}]", param_type(inner)),
        TypeDoc::Struct(_) | TypeDoc::Custom(_) => "Any".to_owned(),
    }
}

/// A default as Python source, when it is a plain value an editor should
/// show; `...` (the stub's "has a default") otherwise.
fn python_literal(value: &Value) -> String {
    match value {
        Value::Null => "None".to_owned(),
        Value::Bool(true) => "True".to_owned(),
        Value::Bool(false) => "False".to_owned(),
        Value::Number(n) => n.to_string(),
        Value::String(s) => py_str(s),
        Value::Array(_) | Value::Object(_) => "...".to_owned(),
    }
}

fn product_type(kind: ProductKind) -> &'static str {
    match kind {
        ProductKind::Table => "Table",
        ProductKind::Field => "Field",
        ProductKind::Files => "FilesLike",
    }
}

fn output_type(kind: ProductKind) -> &'static str {
    match kind {
        ProductKind::Table => "pl.DataFrame",
        ProductKind::Field => "Field",
        ProductKind::Files => "Files",
    }
}

/// An input's Python type and whether it may be left out.
fn input_type(kind: ProductKind, arity: Arity) -> (String, bool) {
    let one = product_type(kind);
    match arity {
        Arity::One => (one.to_owned(), false),
        Arity::Optional => (format!("Optional[{one}]"), true),
        Arity::Many => (format!("Optional[Mapping[str, {one}]]"), true),
        Arity::OneOrMore => (format!("Union[{one}, Mapping[str, {one}]]"), false),
        Arity::Nested => (format!("Optional[Mapping[str, Mapping[str, {one}]]]"), true),
    }
}

fn param_line(p: &ParamSpec) -> String {
    let unit = if p.unit.is_empty() {
        String::new()
    } else {
        format!(" [{}]", p.unit)
    };
    let default = if p.required {
        "required".to_owned()
    } else {
        match &p.default {
            Some(v) => format!("default {v}"),
            None => "optional".to_owned(),
        }
    };
    format!("    {} ({default}){unit}: {}", p.name, one_line(p.doc))
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The docstring of `hypercontact.stages.<kind>`: summary, doc, then every
/// parameter, input and output with its unit and doc.
pub fn docstring(stage: &dyn DynStage) -> String {
    let info = stage.info();
    let mut out = format!("{}\n", info.summary);
    if !info.doc.is_empty() {
        out.push('\n');
        out.push_str(info.doc.trim_end());
        out.push('\n');
    }
    let params = stage.params_spec();
    if !params.is_empty() {
        out.push_str("\nParameters (keywords, as in a pipeline's `with:` block):\n");
        for p in &params {
            out.push_str(&param_line(p));
            out.push('\n');
        }
    }
    if !info.inputs.is_empty() {
        out.push_str("\nInputs (keywords; a table as a polars or pandas DataFrame):\n");
        for i in info.inputs {
            let arity = format!("{:?}", i.arity).to_lowercase();
            let _ = writeln!(
                out,
                "    {} ({}, {arity}): {}",
                i.name,
                i.kind,
                one_line(i.doc)
            );
        }
    }
    out.push_str(if info.outputs.len() == 1 {
        "\nReturns the output:\n"
    } else {
        "\nReturns a dict of the outputs:\n"
    });
    for o in info.outputs {
        let _ = writeln!(out, "    {} ({}): {}", o.name, o.kind, one_line(o.doc));
    }
    out.push_str(
        "\nAlso: out_dir, the folder for file outputs (default a new temporary folder); \
         progress, bars on stderr (default: when stderr is a terminal).\n",
    );
    out
}

/// A Python string literal holding `text` as a docstring.
fn docstring_literal(text: &str) -> String {
    let escaped = text.replace('\\', "\\\\").replace("\"\"\"", "\\\"\\\"\\\"");
    format!("\"\"\"{escaped}\"\"\"")
}

/// One kind's outputs as a TypedDict (functional form: output names need
/// not be identifiers) when it has several, and its function.
fn stub_of(stage: &dyn DynStage, out: &mut String) {
    let info = stage.info();
    let name = attribute(info.kind);
    let returns = if info.outputs.len() == 1 {
        output_type(info.outputs[0].kind).to_owned()
    } else {
        let class = format!("_{}Outputs", name);
        let fields: Vec<String> = info
            .outputs
            .iter()
            .map(|o| format!("{}: {}", py_str(o.name), output_type(o.kind)))
            .collect();
        let _ = writeln!(
            out,
            "{class} = TypedDict({}, {{{}}})\n",
            py_str(&class),
            fields.join(", ")
        );
        class
    };
    let mut args = Vec::new();
    for i in info.inputs {
        let (ty, optional) = input_type(i.kind, i.arity);
        args.push(if optional {
            format!("{}: {ty} = None", i.name)
        } else {
            format!("{}: {ty}", i.name)
        });
    }
    for p in stage.params_spec() {
        let ty = param_type(&p.ty);
        args.push(match (&p.default, p.required) {
            (_, true) => format!("{}: {ty}", p.name),
            (Some(v), false) => format!("{}: {ty} = {}", p.name, python_literal(v)),
            (None, false) if ty.starts_with("Optional[") => format!("{}: {ty} = None", p.name),
            (None, false) => format!("{}: Optional[{ty}] = None", p.name),
        });
    }
    args.push("out_dir: Union[str, PathLike[str], None] = None".to_owned());
    args.push("progress: Optional[bool] = None".to_owned());
    let _ = writeln!(out, "def {name}(\n    *,");
    for a in &args {
        let _ = writeln!(out, "    {a},");
    }
    let doc = docstring(stage);
    let indented: String = doc
        .lines()
        .map(|l| {
            if l.is_empty() {
                "\n".to_owned()
            } else {
                format!("    {l}\n")
            }
        })
        .collect();
    let _ = writeln!(
        out,
        ") -> {returns}:\n    {}\n    ...\n",
        docstring_literal(indented.trim())
    );
}

/// The whole `stages.pyi`.
pub fn stages_pyi(registry: &Registry) -> String {
    let mut out = String::from(
        "# The type stub of `hypercontact.stages`, generated from the stage declarations by\n\
         # crates/python/src/stubs.rs; do not edit. After changing a stage, rewrite it with\n\
         # HYPERCONTACT_WRITE_STUBS=1 cargo test --release -p hypercontact-python --test stubs\n\n\
         from os import PathLike\n\
         from typing import Any, Literal, Mapping, Optional, Sequence, TypedDict, Union\n\n\
         import polars as pl\n\n\
         from . import Field, Files, FilesLike, Table\n\n",
    );
    let mut names = Vec::new();
    for stage in registry.iter() {
        stub_of(stage.as_ref(), &mut out);
        names.push(py_str(&attribute(stage.info().kind)));
    }
    let _ = writeln!(out, "__all__ = [{}]", names.join(", "));
    out
}
