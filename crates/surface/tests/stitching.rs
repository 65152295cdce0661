//! Stitching synthetic interferometer tiles against their ground truth,
//! and the stage end to end: synth-surface → surface.

use crate::common;

use hypercontact_core::{Context, Inputs, Params, Product, Schema, Stage};
use hypercontact_labfiles::FileSource;
use hypercontact_surface::stitch::stitch;
use hypercontact_surface::surface_stage::{Surface, SurfaceParams};
use hypercontact_surface::tiles::read_tiles;
use hypercontact_synth::surface::{SynthSurface, SynthSurfaceParams, synthesise};
use ndarray::Array2;

#[test]

fn stitching_recovers_offsets_and_the_true_surface() {
    let p = SynthSurfaceParams {
        position_error_px: 4.0,
        seed: 7,
        ..Default::default()
    }
    .check()
    .unwrap();
    let scan = synthesise(&p).unwrap();
    let files = scan.files().unwrap();
    let set = read_tiles(&FileSource::Files {
        files: &files,
        input: "tiles".into(),
    })
    .unwrap();
    let mosaic = stitch(&set, 16).unwrap();

    // Offsets, up to one common translation (the gauge).
    let n = scan.tiles.len();
    let found: Vec<[f64; 2]> = mosaic
        .tiles
        .iter()
        .map(|t| {
            [
                t.found_px[0] - t.nominal_px[0],
                t.found_px[1] - t.nominal_px[1],
            ]
        })
        .collect();
    let truth: Vec<[f64; 2]> = scan
        .tiles
        .iter()
        .map(|t| t.offset_px.map(|v| v as f64))
        .collect();
    assert!(
        truth.iter().any(|t| t[0] != 0.0 || t[1] != 0.0),
        "the test needs position errors"
    );
    eprintln!("found {found:?}\ntruth {truth:?}");
    for a in 0..2 {
        let shift = (0..n).map(|t| found[t][a] - truth[t][a]).sum::<f64>() / n as f64;
        for t in 0..n {
            let error = found[t][a] - truth[t][a] - shift;
            assert!(error.abs() < 0.1, "tile {t} axis {a}: off by {error} px");
        }
    }
    for t in &mosaic.tiles {
        assert!(t.correlation > 0.9, "overlap correlation {}", t.correlation);
    }

    // The map against the truth: mosaic pixel X of tile 0's found position
    // is truth pixel x_truth of tile 0.
    let origin = [0, 1].map(|a| {
        mosaic
            .tiles
            .iter()
            .map(|t| t.found_px[a].round() as i64)
            .min()
            .unwrap()
    });
    let t0 = [0, 1].map(|a| mosaic.tiles[0].found_px[a].round() as i64 - origin[a]);
    let truth0 = scan.tiles[0].truth_px.map(|v| v as i64);
    let (tx, ty) = scan.truth.values.dim();
    let mut diffs = Vec::new();
    for ((x, y), &h) in mosaic.heights.indexed_iter() {
        let (u, v) = (x as i64 - t0[0] + truth0[0], y as i64 - t0[1] + truth0[1]);
        if h.is_nan() || u < 0 || v < 0 || u >= tx as i64 || v >= ty as i64 {
            continue;
        }
        diffs.push((
            x as f64,
            y as f64,
            h - scan.truth.values[[u as usize, v as usize]],
        ));
    }
    assert!(diffs.len() > mosaic.heights.len() * 8 / 10);
    // Levelling fixes every tile's plane up to one common plane: remove it.
    let residual = without_plane(&diffs);
    let rms = (residual.iter().map(|r| r * r).sum::<f64>() / residual.len() as f64).sqrt();
    assert!(
        rms < 1.5 * p.noise_m,
        "rms misfit {rms} m vs noise {} m",
        p.noise_m
    );
    let sigma = (scan.truth.values.iter().map(|h| h * h).sum::<f64>()
        / scan.truth.values.len() as f64)
        .sqrt();
    assert!(
        sigma > 500.0 * p.noise_m,
        "the surface must dwarf the noise"
    );
}

fn without_plane(points: &[(f64, f64, f64)]) -> Vec<f64> {
    let mut h = Array2::from_elem((1, points.len()), 0.0);
    // Least squares by the 3 × 3 normal equations.
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for &(x, y, d) in points {
        let b = [1.0, x, y];
        for p in 0..3 {
            r[p] += b[p] * d;
            for q in 0..3 {
                m[p][q] += b[p] * b[q];
            }
        }
    }
    let c = hypercontact_surface::plane::solve3(m, r).unwrap();
    for (k, &(x, y, d)) in points.iter().enumerate() {
        h[[0, k]] = d - c[0] - c[1] * x - c[2] * y;
    }
    h.into_iter().collect()
}

