//! NetCDF classic files (`CDF\x01`, 64-bit offset `CDF\x02` and 64-bit
//! data `CDF\x05`) laid out as SurfaceTopography writes topographies
//! (`IO/NC.py`): dimensions `x` and `y`, a variable `heights(x, y)` (axis 0
//! = x), variables `x` and `y` whose attribute `length` is the physical
//! size along that axis, the length unit as the attribute `unit` of `x`
//! (and of `heights`, which must agree); an optional variable `mask` marks
//! missing points where non-zero. As scipy's reader does with
//! `maskandscale`, a `_FillValue` or `missing_value` of `heights` is a
//! missing point and `scale_factor` and `add_offset` are applied. A 1-D
//! `heights(x)` is a line scan (n × 1).
//!
//! The header is parsed after the NetCDF Classic Format Specification
//! (Unidata, "The NetCDF Classic Format"): big-endian, names and values
//! padded to 4 bytes, sizes 4 bytes wide except in CDF-5 (8); every count
//! is checked against the bytes left before anything is allocated.

use ndarray::Array2;

use crate::bytes::{ByteOrder, Bytes, Cursor, grid_points};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::NetCdf;

const TAG_DIMENSION: u32 = 0x0A;
const TAG_VARIABLE: u32 = 0x0B;
const TAG_ATTRIBUTE: u32 = 0x0C;

/// Whether the file starts with a classic NetCDF magic.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    matches!(bytes, [b'C', b'D', b'F', 1 | 2 | 5, ..])
}

/// An attribute's value: text or numbers.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Text(String),
    Numbers(Vec<f64>),
}

impl Value {
    fn number(&self) -> Option<f64> {
        match self {
            Value::Numbers(values) => values.first().copied(),
            Value::Text(text) => text.trim().parse().ok(),
        }
    }

    fn text(&self) -> Option<&str> {
        match self {
            Value::Text(text) => Some(text.trim_end_matches('\0').trim()),
            Value::Numbers(_) => None,
        }
    }
}

/// A variable: its dimensions (indices), attributes, type and data offset.
struct Variable {
    name: String,
    dims: Vec<usize>,
    attributes: Vec<(String, Value)>,
    kind: u32,
    begin: usize,
}

impl Variable {
    fn attribute(&self, name: &str) -> Option<&Value> {
        crate::lookup(&self.attributes, name)
    }
}

/// The header's parser: the width of sizes and offsets by version.
struct Header<'a> {
    c: Cursor<'a>,
    len: usize,
    /// CDF-5: counts and sizes are 8 bytes
    wide: bool,
    /// CDF-2 and CDF-5: offsets are 8 bytes
    wide_offsets: bool,
}

impl Header<'_> {
    /// A count or size, at most the bytes left divided by `each`.
    fn count(&mut self, what: &str, each: usize) -> Result<usize, FormatError> {
        let at = self.c.offset();
        let count = if self.wide {
            self.c.read::<u64>(what)?
        } else {
            u64::from(self.c.read::<u32>(what)?)
        };
        let left = self.len.saturating_sub(self.c.offset());
        usize::try_from(count)
            .ok()
            .filter(|&n| n.saturating_mul(each.max(1)) <= left)
            .ok_or_else(|| {
                FORMAT.invalid(format!(
                    "byte {at}: {what} {count} does not fit in the {left} bytes left"
                ))
            })
    }

    fn name(&mut self, what: &str) -> Result<String, FormatError> {
        let len = self.count(what, 1)?;
        let bytes = self.c.take(len.div_ceil(4) * 4, what)?;
        Ok(String::from_utf8_lossy(&bytes[..len]).into_owned())
    }

    /// A list's tag and element count (`ABSENT` is two zeros).
    fn list(&mut self, tag: u32, what: &str) -> Result<usize, FormatError> {
        let at = self.c.offset();
        let found = self.c.read::<u32>(what)?;
        let count = self.count(what, 4)?;
        if found != tag && !(found == 0 && count == 0) {
            return Err(FORMAT.invalid(format!(
                "byte {at}: expected the {what} tag {tag:#x}, found {found:#x}"
            )));
        }
        Ok(count)
    }

    fn attributes(&mut self) -> Result<Vec<(String, Value)>, FormatError> {
        let count = self.list(TAG_ATTRIBUTE, "attribute list")?;
        let mut attributes = Vec::new();
        for _ in 0..count {
            let name = self.name("an attribute name")?;
            let kind = self.c.read::<u32>("an attribute type")?;
            let size = type_size(kind, &name)?;
            let n = self.count("an attribute's length", size)?;
            let raw = self
                .c
                .take((n * size).div_ceil(4) * 4, "an attribute's values")?;
            let value = if kind == 2 {
                Value::Text(String::from_utf8_lossy(&raw[..n]).into_owned())
            } else {
                let bytes = Bytes::new(raw, FORMAT.name(), ByteOrder::Big);
                Value::Numbers((0..n).map(|i| value(&bytes, kind, i * size)).collect())
            };
            attributes.push((name, value));
        }
        Ok(attributes)
    }
}

