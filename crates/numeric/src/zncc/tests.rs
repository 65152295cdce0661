use hypercontact_fuzz::on_threads;
use proptest::prelude::*;

use super::*;

/// Uniform numbers in [0, 1) by SplitMix64 (Steele, Lea & Flood, OOPSLA
/// 2014): enough for test fields, and the same on every machine.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }
}

fn random_field(w: usize, h: usize, nan_share: f64, rng: &mut Uniform) -> Vec<f64> {
    (0..w * h)
        .map(|_| {
            if rng.next() < nan_share {
                f64::NAN
            } else {
                rng.next()
            }
        })
        .collect()
}

/// The definition: ZNCC over the measured cells under the template, each
/// placement summed directly.
fn brute_force(
    template: &[f64],
    (tw, th): (usize, usize),
    image: &[f64],
    (iw, ih): (usize, usize),
    min_count: usize,
) -> Vec<f64> {
    let (px, py) = (iw - tw + 1, ih - th + 1);
    let mean_t = template.iter().sum::<f64>() / template.len() as f64;
    let mut out = vec![f64::NAN; px * py];
    for y in 0..py {
        for x in 0..px {
            let pairs: Vec<(f64, f64)> = (0..th)
                .flat_map(|v| (0..tw).map(move |u| (u, v)))
                .map(|(u, v)| (template[v * tw + u] - mean_t, image[(y + v) * iw + x + u]))
                .filter(|(_, r)| !r.is_nan())
                .collect();
            let n = pairs.len() as f64;
            if pairs.len() < min_count {
                continue;
            }
            let (mt, mr) = (
                pairs.iter().map(|p| p.0).sum::<f64>() / n,
                pairs.iter().map(|p| p.1).sum::<f64>() / n,
            );
            let (mut c, mut vt, mut vr) = (0.0, 0.0, 0.0);
            for (t, r) in &pairs {
                c += (t - mt) * (r - mr);
                vt += (t - mt) * (t - mt);
                vr += (r - mr) * (r - mr);
            }
            if vt <= FLAT_VARIANCE * n || vr <= FLAT_VARIANCE * n {
                continue;
            }
            out[y * px + x] = c / (vt * vr).sqrt();
        }
    }
    out
}

#[test]
fn an_embedded_template_is_found_where_it_was_cut() {
    let mut rng = Uniform(3);
    let (iw, ih, tw, th) = (61, 47, 19, 13);
    let image = random_field(iw, ih, 0.0, &mut rng);
    let (x0, y0) = (23, 17);
    let template: Vec<f64> = (0..th)
        .flat_map(|v| (0..tw).map(move |u| (u, v)))
        .map(|(u, v)| 0.5 * image[(y0 + v) * iw + x0 + u] + 0.2)
        .collect();
    let c = Correlator::new(&template, (tw, th), (iw, ih), 1.0)
        .unwrap()
        .unwrap();
    let peak = c.best(&image).unwrap().unwrap();
    // a gain and offset do not change the ZNCC
    assert!((peak.zncc - 1.0).abs() < 1e-12, "{peak:?}");
    assert_eq!(peak.cell, (x0, y0));
    assert!((peak.x - x0 as f64).abs() < 0.5 && (peak.y - y0 as f64).abs() < 0.5);
}

#[test]
fn a_smooth_peak_is_located_between_cells() {
    // a Gaussian blob at a fractional position, a template of the same blob
    // centred: the parabola refines the placement towards it
    let (iw, ih, tw, th) = (64, 64, 21, 21);
    let blob =
        |x: f64, y: f64, cx: f64, cy: f64| (-((x - cx).powi(2) + (y - cy).powi(2)) / 18.0).exp();
    let (cx, cy) = (30.3, 25.7);
    let image: Vec<f64> = (0..iw * ih)
        .map(|k| blob((k % iw) as f64, (k / iw) as f64, cx, cy))
        .collect();
    let template: Vec<f64> = (0..tw * th)
        .map(|k| blob((k % tw) as f64, (k / tw) as f64, 10.0, 10.0))
        .collect();
    let c = Correlator::new(&template, (tw, th), (iw, ih), 1.0)
        .unwrap()
        .unwrap();
    let peak = c.best(&image).unwrap().unwrap();
    assert_eq!(peak.cell, (20, 16));
    assert!((peak.x - (cx - 10.0)).abs() < 0.1, "{peak:?}");
    assert!((peak.y - (cy - 10.0)).abs() < 0.1, "{peak:?}");
}

