//! Self-affine random surfaces by Fourier filtering.
//!
//! The prescribed isotropic 2-D power spectral density follows the
//! SurfaceTopography normalisation (Jacobs, Junge & Pastewka, Surf. Topogr.
//! Metrol. Prop. 5, 013001, 2017): C(q) = |Δx Δy FFT2(h)|² / (Lx Ly), so that
//! the mean square height is Σ_q C(q) / (Lx Ly). Its shape is
//!
//! - C = C0 · q_r^(−2−2H) for 0 < q < q_r = 2π/λ_max (the roll-off),
//! - C = C0 · q^(−2−2H)   for q_r ≤ q ≤ q_s = 2π/λ_min (self-affine),
//! - C = 0                for q > q_s and at q = 0,
//!
//! with C0 chosen so that the expected rms height is `rms_m`. A realisation
//! is white Gaussian noise shaped in Fourier space, so it is periodic over
//! the generated grid; callers that need a non-periodic sample crop a part.

use hypercontact_numeric::NumericError;
use hypercontact_numeric::fft2::RealFft2;
use ndarray::Array2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

/// The statistics a synthetic surface is drawn from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelfAffine {
    pub hurst: f64,
    /// Expected rms height over the periodic grid, metres.
    pub rms_m: f64,
    /// Short-wavelength cut-off λ_min, metres (no power at shorter ones).
    pub lambda_min_m: f64,
    /// Roll-off wavelength λ_max, metres (flat spectrum at longer ones).
    pub lambda_max_m: f64,
}

impl SelfAffine {
    /// The micrometre-scale spectrum of `hypercontact-surface`'s PSD tests,
    /// bench and SurfaceTopography cross-check: H = 0.8, rms 1 µm, power from
    /// 1 mm down to 4 µm. Callers change a field with `..SelfAffine::MICRON`.
    pub const MICRON: SelfAffine = SelfAffine {
        hurst: 0.8,
        rms_m: 1e-6,
        lambda_min_m: 4e-6,
        lambda_max_m: 1e-3,
    };

    /// The spectrum of the ICM and truncation tests and benches on an
    /// n × n map of `pixel_m` pixels: H = 0.8, rms 10 µm, power from the
    /// map's side down to two pixels.
    pub fn whole_band(n: usize, pixel_m: f64) -> SelfAffine {
        SelfAffine {
            hurst: 0.8,
            rms_m: 1e-5,
            lambda_min_m: 2.0 * pixel_m,
            lambda_max_m: n as f64 * pixel_m,
        }
    }

    /// A T1-like rubber sample at 20 µm pixels (H = 0.65, rms 15 µm, power
    /// from 5 mm down to 40 µm): what the bem and synth-contact benches solve.
    pub const T1_LIKE: SelfAffine = SelfAffine {
        hurst: 0.65,
        rms_m: 15e-6,
        lambda_min_m: 40e-6,
        lambda_max_m: 5e-3,
    };

    /// The spectrum's shape at |q| (rad/m), without the prefactor C0.
    pub fn shape(&self, q_per_m: f64) -> f64 {
        let q_roll = std::f64::consts::TAU / self.lambda_max_m;
        let q_short = std::f64::consts::TAU / self.lambda_min_m;
        if q_per_m <= 0.0 || q_per_m > q_short {
            0.0
        } else {
            q_per_m.max(q_roll).powf(-2.0 - 2.0 * self.hurst)
        }
    }

    /// C0 such that Σ_q C0·shape(q) / (Lx Ly) = rms², over the wavevectors
    /// q = 2π (i/Lx, j/Ly) of an nx × ny periodic grid.
    pub fn prefactor(&self, nx: usize, ny: usize, pixel_m: f64) -> f64 {
        let (lx, ly) = (nx as f64 * pixel_m, ny as f64 * pixel_m);
        // Row sums in parallel, added in row order: a parallel `sum` would
        // add them in an order that depends on the thread count.
        let row_sums: Vec<f64> = (0..nx)
            .into_par_iter()
            .map(|i| {
                let qx = wavevector(i, nx, lx);
                (0..ny)
                    .map(|j| self.shape(qx.hypot(wavevector(j, ny, ly))))
                    .sum::<f64>()
            })
            .collect();
        let sum: f64 = row_sums.iter().sum();
        if sum > 0.0 {
            self.rms_m * self.rms_m * lx * ly / sum
        } else {
            0.0
        }
    }

