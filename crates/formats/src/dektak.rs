//! Bruker Dektak stylus profiles exported as CSV: `Scan Parameters` and
//! `Analytical Results` sections of `key,value` lines, then `Scan Data`, an
//! empty line, a column header naming the units (`Lateral um,Raw
//! Micrometer,`) and one `position,height` line a point (the layout
//! SurfaceTopography's `IO/XYZ.py` reads, Latin-1 text).
//!
//! A profile is returned as a line scan: an n × 1 map along x, `dy_m` =
//! `dx_m`, the metadata key `line_scan`. Its spacing is the least-squares
//! slope of the recorded positions against the point index. The file
//! rounds positions to 0.1 µm, so neither end-to-end difference is exact;
//! the slope of `dektak-1.csv` is 0.15624999 µm, the 1500 µm / 9600 points
//! its header's `Length` gives, to 3e-8. SurfaceTopography keeps the
//! positions themselves (a non-uniform line scan); the reference index's
//! `dx_m` (0.1562292 µm) is their range over the number of points, one
//! interval short, which this reader does not copy.

use ndarray::Array2;

use crate::bytes::grid_points;
use crate::text::{decode, lines, number};
use crate::units::metres_per;
use crate::{Format, FormatError, Topography};

const FORMAT: Format = Format::DektakCsv;

const MAGIC: &[u8] = b"Scan Parameters";

/// Whether the file starts with Dektak's first section title.
pub(crate) fn matches(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Metres per unit of a column title (`Lateral um`, `Raw Micrometer`): its
/// last word.
fn column_unit_m(title: &str, line: usize) -> Result<f64, FormatError> {
    let unit = title.split_whitespace().last().unwrap_or_default();
    metres_per(&unit.to_ascii_lowercase())
        .or_else(|| metres_per(unit))
        .ok_or_else(|| {
            FORMAT.unsupported(format!(
                "line {line}: the column \"{title}\" is not in a length unit"
            ))
        })
}

/// Reads the profile as an n × 1 map in metres.
pub(crate) fn read(data: &[u8], max_points: usize) -> Result<Topography, FormatError> {
    let text = decode(data);
    let mut lines = lines(&text).enumerate().map(|(i, l)| (i + 1, l));
    let mut metadata = Vec::new();
    for (_, line) in lines.by_ref() {
        if line.starts_with("Scan Data") {
            break;
        }
        if let Some((key, value)) = line.trim().split_once(',')
            && ["Stylus", "Length", "Resolution", "Force", "Scan Type"].contains(&key)
        {
            metadata.push((key.to_ascii_lowercase(), value.trim().to_string()));
        }
    }
    let mut titles = lines.by_ref().skip_while(|(_, l)| l.trim().is_empty());
    let Some((title_line, title)) = titles.next() else {
        return Err(FORMAT.invalid("no \"Scan Data\" section with a column header"));
    };
    let columns: Vec<&str> = title.split(',').collect();
    if columns.len() < 2 {
        return Err(FORMAT.invalid(format!(
            "line {title_line}: expected the columns position,height, found \"{title}\""
        )));
    }
    let x_m = column_unit_m(columns[0], title_line)?;
    let z_m = column_unit_m(columns[1], title_line)?;
    let mut positions = Vec::new();
    let mut heights = Vec::new();
    for (index, line) in titles.filter(|(_, l)| !l.trim().is_empty()) {
        let mut words = line.split(',');
        let mut value = |what: &str| {
            words
                .next()
                .and_then(number)
                .ok_or_else(|| FORMAT.invalid(format!("line {index}: no {what} in \"{line}\"")))
        };
        positions.push(value("position")?);
        heights.push(value("height")?);
    }
    grid_points(
        FORMAT.name(),
        heights.len(),
        1,
        "the Scan Data rows",
        max_points,
    )?;
    let dx_m = slope(&positions) * x_m;
    if !(dx_m.is_finite() && dx_m > 0.0) {
        return Err(FORMAT.invalid(format!(
            "the {} positions give no positive spacing (least-squares slope {dx_m} m)",
            positions.len()
        )));
    }
    let heights_m = Array2::from_shape_fn((heights.len(), 1), |(i, _)| heights[i] * z_m);
    metadata.push(("line_scan".into(), "true".into()));
    Ok(Topography {
        heights_m,
        dx_m,
        dy_m: dx_m,
        format: FORMAT,
        position_m: positions.first().map(|x| (x * x_m, 0.0)),
        metadata,
    })
}

/// The least-squares slope of `values` against their index (NaN for fewer
/// than two values), summed in index order.
fn slope(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean_index = (n - 1.0) / 2.0;
    let mean = values.iter().sum::<f64>() / n;
    let (mut covariance, mut variance) = (0.0, 0.0);
    for (i, v) in values.iter().enumerate() {
        let di = i as f64 - mean_index;
        covariance += di * (v - mean);
        variance += di * di;
    }
    covariance / variance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_are_n_by_1_maps_with_the_fitted_spacing() {
        let file = b"Scan Parameters\r\r\nLength,0.5 um\r\r\nScan Data\r\r\n\
                     Lateral um,Raw Micrometer,\r\n0.0,1.0,,\r\n0.2,2.0,,\r\n0.3,-1.0,,\r\n0.5,0,,\r\n";
        assert!(matches(file));
        let map = read(file, crate::DEFAULT_MAX_POINTS).unwrap();
        assert_eq!(map.heights_m.dim(), (4, 1));
        assert_eq!(map.heights_m[[2, 0]], -1e-6);
        // positions 0.15625 i rounded to 0.1: the fit recovers the spacing
        assert!((map.dx_m - 0.16e-6).abs() < 1e-12, "{}", map.dx_m);
        assert!(map.metadata.contains(&("length".into(), "0.5 um".into())));
    }

    #[test]
    fn slopes_of_exact_lines_are_exact() {
        assert_eq!(slope(&[1.0, 3.0, 5.0, 7.0]), 2.0);
        assert!(slope(&[1.0]).is_nan());
    }

    #[test]
    fn broken_files_say_where() {
        let err = read(
            b"Scan Parameters\nScan Data\n\nLateral um,Raw V,\n",
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("line 4") && err.contains("Raw V"), "{err}");
        let err = read(
            b"Scan Parameters\nScan Data\n\nLateral um,Raw um,\n1,x\n",
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("line 5: no height"), "{err}");
        assert!(read(b"Scan Parameters\n", crate::DEFAULT_MAX_POINTS).is_err());
        let err = read(
            b"Scan Parameters\nScan Data\n\nLateral um,Raw um,\n1,2\n",
            crate::DEFAULT_MAX_POINTS,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("no positive spacing"), "{err}");
    }
}
