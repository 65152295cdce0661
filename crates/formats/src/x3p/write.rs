//! Writes a [`Topography`] as ISO 25178-72 X3P, in the layout the reader
//! of [`super`] reads: float64 heights (data type D, metres, x fastest) in
//! `bindata/data.bin`; where a height is NaN, a valid-points member
//! `bindata/valid.bin` (one bit a point, least significant first, 1 =
//! measured); `main.xml` with the MD5 of each binary member; and
//! `md5checksum.hex` with the MD5 of `main.xml` (Record4).
//!
//! Elements and their order follow the openGPS schema (ISO5436_2.xsd) as the
//! MountainsMap export `x3p-2.x3p` lays them out. The members are stored,
//! not deflated: float64 heights hardly compress (deflate saves 4 % of
//! x3p-2's data.bin), and a stored member is written at memory speed and
//! read by every zip reader.

use std::fmt::Write as _;
use std::io::{Cursor, Write as _};

use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

use super::{FORMAT, md5_hex};
use crate::bytes::MAX_POINTS;
use crate::{FormatError, Topography};

const DATA_MEMBER: &str = "bindata/data.bin";
const VALID_MEMBER: &str = "bindata/valid.bin";
const CHECKSUM_MEMBER: &str = "md5checksum.hex";

/// X3P requires a measurement and a calibration date (Record2). Where the
/// map records no acquisition date, and always for the calibration date (no
/// format read here records one), the Unix epoch stands for "unknown", as
/// in the MountainsMap export x3p-2 (which writes it in its local time).
const UNKNOWN_DATE: &str = "1970-01-01T00:00:00Z";

/// The map as an X3P file's bytes: the heights bit for bit (NaN as a point
/// not measured), the spacing as CX/CY increments, `position_m` as their
/// offsets (left out, which means 0, when the map has none), the
/// acquisition date where the map's metadata gives one in ISO 8601.
///
/// Refuses what X3P or its reader cannot hold: an empty grid or one of more
/// than 2^28 points, a spacing that is not positive and finite, an infinite
/// height or position.
pub fn write_x3p(map: &Topography) -> Result<Vec<u8>, FormatError> {
    check(map)?;
    let (nx, ny) = map.heights_m.dim();
    let n = nx * ny;
    let mut data = Vec::with_capacity(8 * n);
    let mut valid = vec![0u8; n.div_ceil(8)];
    let mut missing = false;
    // x fastest: the transposed view iterates rows of constant y
    for (k, &height_m) in map.heights_m.t().iter().enumerate() {
        data.extend_from_slice(&height_m.to_le_bytes());
        if height_m.is_nan() {
            missing = true;
        } else {
            valid[k / 8] |= 1 << (k % 8);
        }
    }
    let valid = missing.then_some(valid);
    let main_xml = main_xml(map, &data, valid.as_deref());
    let checksum = format!("{} *main.xml\n", md5_hex(main_xml.as_bytes()));
    let mut members: Vec<(&str, &[u8])> = vec![
        ("main.xml", main_xml.as_bytes()),
        (CHECKSUM_MEMBER, checksum.as_bytes()),
        (DATA_MEMBER, &data),
    ];
    if let Some(valid) = &valid {
        members.push((VALID_MEMBER, valid));
    }
    stored_zip(&members)
}

fn cannot(message: String) -> FormatError {
    FORMAT.unsupported(format!("cannot write {message}"))
}

