//! YAML read once into JSON values with the position of every key, so any
//! later error about a value — a serde error with its path, a failed
//! parameter check with its parameter path, a missing file — points at its
//! line and column without parsing message text.
//!
//! Parsing is `saphyr`'s (YAML 1.2 core schema: `1e-6` is a number, quoted
//! scalars stay text; duplicate keys are an error; alias expansion has a
//! node budget). A tag saphyr does not honour (`!!binary`, `!custom`) is
//! refused naming it and its line, never read as plain text.

use std::collections::BTreeMap;
use std::fmt;

use saphyr::{LoadableYamlNode, MarkedYaml, Scalar, YamlData};

/// A 1-based line and column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// A YAML text that is not a document we can read, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct YamlError {
    pub at: Option<Location>,
    pub message: String,
}

/// A value and the location of each key (map entries) and item (list
/// entries) in it, addressed by its path of keys and indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Located {
    pub value: serde_json::Value,
    spans: BTreeMap<Vec<String>, Location>,
}

/// Nesting beyond this is refused rather than followed (a recursion guard).
const MAX_DEPTH: usize = 128;

impl Located {
    /// Parses one YAML document (an empty text is `null`).
    pub fn parse(text: &str) -> Result<Self, YamlError> {
        check_depth(text)?;
        let docs = MarkedYaml::load_from_str(text).map_err(|e| {
            let at = location(e.marker());
            let message = match (e.info(), key_at(text, at)) {
                ("duplicated key in mapping", Some(key)) => {
                    format!("duplicate key `{key}` (each key may appear once in a map)")
                }
                (info, _) => info.to_owned(),
            };
            YamlError {
                at: Some(at),
                message,
            }
        })?;
        let mut located = Located::default();
        match docs.as_slice() {
            [] => Ok(located),
            [doc] => {
                located.value = convert(doc, &mut Vec::new(), &mut located.spans)
                    .map_err(|e| name_the_tag(e, text))?;
                Ok(located)
            }
            [_, second, ..] => Err(YamlError {
                at: Some(location(&second.span.start)),
                message: "expected one YAML document, found several".into(),
            }),
        }
    }

    /// The location of `path`, or of its longest prefix that has one (a
    /// missing key is reported at the map that lacks it).
    pub fn locate<S: AsRef<str>>(&self, path: &[S]) -> Option<Location> {
        let mut key: Vec<String> = path.iter().map(|s| s.as_ref().to_owned()).collect();
        loop {
            if let Some(at) = self.spans.get(&key) {
                return Some(*at);
            }
            key.pop()?;
        }
    }

    /// The part below `path`, with locations relative to it.
    pub fn sub<S: AsRef<str>>(&self, path: &[S]) -> Located {
        let prefix: Vec<String> = path.iter().map(|s| s.as_ref().to_owned()).collect();
        let mut value = &self.value;
        for key in &prefix {
            value = match value {
                serde_json::Value::Object(map) => map.get(key).unwrap_or(&serde_json::Value::Null),
                serde_json::Value::Array(items) => key
                    .parse::<usize>()
                    .ok()
                    .and_then(|i| items.get(i))
                    .unwrap_or(&serde_json::Value::Null),
                _ => &serde_json::Value::Null,
            };
        }
        // The keys below the prefix follow it in the map's order: a range,
        // not a scan of every key (a scan per stage made loading 5 000
        // stages quadratic, #50, 4).
        let below = (
            std::ops::Bound::Excluded(prefix.clone()),
            std::ops::Bound::Unbounded,
        );
        let spans = self
            .spans
            .range(below)
            .take_while(|(k, _)| k.starts_with(&prefix))
            .map(|(k, at)| (k[prefix.len()..].to_vec(), *at))
            .collect();
        Located {
            value: value.clone(),
            spans,
        }
    }
}

