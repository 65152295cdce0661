//! The `contact-images` stage on a sequence rendered by the interference
//! model: a sphere (R = 5 mm) pressed into the glass, its gap field seen
//! through white-light thin-film optics and a noisy, vignetted 16-bit camera
//! whose pixels differ from the gap map's, and a 50 Hz force log on a clock
//! 0.37 s ahead of the camera's. The true contact of each frame is the
//! resampled gap ≤ 0.

use crate::common;

use common::{params, run};
use hypercontact_contact_images::stage::{ContactImagesParams, ContactMapIndex};
use hypercontact_core::{Files, Params, Schema};
use hypercontact_interference::camera::{Camera, CameraParams};
use hypercontact_interference::geometry::{CameraGrid, GapMap, Placement, resample};
use hypercontact_interference::render::{OpticsParams, render_frame};
use hypercontact_labfiles::png::{Pixels, encode_png};
use ndarray::Array2;

const RADIUS_M: f64 = 5e-3;
const MAP_N: usize = 200;
const MAP_DX_M: f64 = 2e-6;
const CAMERA_PX: usize = 160;
const CAMERA_PIXEL_M: f64 = 2.5e-6;
const FRAMES: usize = 12;
const OFFSET_S: f64 = 0.37;

/// Penetration at camera time t: first contact at t = 1.43 s.
fn penetration_m(t_s: f64) -> f64 {
    (-0.5 + 0.35 * t_s) * 1e-6
}

fn gap_map(delta_m: f64) -> Array2<f64> {
    Array2::from_shape_fn((MAP_N, MAP_N), |(i, j)| {
        let x = (i as f64 - (MAP_N as f64 - 1.0) / 2.0) * MAP_DX_M;
        let y = (j as f64 - (MAP_N as f64 - 1.0) / 2.0) * MAP_DX_M;
        ((x * x + y * y) / (2.0 * RADIUS_M) - delta_m).max(0.0)
    })
}

fn grid() -> CameraGrid {
    CameraGrid {
        width_px: CAMERA_PX,
        height_px: CAMERA_PX,
        pixel_m: CAMERA_PIXEL_M,
    }
}

/// The rendered lab: files for the stage and the true area fraction per
/// frame. `bits`: the camera's depth; `scale`: a factor applied to the
/// counts before they are stored in 16-bit PNGs.
fn lab(bits: u32, scale: u16, seed: u64) -> (Files, Vec<f64>) {
    let table = OpticsParams::default().build().unwrap();
    let camera = Camera::new(
        CameraParams {
            bits,
            ..CameraParams::default()
        },
        table.max_reflectance(),
    )
    .unwrap();
    let placement = Placement {
        angle_rad: 0.0,
        shift_x_m: 0.0,
        shift_y_m: 0.0,
    };
    let mut files = Files::new();
    let mut frames_csv = String::from("frame,time_s,file\n");
    let mut truth = Vec::new();
    for k in 0..FRAMES {
        let t = k as f64;
        let field = gap_map(penetration_m(t));
        let gap = GapMap {
            gap_m: field.view(),
            dx_m: MAP_DX_M,
            dy_m: MAP_DX_M,
        };
        let seen = resample(&gap, &placement, &grid()).unwrap();
        truth.push(seen.iter().filter(|g| **g <= 0.0).count() as f64 / seen.len() as f64);
        let frame =
            render_frame(&gap, &placement, &grid(), &table, &camera, seed + k as u64).unwrap();
        let counts: Vec<u16> = frame.counts.iter().map(|c| c * scale).collect();
        let name = format!("frame_{k:03}.png");
        let png = encode_png(CAMERA_PX as u32, CAMERA_PX as u32, Pixels::Gray16(counts)).unwrap();
        files = files.with(&name, png);
        frames_csv.push_str(&format!("{k},{t},{name}\n"));
    }
    // Force: 5 N/µm^1.5 · δ^1.5 on the sensor's clock, 50 Hz from 2 s before
    // the camera's t = 0, 0.002 N of noise, 0.001 N resolution.
    let mut force_csv = String::from("time_s,force_n\n");
    for i in 0..((FRAMES as f64 + 3.0) * 50.0) as usize {
        let t_force = -2.0 + i as f64 / 50.0;
        let delta_um = penetration_m(t_force - OFFSET_S).max(0.0) * 1e6;
        let noise = 0.002 * (((i * 7919) % 17) as f64 / 8.0 - 1.0);
        let f = ((5.0 * delta_um.powf(1.5) + noise) / 0.001).round() * 0.001;
        force_csv.push_str(&format!("{t_force:.4},{f:.3}\n"));
    }
    let files = files
        .with("frames.csv", frames_csv.into_bytes())
        .with("force.csv", force_csv.into_bytes());
    (files, truth)
}

