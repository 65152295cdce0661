//! R̄(g) tabulated for rendering: a 2048² frame needs four million
//! reflectances, and the spectral sum costs ~800 cosines each.
//!
//! The table holds the spectral average on an even gap grid from 0 to a
//! coherence cutoff and interpolates linearly between nodes; node 0 is the
//! contact reflectance exactly (at g = 0 every wavelength gives the
//! glass–rubber value). Beyond the cutoff the fringes have washed out and
//! the incoherent sum is returned.
//!
//! **The cutoff** is found, not assumed: R̄(g) − R_inc is scanned every 5 nm
//! (38 samples per fringe period at 380 nm, so a fringe's extremum is seen to
//! within 0.4 %) out to `max_gap_m`, and the cutoff is the first scan node
//! after which every node stays within half the tolerance. The fringes must
//! have settled over the last tenth of the scanned range, else the spectrum
//! is refused as too narrow ([`InterferenceError::Coherent`]). For the
//! built-in white LED the blue line (20 nm wide, coherence length
//! λ²/Δλ ≈ 10 µm) sets it: 9.79 µm at the default tolerance 1e-7, which
//! is 4 % of one 16-bit count when the brightest fringe is exposed to 80 %
//! of full scale (and 1/3000 of the shot noise there).
//!
//! **The wavelength grids** are chosen by [`SpectralAverage::resolving`]:
//! one that resolves R(δ)'s harmonics out to `max_gap_m` for the scan, one
//! out to the cutoff for the table.
//!
//! **The gap step** bounds the interpolation error by h²/8 · max |R̄''| ≈
//! h²/8 · |a1| (4π n/λ)² ≈ 3e-7 at h = 0.2 nm and λ = 450 nm (2.3e-7
//! measured), inside the 1e-6 the tests hold it to.

use rayon::prelude::*;

use crate::error::{InterferenceError, positive};
use crate::film::{SpectralAverage, Stack};
use crate::spectrum::Spectrum;

/// Gap step of the coherence scan, m.
const SCAN_STEP_M: f64 = 5e-9;
/// The range `max_gap_m` may take, m: at 200 µm the scan's wavelength grid
/// already has ~13 000 nodes for 40 000 gaps (about a second).
const MIN_SCAN_M: f64 = 1e-7;
const MAX_SCAN_M: f64 = 200e-6;
/// Table nodes per parallel block; blocks are fixed by index, so the values
/// do not depend on the thread count.
const BLOCK: usize = 4096;
/// The largest table accepted (400 MB; more would be a mistake in the inputs).
const MAX_NODES: usize = 50_000_000;

/// How the table is laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableParams {
    /// gap between nodes, m
    pub step_m: f64,
    /// |R̄ − R_inc| accepted beyond the cutoff (absolute reflectance)
    pub coherence_tolerance: f64,
    /// how far the cutoff is searched for, m
    pub max_gap_m: f64,
}

impl Default for TableParams {
    fn default() -> Self {
        Self {
            step_m: 0.2e-9,
            coherence_tolerance: 1e-7,
            max_gap_m: 20e-6,
        }
    }
}

impl TableParams {
    pub fn check(&self) -> Result<(), InterferenceError> {
        positive("step_m", self.step_m)?;
        positive("coherence_tolerance", self.coherence_tolerance)?;
        positive("max_gap_m", self.max_gap_m)?;
        if self.step_m > 5e-9 {
            return Err(InterferenceError::param(
                "step_m",
                self.step_m,
                "must be at most 5e-9 m (a fortieth of a fringe) for linear interpolation",
            ));
        }
        if !(MIN_SCAN_M..=MAX_SCAN_M).contains(&self.max_gap_m) {
            return Err(InterferenceError::param(
                "max_gap_m",
                self.max_gap_m,
                format!(
                    "must lie in [{MIN_SCAN_M:e}, {MAX_SCAN_M:e}] m (a source coherent beyond \
                     is no white light)"
                ),
            ));
        }
        Ok(())
    }
}

