//! The tables of stage `surface`, declared once: each struct is both the
//! column list the stage declares and the table it builds (the report reads
//! them from here).

use hypercontact_core::Schema;

use ndarray::Array2;

use crate::SurfaceError;
use crate::iso25178::{
    ArealParameters, Autocorrelation, Axis, Histogram, MaterialRatio, lag_ladder,
    scale_dependent_curvature, scale_dependent_slope,
};
use crate::psd::Spectrum;
use crate::stitch::TileFit;
use crate::tiles::TileSet;

/// Output `psd`: the binned PSDs along x, y and radially, one after another.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct PsdTable {
    /// x, y or radial
    pub direction: Vec<String>,
    /// wavevector, mean of the bin's members
    #[column(unit = "rad/m")]
    pub q_per_m: Vec<f64>,
    /// PSD, mean of the bin's members
    #[column(unit = "m³ (x, y) or m⁴ (radial)")]
    pub c: Vec<f64>,
}

impl PsdTable {
    /// Appends the bins of one spectrum under `direction`.
    pub fn push(&mut self, direction: &str, spectrum: &Spectrum) {
        let bins = spectrum.c.len();
        self.direction
            .extend(std::iter::repeat_n(direction.to_owned(), bins));
        self.q_per_m.extend_from_slice(&spectrum.q_per_m);
        self.c.extend_from_slice(&spectrum.c);
    }
}

/// Output `stats`: one row.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct StatsTable {
    /// areal rms height Sq after detrending
    #[column(unit = "m")]
    pub sigma_m: Vec<f64>,
    /// rms gradient √⟨|∇h|²⟩
    pub rms_slope: Vec<f64>,
    /// Hurst exponent from the PSD along x
    pub hurst_x: Vec<f64>,
    /// Hurst exponent from the PSD along y
    pub hurst_y: Vec<f64>,
    /// Hurst exponent from the radial PSD
    pub hurst_radial: Vec<f64>,
    /// R² of the Hurst fit along x (ln C on ln q)
    pub hurst_x_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along x used
    #[column(unit = "rad/m")]
    pub hurst_x_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along x used
    #[column(unit = "rad/m")]
    pub hurst_x_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_x_flag: Vec<String>,
    /// R² of the Hurst fit along y (ln C on ln q)
    pub hurst_y_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along y used
    #[column(unit = "rad/m")]
    pub hurst_y_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along y used
    #[column(unit = "rad/m")]
    pub hurst_y_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_y_flag: Vec<String>,
    /// R² of the Hurst fit along radial (ln C on ln q)
    pub hurst_radial_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along radial used
    #[column(unit = "rad/m")]
    pub hurst_radial_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along radial used
    #[column(unit = "rad/m")]
    pub hurst_radial_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_radial_flag: Vec<String>,
    /// points along x of the analysed (filtered) map
    pub nx: Vec<i64>,
    /// points along y of the analysed (filtered) map
    pub ny: Vec<i64>,
    /// grid spacing along x of the analysed (filtered) map
    #[column(unit = "m")]
    pub dx_m: Vec<f64>,
    /// grid spacing along y of the analysed (filtered) map
    #[column(unit = "m")]
    pub dy_m: Vec<f64>,
    /// points along x of the map before filtering (as measured or stitched)
    pub nx_measured: Vec<i64>,
    /// points along y before filtering
    pub ny_measured: Vec<i64>,
    /// grid spacing along x before filtering
    #[column(unit = "m")]
    pub dx_measured_m: Vec<f64>,
    /// grid spacing along y before filtering
    #[column(unit = "m")]
    pub dy_measured_m: Vec<f64>,
    /// share of unmeasured points in `height`
    pub nan_fraction: Vec<f64>,
    /// how missing points were filled before the PSDs: harmonic or zero
    pub fill: Vec<String>,
    /// missing points filled before the PSDs
    pub filled_points: Vec<i64>,
    /// filled_points over all points of the analysed grid
    pub filled_fraction: Vec<f64>,
}

