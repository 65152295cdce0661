//! Marker centroids against the synthetic truth: each painted dot's
//! detected centre must follow the exact map of its reference centre.

use hypercontact_core::Mode;
use hypercontact_dic::GrayImage;
use hypercontact_dic::markers::detect;
use hypercontact_synth::tensile::SynthTensileParams;
use hypercontact_synth::tensile::experiment::{Experiment, expose};

#[test]
fn marker_centroids_follow_the_map_within_0_05_px() {
    let p = SynthTensileParams {
        mode: Mode::Uniaxial,
        max_stretch: Some(2.0),
        frames: 12,
        seed: 5,
        ..Default::default()
    };
    let e = Experiment::new(&p.recipe());
    let mut worst: f64 = 0.0;
    for k in [0, 6, 11] {
        let counts = expose(&e.render_frame(k), 0.005, 16, k as u64);
        let pixels = counts.iter().map(|&c| f64::from(c) / 65535.0).collect();
        let image = GrayImage::new(512, 512, pixels).unwrap();
        let blobs = detect(&image, 0.07, 10);
        assert_eq!(blobs.len(), 4, "frame {k}");
        let map = e.maps[k];
        for m in &e.pattern.markers {
            let truth = [map.to_image(0, m.x), map.to_image(1, m.y)];
            let error = blobs
                .iter()
                .map(|b| (b.centroid[0] - truth[0]).hypot(b.centroid[1] - truth[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(error);
        }
    }
    // 0.5 % noise on the ~150 pixels of a marker window: a few 0.01 px.
    assert!(worst < 0.05, "worst marker error {worst} px");
}
