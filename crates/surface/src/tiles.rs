//! Reading interferometer tiles: where the bytes come from (a
//! [`FileSource`]: a `Files` product or a folder), how a tile file becomes
//! heights ([`decode_tile`]: `.npy`, or an instrument's own file in any
//! format `hypercontact-formats` reads, told by its first bytes), and where
//! each tile stood: the `positions.csv` a scanner writes (`tile, file, x_m,
//! y_m[, pixel_m]`: the nominal position of each tile's pixel [0, 0]), or,
//! without one, the stage positions the files record (X3P's axis offsets).
//!
//! A `.npy` tile of little-endian float64 in C order, as NumPy and
//! `synth-surface` write them, is read in place: its heights are a view of
//! the file's bytes when those sit at an 8-byte boundary in memory (a scan
//! of 100 tiles of 1024² px then costs no second 0.8 GB copy, #35); any
//! other tile is decoded into an array of its own, to the same values.

use std::borrow::Cow;
use std::collections::BTreeMap;

use hypercontact_core::{ColumnData, Field};
use hypercontact_formats::Format;
use hypercontact_labfiles::FileSource;
use hypercontact_labfiles::csv_table::{CsvTable, RowPlace};
use ndarray::{ArrayView2, CowArray, Ix2};
use ndarray_npy::npy::header::Header;

use crate::error::SurfaceError;

/// The name of the positions file in a tile set.
pub const POSITIONS: &str = "positions.csv";

/// Farthest a tile may sit from the origin, in pixels: a kilometre of
/// micrometre pixels. Beyond it a position is a unit mistake, and pixel
/// arithmetic on it would leave i64 (a tile at −1e300 m once made the
/// stitcher index out of bounds).
pub const MAX_POSITION_PX: f64 = 1e9;

/// Extensions of the files a tile folder's scan takes for tiles (the
/// reader itself goes by the first bytes).
pub const TILE_EXTENSIONS: &[&str] = &["npy", "x3p", "sur", "plu", "dat", "datx", "opd"];

/// A tile's heights: a view of its file's bytes, or an array of its own.
pub type TileHeights<'a> = CowArray<'a, f64, Ix2>;

/// A tile file's heights and what the file says of its grid.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedTile<'a> {
    /// metres, axis 0 = x, NaN where not measured
    pub heights: TileHeights<'a>,
    /// the file's (dx, dy), None for `.npy`
    pub spacing_m: Option<(f64, f64)>,
    /// the stage position of pixel [0, 0] the file records, if any
    pub position_m: Option<(f64, f64)>,
    /// the format it was read as
    pub format: Format,
}

impl DecodedTile<'_> {
    /// The tile with heights of its own, free of the bytes it was read from.
    pub fn into_owned<'b>(self) -> DecodedTile<'b> {
        DecodedTile {
            heights: CowArray::from(self.heights.into_owned()),
            spacing_m: self.spacing_m,
            position_m: self.position_m,
            format: self.format,
        }
    }
}

/// The heights of a `.npy` file of little-endian float64 in C order, read
/// in place; None for any other `.npy` (or not `.npy`), for data that does
/// not sit at an 8-byte boundary in memory, and on a big-endian machine:
/// those are decoded by [`Field::read_npy`] (which accepts every file this
/// does, to the same values).
pub fn npy_view(bytes: &[u8]) -> Option<ArrayView2<'_, f64>> {
    if cfg!(target_endian = "big") {
        return None;
    }
    let mut data = bytes;
    let header = Header::from_reader(&mut data).ok()?;
    let descr = header.type_descriptor.as_string()?;
    let [nx, ny] = header.shape[..] else {
        return None;
    };
    if descr != "<f8"
        || header.layout.is_fortran()
        || Some(data.len()) != nx.checked_mul(ny).and_then(|n| n.checked_mul(8))
    {
        return None;
    }
    // Fails (None) where the bytes are not 8-byte aligned.
    let values: &[f64] = bytemuck::try_cast_slice(data).ok()?;
    ArrayView2::from_shape((nx, ny), values).ok()
}

