//! Synthetic tensile curves from a known model, standing in for the lab
//! until the DIC stage delivers real ones: UT to λ = 2.5, PT to 2.0 and BT
//! to 1.4 (the ranges of rubber tests like the paper's), with multiplicative
//! Gaussian noise T (1 + s ξ), ξ ~ N(0, 1), from a seeded ChaCha8 generator.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::tensile::{TensileCurve, TensileData};
use crate::{Hyperelastic, Mode};

/// Largest stretch per mode.
pub const SAMPLE_RANGES: [(Mode, f64); 3] = [
    (Mode::Uniaxial, 2.5),
    (Mode::Planar, 2.0),
    (Mode::Equibiaxial, 1.4),
];
/// Points per mode (150 in all).
pub const SAMPLE_POINTS: usize = 50;
/// The noise of the shipped sample: 0.5 % of the stress.
pub const SAMPLE_NOISE: f64 = 0.005;
/// The seed of the shipped sample.
pub const SAMPLE_SEED: u64 = 20_240_501;

/// `points` evenly spaced stretches per mode, from just above 1 to the
/// mode's largest stretch, with the model's stresses times (1 + noise ξ).
pub fn synthetic_tensile(
    model: &dyn Hyperelastic,
    points: usize,
    noise_rel: f64,
    seed: u64,
) -> TensileData {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let curves = SAMPLE_RANGES
        .iter()
        .map(|&(mode, max)| {
            let stretch: Vec<f64> = (1..=points)
                .map(|i| 1.0 + (max - 1.0) * i as f64 / points as f64)
                .collect();
            let stress_pa = stretch
                .iter()
                .map(|&l| {
                    let xi: f64 = StandardNormal.sample(&mut rng);
                    model.nominal_stress_pa(mode, l) * (1.0 + noise_rel * xi)
                })
                .collect();
            TensileCurve {
                mode,
                stretch,
                stress_pa,
            }
        })
        .collect();
    TensileData { curves }
}

/// The shipped sample: `paper-epdm` with 0.5 % noise (what
/// `examples/tensile_sample.rs` writes to `data/tensile/epdm.csv`).
pub fn paper_sample() -> TensileData {
    synthetic_tensile(
        &crate::presets::paper_epdm(),
        SAMPLE_POINTS,
        SAMPLE_NOISE,
        SAMPLE_SEED,
    )
}

/// The data as CSV text with a provenance comment line.
pub fn to_csv(data: &TensileData, comment: &str) -> String {
    let mut out = format!("# {comment}\nmode,stretch,nominal_stress_pa\n");
    for c in &data.curves {
        for (l, t) in c.stretch.iter().zip(&c.stress_pa) {
            out.push_str(&format!("{},{l},{t}\n", c.mode));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_is_reproducible_with_the_requested_noise() {
        let a = paper_sample();
        assert_eq!(a, paper_sample());
        assert_eq!(a.n_points(), 3 * SAMPLE_POINTS);
        let model = crate::presets::paper_epdm();
        // The relative deviations are the noise draws: mean ≈ 0, sd ≈ 0.5 %.
        let dev: Vec<f64> = a
            .curves
            .iter()
            .flat_map(|c| {
                c.stretch
                    .iter()
                    .zip(&c.stress_pa)
                    .map(|(&l, &t)| t / model.nominal_stress_pa(c.mode, l) - 1.0)
                    .collect::<Vec<_>>()
            })
            .collect();
        let n = dev.len() as f64;
        let mean = dev.iter().sum::<f64>() / n;
        let sd = (dev.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        // 150 draws: the sample sd is within ±20 % of 0.005 with
        // overwhelming probability, the mean within 4 standard errors.
        assert!((sd / SAMPLE_NOISE - 1.0).abs() < 0.2, "sd {sd}");
        assert!(mean.abs() < 4.0 * SAMPLE_NOISE / n.sqrt(), "mean {mean}");
        let bt = a.curve(Mode::Equibiaxial).unwrap();
        assert!((bt.stretch.last().unwrap() - 1.4).abs() < 1e-12);
    }

    #[test]
    fn shipped_csv_is_the_sample() {
        // data/tensile/epdm.csv is written by examples/tensile_sample.rs;
        // rerun it if this fails after a change to the sample.
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/tensile/epdm.csv");
        let table = hypercontact_labfiles::csv_table::read_csv(&path).unwrap();
        let shipped = TensileData::from_table(&table, "epdm.csv").unwrap();
        assert_eq!(shipped, paper_sample());
    }

    #[test]
    fn csv_text_reads_back_through_core() {
        let data = synthetic_tensile(&crate::presets::paper_epdm(), 5, 0.0, 1);
        let dir = std::env::temp_dir().join(format!("hc-sample-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.csv");
        std::fs::write(&path, to_csv(&data, "test")).unwrap();
        let table = hypercontact_labfiles::csv_table::read_csv(&path).unwrap();
        let back = TensileData::from_table(&table, "t.csv").unwrap();
        assert_eq!(back, data);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
