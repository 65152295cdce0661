//! ISO 25178-72 X3P (formerly ISO 5436-2), the open exchange format of
//! surface metrology: a zip holding `main.xml` (axes, grid size, instrument)
//! and the heights as a little-endian binary member, or inline in the XML.
//!
//! Layout facts from the openGPS reference implementation and its XML schema
//! (<https://sourceforge.net/p/open-gps>): data types I/L/F/D are int16,
//! int32, float32 and float64; points are stored x fastest; an axis value is
//! `Offset + Increment × raw`; the optional valid-points member holds one bit
//! per point, least-significant bit first, 1 = measured. SurfaceTopography
//! (`IO/X3P.py`) reads I and L as unsigned; openGPS, whose types are
//! `short`/`int`, is followed here.
//!
//! `position_m` is the offset of the CX and CY axes (the coordinates of the
//! first point, e.g. the stage position of a tile), when the file gives one.

use std::io::{Cursor, Read};

use md5::{Digest, Md5};
use roxmltree::{Document, Node, ParsingOptions};
use zip::ZipArchive;

use crate::bytes::{ByteOrder, Bytes, Stored, grid_points, x_major};
use crate::{Format, FormatError, Topography};

mod write;
pub use write::write_x3p;

const FORMAT: Format = Format::X3p;

/// The local-file-header signature every zip starts with. X3P is the only
/// zip-based format read here, so any zip is handed to this reader (which
/// then says so if `main.xml` is missing).
const ZIP_MAGIC: &[u8] = b"PK\x03\x04";

/// Largest `main.xml` read (an inline `DataList` is the only reason for a
/// large one; it is meant for small maps, and about 16 bytes a point).
const MAX_XML_BYTES: usize = 32 << 20;

/// Most XML nodes parsed from `main.xml` (two per inline point: the Datum
/// element and its text), which bounds the tree's memory too.
const MAX_XML_NODES: u32 = 1 << 22;

/// Whether the first bytes are this format's magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(ZIP_MAGIC)
}

/// Reads the file's bytes.
pub(crate) fn read(bytes: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let mut archive = ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| FORMAT.invalid(format!("not a readable zip archive: {e}")))?;
    let main_xml = read_member(&mut archive, "main.xml", MAX_XML_BYTES)?
        .ok_or_else(|| FORMAT.invalid("the zip holds no main.xml (not an X3P file)"))?;
    let text = std::str::from_utf8(&main_xml)
        .map_err(|e| FORMAT.invalid(format!("main.xml is not UTF-8 text: {e}")))?;
    let options = ParsingOptions {
        nodes_limit: MAX_XML_NODES,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(text, options)
        .map_err(|e| FORMAT.invalid(format!("main.xml is not well-formed XML: {e}")))?;
    let root = doc.root_element();
    if root.tag_name().name() != "ISO5436_2" {
        return Err(FORMAT.invalid(format!(
            "main.xml: expected the root element ISO5436_2, found {} at {}",
            root.tag_name().name(),
            at(root)
        )));
    }

    let mut metadata = Vec::new();
    let main_checksum = verify_main_xml(&mut archive, root, &main_xml)?;
    metadata.push(("md5_main_xml".to_string(), main_checksum.to_string()));

    let header = Header::parse(root, &mut metadata)?;
    let record3 = child(root, "Record3", "Record3")?;
    let (nx, ny) = matrix_size(record3, max_points)?;
    let n = nx * ny;
    let raw = if let Some(link) = first_child(record3, "DataLink") {
        read_linked(&mut archive, link, &header, n, &mut metadata)?
    } else if let Some(list) = first_child(record3, "DataList") {
        read_listed(list, n)?
    } else {
        return Err(FORMAT.invalid(format!(
            "main.xml: Record3 at {} has neither a DataLink nor a DataList",
            at(record3)
        )));
    };
    // stored x fastest: rows of constant y; axis 0 of the result is x
    let heights_m = x_major(nx, ny, &raw, |r| header.z.value(r));
    Ok(Topography {
        heights_m,
        dx_m: header.x.increment,
        dy_m: header.y.increment,
        format: Format::X3p,
        position_m: header.position_m,
        metadata,
    })
}

