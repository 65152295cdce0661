//! A field as VTK ImageData (`.vti`), the XML format ParaView and VisIt
//! read: one point array of float64 on a regular grid, stored raw and
//! little-endian in an appended block (the layout of VTK's "VTK File
//! Formats" document, version 1.0 with UInt64 block headers), so NaN stays
//! NaN, which VTK's ASCII reader does not promise.
//!
//! VTK orders points x fastest; a field's axis 0 is x, so point
//! `ix + nx · iy` is `values[[ix, iy]]`. The origin is 0 (a grid file holds
//! no origin): point (ix, iy) sits at (ix · dx_m, iy · dy_m, 0) metres.

use std::fmt::Write as _;

use hypercontact_core::Field;

/// The `.vti` bytes of `field`, its values named `array` (`height [m]`).
pub fn vti_bytes(field: &Field, array: &str) -> Vec<u8> {
    let (nx, ny) = field.values.dim();
    let extent = format!("0 {} 0 {} 0 0", nx.saturating_sub(1), ny.saturating_sub(1));
    let name = xml_attribute(array);
    let mut head = String::new();
    head.push_str("<?xml version=\"1.0\"?>\n");
    head.push_str(
        "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    let _ = writeln!(
        head,
        "  <ImageData WholeExtent=\"{extent}\" Origin=\"0 0 0\" Spacing=\"{:?} {:?} {:?}\">",
        field.dx_m, field.dy_m, field.dx_m
    );
    let _ = writeln!(head, "    <Piece Extent=\"{extent}\">");
    let _ = writeln!(head, "      <PointData Scalars=\"{name}\">");
    let _ = writeln!(
        head,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"1\" \
         format=\"appended\" offset=\"0\"/>"
    );
    head.push_str("      </PointData>\n      <CellData/>\n    </Piece>\n  </ImageData>\n");
    head.push_str("  <AppendedData encoding=\"raw\">\n   _");
    let mut bytes = head.into_bytes();
    let points = nx * ny;
    bytes.reserve(8 + 8 * points + 40);
    bytes.extend_from_slice(&((8 * points) as u64).to_le_bytes());
    for iy in 0..ny {
        for ix in 0..nx {
            bytes.extend_from_slice(&field.values[[ix, iy]].to_le_bytes());
        }
    }
    bytes.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
    bytes
}

/// Text for an XML attribute in double quotes.
fn xml_attribute(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// What a `.vti` file written by [`vti_bytes`] holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Vti {
    /// The point array's name (`height [m]`), as written (XML-escaped).
    pub name: String,
    pub nx: usize,
    pub ny: usize,
    pub spacing: [f64; 3],
    pub origin: [f64; 3],
    /// Point values, x fastest.
    pub values: Vec<f64>,
}

/// The value of attribute `name` of the first `<element ...>` in `text`.
fn attribute<'a>(text: &'a str, element: &str, name: &str) -> Result<&'a str, String> {
    let start = text
        .find(&format!("<{element} "))
        .ok_or_else(|| format!("no <{element}> element"))?;
    let rest = &text[start..];
    let key = format!(" {name}=\"");
    let at = rest
        .find(&key)
        .ok_or_else(|| format!("<{element}> has no {name}"))?
        + key.len();
    let end = rest[at..]
        .find('"')
        .ok_or_else(|| format!("<{element}>: {name} is not closed"))?;
    Ok(&rest[at..at + end])
}

fn numbers<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let parsed: Vec<f64> = text
        .split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| format!("`{t}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    parsed
        .try_into()
        .map_err(|_| format!("`{text}` is not {N} numbers"))
}