/// Output `stitch`: one row per tile (none for a map from input `height`).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct StitchTable {
    /// the tile column of positions.csv
    pub tile: Vec<i64>,
    /// tile file
    pub file: Vec<String>,
    /// recorded position of pixel [0, 0], x
    #[column(unit = "px")]
    pub x_nominal_px: Vec<f64>,
    /// recorded position of pixel [0, 0], y
    #[column(unit = "px")]
    pub y_nominal_px: Vec<f64>,
    /// position found by stitching, x
    #[column(unit = "px")]
    pub x_found_px: Vec<f64>,
    /// position found by stitching, y
    #[column(unit = "px")]
    pub y_found_px: Vec<f64>,
    /// found minus nominal, x
    #[column(unit = "px")]
    pub x_offset_px: Vec<f64>,
    /// found minus nominal, y
    #[column(unit = "px")]
    pub y_offset_px: Vec<f64>,
    /// slope removed along x (about the tile centre)
    #[column(unit = "rad")]
    pub tilt_x_rad: Vec<f64>,
    /// slope removed along y
    #[column(unit = "rad")]
    pub tilt_y_rad: Vec<f64>,
    /// height removed at the tile centre
    #[column(unit = "m")]
    pub piston_m: Vec<f64>,
    /// mean Pearson correlation of its aligned overlaps
    pub overlap_correlation: Vec<f64>,
    /// overlaps of this tile dropped as outliers (registered offset > 0.5 px from the joint solution)
    pub pairs_rejected: Vec<i64>,
}

impl StitchTable {
    /// One row per tile of the set, from the stitching's fits (in set order).
    pub fn new(set: &TileSet, fits: &[TileFit]) -> Self {
        let column = |f: fn(&TileFit) -> f64| fits.iter().map(f).collect();
        StitchTable {
            tile: set.ids.clone(),
            file: set.names.clone(),
            x_nominal_px: column(|t| t.nominal_px[0]),
            y_nominal_px: column(|t| t.nominal_px[1]),
            x_found_px: column(|t| t.found_px[0]),
            y_found_px: column(|t| t.found_px[1]),
            x_offset_px: column(|t| t.found_px[0] - t.nominal_px[0]),
            y_offset_px: column(|t| t.found_px[1] - t.nominal_px[1]),
            tilt_x_rad: column(|t| t.tilt_rad[0]),
            tilt_y_rad: column(|t| t.tilt_rad[1]),
            piston_m: column(|t| t.piston_m),
            overlap_correlation: column(|t| t.correlation),
            pairs_rejected: fits.iter().map(|t| t.pairs_rejected as i64).collect(),
        }
    }
}

/// Output `areal`: one row, the ISO 25178-2 areal parameters of the
/// analysed map about its mean plane (see [`crate::iso25178`]).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ArealTable {
    /// arithmetical mean height Sa = ⟨|z|⟩
    #[column(unit = "m")]
    pub sa_m: Vec<f64>,
    /// root mean square height Sq (= stats' sigma_m up to rounding)
    #[column(unit = "m")]
    pub sq_m: Vec<f64>,
    /// skewness Ssk = ⟨z³⟩/Sq³
    pub ssk: Vec<f64>,
    /// kurtosis Sku = ⟨z⁴⟩/Sq⁴ (3 for Gaussian heights)
    pub sku: Vec<f64>,
    /// maximum peak height Sp
    #[column(unit = "m")]
    pub sp_m: Vec<f64>,
    /// maximum pit depth Sv (positive)
    #[column(unit = "m")]
    pub sv_m: Vec<f64>,
    /// maximum height Sz = Sp + Sv
    #[column(unit = "m")]
    pub sz_m: Vec<f64>,
    /// root mean square gradient Sdq (forward differences, as stats' rms_slope)
    pub sdq: Vec<f64>,
    /// developed interfacial area ratio Sdr (cells with four measured corners, two triangulations averaged)
    #[column(unit = "%")]
    pub sdr_percent: Vec<f64>,
    /// autocorrelation length Sal: shortest lag at which the ACF falls to 0.2
    #[column(unit = "m")]
    pub sal_m: Vec<f64>,
    /// texture aspect ratio Str: shortest / longest decay length to 0.2 (an upper bound where a direction never decays within half the map)
    pub str: Vec<f64>,
    /// core height Sk (ISO 13565-2 equivalence line over 40 % of material ratio)
    #[column(unit = "m")]
    pub sk_m: Vec<f64>,
    /// reduced peak height Spk
    #[column(unit = "m")]
    pub spk_m: Vec<f64>,
    /// reduced valley depth Svk
    #[column(unit = "m")]
    pub svk_m: Vec<f64>,
    /// material ratio at the top of the core Smr1
    #[column(unit = "%")]
    pub smr1_percent: Vec<f64>,
    /// material ratio at the bottom of the core Smr2
    #[column(unit = "%")]
    pub smr2_percent: Vec<f64>,
    /// lag at which the radially averaged ACF falls to 1/e
    #[column(unit = "m")]
    pub correlation_length_m: Vec<f64>,
}

