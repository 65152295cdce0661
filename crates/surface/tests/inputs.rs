//! The surface stage on bad inputs (clear errors naming the file) and on
//! real instrument maps (`data/reference/topography/`).

use std::path::PathBuf;

use crate::common;

use common::{npy, run};
use hypercontact_core::{Field, Files, Inputs, Product};
use hypercontact_surface::surface_stage::{ReferenceKind, SurfaceParams};
use ndarray::Array2;

fn rough(n: usize, seed: f64) -> Array2<f64> {
    Array2::from_shape_fn((n, n), |(i, j)| {
        1e-6 * ((i as f64 * 0.37 + seed).sin() * (j as f64 * 0.23).cos()
            + (i as f64 * j as f64 * 0.01 + seed).sin())
    })
}

fn tiles(csv: &str, tiles: Vec<(&str, Array2<f64>)>) -> Inputs {
    let mut files = Files::new().with("positions.csv", csv.as_bytes().to_vec());
    for (name, values) in tiles {
        files = files.with(name, npy(&values));
    }
    Inputs::new().with("tiles", Product::Files(files))
}

#[test]
fn bad_inputs_are_clear_errors_naming_the_file() {
    let p = SurfaceParams {
        resolution_m: 0.0,
        ..Default::default()
    };
    let head = "tile,file,x_m,y_m,pixel_m\n";
    let message = |inputs: Inputs| run(&p, inputs).unwrap_err().to_string();

    // A tile with no overlap to any other.
    let m = message(tiles(
        &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,1e-6\n2,c.npy,0,500e-6,1e-6\n"),
        vec![
            ("a.npy", rough(64, 0.0)),
            ("b.npy", rough(64, 1.0)),
            ("c.npy", rough(64, 2.0)),
        ],
    ));
    assert!(
        m.contains("c.npy") && m.contains("overlaps no other tile"),
        "{m}"
    );
    // Tiles of different shapes, and of different spacings.
    let m = message(tiles(
        &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,1e-6\n"),
        vec![("a.npy", rough(64, 0.0)), ("b.npy", rough(60, 1.0))],
    ));
    assert!(m.contains("b.npy") && m.contains("shape"), "{m}");
    let m = message(tiles(
        &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,2e-6\n"),
        vec![("a.npy", rough(64, 0.0)), ("b.npy", rough(64, 1.0))],
    ));
    assert!(m.contains("b.npy") && m.contains("spacing"), "{m}");
    // A positions file that does not match the tiles.
    let m = message(tiles(
        &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,1e-6\n"),
        vec![("a.npy", rough(64, 0.0)), ("B.npy", rough(64, 1.0))],
    ));
    assert!(
        m.contains("positions.csv") && m.contains("does not match"),
        "{m}"
    );
    // An all-NaN tile.
    let m = message(tiles(
        &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,1e-6\n"),
        vec![
            ("a.npy", rough(64, 0.0)),
            ("b.npy", Array2::from_elem((64, 64), f64::NAN)),
        ],
    ));
    assert!(m.contains("b.npy") && m.contains("NaN"), "{m}");
    // No source, two sources, a folder that does not exist.
    let m = message(Inputs::new());
    assert!(m.contains("exactly one source"), "{m}");
    let two = SurfaceParams {
        dir: Some("x".into()),
        ..p.clone()
    };
    let m = run(
        &two,
        tiles(
            &format!("{head}0,a.npy,0,0,1e-6\n"),
            vec![("a.npy", rough(64, 0.0))],
        ),
    )
    .unwrap_err()
    .to_string();
    assert!(m.contains("exactly one source"), "{m}");
    let missing = SurfaceParams {
        dir: Some("/nonexistent/scan".into()),
        ..p.clone()
    };
    let m = run(&missing, Inputs::new()).unwrap_err().to_string();
    assert!(
        m.contains("/nonexistent/scan") && m.contains("No such file"),
        "{m}"
    );
}

fn reference(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/reference/topography")
        .join(name)
}

