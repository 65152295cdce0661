//! Property tests of the tile-set readers: `positions.csv` edited (bad and
//! extreme values, broken lines, changed bytes) and tiles with changed
//! bytes, through the tile reader and the whole `surface` stage. Never a
//! panic; every error names a file of the set, or the stage's input.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property;
//! `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen or move the search.

use crate::common;

use common::npy;
use hypercontact_core::{Files, Inputs, Outputs, Product, StageError};
use hypercontact_fuzz::{config, splice};
use hypercontact_labfiles::FileSource;
use hypercontact_surface::surface_stage::SurfaceParams;
use hypercontact_surface::tiles::{POSITIONS, read_tiles};
use ndarray::Array2;
use proptest::prelude::*;

const SIDE: usize = 40;
const PIXEL_M: f64 = 1e-6;
/// Tile pitch: 24 px, so neighbours overlap by 16 px.
const PITCH: usize = 24;

/// positions.csv rows as cells, and the tile files by name.
type TileSet = (Vec<[String; 5]>, Vec<(String, Vec<u8>)>);

/// A 2 × 2 tile set cut from one surface.
fn valid_set() -> TileSet {
    let big = Array2::from_shape_fn((SIDE + PITCH, SIDE + PITCH), |(i, j)| {
        let (x, y) = (i as f64 * 0.31, j as f64 * 0.27);
        1e-6 * ((x.sin() * y.cos()) + (0.37 * x * y).sin() + 0.3 * (2.1 * x + 1.3 * y).cos())
    });
    let mut rows = Vec::new();
    let mut tiles = Vec::new();
    for t in 0..4 {
        let (ox, oy) = ((t % 2) * PITCH, (t / 2) * PITCH);
        let tile = Array2::from_shape_fn((SIDE, SIDE), |(i, j)| big[[ox + i, oy + j]]);
        let name = format!("tile_{t:03}.npy");
        rows.push([
            t.to_string(),
            name.clone(),
            (ox as f64 * PIXEL_M).to_string(),
            (oy as f64 * PIXEL_M).to_string(),
            PIXEL_M.to_string(),
        ]);
        tiles.push((name, npy(&tile)));
    }
    (rows, tiles)
}

fn positions_text(rows: &[[String; 5]]) -> String {
    let mut text = "# scanner export\ntile,file,x_m,y_m,pixel_m\n".to_owned();
    for row in rows {
        text.push_str(&row.join(","));
        text.push('\n');
    }
    text
}

/// Values that break a positions file, or stretch a reader.
fn bad_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("NaN".into()),
        Just("inf".into()),
        Just("-1e300".into()),
        Just("1e300".into()),
        Just("1e-300".into()),
        Just("0".into()),
        Just("-0".into()),
        Just("1e5".into()),
        Just("-5e-6".into()),
        Just("9223372036854775808".into()),
        Just("-1".into()),
        Just("tile_000.npy".into()),
        Just("tile_009.npy".into()),
        Just("../x.npy".into()),
        Just("a.x3p".into()),
        Just("\"".into()),
        "[ -~]{0,6}",
    ]
}

#[derive(Clone, Debug)]
enum Edit {
    Cell(usize, usize, String),
    Delete(usize),
    Double(usize),
    /// Bytes of tile `t` spliced: (tile, at, remove, insert).
    Tile(usize, usize, usize, Vec<u8>),
    DropTile(usize),
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    prop::collection::vec(
        prop_oneof![
            2 => (any::<usize>(), 0usize..5, bad_token()).prop_map(|(r, c, t)| Edit::Cell(r, c, t)),
            // A position moved by up to 30 pixels: still a tile set.
            3 => (any::<usize>(), 2usize..4, -30.0f64..30.0)
                .prop_map(|(r, c, px)| Edit::Cell(r, c, (px * PIXEL_M).to_string())),
            1 => any::<usize>().prop_map(Edit::Delete),
            1 => any::<usize>().prop_map(Edit::Double),
            // Bytes of a tile overwritten in place (heights changed, or
            // its header), or spliced (its length changed).
            3 => (0usize..4, any::<usize>(), prop::collection::vec(any::<u8>(), 1..4))
                .prop_map(|(t, at, bytes)| Edit::Tile(t, at, bytes.len(), bytes)),
            1 => (
                0usize..4,
                any::<usize>(),
                prop_oneof![Just(0usize), 1usize..4, 0usize..400],
                prop::collection::vec(any::<u8>(), 0..4),
            )
                .prop_map(|(t, at, remove, insert)| Edit::Tile(t, at, remove, insert)),
            1 => (0usize..4).prop_map(Edit::DropTile),
        ],
        1..3,
    )
}

