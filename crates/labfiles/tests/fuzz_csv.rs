//! Property tests of the CSV reader: arbitrary bytes never panic and every
//! error names the file; on tables written with comment lines, blank lines
//! and either line ending, every row keeps the line it stands on.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property;
//! `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen or move the search.

use hypercontact_core::{ColumnData, Table};
use hypercontact_fuzz::config;
use hypercontact_labfiles::csv_table::{RowPlace, read_csv_bytes_with_lines};
use proptest::prelude::*;

const NAME: &str = "data/t.csv";

/// Reads `bytes`; an error must name the file.
fn read(bytes: &[u8]) -> Option<(Table, Vec<RowPlace>)> {
    match read_csv_bytes_with_lines(bytes, NAME) {
        Ok(csv) => {
            let places = (0..csv.table.n_rows())
                .map(|r| csv.lines.place(r))
                .collect();
            Some((csv.table, places))
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.starts_with(&format!("{NAME}: ")),
                "the error does not name the file: {message}"
            );
            None
        }
    }
}

/// Bytes that are mostly CSV punctuation, so the parser's states are all
/// visited: quotes, separators, comments, line ends, a byte-order mark,
/// invalid UTF-8.
fn csvish_bytes() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(
        prop_oneof![
            Just(b",".to_vec()),
            Just(b"\"".to_vec()),
            Just(b"\"\"".to_vec()),
            Just(b"#".to_vec()),
            Just(b"\n".to_vec()),
            Just(b"\r\n".to_vec()),
            Just(b"\r".to_vec()),
            Just(b" ".to_vec()),
            Just(b"\xEF\xBB\xBF".to_vec()),
            Just(b"\xff".to_vec()),
            Just(b"1.5".to_vec()),
            Just(b"-7".to_vec()),
            Just(b"NaN".to_vec()),
            Just(b"x".to_vec()),
            prop::collection::vec(any::<u8>(), 1..4),
        ],
        0..60,
    )
    .prop_map(|parts| parts.concat())
}

/// One line of a written table, as the generator lays it out.
#[derive(Clone, Debug)]
enum Line {
    Comment(String),
    Blank,
    Row(Vec<String>),
}

/// A table written by hand: a header of `columns` names, rows of plain
/// cells (numbers or words), comment and blank lines anywhere, `\n` or
/// `\r\n` line ends, with or without a final line end.
fn written_table() -> impl Strategy<Value = (Vec<Line>, bool, bool)> {
    let cell = prop_oneof![
        (-1e6f64..1e6).prop_map(|v| v.to_string()),
        (-1000i64..1000).prop_map(|v| v.to_string()),
        "[a-zA-Z][a-zA-Z0-9_]{0,6}",
    ];
    (1usize..5).prop_flat_map(move |columns| {
        let row = prop::collection::vec(cell.clone(), columns).prop_map(Line::Row);
        let line = prop_oneof![
            3 => row,
            1 => "#[ -~]{0,20}".prop_map(Line::Comment),
            1 => Just(Line::Blank),
        ];
        (
            prop::collection::vec(line, 0..25),
            prop::collection::vec("[a-z][a-z0-9_]{0,5}", columns),
            prop::collection::vec(
                prop_oneof!["#[ -~]{0,20}".prop_map(Line::Comment), Just(Line::Blank)],
                0..3,
            ),
            any::<bool>(),
            any::<bool>(),
        )
            .prop_map(|(body, names, above, crlf, final_end)| {
                // Column names unique, so the header is valid.
                let names: Vec<String> = names
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{n}{i}"))
                    .collect();
                let mut lines = above;
                lines.push(Line::Row(names));
                lines.extend(body);
                (lines, crlf, final_end)
            })
    })
}

fn render(lines: &[Line], crlf: bool, final_end: bool) -> String {
    let end = if crlf { "\r\n" } else { "\n" };
    let mut text = lines
        .iter()
        .map(|line| match line {
            Line::Comment(c) => c.clone(),
            Line::Blank => String::new(),
            Line::Row(cells) => cells.join(","),
        })
        .collect::<Vec<_>>()
        .join(end);
    if final_end {
        text.push_str(end);
    }
    text
}

fn cell_text(column: &ColumnData, row: usize) -> String {
    match column {
        ColumnData::F64(v) => v[row].to_string(),
        ColumnData::I64(v) => v[row].to_string(),
        ColumnData::Str(v) => v[row].clone(),
    }
}

proptest! {
    #![proptest_config(config(512))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        read(&bytes);
    }

    #[test]
    fn csv_like_bytes_never_panic_and_lines_increase(bytes in csvish_bytes()) {
        if let Some((_, places)) = read(&bytes) {
            let lines: Vec<u64> = places
                .iter()
                .map(|p| match p {
                    RowPlace::Line(l) => *l,
                    RowPlace::Row(_) => panic!("a CSV row without its line"),
                })
                .collect();
            prop_assert!(lines.windows(2).all(|w| w[0] < w[1]), "{:?}", lines);
            // Every line number exists in the file.
            let total = 1 + bytes
                .iter()
                .enumerate()
                .filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')))
                .count() as u64;
            prop_assert!(lines.iter().all(|&l| l >= 1 && l <= total), "{:?} of {}", lines, total);
        }
    }

    /// Rows keep their file lines past comments, blank lines and either
    /// line end, and their cells are read as written.
    #[test]
    fn rows_are_placed_on_their_own_lines((lines, crlf, final_end) in written_table()) {
        let text = render(&lines, crlf, final_end);
        let rows: Vec<(u64, &Vec<String>)> = lines
            .iter()
            .enumerate()
            .filter_map(|(i, line)| match line {
                Line::Row(cells) => Some((i as u64 + 1, cells)),
                _ => None,
            })
            .collect();
        let result = read_csv_bytes_with_lines(text.as_bytes(), NAME);
        if rows.len() == 1 {
            let e = result.unwrap_err().to_string();
            prop_assert!(e.contains("no data rows"), "{}", e);
            return Ok(());
        }
        let csv = result.unwrap();
        prop_assert_eq!(csv.header_line, rows[0].0);
        let data = &rows[1..];
        prop_assert_eq!(csv.table.n_rows(), data.len());
        for (r, (line, cells)) in data.iter().enumerate() {
            prop_assert_eq!(csv.lines.place(r), RowPlace::Line(*line));
            for (column, written) in csv.table.columns().iter().zip(cells.iter()) {
                let read = cell_text(&column.data, r);
                // Numbers may come back in Rust's spelling of the same value.
                let same = read == *written
                    || read.parse::<f64>().ok() == written.parse::<f64>().ok()
                        && read.parse::<f64>().is_ok();
                prop_assert!(same, "line {}: `{}` read as `{}`", line, written, read);
            }
        }
    }
}
