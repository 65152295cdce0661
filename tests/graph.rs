//! `hypercontact graph`: the paper pipeline's graph holds every stage and
//! every edge of its plan, in Mermaid and in dot, and both texts pass a
//! structural check (ids valid, every edge's ends declared); after a run
//! the graph marks the stages cached, and after a parameter changes, the
//! changed stage and everything downstream of it stale.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use hypercontact_runner::graph::{self, NodeState};
use hypercontact_runner::{Pipeline, Plan, RunOptions};

use crate::common::{bin, repo, text};

/// (from stage, to stage, label) of each edge, counted.
type Edges = BTreeMap<(String, String, String), usize>;

/// The plan `run --dry-run` makes of `pipeline` against `cache`.
fn dry_plan(pipeline: &Pipeline, out: &Path, cache: &Path) -> Plan {
    let mut options = RunOptions::in_folders(out.to_owned(), cache.to_owned());
    options.dry_run = true;
    hypercontact_runner::run(pipeline, &options).unwrap().plan
}

/// The edges the pipeline file wires, from its declarations (not from the
/// plan): one per input binding, labelled with the output the plan
/// resolved for it.
fn plan_edges(plan: &Plan) -> Edges {
    let mut edges = Edges::new();
    for s in &plan.stages {
        for i in &s.inputs {
            let label = format!("{} → {}", i.from_output, i.input);
            *edges
                .entry((i.from_stage.clone(), s.name.clone(), label))
                .or_default() += 1;
        }
    }
    edges
}

fn valid_id(id: &str) -> bool {
    let mut chars = id.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Mermaid's `#quot;`-style codes back to characters.
fn mermaid_unescape(text: &str) -> String {
    text.replace("#quot;", "\"")
        .replace("#lt;", "<")
        .replace("#gt;", ">")
        .replace("#124;", "|")
        .replace("#35;", "#")
}

/// A flowchart checked line by line: front matter, `flowchart LR`, then
/// only node declarations `ID["label"]:::class`, edges
/// `ID -->|"label"| ID` and `classDef` lines; every id valid, no id
/// declared twice, every edge's ends declared, every class defined, no
/// stray `"` inside a label. Returns node id → (name, state word) and the
/// edges by stage name.
fn parse_mermaid(text: &str) -> (BTreeMap<String, (String, String)>, Edges) {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("---"));
    assert!(lines.next().unwrap().starts_with("title: "));
    assert_eq!(lines.next(), Some("---"));
    assert_eq!(lines.next(), Some("flowchart LR"));
    let mut nodes = BTreeMap::new();
    let mut raw_edges = Vec::new();
    let mut classes = BTreeSet::new();
    let mut used_classes = BTreeSet::new();
    for line in lines {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix("classDef ") {
            classes.insert(rest.split_whitespace().next().unwrap().to_owned());
        } else if let Some((from, rest)) = line.split_once(" -->|\"") {
            let (label, to) = rest.split_once("\"| ").expect(line);
            assert!(valid_id(from) && valid_id(to), "{line}");
            assert!(!label.contains('"'), "{line}");
            raw_edges.push((from.to_owned(), to.to_owned(), mermaid_unescape(label)));
        } else {
            let (id, rest) = line.split_once("[\"").expect(line);
            let (label, class) = rest.split_once("\"]:::").expect(line);
            assert!(valid_id(id) && valid_id(class), "{line}");
            assert!(!label.contains('"'), "{line}");
            let name = label
                .strip_prefix("<b>")
                .and_then(|l| l.split_once("</b>"))
                .expect(line)
                .0;
            used_classes.insert(class.to_owned());
            let old = nodes.insert(id.to_owned(), (mermaid_unescape(name), class.to_owned()));
            assert!(old.is_none(), "{id} declared twice");
        }
    }
    assert!(
        used_classes.is_subset(&classes),
        "{used_classes:?} {classes:?}"
    );
    let mut edges = Edges::new();
    for (from, to, label) in raw_edges {
        let name = |id: &str| {
            nodes
                .get(id)
                .unwrap_or_else(|| panic!("edge end {id} not declared"))
                .0
                .clone()
        };
        *edges.entry((name(&from), name(&to), label)).or_default() += 1;
    }
    (nodes, edges)
}

/// A dot string starting at a `"`: its text and the rest after the
/// closing quote.
fn dot_string(s: &str) -> (String, &str) {
    let mut out = String::new();
    let mut chars = s.strip_prefix('"').expect(s).char_indices();
    while let Some((i, c)) = chars.next() {
        match c {
            '\\' => match chars.next().unwrap().1 {
                'n' => out.push('\n'),
                c => out.push(c),
            },
            '"' => return (out, &s[i + 2..]),
            c => out.push(c),
        }
    }
    panic!("unterminated string in {s}")
}