/// Bytes of one value of a NetCDF type.
fn type_size(kind: u32, name: &str) -> Result<usize, FormatError> {
    match kind {
        1 | 2 | 7 => Ok(1),
        3 | 8 => Ok(2),
        4 | 5 | 9 => Ok(4),
        6 | 10 | 11 => Ok(8),
        _ => Err(FORMAT.invalid(format!("\"{name}\" has the unknown type {kind}"))),
    }
}

/// The value of type `kind` at `at` (NaN where the bytes are missing).
fn value(bytes: &Bytes, kind: u32, at: usize) -> f64 {
    let value = match kind {
        1 => bytes.read::<i8>(at, "a value").map(f64::from),
        2 | 7 => bytes.read::<u8>(at, "a value").map(f64::from),
        3 => bytes.read::<i16>(at, "a value").map(f64::from),
        8 => bytes.read::<u16>(at, "a value").map(f64::from),
        4 => bytes.read::<i32>(at, "a value").map(f64::from),
        9 => bytes.read::<u32>(at, "a value").map(f64::from),
        5 => bytes.read::<f32>(at, "a value").map(f64::from),
        10 => bytes.read::<i64>(at, "a value").map(|v| v as f64),
        11 => bytes.read::<u64>(at, "a value").map(|v| v as f64),
        _ => bytes.read::<f64>(at, "a value"),
    };
    value.unwrap_or(f64::NAN)
}

/// The dimensions of a file: name and length.
type Dimensions = Vec<(String, usize)>;

/// The dimensions and variables of the header.
fn parse(bytes: Bytes) -> Result<(Dimensions, Vec<Variable>), FormatError> {
    let version = bytes.read::<u8>(3, "the version")?;
    let mut h = Header {
        c: bytes.cursor(4),
        len: bytes.len(),
        wide: version == 5,
        wide_offsets: version != 1,
    };
    // the record count (or STREAMING): no record variable is read here
    h.c.skip(if h.wide { 8 } else { 4 });
    let mut dims = Vec::new();
    for _ in 0..h.list(TAG_DIMENSION, "dimension list")? {
        let name = h.name("a dimension name")?;
        dims.push((name, h.count("a dimension length", 0)?));
    }
    h.attributes()?;
    let mut variables = Vec::new();
    for _ in 0..h.list(TAG_VARIABLE, "variable list")? {
        let name = h.name("a variable name")?;
        let rank = h.count("a variable's rank", 4)?;
        let mut ids = Vec::with_capacity(rank);
        for _ in 0..rank {
            let id = h.count("a dimension id", 0)?;
            if id >= dims.len() {
                return Err(FORMAT.invalid(format!(
                    "variable \"{name}\" names dimension {id} of {}",
                    dims.len()
                )));
            }
            ids.push(id);
        }
        let attributes = h.attributes()?;
        let kind = h.c.read::<u32>("a variable's type")?;
        type_size(kind, &name)?;
        h.count("a variable's size", 0).ok();
        let begin = if h.wide_offsets {
            h.c.read::<u64>("a variable's offset")? as usize
        } else {
            h.c.read::<u32>("a variable's offset")? as usize
        };
        variables.push(Variable {
            name,
            dims: ids,
            attributes,
            kind,
            begin,
        });
    }
    Ok((dims, variables))
}

