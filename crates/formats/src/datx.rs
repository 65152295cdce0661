//! Zygo Mx `.datx` files: HDF5, read with the pure-Rust `hdf5-reader`.
//!
//! The layout is the one SurfaceTopography's `IO/DATX.py` (and prysm's
//! reader) take from files written by Mx: a `/MetaData` table of
//! (source, link, destination) strings leads from `Root` through
//! `Measurement` and `Surface` to the `Path` of the height dataset, stored as
//! rows of constant y. On that dataset, `Unit` names the height unit,
//! `No Data` the value of a missing point, and `X Converter`, `Y Converter`
//! and `Z Converter` (compounds of `Category`, `BaseUnit`, `Parameters`)
//! the calibration: `LateralCat` in `Pixels` with the pixel size in metres
//! as `Parameters[1]`, and `HeightCat` in the height unit. Heights kept in
//! fringes or waves are refused: Mx exports those maps to X3P or `.sur`.

use hdf5_reader::{Attribute, Datatype, Hdf5File, OpenOptions, StringSize, VarLenKind};

use crate::bytes::{ByteOrder, Bytes, MAX_POINTS, Stored, grid_points, x_major};
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::Datx;

/// The HDF5 signature, which a `.datx` file starts with.
const HDF5_MAGIC: &[u8] = b"\x89HDF\r\n\x1a\n";

/// Most `/MetaData` rows read (real files hold a few hundred).
const MAX_METADATA_ROWS: u64 = 100_000;

/// What to do when the heights are not in a length unit.
const EXPORT_ADVICE: &str = "export the measurement from Mx as X3P or .sur instead";

/// Whether the bytes start with the HDF5 signature.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(HDF5_MAGIC)
}

/// An HDF5 error, with what was being read.
fn hdf5(what: &str) -> impl FnOnce(hdf5_reader::error::Error) -> FormatError + '_ {
    move |e| FORMAT.invalid(format!("{what}: {e}"))
}

/// Metres per unit of a height or length unit name as Mx writes it
/// (`NanoMeters`…) or abbreviated (SurfaceTopography's unit table).
fn metres_per_unit(unit: &str) -> Option<f64> {
    match unit.trim() {
        "Meters" | "m" => Some(1.0),
        "MilliMeters" | "mm" => Some(1e-3),
        "MicroMeters" | "um" | "µm" | "μm" => Some(1e-6),
        "NanoMeters" | "nm" => Some(1e-9),
        "Angstroms" | "Å" => Some(1e-10),
        _ => None,
    }
}

/// Reads an HDF5 variable-length reference (`seq_len`, heap address, index).
type Resolve<'a> = dyn Fn(&[u8]) -> Result<Vec<u8>, hdf5_reader::error::Error> + 'a;

/// Decodes the values a `.datx` stores: strings (fixed or variable length),
/// numbers and arrays of numbers, each from its raw bytes.
struct Decoder<'a> {
    /// bytes of one variable-length reference
    vlen_size: usize,
    resolve: &'a Resolve<'a>,
}

impl Decoder<'_> {
    /// The byte width of one value of `dtype` as stored.
    fn size(&self, dtype: &Datatype) -> Option<usize> {
        match dtype {
            Datatype::String {
                size: StringSize::Variable,
                ..
            }
            | Datatype::VarLen { .. } => Some(self.vlen_size),
            _ => hdf5_reader::dtype_element_size(dtype).ok(),
        }
    }

    /// The text of a string value, NULs and blanks trimmed.
    fn text(&self, dtype: &Datatype, raw: &[u8]) -> Option<String> {
        let bytes = match dtype {
            Datatype::String {
                size: StringSize::Fixed(n),
                ..
            } => raw.get(..*n as usize)?.to_vec(),
            Datatype::String {
                size: StringSize::Variable,
                ..
            }
            | Datatype::VarLen {
                kind: VarLenKind::String,
                ..
            } => (self.resolve)(raw.get(..self.vlen_size)?).ok()?,
            _ => return None,
        };
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        Some(String::from_utf8_lossy(&bytes[..end]).trim().to_string())
    }

    /// The numbers of a numeric value or array of numbers.
    fn numbers(&self, dtype: &Datatype, raw: &[u8]) -> Option<Vec<f64>> {
        match dtype {
            Datatype::Array { base, .. } => {
                let size = self.size(base).filter(|&s| s > 0)?;
                let count = self.size(dtype)? / size;
                (0..count)
                    .map(|i| number(base, raw.get(i * size..(i + 1) * size)?))
                    .collect()
            }
            _ => number(dtype, raw).map(|n| vec![n]),
        }
    }

    /// The first element of a compound attribute: its fields by name.
    fn fields<'r>(
        &self,
        attribute: &'r Attribute,
    ) -> Option<Vec<(&'r str, &'r Datatype, &'r [u8])>> {
        let Datatype::Compound { size, fields } = &attribute.datatype else {
            return None;
        };
        let element = attribute.raw_data.get(..*size as usize)?;
        fields
            .iter()
            .map(|field| {
                let at = field.byte_offset as usize;
                let len = self.size(&field.datatype)?;
                Some((
                    field.name.as_str(),
                    &field.datatype,
                    element.get(at..at.checked_add(len)?)?,
                ))
            })
            .collect()
    }

    /// The first string of a string attribute (a scalar or a one-element array).
    fn attribute_text(&self, attribute: &Attribute) -> Option<String> {
        if let Some(strings) = &attribute.decoded_strings {
            return strings
                .first()
                .map(|s| s.trim_end_matches('\0').trim().to_string());
        }
        self.text(&attribute.datatype, &attribute.raw_data)
    }
}