/// The edited set as a `Files` product, and the names of its files.
fn edited(edits: &[Edit]) -> Files {
    let (mut rows, mut tiles) = valid_set();
    for edit in edits {
        match edit {
            Edit::Cell(r, c, token) if !rows.is_empty() => {
                let n = rows.len();
                rows[r % n][*c] = token.clone();
            }
            Edit::Delete(r) if !rows.is_empty() => {
                let n = rows.len();
                rows.remove(r % n);
            }
            Edit::Double(r) if !rows.is_empty() => {
                let n = rows.len();
                let row = rows[r % n].clone();
                rows.push(row);
            }
            Edit::Tile(t, at, remove, insert) => {
                let bytes = std::mem::take(&mut tiles[*t].1);
                tiles[*t].1 = splice(bytes, &[(*at, *remove, insert.clone())]);
            }
            Edit::DropTile(t) => tiles[*t].1.clear(),
            _ => {}
        }
    }
    let mut files = Files::new().with(POSITIONS, positions_text(&rows).into_bytes());
    for (name, bytes) in tiles {
        if !bytes.is_empty() {
            files = files.with(&name, bytes);
        }
    }
    files
}

/// The stage on the set at its measured grid.
fn stage(files: Files) -> Result<Outputs, StageError> {
    let p = SurfaceParams {
        resolution_m: 0.0,
        ..Default::default()
    };
    common::run(&p, Inputs::new().with("tiles", Product::Files(files)))
}

/// An error of the tile set must name `positions.csv`, a tile file or the
/// input the set came from.
fn names_a_file(message: &str) -> bool {
    message.contains(POSITIONS)
        || message.contains(".npy")
        || message.contains(".x3p")
        || message.contains("input `tiles`")
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn edited_tile_sets_never_panic_in_the_reader(edits in edits()) {
        let files = edited(&edits);
        let source = FileSource::Files { files: &files, input: "tiles".into() };
        if let Err(e) = read_tiles(&source) {
            let message = e.to_string();
            prop_assert!(names_a_file(&message), "{}", message);
        }
    }

    #[test]
    fn edited_tile_sets_never_panic_in_the_stage(edits in edits()) {
        // Errors past reading (a mosaic that falls apart, a singular
        // system) concern the set as a whole; reading errors name a file.
        let _ = stage(edited(&edits));
    }
}

#[test]
fn the_valid_set_runs_through_the_stage() {
    let out = stage(edited(&[])).unwrap();
    let Some(Product::Field(height)) = out.get("height") else {
        panic!("no height")
    };
    assert_eq!(height.values.dim(), (SIDE + PITCH, SIDE + PITCH));
}

/// The fuzzer's first find: one tile at x = −1e300 m made the pair overlap
/// arithmetic wrap around i64 and index a tile out of bounds.
#[test]
fn a_position_far_beyond_the_scan_is_an_error_not_a_panic() {
    let message = stage(edited(&[Edit::Cell(0, 2, "-1e300".into())]))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("positions.csv") && message.contains("line 3") && message.contains("x_m"),
        "{message}"
    );
}

/// The fuzzer's second find: three bytes of tile_000.npy changed make one
/// height 1.8e159; the sub-pixel refinement's normal equations overflowed to
/// a NaN shift, whose interpolation stencil indexed out of bounds.
#[test]
fn a_huge_height_in_a_tile_is_no_panic() {
    let _ = stage(edited(&[Edit::Tile(
        0,
        8_330_844_503_619_979_490,
        3,
        vec![0, 97, 0],
    )]));
}