/// Reads `heights` as a map in metres, axis 0 = x.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let bytes = Bytes::new(data, FORMAT.name(), ByteOrder::Big);
    let (dims, variables) = parse(bytes)?;
    let variable = |name: &str| variables.iter().find(|v| v.name == name);
    let Some(heights) = variable("heights") else {
        return Err(FORMAT.unsupported("no variable \"heights\" (SurfaceTopography's layout)"));
    };
    let sizes: Vec<usize> = heights.dims.iter().map(|&d| dims[d].1).collect();
    let (nx, ny, line_scan) = match sizes[..] {
        [nx, ny] => (nx, ny, false),
        [nx] => (nx, 1, true),
        _ => {
            return Err(FORMAT.unsupported(format!(
                "\"heights\" has {} dimensions, expected 1 or 2",
                sizes.len()
            )));
        }
    };
    if sizes.contains(&0) {
        return Err(FORMAT.unsupported("\"heights\" is a record variable (unlimited dimension)"));
    }
    let points = grid_points(
        FORMAT.name(),
        nx,
        ny,
        "the dimensions of \"heights\"",
        max_points,
    )?;
    let axes: Vec<&str> = heights.dims.iter().map(|&d| dims[d].0.as_str()).collect();
    let axis = |k: usize| axes.get(k).and_then(|name| variable(name));
    let unit = axis(0)
        .and_then(|x| x.attribute("unit"))
        .or_else(|| heights.attribute("unit"))
        .and_then(Value::text)
        .ok_or_else(|| FORMAT.unsupported("neither \"x\" nor \"heights\" has a \"unit\""))?
        .to_string();
    let unit_m = metres_per(&unit)
        .ok_or_else(|| FORMAT.unsupported(format!("the unit \"{unit}\" is not a length unit")))?;
    if let Some(height_unit) = heights.attribute("unit").and_then(Value::text)
        && metres_per(height_unit) != Some(unit_m)
    {
        return Err(FORMAT.invalid(format!(
            "\"heights\" is in \"{height_unit}\" but \"x\" in \"{unit}\""
        )));
    }
    let length = |k: usize, n: usize| -> Result<f64, FormatError> {
        let size = axis(k)
            .and_then(|v| v.attribute("length"))
            .and_then(Value::number)
            .filter(|l| l.is_finite() && *l > 0.0)
            .ok_or_else(|| {
                FORMAT.unsupported(format!(
                    "the variable \"{}\" has no positive \"length\": the spacing is unknown",
                    axes.get(k).copied().unwrap_or("?")
                ))
            })?;
        Ok(size * unit_m / n as f64)
    };
    let dx_m = length(0, nx)?;
    let dy_m = if line_scan { dx_m } else { length(1, ny)? };
    let values = values(&bytes, heights, points)?;
    let mask = variable("mask")
        .filter(|m| m.dims == heights.dims)
        .map(|m| values_raw(&bytes, m, points))
        .transpose()?;
    let fill = ["_FillValue", "missing_value"]
        .iter()
        .filter_map(|name| heights.attribute(name).and_then(Value::number))
        .collect::<Vec<f64>>();
    let scale = heights.attribute("scale_factor").and_then(Value::number);
    let offset = heights.attribute("add_offset").and_then(Value::number);
    // stored with the last dimension fastest: (x, y) row-major
    let heights_m = Array2::from_shape_fn((nx, ny), |(i, j)| {
        let k = i * ny + j;
        let raw = values[k];
        let masked = mask.as_ref().is_some_and(|m| m[k] != 0.0) || fill.contains(&raw);
        if masked {
            return f64::NAN;
        }
        let scaled = match (scale, offset) {
            (None, None) => raw,
            _ => raw * scale.unwrap_or(1.0) + offset.unwrap_or(0.0),
        };
        scaled * unit_m
    });
    let mut metadata = vec![("unit".to_string(), unit)];
    if line_scan {
        metadata.push(("line_scan".into(), "true".into()));
    }
    Ok(Topography::new(FORMAT, heights_m, dx_m, dy_m, metadata))
}

/// A variable's `points` values as f64.
fn values_raw(bytes: &Bytes, variable: &Variable, points: usize) -> Result<Vec<f64>, FormatError> {
    let size = type_size(variable.kind, &variable.name)?;
    let what = format!("the values of \"{}\"", variable.name);
    let len = points
        .checked_mul(size)
        .ok_or_else(|| FORMAT.invalid(format!("{what}: {points} values overflow")))?;
    let raw = bytes.slice(variable.begin, len, &what)?;
    let raw = Bytes::new(raw, FORMAT.name(), ByteOrder::Big);
    Ok((0..points)
        .map(|k| value(&raw, variable.kind, k * size))
        .collect())
}