#[test]
fn synth_then_surface_stage_gives_report_tables() {
    let synth = SynthSurface
        .run(
            &SynthSurfaceParams::default().check().unwrap(),
            &Inputs::new(),
            &Context::new("synth"),
        )
        .unwrap();
    let Some(Product::Files(tiles)) = synth.get("tiles") else {
        panic!("no tiles")
    };
    let params = SurfaceParams {
        resolution_m: 5e-6,
        ..Default::default()
    };
    let out = common::run(
        &params,
        Inputs::new().with("tiles", Product::Files(tiles.clone())),
    )
    .unwrap();
    let info = Surface.info();
    for name in ["psd", "stats", "stitch"] {
        let Some(Product::Table(t)) = out.get(name) else {
            panic!("no {name}")
        };
        t.conform(info.output(name).unwrap().columns).unwrap();
    }
    let Some(Product::Table(stats)) = out.get("stats") else {
        unreachable!()
    };
    let Some(Product::Field(height)) = out.get("height") else {
        panic!("no height")
    };
    assert_eq!(height.dx_m, 5e-6);
    // Lowest point is the reference.
    let lowest = height
        .values
        .iter()
        .copied()
        .filter(|v| !v.is_nan())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(lowest, 0.0);
    assert_eq!(stats.i64("nx").unwrap()[0] as usize, height.nx());
    // The synthetic surface (H = 0.8, rms 5 µm before cropping and filtering).
    let sigma = stats.f64("sigma_m").unwrap()[0];
    assert!(sigma > 1e-6 && sigma < 8e-6, "σ {sigma}");
    for column in ["hurst_x", "hurst_y", "hurst_radial"] {
        let h = stats.f64(column).unwrap()[0];
        assert!((0.5..1.1).contains(&h), "{column} = {h}");
    }
    let Some(Product::Table(psd)) = out.get("psd") else {
        unreachable!()
    };
    let directions = psd.str("direction").unwrap();
    for d in ["x", "y", "radial"] {
        assert!(directions.iter().filter(|v| *v == d).count() > 5);
    }
    assert!(
        psd.f64("c")
            .unwrap()
            .iter()
            .all(|c| c.is_finite() && *c >= 0.0)
    );
}