/// One numeric value of any integer or float type and byte order.
fn number(dtype: &Datatype, raw: &[u8]) -> Option<f64> {
    fn decode<T: Stored>(raw: &[u8], order: hdf5_reader::ByteOrder) -> Option<T> {
        let order = match order {
            hdf5_reader::ByteOrder::LittleEndian => ByteOrder::Little,
            hdf5_reader::ByteOrder::BigEndian => ByteOrder::Big,
        };
        Bytes::new(raw, FORMAT.name(), order)
            .read::<T>(0, "a number")
            .ok()
    }
    let value = match *dtype {
        Datatype::FloatingPoint {
            size: 4,
            byte_order,
        } => f64::from(decode::<f32>(raw, byte_order)?),
        Datatype::FloatingPoint {
            size: 8,
            byte_order,
        } => decode::<f64>(raw, byte_order)?,
        Datatype::FixedPoint {
            size,
            signed,
            byte_order,
        } => match (size, signed) {
            (1, true) => f64::from(decode::<i8>(raw, byte_order)?),
            (1, false) => f64::from(decode::<u8>(raw, byte_order)?),
            (2, true) => f64::from(decode::<i16>(raw, byte_order)?),
            (2, false) => f64::from(decode::<u16>(raw, byte_order)?),
            (4, true) => f64::from(decode::<i32>(raw, byte_order)?),
            (4, false) => f64::from(decode::<u32>(raw, byte_order)?),
            // 64-bit counts lose precision past 2^53, as in any f64 map
            (8, true) => decode::<i64>(raw, byte_order)? as f64,
            (8, false) => decode::<u64>(raw, byte_order)? as f64,
            _ => return None,
        },
        _ => return None,
    };
    Some(value)
}

/// The path of the height dataset: `/MetaData`'s Root → Measurement →
/// Surface → Path (SurfaceTopography's DATX.py), else the first dataset in
/// `/Data/Surface` (prysm's reader); `rows` reads `/MetaData`'s table.
fn surface_path(
    file: &Hdf5File,
    rows: impl Fn(&hdf5_reader::Dataset) -> Option<Vec<[String; 3]>>,
) -> Result<String, FormatError> {
    let from_metadata = file
        .dataset("/MetaData")
        .map_err(|_| FORMAT.invalid("neither /MetaData nor /Data/Surface: not a Zygo .datx file"))
        .and_then(|metadata| {
            rows(&metadata).ok_or_else(|| {
                FORMAT.invalid(
                    "/MetaData is not a table of three strings (source, link, destination)",
                )
            })
        })
        .and_then(|rows| {
            let link = |source: &str, key: &str| {
                rows.iter()
                    .find(|[s, k, _]| s == source && k == key)
                    .map(|[_, _, d]| d.clone())
            };
            link("Root", "Measurement")
                .and_then(|measurement| link(&measurement, "Surface"))
                .and_then(|surface| link(&surface, "Path"))
                .ok_or_else(|| {
                    FORMAT.invalid(
                        "/MetaData has no Root → Measurement → Surface → Path to the heights",
                    )
                })
        });
    from_metadata.or_else(|why| {
        let first = file
            .group("/Data/Surface")
            .and_then(|surfaces| surfaces.member_names())
            .ok()
            .and_then(|(_, datasets)| datasets.into_iter().next());
        first.map(|name| format!("/Data/Surface/{name}")).ok_or(why)
    })
}