/// R̄(g) by table lookup.
#[derive(Clone, Debug, PartialEq)]
pub struct ReflectanceTable {
    step_m: f64,
    inverse_step: f64,
    /// R̄ at k · step_m, k = 0 … n − 1; the last node is the cutoff
    values: Vec<f64>,
    background: f64,
    max_reflectance: f64,
    quadrature_step_nm: f64,
}

impl ReflectanceTable {
    pub fn new(
        stack: Stack,
        spectrum: &Spectrum,
        params: &TableParams,
    ) -> Result<Self, InterferenceError> {
        params.check()?;
        let background = stack.incoherent_reflectance();
        let scan = SpectralAverage::resolving(stack, spectrum, params.max_gap_m)?;
        let cutoff_m = coherence_cutoff(&scan, background, params)?;
        let average = SpectralAverage::resolving(stack, spectrum, cutoff_m)?;

        let nodes = (cutoff_m / params.step_m).ceil() as usize + 1;
        if nodes > MAX_NODES {
            return Err(InterferenceError::param(
                "step_m",
                params.step_m,
                format!(
                    "gives {nodes} nodes up to the cutoff {cutoff_m:e} m (at most {MAX_NODES})"
                ),
            ));
        }
        let mut values = vec![0.0; nodes];
        values
            .par_chunks_mut(BLOCK)
            .enumerate()
            .for_each(|(block, chunk)| {
                let first = (block * BLOCK) as f64 * params.step_m;
                average.reflectance_run(first, params.step_m, chunk);
            });
        values[0] = stack.contact_reflectance();
        let max_reflectance = values.iter().fold(background, |m, &v| m.max(v));
        Ok(Self {
            step_m: params.step_m,
            inverse_step: 1.0 / params.step_m,
            values,
            background,
            max_reflectance,
            quadrature_step_nm: average.step_nm(),
        })
    }

    /// R̄ at a gap of `gap_m`: linear between nodes, the contact value at
    /// g ≤ 0 (a solver's slight overlap is contact), the background beyond
    /// the cutoff and for NaN (a point nobody measured shows as far away).
    #[inline]
    pub fn reflectance(&self, gap_m: f64) -> f64 {
        let u = gap_m * self.inverse_step;
        let last = (self.values.len() - 1) as f64;
        // NaN and +∞ show as the background
        if u.is_nan() || u >= last {
            return self.background;
        }
        if u <= 0.0 {
            return self.values[0];
        }
        let k = u as usize;
        let t = u - k as f64;
        let (v0, v1) = (self.values[k], self.values[k + 1]);
        v0 + t * (v1 - v0)
    }

    /// Replaces every gap (m) by its reflectance, in parallel.
    pub fn apply(&self, gap_to_reflectance: &mut [f64]) {
        gap_to_reflectance
            .par_chunks_mut(BLOCK)
            .for_each(|chunk| chunk.iter_mut().for_each(|v| *v = self.reflectance(*v)));
    }

    /// R at contact (node 0).
    pub fn contact(&self) -> f64 {
        self.values[0]
    }

    /// The incoherent sum, returned beyond the cutoff.
    pub fn background(&self) -> f64 {
        self.background
    }

    /// The brightest value the table returns (the first bright fringe).
    pub fn max_reflectance(&self) -> f64 {
        self.max_reflectance
    }

    /// The gap beyond which the background is returned, m.
    pub fn cutoff_m(&self) -> f64 {
        (self.values.len() - 1) as f64 * self.step_m
    }

    pub fn step_m(&self) -> f64 {
        self.step_m
    }

    /// The wavelength step the nodes were integrated with, nm.
    pub fn quadrature_step_nm(&self) -> f64 {
        self.quadrature_step_nm
    }