    /// The prescribed C(q) (m⁴) on an nx × ny grid of spacing `pixel_m`.
    pub fn psd(&self, nx: usize, ny: usize, pixel_m: f64) -> impl Fn(f64) -> f64 + use<> {
        let c0 = self.prefactor(nx, ny, pixel_m);
        let this = *self;
        move |q| c0 * this.shape(q)
    }

    /// One periodic realisation on an nx × ny grid (axis 0 = x), metres.
    pub fn periodic(&self, nx: usize, ny: usize, pixel_m: f64, seed: u64) -> Array2<f64> {
        self.periodic_corner(nx, ny, pixel_m, seed, [nx, ny])
            .expect("the generator's grids are not empty")
    }

    /// The `corner_px[0] × corner_px[1]` corner of [`Self::periodic`]'s
    /// realisation on an nx × ny grid, to the bit, without that grid ever
    /// existing (issue #35: a paper-scale grid is ~14 000² points): the
    /// white noise is drawn a band of rows at a time straight into the row
    /// transforms, in the order a whole grid would take its draws, and only
    /// the corner comes back from the spectrum.
    pub fn periodic_corner(
        &self,
        nx: usize,
        ny: usize,
        pixel_m: f64,
        seed: u64,
        corner_px: [usize; 2],
    ) -> Result<Array2<f64>, NumericError> {
        let c0 = self.prefactor(nx, ny, pixel_m);
        let (lx, ly) = (nx as f64 * pixel_m, ny as f64 * pixel_m);
        let n = (nx * ny) as f64;
        // White noise of unit variance has E|W_k|² = N; the filter makes
        // E|Δx Δy H_k|² = C(q_k) Lx Ly, the normalisation in the module doc.
        // The unnormalised inverse transforms contribute the last 1/N.
        let gain = |q: f64| (c0 * self.shape(q) * lx * ly / n).sqrt() / (pixel_m * pixel_m) / n;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let corner = RealFft2::new(nx, ny)?.filtered_crop(
            // Row-major draws, band after band: a whole grid's order, drawn
            // again from the seed by each pass over the rows.
            |first, lines| {
                if first == 0 {
                    rng = ChaCha8Rng::seed_from_u64(seed);
                }
                for h in lines {
                    *h = StandardNormal.sample(&mut rng);
                }
            },
            |i, j| gain(wavevector(i, nx, lx).hypot(wavevector(j, ny, ly))),
            (corner_px[0], corner_px[1]),
        )?;
        Ok(Array2::from_shape_vec((corner_px[0], corner_px[1]), corner)
            .expect("the crop has the corner's points"))
    }

    /// A non-periodic nx × ny map: the corner of a periodic realisation
    /// twice as large each way, so opposite edges do not match (as on a
    /// measured sample), metres.
    pub fn non_periodic(&self, nx: usize, ny: usize, pixel_m: f64, seed: u64) -> Array2<f64> {
        self.periodic_corner(2 * nx, 2 * ny, pixel_m, seed, [nx, ny])
            .expect("the generator's grids are not empty")
    }
}