/// The archive member `name`, at most `limit` bytes, or None if it is absent.
/// Reads no more than `limit + 1` bytes whatever the zip declares, so a
/// member that inflates without end cannot exhaust memory.
fn read_member(
    archive: &mut ZipArchive<Cursor<&[u8]>>,
    name: &str,
    limit: usize,
) -> Result<Option<Vec<u8>>, FormatError> {
    // some writers use Windows separators in the links
    let Some(index) = archive
        .index_for_name(name)
        .or_else(|| archive.index_for_name(&name.replace('\\', "/")))
    else {
        return Ok(None);
    };
    let member = archive
        .by_index(index)
        .map_err(|e| FORMAT.invalid(format!("zip member {name}: {e}")))?;
    let mut content = Vec::new();
    member
        .take(limit as u64 + 1)
        .read_to_end(&mut content)
        .map_err(|e| FORMAT.invalid(format!("zip member {name} cannot be inflated: {e}")))?;
    if content.len() > limit {
        return Err(FORMAT.invalid(format!(
            "zip member {name} is larger than the {limit} bytes expected"
        )));
    }
    Ok(Some(content))
}

/// `Record4/ChecksumFile` names a member holding the MD5 of main.xml
/// (`<hex> *main.xml`); checks it when the file gives one.
fn verify_main_xml(
    archive: &mut ZipArchive<Cursor<&[u8]>>,
    root: Node,
    main_xml: &[u8],
) -> Result<&'static str, FormatError> {
    let Some(name) = first_child(root, "Record4").and_then(|r| text_of(r, "ChecksumFile")) else {
        return Ok("not given");
    };
    let content = read_member(archive, &name, 4096)?.ok_or_else(|| {
        FORMAT.invalid(format!(
            "Record4/ChecksumFile names {name}, which the zip does not hold"
        ))
    })?;
    let content = String::from_utf8_lossy(&content);
    let expected = content.split_whitespace().next().unwrap_or("");
    check_md5(main_xml, expected, "main.xml", &format!("{name} (Record4)"))?;
    Ok("verified")
}

/// Compares the MD5 of `bytes` with the hex digest `expected` (any case).
fn check_md5(bytes: &[u8], expected: &str, what: &str, source: &str) -> Result<(), FormatError> {
    let actual = md5_hex(bytes);
    if actual.eq_ignore_ascii_case(expected.trim()) {
        Ok(())
    } else {
        Err(FORMAT.invalid(format!(
            "MD5 of {what} is {actual}, but {source} says {}: the file is corrupt",
            expected.trim()
        )))
    }
}

/// The MD5 digest of `bytes` as lower-case hex.
fn md5_hex(bytes: &[u8]) -> String {
    Md5::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// One axis of `Record1/Axes`: value = offset + increment × raw.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Axis {
    increment: f64,
    offset: f64,
}

impl Axis {
    fn value(self, raw: f64) -> f64 {
        // without an offset nothing is added, so a stored -0.0 stays -0.0
        // (0 + -0 would be +0; SurfaceTopography adds only a nonzero offset too)
        if self.offset == 0.0 {
            self.increment * raw
        } else {
            self.offset + self.increment * raw
        }
    }
}

/// How the Z values are stored (`Record1/Axes/CZ/DataType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DataType {
    Int16,
    Int32,
    Float32,
    Float64,
}

impl DataType {
    fn parse(code: &str, node: Node) -> Result<Self, FormatError> {
        match code {
            "I" => Ok(DataType::Int16),
            "L" => Ok(DataType::Int32),
            "F" => Ok(DataType::Float32),
            "D" => Ok(DataType::Float64),
            other => Err(FORMAT.invalid(format!(
                "Record1/Axes/CZ/DataType at {}: expected I, L, F or D, found {other:?}",
                at(node)
            ))),
        }
    }

    fn bytes(self) -> usize {
        match self {
            DataType::Int16 => 2,
            DataType::Int32 | DataType::Float32 => 4,
            DataType::Float64 => 8,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            DataType::Int16 => "I (int16)",
            DataType::Int32 => "L (int32)",
            DataType::Float32 => "F (float32)",
            DataType::Float64 => "D (float64)",
        }
    }