/// saphyr's loader recurses once per nesting level, so block nesting some
/// ten thousand levels deep (`- - - …`) overflows the stack; its event
/// parser does not. The events are walked first and what `convert` would
/// refuse is refused before loading.
fn check_depth(text: &str) -> Result<(), YamlError> {
    use saphyr_parser::{Event, Parser};
    let mut depth = 0usize;
    for event in Parser::new_from_str(text) {
        match event {
            Ok((Event::SequenceStart(..) | Event::MappingStart(..), span)) => {
                depth += 1;
                if depth > MAX_DEPTH + 1 {
                    return Err(YamlError {
                        at: Some(location(&span.start)),
                        message: format!("nested more than {MAX_DEPTH} levels deep"),
                    });
                }
            }
            Ok((Event::SequenceEnd | Event::MappingEnd, _)) => depth = depth.saturating_sub(1),
            Ok(_) => {}
            // The loader reports a syntax error with its own message.
            Err(_) => break,
        }
    }
    Ok(())
}

fn location(marker: &saphyr::Marker) -> Location {
    Location {
        line: marker.line(),
        column: marker.col() + 1,
    }
}

fn convert(
    node: &MarkedYaml,
    path: &mut Vec<String>,
    spans: &mut BTreeMap<Vec<String>, Location>,
) -> Result<serde_json::Value, YamlError> {
    use serde_json::Value;
    let at = location(&node.span.start);
    let fail = |message: String| YamlError {
        at: Some(at),
        message,
    };
    if path.len() > MAX_DEPTH {
        return Err(fail(format!("nested more than {MAX_DEPTH} levels deep")));
    }
    Ok(match &node.data {
        YamlData::Value(scalar) => {
            scalar_value(scalar).map_err(|message| fail(format!("{}{message}", where_(path))))?
        }
        YamlData::Sequence(items) => {
            let mut out = Vec::with_capacity(items.len());
            for (i, item) in items.iter().enumerate() {
                path.push(i.to_string());
                spans.insert(path.clone(), location(&item.span.start));
                out.push(convert(item, path, spans)?);
                path.pop();
            }
            Value::Array(out)
        }
        YamlData::Mapping(entries) => {
            let mut out = serde_json::Map::new();
            for (key, value) in entries {
                let name = match &key.data {
                    YamlData::Value(Scalar::String(s)) => s.to_string(),
                    YamlData::Value(Scalar::Integer(i)) => i.to_string(),
                    YamlData::Value(Scalar::Boolean(b)) => b.to_string(),
                    YamlData::Value(Scalar::FloatingPoint(f)) => f.to_string(),
                    _ => {
                        return Err(YamlError {
                            at: Some(location(&key.span.start)),
                            message: "a key must be plain text".into(),
                        });
                    }
                };
                path.push(name.clone());
                spans.insert(path.clone(), location(&key.span.start));
                let value = convert(value, path, spans)?;
                path.pop();
                out.insert(name, value);
            }
            Value::Object(out)
        }
        YamlData::Tagged(tag, _) => {
            return Err(fail(format!(
                "YAML tags (`!{}`) are not supported",
                tag.suffix
            )));
        }
        YamlData::Representation(text, _, _) => Value::String(text.to_string()),
        YamlData::Alias(_) => {
            return Err(fail("an alias that names no anchor".into()));
        }
        // saphyr's mark of a scalar whose `!!` tag it does not honour
        // (`!!binary`, `!!timestamp`) or that does not parse as its tag
        // says (`!!int abc`); `Located::parse` names the tag.
        YamlData::BadValue => {
            return Err(fail(format!("{}a value that cannot be read", where_(path))));
        }
    })
}

/// The tags saphyr honours: a value so tagged is read as that type.
const HONOURED_TAGS: &str = "!!str, !!int, !!float, !!bool and !!null";

/// `error` naming the YAML tag written where it points, if one is: a
/// tag the loader does not honour is refused, never read as plain text.
fn name_the_tag(error: YamlError, text: &str) -> YamlError {
    let tag = error.at.and_then(|at| {
        let line = text.lines().nth(at.line.checked_sub(1)?)?;
        let from: String = line.chars().skip(at.column.checked_sub(1)?).collect();
        let tag: String = from.chars().take_while(|c| !c.is_whitespace()).collect();
        tag.starts_with('!').then_some(tag)
    });
    match tag {
        Some(tag) => YamlError {
            message: format!(
                "{}: the YAML tag `{tag}` is not honoured here (only {HONOURED_TAGS} are, on a \
                 value of that type): write the value without it",
                error.message
            ),
            ..error
        },
        None => error,
    }
}