impl ArealTable {
    /// One row of NaN: parameters that could not be computed.
    pub fn unknown() -> Self {
        let nan = f64::NAN;
        Self::new(&ArealParameters {
            sa_m: nan,
            sq_m: nan,
            ssk: nan,
            sku: nan,
            sp_m: nan,
            sv_m: nan,
            sz_m: nan,
            sdq: nan,
            sdr_percent: nan,
            sal_m: nan,
            str: nan,
            sk_m: nan,
            spk_m: nan,
            svk_m: nan,
            smr1_percent: nan,
            smr2_percent: nan,
            correlation_length_m: nan,
        })
    }

    /// The one row of `a`.
    pub fn new(a: &ArealParameters) -> Self {
        Self {
            sa_m: vec![a.sa_m],
            sq_m: vec![a.sq_m],
            ssk: vec![a.ssk],
            sku: vec![a.sku],
            sp_m: vec![a.sp_m],
            sv_m: vec![a.sv_m],
            sz_m: vec![a.sz_m],
            sdq: vec![a.sdq],
            sdr_percent: vec![a.sdr_percent],
            sal_m: vec![a.sal_m],
            str: vec![a.str],
            sk_m: vec![a.sk_m],
            spk_m: vec![a.spk_m],
            svk_m: vec![a.svk_m],
            smr1_percent: vec![a.smr1_percent],
            smr2_percent: vec![a.smr2_percent],
            correlation_length_m: vec![a.correlation_length_m],
        }
    }
}

/// Output `material_ratio`: the Abbott–Firestone curve, heights about the
/// mean plane against the share of the area at or above them.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct MaterialRatioTable {
    /// material ratio Smr, 0 … 100 in even steps
    #[column(unit = "%")]
    pub material_ratio_percent: Vec<f64>,
    /// height Smc at that ratio, about the mean plane
    #[column(unit = "m")]
    pub height_m: Vec<f64>,
}

impl MaterialRatioTable {
    /// The curve of `ratio` at `points` even steps of material ratio.
    pub fn new(ratio: &MaterialRatio, points: usize) -> Self {
        let (material_ratio_percent, height_m) = ratio.curve(points);
        Self {
            material_ratio_percent,
            height_m,
        }
    }
}

/// Output `distributions`: the histograms of height (about the mean
/// plane), slope |∇h| and curvature ∇²h/2 (central differences), one after
/// another, equal-width bins from each quantity's smallest value to its
/// largest (see [`crate::iso25178::distributions`]).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct DistributionsTable {
    /// height, slope or curvature
    pub quantity: Vec<String>,
    /// the unit of bin_lo and bin_hi on this row: m (height), 1 (slope, dimensionless) or 1/m (curvature)
    pub unit: Vec<String>,
    /// lower edge of the bin
    #[column(unit = "m (height), 1 (slope) or 1/m (curvature): see unit")]
    pub bin_lo: Vec<f64>,
    /// upper edge of the bin (the last bin holds its upper edge)
    #[column(unit = "m (height), 1 (slope) or 1/m (curvature): see unit")]
    pub bin_hi: Vec<f64>,
    /// points in the bin
    pub count: Vec<i64>,
    /// probability density count / (points · bin width), integrating to 1 (NaN for a bin of zero width)
    #[column(unit = "1/m (height), 1 (slope) or m (curvature): 1 over unit")]
    pub density: Vec<f64>,
}

impl DistributionsTable {
    /// Appends the bins of `histogram` as `quantity` in `unit`.
    pub fn push(&mut self, quantity: &str, unit: &str, histogram: &Histogram) {
        let bins = histogram.counts.len();
        self.quantity
            .extend(std::iter::repeat_n(quantity.to_owned(), bins));
        self.unit.extend(std::iter::repeat_n(unit.to_owned(), bins));
        self.bin_lo.extend_from_slice(&histogram.edges[..bins]);
        self.bin_hi.extend_from_slice(&histogram.edges[1..]);
        self.count.extend(
            histogram
                .counts
                .iter()
                .map(|&c| i64::try_from(c).unwrap_or(i64::MAX)),
        );
        self.density.extend(histogram.density());
    }
}