/// What the map must be for the file to be valid and read back the same.
fn check(map: &Topography) -> Result<(), FormatError> {
    let (nx, ny) = map.heights_m.dim();
    if nx == 0 || ny == 0 || nx.saturating_mul(ny) > MAX_POINTS {
        return Err(cannot(format!(
            "a {nx} × {ny} map: X3P maps here have 1 to {MAX_POINTS} points"
        )));
    }
    for (name, spacing_m) in [("dx_m", map.dx_m), ("dy_m", map.dy_m)] {
        if !(spacing_m.is_finite() && spacing_m > 0.0) {
            return Err(cannot(format!(
                "{name} = {spacing_m}: the grid spacing must be positive and finite"
            )));
        }
    }
    if let Some((x_m, y_m)) = map.position_m
        && !(x_m.is_finite() && y_m.is_finite())
    {
        return Err(cannot(format!(
            "the position ({x_m}, {y_m}) m: it must be finite"
        )));
    }
    if let Some(((i, j), h)) = map.heights_m.indexed_iter().find(|(_, h)| h.is_infinite()) {
        return Err(cannot(format!(
            "the height {h} at x index {i}, y index {j}: heights are finite or NaN (not measured)"
        )));
    }
    Ok(())
}

/// `main.xml`: Record1 (axes), Record2 (date, writer, provenance), Record3
/// (grid and data links with MD5s), Record4 (the checksum member).
fn main_xml(map: &Topography, data: &[u8], valid: Option<&[u8]>) -> String {
    let (nx, ny) = map.heights_m.dim();
    let namespace = "http://www.opengps.eu/2008/ISO5436_2";
    // `{:e}` prints the shortest digits that parse back to the same f64
    let axis = |name: &str, increment_m: f64, offset_m: Option<f64>| {
        let offset = offset_m.map_or(String::new(), |v| format!("<Offset>{v:e}</Offset>"));
        format!(
            "      <{name}><AxisType>I</AxisType><DataType>L</DataType>\
             <Increment>{increment_m:e}</Increment>{offset}</{name}>"
        )
    };
    let mut xml = String::new();
    let mut line = |text: &str| {
        xml += text;
        xml.push('\n');
    };
    line(r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    line(&format!(
        r#"<p:ISO5436_2 xmlns:p="{namespace}" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:schemaLocation="{namespace} {namespace}/ISO5436_2.xsd">"#
    ));
    line("  <Record1>");
    line("    <Revision>ISO5436 - 2000</Revision>");
    line("    <FeatureType>SUR</FeatureType>");
    line("    <Axes>");
    line(&axis("CX", map.dx_m, map.position_m.map(|(x, _)| x)));
    line(&axis("CY", map.dy_m, map.position_m.map(|(_, y)| y)));
    line("      <CZ><AxisType>A</AxisType><DataType>D</DataType></CZ>");
    line("    </Axes>");
    line("  </Record1>");
    record2(map, &mut line);
    line("  <Record3>");
    line(&format!(
        "    <MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>"
    ));
    line("    <DataLink>");
    line(&format!(
        "      <PointDataLink>{DATA_MEMBER}</PointDataLink>"
    ));
    line(&format!(
        "      <MD5ChecksumPointData>{}</MD5ChecksumPointData>",
        md5_hex(data).to_uppercase()
    ));
    if let Some(valid) = valid {
        line(&format!(
            "      <ValidPointsLink>{VALID_MEMBER}</ValidPointsLink>"
        ));
        line(&format!(
            "      <MD5ChecksumValidPoints>{}</MD5ChecksumValidPoints>",
            md5_hex(valid).to_uppercase()
        ));
    }
    line("    </DataLink>");
    line("  </Record3>");
    line(&format!(
        "  <Record4><ChecksumFile>{CHECKSUM_MEMBER}</ChecksumFile></Record4>"
    ));
    line("</p:ISO5436_2>");
    xml
}

/// Record2: the acquisition date, the creator, hypercontact as the
/// instrument (a software export, as MountainsMap declares itself), and in
/// the comment the format and instrument the map came from.
fn record2(map: &Topography, line: &mut impl FnMut(&str)) {
    let meta = |key: &str| {
        map.metadata
            .iter()
            .find(|(k, v)| k == key && !v.is_empty())
            .map(|(_, v)| v.as_str())
    };
    let date = ["date_utc", "date"]
        .into_iter()
        .filter_map(meta)
        .find(|text| is_date_time(text))
        .unwrap_or(UNKNOWN_DATE);
    let mut comment = format!(
        "written by hypercontact from a map read as {}",
        map.format.name()
    );
    for key in ["instrument", "comment"] {
        if let Some(value) = meta(key) {
            let _ = write!(comment, "; {key}: {value}");
        }
    }
    line("  <Record2>");
    line(&format!("    <Date>{date}</Date>"));
    if let Some(creator) = meta("creator").or_else(|| meta("operator_name")) {
        line(&format!("    <Creator>{}</Creator>", escape(creator)));
    }
    line("    <Instrument>");
    line("      <Manufacturer>unknown</Manufacturer>");
    line("      <Model>hypercontact</Model>");
    line("      <Serial>not available</Serial>");
    line(&format!(
        "      <Version>{}</Version>",
        env!("CARGO_PKG_VERSION")
    ));
    line("    </Instrument>");
    line(&format!(
        "    <CalibrationDate>{UNKNOWN_DATE}</CalibrationDate>"
    ));
    line(
        "    <ProbingSystem><Type>Software</Type><Identification>hypercontact</Identification></ProbingSystem>",
    );
    line(&format!("    <Comment>{}</Comment>", escape(&comment)));
    line("  </Record2>");
}

/// Whether `text` is an xsd:dateTime: ISO 8601 date and time with a `T`,
/// optional fractional seconds, optional `Z` or ±hh:mm (what X3P and .sur
/// dates and the UTC stamps of MetroPro and Sensofar are; .opd's
/// month/day/year and Sensofar's ctime-style text are not).
fn is_date_time(text: &str) -> bool {
    use chrono::{DateTime, NaiveDateTime};
    DateTime::parse_from_str(text, "%Y-%m-%dT%H:%M:%S%.f%:z").is_ok()
        || NaiveDateTime::parse_from_str(
            text.strip_suffix('Z').unwrap_or(text),
            "%Y-%m-%dT%H:%M:%S%.f",
        )
        .is_ok()
}

/// Text as XML character data: markup characters escaped, and characters
/// XML 1.0 cannot hold at all (control codes from binary headers) replaced.
fn escape(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => escaped += "&lt;",
            '>' => escaped += "&gt;",
            '&' => escaped += "&amp;",
            '\t' | '\n' | '\r' => escaped.push(c),
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => escaped.push('\u{fffd}'),
            c => escaped.push(c),
        }
    }
    escaped
}

