//! A scientific CMOS camera turning a reflectance map into counts.
//!
//! Per pixel, in order (the EMVA 1288 linear camera model):
//! 1. mean photo-electrons μ = exposure · V(r) · R / R_ref, where the
//!    exposure puts R_ref at `exposure_fraction` of the full well at the
//!    image centre, and V(r) = 1 − v (r / r_corner)² is the flat-field
//!    fall-off (vignetting: the leading term of the cos⁴ law, r from the
//!    image centre, v the loss at the corners);
//! 2. shot noise: Poisson(μ) below [`GAUSSIAN_SHOT_ABOVE_E`] electrons, its
//!    Gaussian approximation N(μ, μ) above (same mean and variance; the
//!    skewness 1/√μ it drops is below 0.032 there);
//! 3. the well saturates: at most `full_well_e` electrons;
//! 4. read noise, Gaussian with `read_noise_e` rms;
//! 5. the ADC: electrons / gain + black level, rounded to the nearest count
//!    and clipped to [0, 2^bits − 1].
//!
//! Random numbers: ChaCha8 seeded with the frame's seed, one stream per
//! image row, so a frame's bytes do not depend on how rows are shared
//! between threads.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};
use rayon::prelude::*;

use crate::error::{InterferenceError, non_negative, positive};

/// Mean electron count above which shot noise is drawn as a Gaussian.
pub const GAUSSIAN_SHOT_ABOVE_E: f64 = 1000.0;

/// The sensor and its exposure. Defaults are typical of a 6.5 µm-pixel
/// scientific CMOS (full well 2–3·10⁴ e⁻, read noise 1–2 e⁻ rms, 16-bit
/// output), not one product's data sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraParams {
    /// output bit depth, 8 …= 16 (counts in 0 … 2^bits − 1)
    pub bits: u32,
    pub full_well_e: f64,
    /// electrons of the reference reflectance at the image centre, as a
    /// fraction of the full well (above 1 overexposes)
    pub exposure_fraction: f64,
    /// rms, electrons
    pub read_noise_e: f64,
    /// conversion gain, electrons per count; `None`: the full well spans the
    /// output range (full_well_e / (2^bits − 1)), so a saturated pixel reads
    /// the full scale less its read noise (the ADC clips the upper half)
    pub gain_e_per_dn: Option<f64>,
    /// the counts of a dark pixel (offset added before rounding)
    pub black_level_dn: f64,
    /// relative fall-off of the flat field at the image corners, 0 …< 1
    pub vignetting: f64,
    /// shot and read noise on (off: the mean signal, only quantised; for
    /// tests that need the optics alone)
    pub noise: bool,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            bits: 16,
            full_well_e: 30_000.0,
            exposure_fraction: 0.8,
            read_noise_e: 1.6,
            gain_e_per_dn: None,
            black_level_dn: 0.0,
            vignetting: 0.15,
            noise: true,
        }
    }
}

impl CameraParams {
    pub fn check(&self) -> Result<(), InterferenceError> {
        if !(8..=16).contains(&self.bits) {
            return Err(InterferenceError::param(
                "bits",
                self.bits,
                "must be 8 …= 16",
            ));
        }
        positive("full_well_e", self.full_well_e)?;
        positive("exposure_fraction", self.exposure_fraction)?;
        if self.exposure_fraction > 100.0 {
            return Err(InterferenceError::param(
                "exposure_fraction",
                self.exposure_fraction,
                "must be at most 100 (times the full well)",
            ));
        }
        non_negative("read_noise_e", self.read_noise_e)?;
        if let Some(gain) = self.gain_e_per_dn {
            positive("gain_e_per_dn", gain)?;
        }
        non_negative("black_level_dn", self.black_level_dn)?;
        if self.black_level_dn >= self.full_scale() as f64 {
            return Err(InterferenceError::param(
                "black_level_dn",
                self.black_level_dn,
                format!("must be below the full scale {}", self.full_scale()),
            ));
        }
        if !(self.vignetting >= 0.0 && self.vignetting < 1.0) {
            return Err(InterferenceError::param(
                "vignetting",
                self.vignetting,
                "must lie in [0, 1)",
            ));
        }
        Ok(())
    }

