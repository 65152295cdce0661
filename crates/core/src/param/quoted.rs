//! A number written in quotes (`levels: "10"`): YAML types `"10"` as text,
//! so a numeric parameter refuses it rather than guessing, and the message
//! says how to write it. `--set levels=10` is read as YAML too, so it
//! arrives as the number 10 and is unaffected.

/// The advice for `text` given where a number belongs, when `text` reads as
/// one (`write 10, not "10"`); `None` for text that is no number.
pub fn quoted_number_advice(text: &str) -> Option<String> {
    let trimmed = text.trim();
    if trimmed.is_empty() || trimmed.parse::<f64>().is_err() {
        return None;
    }
    Some(format!(
        "a number is written without quotes: write {trimmed}, not \"{text}\""
    ))
}

/// Serde's `invalid type: string "10", expected f64` with the advice of
/// [`quoted_number_advice`] added when the string reads as a number and a
/// number was expected; any other message unchanged.
pub fn explain_quoted_number(message: &str) -> String {
    let Some(rest) = message.strip_prefix("invalid type: string \"") else {
        return message.to_owned();
    };
    let Some((text, expected)) = rest.rsplit_once("\", expected ") else {
        return message.to_owned();
    };
    if !expects_a_number(expected) {
        return message.to_owned();
    }
    match quoted_number_advice(text) {
        Some(advice) => format!("{message}; {advice}"),
        None => message.to_owned(),
    }
}

/// Whether serde's `expected …` names a number type.
fn expects_a_number(expected: &str) -> bool {
    let numeric = [
        "f32", "f64", "u8", "u16", "u32", "u64", "usize", "i8", "i16", "i32", "i64", "isize",
    ];
    numeric.contains(&expected) || expected.contains("number") || expected.contains("integer")
}
