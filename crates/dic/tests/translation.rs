//! Rigid sub-pixel translations of an analytically rendered speckle image:
//! IC-GN (first-order, bicubic B-spline) must recover them with an RMS
//! error below 0.01 px without noise and below 0.03 px with 1 % noise.

use hypercontact_dic::GrayImage;
use hypercontact_dic::bspline::BSplineImage;
use hypercontact_dic::icgn::{IcgnSettings, ReferenceFrame, Warp};
use hypercontact_synth::tensile::experiment::expose;
use hypercontact_synth::tensile::render::{AxisMap, render};
use hypercontact_synth::tensile::speckle::SpecklePattern;

const SIZE: usize = 160;

fn image(pattern: &SpecklePattern, shift: [f64; 2], noise: f64, seed: u64) -> GrayImage {
    let centre = [SIZE as f64 / 2.0; 2];
    let map = AxisMap {
        shift,
        ..AxisMap::identity(centre)
    };
    let pixels = render(pattern, &map, SIZE, SIZE, 4);
    let pixels = if noise > 0.0 {
        expose(&pixels, noise, 16, seed)
            .iter()
            .map(|&c| f64::from(c) / 65535.0)
            .collect()
    } else {
        pixels
    };
    GrayImage::new(SIZE, SIZE, pixels).unwrap()
}

/// RMS displacement error over a POI grid and a set of sub-pixel shifts.
fn rms_error(noise: f64) -> f64 {
    let pattern = SpecklePattern::random([-10.0, -10.0, 170.0, 170.0], 2.5, 0.5, Vec::new(), 3);
    let settings = IcgnSettings {
        subset_px: 31,
        max_iterations: 30,
        convergence_px: 1e-4,
    };
    let reference = image(&pattern, [0.0, 0.0], noise, 100);
    let reference = ReferenceFrame::new(reference);
    let shifts = [
        [0.1, 0.0],
        [0.25, -0.4],
        [0.5, 0.5],
        [-0.7, 0.3],
        [0.9, -0.15],
        [1.35, 2.6],
    ];
    let (mut sum_sq, mut count) = (0.0, 0usize);
    for (s, shift) in shifts.iter().enumerate() {
        let target = BSplineImage::new(&image(&pattern, *shift, noise, s as u64));
        for y in (40..=120).step_by(10) {
            for x in (40..=120).step_by(10) {
                let subset = reference.subset(x, y, 15).unwrap();
                let guess = Warp::translation(shift[0].round(), shift[1].round());
                let m = subset.solve(&target, guess, &settings);
                assert!(
                    m.converged && m.zncc > 0.99,
                    "({x}, {y}) shift {shift:?}: {m:?}"
                );
                sum_sq += (m.warp.u - shift[0]).powi(2) + (m.warp.v - shift[1]).powi(2);
                count += 1;
            }
        }
    }
    (sum_sq / count as f64).sqrt()
}

#[test]
fn noise_free_translations_within_0_01_px_rms() {
    let rms = rms_error(0.0);
    eprintln!("noise-free RMS error {rms:.5} px");
    assert!(rms < 0.01, "RMS error {rms} px");
}

#[test]
fn translations_with_1_percent_noise_within_0_03_px_rms() {
    let rms = rms_error(0.01);
    eprintln!("1 % noise RMS error {rms:.5} px");
    assert!(rms < 0.03, "RMS error {rms} px");
}