/// Reads back a `.vti` of the layout [`vti_bytes`] writes (one Float64
/// point array, raw appended, UInt64 header), by a parser of its own: the
/// export's round-trip tests hold the written file against the field.
pub fn parse_vti(bytes: &[u8]) -> Result<Vti, String> {
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or("no raw <AppendedData>")?;
    let head = std::str::from_utf8(&bytes[..at]).map_err(|e| e.to_string())?;
    for (element, key, wanted) in [
        ("VTKFile", "type", "ImageData"),
        ("VTKFile", "byte_order", "LittleEndian"),
        ("VTKFile", "header_type", "UInt64"),
        ("DataArray", "type", "Float64"),
        ("DataArray", "format", "appended"),
        ("DataArray", "offset", "0"),
    ] {
        let got = attribute(head, element, key)?;
        if got != wanted {
            return Err(format!("<{element}> {key} is `{got}`, not `{wanted}`"));
        }
    }
    let whole = numbers::<6>(attribute(head, "ImageData", "WholeExtent")?)?;
    if whole != numbers::<6>(attribute(head, "Piece", "Extent")?)? {
        return Err("the piece's extent is not the whole extent".into());
    }
    let (nx, ny) = (
        (whole[1] as usize).saturating_add(1),
        (whole[3] as usize).saturating_add(1),
    );
    let expected = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(8))
        .ok_or("the extent is too large")?;
    // The block starts after the `_` that follows the element's tag.
    let underscore = bytes[at..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or("no `_` before the appended data")?
        + at
        + 1;
    let count_bytes: [u8; 8] = bytes
        .get(underscore..underscore + 8)
        .and_then(|b| b.try_into().ok())
        .ok_or("the appended block has no size")?;
    let count = usize::try_from(u64::from_le_bytes(count_bytes)).map_err(|e| e.to_string())?;
    if count != expected {
        return Err(format!("{count} bytes of data for {nx} × {ny} points"));
    }
    let data = bytes
        .get(underscore + 8..underscore + 8 + count)
        .ok_or("the appended block is cut short")?;
    let tail = std::str::from_utf8(&bytes[underscore + 8 + count..])
        .map_err(|e| format!("after the data: {e}"))?;
    if !tail.trim_start().starts_with("</AppendedData>") {
        return Err("no </AppendedData> after the data".into());
    }
    Ok(Vti {
        name: attribute(head, "DataArray", "Name")?.to_owned(),
        nx,
        ny,
        spacing: numbers(attribute(head, "ImageData", "Spacing")?)?,
        origin: numbers(attribute(head, "ImageData", "Origin")?)?,
        values: data
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 field with a NaN comes back with its values at the same
    /// points (x fastest), its spacing, origin and name.
    #[test]
    fn round_trip_keeps_values_spacing_and_nan() {
        let values = ndarray_like(3, 2, |ix, iy| {
            if (ix, iy) == (1, 1) {
                f64::NAN
            } else {
                1e-6 * (ix as f64) - 2.5e-7 * (iy as f64) + 1.0 / 3.0
            }
        });
        let field = Field::new(values, 2.5e-6, 4e-6).unwrap();
        let back = parse_vti(&vti_bytes(&field, "height [m]")).unwrap();
        assert_eq!(back.name, "height [m]");
        assert_eq!((back.nx, back.ny), (3, 2));
        assert_eq!(back.spacing, [2.5e-6, 4e-6, 2.5e-6]);
        assert_eq!(back.origin, [0.0; 3]);
        for iy in 0..2 {
            for ix in 0..3 {
                let (a, b) = (back.values[ix + 3 * iy], field.values[[ix, iy]]);
                assert!(a.to_bits() == b.to_bits(), "({ix}, {iy}): {a} vs {b}");
            }
        }
        assert!(back.values[1 + 3].is_nan());
        assert_eq!(back.values.iter().filter(|v| v.is_nan()).count(), 1);
        let odd = parse_vti(&vti_bytes(&field, "a \"q\" <b>")).unwrap();
        assert_eq!(odd.name, "a &quot;q&quot; &lt;b&gt;");
    }

    fn ndarray_like(nx: usize, ny: usize, f: impl Fn(usize, usize) -> f64) -> ndarray::Array2<f64> {
        ndarray::Array2::from_shape_fn((nx, ny), |(ix, iy)| f(ix, iy))
    }
}