/// The heights' values: numbers only.
fn values(bytes: &Bytes, heights: &Variable, points: usize) -> Result<Vec<f64>, FormatError> {
    if heights.kind == 2 {
        return Err(FORMAT.invalid("\"heights\" holds characters, not numbers"));
    }
    values_raw(bytes, heights, points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(s: &str) -> Vec<u8> {
        let mut v = (s.len() as u32).to_be_bytes().to_vec();
        v.extend(s.as_bytes());
        v.resize(4 + s.len().div_ceil(4) * 4, 0);
        v
    }

    fn text_attribute(key: &str, value: &str) -> Vec<u8> {
        let mut v = name(key);
        v.extend(2u32.to_be_bytes());
        v.extend(name(value));
        v
    }

    /// A CDF-1 file: heights(x, y) of 2 × 3 doubles in µm, x of length 4 µm, y of 3 µm.
    fn file(fill: Option<f64>) -> Vec<u8> {
        let mut f = b"CDF\x01".to_vec();
        f.extend(0u32.to_be_bytes());
        f.extend(TAG_DIMENSION.to_be_bytes());
        f.extend(2u32.to_be_bytes());
        for (n, len) in [("x", 2u32), ("y", 3)] {
            f.extend(name(n));
            f.extend(len.to_be_bytes());
        }
        f.extend([0; 8]);
        f.extend(TAG_VARIABLE.to_be_bytes());
        f.extend(3u32.to_be_bytes());
        let mut begins = Vec::new();
        for (n, dims, length) in [
            ("x", vec![0u32], 4i32),
            ("y", vec![1], 3),
            ("heights", vec![0, 1], 0),
        ] {
            f.extend(name(n));
            f.extend((dims.len() as u32).to_be_bytes());
            for d in &dims {
                f.extend(d.to_be_bytes());
            }
            f.extend(TAG_ATTRIBUTE.to_be_bytes());
            let mut attributes = vec![text_attribute("unit", "um")];
            if length > 0 {
                let mut a = name("length");
                a.extend(4u32.to_be_bytes());
                a.extend(1u32.to_be_bytes());
                a.extend(length.to_be_bytes());
                attributes.push(a);
            }
            if let (Some(fill), "heights") = (fill, n) {
                let mut a = name("_FillValue");
                a.extend(6u32.to_be_bytes());
                a.extend(1u32.to_be_bytes());
                a.extend(fill.to_be_bytes());
                attributes.push(a);
            }
            f.extend((attributes.len() as u32).to_be_bytes());
            attributes.iter().for_each(|a| f.extend(a));
            f.extend(6u32.to_be_bytes());
            f.extend(0u32.to_be_bytes());
            begins.push(f.len());
            f.extend(0u32.to_be_bytes());
        }
        let begin = f.len() as u32;
        f[begins[2]..begins[2] + 4].copy_from_slice(&begin.to_be_bytes());
        for v in [1.0f64, 2.0, 3.0, 4.0, 5.0, -9.0] {
            f.extend(v.to_be_bytes());
        }
        f
    }

    #[test]
    fn heights_x_y_in_the_unit_of_x() {
        let map = read(&file(None), crate::DEFAULT_MAX_POINTS).unwrap();
        assert!(matches(&file(None)));
        assert_eq!(map.heights_m.dim(), (2, 3));
        assert_eq!(map.heights_m[[0, 2]], 3e-6);
        assert_eq!(map.heights_m[[1, 0]], 4e-6);
        assert_eq!((map.dx_m, map.dy_m), (2e-6, 1e-6));
        let map = read(&file(Some(-9.0)), crate::DEFAULT_MAX_POINTS).unwrap();
        assert!(map.heights_m[[1, 2]].is_nan());
    }

    #[test]
    fn broken_headers_are_named() {
        let f = file(None);
        let err = read(&f[..f.len() - 1], crate::DEFAULT_MAX_POINTS)
            .unwrap_err()
            .to_string();
        assert!(err.contains("the values of \"heights\""), "{err}");
        let mut f = file(None);
        f[15] = 0xff; // 255 dimensions
        let err = read(&f, crate::DEFAULT_MAX_POINTS).unwrap_err().to_string();
        assert!(err.contains("does not fit"), "{err}");
        assert!(!matches(b"CDF\x03"));
    }
}