    /// 2^bits − 1 (for bits in range).
    pub fn full_scale(&self) -> u16 {
        ((1u32 << self.bits.clamp(1, 16)) - 1) as u16
    }

    /// Electrons per count.
    pub fn gain(&self) -> f64 {
        self.gain_e_per_dn
            .unwrap_or(self.full_well_e / self.full_scale() as f64)
    }
}

/// One captured frame: row-major counts, `counts[y * width + x]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub width: usize,
    pub height: usize,
    /// the camera's bit depth: counts lie in 0 … 2^bits − 1
    pub bits: u32,
    pub counts: Vec<u16>,
}

/// A checked camera with its exposure set for a reference reflectance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    params: CameraParams,
    /// electrons per unit reflectance at the image centre
    electrons_per_reflectance: f64,
    gain: f64,
}

impl Camera {
    /// `reference_reflectance`: the reflectance exposed to
    /// `exposure_fraction` of the full well (pass the brightest fringe to
    /// keep every fringe below saturation, or the background).
    pub fn new(
        params: CameraParams,
        reference_reflectance: f64,
    ) -> Result<Self, InterferenceError> {
        params.check()?;
        positive("reference_reflectance", reference_reflectance)?;
        Ok(Self {
            params,
            electrons_per_reflectance: params.exposure_fraction * params.full_well_e
                / reference_reflectance,
            gain: params.gain(),
        })
    }

    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// V at pixel (x, y) of a width × height frame: 1 at the centre,
    /// 1 − vignetting at the corner pixels' centres.
    pub fn flat_field(&self, x: usize, y: usize, width: usize, height: usize) -> f64 {
        let (cx, cy) = ((width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0);
        let corner2 = cx * cx + cy * cy;
        if corner2 == 0.0 {
            return 1.0;
        }
        let (dx, dy) = (x as f64 - cx, y as f64 - cy);
        1.0 - self.params.vignetting * (dx * dx + dy * dy) / corner2
    }

    /// Mean photo-electrons of a pixel of reflectance `reflectance` at (x, y).
    pub fn mean_electrons(
        &self,
        reflectance: f64,
        x: usize,
        y: usize,
        width: usize,
        height: usize,
    ) -> f64 {
        self.electrons_per_reflectance * self.flat_field(x, y, width, height) * reflectance
    }

    /// Counts of a row-major `width × height` reflectance map
    /// (`reflectance[y * width + x]`, finite and ≥ 0), with the noise drawn
    /// from `seed` (give every frame of a sequence its own).
    pub fn capture(
        &self,
        reflectance: &[f64],
        width: usize,
        height: usize,
        seed: u64,
    ) -> Result<Frame, InterferenceError> {
        if width == 0 || height == 0 {
            return Err(InterferenceError::Empty {
                what: "reflectance map",
                detail: format!("{width} × {height} pixels"),
            });
        }
        let expected = width.checked_mul(height).ok_or(InterferenceError::Length {
            what: "reflectance map",
            expected: usize::MAX,
            got: reflectance.len(),
        })?;
        if reflectance.len() != expected {
            return Err(InterferenceError::Length {
                what: "reflectance map",
                expected,
                got: reflectance.len(),
            });
        }
        if let Some(index) = reflectance
            .iter()
            .position(|r| !(r.is_finite() && *r >= 0.0))
        {
            return Err(InterferenceError::Value {
                what: "reflectance map",
                index,
                value: reflectance[index],
                message: "a reflectance must be finite and at least 0",
            });
        }

        let p = &self.params;
        let full_scale = p.full_scale() as f64;
        let (cx, cy) = ((width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0);
        let corner2 = cx * cx + cy * cy;
        let falloff = if corner2 > 0.0 {
            p.vignetting / corner2
        } else {
            0.0
        };
        let mut counts = vec![0u16; expected];
        counts
            .par_chunks_mut(width)
            .zip(reflectance.par_chunks(width))
            .enumerate()
            .for_each(|(y, (row_out, row_in))| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(y as u64);
                let dy2 = (y as f64 - cy).powi(2);
                for (x, (out, &r)) in row_out.iter_mut().zip(row_in).enumerate() {
                    let dx = x as f64 - cx;
                    let mean_e =
                        self.electrons_per_reflectance * (1.0 - falloff * (dx * dx + dy2)) * r;
                    let signal_e = if p.noise {
                        let shot_e = shot(mean_e, &mut rng).min(p.full_well_e);
                        let read: f64 = StandardNormal.sample(&mut rng);
                        shot_e + p.read_noise_e * read
                    } else {
                        mean_e.min(p.full_well_e)
                    };
                    // round half up by truncation (`round` is a library call)
                    let dn = (signal_e / self.gain + p.black_level_dn).clamp(0.0, full_scale);
                    *out = (dn + 0.5) as u16;
                }
            });
        Ok(Frame {
            width,
            height,
            bits: p.bits,
            counts,
        })
    }
}

/// Photo-electrons collected for a mean of `mean_e`.
#[inline]
fn shot(mean_e: f64, rng: &mut ChaCha8Rng) -> f64 {
    if mean_e > GAUSSIAN_SHOT_ABOVE_E {
        let z: f64 = StandardNormal.sample(rng);
        mean_e + mean_e.sqrt() * z
    } else if mean_e > 0.0 {
        // `mean_e` is finite and positive here, so `new` cannot fail
        Poisson::new(mean_e).map_or(mean_e, |d| d.sample(rng))
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sample mean, variance and standardised skewness.
    fn moments(counts: &[u16]) -> (f64, f64, f64) {
        let n = counts.len() as f64;
        let mean = counts.iter().map(|&c| c as f64).sum::<f64>() / n;
        let m2 = counts
            .iter()
            .map(|&c| (c as f64 - mean).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        let m3 = counts
            .iter()
            .map(|&c| (c as f64 - mean).powi(3))
            .sum::<f64>()
            / n;
        (mean, m2, m3 / m2.powf(1.5))
    }

    fn flat(camera: &Camera, n: usize, reflectance: f64, seed: u64) -> Frame {
        camera
            .capture(&vec![reflectance; n * n], n, n, seed)
            .unwrap()
    }

    #[test]
    fn without_noise_the_counts_are_the_rounded_mean_signal() {
        let params = CameraParams {
            exposure_fraction: 0.5,
            vignetting: 0.0,
            black_level_dn: 100.0,
            noise: false,
            ..CameraParams::default()
        };
        let camera = Camera::new(params, 0.07).unwrap();
        let a = flat(&camera, 16, 0.07, 1);
        assert_eq!(a, flat(&camera, 16, 0.07, 2));
        let want = (0.5 * 30_000.0 / params.gain() + 100.0).round() as u16;
        assert!(
            a.counts.iter().all(|&c| c == want),
            "{:?} vs {want}",
            &a.counts[..4]
        );
    }

    #[test]
    fn flat_field_moments_gaussian_branch() {
        let params = CameraParams {
            exposure_fraction: 0.5,
            vignetting: 0.0,
            black_level_dn: 100.0,
            ..CameraParams::default()
        };
        let camera = Camera::new(params, 0.07).unwrap();
        let n = 512;
        let frame = flat(&camera, n, 0.07, 11);
        let (mean, var, _) = moments(&frame.counts);
        let gain = params.gain();
        let mu_e = 0.5 * 30_000.0;
        let expected_mean = mu_e / gain + 100.0;
        // shot + read noise, plus the rounding's uniform 1/12 count²
        let expected_var = (mu_e + 1.6 * 1.6) / (gain * gain) + 1.0 / 12.0;
        let samples = (n * n) as f64;
        let se_mean = (expected_var / samples).sqrt();
        let se_var = expected_var * (2.0 / samples).sqrt();
        assert!(
            (mean - expected_mean).abs() < 5.0 * se_mean,
            "{mean} vs {expected_mean}"
        );
        assert!(
            (var - expected_var).abs() < 5.0 * se_var,
            "{var} vs {expected_var}"
        );
    }

    #[test]
    fn flat_field_moments_poisson_branch() {
        // 50 e⁻: Poisson shot noise, whose skewness 1/√μ a Gaussian would miss
        let params = CameraParams {
            exposure_fraction: 50.0 / 30_000.0,
            gain_e_per_dn: Some(0.25),
            vignetting: 0.0,
            black_level_dn: 20.0,
            ..CameraParams::default()
        };
        let camera = Camera::new(params, 1.0).unwrap();
        let n = 512;
        let frame = flat(&camera, n, 1.0, 5);
        let (mean, var, skew) = moments(&frame.counts);
        let (mu_e, g, read): (f64, f64, f64) = (50.0, 0.25, 1.6);
        let expected_mean = mu_e / g + 20.0;
        let expected_var = (mu_e + read * read) / (g * g) + 1.0 / 12.0;
        // third central moment μ/g³ (read noise and rounding are symmetric)
        let expected_skew = (mu_e / (g * g * g)) / expected_var.powf(1.5);
        let samples = (n * n) as f64;
        assert!((mean - expected_mean).abs() < 5.0 * (expected_var / samples).sqrt());
        assert!((var - expected_var).abs() < 5.0 * expected_var * (2.0 / samples).sqrt());
        assert!(
            (skew - expected_skew).abs() < 5.0 * (6.0 / samples).sqrt(),
            "skewness {skew} vs {expected_skew}"
        );
        assert!(expected_skew > 0.12);
    }

    #[test]
    fn vignetting_profile() {
        let params = CameraParams {
            vignetting: 0.3,
            read_noise_e: 0.0,
            ..CameraParams::default()
        };
        let camera = Camera::new(params, 0.1).unwrap();
        let (w, h) = (300, 200);
        let frame = camera.capture(&vec![0.1; w * h], w, h, 3).unwrap();
        // analytic profile at the corners and the centre
        assert!((camera.flat_field(0, 0, w, h) - 0.7).abs() < 1e-12);
        assert!((camera.flat_field(w - 1, h - 1, w, h) - 0.7).abs() < 1e-12);
        assert!(
            (camera.flat_field(150, 100, w, h)
                - (1.0 - 0.3 * 0.5 / (149.5f64.powi(2) + 99.5f64.powi(2))))
            .abs()
                < 1e-12
        );
        // ring averages of the noisy frame against V(r) = 1 − 0.3 (r/r_c)²
        let (cx, cy): (f64, f64) = (149.5, 99.5);
        let rc = (cx * cx + cy * cy).sqrt();
        let top = 0.8 * 30_000.0 / params.gain();
        let bins = 12;
        let mut sum = vec![0.0; bins];
        let mut count = vec![0usize; bins];
        let mut expect = vec![0.0; bins];
        for y in 0..h {
            for x in 0..w {
                let r = ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt() / rc;
                let b = ((r * bins as f64) as usize).min(bins - 1);
                sum[b] += frame.counts[y * w + x] as f64;
                count[b] += 1;
                expect[b] += top * (1.0 - 0.3 * r * r);
            }
        }
        for b in 0..bins {
            let (mean, want) = (sum[b] / count[b] as f64, expect[b] / count[b] as f64);
            // per-pixel σ ≈ √(μ_e)/gain
            let sigma = (want * params.gain()).sqrt() / params.gain();
            assert!(
                (mean - want).abs() < 5.0 * sigma / (count[b] as f64).sqrt(),
                "ring {b}: {mean} vs {want}"
            );
        }
        // the fall-off is resolved: outer ring ~25 % below the centre
        assert!(sum[bins - 1] / (count[bins - 1] as f64) < 0.8 * sum[0] / count[0] as f64);
    }

    #[test]
    fn clipping_at_full_scale_and_at_the_full_well() {
        for bits in [8, 12, 16] {
            // the ADC's range ends at 90 % of the well, so it clips first
            let full_scale = ((1u32 << bits) - 1) as f64;
            let params = CameraParams {
                bits,
                exposure_fraction: 1.5,
                gain_e_per_dn: Some(0.9 * 30_000.0 / full_scale),
                ..CameraParams::default()
            };
            let camera = Camera::new(params, 0.05).unwrap();
            let frame = flat(&camera, 64, 0.05, 1);
            let top = ((1u32 << bits) - 1) as u16;
            assert!(frame.counts.iter().all(|&c| c == top), "bits {bits}");
            assert_eq!(frame.bits, bits);
            // a dark frame is within range too
            let dark = flat(&camera, 64, 0.0, 1);
            let six_sigma = 6.0 * 1.6 / params.gain();
            assert!(dark.counts.iter().all(|&c| c as f64 <= six_sigma + 1.0));
        }
        // one electron per count, 16 bits: the well (30 000 e⁻) fills before the ADC
        let params = CameraParams {
            gain_e_per_dn: Some(1.0),
            exposure_fraction: 3.0,
            read_noise_e: 2.0,
            vignetting: 0.0,
            ..CameraParams::default()
        };
        let frame = flat(&Camera::new(params, 1.0).unwrap(), 128, 1.0, 2);
        let (mean, var, _) = moments(&frame.counts);
        assert!((mean - 30_000.0).abs() < 0.1, "{mean}");
        assert!((var - (4.0 + 1.0 / 12.0)).abs() < 0.3, "{var}");
    }

    #[test]
    fn same_seed_same_bytes_on_one_and_two_threads() {
        let camera = Camera::new(CameraParams::default(), 0.1).unwrap();
        let (w, h) = (97, 61);
        // a mix of both shot-noise branches
        let map: Vec<f64> = (0..w * h)
            .map(|k| 0.1 * ((k % 13) as f64 / 12.0).powi(3))
            .collect();
        let run = |threads: usize, seed: u64| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| camera.capture(&map, w, h, seed).unwrap())
        };
        let one = run(1, 42);
        assert_eq!(one, run(2, 42));
        assert_eq!(one, run(3, 42));
        assert_ne!(one, run(2, 43));
    }

    #[test]
    fn bad_inputs_are_refused() {
        let camera = Camera::new(CameraParams::default(), 0.1).unwrap();
        assert!(matches!(
            camera.capture(&[], 0, 3, 0),
            Err(InterferenceError::Empty { .. })
        ));
        assert!(matches!(
            camera.capture(&[0.1; 5], 2, 3, 0),
            Err(InterferenceError::Length { .. })
        ));
        assert!(matches!(
            camera.capture(&[0.1, f64::NAN, 0.1, 0.1], 2, 2, 0),
            Err(InterferenceError::Value { index: 1, .. })
        ));
        assert!(camera.capture(&[0.1, -0.1, 0.1, 0.1], 2, 2, 0).is_err());
        assert!(camera.capture(&[0.1; 4], usize::MAX, 2, 0).is_err());
        for bad in [
            CameraParams {
                bits: 7,
                ..CameraParams::default()
            },
            CameraParams {
                bits: 17,
                ..CameraParams::default()
            },
            CameraParams {
                full_well_e: 0.0,
                ..CameraParams::default()
            },
            CameraParams {
                exposure_fraction: f64::NAN,
                ..CameraParams::default()
            },
            CameraParams {
                read_noise_e: -1.0,
                ..CameraParams::default()
            },
            CameraParams {
                gain_e_per_dn: Some(0.0),
                ..CameraParams::default()
            },
            CameraParams {
                black_level_dn: 255.0,
                bits: 8,
                ..CameraParams::default()
            },
            CameraParams {
                vignetting: 1.0,
                ..CameraParams::default()
            },
        ] {
            assert!(Camera::new(bad, 0.1).is_err(), "{bad:?}");
        }
        assert!(Camera::new(CameraParams::default(), 0.0).is_err());
        // a single pixel has no vignetting to apply
        let one = camera.capture(&[0.1], 1, 1, 0).unwrap();
        assert_eq!(one.counts.len(), 1);
    }
}