#[test]
fn calibrated_recovers_the_true_area_and_otsu_counts_the_fringes() {
    let (files, truth) = lab(16, 1, 7);
    let (calibrated, sync, maps) = run(&params("{}"), files.clone()).unwrap();
    // Otsu finds "contact" (dim corners) before first contact; the offset
    // is still estimated, from the calibrated view of the frames.
    let (otsu, otsu_sync, _) = run(&params(r#"{"method": "otsu"}"#), files).unwrap();
    assert_eq!(otsu_sync, sync);
    assert!(otsu.area_fraction[0] > 0.0);
    let mut checked = 0;
    for (k, &want) in truth.iter().enumerate() {
        let got = calibrated.area_fraction[k];
        eprintln!(
            "frame {k}: true A/A0 {want:.4}, calibrated {got:.4}, otsu {:.4} ({} patches)",
            otsu.area_fraction[k], calibrated.patches[k]
        );
        if want == 0.0 {
            assert_eq!(got, 0.0, "frame {k}: contact before first contact");
            assert_eq!(calibrated.patches[k], 0);
        } else if (0.02..0.9).contains(&want) {
            checked += 1;
            assert!(
                (got / want - 1.0).abs() < 0.25,
                "frame {k}: {got} vs {want}"
            );
            // One contact disc.
            assert_eq!(calibrated.patches[k], 1, "frame {k}");
            // The paper's global Otsu counts dark fringes and dim corners.
            assert!(otsu.area_fraction[k] > got, "frame {k}");
        }
    }
    assert!(checked >= 8, "{checked} frames checked");
    // The clock offset from first contact, within one frame interval (1 s).
    assert_eq!(sync.estimated, [1]);
    assert!(
        (sync.clock_offset_s[0] - OFFSET_S).abs() < 1.0,
        "{:?}",
        sync
    );
    // Forces follow the penetration on the camera's clock.
    let last = FRAMES - 1;
    let want = 5.0 * (penetration_m(last as f64) * 1e6).powf(1.5);
    assert!(
        (calibrated.force_n[last] / want - 1.0).abs() < 0.25,
        "{}",
        calibrated.force_n[last]
    );
    assert!(calibrated.contact_area_m2[last] > 0.0);
    // Contact maps at the nearest frames, as 8-bit PNGs, listed in the index.
    let index = ContactMapIndex::from_table(maps.index.as_ref().unwrap()).unwrap();
    assert_eq!(index.maps.file.len(), 3, "{index:?}");
    assert!(maps.files.contains_key("mask_a0.500.png"));
}

#[test]
fn a_12_bit_camera_in_16_bit_files_gives_what_its_scaled_copy_gives() {
    let (twelve, _) = lab(12, 1, 3);
    let (scaled, _) = lab(12, 16, 3);
    for method in ["calibrated", "otsu", "multi-otsu"] {
        let given = format!(r#"{{"method": "{method}", "clock_offset_s": 0.37}}"#);
        let with_bits = format!(r#"{{"method": "{method}", "clock_offset_s": 0.37, "bits": 12}}"#);
        let (a, _, _) = run(&params(&with_bits), twelve.clone()).unwrap();
        let (b, _, _) = run(&params(&given), scaled.clone()).unwrap();
        assert_eq!(a.area_fraction, b.area_fraction, "{method}");
        assert_eq!(a.patches, b.patches, "{method}");
    }
    // 16-bit data declared 12-bit is refused, naming the file.
    let e = run(&params(r#"{"bits": 12, "clock_offset_s": 0.0}"#), scaled).unwrap_err();
    assert!(e.contains("frame_000.png") && e.contains("12-bit"), "{e}");
}

#[test]
fn a_given_clock_offset_is_used_and_bad_sequences_are_named() {
    let (files, _) = lab(16, 1, 5);
    let (t, sync, _) = run(&params(r#"{"clock_offset_s": 0.37}"#), files.clone()).unwrap();
    assert_eq!(sync.estimated, [0]);
    assert!(sync.force_onset_s[0].is_nan());
    assert_eq!(t.method[0], "calibrated");
    let e = run(&params(r#"{"reference_frame": 99}"#), files.clone()).unwrap_err();
    assert!(
        e.contains("reference_frame") && e.contains("12 frames"),
        "{e}"
    );
    let mut broken = files.clone();
    broken
        .files
        .insert("frame_004.png".into(), b"not a png".to_vec());
    let e = run(&params("{}"), broken).unwrap_err();
    assert!(e.contains("frame_004.png") && e.contains("PNG/TIFF"), "{e}");
    let mut gone = files;
    gone.files.remove("frame_002.png");
    let e = run(&params("{}"), gone).unwrap_err();
    assert!(
        e.contains("frame_002.png") && e.contains("frames.csv lists it on line 4"),
        "{e}"
    );
    let e = serde_json::from_str::<ContactImagesParams>(r#"{"seed_fraction": 0.6}"#)
        .unwrap()
        .check()
        .unwrap_err();
    assert_eq!(e.param, "seed_fraction");
    // Two fractions that would write one mask file.
    let e = serde_json::from_str::<ContactImagesParams>(r#"{"map_fractions": [0.1, 0.5, 0.1004]}"#)
        .unwrap()
        .check()
        .unwrap_err();
    assert_eq!(e.param, "map_fractions.2");
    assert!(
        e.to_string().contains("same file names as map_fractions.0"),
        "{e}"
    );
}

/// The lab's frames as 16-bit TIFFs in a folder, their times in their names
/// (milliseconds, as many acquisition scripts write them) and no
/// frames.csv: the same table as the PNGs listed in frames.csv.
#[test]
fn a_folder_of_tiffs_timed_by_their_names_reads_as_its_frames_csv() {
    let (files, _) = lab(16, 1, 7);
    let dir = std::env::temp_dir().join(format!("hc-contact-named-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for k in 0..FRAMES {
        let png = &files.files[&format!("frame_{k:03}.png")];
        let image = image::load_from_memory(png).unwrap();
        assert_eq!(image.color(), image::ColorType::L16);
        // frames.csv's time of frame k is k s.
        let name = format!("img_{k:04}_{}ms.tif", k * 1000);
        image
            .save_with_format(dir.join(name), image::ImageFormat::Tiff)
            .unwrap();
    }
    std::fs::write(dir.join("force.csv"), &files.files["force.csv"]).unwrap();
    std::fs::write(dir.join("notes.txt"), b"rig 2, quartz flat").unwrap();
    let folder = format!(r#"{{"dir": "{}"}}"#, dir.display());
    let out = common::run_on(&params(&folder), hypercontact_core::Inputs::new());
    let (listed, listed_sync, _) = run(&params("{}"), files).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let (named, named_sync, _) = out.unwrap();
    assert_eq!(named.frame, listed.frame);
    assert_eq!(named.time_s, listed.time_s);
    assert_eq!(named.area_fraction, listed.area_fraction);
    assert_eq!(named.patches, listed.patches);
    assert_eq!(named.force_n, listed.force_n);
    assert_eq!(named_sync.clock_offset_s, listed_sync.clock_offset_s);
}