/// Output `acf`: the normalised areal autocorrelation f_ACF (see
/// [`crate::iso25178::acf`]) radially averaged, and along the x and y axes,
/// one after another.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct AcfTable {
    /// radial (mean over a ring of lags), x or y
    pub direction: Vec<String>,
    /// lag length (radial: mean |τ| of the ring's lags)
    #[column(unit = "m")]
    pub lag_m: Vec<f64>,
    /// f_ACF = ⟨z(r) z(r + τ)⟩ / ⟨z²⟩ over pairs of measured points (1 at lag 0; NaN where no pair)
    pub acf: Vec<f64>,
}

impl AcfTable {
    /// The radial average and the two axis profiles of `acf`.
    pub fn new(acf: &Autocorrelation) -> Self {
        let mut table = Self::default();
        for (direction, (lag_m, values)) in [
            ("radial", acf.radial_average()),
            ("x", acf.axis_profile(Axis::X)),
            ("y", acf.axis_profile(Axis::Y)),
        ] {
            table
                .direction
                .extend(std::iter::repeat_n(direction.to_owned(), lag_m.len()));
            table.lag_m.extend(lag_m);
            table.acf.extend(values);
        }
        table
    }
}

/// Output `scale_dependent`: rms slope and rms curvature at the scales
/// k·Δ, k = 1, 2, 4, … ≤ ⌊(min(nx, ny) − 1)/2⌋, Δ = (dx + dy)/2 (see
/// [`crate::iso25178::distributions`]): the slope by upwind differences
/// over k pixels, the curvature by central second differences of step k/2
/// (a stencil k pixels long, so both are read at the same scale).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ScaleDependentTable {
    /// scale k·Δ: the slope's lag and the curvature stencil's length
    #[column(unit = "m")]
    pub scale_m: Vec<f64>,
    /// k, the scale in pixels
    #[column(unit = "px")]
    pub lag_px: Vec<i64>,
    /// rms gradient ⟨gx² + gy²⟩^½, gx = (h[i+k, j] − h[i, j])/(k dx) (fewer than 4 values: NaN)
    pub rms_slope: Vec<f64>,
    /// rms of ∇²h/2 by central second differences of step k/2 (NaN at k = 1 and for fewer than 4 values)
    #[column(unit = "1/m")]
    pub rms_curvature_per_m: Vec<f64>,
}

