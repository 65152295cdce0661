//! Property tests of the pipeline reading: `yaml::Located::parse` on
//! arbitrary text, on YAML-like token soup and on the shipped pipelines with
//! characters inserted, deleted or replaced; `Pipeline::parse` of edited
//! pipelines over the test stages; `--set` assignments. Never a panic; an
//! error's location lies inside the text; a pipeline error names the file.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property;
//! `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen or move the search.

use crate::common;

use std::path::Path;

use hypercontact_fuzz::config;
use hypercontact_runner::Pipeline;
use hypercontact_runner::yaml::Located;
use proptest::prelude::*;

/// The name the pipelines are parsed under; a folder that does not exist,
/// so no `with_file:` or `path:` an edit makes up reads a real file.
const FILE: &str = "/nonexistent-hc-fuzz/p.yaml";

/// Texts the edits start from: the test pipeline and the shipped ones.
fn seeds() -> Vec<&'static str> {
    vec![
        common::BASIC,
        include_str!("../../../pipelines/quick.yaml"),
        include_str!("../../../pipelines/paper.yaml"),
        include_str!("../../../pipelines/demo.yaml"),
        include_str!("../../../pipelines/tensile-csv.yaml"),
    ]
}

/// Pieces of YAML syntax, scalars of every type, multi-byte text.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(": ".into()),
        Just(":".into()),
        Just("- ".into()),
        Just("\n".into()),
        Just("\r\n".into()),
        Just("  ".into()),
        Just("\t".into()),
        Just("{".into()),
        Just("}".into()),
        Just("[".into()),
        Just("]".into()),
        Just(", ".into()),
        Just("&a ".into()),
        Just("*a".into()),
        Just("<<: *a".into()),
        Just("!!str ".into()),
        Just("!custom ".into()),
        Just("? ".into()),
        Just("| ".into()),
        Just("> ".into()),
        Just("'".into()),
        Just("\"".into()),
        Just("\\u00e9".into()),
        Just("# c".into()),
        Just("---\n".into()),
        Just("...\n".into()),
        Just("%YAML 1.2\n".into()),
        Just("~".into()),
        Just("null".into()),
        Just("true".into()),
        Just("1e-6".into()),
        Just(".inf".into()),
        Just(".nan".into()),
        Just("0x1F".into()),
        Just("99999999999999999999999".into()),
        Just("stages".into()),
        Just("uses".into()),
        Just("with".into()),
        Just("inputs".into()),
        Just("study".into()),
        Just("grid".into()),
        Just("source".into()),
        Just("scale".into()),
        Just("é".into()),
        Just("µm".into()),
        Just("日本".into()),
        Just("\u{feff}".into()),
        "[a-z_.]{1,6}",
    ]
}

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(token(), 0..40).prop_map(|parts| parts.concat())
}

/// Character edits: at `at` (modulo the length + 1) remove `remove`
/// characters and put `insert` there.
fn edits() -> impl Strategy<Value = Vec<(usize, usize, String)>> {
    prop::collection::vec(
        (
            any::<usize>(),
            prop_oneof![Just(0usize), 1usize..3, 0usize..40],
            prop_oneof![3 => token(), 1 => Just(String::new()), 1 => any::<char>().prop_map(String::from)],
        ),
        1..5,
    )
}

fn edit(text: &str, edits: &[(usize, usize, String)]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for (at, remove, insert) in edits {
        let at = at % (chars.len() + 1);
        let end = (at + remove).min(chars.len());
        chars.splice(at..end, insert.chars());
    }
    chars.into_iter().collect()
}

/// Parses `text`; an error's location must lie inside it.
fn parse(text: &str) {
    if let Err(e) = Located::parse(text)
        && let Some(at) = e.at
    {
        // YAML breaks lines at \n, \r\n and a lone \r; one more line
        // for an error at the very end.
        let lines = text
            .replace("\r\n", "\n")
            .replace('\r', "\n")
            .split('\n')
            .count()
            + 1;
        assert!(
            at.line >= 1 && at.line <= lines && at.column >= 1,
            "{at} outside a text of {lines} lines: {}",
            e.message
        );
    }
}

/// Parses `text` as a pipeline over the test stages; an error names the
/// file.
fn pipeline(text: &str) -> Option<Pipeline> {
    match Pipeline::parse(Path::new(FILE), text, &common::registry()) {
        Ok(p) => Some(p),
        Err(e) => {
            let message = e.to_string();
            assert!(message.starts_with(FILE), "{message}");
            None
        }
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_text_never_panics(text in any::<String>()) {
        parse(&text);
        pipeline(&text);
    }

    #[test]
    fn yaml_like_text_never_panics(text in soup()) {
        parse(&text);
        pipeline(&text);
    }

    #[test]
    fn edited_pipelines_never_panic(seed in 0usize..5, edits in edits()) {
        let text = edit(seeds()[seed], &edits);
        parse(&text);
        pipeline(&text);
    }

    /// `--set` on a valid pipeline: any assignment is applied or refused
    /// with a message naming the file.
    #[test]
    fn set_assignments_never_panic(
        target in prop_oneof![
            Just("src.value".to_owned()),
            Just("src.n".to_owned()),
            Just("src.label".to_owned()),
            Just("double.factor".to_owned()),
            Just("double".to_owned()),
            Just("nope.x".to_owned()),
            "[a-z.]{0,12}",
        ],
        value in prop_oneof![soup(), any::<String>()],
    ) {
        let mut p = pipeline(common::BASIC).unwrap();
        if let Err(e) = p.set(&format!("{target}={value}")) {
            let message = e.to_string();
            prop_assert!(message.starts_with(FILE), "{}", message);
        }
    }
}

#[test]
fn the_shipped_pipelines_parse_as_yaml() {
    for text in seeds() {
        Located::parse(text).unwrap();
    }
    pipeline(common::BASIC).unwrap();
}

/// Block nesting some ten thousand levels deep (`- - - …`, 2 bytes a
/// level) overflowed the stack inside saphyr's loader, whose `load_node`
/// recurses per level (flow nesting has a recursion limit in its scanner,
/// block nesting none), and the process aborted. `Located::parse` now walks
/// the parser's events first and refuses nesting beyond its limit.
#[test]
fn deep_block_nesting_is_an_error_not_an_abort() {
    let text = "- ".repeat(100_000) + "x\n";
    let e = Located::parse(&text).unwrap_err();
    assert!(e.message.contains("nested"), "{}", e.message);
}
