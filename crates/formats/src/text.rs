//! What the text formats share (ASCII matrices, Dektak's CSV, the headers
//! of Nanoscope, Nanosurf and Molecular Imaging files): bytes as text, a
//! number as Python's `float` reads it, and the bound on lines read.

/// The text of `bytes`: UTF-8 where it is, else Latin-1 (which never fails).
pub(crate) fn decode(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(text) => std::borrow::Cow::Borrowed(text),
        Err(_) => std::borrow::Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

/// The lines of `text` as Python's universal newlines split them: at
/// `\r\n`, `\n` or a lone `\r` (Dektak ends some lines in `\r\r\n`, which
/// is a line and an empty one).
pub(crate) fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let current = rest?;
        match current.find(['\r', '\n']) {
            Some(end) => {
                let skip = if current[end..].starts_with("\r\n") {
                    2
                } else {
                    1
                };
                rest = Some(&current[end + skip..]);
                Some(&current[..end])
            }
            None => {
                rest = None;
                (!current.is_empty()).then_some(current)
            }
        }
    })
}

/// A number as Python's `float` parses it: decimal or exponent notation,
/// `nan` and `inf` in any case; `None` for anything else. Rust's parser is
/// correctly rounded, as CPython's is, so the same text gives the same bits.
pub(crate) fn number(word: &str) -> Option<f64> {
    let word = word.trim();
    // Rust would also take "infinity" and "+nan"; Python takes those too
    word.parse::<f64>().ok()
}

/// Whether `bytes` look like text: no NUL and no control bytes but tab,
/// line feed, carriage return and form feed in the first `window` bytes.
pub(crate) fn looks_like_text(bytes: &[u8], window: usize) -> bool {
    bytes
        .iter()
        .take(window)
        .all(|&b| b >= 0x20 || matches!(b, b'\t' | b'\n' | b'\r' | 0x0c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_parse_as_python_floats() {
        assert_eq!(number("3.69862e-007"), Some(3.69862e-7));
        assert_eq!(number(" -2 "), Some(-2.0));
        assert_eq!(number(".5"), Some(0.5));
        assert!(number("NaN").unwrap().is_nan());
        assert_eq!(number("-inf"), Some(f64::NEG_INFINITY));
        assert_eq!(number("1,5"), None);
        assert_eq!(number(""), None);
    }

    #[test]
    fn lines_split_as_python_splits_them() {
        let split: Vec<&str> = lines("a\r\r\nb\nc\rd\r\n").collect();
        assert_eq!(split, ["a", "", "b", "c", "d"]);
        assert_eq!(lines("").count(), 0);
        assert_eq!(lines("x").collect::<Vec<_>>(), ["x"]);
    }

    #[test]
    fn text_is_utf8_or_latin1() {
        assert_eq!(decode("µm".as_bytes()), "µm");
        assert_eq!(decode(&[0xb5, b'm']), "µm");
        assert!(looks_like_text(b"1 2\r\n3\t4\n", 100));
        assert!(!looks_like_text(b"1 2\0", 100));
        assert!(looks_like_text(b"1 2\0", 3));
    }
}