/// Reads a tile file by its first bytes: `.npy` (float64/float32, metres,
/// axis 0 = x, NaN = missing, no spacing; in place where [`npy_view`] can)
/// or an instrument's format.
pub fn decode_tile<'a>(name: &str, bytes: &'a [u8]) -> Result<DecodedTile<'a>, String> {
    let path = Some(std::path::Path::new(name));
    match hypercontact_formats::detect(bytes, path) {
        None | Some(Format::Npy) => {
            let heights = match npy_view(bytes) {
                Some(view) => CowArray::from(view),
                None => CowArray::from(
                    Field::read_npy(bytes, 1.0, 1.0)
                        .map_err(|e| e.to_string())?
                        .values,
                ),
            };
            Ok(DecodedTile {
                heights,
                spacing_m: None,
                position_m: None,
                format: Format::Npy,
            })
        }
        Some(_) => hypercontact_formats::read_bytes(bytes, path)
            .map(|t| DecodedTile {
                heights: CowArray::from(t.heights_m),
                spacing_m: Some((t.dx_m, t.dy_m)),
                position_m: t.position_m,
                format: t.format,
            })
            .map_err(|e| e.to_string()),
    }
}

/// The lower-case extension of a file name, "" without one.
fn extension(name: &str) -> String {
    name.rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default()
}

/// One row of `positions.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct Position {
    pub tile: i64,
    pub file: String,
    pub x_m: f64,
    pub y_m: f64,
    /// the scanner's spacing; optional when the tile files state theirs
    pub pixel_m: Option<f64>,
}

/// Cell `row` of a column as text (a number as Rust prints it).
fn cell_text(column: &ColumnData, row: usize) -> String {
    match column {
        ColumnData::F64(v) => v[row].to_string(),
        ColumnData::I64(v) => v[row].to_string(),
        ColumnData::Str(v) => v[row].clone(),
    }
}

/// Reads `positions.csv`, already parsed into a table with the file line of
/// each row (header required, columns in any order, extra columns ignored);
/// `display` names the file in errors, with the line of a bad value.
pub fn parse_positions(csv: &CsvTable, display: &str) -> Result<Vec<Position>, SurfaceError> {
    let table = &csv.table;
    let err = |line: u64, message: String| SurfaceError::Positions {
        file: display.to_owned(),
        line,
        message,
    };
    let line_of = |row: usize| match csv.lines.place(row) {
        RowPlace::Line(line) => line,
        RowPlace::Row(row) => row as u64 + csv.header_line,
    };
    let column = |name: &str| {
        table.column(name).map_err(|_| {
            err(
                csv.header_line,
                format!(
                    "no column `{name}` (expected tile, file, x_m, y_m and, unless the tile \
                     files state their spacing, pixel_m)"
                ),
            )
        })
    };
    let [tile, file, x, y] = [
        column("tile")?,
        column("file")?,
        column("x_m")?,
        column("y_m")?,
    ];
    let pixel = table.column("pixel_m").ok();
    let rows = table.n_rows();
    if rows == 0 {
        return Err(err(csv.header_line, "lists no tiles".into()));
    }
    let number = |data: &ColumnData, name: &str, row: usize| -> Result<f64, SurfaceError> {
        let text = cell_text(data, row);
        let v: f64 = text.parse().map_err(|_| {
            err(
                line_of(row),
                format!("column `{name}`: `{text}` is not a number"),
            )
        })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(err(
                line_of(row),
                format!("column `{name}`: `{text}` is not finite"),
            ))
        }
    };
    let mut positions = Vec::with_capacity(rows);
    for row in 0..rows {
        let tile_text = cell_text(tile, row);
        let position = Position {
            tile: tile_text.parse().map_err(|_| {
                err(
                    line_of(row),
                    format!("column `tile`: `{tile_text}` is not an integer"),
                )
            })?,
            file: match cell_text(file, row) {
                name if name.is_empty() => {
                    return Err(err(
                        line_of(row),
                        "column `file`: no tile file named".into(),
                    ));
                }
                name => name,
            },
            x_m: number(x, "x_m", row)?,
            y_m: number(y, "y_m", row)?,
            pixel_m: match pixel {
                Some(pixel) => Some(number(pixel, "pixel_m", row)?),
                None => None,
            },
        };
        if let Some(pixel_m) = position.pixel_m {
            if pixel_m <= 0.0 {
                return Err(err(
                    line_of(row),
                    format!("column `pixel_m`: must be positive, got {pixel_m}"),
                ));
            }
            check_in_reach(position.x_m, position.y_m, pixel_m)
                .map_err(|message| err(line_of(row), message))?;
        }
        positions.push(position);
    }
    Ok(positions)
}