    /// The `n` little-endian values of this type in member `name`.
    fn decode(self, member: &[u8], n: usize, name: &str) -> Result<Vec<f64>, FormatError> {
        fn widen<T: Stored + Into<f64>>(values: Vec<T>) -> Vec<f64> {
            values.into_iter().map(Into::into).collect()
        }
        let member = Bytes::new(member, FORMAT.name(), ByteOrder::Little);
        Ok(match self {
            DataType::Int16 => widen(member.values::<i16>(0, n, name)?),
            DataType::Int32 => widen(member.values::<i32>(0, n, name)?),
            DataType::Float32 => widen(member.values::<f32>(0, n, name)?),
            DataType::Float64 => member.values::<f64>(0, n, name)?,
        })
    }
}

/// What `Record1` says about the grid and the heights.
struct Header {
    x: Axis,
    y: Axis,
    z: Axis,
    z_type: DataType,
    position_m: Option<(f64, f64)>,
}

impl Header {
    /// Record1 (axes) and, into `metadata`, Record2 (instrument, dates).
    fn parse(root: Node, metadata: &mut Vec<(String, String)>) -> Result<Self, FormatError> {
        let record1 = child(root, "Record1", "Record1")?;
        if let Some(revision) = text_of(record1, "Revision") {
            metadata.push(("revision".into(), revision));
        }
        let feature = child(record1, "FeatureType", "Record1/FeatureType")?;
        match feature.text().map(str::trim) {
            Some("SUR") => {}
            Some("PRF") => {
                return Err(FORMAT.unsupported("FeatureType PRF: a profile, not a surface"));
            }
            Some("PCL") => {
                return Err(FORMAT.unsupported("FeatureType PCL: a point cloud, not a grid"));
            }
            other => {
                return Err(FORMAT.invalid(format!(
                    "Record1/FeatureType at {}: expected SUR, found {other:?}",
                    at(feature)
                )));
            }
        }
        let axes = child(record1, "Axes", "Record1/Axes")?;
        let cx = child(axes, "CX", "Record1/Axes/CX")?;
        let cy = child(axes, "CY", "Record1/Axes/CY")?;
        let cz = child(axes, "CZ", "Record1/Axes/CZ")?;
        let x = lateral_axis(cx, "CX")?;
        let y = lateral_axis(cy, "CY")?;
        let z_kind = child(cz, "AxisType", "Record1/Axes/CZ/AxisType")?;
        if z_kind.text().map(str::trim) != Some("A") {
            return Err(FORMAT.invalid(format!(
                "Record1/Axes/CZ/AxisType at {}: expected A (absolute heights), found {:?}",
                at(z_kind),
                z_kind.text().unwrap_or("")
            )));
        }
        let z_type_node = child(cz, "DataType", "Record1/Axes/CZ/DataType")?;
        let z_type = DataType::parse(z_type_node.text().unwrap_or("").trim(), z_type_node)?;
        let z = Axis {
            increment: number_or(cz, "Increment", "CZ", 1.0)?,
            offset: number_or(cz, "Offset", "CZ", 0.0)?,
        };
        if !(z.increment.is_finite() && z.offset.is_finite()) {
            return Err(FORMAT.invalid(format!(
                "Record1/Axes/CZ at {}: Increment {} and Offset {} must be finite",
                at(cz),
                z.increment,
                z.offset
            )));
        }
        metadata.push(("z_data_type".into(), z_type.describe().into()));
        if let Some(rotation) = first_child(axes, "Rotation") {
            let entries: Vec<String> = rotation
                .children()
                .filter(Node::is_element)
                .map(|e| format!("{}={}", e.tag_name().name(), e.text().unwrap_or("").trim()))
                .collect();
            metadata.push(("rotation".into(), entries.join(" ")));
        }
        let has_offset = first_child(cx, "Offset").is_some() || first_child(cy, "Offset").is_some();
        let position_m = has_offset.then_some((x.offset, y.offset));
        if let Some(record2) = first_child(root, "Record2") {
            instrument_metadata(record2, metadata);
        }
        Ok(Header {
            x,
            y,
            z,
            z_type,
            position_m,
        })
    }
}