/// `/MetaData`'s rows of (source, link, destination) strings, `None`
/// where it is not such a table (or has more than MAX_METADATA_ROWS rows).
fn metadata_rows(metadata: &hdf5_reader::Dataset, vlen_size: usize) -> Option<Vec<[String; 3]>> {
    if metadata.num_elements().ok()? > MAX_METADATA_ROWS {
        return None;
    }
    let resolve = |reference: &[u8]| metadata.resolve_vlen_reference_bytes(reference, 1);
    let decoder = Decoder {
        vlen_size,
        resolve: &resolve,
    };
    let Datatype::Compound { fields, .. } = metadata.dtype() else {
        return None;
    };
    let row_len = metadata.raw_element_size().ok()?;
    let raw = metadata.read_raw_bytes().ok()?;
    if fields.len() < 3 || row_len == 0 {
        return None;
    }
    raw.chunks_exact(row_len)
        .map(|row| {
            let text = |i: usize| {
                let field: &hdf5_reader::CompoundField = &fields[i];
                let at = field.byte_offset as usize;
                decoder.text(
                    &field.datatype,
                    row.get(at..at + decoder.size(&field.datatype)?)?,
                )
            };
            Some([text(0)?, text(1)?, text(2)?])
        })
        .collect()
}

/// Reads the surface dataset as heights in metres, axis 0 = x, NaN where
/// the file has no data.
pub(crate) fn read(bytes: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let options = OpenOptions {
        chunk_cache_bytes: 0,
        // the heights are the largest read: at most max_points f64 values
        max_read_bytes: max_points.min(MAX_POINTS).saturating_mul(8),
        ..OpenOptions::default()
    };
    let file = Hdf5File::from_bytes_with_options(bytes, options)
        .map_err(hdf5("not a readable HDF5 file"))?;
    let root = file.root_group().map_err(hdf5("the root group"))?;
    let vlen_size = 4 + usize::from(root.offset_size()) + 4;

    let path = surface_path(&file, |metadata| metadata_rows(metadata, vlen_size))?;
    let surface = file.dataset(&path).map_err(|e| {
        FORMAT.invalid(format!("the height dataset {path} named in /MetaData: {e}"))
    })?;
    let resolve = |reference: &[u8]| surface.resolve_vlen_reference_bytes(reference, 1);
    let decoder = Decoder {
        vlen_size,
        resolve: &resolve,
    };
    let attribute = |name: &str| {
        surface
            .attribute(name)
            .map_err(|_| FORMAT.invalid(format!("{path} has no \"{name}\" attribute")))
    };

    let (unit, unit_m, pixel_m) = calibration(&decoder, &attribute, &path)?;
    let no_data = surface
        .attribute("No Data")
        .ok()
        .and_then(|a| number(&a.datatype, &a.raw_data));

    let heights_m = heights(&surface, &path, unit_m, no_data, max_points)?;

    let mut metadata = vec![
        ("vendor".to_string(), "Zygo".to_string()),
        ("surface".into(), path.clone()),
        ("unit".into(), unit),
    ];
    for (key, suffix) in [
        ("instrument", "System Type"),
        ("serial", "System Serial Number"),
    ] {
        if let Some(value) = find_attribute(&file, &path, suffix, vlen_size) {
            metadata.push((key.into(), value));
        }
    }
    Ok(Topography {
        heights_m,
        dx_m: pixel_m[0],
        dy_m: pixel_m[1],
        format: Format::Datx,
        // no stage position is known to be recorded in .datx
        position_m: None,
        metadata,
    })
}