#[test]
fn real_maps_give_finite_psd_and_stats() {
    for (name, nan_points, measured, filtered) in [
        ("sur-2", 117, (563, 484, 3.4840002190321683e-06), (98, 85)),
        (
            "metropro-1",
            0,
            (640, 480, 1.0982520279867458e-06),
            (36, 27),
        ),
    ] {
        for resolution_m in [0.0, 20e-6] {
            let p = SurfaceParams {
                dir: Some(reference(name).into()),
                resolution_m,
                reference: ReferenceKind::Percentile,
                ..Default::default()
            };
            let out = run(&p, Inputs::new()).unwrap_or_else(|e| panic!("{name}: {e}"));
            let Some(Product::Table(stats)) = out.get("stats") else {
                panic!("no stats")
            };
            let Some(Product::Table(psd)) = out.get("psd") else {
                panic!("no psd")
            };
            let Some(Product::Field(height)) = out.get("height") else {
                panic!("no height")
            };
            for column in [
                "sigma_m",
                "rms_slope",
                "hurst_x",
                "hurst_y",
                "hurst_radial",
                "dx_m",
            ] {
                let v = stats.f64(column).unwrap()[0];
                assert!(v.is_finite(), "{name} at {resolution_m} m: {column} = {v}");
            }
            assert!(
                psd.f64("c")
                    .unwrap()
                    .iter()
                    .all(|c| c.is_finite() && *c >= 0.0)
            );
            for d in ["x", "y", "radial"] {
                let text = |c: &str| stats.str(&format!("hurst_{d}{c}")).unwrap()[0].clone();
                let number = |c: &str| stats.f64(&format!("hurst_{d}{c}")).unwrap()[0];
                eprintln!(
                    "{name} at {resolution_m} m, {d}: H {:.3}, R² {:.3}, {}",
                    number(""),
                    number("_r2"),
                    text("_flag")
                );
            }
            // The grid before and after filtering: ⌊(n − 1)·dx / 20 µm⌋ + 1 points
            // (issue #17: 36 × 27 for metropro-1).
            let grid = |n: &str| stats.i64(n).unwrap()[0] as usize;
            let spacing = |n: &str| stats.f64(n).unwrap()[0];
            assert_eq!(
                (grid("nx_measured"), grid("ny_measured")),
                (measured.0, measured.1)
            );
            assert_eq!(spacing("dx_measured_m"), measured.2);
            assert_eq!(spacing("dy_measured_m"), measured.2);
            let (nx, ny, d) = if resolution_m == 0.0 {
                measured
            } else {
                (filtered.0, filtered.1, resolution_m)
            };
            assert_eq!((grid("nx"), grid("ny")), (nx, ny), "{name}");
            assert_eq!((spacing("dx_m"), spacing("dy_m")), (d, d));
            let nan = height.values.iter().filter(|v| v.is_nan()).count();
            let fraction = stats.f64("nan_fraction").unwrap()[0];
            assert_eq!(fraction, nan as f64 / height.values.len() as f64);
            if resolution_m == 0.0 {
                // The measured grid is kept with its gaps, and a single tile is not moved.
                assert_eq!(nan, nan_points, "{name}");
                let Some(Product::Table(stitch)) = out.get("stitch") else {
                    panic!("no stitch")
                };
                assert_eq!(stitch.f64("x_offset_px").unwrap(), &[0.0]);
            } else {
                // Gaps are mostly filled by the filter (a cluster may stay).
                assert!(nan * 10 < nan_points.max(1), "{name}: {nan} NaN left");
                assert_eq!(height.dx_m, 20e-6);
            }
        }
    }
}

#[test]
fn a_stitched_map_can_come_from_the_height_input() {
    let map = Field::new(rough(128, 0.5), 1e-6, 1e-6).unwrap();
    let p = SurfaceParams {
        resolution_m: 0.0,
        ..Default::default()
    };
    let out = run(&p, Inputs::new().with("height", Product::Field(map))).unwrap();
    let Some(Product::Table(stitch)) = out.get("stitch") else {
        panic!("no stitch")
    };
    assert_eq!(stitch.n_rows(), 0);
    let Some(Product::Field(h)) = out.get("height") else {
        panic!("no height")
    };
    assert_eq!(h.values.dim(), (128, 128));
}

#[test]
fn a_flat_map_is_refused_naming_its_source() {
    let p = SurfaceParams {
        resolution_m: 0.0,
        ..Default::default()
    };
    // Constant tiles stitch into a constant map: σ was rounding noise
    // (8e-23 m) and the Hurst exponents nonsense (−0.59, 2.35).
    let head = "tile,file,x_m,y_m,pixel_m\n";
    let m = run(
        &p,
        tiles(
            &format!("{head}0,a.npy,0,0,1e-6\n1,b.npy,48e-6,0,1e-6\n"),
            vec![
                ("a.npy", Array2::from_elem((64, 64), 3e-6)),
                ("b.npy", Array2::from_elem((64, 64), 3e-6)),
            ],
        ),
    )
    .unwrap_err()
    .to_string();
    assert!(m.contains("input `tiles`") && m.contains("flat"), "{m}");
    // A tilted plane is as flat once the plane is removed; so is zero.
    let plane = Array2::from_shape_fn((64, 64), |(i, j)| 1e-3 + 2e-7 * i as f64 - 1e-7 * j as f64);
    for values in [plane, Array2::zeros((64, 64))] {
        let field = Field::new(values, 1e-6, 1e-6).unwrap();
        let m = run(&p, Inputs::new().with("height", Product::Field(field)))
            .unwrap_err()
            .to_string();
        assert!(m.contains("input `height`") && m.contains("flat"), "{m}");
    }
    // A rough map with a large offset is not flat.
    let offset = rough(64, 0.0).mapv(|h| h + 1e-2);
    let field = Field::new(offset, 1e-6, 1e-6).unwrap();
    run(&p, Inputs::new().with("height", Product::Field(field))).unwrap();
}

#[test]
fn overflowing_heights_are_named_not_blamed_on_the_hurst_range() {
    let p = SurfaceParams {
        resolution_m: 0.0,
        ..Default::default()
    };
    // σ² overflows from 1e154 on; the PSD (dx·dy times that) a bit later,
    // where it used to say "too few PSD points (10) … widen
    // hurst_lambda_min_m / hurst_lambda_max_m".
    for scale in [1e155, 1e160, 1e200] {
        let field = Field::new(rough(64, 0.0).mapv(|h| h * scale), 1e-6, 1e-6).unwrap();
        let m = run(&p, Inputs::new().with("height", Product::Field(field)))
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("input `height`") && m.contains("overflow") && !m.contains("Hurst"),
            "{m}"
        );
    }
    // Large but representable heights still go through; their fourth
    // powers overflow, so the ISO 25178 table is NaN (with a warning).
    let field = Field::new(rough(64, 0.0).mapv(|h| h * 1e140), 1e-6, 1e-6).unwrap();
    let out = run(&p, Inputs::new().with("height", Product::Field(field))).unwrap();
    let Some(Product::Table(areal)) = out.get("areal") else {
        panic!("no areal table")
    };
    assert!(areal.f64("sku").unwrap()[0].is_nan());
}
