//! Reading interferometer tiles: where the bytes come from (`TileSource`: a
//! `Files` product or a folder), how a tile file becomes heights
//! (`TileDecoder`: `.npy` now, ISO 25178-72 `.x3p` can follow), and the
//! `positions.csv` a scanner writes (`tile, file, x_m, y_m, pixel_m`: the
//! nominal position of each tile's pixel [0, 0]).

use std::collections::BTreeMap;
use std::path::PathBuf;

use hypercontact_core::{Field, Files};
use ndarray::Array2;

use crate::error::SurfaceError;

/// The name of the positions file in a tile set.
pub const POSITIONS: &str = "positions.csv";

/// Where tile files are read from.
pub trait TileSource {
    /// The raw bytes of a file of the tile set.
    fn bytes(&self, name: &str) -> Result<Vec<u8>, SurfaceError>;
    /// The names of all files in the set.
    fn names(&self) -> Result<Vec<String>, SurfaceError>;
    /// How to show a file of the set in a message.
    fn display(&self, name: &str) -> String;
}

/// Turns a tile file into heights in metres (axis 0 = x).
pub trait TileDecoder {
    /// Lower-case extensions this decoder reads, without the dot.
    fn extensions(&self) -> &'static [&'static str];
    fn decode(&self, bytes: &[u8]) -> Result<Array2<f64>, String>;
}

/// `.npy`, float64 or float32, metres, axis 0 = x, NaN where not measured.
pub struct NpyDecoder;

impl TileDecoder for NpyDecoder {
    fn extensions(&self) -> &'static [&'static str] {
        &["npy"]
    }

    fn decode(&self, bytes: &[u8]) -> Result<Array2<f64>, String> {
        Field::read_npy(bytes, 1.0, 1.0)
            .map(|f| f.values)
            .map_err(|e| e.to_string())
    }
}

/// The decoders this build knows.
pub fn decoders() -> Vec<Box<dyn TileDecoder>> {
    vec![Box::new(NpyDecoder)]
}

/// A `Files` product (e.g. from `synth-surface`).
pub struct FilesSource<'a> {
    pub files: &'a Files,
    /// The input's name, for messages.
    pub label: String,
}

impl TileSource for FilesSource<'_> {
    fn bytes(&self, name: &str) -> Result<Vec<u8>, SurfaceError> {
        self.files
            .files
            .get(name)
            .cloned()
            .ok_or_else(|| SurfaceError::Tile {
                file: self.display(name),
                message: "no such file in the tile set".into(),
            })
    }

    fn names(&self) -> Result<Vec<String>, SurfaceError> {
        Ok(self.files.files.keys().cloned().collect())
    }

    fn display(&self, name: &str) -> String {
        format!("{}/{name}", self.label)
    }
}

/// A folder holding the tile files and `positions.csv`.
pub struct DirSource {
    pub dir: PathBuf,
}

impl TileSource for DirSource {
    fn bytes(&self, name: &str) -> Result<Vec<u8>, SurfaceError> {
        std::fs::read(self.dir.join(name)).map_err(|e| SurfaceError::Tile {
            file: self.display(name),
            message: e.to_string(),
        })
    }

    fn names(&self) -> Result<Vec<String>, SurfaceError> {
        let entries = std::fs::read_dir(&self.dir).map_err(|e| SurfaceError::Tile {
            file: self.dir.display().to_string(),
            message: e.to_string(),
        })?;
        let mut names = Vec::new();
        for entry in entries.flatten() {
            if entry.path().is_file() {
                names.push(entry.file_name().to_string_lossy().into_owned());
            }
        }
        names.sort();
        Ok(names)
    }

    fn display(&self, name: &str) -> String {
        self.dir.join(name).display().to_string()
    }
}

/// One row of `positions.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct Position {
    pub tile: i64,
    pub file: String,
    pub x_m: f64,
    pub y_m: f64,
    pub pixel_m: f64,
}