/// The signed wavevector (rad/m) of FFT index `i` on `n` points over `l`.
fn wavevector(i: usize, n: usize, l: f64) -> f64 {
    let k = if i <= n / 2 {
        i as f64
    } else {
        i as f64 - n as f64
    };
    std::f64::consts::TAU * k / l
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(hurst: f64) -> SelfAffine {
        SelfAffine {
            hurst,
            rms_m: 1e-6,
            lambda_min_m: 4e-6,
            lambda_max_m: 64e-6,
        }
    }

    #[test]
    fn realisation_has_the_prescribed_rms_and_zero_mean() {
        let h = spec(0.8).periodic(256, 192, 1e-6, 7);
        let n = h.len() as f64;
        let mean = h.sum() / n;
        let rms = (h.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        assert!(mean.abs() < 1e-12, "mean {mean}");
        // The rms of one realisation scatters with the few long-wavelength
        // modes of the roll-off: a few per cent here.
        assert!((rms / 1e-6 - 1.0).abs() < 0.1, "rms {rms}");
    }

    #[test]
    fn a_non_periodic_map_is_the_corner_of_a_doubled_periodic_one() {
        let corner = spec(0.8).non_periodic(40, 30, 1e-6, 5);
        let full = spec(0.8).periodic(80, 60, 1e-6, 5);
        assert_eq!(corner.dim(), (40, 30));
        for ((i, j), h) in corner.indexed_iter() {
            assert_eq!(*h, full[[i, j]]);
        }
    }

    /// The realisation as it was made before issue #35: the whole noise
    /// grid drawn, filtered in place, the corner copied out.
    fn corner_of_the_whole_grid(
        s: &SelfAffine,
        (nx, ny): (usize, usize),
        seed: u64,
        [cx, cy]: [usize; 2],
    ) -> Array2<f64> {
        let pixel_m = 1e-6;
        let c0 = s.prefactor(nx, ny, pixel_m);
        let (lx, ly) = (nx as f64 * pixel_m, ny as f64 * pixel_m);
        let n = (nx * ny) as f64;
        let gain = |q: f64| (c0 * s.shape(q) * lx * ly / n).sqrt() / (pixel_m * pixel_m) / n;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut grid = Array2::<f64>::zeros((nx, ny));
        for h in grid.iter_mut() {
            *h = StandardNormal.sample(&mut rng);
        }
        RealFft2::new(nx, ny)
            .unwrap()
            .filter_in_place(grid.as_slice_mut().unwrap(), |i, j| {
                gain(wavevector(i, nx, lx).hypot(wavevector(j, ny, ly)))
            })
            .unwrap();
        Array2::from_shape_fn((cx, cy), |(i, j)| grid[[i, j]])
    }

    #[test]
    fn a_corner_has_the_bits_of_the_whole_grid_drawn_filtered_and_cut() {
        // Grids of several noise bands, odd and even sides; the whole grid,
        // a corner as synth-surface cuts it, a thin strip.
        let s = spec(0.7);
        for (grid, corner) in [
            ((150, 97), [150, 97]),
            ((150, 97), [101, 66]),
            ((128, 135), [3, 135]),
            ((75, 64), [60, 1]),
        ] {
            let expected = corner_of_the_whole_grid(&s, grid, 9, corner);
            let got = s.periodic_corner(grid.0, grid.1, 1e-6, 9, corner).unwrap();
            let bits = |h: &Array2<f64>| h.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
            assert!(bits(&got) == bits(&expected), "{grid:?} cut to {corner:?}");
        }
        let whole = corner_of_the_whole_grid(&s, (90, 70), 4, [90, 70]);
        assert_eq!(s.periodic(90, 70, 1e-6, 4), whole);
    }

    #[test]
    fn a_corner_larger_than_the_grid_is_refused() {
        let e = spec(0.7)
            .periodic_corner(40, 30, 1e-6, 1, [41, 30])
            .unwrap_err();
        assert!(matches!(e, NumericError::MapTooLarge { .. }), "{e}");
    }

    #[test]
    fn realisation_has_the_same_bits_on_any_number_of_threads() {
        let make = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| spec(0.7).periodic(300, 200, 1e-6, 3))
        };
        let bits = |h: Array2<f64>| h.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
        let one = bits(make(1));
        for threads in [2, 4] {
            assert!(bits(make(threads)) == one, "{threads} threads");
        }
    }

    #[test]
    fn spectrum_shape_has_roll_off_and_cut_off() {
        let s = spec(0.5);
        let q_roll = std::f64::consts::TAU / 64e-6;
        assert_eq!(s.shape(0.0), 0.0);
        assert_eq!(s.shape(q_roll / 3.0), s.shape(q_roll));
        assert!((s.shape(2.0 * q_roll) / s.shape(q_roll) - 2f64.powf(-3.0)).abs() < 1e-12);
        assert_eq!(s.shape(std::f64::consts::TAU / 3.9e-6), 0.0);
    }

    #[test]
    fn rms_of_differences_scales_with_the_hurst_exponent() {
        // For a self-affine profile the height difference over a lag δ grows
        // as δ^H; check the exponent from lags 2 and 8 pixels along x, well
        // inside the band (2 to 512 pixels).
        let hurst = 0.8;
        let n = 512;
        let h = SelfAffine {
            hurst,
            rms_m: 1.0,
            lambda_min_m: 2.0,
            lambda_max_m: n as f64,
        }
        .periodic(n, n, 1.0, 11);
        let rms_diff = |lag: usize| {
            let mut s = 0.0;
            for ix in 0..n - lag {
                for iy in 0..n {
                    s += (h[[ix + lag, iy]] - h[[ix, iy]]).powi(2);
                }
            }
            (s / ((n - lag) * n) as f64).sqrt()
        };
        let slope = (rms_diff(8) / rms_diff(2)).ln() / 4.0_f64.ln();
        assert!((slope - hurst).abs() < 0.1, "fitted H = {slope}");
    }

    #[test]
    fn same_seed_same_surface() {
        let a = spec(0.7).periodic(64, 64, 1e-6, 3);
        let b = spec(0.7).periodic(64, 64, 1e-6, 3);
        let c = spec(0.7).periodic(64, 64, 1e-6, 4);
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