#[test]
fn too_large_templates_wrong_images_and_flat_templates_are_refused() {
    assert!(
        Correlator::new(&[0.0; 6], (3, 2), (2, 5), 1.0)
            .unwrap()
            .is_none()
    );
    assert!(matches!(
        Correlator::new(&[0.0; 5], (3, 2), (4, 5), 1.0),
        Err(NumericError::Length { expected: 6, .. })
    ));
    let c = Correlator::new(&[0.0, 1.0, 1.0, 0.0], (2, 2), (4, 4), 1.0)
        .unwrap()
        .unwrap();
    assert!(matches!(
        c.zncc_map(&[0.0; 15]),
        Err(NumericError::Length { got: 15, .. })
    ));
    // all unmeasured: no placement
    assert_eq!(c.best(&[f64::NAN; 16]).unwrap(), None);
    // a flat template matches nothing
    let mut rng = Uniform(5);
    let image = random_field(9, 8, 0.0, &mut rng);
    let flat = Correlator::new(&[0.7; 9], (3, 3), (9, 8), 1.0)
        .unwrap()
        .unwrap();
    assert_eq!(flat.best(&image).unwrap(), None);
}

#[test]
fn a_shifted_texture_is_found_at_its_integer_shift() {
    // A pseudo-random texture and the same texture moved by (7, −4): the
    // template cut at (33, 33) of the first lies at (40, 29) in the second.
    let (w, h) = (96, 80);
    let texture = |x: i64, y: i64| {
        let k = (x * 73_856_093) ^ (y * 19_349_663);
        ((k.wrapping_mul(2_654_435_761) >> 7) & 1023) as f64 / 1023.0
    };
    let moved: Vec<f64> = (0..w * h)
        .map(|k| texture((k % w) as i64 - 7, (k / w) as i64 + 4))
        .collect();
    let side = 15;
    let template: Vec<f64> = (0..side * side)
        .map(|k| texture(33 + (k % side) as i64, 33 + (k / side) as i64))
        .collect();
    let c = Correlator::new(&template, (side, side), (w, h), 1.0)
        .unwrap()
        .unwrap();
    let peak = c.best(&moved).unwrap().unwrap();
    assert_eq!(peak.cell, (40, 29));
    assert!((peak.zncc - 1.0).abs() < 1e-9, "{}", peak.zncc);
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    let mut rng = Uniform(17);
    let (iw, ih, tw, th) = (83, 71, 20, 17);
    let image = random_field(iw, ih, 0.05, &mut rng);
    let template = random_field(tw, th, 0.0, &mut rng);
    let run = || {
        let c = Correlator::new(&template, (tw, th), (iw, ih), 0.8)
            .unwrap()
            .unwrap();
        c.zncc_map(&image)
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(on_threads(1, run), on_threads(2, run));
}

proptest! {
    #![proptest_config(hypercontact_fuzz::config(40))]

    /// The FFT and summed-area evaluation equals the definition at every
    /// placement, with unmeasured cells skipped (not read as 0); odd and
    /// prime sizes, fast grids larger than the image.
    #[test]
    fn fft_zncc_equals_the_definition(
        tw in 1usize..9,
        th in 1usize..9,
        extra_w in 0usize..12,
        extra_h in 0usize..12,
        nan_share in 0.0f64..0.3,
        min_overlap in prop_oneof![Just(1.0), 0.3f64..1.0],
        seed in 0u64..1000,
    ) {
        let mut rng = Uniform(seed);
        let (iw, ih) = (tw + extra_w, th + extra_h);
        let template = random_field(tw, th, 0.0, &mut rng);
        let image = random_field(iw, ih, nan_share, &mut rng);
        let c = Correlator::new(&template, (tw, th), (iw, ih), min_overlap).unwrap().unwrap();
        let fast = c.zncc_map(&image).unwrap();
        let slow = brute_force(&template, (tw, th), &image, (iw, ih), c.min_count());
        prop_assert_eq!(fast.len(), slow.len());
        for (k, (a, b)) in fast.iter().zip(&slow).enumerate() {
            prop_assert!(
                (a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-9,
                "placement {}: fft {} vs definition {}", k, a, b
            );
        }
    }
}
