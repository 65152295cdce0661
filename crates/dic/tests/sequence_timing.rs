//! Timing of the sequence benchmark (ignored by default): a
//! 2048 × 2048, 50-frame UT sequence to λ = 1.5, subset 31 px at step 16 px,
//! through the subset tracker with all cores (target: under a minute).
//! Frames are rendered (point-sampled) and quantised before the clock
//! starts; decoding 16-bit PNGs is timed separately on one frame.
//!
//! Run: `cargo test --workspace --release --test integration -- sequence_timing:: --ignored --nocapture`.

use std::time::Instant;

use hypercontact_core::Mode;
use hypercontact_dic::GrayImage;
use hypercontact_dic::icgn::IcgnSettings;
use hypercontact_dic::poi_grid::PoiGrid;
use hypercontact_dic::strain::{affine_fit, principal_stretches};
use hypercontact_dic::subset_tracking::{SubsetSettings, SubsetTracker};
use hypercontact_synth::encode_png;
use hypercontact_synth::tensile::SynthTensileParams;
use hypercontact_synth::tensile::experiment::{Experiment, expose};

#[test]
#[ignore = "benchmark: minutes of rendering, run on demand"]
fn sequence_2048_50_frames_step_16() {
    let params = SynthTensileParams {
        mode: Mode::Uniaxial,
        max_stretch: Some(1.5),
        frames: 50,
        width_px: 2048,
        height_px: 2048,
        supersample: 1,
        markers: false,
        ..Default::default()
    };
    let experiment = Experiment::new(&params.recipe());
    let start = Instant::now();
    let frames: Vec<Vec<u16>> = (0..50)
        .map(|k| expose(&experiment.render_frame(k), 0.005, 16, k as u64))
        .collect();
    eprintln!(
        "rendered 50 frames in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let to_image = |counts: &[u16]| {
        GrayImage::new(
            2048,
            2048,
            counts.iter().map(|&c| f64::from(c) / 65535.0).collect(),
        )
        .unwrap()
    };

    let png = encode_png(2048, 2048, 16, frames[1].clone()).unwrap();
    let start = Instant::now();
    let decoded = GrayImage::decode("frame_001.png", &png).unwrap();
    let decode_s = start.elapsed().as_secs_f64();
    assert_eq!(decoded.width, 2048);

    let settings = SubsetSettings {
        icgn: IcgnSettings {
            subset_px: 31,
            max_iterations: 30,
            convergence_px: 1e-3,
        },
        min_zncc: 0.9,
        update_strain: 0.1,
        search_px: 64,
    };
    let start = Instant::now();
    let grid = PoiGrid::new(experiment.roi_px, "roi_px", 16, 31, 2048, 2048).unwrap();
    let n_pois = grid.len();
    let reference = grid.points.clone();
    let mut tracker = SubsetTracker::new(settings, grid, to_image(&frames[0]));
    let mut worst: f64 = 0.0;
    for (k, counts) in frames.iter().enumerate().skip(1) {
        let track = tracker.track(to_image(counts), k, "frame").unwrap();
        let (from, to): (Vec<_>, Vec<_>) = reference
            .iter()
            .zip(&track.positions)
            .filter_map(|(&a, b)| b.map(|b| (a, b)))
            .unzip();
        let (_, _, f) = affine_fit(&from, &to).unwrap();
        worst = worst.max((principal_stretches(&f).0 - experiment.stretches[k]).abs());
    }
    let track_s = start.elapsed().as_secs_f64();
    let threads = rayon::current_num_threads();
    eprintln!(
        "{n_pois} POIs × 49 frames tracked in {track_s:.1} s on {threads} threads \
         ({:.0} POI/s); PNG decode {decode_s:.2} s/frame → about {:.1} s with decoding; \
         worst stretch error {worst:.1e}",
        (n_pois * 49) as f64 / track_s,
        track_s + 50.0 * decode_s
    );
    assert!(worst < 2e-4);
}
