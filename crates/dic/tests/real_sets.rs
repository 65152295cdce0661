//! A lab's own image set, as it comes off the camera: a folder of 16-bit
//! TIFFs holding 12-bit counts, no frames.csv (natural order of the names,
//! times from `frame_rate_hz`), no force.csv, a specimen stretched along
//! the image's y axis (λ_y to 1.08, λ_x = λ_y^−½) with an open hole at the
//! centre, cut out by a mask image. Checked against the rendering map:
//! gauge stretch and strain per frame, and u, v, Green–Lagrange E at every
//! point of the `field` table; and the seeding with the hole not masked,
//! where the old centre-nearest seeds all fell in the featureless hole.

use std::path::{Path, PathBuf};

use hypercontact_core::{Context, Files, Inputs, Params, Product, Stage, Table};
use hypercontact_dic::sequence::Sequence;
use hypercontact_dic::stage::analyse;
use hypercontact_dic::{Dic, DicParams, LoadingAxis};

use hypercontact_synth::tensile::open_hole::{CENTRE, FILE_NUMBERS, HOLE_PX, STRETCH_Y, stretch_x};

/// The set (`hypercontact_synth::tensile::open_hole`).
fn files() -> Files {
    hypercontact_synth::tensile::open_hole::files().unwrap()
}

fn folder(files: &Files, tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hc-dic-real-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in &files.files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    dir
}

fn params(dir: &Path) -> DicParams {
    DicParams {
        dir: Some(dir.to_path_buf().into()),
        mode: Some(hypercontact_core::Mode::Uniaxial),
        pixel_m: Some(1e-5),
        roi_px: Some([16, 16, 239, 239]),
        mask: Some("mask.png".into()),
        subset_px: 21,
        step_px: 8,
        frame_rate_hz: Some(10.0),
        bit_depth: Some(12),
        loading_axis: LoadingAxis::Y,
        ..Default::default()
    }
}

/// Runs the stage on a folder: its tables and notes.
fn run(p: &DicParams) -> (Table, Table, Vec<String>) {
    let checked = p.clone().check().unwrap();
    let out = Dic
        .run(&checked, &Inputs::new(), &Context::new("dic"))
        .unwrap();
    let (Some(Product::Table(tensile)), Some(Product::Table(field))) =
        (out.get("tensile"), out.get("field"))
    else {
        panic!("no tables")
    };
    // The notes, from the analysis itself.
    let source = hypercontact_labfiles::FileSource::Dir(p.dir.as_ref().unwrap().path().to_owned());
    let sequence = Sequence::open(source, p.frame_rate_hz, p.mask.as_deref()).unwrap();
    let notes = analyse(&sequence, &checked, &Context::new("dic"))
        .unwrap()
        .notes;
    (tensile.clone(), field.clone(), notes)
}