/// Issue 17: a lab's tiles in an instrument format, placed by the stage
/// positions the files record (X3P's CX/CY offsets) with no positions.csv,
/// stitch to the same map, bit for bit, as the same tiles as `.npy` with
/// positions.csv; positions.csv without `pixel_m` takes the files' spacing.
#[test]
fn x3p_tiles_placed_by_their_own_offsets_stitch_like_npy_with_positions() {
    use hypercontact_core::{Files, Table};
    use hypercontact_formats::{Format, Topography, write_x3p};

    let p = SynthSurfaceParams {
        position_error_px: 3.0,
        seed: 5,
        ..Default::default()
    }
    .check()
    .unwrap();
    let npy_files = synthesise(&p).unwrap().files().unwrap();
    let set = read_tiles(&FileSource::Files {
        files: &npy_files,
        input: "tiles".into(),
    })
    .unwrap();
    let mut x3p_files = Files::new();
    let mut csv = String::from("tile,file,x_m,y_m\n");
    for (k, name) in set.names.iter().enumerate() {
        let [x_m, y_m] = set.nominal_px[k].map(|px| px * set.pixel_m);
        let tile = Topography {
            heights_m: set.heights[k].to_owned(),
            dx_m: set.pixel_m,
            dy_m: set.pixel_m,
            format: Format::X3p,
            position_m: Some((x_m, y_m)),
            metadata: Vec::new(),
        };
        let x3p_name = name.replace(".npy", ".x3p");
        csv.push_str(&format!("{},{x3p_name},{x_m:e},{y_m:e}\n", set.ids[k]));
        x3p_files = x3p_files.with(&x3p_name, write_x3p(&tile).unwrap());
    }
    let listed = x3p_files.clone().with("positions.csv", csv.into_bytes());

    let run = |files: &Files| -> (Table, Vec<f64>) {
        let inputs = Inputs::new().with("tiles", Product::Files(files.clone()));
        let out = common::run(&SurfaceParams::default(), inputs).unwrap();
        let (Some(Product::Table(stats)), Some(Product::Field(height))) =
            (out.get("stats"), out.get("height"))
        else {
            panic!("no stats or height")
        };
        (stats.clone(), height.values.iter().copied().collect())
    };
    let (npy_stats, npy_height) = run(&npy_files);
    for (what, files) in [("offsets", &x3p_files), ("positions.csv", &listed)] {
        let (stats, height) = run(files);
        assert_eq!(height.len(), npy_height.len(), "{what}");
        assert!(
            height
                .iter()
                .zip(&npy_height)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{what}: the stitched map differs"
        );
        assert_eq!(stats.f64("sigma_m"), npy_stats.f64("sigma_m"), "{what}");
    }

    // The same tiles as a list of files on disk, placed by their offsets or
    // by a positions file given beside the list.
    let dir = std::env::temp_dir().join(format!("hc-x3p-tiles-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in &listed.files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let tile_files: Vec<_> = x3p_files.files.keys().map(|n| dir.join(n).into()).collect();
    for positions in [None, Some(dir.join("positions.csv").into())] {
        let params = SurfaceParams {
            tile_files: tile_files.clone(),
            positions,
            ..Default::default()
        };
        let out = common::run(&params, Inputs::new()).unwrap();
        let Some(Product::Field(height)) = out.get("height") else {
            panic!("no height")
        };
        assert!(
            height
                .values
                .iter()
                .zip(&npy_height)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();

    // `.npy` tiles without positions.csv: what to write, with an example.
    let bare: Files = npy_files
        .files
        .iter()
        .filter(|(name, _)| name.ends_with(".npy"))
        .fold(Files::new(), |f, (name, bytes)| f.with(name, bytes.clone()));
    let inputs = Inputs::new().with("tiles", Product::Files(bare));
    let e = common::run(&SurfaceParams::default(), inputs)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("records no stage position") && e.contains("x_m, y_m, pixel_m"),
        "{e}"
    );
}

/// The products' bits: each field's values, each table as its Debug text
/// (f64's Debug form round-trips).
fn product_bits(out: &hypercontact_core::Outputs) -> Vec<(String, Vec<u64>, String)> {
    out.iter()
        .map(|(name, product)| match product {
            Product::Field(f) => (
                name.to_owned(),
                f.values
                    .iter()
                    .chain([f.dx_m, f.dy_m].iter())
                    .map(|v| v.to_bits())
                    .collect(),
                String::new(),
            ),
            Product::Table(t) => (name.to_owned(), Vec::new(), format!("{t:?}")),
            Product::Files(_) => panic!("surface writes no files"),
        })
        .collect()
}

/// Issue 35: the stage reads tiles in place and makes the mosaic a band of
/// rows at a time as the filter reads it. Its products keep the bits of the
/// old flow, the whole mosaic cropped and analysed as a field, whether the
/// tiles are views (input `tiles`) or decoded (a folder), and a `height`
/// input read a row at a time gives the bits of the same map held whole.
#[test]
fn stitching_in_bands_keeps_the_bits_of_the_whole_mosaic() {
    use hypercontact_core::{Field, InputPath};
    use hypercontact_surface::stitch::covered_region;
    use hypercontact_surface::surface_stage::analyse_named;

    let p = SynthSurfaceParams {
        position_error_px: 3.0,
        dropout_fraction: 0.05,
        seed: 11,
        ..Default::default()
    }
    .check()
    .unwrap();
    let files = synthesise(&p).unwrap().files().unwrap();
    let params = SurfaceParams {
        resolution_m: 4e-6,
        ..Default::default()
    };
    let in_place = common::run(
        &params,
        Inputs::new().with("tiles", Product::Files(files.clone())),
    )
    .unwrap();

    let dir = std::env::temp_dir().join(format!("hc-bands-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in &files.files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let from_dir = common::run(
        &SurfaceParams {
            dir: Some(InputPath::from(dir.clone())),
            ..params.clone()
        },
        Inputs::new(),
    );
    std::fs::remove_dir_all(&dir).unwrap();
    let from_dir = from_dir.unwrap();

    // The old flow: the whole mosaic, cropped, analysed as a field.
    let set = read_tiles(&FileSource::Files {
        files: &files,
        input: "tiles".into(),
    })
    .unwrap();
    let mosaic = stitch(&set, params.min_overlap_px).unwrap();
    let [(x0, x1), (y0, y1)] = covered_region(&mosaic.covered);
    let cropped = Array2::from_shape_fn((x1 - x0, y1 - y0), |(i, j)| {
        mosaic.heights[[x0 + i, y0 + j]]
    });
    let map = Field::new(cropped, set.pixel_m, set.pixel_m).unwrap();
    let checked = params.clone().check().unwrap();
    let whole = analyse_named(
        map.clone(),
        "the map stitched from input `tiles`",
        &checked,
        &Context::new("surface"),
    )
    .unwrap();
    let heights = |out: &hypercontact_core::Outputs| {
        let Some(Product::Field(h)) = out.get("height") else {
            panic!("no height")
        };
        h.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    };
    let expected: Vec<u64> = whole.height.values.iter().map(|v| v.to_bits()).collect();
    assert_eq!(heights(&in_place), expected);
    assert_eq!(
        format!("{:?}", in_place.get("psd")),
        format!("{:?}", Some(Product::Table(whole.psd.into_table())))
    );
    assert_eq!(
        format!("{:?}", in_place.get("stats")),
        format!("{:?}", Some(Product::Table(whole.stats.into_table())))
    );
    assert_eq!(product_bits(&in_place), product_bits(&from_dir));

    // The same map as a `height` input, at the filtered and the measured grid.
    for resolution_m in [4e-6, 0.0] {
        let params = SurfaceParams {
            resolution_m,
            ..Default::default()
        };
        let given = common::run(
            &params,
            Inputs::new().with("height", Product::Field(map.clone())),
        )
        .unwrap();
        let held = analyse_named(
            map.clone(),
            "input `height`",
            &params.clone().check().unwrap(),
            &Context::new("surface"),
        )
        .unwrap();
        let held_bits: Vec<u64> = held.height.values.iter().map(|v| v.to_bits()).collect();
        assert_eq!(heights(&given), held_bits, "resolution_m {resolution_m}");
        assert_eq!(
            format!("{:?}", given.get("stats")),
            format!("{:?}", Some(Product::Table(held.stats.into_table())))
        );
    }
}