/// A position's distance from the origin in pixels, refused beyond any
/// scan (a unit mistake).
fn check_in_reach(x_m: f64, y_m: f64, pixel_m: f64) -> Result<(), String> {
    for (name, value) in [("x_m", x_m), ("y_m", y_m)] {
        let px = value / pixel_m;
        if px.is_nan() || px.abs() > MAX_POSITION_PX {
            return Err(format!(
                "column `{name}`: {value} m is {px:e} pixels of {pixel_m} m from the origin, \
                 beyond any scan ({MAX_POSITION_PX:e} pixels; a unit mistake?)"
            ));
        }
    }
    Ok(())
}

/// Tiles read, checked and ready to stitch; their heights may be views of
/// the bytes of the source they were read from (`'a`).
#[derive(Clone, Debug)]
pub struct TileSet<'a> {
    /// The `tile` column of positions.csv.
    pub ids: Vec<i64>,
    pub names: Vec<String>,
    pub heights: Vec<TileHeights<'a>>,
    /// Nominal positions of pixel [0, 0], pixels.
    pub nominal_px: Vec<[f64; 2]>,
    pub pixel_m: f64,
}

/// A tile's bytes, refused unread when larger than a map of its format
/// (by extension) with the readers' default points limit can be (#31, 6).
fn read_tile_bytes<'a>(
    source: &FileSource<'a>,
    name: &str,
) -> Result<std::borrow::Cow<'a, [u8]>, SurfaceError> {
    let format = hypercontact_formats::format_of_extension(std::path::Path::new(name));
    let max_points = hypercontact_formats::DEFAULT_MAX_POINTS;
    let limit_bytes = hypercontact_formats::max_file_bytes(format, max_points);
    let what = format!(
        "{} tiles of at most {max_points} points",
        format.map_or("height-map", Format::name)
    );
    Ok(source.read_at_most(name, &what, limit_bytes)?)
}

/// Reads and checks a tile set: the positions file matches the tile files
/// (every listed file exists, no tile file is unlisted, no duplicates),
/// tiles share one shape and one square spacing, no tile is all NaN.
/// Without `positions.csv` the tiles are the folder's tile files in
/// natural order of their names, each placed where the file says it stood.
pub fn read_tiles<'a>(source: &FileSource<'a>) -> Result<TileSet<'a>, SurfaceError> {
    let positions_name = source.display(POSITIONS);
    let listed = source.exists(POSITIONS);
    let tile_names: Vec<String> = source
        .names()?
        .into_iter()
        .filter(|name| TILE_EXTENSIONS.contains(&extension(name).as_str()))
        .collect();
    let positions = if listed {
        parse_positions(&source.read_csv_with_lines(POSITIONS)?, &positions_name)?
    } else {
        unlisted_positions(tile_names.clone(), &positions_name)?
    };
    let mismatch = |message: String| SurfaceError::PositionsMismatch {
        file: positions_name.clone(),
        message,
    };
    check_listing(&positions, &tile_names).map_err(mismatch)?;
    let first_shown = source.display(&positions[0].file);
    let mut set = TileSet {
        ids: Vec::new(),
        names: Vec::new(),
        heights: Vec::new(),
        nominal_px: Vec::new(),
        pixel_m: f64::NAN,
    };
    for p in &positions {
        let shown = source.display(&p.file);
        let tile_err = |message: String| SurfaceError::Tile {
            file: shown.clone(),
            message,
        };
        if !source.exists(&p.file) {
            return Err(mismatch(format!(
                "{} is listed but not in the tile set",
                p.file
            )));
        }
        let tile = match read_tile_bytes(source, &p.file)? {
            Cow::Borrowed(bytes) => decode_tile(&p.file, bytes),
            Cow::Owned(bytes) => decode_tile(&p.file, &bytes).map(DecodedTile::into_owned),
        }
        .map_err(&tile_err)?;
        let position_m = if listed {
            (p.x_m, p.y_m)
        } else {
            recorded_position(&p.file, &tile).map_err(&tile_err)?
        };
        let pixel_m = tile_spacing(p, &tile).map_err(&tile_err)?;
        set.push(p, tile.heights, position_m, pixel_m, (&shown, &first_shown))?;
    }
    Ok(set)
}