/// CX or CY: an incremental axis with a positive spacing.
fn lateral_axis(node: Node, name: &str) -> Result<Axis, FormatError> {
    let path = format!("Record1/Axes/{name}");
    let kind = child(node, "AxisType", &format!("{path}/AxisType"))?;
    match kind.text().map(str::trim) {
        Some("I") => {}
        Some("A") => {
            return Err(FORMAT.unsupported(format!(
                "{path}/AxisType A: explicit coordinates per point, not a regular grid"
            )));
        }
        other => {
            return Err(FORMAT.invalid(format!(
                "{path}/AxisType at {}: expected I (incremental), found {other:?}",
                at(kind)
            )));
        }
    }
    let increment_node = child(node, "Increment", &format!("{path}/Increment"))?;
    let increment = number(increment_node, &format!("{path}/Increment"))?;
    if !(increment.is_finite() && increment > 0.0) {
        return Err(FORMAT.invalid(format!(
            "{path}/Increment at {}: expected a positive grid spacing in metres, found {increment}",
            at(increment_node)
        )));
    }
    let offset = number_or(node, "Offset", name, 0.0)?;
    if !offset.is_finite() {
        return Err(FORMAT.invalid(format!(
            "{path}/Offset at {}: expected a finite position in metres, found {offset}",
            at(node)
        )));
    }
    Ok(Axis { increment, offset })
}

/// Record2: date, creator, instrument, calibration, probing system, comment.
fn instrument_metadata(record2: Node, metadata: &mut Vec<(String, String)>) {
    let mut put = |key: &str, value: Option<String>| {
        if let Some(value) = value.filter(|v| !v.is_empty()) {
            metadata.push((key.to_string(), value));
        }
    };
    put("date", text_of(record2, "Date"));
    put("creator", text_of(record2, "Creator"));
    if let Some(instrument) = first_child(record2, "Instrument") {
        let manufacturer = text_of(instrument, "Manufacturer");
        let model = text_of(instrument, "Model");
        let version = text_of(instrument, "Version");
        // one readable name, skipping the placeholders writers use
        let known = |v: &Option<String>| {
            v.clone()
                .filter(|v| !v.is_empty() && v != "unknown" && v != "not available")
        };
        let mut name: Vec<String> = [known(&manufacturer), known(&model)]
            .into_iter()
            .flatten()
            .collect();
        if let Some(version) = known(&version) {
            name.push(format!("version {version}"));
        }
        put("instrument", (!name.is_empty()).then(|| name.join(" ")));
        put("instrument_manufacturer", manufacturer);
        put("instrument_model", model);
        put("instrument_serial", text_of(instrument, "Serial"));
        put("instrument_version", version);
    }
    put("calibration_date", text_of(record2, "CalibrationDate"));
    if let Some(probe) = first_child(record2, "ProbingSystem") {
        put("probing_system_type", text_of(probe, "Type"));
        put(
            "probing_system_identification",
            text_of(probe, "Identification"),
        );
    }
    put("comment", text_of(record2, "Comment"));
}

/// `Record3/MatrixDimension`: SizeX × SizeY points, one layer, at most
/// `max_points`.
fn matrix_size(record3: Node, max_points: usize) -> Result<(usize, usize), FormatError> {
    let Some(matrix) = first_child(record3, "MatrixDimension") else {
        if first_child(record3, "ListDimension").is_some() {
            return Err(FORMAT.unsupported("Record3/ListDimension: a list of points, not a matrix"));
        }
        return Err(FORMAT.invalid(format!(
            "Record3 at {}: expected a MatrixDimension",
            at(record3)
        )));
    };
    let size = |name: &str| -> Result<usize, FormatError> {
        let path = format!("Record3/MatrixDimension/{name}");
        let node = child(matrix, name, &path)?;
        let text = node.text().unwrap_or("").trim();
        text.parse::<usize>()
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| {
                FORMAT.invalid(format!(
                    "{path} at {}: expected a positive integer, found {text:?}",
                    at(node)
                ))
            })
    };
    let (nx, ny, nz) = (size("SizeX")?, size("SizeY")?, size("SizeZ")?);
    if nz != 1 {
        return Err(FORMAT.unsupported(format!(
            "Record3/MatrixDimension/SizeZ = {nz}: several layers per point"
        )));
    }
    grid_points(FORMAT.name(), nx, ny, "Record3/MatrixDimension", max_points)?;
    Ok((nx, ny))
}