/// Parses `positions.csv` (header required, columns in any order, extra
/// columns ignored); `display` names the file in errors.
pub fn parse_positions(bytes: &[u8], display: &str) -> Result<Vec<Position>, SurfaceError> {
    let err = |line: u64, message: String| SurfaceError::Positions {
        file: display.to_owned(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(bytes);
    let header = reader.headers().map_err(|e| err(1, e.to_string()))?.clone();
    let column = |name: &str| {
        header.iter().position(|h| h == name).ok_or_else(|| {
            err(
                1,
                format!("no column `{name}` (expected tile, file, x_m, y_m, pixel_m)"),
            )
        })
    };
    let [tile, file, x, y, pixel] = [
        column("tile")?,
        column("file")?,
        column("x_m")?,
        column("y_m")?,
        column("pixel_m")?,
    ];
    let mut rows = Vec::new();
    for record in reader.records() {
        let record =
            record.map_err(|e| err(e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        let get = |i: usize, name: &str| {
            record
                .get(i)
                .ok_or_else(|| err(line, format!("column `{name}` is missing")))
        };
        let number = |i: usize, name: &str| -> Result<f64, SurfaceError> {
            let text = get(i, name)?;
            let v: f64 = text
                .parse()
                .map_err(|_| err(line, format!("column `{name}`: `{text}` is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(err(
                    line,
                    format!("column `{name}`: `{text}` is not finite"),
                ))
            }
        };
        let tile_text = get(tile, "tile")?;
        let position = Position {
            tile: tile_text.parse().map_err(|_| {
                err(
                    line,
                    format!("column `tile`: `{tile_text}` is not an integer"),
                )
            })?,
            file: get(file, "file")?.to_owned(),
            x_m: number(x, "x_m")?,
            y_m: number(y, "y_m")?,
            pixel_m: number(pixel, "pixel_m")?,
        };
        if position.pixel_m <= 0.0 {
            return Err(err(
                line,
                format!(
                    "column `pixel_m`: must be positive, got {}",
                    position.pixel_m
                ),
            ));
        }
        rows.push(position);
    }
    if rows.is_empty() {
        return Err(err(1, "lists no tiles".into()));
    }
    Ok(rows)
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

/// Reads and checks a tile set: the positions file matches the tile files
/// (every listed file exists, no tile file is unlisted, no duplicates),
/// tiles share one shape and one spacing, no tile is all NaN.
pub fn read_tiles(source: &dyn TileSource) -> Result<TileSet, SurfaceError> {
    let positions_name = source.display(POSITIONS);
    let positions = parse_positions(&source.bytes(POSITIONS)?, &positions_name)?;
    let decoders = decoders();
    let extension = |name: &str| {
        name.rsplit_once('.')
            .map(|(_, e)| e.to_ascii_lowercase())
            .unwrap_or_default()
    };
    let mismatch = |message: String| SurfaceError::PositionsMismatch {
        file: positions_name.clone(),
        message,
    };
    let mut seen = BTreeMap::new();
    for p in &positions {
        if let Some(first) = seen.insert(p.file.clone(), p.tile) {
            return Err(mismatch(format!(
                "{} is listed twice (tiles {first} and {})",
                p.file, p.tile
            )));
        }
    }
    let known: Vec<&str> = decoders
        .iter()
        .flat_map(|d| d.extensions().iter().copied())
        .collect();
    for name in source.names()? {
        if name != POSITIONS
            && known.contains(&extension(&name).as_str())
            && !seen.contains_key(&name)
        {
            return Err(mismatch(format!("tile file {name} is not listed")));
        }
    }
    let first = &positions[0];
    let mut set = TileSet {
        ids: Vec::new(),
        names: Vec::new(),
        heights: Vec::new(),
        nominal_px: Vec::new(),
        pixel_m: first.pixel_m,
    };
    for p in &positions {
        let shown = source.display(&p.file);
        if (p.pixel_m - first.pixel_m).abs() > 1e-9 * first.pixel_m {
            return Err(SurfaceError::Spacing {
                file: shown,
                found: p.pixel_m,
                first: source.display(&first.file),
                expected: first.pixel_m,
            });
        }
        let ext = extension(&p.file);
        let decoder = decoders
            .iter()
            .find(|d| d.extensions().contains(&ext.as_str()))
            .ok_or_else(|| SurfaceError::Tile {
                file: shown.clone(),
                message: format!("cannot read `.{ext}` tiles (known: {})", known.join(", ")),
            })?;
        let bytes = source
            .bytes(&p.file)
            .map_err(|_| mismatch(format!("{} is listed but not in the tile set", p.file)))?;
        let heights = decoder
            .decode(&bytes)
            .map_err(|message| SurfaceError::Tile {
                file: shown.clone(),
                message,
            })?;
        if let Some(h0) = set.heights.first()
            && h0.dim() != heights.dim()
        {
            return Err(SurfaceError::Shape {
                file: shown,
                found: heights.dim(),
                first: source.display(&first.file),
                expected: h0.dim(),
            });
        }
        if heights.iter().all(|h| h.is_nan()) {
            return Err(SurfaceError::Tile {
                file: shown,
                message: "every point is NaN".into(),
            });
        }
        if heights.iter().any(|h| h.is_infinite()) {
            return Err(SurfaceError::Tile {
                file: shown,
                message: "holds an infinite height".into(),
            });
        }
        set.ids.push(p.tile);
        set.names.push(p.file.clone());
        set.heights.push(heights);
        set.nominal_px
            .push([p.x_m / first.pixel_m, p.y_m / first.pixel_m]);
    }
    Ok(set)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        read_tiles(&FilesSource {
            files,
            label: "tiles".into(),
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
        assert!(m.contains("tiles/b.npy") && m.contains("shape"), "{m}");
        // Different spacings.
        let m = message(
            &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,3e-6,0,2e-6\n"),
            &[("a.npy", z()), ("b.npy", z())],
        );
        assert!(m.contains("tiles/b.npy") && m.contains("pixel_m"), "{m}");
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
        assert!(m.contains("tiles/a.npy") && m.contains("NaN"), "{m}");
        // A bad number, with its line, and a missing column.
        let m = message(&format!("{head}0,a.npy,zero,0,1e-6\n"), &[("a.npy", z())]);
        assert!(m.contains("line 2") && m.contains("x_m"), "{m}");
        let m = message("tile,file,x_m,pixel_m\n0,a.npy,0,1e-6\n", &[("a.npy", z())]);
        assert!(m.contains("y_m"), "{m}");
        // An unknown format.
        let m = message(&format!("{head}0,a.x3p,0,0,1e-6\n"), &[]);
        assert!(m.contains("a.x3p") && m.contains(".x3p"), "{m}");
    }
}
