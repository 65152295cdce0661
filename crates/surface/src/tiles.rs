//! Reading interferometer tiles: where the bytes come from (a
//! [`FileSource`]: a `Files` product or a folder), how a tile file becomes
//! heights ([`decode_tile`]: `.npy`, or an instrument's own file in any
//! format `hypercontact-formats` reads, told by its first bytes), and where
//! each tile stood: the `positions.csv` a scanner writes (`tile, file, x_m,
//! y_m[, pixel_m]`: the nominal position of each tile's pixel [0, 0]), or,
//! without one, the stage positions the files record (X3P's axis offsets).

use std::collections::BTreeMap;

use hypercontact_core::{ColumnData, Field};
use hypercontact_formats::Format;
use hypercontact_labfiles::FileSource;
use hypercontact_labfiles::csv_table::{CsvTable, RowPlace};
use ndarray::Array2;

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

/// A tile file's heights and what the file says of its grid.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedTile {
    /// metres, axis 0 = x, NaN where not measured
    pub heights: Array2<f64>,
    /// the file's (dx, dy), None for `.npy`
    pub spacing_m: Option<(f64, f64)>,
    /// the stage position of pixel [0, 0] the file records, if any
    pub position_m: Option<(f64, f64)>,
    /// the format it was read as
    pub format: Format,
}

/// Reads a tile file by its first bytes: `.npy` (float64/float32, metres,
/// axis 0 = x, NaN = missing, no spacing) or an instrument's format.
pub fn decode_tile(name: &str, bytes: &[u8]) -> Result<DecodedTile, String> {
    match hypercontact_formats::detect(bytes, Some(std::path::Path::new(name))) {
        None | Some(Format::Npy) => Field::read_npy(bytes, 1.0, 1.0)
            .map(|f| DecodedTile {
                heights: f.values,
                spacing_m: None,
                position_m: None,
                format: Format::Npy,
            })
            .map_err(|e| e.to_string()),
        Some(_) => hypercontact_formats::read_bytes(bytes, Some(std::path::Path::new(name)))
            .map(|t| DecodedTile {
                heights: t.heights_m,
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

/// Tiles read, checked and ready to stitch.
#[derive(Clone, Debug)]
pub struct TileSet {
    /// The `tile` column of positions.csv.
    pub ids: Vec<i64>,
    pub names: Vec<String>,
    pub heights: Vec<Array2<f64>>,
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
pub fn read_tiles(source: &FileSource) -> Result<TileSet, SurfaceError> {
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
        let bytes = read_tile_bytes(source, &p.file)?;
        let tile = decode_tile(&p.file, &bytes).map_err(&tile_err)?;
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

impl TileSet {
    /// Adds a tile after checking it against the set: the first tile's
    /// spacing and shape, a position within reach, heights neither all NaN
    /// nor infinite. `shown` names it in errors, `first_shown` the first.
    fn push(
        &mut self,
        p: &Position,
        heights: Array2<f64>,
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

    fn read(files: &Files) -> Result<TileSet, SurfaceError> {
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