    /// R̄ at the nodes k · step_m.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// The gap beyond which |R̄ − R_inc| stays within half the tolerance.
fn coherence_cutoff(
    average: &SpectralAverage,
    background: f64,
    params: &TableParams,
) -> Result<f64, InterferenceError> {
    let nodes = (params.max_gap_m / SCAN_STEP_M).ceil() as usize + 1;
    let mut residual = vec![0.0; nodes];
    residual
        .par_chunks_mut(BLOCK)
        .enumerate()
        .for_each(|(block, chunk)| {
            average.reflectance_run((block * BLOCK) as f64 * SCAN_STEP_M, SCAN_STEP_M, chunk);
            chunk.iter_mut().for_each(|v| *v = (*v - background).abs());
        });
    let half = 0.5 * params.coherence_tolerance;
    let settled_from = residual
        .iter()
        .rposition(|&r| r > half)
        .map_or(0, |k| k + 1);
    if settled_from as f64 > 0.9 * (nodes - 1) as f64 {
        return Err(InterferenceError::Coherent {
            residual: residual[nodes - 1].max(residual[settled_from.min(nodes) - 1]),
            tolerance: params.coherence_tolerance,
            max_gap_m: params.max_gap_m,
        });
    }
    // at least one fringe period of table even for a nearly incoherent source
    Ok((settled_from as f64 * SCAN_STEP_M).max(1e-6))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Indices;
    use crate::spectrum::GaussianLine;

    fn stack() -> Stack {
        Stack::new(Indices::default()).unwrap()
    }

    fn white_table() -> ReflectanceTable {
        ReflectanceTable::new(stack(), &Spectrum::white_led(), &TableParams::default()).unwrap()
    }

    #[test]
    fn lookup_matches_the_direct_integral() {
        let table = white_table();
        // the direct integral on a finer grid than either of the table's
        let direct = SpectralAverage::new(stack(), &Spectrum::white_led(), 0.1).unwrap();
        assert_eq!(table.contact(), stack().contact_reflectance());
        assert_eq!(table.reflectance(0.0), table.contact());
        // off-node gaps from a fixed quasi-random sequence, dense near contact
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            let u = (k as f64 * 0.618_033_988_749_895).fract();
            let g = u * u * 1.5 * table.cutoff_m();
            worst = worst.max((table.reflectance(g) - direct.reflectance(g)).abs());
        }
        assert!(worst < 1e-6, "worst {worst:e}");
        // beyond the cutoff: the background, and the direct integral agrees
        for g in [1.0001, 1.3, 2.0, 4.0].map(|f| f * table.cutoff_m()) {
            assert_eq!(table.reflectance(g), table.background());
            assert!(
                (direct.reflectance(g) - table.background()).abs() < 1e-7,
                "{g}"
            );
        }
        // the cutoff is where the blue line's coherence runs out (see below)
        assert!(
            (8e-6..12e-6).contains(&table.cutoff_m()),
            "{}",
            table.cutoff_m()
        );
        println!(
            "cutoff {:.3} µm, {} nodes, λ step {:.3} nm, worst lookup error {worst:.2e}",
            table.cutoff_m() * 1e6,
            table.values().len(),
            table.quadrature_step_nm()
        );
    }

