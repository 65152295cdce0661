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
}