/// Without positions.csv: the tile files in natural order of their names,
/// numbered from 0, positions to be read from the files.
fn unlisted_positions(
    mut names: Vec<String>,
    positions_name: &str,
) -> Result<Vec<Position>, SurfaceError> {
    if names.is_empty() {
        return Err(SurfaceError::Input(format!(
            "{positions_name} is missing and there are no tile files ({}) beside it",
            TILE_EXTENSIONS.join(", ")
        )));
    }
    alphanumeric_sort::sort_str_slice(&mut names);
    Ok(names
        .into_iter()
        .enumerate()
        .map(|(k, file)| Position {
            tile: k as i64,
            file,
            x_m: f64::NAN,
            y_m: f64::NAN,
            pixel_m: None,
        })
        .collect())
}

/// No file listed twice, and every tile file listed.
fn check_listing(positions: &[Position], tile_names: &[String]) -> Result<(), String> {
    let mut seen = BTreeMap::new();
    for p in positions {
        if let Some(first) = seen.insert(p.file.clone(), p.tile) {
            return Err(format!(
                "{} is listed twice (tiles {first} and {})",
                p.file, p.tile
            ));
        }
    }
    if let Some(name) = tile_names.iter().find(|name| !seen.contains_key(*name)) {
        return Err(format!("tile file {name} is not listed"));
    }
    Ok(())
}

/// The stage position a tile file records, or what to write instead.
fn recorded_position(file: &str, tile: &DecodedTile) -> Result<(f64, f64), String> {
    tile.position_m.ok_or_else(|| {
        let columns = match tile.spacing_m {
            Some(_) => "tile, file, x_m, y_m",
            None => "tile, file, x_m, y_m, pixel_m",
        };
        format!(
            "records no stage position ({} files do not), and there is no {POSITIONS}: \
             write one with columns {columns} (e.g. `0,{},0.0,0.0{}`)",
            tile.format.name(),
            file,
            if tile.spacing_m.is_some() {
                ""
            } else {
                ",1.0e-6"
            }
        )
    })
}

impl<'a> TileSet<'a> {
    /// Adds a tile after checking it against the set: the first tile's
    /// spacing and shape, a position within reach, heights neither all NaN
    /// nor infinite. `shown` names it in errors, `first_shown` the first.
    fn push(
        &mut self,
        p: &Position,
        heights: TileHeights<'a>,
        (x_m, y_m): (f64, f64),
        pixel_m: f64,
        (shown, first_shown): (&str, &str),
    ) -> Result<(), SurfaceError> {
        let tile_err = |message: String| SurfaceError::Tile {
            file: shown.to_owned(),
            message,
        };
        if self.names.is_empty() {
            self.pixel_m = pixel_m;
        } else if (pixel_m - self.pixel_m).abs() > 1e-9 * self.pixel_m {
            return Err(SurfaceError::Spacing {
                file: shown.to_owned(),
                found: pixel_m,
                first: first_shown.to_owned(),
                expected: self.pixel_m,
            });
        }
        check_in_reach(x_m, y_m, pixel_m).map_err(tile_err)?;
        if let Some(h0) = self.heights.first()
            && h0.dim() != heights.dim()
        {
            return Err(SurfaceError::Shape {
                file: shown.to_owned(),
                found: heights.dim(),
                first: first_shown.to_owned(),
                expected: h0.dim(),
            });
        }
        if heights.iter().all(|h| h.is_nan()) {
            return Err(tile_err("every point is NaN".into()));
        }
        if heights.iter().any(|h| h.is_infinite()) {
            return Err(tile_err("holds an infinite height".into()));
        }
        self.ids.push(p.tile);
        self.names.push(p.file.clone());
        self.heights.push(heights);
        self.nominal_px.push([x_m / pixel_m, y_m / pixel_m]);
        Ok(())
    }
}