/// Names a value's place for a message: `stage \`s\`: parameter \`p.q\`: `
/// inside a stage's `with:`, else its dotted path.
fn where_(path: &[String]) -> String {
    match path {
        [] => String::new(),
        [stages, stage, with, param @ ..]
            if stages == "stages" && with == "with" && !param.is_empty() =>
        {
            format!("stage `{stage}`: parameter `{}`: ", param.join("."))
        }
        _ => format!("`{}`: ", path.join(".")),
    }
}

/// Why a number cannot be a parameter (NaN, ±inf), in the words a YAML
/// value gets; the Python bridge says the same of a float argument.
pub fn not_finite(value: f64) -> String {
    format!("`{value}` is not a finite number")
}

fn scalar_value(scalar: &Scalar) -> Result<serde_json::Value, String> {
    use serde_json::Value;
    Ok(match scalar {
        Scalar::Null => Value::Null,
        Scalar::Boolean(b) => Value::Bool(*b),
        Scalar::Integer(i) => Value::from(*i),
        Scalar::FloatingPoint(f) => {
            let f = f.into_inner();
            serde_json::Number::from_f64(f)
                .map(Value::Number)
                .ok_or_else(|| not_finite(f))?
        }
        Scalar::String(s) => Value::String(s.to_string()),
    })
}

/// The plain key that starts at `at` (1-based line and column, in
/// characters), as a reader would name it in a message.
fn key_at(text: &str, at: Location) -> Option<String> {
    let line = text.lines().nth(at.line.checked_sub(1)?)?;
    let key: String = line
        .chars()
        .skip(at.column.saturating_sub(1))
        .take_while(|&c| !matches!(c, ':' | ',' | '{' | '}'))
        .collect();
    let key = key.trim().trim_matches(|c| c == '"' || c == '\'');
    (!key.is_empty() && key.chars().count() <= 64).then(|| key.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn values_and_key_locations() {
        let doc = Located::parse(
            "name: x\nstages:\n  a:\n    with: { n: 5, v: 2.0e-5, s: \"5\", unit: µm }\n    list:\n      - 1\n      - two\n",
        )
        .unwrap();
        assert_eq!(
            doc.value["stages"]["a"]["with"],
            json!({"n": 5, "v": 2.0e-5, "s": "5", "unit": "µm"})
        );
        let at = |path: &[&str]| doc.locate(path).map(|l| (l.line, l.column));
        assert_eq!(at(&["stages", "a"]), Some((3, 3)));
        assert_eq!(at(&["stages", "a", "with", "v"]), Some((4, 19)));
        assert_eq!(at(&["stages", "a", "list", "1"]), Some((7, 9)));
        // A missing key falls back to the map that lacks it.
        assert_eq!(at(&["stages", "a", "with", "nope"]), Some((4, 5)));
        let with = doc.sub(&["stages", "a", "with"]);
        assert_eq!(with.value["n"], 5);
        assert_eq!(with.locate(&["s"]).map(|l| l.line), Some(4));
    }

    #[test]
    fn bad_documents_are_located() {
        let e = Located::parse("a: 1\na: 2\n").unwrap_err();
        assert_eq!(e.at.map(|l| l.line), Some(2));
        assert!(e.message.contains("duplicate"), "{}", e.message);
        let e = Located::parse("a: [1\n").unwrap_err();
        assert_eq!(e.at.map(|l| l.line), Some(2));
        let e = Located::parse("a: .inf\n").unwrap_err();
        assert!(e.message.contains("finite"), "{}", e.message);
        let e = Located::parse("a: 1\n---\nb: 2\n").unwrap_err();
        assert!(e.message.contains("one YAML document"), "{}", e.message);
        let deep = "[".repeat(200) + &"]".repeat(200);
        assert!(Located::parse(&deep).is_err());
        assert_eq!(Located::parse("").unwrap().value, json!(null));
    }
}