/// The raw values of a `DataLink`ed binary member, NaN where the
/// valid-points member says a point was not measured; checks the MD5 sums
/// the file gives.
fn read_linked(
    archive: &mut ZipArchive<Cursor<&[u8]>>,
    link: Node,
    header: &Header,
    n: usize,
    metadata: &mut Vec<(String, String)>,
) -> Result<Vec<f64>, FormatError> {
    let name = text_of(link, "PointDataLink").ok_or_else(|| {
        FORMAT.invalid(format!(
            "Record3/DataLink/PointDataLink at {}: expected the name of the binary member",
            at(link)
        ))
    })?;
    let expected_bytes = n * header.z_type.bytes();
    let data = read_member(archive, &name, expected_bytes)?.ok_or_else(|| {
        FORMAT.invalid(format!(
            "Record3/DataLink/PointDataLink names {name}, which the zip does not hold"
        ))
    })?;
    if data.len() != expected_bytes {
        return Err(FORMAT.invalid(format!(
            "{name} holds {} bytes, but {n} points of {} take {expected_bytes}",
            data.len(),
            header.z_type.describe()
        )));
    }
    let checksum = match text_of(link, "MD5ChecksumPointData") {
        Some(expected) => {
            check_md5(
                &data,
                &expected,
                &name,
                "Record3/DataLink/MD5ChecksumPointData",
            )?;
            "verified"
        }
        None => "not given",
    };
    metadata.push(("md5_point_data".into(), checksum.into()));
    let mut raw = header.z_type.decode(&data, n, &name)?;
    drop(data);

    if let Some(valid_name) = text_of(link, "ValidPointsLink") {
        let mask_bytes = n.div_ceil(8);
        // a little slack: some writers pad the bit array
        let mask = read_member(archive, &valid_name, mask_bytes + 64)?.ok_or_else(|| {
            FORMAT.invalid(format!(
                "Record3/DataLink/ValidPointsLink names {valid_name}, which the zip does not hold"
            ))
        })?;
        if mask.len() < mask_bytes {
            return Err(FORMAT.invalid(format!(
                "{valid_name} holds {} bytes, but one bit for each of {n} points takes {mask_bytes}",
                mask.len()
            )));
        }
        if let Some(expected) = text_of(link, "MD5ChecksumValidPoints") {
            check_md5(
                &mask,
                &expected,
                &valid_name,
                "Record3/DataLink/MD5ChecksumValidPoints",
            )?;
        }
        apply_valid_mask(&mut raw, &mask);
    }
    Ok(raw)
}

/// Sets the points whose bit is 0 to NaN: bit `i % 8` (least significant
/// first) of byte `i / 8` is point `i`, as openGPS's `ValidBuffer` stores it.
fn apply_valid_mask(raw: &mut [f64], mask: &[u8]) {
    for (i, value) in raw.iter_mut().enumerate() {
        let measured = mask
            .get(i / 8)
            .is_some_and(|byte| byte & (1 << (i % 8)) != 0);
        if !measured {
            *value = f64::NAN;
        }
    }
}

/// `Record3/DataList`: one `Datum` per point in the XML (x fastest), an empty
/// one for a point not measured.
fn read_listed(list: Node, n: usize) -> Result<Vec<f64>, FormatError> {
    let mut raw = Vec::new();
    for datum in list
        .children()
        .filter(|c| c.is_element() && c.tag_name().name() == "Datum")
    {
        if raw.len() == n {
            return Err(FORMAT.invalid(format!(
                "Record3/DataList at {}: more than the {n} Datum elements of the matrix",
                at(list)
            )));
        }
        let text = datum.text().unwrap_or("").trim();
        let value = if text.is_empty() {
            f64::NAN
        } else {
            text.parse::<f64>().map_err(|_| {
                FORMAT.invalid(format!(
                    "Record3/DataList/Datum at {}: expected a number, found {text:?}",
                    at(datum)
                ))
            })?
        };
        raw.push(value);
    }
    if raw.len() != n {
        return Err(FORMAT.invalid(format!(
            "Record3/DataList at {}: {} Datum elements for a matrix of {n} points",
            at(list),
            raw.len()
        )));
    }
    Ok(raw)
}

/// Line and column of an element in main.xml, for messages.
fn at(node: Node) -> String {
    let pos = node.document().text_pos_at(node.range().start);
    format!("main.xml line {}, column {}", pos.row, pos.col)
}

/// The first child element named `name` (namespace ignored: the schema's
/// elements are unqualified, only the root carries a prefix).
fn first_child<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == name)
}

