//! The pipeline as a picture: a [`Plan`] drawn as a Mermaid flowchart or a
//! Graphviz digraph, one node per stage (name, kind and what a run would do
//! with it) and one edge per resolved input, labelled `output → input`.
//!
//! What a run would do is the plan's own verdict, the one `run --dry-run`
//! prints ([`PlannedStage::action`]): a stage is *cached*, *stale* (it would
//! run, with the plan's reason) or *temporary* (a `temp: true` stage whose
//! entry is gone and which no stage of the run needs). Snakemake's `--dag`
//! and `dvc dag --mermaid` are the models; the colours follow the
//! colour-blind-safe Okabe–Ito palette the report's figures use.

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::plan::{Action, Plan, PlannedStage, Reason};

/// What the graph says of one stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeState {
    /// Its entry is in the cache and valid: a run reuses it.
    Cached,
    /// A run would compute it (new, changed, forced or missing).
    Stale,
    /// A temporary stage no stage of this run needs: it would not run and
    /// has no entry.
    Temporary,
    /// Not needed for `--only`.
    Skipped,
}

impl NodeState {
    /// The state of a planned stage, from the plan's action.
    pub fn of(stage: &PlannedStage) -> Self {
        match stage.action() {
            Action::Cached => NodeState::Cached,
            Action::Run => NodeState::Stale,
            Action::Skip if stage.reason == Reason::TempNotNeeded => NodeState::Temporary,
            Action::Skip => NodeState::Skipped,
        }
    }

    /// The word the node shows, also its Mermaid class.
    pub fn word(self) -> &'static str {
        match self {
            NodeState::Cached => "cached",
            NodeState::Stale => "stale",
            NodeState::Temporary => "temporary",
            NodeState::Skipped => "skipped",
        }
    }

    /// Fill and border colours (Okabe–Ito: bluish green, orange, grey, grey).
    fn colours(self) -> (&'static str, &'static str) {
        match self {
            NodeState::Cached => ("#d5efe6", "#009e73"),
            NodeState::Stale => ("#fde9c9", "#e69f00"),
            NodeState::Temporary | NodeState::Skipped => ("#eeeeee", "#999999"),
        }
    }
}

/// The output format of [`render`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraphFormat {
    /// Mermaid `flowchart LR` (GitHub, GitLab and most Markdown viewers draw it).
    Mermaid,
    /// Graphviz `digraph` (`dot -Tsvg`).
    Dot,
}

/// One edge: `from` stage's output feeds `to` stage's input.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    pub from: String,
    pub to: String,
    /// `output → input` (`height → surface`, `response → responses.T1.icm`).
    pub label: String,
}

/// Every edge of the plan, in plan order: one per resolved input.
pub fn edges(plan: &Plan) -> Vec<Edge> {
    plan.stages
        .iter()
        .flat_map(|s| {
            s.inputs.iter().map(move |i| Edge {
                from: i.from_stage.clone(),
                to: s.name.clone(),
                label: format!("{} → {}", i.from_output, i.input),
            })
        })
        .collect()
}

/// The second line of a node: its state, and why it would run.
fn state_text(stage: &PlannedStage) -> String {
    let state = NodeState::of(stage);
    let why = match &stage.reason {
        Reason::New => "new",
        Reason::Forced => "forced",
        Reason::VersionChanged { .. } => "version changed",
        Reason::KindChanged { .. } => "kind changed",
        Reason::ParamsChanged(_) => "params changed",
        Reason::InputsChanged(_) => "input changed",
        Reason::FilesChanged(_) => "input file changed",
        Reason::NotInCache(_) => "not in cache",
        Reason::Unreadable(_) => "input file unreadable",
        Reason::Cached | Reason::NotSelected | Reason::TempNotNeeded => "",
    };
    let temp = if stage.temp && state != NodeState::Temporary {
        ", temp"
    } else {
        ""
    };
    match why {
        "" => format!("{}{temp}", state.word()),
        why => format!("{}: {why}{temp}", state.word()),
    }
}

/// The plan drawn in `format`, titled `name` (the pipeline's name).
pub fn render(plan: &Plan, name: &str, format: GraphFormat) -> String {
    match format {
        GraphFormat::Mermaid => mermaid(plan, name),
        GraphFormat::Dot => dot(plan, name),
    }
}