/// A tile's square grid spacing: positions.csv's `pixel_m` and the file's
/// own must agree where both exist (1e-6 relative), and one must exist.
fn tile_spacing(p: &Position, tile: &DecodedTile) -> Result<f64, String> {
    match (p.pixel_m, tile.spacing_m) {
        (_, Some((dx, dy))) if (dx - dy).abs() > 1e-6 * dx => Err(format!(
            "has pixels of {dx:e} × {dy:e} m: stitching needs square pixels (resample the \
             tiles, or analyse them one by one with height-map)"
        )),
        (Some(listed), Some((dx, _))) if (listed - dx).abs() > 1e-6 * dx => Err(format!(
            "states a spacing of {dx:e} m but {POSITIONS} gives pixel_m = {listed:e} m for it"
        )),
        (_, Some((dx, _))) => Ok(dx),
        (Some(listed), None) => Ok(listed),
        (None, None) => Err(format!(
            "is a {} file, which holds no spacing: give {POSITIONS} a column pixel_m",
            tile.format.name()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Files;
    use ndarray::Array2;

    fn npy(values: Array2<f64>) -> Vec<u8> {
        let mut bytes = Vec::new();
        Field::new(values, 1.0, 1.0)
            .unwrap()
            .write_npy(&mut bytes)
            .unwrap();
        bytes
    }

    fn set(csv: &str, tiles: &[(&str, Array2<f64>)]) -> Files {
        let mut files = Files::new().with(POSITIONS, csv.as_bytes().to_vec());
        for (name, values) in tiles {
            files = files.with(name, npy(values.clone()));
        }
        files
    }

    fn read(files: &Files) -> Result<TileSet<'_>, SurfaceError> {
        read_tiles(&FileSource::Files {
            files,
            input: "tiles".into(),
        })
    }

    #[test]
    fn reads_positions_in_pixels() {
        let files = set(
            "tile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n1,b.npy,3e-6,0,1e-6\n",
            &[
                ("a.npy", Array2::zeros((4, 4))),
                ("b.npy", Array2::ones((4, 4))),
            ],
        );
        let s = read(&files).unwrap();
        assert_eq!(s.names, ["a.npy", "b.npy"]);
        assert!((s.nominal_px[1][0] - 3.0).abs() < 1e-9);
        assert_eq!(s.heights[1][[0, 0]], 1.0);
    }

    #[test]
    fn positions_errors_name_the_line_as_the_file_has_it() {
        let z = || Array2::<f64>::zeros((4, 4));
        let message = |csv: &str| {
            read(&set(csv, &[("a.npy", z()), ("b.npy", z())]))
                .unwrap_err()
                .to_string()
        };
        let m = message(
            "# scanner export\n\ntile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n# row 2\n\n\
             1,b.npy,zero,0,1e-6\n",
        );
        assert!(
            m.contains("positions.csv") && m.contains("line 7") && m.contains("`x_m`"),
            "{m}"
        );
        let m = message("# scanner export\ntile,file,x_m,pixel_m\n0,a.npy,0,1e-6\n");
        assert!(m.contains("line 2") && m.contains("`y_m`"), "{m}");
        let m = message("tile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n# b\n1,,0,0,1e-6\n");
        assert!(
            m.contains("line 4") && m.contains("no tile file named"),
            "{m}"
        );
        let m = message("tile,file,x_m,y_m,pixel_m\n");
        assert!(
            m.contains("positions.csv") && m.contains("no data rows"),
            "{m}"
        );
    }

    #[test]
    fn positions_beyond_any_scan_are_refused_with_their_line() {
        let z = || Array2::<f64>::zeros((4, 4));
        for (csv, column) in [
            (
                "tile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n1,b.npy,-1e300,0,1e-6\n",
                "x_m",
            ),
            (
                "tile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n1,b.npy,0,3e-6,1e-300\n",
                "y_m",
            ),
        ] {
            let m = read(&set(csv, &[("a.npy", z()), ("b.npy", z())]))
                .unwrap_err()
                .to_string();
            assert!(
                m.contains("positions.csv, line 3") && m.contains(column) && m.contains("pixels"),
                "{m}"
            );
        }
    }

    #[test]
    fn bad_tile_sets_name_the_file() {
        let head = "tile,file,x_m,y_m,pixel_m\n";
        let z = || Array2::<f64>::zeros((4, 4));
        let message = |csv: &str, tiles: &[(&str, Array2<f64>)]| {
            read(&set(csv, tiles)).unwrap_err().to_string()
        };
        // Different shapes.
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,3e-6,0,1e-6\n"),
            &[("a.npy", z()), ("b.npy", Array2::zeros((4, 5)))],
        );
        assert!(
            m.contains("input `tiles`/b.npy") && m.contains("shape"),
            "{m}"
        );
        // Different spacings.
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,3e-6,0,2e-6\n"),
            &[("a.npy", z()), ("b.npy", z())],
        );
        assert!(
            m.contains("input `tiles`/b.npy") && m.contains("pixel_m"),
            "{m}"
        );
        // A listed tile that is missing, and a tile that is not listed.
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n1,c.npy,3e-6,0,1e-6\n"),
            &[("a.npy", z())],
        );
        assert!(m.contains("positions.csv") && m.contains("c.npy"), "{m}");
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n"),
            &[("a.npy", z()), ("b.npy", z())],
        );
        assert!(m.contains("b.npy is not listed"), "{m}");
        // An all-NaN tile.
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n"),
            &[("a.npy", Array2::from_elem((4, 4), f64::NAN))],
        );
        assert!(
            m.contains("input `tiles`/a.npy") && m.contains("NaN"),
            "{m}"
        );
        // A bad number, with its line, and a missing column.
        let m = message(&format!("{head}0,a.npy,zero,0,1e-6\n"), &[("a.npy", z())]);
        assert!(m.contains("line 2") && m.contains("x_m"), "{m}");
        let m = message("tile,file,x_m,pixel_m\n0,a.npy,0,1e-6\n", &[("a.npy", z())]);
        assert!(m.contains("y_m"), "{m}");
        // An unknown format.
        let m = message(&format!("{head}0,a.x3p,0,0,1e-6\n"), &[]);
        assert!(m.contains("a.x3p") && m.contains(".x3p"), "{m}");
    }

    /// Heights with every kind of f64 a tile holds: NaN, −0, subnormals.
    fn awkward_heights() -> Array2<f64> {
        Array2::from_shape_fn((7, 5), |(i, j)| match (i + 3 * j) % 6 {
            0 => f64::NAN,
            1 => -0.0,
            2 => f64::MIN_POSITIVE / 3.0,
            _ => (i as f64 * 0.37 - j as f64 * 1.1) * 1e-6,
        })
    }

    fn bits(heights: &TileHeights) -> Vec<u64> {
        heights.iter().map(|v| v.to_bits()).collect()
    }

    #[test]
    fn npy_tiles_are_read_in_place_with_the_decoders_bits() {
        let values = awkward_heights();
        let bytes = npy(values.clone());
        let decoded = Field::read_npy(bytes.as_slice(), 1.0, 1.0).unwrap().values;
        // A Vec's buffer is 8-byte aligned and the header pads the data to a
        // multiple of 16 bytes: the view path.
        let tile = decode_tile("t.npy", &bytes).unwrap();
        assert!(tile.heights.is_view(), "not read in place");
        let range = bytes.as_ptr_range();
        assert!(range.contains(&tile.heights.as_ptr().cast::<u8>()));
        assert_eq!(tile.heights.dim(), (7, 5));
        assert_eq!(bits(&tile.heights), bits(&CowArray::from(decoded.view())));
        assert_eq!(
            bits(&tile.heights),
            values.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        // The same bytes one byte off an 8-byte boundary: decoded, same bits.
        let mut shifted = vec![0u8; bytes.len() + 1];
        shifted[1..].copy_from_slice(&bytes);
        assert!(npy_view(&shifted[1..]).is_none());
        let copy = decode_tile("t.npy", &shifted[1..]).unwrap();
        assert!(copy.heights.is_owned());
        assert_eq!(bits(&copy.heights), bits(&tile.heights));
        assert!(tile.into_owned().heights.is_owned());
    }

    #[test]
    fn npy_tiles_a_view_cannot_read_are_decoded() {
        let values = awkward_heights();
        let little = npy(values.clone());
        let expected: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
        let data_start = little.len() - 8 * values.len();
        let header = &little[..data_start];
        let find = |text: &[u8]| header.windows(text.len()).position(|w| w == text).unwrap();
        // Big-endian: the header says `>f8` and each value's bytes turn round.
        let mut big = header.to_vec();
        big[find(b"<f8")] = b'>';
        for v in &values {
            big.extend_from_slice(&v.to_be_bytes());
        }
        // Fortran order: the header says so and the values go column by column.
        let mut fortran = header.to_vec();
        let at = find(b"False");
        fortran[at..at + 5].copy_from_slice(b"True ");
        for v in values.t().iter() {
            fortran.extend_from_slice(&v.to_le_bytes());
        }
        // A value short: refused by both paths.
        let short = &little[..little.len() - 8];
        for (name, bytes) in [("big-endian", &big), ("Fortran order", &fortran)] {
            assert!(npy_view(bytes).is_none(), "{name}");
            let tile = decode_tile("t.npy", bytes).unwrap();
            assert!(tile.heights.is_owned(), "{name}");
            assert_eq!(bits(&tile.heights), expected, "{name}");
        }
        assert!(npy_view(short).is_none());
        assert!(decode_tile("t.npy", short).is_err());
    }

    #[test]
    fn a_files_product_lends_its_tiles_and_a_folder_owns_them() {
        let files = set(
            "tile,file,x_m,y_m,pixel_m\n0,a.npy,0,0,1e-6\n1,b.npy,3e-6,0,1e-6\n",
            &[("a.npy", awkward_heights()), ("b.npy", awkward_heights())],
        );
        let lent = read(&files).unwrap();
        assert!(lent.heights.iter().all(|h| h.is_view()));
        let dir = std::env::temp_dir().join(format!("hc-tiles-owned-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, bytes) in &files.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let owned = read_tiles(&FileSource::Dir(dir.clone())).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
        assert!(owned.heights.iter().all(|h| h.is_owned()));
        for (a, b) in lent.heights.iter().zip(&owned.heights) {
            assert_eq!(bits(a), bits(b));
        }
    }

    /// A 4 GiB tile (holes) in a folder is refused from its size before it
    /// is read (#31, 6; before, read whole into memory).
    #[test]
    fn a_tile_beyond_its_formats_bound_is_refused_unread() {
        let dir = std::env::temp_dir().join(format!("hc-tiles-bound-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::File::create(dir.join("tile_000.npy"))
            .unwrap()
            .set_len(4 << 30)
            .unwrap();
        let started = std::time::Instant::now();
        let e = read_tiles(&FileSource::Dir(dir.clone()))
            .unwrap_err()
            .to_string();
        assert!(
            started.elapsed().as_secs_f64() < 1.0,
            "{:?}",
            started.elapsed()
        );
        assert!(
            e.contains("tile_000.npy")
                && e.contains("NumPy .npy tiles of at most 67108864 points are at most"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