/// Like [`first_child`], an error naming `path` when it is missing.
fn child<'a, 'input>(
    node: Node<'a, 'input>,
    name: &str,
    path: &str,
) -> Result<Node<'a, 'input>, FormatError> {
    first_child(node, name).ok_or_else(|| {
        FORMAT.invalid(format!(
            "main.xml: expected the element {path} inside the element at {}",
            at(node)
        ))
    })
}

/// The trimmed text of child `name`, if it is there.
fn text_of(node: Node, name: &str) -> Option<String> {
    first_child(node, name).map(|c| c.text().unwrap_or("").trim().to_string())
}

fn number(node: Node, path: &str) -> Result<f64, FormatError> {
    let text = node.text().unwrap_or("").trim();
    text.parse::<f64>().map_err(|_| {
        FORMAT.invalid(format!(
            "{path} at {}: expected a number, found {text:?}",
            at(node)
        ))
    })
}

/// Child `name` of an axis as a number, `default` when absent.
fn number_or(axis: Node, name: &str, axis_name: &str, default: f64) -> Result<f64, FormatError> {
    match first_child(axis, name) {
        Some(node) => number(node, &format!("Record1/Axes/{axis_name}/{name}")),
        None => Ok(default),
    }
}

#[cfg(test)]
mod tests {
    use ndarray::Array2;

    use super::*;