/// A zip of stored members with fixed times, so the same map always gives
/// the same bytes.
pub(super) fn stored_zip(members: &[(&str, &[u8])]) -> Result<Vec<u8>, FormatError> {
    let failed = |e: &dyn std::fmt::Display| cannot(format!("the zip archive: {e}"));
    let options = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Stored)
        .last_modified_time(zip::DateTime::default())
        .unix_permissions(0o644);
    let mut writer = ZipWriter::new(Cursor::new(Vec::new()));
    for (name, content) in members {
        writer.start_file(*name, options).map_err(|e| failed(&e))?;
        writer.write_all(content).map_err(|e| failed(&e))?;
    }
    let archive = writer.finish().map_err(|e| failed(&e))?;
    Ok(archive.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_taken_only_in_iso_8601() {
        assert!(is_date_time("2024-05-01T10:00:00"));
        assert!(is_date_time("2011-07-23T16:49:36Z"));
        assert!(is_date_time("2011-07-23T16:49:36.25+02:00"));
        assert!(!is_date_time("Fri Mar 10 16:35:59 2023"));
        assert!(!is_date_time("7/7/2015 16:19:48"));
        assert!(!is_date_time("2024-05-01 10:00:00"));
        assert!(!is_date_time("2024-05-01"));
    }

    #[test]
    fn text_is_escaped_for_xml() {
        assert_eq!(escape("a<b & c>d"), "a&lt;b &amp; c&gt;d");
        assert_eq!(escape("µm\tok\u{1}"), "µm\tok\u{fffd}");
        let xml = format!("<a>{}</a>", escape("x\u{0}<&\u{1f}\u{ffff}y"));
        assert!(roxmltree::Document::parse(&xml).is_ok(), "{xml}");
    }
}