/// The dataset's height unit (its name and metres per unit) and its pixel
/// sizes along x and y in metres, from `Unit` and the three converters.
fn calibration(
    decoder: &Decoder,
    attribute: &dyn Fn(&str) -> Result<Attribute, FormatError>,
    path: &str,
) -> Result<(String, f64, [f64; 2]), FormatError> {
    let unit = decoder
        .attribute_text(&attribute("Unit")?)
        .ok_or_else(|| FORMAT.invalid(format!("{path}: \"Unit\" is not a string")))?;
    let Some(unit_m) = metres_per_unit(&unit) else {
        return Err(FORMAT.unsupported(format!(
            "{path}: heights in \"{unit}\", not a length unit: {EXPORT_ADVICE}"
        )));
    };
    let z = converter(decoder, &attribute("Z Converter")?, path, "Z Converter")?;
    if z.category != "HeightCat" {
        return Err(FORMAT.unsupported(format!(
            "{path}: Z Converter category \"{}\", expected HeightCat: {EXPORT_ADVICE}",
            z.category
        )));
    }
    if metres_per_unit(&z.base_unit) != Some(unit_m) {
        return Err(FORMAT.invalid(format!(
            "{path}: the Z Converter's unit \"{}\" contradicts \"Unit\" = \"{unit}\"",
            z.base_unit
        )));
    }
    let mut pixel_m = [0.0; 2];
    for (pixel, name) in pixel_m.iter_mut().zip(["X Converter", "Y Converter"]) {
        let lateral = converter(decoder, &attribute(name)?, path, name)?;
        let metres = lateral.parameters.get(1).copied().unwrap_or(f64::NAN);
        if lateral.category != "LateralCat" || lateral.base_unit != "Pixels" {
            return Err(FORMAT.unsupported(format!(
                "{path}: {name} is {} in {}, expected LateralCat in Pixels: {EXPORT_ADVICE}",
                lateral.category, lateral.base_unit
            )));
        }
        if !(metres.is_finite() && metres > 0.0) {
            return Err(FORMAT.invalid(format!(
                "{path}: {name}'s pixel size (Parameters[1]) is {metres} m, expected a positive number"
            )));
        }
        *pixel = metres;
    }
    Ok((unit, unit_m, pixel_m))
}

/// The dataset's values (rows of constant y) as heights in metres, axis 0
/// = x, NaN where not finite or equal to `no_data`.
fn heights(
    surface: &hdf5_reader::Dataset,
    path: &str,
    unit_m: f64,
    no_data: Option<f64>,
    max_points: usize,
) -> Result<ndarray::Array2<f64>, FormatError> {
    let &[ny, nx] = surface.shape() else {
        return Err(FORMAT.invalid(format!(
            "{path} has shape {:?}, expected rows × columns",
            surface.shape()
        )));
    };
    let (nx, ny) = (
        usize::try_from(nx).unwrap_or(usize::MAX),
        usize::try_from(ny).unwrap_or(usize::MAX),
    );
    let points = grid_points(FORMAT.name(), nx, ny, path, max_points)?;
    let dtype = surface.dtype().clone();
    let size = match dtype {
        Datatype::FloatingPoint {
            size: size @ (4 | 8),
            ..
        }
        | Datatype::FixedPoint {
            size: size @ (1 | 2 | 4 | 8),
            ..
        } => usize::from(size),
        _ => {
            return Err(FORMAT.unsupported(format!(
                "{path}: heights of type {dtype:?}, expected numbers"
            )));
        }
    };
    let raw = surface.read_raw_bytes().map_err(hdf5(path))?;
    if raw.len() != points * size {
        return Err(FORMAT.invalid(format!(
            "{path}: {} bytes of heights for {nx} × {ny} values of {size} bytes",
            raw.len()
        )));
    }
    let values: Vec<f64> = raw
        .chunks_exact(size)
        .map(|value| number(&dtype, value).unwrap_or(f64::NAN))
        .collect();
    // stored as rows of constant y
    let heights_m = x_major(nx, ny, &values, |h| {
        if !h.is_finite() || Some(h) == no_data {
            f64::NAN
        } else {
            h * unit_m
        }
    });
    Ok(heights_m)
}

/// A converter attribute's category, unit and parameters.
struct Converter {
    category: String,
    base_unit: String,
    parameters: Vec<f64>,
}