    /// main.xml for a SizeX × SizeY map with the given CZ and data link.
    fn main_xml(cz: &str, nx: usize, ny: usize, record3_data: &str) -> String {
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
  <Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType>
    <Axes>
      <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>0.25</Increment><Offset>1</Offset></CX>
      <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>0.5</Increment><Offset>2</Offset></CY>
      <CZ>{cz}</CZ>
    </Axes>
  </Record1>
  <Record2><Date>2024-05-01T10:00:00</Date><Creator>test</Creator>
    <Instrument><Manufacturer>ACME</Manufacturer><Model>Profiler</Model><Serial>7</Serial><Version>unknown</Version></Instrument>
  </Record2>
  <Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
    {record3_data}
  </Record3>
</p:ISO5436_2>"#
        )
    }

    fn zip_of(members: &[(&str, &[u8])]) -> Vec<u8> {
        write::stored_zip(members).unwrap()
    }

    /// A 5 × 2 map of `raw` stored as `code`, with increment 0.5 and offset
    /// 100, and optionally a valid-points member.
    fn synthetic(code: &str, raw: &[u8], valid: Option<&[u8]>) -> Vec<u8> {
        synthetic_with_checksum(code, raw, &md5_hex(raw).to_uppercase(), valid)
    }

    /// Like [`synthetic`], main.xml giving `checksum` for the data member.
    fn synthetic_with_checksum(
        code: &str,
        raw: &[u8],
        checksum: &str,
        valid: Option<&[u8]>,
    ) -> Vec<u8> {
        let mut link = format!(
            "<DataLink><PointDataLink>bindata/data.bin</PointDataLink>\
             <MD5ChecksumPointData>{checksum}</MD5ChecksumPointData>"
        );
        if let Some(valid) = valid {
            link += &format!(
                "<ValidPointsLink>bindata/valid.bin</ValidPointsLink>\
                 <MD5ChecksumValidPoints>{}</MD5ChecksumValidPoints>",
                md5_hex(valid)
            );
        }
        link += "</DataLink>";
        let cz = format!(
            "<AxisType>A</AxisType><DataType>{code}</DataType><Increment>0.5</Increment><Offset>100</Offset>"
        );
        let xml = main_xml(&cz, 5, 2, &link);
        let mut members: Vec<(&str, &[u8])> =
            vec![("main.xml", xml.as_bytes()), ("bindata/data.bin", raw)];
        if let Some(valid) = valid {
            members.push(("bindata/valid.bin", valid));
        }
        zip_of(&members)
    }

    /// The expected map: point i (x fastest) = 100 + 0.5 × values[i].
    fn expected(values: &[f64]) -> Array2<f64> {
        Array2::from_shape_fn((5, 2), |(ix, iy)| 100.0 + 0.5 * values[iy * 5 + ix])
    }

    fn assert_same(actual: &Array2<f64>, expected: &Array2<f64>) {
        assert_eq!(actual.dim(), expected.dim());
        for (a, e) in actual.iter().zip(expected) {
            assert!(
                a == e || (a.is_nan() && e.is_nan()),
                "{actual:?} != {expected:?}"
            );
        }
    }

    #[test]
    fn each_data_type_is_scaled_by_the_z_increment_and_offset() {
        let values: Vec<f64> = (-10..0).map(f64::from).collect();
        let int16: Vec<u8> = (-10i16..0).flat_map(i16::to_le_bytes).collect();
        let int32: Vec<u8> = (-10i32..0).flat_map(i32::to_le_bytes).collect();
        let float32: Vec<u8> = values
            .iter()
            .flat_map(|&v| (v as f32).to_le_bytes())
            .collect();
        let float64: Vec<u8> = values.iter().flat_map(|&v| v.to_le_bytes()).collect();
        for (code, raw) in [("I", int16), ("L", int32), ("F", float32), ("D", float64)] {
            let map = read(&synthetic(code, &raw, None), crate::DEFAULT_MAX_POINTS).unwrap();
            // negative raw values: I and L are signed (openGPS short/int)
            assert_same(&map.heights_m, &expected(&values));
            assert_eq!((map.dx_m, map.dy_m), (0.25, 0.5));
            assert_eq!(map.position_m, Some((1.0, 2.0)));
        }
    }

    #[test]
    fn the_valid_points_mask_is_read_least_significant_bit_first() {
        // 0x95 = 1001_0101: points 0, 2, 4, 7 measured; 0xfd = 1111_1101:
        // point 8 measured, point 9 not (the six spare bits are set)
        let values: Vec<f64> = (0..10).map(f64::from).collect();
        let raw: Vec<u8> = (0i32..10).flat_map(i32::to_le_bytes).collect();
        let map = read(
            &synthetic("L", &raw, Some(&[0x95, 0xfd])),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        let measured = [0, 2, 4, 7, 8];
        let masked: Vec<f64> = values
            .iter()
            .enumerate()
            .map(|(i, &v)| if measured.contains(&i) { v } else { f64::NAN })
            .collect();
        assert_same(&map.heights_m, &expected(&masked));
    }

    #[test]
    fn nan_in_float_data_is_a_missing_point() {
        let mut values: Vec<f64> = (0..10).map(f64::from).collect();
        values[3] = f64::NAN;
        let raw: Vec<u8> = values.iter().flat_map(|&v| v.to_le_bytes()).collect();
        let map = read(&synthetic("D", &raw, None), crate::DEFAULT_MAX_POINTS).unwrap();
        assert_same(&map.heights_m, &expected(&values));
        assert!(map.heights_m[[3, 0]].is_nan());
    }

    #[test]
    fn an_inline_data_list_is_read_like_the_binary() {
        let values = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0];
        let mut list = String::from("<DataList>");
        for (i, v) in values.iter().enumerate() {
            if i == 6 {
                list += "<Datum/>";
            } else {
                list += &format!("<Datum>{v}</Datum>");
            }
        }
        list += "</DataList>";
        let cz = "<AxisType>A</AxisType><DataType>D</DataType><Increment>0.5</Increment><Offset>100</Offset>";
        let xml = main_xml(cz, 5, 2, &list);
        let map = read(
            &zip_of(&[("main.xml", xml.as_bytes())]),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap();
        let mut with_gap = values.to_vec();
        with_gap[6] = f64::NAN;
        assert_same(&map.heights_m, &expected(&with_gap));
    }

    #[test]
    fn record2_becomes_metadata() {
        let raw: Vec<u8> = (0..10).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let map = read(&synthetic("D", &raw, None), crate::DEFAULT_MAX_POINTS).unwrap();
        let get = |key: &str| map.meta(key);
        assert_eq!(get("date"), Some("2024-05-01T10:00:00"));
        assert_eq!(get("instrument"), Some("ACME Profiler"));
        assert_eq!(get("instrument_serial"), Some("7"));
        assert_eq!(get("md5_point_data"), Some("verified"));
        assert_eq!(get("md5_main_xml"), Some("not given"));
    }

    #[test]
    fn a_wrong_checksum_is_refused_with_both_digests() {
        let raw: Vec<u8> = (0..10).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let mut changed = raw.clone();
        changed[0] ^= 1;
        let file = synthetic_with_checksum("D", &changed, &md5_hex(&raw), None);
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(message.contains(&md5_hex(&changed)), "{message}");
        assert!(message.contains(&md5_hex(&raw)), "{message}");
        assert!(message.contains("corrupt"), "{message}");
    }

    #[test]
    fn the_main_xml_checksum_is_checked_when_record4_names_one() {
        let cz = "<AxisType>A</AxisType><DataType>D</DataType>";
        let list = format!("<DataList>{}</DataList>", "<Datum>1</Datum>".repeat(10));
        let xml = main_xml(cz, 5, 2, &list).replace(
            "</p:ISO5436_2>",
            "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4></p:ISO5436_2>",
        );
        let good = format!("{} *main.xml\n", md5_hex(xml.as_bytes()));
        let file = zip_of(&[
            ("main.xml", xml.as_bytes()),
            ("md5checksum.hex", good.as_bytes()),
        ]);
        let map = read(&file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert!(
            map.metadata
                .contains(&("md5_main_xml".into(), "verified".into()))
        );
        let bad = format!("{} *main.xml\n", md5_hex(b"something else"));
        let file = zip_of(&[
            ("main.xml", xml.as_bytes()),
            ("md5checksum.hex", bad.as_bytes()),
        ]);
        assert!(
            read(&file, crate::DEFAULT_MAX_POINTS)
                .unwrap_err()
                .to_string()
                .contains("main.xml")
        );
    }

    #[test]
    fn sizes_beyond_the_cap_are_refused_before_reading_the_data() {
        let cz = "<AxisType>A</AxisType><DataType>D</DataType>";
        let link = "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>";
        let xml = main_xml(cz, 1_000_000_000, 1_000_000_000, link);
        let message = read(
            &zip_of(&[("main.xml", xml.as_bytes())]),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(
            message.contains(
                "1000000000 × 1000000000 = 1 000 000 000 000 000 000 points, above the limit of 67 108 864"
            ),
            "{message}"
        );
    }

    /// The issue's bomb: main.xml claims 16384² doubles (2 GiB) beside a
    /// member of deflated zeros. Refused from the header by default; with
    /// the limit raised, the member is inflated no further than promised.
    #[test]
    fn a_deflated_bomb_is_refused_before_inflating() {
        use std::io::Write;
        let cz = "<AxisType>A</AxisType><DataType>D</DataType>";
        let link = "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>";
        let xml = main_xml(cz, 16384, 16384, link);
        let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let deflated = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        zip.start_file("main.xml", deflated).unwrap();
        zip.write_all(xml.as_bytes()).unwrap();
        zip.start_file("bindata/data.bin", deflated).unwrap();
        // 64 MiB of zeros deflate to about 64 kB; the header claims 32 times more
        let zeros = vec![0u8; 1 << 20];
        for _ in 0..64 {
            zip.write_all(&zeros).unwrap();
        }
        let file = zip.finish().unwrap().into_inner();
        assert!(file.len() < 1 << 20, "{} bytes", file.len());
        let message = read(&file, crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(
                "Record3/MatrixDimension: the header claims 16384 × 16384 = 268 435 456 points, \
                 above the limit of 67 108 864 (max_points)"
            ),
            "{message}"
        );
        let message = read(&file, 1 << 28).unwrap_err().to_string();
        assert!(
            message.contains("bindata/data.bin holds 67108864 bytes"),
            "{message}"
        );
    }

    #[test]
    fn a_data_member_of_the_wrong_length_is_refused() {
        let raw: Vec<u8> = (0..9).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let message = read(&synthetic("D", &raw, None), crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(message.contains("holds 72 bytes"), "{message}");
        assert!(message.contains("take 80"), "{message}");
    }

    #[test]
    fn errors_name_the_element_and_its_line() {
        let cz = "<AxisType>A</AxisType><DataType>Q</DataType>";
        let xml = main_xml(cz, 5, 2, "<DataList/>");
        let message = read(
            &zip_of(&[("main.xml", xml.as_bytes())]),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(message.contains("Record1/Axes/CZ/DataType"), "{message}");
        assert!(message.contains("line 7"), "{message}");
        let message = read(
            &zip_of(&[("other.xml", b"<a/>")]),
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(message.contains("no main.xml"), "{message}");
    }
}