    #[test]
    fn same_table_on_one_and_two_threads() {
        let build = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(white_table)
        };
        assert_eq!(build(1), build(2));
    }

    #[test]
    fn special_gaps() {
        let table = white_table();
        assert_eq!(table.reflectance(f64::NAN), table.background());
        assert_eq!(table.reflectance(f64::INFINITY), table.background());
        assert_eq!(table.reflectance(-1e-9), table.contact());
        assert_eq!(table.reflectance(f64::NEG_INFINITY), table.contact());
        assert_eq!(table.reflectance(1.0), table.background());
        let mut gaps = vec![0.0, f64::NAN, 1.0, 0.1e-9];
        table.apply(&mut gaps);
        assert_eq!(
            gaps[..3],
            [table.contact(), table.background(), table.background()]
        );
        assert!((gaps[3] - 0.5 * (table.values()[0] + table.values()[1])).abs() < 1e-15);
        // the first bright fringe, ~1.86 × the background
        assert!((table.max_reflectance() / table.background() - 1.86).abs() < 0.02);
    }

    #[test]
    fn cutoff_follows_the_coherence_length() {
        // one Gaussian line: harmonic 1 of R̄ − R_inc is a1 · Re Γ(g), with
        // Γ(g) = ∫ S e^{i 4π n g / λ} dλ / ∫ S the source's coherence; the
        // cutoff is where a1 |Γ| falls to half the tolerance for good, within
        // one fringe period (the residual peaks once per period). |Γ| is
        // brute-forced here on a fine grid; the Gaussian-in-k estimate
        // exp(−(2 n g σ_k)² / 2) is checked loosely (the line is skewed in k).
        let stack = stack();
        for fwhm_nm in [15.0, 30.0] {
            let spectrum = Spectrum::Gaussians {
                lines: vec![GaussianLine {
                    centre_nm: 550.0,
                    fwhm_nm,
                    peak: 1.0,
                }],
                min_nm: 350.0,
                max_nm: 750.0,
            };
            let tol = 1e-7;
            let params = TableParams {
                coherence_tolerance: tol,
                max_gap_m: 40e-6,
                ..TableParams::default()
            };
            let table = ReflectanceTable::new(stack, &spectrum, &params).unwrap();
            let a1 = stack.harmonic(1).abs();
            let sigma_k = 2.0 * std::f64::consts::PI * fwhm_nm
                / (8.0 * 2f64.ln()).sqrt()
                / (550.0f64 * 550.0)
                * 1e9;
            let gaussian = (2.0 * (2.0 * a1 / tol).ln()).sqrt() / (2.0 * sigma_k);
            let coherence = |g: f64| {
                let (mut re, mut im, mut total) = (0.0, 0.0, 0.0);
                for k in 0..=20_000 {
                    let lambda_nm = 350.0 + 0.02 * k as f64;
                    let w = spectrum.power(lambda_nm);
                    let phase = 4.0 * std::f64::consts::PI * g * 1e9 / lambda_nm;
                    re += w * phase.cos();
                    im += w * phase.sin();
                    total += w;
                }
                re.hypot(im) / total
            };
            // searched over ±40 % of the Gaussian estimate (asserted below)
            let last = (0..400)
                .rev()
                .map(|k| gaussian * (0.6 + 0.002 * k as f64))
                .find(|&g| a1 * coherence(g) > 0.5 * tol)
                .unwrap();
            let period = 550e-9 / 2.0;
            let search_step = 0.002 * gaussian;
            assert!(
                table.cutoff_m() <= last + search_step && table.cutoff_m() > last - period,
                "FWHM {fwhm_nm}: cutoff {} vs envelope {last}",
                table.cutoff_m()
            );
            assert!((table.cutoff_m() / gaussian - 1.0).abs() < 0.06);
            assert!(a1 * coherence(1.4 * gaussian) < 0.5 * tol);
        }
    }

    #[test]
    fn a_laser_is_refused() {
        let laser = Spectrum::Gaussians {
            lines: vec![GaussianLine {
                centre_nm: 632.8,
                fwhm_nm: 0.5,
                peak: 1.0,
            }],
            min_nm: 630.0,
            max_nm: 636.0,
        };
        let err = ReflectanceTable::new(stack(), &laser, &TableParams::default()).unwrap_err();
        assert!(matches!(err, InterferenceError::Coherent { .. }), "{err}");
    }

    #[test]
    fn bad_params_are_refused() {
        for p in [
            TableParams {
                step_m: 0.0,
                ..TableParams::default()
            },
            TableParams {
                step_m: 1e-8,
                ..TableParams::default()
            },
            TableParams {
                coherence_tolerance: f64::NAN,
                ..TableParams::default()
            },
            TableParams {
                max_gap_m: -1.0,
                ..TableParams::default()
            },
            TableParams {
                max_gap_m: 1.0,
                ..TableParams::default()
            },
        ] {
            assert!(
                ReflectanceTable::new(stack(), &Spectrum::white_led(), &p).is_err(),
                "{p:?}"
            );
        }
    }
}