/// Text for a Mermaid label in double quotes: its entity codes for the
/// characters that would end or break the label (Mermaid's `#quot;` form).
fn mermaid_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("#quot;"),
            '#' => out.push_str("#35;"),
            '<' => out.push_str("#lt;"),
            '>' => out.push_str("#gt;"),
            '|' => out.push_str("#124;"),
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A Mermaid flowchart, left to right. Stage names may hold any letter, so
/// nodes get ids `s0`, `s1`, ... in plan order and show the name as label.
pub fn mermaid(plan: &Plan, name: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "---\ntitle: {}\n---", mermaid_text(name));
    out.push_str("flowchart LR\n");
    let ids: HashMap<&str, String> = plan
        .stages
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.as_str(), format!("s{i}")))
        .collect();
    for (i, s) in plan.stages.iter().enumerate() {
        let _ = writeln!(
            out,
            "    s{i}[\"<b>{}</b><br/>{}<br/><i>{}</i>\"]:::{}",
            mermaid_text(&s.name),
            mermaid_text(&s.kind),
            mermaid_text(&state_text(s)),
            NodeState::of(s).word()
        );
    }
    for e in edges(plan) {
        // Both ends are planned stages: the plan resolved every input.
        if let (Some(from), Some(to)) = (ids.get(e.from.as_str()), ids.get(e.to.as_str())) {
            let _ = writeln!(out, "    {from} -->|\"{}\"| {to}", mermaid_text(&e.label));
        }
    }
    for state in [
        NodeState::Cached,
        NodeState::Stale,
        NodeState::Temporary,
        NodeState::Skipped,
    ] {
        let (fill, stroke) = state.colours();
        let dash = match state {
            NodeState::Temporary | NodeState::Skipped => ",stroke-dasharray:5 5",
            _ => "",
        };
        let _ = writeln!(
            out,
            "    classDef {} fill:{fill},stroke:{stroke},color:#000{dash}",
            state.word()
        );
    }
    out
}

/// Text for a Graphviz double-quoted string: `"` and `\` escaped, line
/// breaks as `\n`.
fn dot_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A Graphviz digraph, left to right; node ids are the quoted stage names.
pub fn dot(plan: &Plan, name: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "digraph \"{}\" {{", dot_text(name));
    out.push_str("    rankdir=LR;\n");
    out.push_str("    node [shape=box, style=\"rounded,filled\", fontname=\"Helvetica\"];\n");
    out.push_str("    edge [fontname=\"Helvetica\", fontsize=10];\n");
    for s in &plan.stages {
        let state = NodeState::of(s);
        let (fill, stroke) = state.colours();
        let style = match state {
            NodeState::Temporary | NodeState::Skipped => "rounded,filled,dashed",
            _ => "rounded,filled",
        };
        let _ = writeln!(
            out,
            "    \"{}\" [label=\"{}\\n{}\\n{}\", fillcolor=\"{fill}\", color=\"{stroke}\", \
             style=\"{style}\"];",
            dot_text(&s.name),
            dot_text(&s.name),
            dot_text(&s.kind),
            dot_text(&state_text(s)),
        );
    }
    for e in edges(plan) {
        let _ = writeln!(
            out,
            "    \"{}\" -> \"{}\" [label=\"{}\"];",
            dot_text(&e.from),
            dot_text(&e.to),
            dot_text(&e.label)
        );
    }
    out.push_str("}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::ResolvedInput;

    fn stage(
        name: &str,
        reason: Reason,
        temp: bool,
        inputs: &[(&str, &str, &str)],
    ) -> PlannedStage {
        PlannedStage {
            name: name.into(),
            kind: "k".into(),
            version: 1,
            key: "0".repeat(64),
            params: serde_json::Value::Null,
            files: Default::default(),
            inputs: inputs
                .iter()
                .map(|(input, from, output)| ResolvedInput {
                    input: (*input).into(),
                    from_stage: (*from).into(),
                    from_output: (*output).into(),
                    upstream_key: "0".repeat(64),
                })
                .collect(),
            runs: !matches!(
                reason,
                Reason::Cached | Reason::NotSelected | Reason::TempNotNeeded
            ),
            reason,
            temp,
            manifest: None,
        }
    }

    /// Names and labels that would end a label or a string early come out
    /// escaped, and each state has its class.
    #[test]
    fn labels_are_escaped_and_states_marked() {
        let plan = Plan {
            stages: vec![
                stage("scan", Reason::TempNotNeeded, true, &[]),
                stage("a\"b", Reason::Cached, false, &[("in", "scan", "tiles")]),
                stage(
                    "c",
                    Reason::ParamsChanged(vec!["x: 1 → 2".into()]),
                    false,
                    &[("responses.T1|x", "a\"b", "out")],
                ),
            ],
        };
        let m = mermaid(&plan, "demo");
        assert!(m.contains("s0[\"<b>scan</b><br/>k<br/><i>temporary</i>\"]:::temporary"));
        assert!(m.contains("s1[\"<b>a#quot;b</b><br/>k<br/><i>cached</i>\"]:::cached"));
        assert!(m.contains("<i>stale: params changed</i>\"]:::stale"));
        assert!(m.contains("s1 -->|\"out → responses.T1#124;x\"| s2"));
        let d = dot(&plan, "demo");
        assert!(d.contains("\"a\\\"b\" -> \"c\" [label=\"out → responses.T1|x\"];"));
        assert!(d.contains("style=\"rounded,filled,dashed\""));
        assert_eq!(edges(&plan).len(), 2);
    }
}