/// The converter in the first element of a compound attribute: fields
/// `Category`, `BaseUnit` and `Parameters` by name, else by position
/// (first, second, last; as SurfaceTopography reads them).
fn converter(
    decoder: &Decoder,
    attribute: &Attribute,
    path: &str,
    name: &str,
) -> Result<Converter, FormatError> {
    let wrong = || {
        FORMAT.invalid(format!(
            "{path}: \"{name}\" is not a (Category, BaseUnit, Parameters) compound"
        ))
    };
    let fields = decoder.fields(attribute).ok_or_else(wrong)?;
    let field = |wanted: &str, fallback: Option<usize>| {
        fields
            .iter()
            .find(|(n, _, _)| *n == wanted)
            .or_else(|| fields.get(fallback?))
            .copied()
    };
    let (_, dtype, raw) = field("Category", Some(0)).ok_or_else(wrong)?;
    let category = decoder.text(dtype, raw).ok_or_else(wrong)?;
    let (_, dtype, raw) = field("BaseUnit", Some(1)).ok_or_else(wrong)?;
    let base_unit = decoder.text(dtype, raw).ok_or_else(wrong)?;
    let (_, dtype, raw) = field("Parameters", fields.len().checked_sub(1)).ok_or_else(wrong)?;
    let parameters = decoder.numbers(dtype, raw).ok_or_else(wrong)?;
    Ok(Converter {
        category,
        base_unit,
        parameters,
    })
}

/// The text of an attribute whose name ends in `suffix`, on the surface
/// dataset, one of its parent groups, or a group under `/Attributes`
/// (where SurfaceTopography's DATX.py looks for the instrument).
fn find_attribute(file: &Hdf5File, path: &str, suffix: &str, vlen_size: usize) -> Option<String> {
    let pick = |attributes: Vec<Attribute>, resolve: &Resolve| {
        let decoder = Decoder { vlen_size, resolve };
        attributes
            .iter()
            .filter(|a| a.name.ends_with(suffix))
            .find_map(|a| decoder.attribute_text(a))
    };
    if let Ok(surface) = file.dataset(path) {
        let resolve = |r: &[u8]| surface.resolve_vlen_reference_bytes(r, 1);
        if let Some(found) = pick(surface.attributes(), &resolve) {
            return Some(found);
        }
    }
    let mut parents: Vec<String> = Vec::new();
    let mut parent = path;
    while let Some((head, _)) = parent.rsplit_once('/') {
        if head.is_empty() {
            break;
        }
        parents.push(head.to_string());
        parent = head;
    }
    let mut groups: Vec<hdf5_reader::group::Group> =
        parents.iter().filter_map(|p| file.group(p).ok()).collect();
    // one level of groups under /Attributes, as Mx writes them
    if let Ok(attributes) = file.group("/Attributes") {
        groups.extend(attributes.groups().unwrap_or_default().into_iter().take(64));
        groups.push(attributes);
    }
    groups.iter().find_map(|group| {
        let resolve = |r: &[u8]| group.resolve_vlen_reference_bytes(r, 1);
        pick(group.attributes().ok()?, &resolve)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_units_in_mx_and_short_names() {
        assert_eq!(metres_per_unit("NanoMeters"), Some(1e-9));
        assert_eq!(metres_per_unit("MicroMeters"), Some(1e-6));
        assert_eq!(metres_per_unit("µm"), Some(1e-6));
        assert_eq!(metres_per_unit("MilliMeters"), Some(1e-3));
        assert_eq!(metres_per_unit("Meters"), Some(1.0));
        assert_eq!(metres_per_unit("Fringes"), None);
        assert_eq!(metres_per_unit("Waves"), None);
    }

    #[test]
    fn numbers_of_every_width_and_byte_order() {
        use hdf5_reader::ByteOrder::{BigEndian, LittleEndian};
        let f32_be = Datatype::FloatingPoint {
            size: 4,
            byte_order: BigEndian,
        };
        assert_eq!(number(&f32_be, &1.5f32.to_be_bytes()), Some(1.5));
        let f64_le = Datatype::FloatingPoint {
            size: 8,
            byte_order: LittleEndian,
        };
        assert_eq!(number(&f64_le, &(-2.25f64).to_le_bytes()), Some(-2.25));
        let i16_be = Datatype::FixedPoint {
            size: 2,
            signed: true,
            byte_order: BigEndian,
        };
        assert_eq!(number(&i16_be, &(-300i16).to_be_bytes()), Some(-300.0));
        let u32_le = Datatype::FixedPoint {
            size: 4,
            signed: false,
            byte_order: LittleEndian,
        };
        assert_eq!(number(&u32_le, &4_000_000_000u32.to_le_bytes()), Some(4e9));
        assert_eq!(number(&u32_le, &[1, 2]), None);
    }

    #[test]
    fn the_magic_is_hdf5s() {
        assert!(matches(b"\x89HDF\r\n\x1a\n\0\0"));
        assert!(!matches(b"\x89HDF\r\n"));
    }
}