#[test]
fn a_folder_of_12_bit_tiffs_without_logs_gives_stretch_strain_and_fields() {
    let files = files();
    let dir = folder(&files, "whole");
    let (tensile, field, notes) = run(&params(&dir));

    // Gauge values: frames in natural order at k / 10 Hz.
    assert_eq!(tensile.i64("frame").unwrap(), &FILE_NUMBERS);
    let time = tensile.f64("time_s").unwrap();
    for (k, t) in time.iter().enumerate() {
        assert!((t - k as f64 / 10.0).abs() < 1e-12, "{t}");
    }
    let stretch = tensile.f64("stretch").unwrap();
    let stretch_2 = tensile.f64("stretch_2").unwrap();
    let strain = tensile.f64("strain").unwrap();
    let mut worst: f64 = 0.0;
    for (k, &l) in STRETCH_Y.iter().enumerate() {
        worst = worst
            .max((stretch[k] - l).abs())
            .max((stretch_2[k] - stretch_x(l)).abs());
        assert!((strain[k] - (stretch[k] - 1.0)).abs() < 1e-15);
    }
    eprintln!("worst gauge stretch error {worst:.1e}");
    assert!(worst < 3e-4, "worst stretch error {worst}");
    assert!(tensile.f64("force_n").unwrap().iter().all(|f| f.is_nan()));
    assert!(
        tensile
            .f64("nominal_stress_pa")
            .unwrap()
            .iter()
            .all(|s| s.is_nan())
    );
    assert!(
        tensile
            .f64("loading_axis_deg")
            .unwrap()
            .iter()
            .all(|&a| a == 90.0)
    );
    assert!(
        tensile
            .f64("valid_fraction")
            .unwrap()
            .iter()
            .all(|&v| v > 0.98)
    );
    assert!(
        notes.iter().any(|n| n.starts_with("no force.csv")),
        "{notes:?}"
    );
    assert!(!notes.iter().any(|n| n.contains("below 4096")), "{notes:?}");

    // The field: every point of every frame against the map.
    let n = field.n_rows();
    let [frame, x, y, u, v, exx, eyy, exy, zncc] = [
        "frame", "x_px", "y_px", "u_px", "v_px", "exx", "eyy", "exy", "zncc",
    ];
    let frame = field.i64(frame).unwrap();
    let valid = field.i64("valid").unwrap();
    let col = |name| field.f64(name).unwrap();
    let (x, y, u, v) = (col(x), col(y), col(u), col(v));
    let (exx, eyy, exy, zncc) = (col(exx), col(eyy), col(exy), col(zncc));
    assert_eq!(n % STRETCH_Y.len(), 0);
    let per_frame = n / STRETCH_Y.len();
    let (mut worst_u, mut worst_e, mut tracked) = (0.0_f64, 0.0_f64, 0);
    for r in 0..n {
        let k = r / per_frame;
        assert_eq!(frame[r], FILE_NUMBERS[k]);
        // Same grid in every frame.
        assert_eq!((x[r], y[r]), (x[r % per_frame], y[r % per_frame]));
        let in_mask = (x[r] - CENTRE).hypot(y[r] - CENTRE) >= HOLE_PX + 3.0 + 10.0;
        if valid[r] == 0 {
            assert!(u[r].is_nan() && exx[r].is_nan() && zncc[r].is_nan());
            continue;
        }
        // A subset reaching into the masked hole is never tracked.
        assert!(in_mask, "({}, {}) tracked inside the hole", x[r], y[r]);
        tracked += 1;
        let (lx, ly) = (stretch_x(STRETCH_Y[k]), STRETCH_Y[k]);
        let du = (u[r] - (lx - 1.0) * (x[r] - CENTRE)).abs();
        let dv = (v[r] - (ly - 1.0) * (y[r] - CENTRE)).abs();
        worst_u = worst_u.max(du).max(dv);
        let de = (exx[r] - 0.5 * (lx * lx - 1.0))
            .abs()
            .max((eyy[r] - 0.5 * (ly * ly - 1.0)).abs())
            .max(exy[r].abs());
        worst_e = worst_e.max(de);
        assert!(zncc[r] >= 0.9 && zncc[r] <= 1.0 + 1e-12, "{}", zncc[r]);
    }
    let active = valid[..per_frame].iter().sum::<i64>() as usize;
    eprintln!(
        "{per_frame} grid points, {active} in the region; {tracked} tracked point-frames; worst \
         |u − u_true| {worst_u:.1e} px, worst |E − E_true| {worst_e:.1e}"
    );
    assert!(tracked as f64 >= 0.98 * (active * STRETCH_Y.len()) as f64);
    assert!(active > 400 && active < per_frame);
    assert!(worst_u < 0.02, "worst displacement error {worst_u} px");
    assert!(worst_e < 1e-3, "worst strain error {worst_e}");

    // Without `bit_depth`, counts are of 65535 (the same fit: ZNCC is
    // blind to the scale) and a note says the camera may be shallower.
    let (tensile_16, _, notes) = run(&DicParams {
        bit_depth: None,
        ..params(&dir)
    });
    assert!(
        notes
            .iter()
            .any(|n| n.contains("largest count is") && n.contains("`bit_depth`"))
    );
    let s16 = tensile_16.f64("stretch").unwrap();
    for k in 0..STRETCH_Y.len() {
        assert!((s16[k] - stretch[k]).abs() < 1e-9);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_loading_axis_picks_the_stretch() {
    let dir = folder(&files(), "axis");
    let (along_x, _, _) = run(&DicParams {
        loading_axis: LoadingAxis::X,
        ..params(&dir)
    });
    let (principal, _, notes) = run(&DicParams {
        loading_axis: LoadingAxis::Principal,
        ..params(&dir)
    });
    let l = STRETCH_Y[4];
    let x = along_x.f64("stretch").unwrap()[4];
    assert!((x - stretch_x(l)).abs() < 3e-4, "{x}");
    assert_eq!(along_x.f64("loading_axis_deg").unwrap()[0], 0.0);
    let p = principal.f64("stretch").unwrap()[4];
    assert!((p - l).abs() < 3e-4, "{p}");
    let deg = principal.f64("loading_axis_deg").unwrap()[0];
    assert!((deg.abs() - 90.0).abs() < 0.5, "{deg}");
    assert!(
        notes
            .iter()
            .any(|n| n.starts_with("loading axis: the final frame's largest principal")),
        "{notes:?}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn seeds_spread_over_the_region_find_the_speckle_around_an_unmasked_hole() {
    // No mask: the POIs nearest the centre (where the old seeding looked)
    // see only the featureless hole and cannot correlate.
    let mut files = files();
    files.files.remove("mask.png");
    let dir = folder(&files, "seed");
    let (tensile, field, _) = run(&DicParams {
        mask: None,
        ..params(&dir)
    });
    let stretch = tensile.f64("stretch").unwrap();
    for (k, &l) in STRETCH_Y.iter().enumerate() {
        assert!(
            (stretch[k] - l).abs() < 3e-4,
            "frame {k}: {} vs {l}",
            stretch[k]
        );
    }
    // Everything outside the hole is found; the hole's own POIs are not.
    let (x, y) = (field.f64("x_px").unwrap(), field.f64("y_px").unwrap());
    let valid = field.i64("valid").unwrap();
    let per_frame = valid.len() / STRETCH_Y.len();
    let last = (STRETCH_Y.len() - 1) * per_frame;
    for i in 0..per_frame {
        let r = (x[i] - CENTRE).hypot(y[i] - CENTRE);
        if r > HOLE_PX + 16.0 {
            assert_eq!(valid[last + i], 1, "({}, {})", x[i], y[i]);
        }
        if r < HOLE_PX - 16.0 {
            assert_eq!(valid[last + i], 0, "({}, {})", x[i], y[i]);
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_region_that_holds_no_subset_names_the_parameter() {
    let dir = folder(&files(), "small");
    let p = DicParams {
        // A diagonal band about 10 px wide: a large bounding box, but no
        // 21 px square inside.
        roi_polygon_px: Some(vec![
            [30.0, 30.0],
            [45.0, 30.0],
            [230.0, 215.0],
            [230.0, 230.0],
            [215.0, 230.0],
            [30.0, 45.0],
        ]),
        ..params(&dir)
    };
    let e = error_of(p);
    assert!(
        e.contains("`roi_px`") && e.contains("whole 21 px subset"),
        "{e}"
    );
    // A mask beside the frames but not named is not taken for a frame.
    let p = DicParams {
        mask: None,
        ..params(&dir)
    };
    let e = error_of(p);
    assert!(
        e.contains("mask.png: would be read as a frame: name it in the parameter `mask`"),
        "{e}"
    );
    std::fs::remove_file(dir.join("mask.png")).unwrap();
    let p = DicParams {
        roi_px: None,
        mask: None,
        ..params(&dir)
    };
    let e = error_of(p);
    assert!(
        e.contains("`roi_px`: is needed") && e.contains("roi_polygon_px"),
        "{e}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The stage's error on parameters `p`.
fn error_of(p: DicParams) -> String {
    Dic.run(&p.check().unwrap(), &Inputs::new(), &Context::new("dic"))
        .unwrap_err()
        .to_string()
}