/// A digraph checked line by line: header, graph and default attributes,
/// `"name" [label=...]` nodes (each declared once) and `"a" -> "b"
/// [label="..."]` edges whose ends are declared nodes, then `}`.
fn parse_dot(text: &str) -> (BTreeMap<String, String>, Edges) {
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("digraph \"") && header.ends_with("\" {"));
    let mut nodes = BTreeMap::new();
    let mut edges = Edges::new();
    let mut closed = false;
    for line in lines {
        assert!(!closed, "text after the closing brace: {line}");
        let line = line.trim();
        if line == "}" {
            closed = true;
            continue;
        }
        if line == "rankdir=LR;" || line.starts_with("node [") || line.starts_with("edge [") {
            continue;
        }
        let (first, rest) = dot_string(line);
        if let Some(rest) = rest.strip_prefix(" -> ") {
            let (second, rest) = dot_string(rest);
            let (label, rest) = dot_string(rest.strip_prefix(" [label=").expect(line));
            assert_eq!(rest, "];", "{line}");
            *edges.entry((first, second, label)).or_default() += 1;
        } else {
            let (label, rest) = dot_string(rest.strip_prefix(" [label=").expect(line));
            assert!(rest.ends_with("\"];"), "{line}");
            let state = label.lines().nth(2).expect(line).to_owned();
            assert!(
                nodes.insert(first, state).is_none(),
                "{line}: declared twice"
            );
        }
    }
    assert!(closed, "no closing brace");
    for (from, to, _) in edges.keys() {
        assert!(
            nodes.contains_key(from) && nodes.contains_key(to),
            "{from} -> {to}"
        );
    }
    (nodes, edges)
}

fn paper() -> Pipeline {
    Pipeline::load(
        &repo().join("pipelines/paper.yaml"),
        &hypercontact::registry(),
    )
    .unwrap()
}

/// The real parsers accept these texts. Checked once by hand (2026-11-27)
/// on `hypercontact graph pipelines/paper.yaml` with a cold cache: Mermaid
/// 11.17.2 (`npm install mermaid@11 jsdom` in a throwaway folder,
/// `await mermaid.parse(text)` under a jsdom window) returned
/// `{"diagramType":"flowchart-v2"}` for it and for a small pipeline's graph
/// with a stale stage, and rejected the same text with one edge label left
/// unclosed; pydot 4.0.1 (`pip install pydot` in a throwaway venv,
/// `pydot.graph_from_dot_file`) read the `--format dot` text as 113 nodes
/// and 386 edges, the counts of the Mermaid text.
#[test]
fn paper_graph_has_every_stage_and_edge_of_the_plan() {
    let t = tempfile::tempdir().unwrap();
    let pipeline = paper();
    let plan = dry_plan(&pipeline, &t.path().join("out"), &t.path().join("cache"));
    let stages: BTreeSet<String> = plan.stages.iter().map(|s| s.name.clone()).collect();
    // The plan itself holds every stage of the file and every binding.
    let declared: BTreeSet<String> = pipeline.stages.iter().map(|s| s.name.clone()).collect();
    assert_eq!(stages, declared);
    let bindings: usize = pipeline.stages.iter().map(|s| s.inputs.len()).sum();
    let expected = plan_edges(&plan);
    assert_eq!(expected.values().sum::<usize>(), bindings);
    assert!(
        bindings > 100 && stages.len() > 80,
        "{bindings} {}",
        stages.len()
    );

    let (nodes, edges) = parse_mermaid(&graph::mermaid(&plan, &pipeline.name));
    let names: BTreeSet<String> = nodes.values().map(|(n, _)| n.clone()).collect();
    assert_eq!(names, stages);
    assert_eq!(nodes.len(), stages.len());
    assert_eq!(edges, expected);
    // A cold cache: every stage would run but the temporary ones, which run
    // too (their readers do).
    assert!(nodes.values().all(|(_, state)| state == "stale"));

    let (nodes, edges) = parse_dot(&graph::dot(&plan, &pipeline.name));
    assert_eq!(nodes.keys().cloned().collect::<BTreeSet<_>>(), stages);
    assert_eq!(edges, expected);
    assert!(nodes.values().all(|state| state.starts_with("stale: new")));
    // The temporary stages say so.
    let temps: Vec<&str> = pipeline
        .stages
        .iter()
        .filter(|s| s.temp)
        .map(|s| s.name.as_str())
        .collect();
    assert!(temps.contains(&"t1-scan"));
    for temp in temps {
        assert!(nodes[temp].ends_with(", temp"), "{temp}: {}", nodes[temp]);
    }
}