impl ScaleDependentTable {
    /// The table of the levelled map `h` (NaN = not measured) with
    /// spacings `dx_m`, `dy_m`.
    pub fn new(h: &Array2<f64>, dx_m: f64, dy_m: f64) -> Result<Self, SurfaceError> {
        let (nx, ny) = h.dim();
        let lags = lag_ladder(nx, ny);
        let slope = scale_dependent_slope(h, dx_m, dy_m, &lags)?;
        let steps: Vec<usize> = lags
            .iter()
            .filter(|&&k| k % 2 == 0)
            .map(|k| k / 2)
            .collect();
        let curvature = scale_dependent_curvature(h, dx_m, dy_m, &steps)?;
        let rms_curvature_per_m = lags
            .iter()
            .map(|&k| {
                let at = curvature.lags.iter().position(|&step| 2 * step == k);
                at.map_or(f64::NAN, |i| curvature.value[i])
            })
            .collect();
        Ok(Self {
            scale_m: slope.scale_m,
            lag_px: lags.iter().map(|&k| k as i64).collect(),
            rms_slope: slope.value,
            rms_curvature_per_m,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use super::*;
    use crate::iso25178::{autocorrelation, height_histogram, slope_and_curvature_histograms};

    const A_M: f64 = 1.5e-6;
    const PERIOD: usize = 24;
    const NX: usize = 4 * PERIOD;
    const NY: usize = 40;
    const DX_M: f64 = 1e-6;
    const DY_M: f64 = 1.5e-6;

    /// h = A sin(θi), θ = 2π/P, over whole periods along x, constant
    /// along y (so every y-row is the same profile).
    fn sinusoid() -> Array2<f64> {
        let theta = TAU / PERIOD as f64;
        Array2::from_shape_fn((NX, NY), |(i, _)| A_M * (theta * i as f64).sin())
    }

    /// Σ_{i=0}^{n−1} cos(α + 2θi) in closed form (a geometric sum).
    fn cos_sum(n: usize, alpha: f64, theta: f64) -> f64 {
        (n as f64 * theta).sin() * (alpha + (n as f64 - 1.0) * theta).cos() / theta.sin()
    }

    fn close(x: f64, y: f64, tol: f64, what: &str) {
        assert!(
            (x - y).abs() <= tol * y.abs().max(1e-300),
            "{what}: {x} against {y}"
        );
    }

    /// The ACF of the sinusoid along x is, with the overlap-count
    /// normalisation over N = n − a pairs, cos(θa) − Σ cos(θ(2i + a))/N
    /// (the sum in closed form): cos(2π·lag/P) up to the end effect of a
    /// partial period; along y it is 1 at every lag. The radial rows are
    /// the core's radial average.
    #[test]
    fn the_acf_table_of_a_sinusoid_is_its_finite_sum_and_the_cores_radial_average() {
        let h = sinusoid();
        let acf = autocorrelation(&h, DX_M, DY_M).unwrap();
        let table = AcfTable::new(&acf);
        let theta = TAU / PERIOD as f64;
        let rows = |d: &str| -> Vec<usize> {
            (0..table.direction.len())
                .filter(|&r| table.direction[r] == d)
                .collect()
        };
        let x = rows("x");
        assert_eq!(x.len(), (NX - 1) / 2 + 1, "lags 0 … ⌊(nx − 1)/2⌋");
        for (a, &r) in x.iter().enumerate() {
            close(table.lag_m[r], a as f64 * DX_M, 1e-15, "lag");
            let n = NX - a;
            let expected =
                (theta * a as f64).cos() - cos_sum(n, theta * a as f64, theta) / n as f64;
            assert!(
                (table.acf[r] - expected).abs() < 1e-12,
                "lag {a}: {} against {expected}",
                table.acf[r]
            );
            // and near cos(2π lag/P): the end effect is O(1/(N sin θ))
            let bound = 1.0 / (n as f64 * theta.sin());
            assert!((table.acf[r] - (theta * a as f64).cos()).abs() <= bound);
        }
        let y = rows("y");
        assert_eq!(y.len(), (NY - 1) / 2 + 1);
        for (b, &r) in y.iter().enumerate() {
            close(table.lag_m[r], b as f64 * DY_M, 1e-15, "lag");
            assert!((table.acf[r] - 1.0).abs() < 1e-12, "y lag {b}");
        }
        let (radial_m, radial) = acf.radial_average();
        let radial_rows = rows("radial");
        assert_eq!(radial_rows, (0..radial_m.len()).collect::<Vec<_>>());
        for (k, &r) in radial_rows.iter().enumerate() {
            assert_eq!((table.lag_m[r], table.acf[r]), (radial_m[k], radial[k]));
        }
        assert_eq!(table.acf[radial_rows[0]], 1.0);
        let t = table.into_table();
        assert_eq!(t.column_names(), ["direction", "lag_m", "acf"]);
    }

    /// Upwind differences over k pixels of A sin(θi): gx = (2A/(k dx))
    /// sin(θk/2) cos(θ(i + k/2)), gy = 0, so the rms over the N = nx − k
    /// columns is (2A|sin(θk/2)|/(k dx))·(½ + Σ cos(θk + 2θi)/(2N))^½;
    /// central second differences of step s = k/2 give ∇²h/2 =
    /// −(2A sin²(θs/2)/(s dx)²) sin(θi) over i = s … nx − s − 1, rms
    /// (2A sin²(θs/2)/(s dx)²)(½ − Σ cos(2θs + 2θi)/(2N))^½, N = nx − 2s.
    /// For whole periods these are 2A sin(πk dx/L)/(k dx)/√2 and its
    /// second-difference analogue.
    #[test]
    fn the_scale_dependent_table_of_a_sinusoid_has_the_stencils_finite_sums() {
        let h = sinusoid();
        let table = ScaleDependentTable::new(&h, DX_M, DY_M).unwrap();
        let theta = TAU / PERIOD as f64;
        assert_eq!(table.lag_px, [1, 2, 4, 8, 16], "⌊(40 − 1)/2⌋ = 19");
        for (r, &k) in table.lag_px.iter().enumerate() {
            let k = k as usize;
            close(
                table.scale_m[r],
                k as f64 * (DX_M + DY_M) / 2.0,
                1e-15,
                "scale",
            );
            let n = NX - k;
            let kf = k as f64;
            let amplitude = 2.0 * A_M * (theta * kf / 2.0).sin().abs() / (kf * DX_M);
            let mean_cos2 = 0.5 + cos_sum(n, theta * kf, theta) / (2.0 * n as f64);
            close(
                table.rms_slope[r],
                amplitude * mean_cos2.sqrt(),
                1e-10,
                &format!("slope at k = {k}"),
            );
            if k == 1 {
                assert!(table.rms_curvature_per_m[r].is_nan());
                continue;
            }
            let s = kf / 2.0;
            let n = NX - k;
            let amplitude = 2.0 * A_M * (theta * s / 2.0).sin().powi(2) / (s * DX_M).powi(2);
            let mean_sin2 = 0.5 - cos_sum(n, 2.0 * theta * s, theta) / (2.0 * n as f64);
            close(
                table.rms_curvature_per_m[r],
                amplitude * mean_sin2.sqrt(),
                1e-9,
                &format!("curvature at k = {k}"),
            );
        }
        // The same numbers as the core's functions at their own lags.
        let core = scale_dependent_slope(&h, DX_M, DY_M, &[1, 2, 4, 8, 16]).unwrap();
        assert_eq!(core.value, table.rms_slope);
        let core = scale_dependent_curvature(&h, DX_M, DY_M, &[1, 2, 4, 8]).unwrap();
        assert_eq!(core.value, table.rms_curvature_per_m[1..]);
        let units: Vec<(&str, &str)> = ScaleDependentTable::COLUMNS
            .iter()
            .map(|c| (c.name, c.unit))
            .collect();
        assert_eq!(
            units,
            [
                ("scale_m", "m"),
                ("lag_px", "px"),
                ("rms_slope", ""),
                ("rms_curvature_per_m", "1/m")
            ]
        );
    }

    /// The sinusoid's heights span ±A, its central-difference slopes
    /// |A cos(θi) sin θ/dx| span 0 … A sin θ/dx and its curvatures
    /// −A(1 − cos θ) sin(θi)/dx² span ±A(1 − cos θ)/dx²; every point is
    /// counted once and each density integrates to 1.
    #[test]
    fn the_distributions_table_holds_the_three_histograms_with_units() {
        let h = sinusoid();
        let bins = 16;
        let mut table = DistributionsTable::default();
        let heights = height_histogram(&h, bins).unwrap();
        let (slope, curvature) = slope_and_curvature_histograms(&h, DX_M, DY_M, bins).unwrap();
        table.push("height", "m", &heights);
        table.push("slope", "1", &slope);
        table.push("curvature", "1/m", &curvature);
        assert_eq!(table.count.len(), 3 * bins);
        let theta = TAU / PERIOD as f64;
        let interior = ((NX - 2) * (NY - 2)) as i64;
        for (quantity, unit, points, lo, hi) in [
            ("height", "m", (NX * NY) as i64, -A_M, A_M),
            ("slope", "1", interior, 0.0, A_M * theta.sin() / DX_M),
            (
                "curvature",
                "1/m",
                interior,
                -A_M * (1.0 - theta.cos()) / DX_M.powi(2),
                A_M * (1.0 - theta.cos()) / DX_M.powi(2),
            ),
        ] {
            let rows: Vec<usize> = (0..table.quantity.len())
                .filter(|&r| table.quantity[r] == quantity)
                .collect();
            assert_eq!(rows.len(), bins);
            assert!(rows.iter().all(|&r| table.unit[r] == unit));
            let count: i64 = rows.iter().map(|&r| table.count[r]).sum();
            assert_eq!(count, points, "{quantity}");
            let scale = hi - lo;
            assert!(
                (table.bin_lo[rows[0]] - lo).abs() < 1e-9 * scale,
                "{quantity} lo"
            );
            assert!(
                (table.bin_hi[rows[bins - 1]] - hi).abs() < 1e-9 * scale,
                "{quantity} hi"
            );
            let integral: f64 = rows
                .iter()
                .map(|&r| table.density[r] * (table.bin_hi[r] - table.bin_lo[r]))
                .sum();
            assert!((integral - 1.0).abs() < 1e-12, "{quantity}: {integral}");
        }
        let h = Array2::from_elem((3, 3), 2.0);
        let flat = height_histogram(&h, 4).unwrap();
        assert!(flat.density().iter().all(|d| d.is_nan()), "zero width");
    }
}
