//! What of a user's input a message may show. A message never echoes a
//! file's contents: a credentials file given as a table or a height map
//! would otherwise be printed to the terminal and into logs (issue #50,
//! item 11). The names a format defines, a CSV header's column names, are
//! shown only when they read as names; anything else is described by its
//! size, or by the format its first bytes' signature names.

/// The longest text that reads as a column name, characters.
const NAME_MAX_CHARS: usize = 64;

/// Whether `text` reads as a column name (`stretch`, `nominal_stress_pa`,
/// `force (N)`, `ε [%]`): at most [`NAME_MAX_CHARS`] characters, letters,
/// digits, spaces and the marks units are written with. A line of a
/// password file (`root:$6$...:19000::`) or of settings (`KEY=value`) does
/// not.
pub fn is_name_like(text: &str) -> bool {
    text.chars().count() <= NAME_MAX_CHARS
        && text
            .chars()
            .all(|c| c.is_alphanumeric() || " _-.+()[]/%°µ²³·'".contains(c))
}

/// The most characters of a value a message echoes (a YAML string, a
/// stage name): a 10 MB value is not printed whole into a 10 MB message.
pub const ECHO_MAX_CHARS: usize = 100;

/// The most characters of a quoted path a message echoes: Linux's
/// `PATH_MAX`, so a real path is always named whole.
pub const PATH_MAX_CHARS: usize = 4096;

/// `text` cut to [`ECHO_MAX_CHARS`] characters, with `…` where it was cut.
pub fn cut(text: &str) -> String {
    cut_to(text, ECHO_MAX_CHARS)
}

/// `text` cut to `max_chars` characters, with `…` where it was cut.
fn cut_to(text: &str, max_chars: usize) -> String {
    match text.char_indices().nth(max_chars) {
        Some((at, _)) => format!("{}…", &text[..at]),
        None => text.to_owned(),
    }
}

/// `message` with every span between backticks or double quotes (how
/// messages quote a value) cut as [`cut`] cuts it; a span that holds a `/`
/// is taken for a path, which a message must name whole, and is cut at
/// [`PATH_MAX_CHARS`] only.
pub fn cut_quoted(message: &str) -> String {
    let cut_span = |span: &str| match span.contains('/') {
        true => cut_to(span, PATH_MAX_CHARS),
        false => cut(span),
    };
    let mut out = String::with_capacity(message.len().min(PATH_MAX_CHARS));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let quote = &rest[open..open + 1];
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        match rest.find(quote) {
            Some(close) => {
                out.push_str(&cut_span(&rest[..close]));
                out.push_str(quote);
                rest = &rest[close + 1..];
            }
            None => {
                out.push_str(&cut_span(rest));
                return out;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_names_read_as_names_and_file_lines_do_not() {
        for name in ["mode", "nominal_stress_pa", "force (N)", "ε [%]", "x_m", ""] {
            assert!(is_name_like(name), "{name}");
        }
        for line in [
            "root:$6$abc:19000:0:99999:7:::",
            "API_KEY=abc123",
            "{\"token\": 1}",
            &"a".repeat(65),
        ] {
            assert!(!is_name_like(line), "{line}");
        }
    }

    #[test]
    fn long_values_are_cut_and_short_ones_kept() {
        let long = "x".repeat(10_000);
        assert_eq!(cut(&long).chars().count(), ECHO_MAX_CHARS + 1);
        assert!(cut(&long).ends_with('…'));
        assert_eq!(cut("µm"), "µm");
        let message = format!("unknown field `{long}`, expected `name` or \"{long}\"");
        let shown = cut_quoted(&message);
        assert!(shown.len() < 300, "{shown}");
        assert!(shown.ends_with("…\""), "{shown}");
        assert!(shown.contains("expected `name`"), "{shown}");
        assert_eq!(cut_quoted("no quotes"), "no quotes");
        assert_eq!(cut_quoted("open `end"), "open `end");
        let path = format!("/data/{}/t.csv", "long".repeat(50));
        assert_eq!(
            cut_quoted(&format!("cannot read `{path}`")),
            format!("cannot read `{path}`")
        );
    }
}