/// The demo pipeline in `dir`, reading the repository's sample map.
fn demo_in(dir: &Path) -> PathBuf {
    let sample = repo().join("data/samples/self-affine-256.npy");
    let yaml = std::fs::read_to_string(repo().join("pipelines/demo.yaml"))
        .unwrap()
        .replace(
            "../data/samples/self-affine-256.npy",
            &sample.display().to_string(),
        );
    let path = dir.join("demo.yaml");
    std::fs::write(&path, yaml).unwrap();
    path
}

/// `name` and every stage that reads it, directly or not, from the
/// pipeline's declared bindings.
fn downstream(pipeline: &Pipeline, name: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::from([name.to_owned()]);
    loop {
        let more: Vec<String> = pipeline
            .stages
            .iter()
            .filter(|s| !out.contains(&s.name))
            .filter(|s| s.inputs.iter().any(|b| out.contains(&b.from_stage)))
            .map(|s| s.name.clone())
            .collect();
        if more.is_empty() {
            return out;
        }
        out.extend(more);
    }
}

#[test]
fn after_a_run_stages_are_cached_and_a_changed_one_is_stale_with_its_dependants() {
    let t = tempfile::tempdir().unwrap();
    let file = demo_in(t.path());
    let (out, cache) = (t.path().join("out"), t.path().join("cache"));
    let registry = hypercontact::registry();
    let pipeline = Pipeline::load(&file, &registry).unwrap();
    hypercontact_runner::run(
        &pipeline,
        &RunOptions::in_folders(out.clone(), cache.clone()),
    )
    .unwrap();
    let plan = dry_plan(&pipeline, &out, &cache);
    assert!(
        plan.stages
            .iter()
            .all(|s| NodeState::of(s) == NodeState::Cached)
    );
    let (nodes, _) = parse_mermaid(&graph::mermaid(&plan, "demo"));
    assert!(
        nodes.values().all(|(_, state)| state == "cached"),
        "{nodes:?}"
    );

    let changed = Pipeline::load_with_sets(&file, &["trunc.levels=500".into()], &registry).unwrap();
    let plan = dry_plan(&changed, &out, &cache);
    let stale = downstream(&changed, "trunc");
    assert_eq!(
        stale,
        BTreeSet::from(["trunc", "contact", "contact-linear"].map(String::from))
    );
    let (nodes, _) = parse_dot(&graph::dot(&plan, "demo"));
    for (name, state) in &nodes {
        if name == "trunc" {
            assert_eq!(state, "stale: params changed");
        } else if stale.contains(name) {
            assert_eq!(state, "stale: input changed");
        } else {
            assert_eq!(state, "cached", "{name}");
        }
    }

    // The command prints the same graph, planned against the same cache.
    let printed = bin()
        .arg("graph")
        .arg(&file)
        .args(["--format", "dot", "--set", "trunc.levels=500", "--cache"])
        .arg(&cache)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(printed.status.success(), "{}", text(&printed));
    let stdout = String::from_utf8(printed.stdout).unwrap();
    assert_eq!(parse_dot(&stdout).0, nodes);
    let mermaid = bin()
        .arg("graph")
        .arg(&file)
        .arg("--cache")
        .arg(&cache)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(mermaid.status.success(), "{}", text(&mermaid));
    let (nodes, _) = parse_mermaid(&String::from_utf8(mermaid.stdout).unwrap());
    assert!(nodes.values().all(|(_, state)| state == "cached"));
}

/// Every pipeline shipped in pipelines/ loads (YAML, stage kinds, checked
/// parameters, wiring) and plans against an empty cache: a pipeline the
/// README names but no test runs (paper.yaml, refinement.yaml) is at least
/// well formed.
#[test]
fn every_shipped_pipeline_loads_and_plans() {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(repo().join("pipelines")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "yaml") {
            continue;
        }
        let pipeline = Pipeline::load(&path, &hypercontact::registry())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let t = tempfile::tempdir().unwrap();
        let plan = dry_plan(&pipeline, &t.path().join("out"), &t.path().join("cache"));
        assert!(!plan.stages.is_empty(), "{}: an empty plan", path.display());
        names.push(path.file_name().unwrap().to_string_lossy().into_owned());
    }
    names.sort();
    assert!(
        ["paper.yaml", "quick.yaml", "refinement.yaml"]
            .iter()
            .all(|n| names.iter().any(|m| m == n)),
        "{names:?}"
    );
}
