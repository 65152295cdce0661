//! Synthetic upstream tables for the report's tests, benchmark and demo:
//! Ogden tensile curves, power-law PSDs, a smoothed random height map with
//! missing points, Gaussian truncation curves and monotone ICM responses.
//! Everything is a closed form or seeded, so expected numbers are known.
//! Each table has every column of its stage's schema, and the moduli agree
//! across tables as the report checks (one ν, one E0*, one A0).

#![allow(dead_code)]

use hypercontact_core::{Context, Field, Files, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_material::fit_stage::ParamsTable;
use hypercontact_material::{Family, Hyperelastic, Ogden, composite_modulus_pa};
use hypercontact_report::{Report, ReportParams};
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Ogden terms (μ_i in Pa, α_i) of the synthetic material.
pub const MU_PA: [f64; 2] = [0.55e6, 0.02e6];
pub const ALPHA: [f64; 2] = [1.8, -2.5];

/// Poisson's ratio of the synthetic fit and responses, unless a test asks
/// for another: the report's default.
pub const POISSON: f64 = 0.5;

/// Nominal area A0 of the synthetic profiles and responses, m².
pub const A0_M2: f64 = 1e-4;

pub fn ogden() -> Ogden {
    Ogden::new(MU_PA.to_vec(), ALPHA.to_vec()).unwrap()
}

/// E0* of the synthetic material at Poisson's ratio `poisson`.
pub fn e0_star_pa(poisson: f64) -> f64 {
    composite_modulus_pa(ogden().shear_modulus_pa(), poisson)
}

/// Nominal stress of the Ogden model in the spec's closed forms
/// (Abaqus convention): UT exponent −α/2 − 1, PT −α − 1, BT −2α − 1.
pub fn ogden_stress_pa(mode: &str, stretch: f64) -> f64 {
    MU_PA
        .iter()
        .zip(ALPHA)
        .map(|(&mu, a)| {
            let lateral = match mode {
                "UT" => -a / 2.0 - 1.0,
                "PT" => -a - 1.0,
                _ => -2.0 * a - 1.0,
            };
            2.0 * mu / a * (stretch.powf(a - 1.0) - stretch.powf(lateral))
        })
        .sum()
}

/// Sample labels and their statistics: σ (m), H along x, H along y and the
/// load scale s of F/(E0* A0) = s a^1.5 (decreasing, so T1 > T2 > T3 > T4).
pub const SAMPLES: [(&str, f64, f64, f64, f64); 4] = [
    ("T1", 12e-6, 0.80, 0.76, 0.40),
    ("T2", 9e-6, 0.72, 0.70, 0.25),
    ("T3", 7e-6, 0.65, 0.62, 0.15),
    ("T4", 5e-6, 0.58, 0.55, 0.08),
];

pub fn curves(points_per_mode: usize) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut mode, mut stretch, mut measured, mut fitted) = (vec![], vec![], vec![], vec![]);
    for (m, max) in [("UT", 3.0), ("PT", 2.4), ("BT", 2.0)] {
        for k in 0..points_per_mode {
            let l = 1.0 + (max - 1.0) * k as f64 / (points_per_mode - 1) as f64;
            let exact = ogden_stress_pa(m, l);
            mode.push(m);
            stretch.push(l);
            fitted.push(exact);
            measured.push(exact * (1.0 + 0.02 * (rng.random::<f64>() - 0.5)));
        }
    }
    Table::new()
        .with("mode", mode)
        .with("stretch", stretch)
        .with("measured_pa", measured)
        .with("fitted_pa", fitted)
}

pub fn quality() -> Table {
    Table::new()
        .with("mode", vec!["UT", "PT", "BT"])
        .with("r2", vec![0.9991, 0.9978, 0.9962])
        .with("rms_rel_err", vec![0.011, 0.017, 0.024])
        .with("max_rel_err", vec![0.031, 0.045, 0.061])
        .with("n_points", vec![60_i64, 60, 60])
        .with("condition_number", vec![f64::NAN; 3])
        .with("max_correlation", vec![f64::NAN; 3])
        .with("free_params", vec![0_i64; 3])
}

pub fn stability() -> Table {
    Table::new()
        .with("mode", vec!["UT", "PT", "BT"])
        .with("lambda_min", vec![0.45, 0.55, 0.7])
        .with("lambda_max", vec![f64::INFINITY, 2.9, 1.8])
        .with("monotonic_min", vec![0.4, 0.5, 0.6])
        .with("monotonic_max", vec![f64::INFINITY, 3.0, 1.9])
        .with("note", vec!["stable in compression", "", ""])
        .with("lambda_min_at_edge", vec![0_i64; 3])
        .with("lambda_max_at_edge", vec![0_i64; 3])
        .with("window_min", vec![f64::NAN; 3])
        .with("window_max", vec![f64::NAN; 3])
}

/// The fit's `params` table for the synthetic material at `poisson`.
pub fn params(poisson: f64) -> Table {
    ParamsTable::new(Family::Ogden(2), &ogden(), poisson).into_table()
}

/// RMS relative errors and condition numbers of the chosen family
/// (ogden-2) in [`comparison`]: with the stable constraint (selected) and
/// without it.
pub const STABLE_RMS: f64 = 0.018;
pub const FREE_RMS: f64 = 0.012;
pub const STABLE_CONDITION: f64 = 3.2;
pub const FREE_CONDITION: f64 = 4.5e5;

/// The full `comparison` schema (every family under both settings of the
/// constraint, the stable ogden-2 selected) plus a column it does not
/// declare (shown as is all the same).
pub fn comparison() -> Table {
    let (nan, inf) = (f64::NAN, f64::INFINITY);
    Table::new()
        .with("rank", vec![1_i64, 2, 3, 4, 5, 6])
        .with(
            "model",
            vec![
                "ogden-2",
                "ogden-2",
                "yeoh",
                "yeoh",
                "mooney-rivlin",
                "neo-hookean",
            ],
        )
        .with(
            "constraint",
            vec!["none", "stable", "none", "stable", "stable", "stable"],
        )
        .with("n_params", vec![4_i64, 4, 3, 3, 2, 1])
        .with("free_params", vec![4_i64, 4, 3, 2, 2, 1])
        .with(
            "condition_number",
            vec![FREE_CONDITION, STABLE_CONDITION, 40.0, 12.0, 3.0, 1.0],
        )
        .with(
            "rms_rel_err",
            vec![FREE_RMS, STABLE_RMS, 0.03, 0.034, 0.081, 0.12],
        )
        .with("max_rel_err", vec![0.04, 0.05, 0.08, 0.09, 0.2, 0.3])
        .with("ut_rms_rel_err", vec![0.01, 0.015, 0.02, 0.03, 0.07, 0.1])
        .with("pt_rms_rel_err", vec![0.011, 0.017, 0.03, 0.03, 0.08, 0.11])
        .with("bt_rms_rel_err", vec![0.015, 0.022, 0.04, 0.04, 0.09, 0.15])
        .with("mu0_pa", vec![0.57e6, 0.56e6, 0.5e6, 0.5e6, 0.49e6, 0.48e6])
        .with("ut_lambda_min", vec![0.5, 0.45, 0.5, 0.5, 0.3, nan])
        .with("ut_lambda_max", vec![inf, inf, 5.0, 6.0, 8.0, nan])
        .with("pt_lambda_min", vec![0.6, 0.55, 0.6, 0.6, 0.4, nan])
        .with("pt_lambda_max", vec![2.5, 2.9, 4.0, 5.0, 7.0, nan])
        .with("bt_lambda_min", vec![0.8, 0.7, 0.75, 0.75, 0.6, nan])
        .with("bt_lambda_max", vec![1.5, 1.8, 2.5, 3.0, 4.0, nan])
        .with("selected", vec![0_i64, 1, 0, 0, 0, 0])
        .with("status", vec!["ok"; 6])
        .with("r2_min", vec![0.997, 0.996, 0.99, 0.989, 0.95, 0.91])
}

/// The fit's `params` table with a bootstrap interval on every row:
/// value ∓ 10 % of its magnitude.
pub fn params_with_intervals(poisson: f64) -> Table {
    let mut t = ParamsTable::new(Family::Ogden(2), &ogden(), poisson);
    t.p05 = t.value.iter().map(|v| v - 0.1 * v.abs()).collect();
    t.p95 = t.value.iter().map(|v| v + 0.1 * v.abs()).collect();
    t.into_table()
}

pub fn material() -> Table {
    Table::new()
        .with("model", vec!["ogden"; 4])
        .with("param", vec!["mu_1", "mu_2", "alpha_1", "alpha_2"])
        .with("value", vec![MU_PA[0], MU_PA[1], ALPHA[0], ALPHA[1]])
}

/// A smoothed random height map (axis 0 = x) of rms `sigma_m`, 20 µm
/// pixels, with a few NaN points.
pub fn height(n: usize, sigma_m: f64, seed: u64) -> Field {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut h = Array2::from_shape_fn((n, n), |_| rng.random::<f64>() - 0.5);
    // Box blurs along both axes give long-wavelength roughness cheaply.
    for _ in 0..3 {
        let r = (n / 40).max(1) as isize;
        for axis in 0..2 {
            let src = h.clone();
            for ((i, j), v) in h.indexed_iter_mut() {
                let (mut sum, mut count) = (0.0, 0.0);
                for d in -r..=r {
                    let (ii, jj) = if axis == 0 {
                        (i as isize + d, j as isize)
                    } else {
                        (i as isize, j as isize + d)
                    };
                    if ii >= 0 && jj >= 0 && (ii as usize) < n && (jj as usize) < n {
                        sum += src[[ii as usize, jj as usize]];
                        count += 1.0;
                    }
                }
                *v = sum / count;
            }
        }
    }
    let mean = h.mean().unwrap();
    let rms = h.mapv(|v| (v - mean).powi(2)).mean().unwrap().sqrt();
    h.mapv_inplace(|v| (v - mean) / rms * sigma_m);
    for k in 0..(n * n / 200) {
        let (i, j) = ((k * 7919) % n, (k * 104729 / 3) % n);
        h[[i, j]] = f64::NAN;
    }
    Field::new(h, 20e-6, 20e-6).unwrap()
}

/// 1-D PSDs C = A q^(−1−2H) along x and y and a radial one, with a 3 %
/// multiplicative ripple, on `n` log-spaced q.
pub fn psd(n: usize, h_x: f64, h_y: f64, sigma_m: f64) -> Table {
    let (mut dir, mut q, mut c) = (vec![], vec![], vec![]);
    for (d, h, exponent) in [
        ("x", h_x, -1.0 - 2.0 * h_x),
        ("y", h_y, -1.0 - 2.0 * h_y),
        ("radial", h_x, -2.0 - 2.0 * h_x),
    ] {
        let _ = h;
        for k in 0..n {
            let qk = 3e2 * (1e5f64 / 3e2).powf(k as f64 / (n - 1) as f64);
            let ripple = 1.0 + 0.03 * (k as f64 * 1.7).sin();
            dir.push(d);
            q.push(qk);
            c.push(sigma_m * sigma_m * 1e-3 * (qk / 1e3).powf(exponent) * ripple);
        }
    }
    Table::new()
        .with("direction", dir)
        .with("q_per_m", q)
        .with("c", c)
}

/// The surface stage's statistics tables of a map, by the report's input
/// names, from the surface crate's own functions (as its stage builds
/// them: 101 points of material ratio, 64 histogram bins).
pub fn surface_statistics(field: &Field) -> Vec<(&'static str, Table)> {
    use hypercontact_surface::iso25178;
    use hypercontact_surface::surface_stage::{
        AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, ScaleDependentTable,
    };
    let (h, dx, dy) = (&field.values, field.dx_m, field.dy_m);
    let (areal, ratio, acf) = iso25178::areal_parameters_curve_and_acf(h, dx, dy).unwrap();
    let mut distributions = DistributionsTable::default();
    distributions.push("height", "m", &iso25178::height_histogram(h, 64).unwrap());
    let (slope, curvature) = iso25178::slope_and_curvature_histograms(h, dx, dy, 64).unwrap();
    distributions.push("slope", "1", &slope);
    distributions.push("curvature", "1/m", &curvature);
    vec![
        ("areal", ArealTable::new(&areal).into_table()),
        (
            "material_ratio",
            MaterialRatioTable::new(&ratio, 101).into_table(),
        ),
        ("acf", AcfTable::new(&acf).into_table()),
        (
            "scale_dependent",
            ScaleDependentTable::new(h, dx, dy).unwrap().into_table(),
        ),
        ("distributions", distributions.into_table()),
    ]
}

pub fn stats(sigma_m: f64, h_x: f64, h_y: f64) -> Table {
    let fit = |h: f64| {
        (
            vec![h],
            vec![0.99],
            vec![1e4],
            vec![1e5],
            vec!["ok".to_owned()],
        )
    };
    let (hurst_x, hurst_x_r2, hurst_x_q_min_per_m, hurst_x_q_max_per_m, hurst_x_flag) = fit(h_x);
    let (hurst_y, hurst_y_r2, hurst_y_q_min_per_m, hurst_y_q_max_per_m, hurst_y_flag) = fit(h_y);
    let (
        hurst_radial,
        hurst_radial_r2,
        hurst_radial_q_min_per_m,
        hurst_radial_q_max_per_m,
        hurst_radial_flag,
    ) = fit((h_x + h_y) / 2.0);
    hypercontact_surface::surface_stage::StatsTable {
        sigma_m: vec![sigma_m],
        rms_slope: vec![sigma_m * 2.0e4],
        hurst_x,
        hurst_y,
        hurst_radial,
        hurst_x_r2,
        hurst_x_q_min_per_m,
        hurst_x_q_max_per_m,
        hurst_x_flag,
        hurst_y_r2,
        hurst_y_q_min_per_m,
        hurst_y_q_max_per_m,
        hurst_y_flag,
        hurst_radial_r2,
        hurst_radial_q_min_per_m,
        hurst_radial_q_max_per_m,
        hurst_radial_flag,
        nx: vec![500],
        ny: vec![500],
        dx_m: vec![20e-6],
        dy_m: vec![20e-6],
        nx_measured: vec![5000],
        ny_measured: vec![5000],
        dx_measured_m: vec![2e-6],
        dy_measured_m: vec![2e-6],
        nan_fraction: vec![0.005],
        fill: vec!["harmonic".to_owned()],
        filled_points: vec![1250],
        filled_fraction: vec![0.005],
    }
    .into_table()
}

/// A/A0 = 1 − Φ(z/σ) (a Gaussian surface) on `levels` planes, top first.
pub fn profile(levels: usize, sigma_m: f64) -> Table {
    let zs: Vec<f64> = (0..levels)
        .map(|k| 3.5 - 7.0 * k as f64 / (levels - 1) as f64)
        .collect();
    // Φ via the Abramowitz–Stegun 7.1.26 erf; accurate enough for a plot.
    let erf = |x: f64| {
        let t = 1.0 / (1.0 + 0.3275911 * x.abs());
        let y = 1.0
            - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t
                + 0.254829592)
                * t
                * (-x * x).exp();
        y.copysign(x)
    };
    let area: Vec<f64> = zs
        .iter()
        .map(|z| 0.5 * (1.0 - erf(z / 2f64.sqrt())))
        .collect();
    let n = levels;
    Table::new()
        .with(
            "z_m",
            zs.iter().map(|z| (z + 3.5) * sigma_m).collect::<Vec<_>>(),
        )
        .with(
            "z_over_sigma",
            zs.iter().map(|z| z + 3.5).collect::<Vec<_>>(),
        )
        .with("area_fraction", area.clone())
        .with(
            "patches",
            (0..n as i64).map(|k| 1 + k % 50).collect::<Vec<_>>(),
        )
        .with(
            "radius_m",
            area.iter().map(|a| 1e-4 * a.sqrt()).collect::<Vec<_>>(),
        )
        .with(
            "area_m2",
            area.iter().map(|a| a * A0_M2).collect::<Vec<_>>(),
        )
}

/// The area fractions of the response rows: non-uniform in A/A0, so the
/// summary's values at 0.1, 0.5, 0.9 come from interpolation.
pub fn response_area(levels: usize) -> Vec<f64> {
    (0..levels)
        .map(|k| (k as f64 / (levels - 1) as f64).powf(1.3))
        .collect()
}

/// Hyperelastic: F/(E0* A0) = s a^1.5, E_t*/E0* = 3 − 1.6 a + 1.2 a²;
/// linear: F/(E0* A0) = s a / 2 (exactly linear), ratio 1; normalised at
/// [`POISSON`].
pub fn response(levels: usize, scale: f64, linear: bool) -> Table {
    response_at(levels, scale, linear, POISSON)
}

/// [`response`] of a contact model that normalised by E0* at `poisson`.
pub fn response_at(levels: usize, scale: f64, linear: bool, poisson: f64) -> Table {
    let a = response_area(levels);
    let load: Vec<f64> = a
        .iter()
        .map(|a| {
            if linear {
                scale * a / 2.0
            } else {
                scale * a.powf(1.5)
            }
        })
        .collect();
    let ratio: Vec<f64> = a
        .iter()
        .map(|a| {
            if linear {
                1.0
            } else {
                3.0 - 1.6 * a + 1.2 * a * a + 0.5 * (scale - 0.2)
            }
        })
        .collect();
    let e0_star = e0_star_pa(poisson);
    Table::new()
        .with(
            "z_m",
            a.iter().map(|a| (1.0 - a) * 5e-5).collect::<Vec<_>>(),
        )
        .with("area_fraction", a.clone())
        .with(
            "load_n",
            load.iter().map(|f| f * e0_star * A0_M2).collect::<Vec<_>>(),
        )
        .with("load_norm", load.clone())
        .with(
            "mean_stress_pa",
            load.iter()
                .zip(&a)
                .map(|(f, a)| if *a > 0.0 { f / a * e0_star } else { 0.0 })
                .collect::<Vec<_>>(),
        )
        .with("tangent_ratio", ratio)
}

/// Bands around [`response`]'s hyperelastic curve: F/(E0* A0) from
/// 0.8 × to 1.25 × the curve, E_t*/E0* from 0.15 below to 0.6 above it;
/// rows above A/A0 = `reached` were reached by no replicate (NaN).
pub fn band(levels: usize, scale: f64, reached: f64) -> Table {
    let curve =
        hypercontact_core::contact::ResponseTable::from_table(&response(levels, scale, false))
            .unwrap();
    let a = curve.area_fraction;
    let beyond = |v: f64, a: f64| if a > reached { f64::NAN } else { v };
    let column = |v: &[f64], f: &dyn Fn(f64) -> f64| -> Vec<f64> {
        v.iter().zip(&a).map(|(&v, &a)| beyond(f(v), a)).collect()
    };
    hypercontact_core::contact::BandTable {
        load_norm_p05: column(&curve.load_norm, &|v| 0.8 * v),
        load_norm_p50: column(&curve.load_norm, &|v| v),
        load_norm_p95: column(&curve.load_norm, &|v| 1.25 * v),
        tangent_ratio_p05: column(&curve.tangent_ratio, &|v| v - 0.15),
        tangent_ratio_p50: column(&curve.tangent_ratio, &|v| v),
        tangent_ratio_p95: column(&curve.tangent_ratio, &|v| v + 0.6),
        replicates: a
            .iter()
            .map(|&a| if a > reached { 0 } else { 200 })
            .collect(),
        area_fraction: a,
    }
    .into_table()
}

/// Which groups of inputs to wire.
#[derive(Clone, Copy)]
pub struct Wiring {
    pub tensile: bool,
    pub surfaces: bool,
    pub responses: bool,
    pub linear: bool,
}

pub const ALL: Wiring = Wiring {
    tensile: true,
    surfaces: true,
    responses: true,
    linear: true,
};

/// Inputs as the runner would hand them: many-inputs as `name.label`.
pub fn inputs(wiring: Wiring, map_n: usize, levels: usize) -> Inputs {
    inputs_at(wiring, map_n, levels, POISSON)
}

/// [`inputs`] of a fit and contact models run at Poisson's ratio `poisson`.
pub fn inputs_at(wiring: Wiring, map_n: usize, levels: usize, poisson: f64) -> Inputs {
    let mut inputs = Inputs::new();
    let table = |t: Table| std::sync::Arc::new(Product::Table(t));
    if wiring.tensile {
        inputs.insert("curves", table(curves(60)));
        inputs.insert("quality", table(quality()));
        inputs.insert("params", table(params(poisson)));
        inputs.insert("stability", table(stability()));
        inputs.insert("comparison", table(comparison()));
        inputs.insert("material", table(material()));
    }
    for (i, (label, sigma, hx, hy, scale)) in SAMPLES.iter().enumerate() {
        if wiring.surfaces {
            let map = height(map_n, *sigma, i as u64);
            for (name, t) in surface_statistics(&map) {
                inputs.insert(&format!("{name}.{label}"), table(t));
            }
            inputs.insert(
                &format!("heights.{label}"),
                std::sync::Arc::new(Product::Field(map)),
            );
            inputs.insert(&format!("psd.{label}"), table(psd(120, *hx, *hy, *sigma)));
            inputs.insert(&format!("stats.{label}"), table(stats(*sigma, *hx, *hy)));
            inputs.insert(&format!("profiles.{label}"), table(profile(levels, *sigma)));
        }
        if wiring.responses {
            inputs.insert(
                &format!("responses.{label}.icm"),
                table(response_at(levels, *scale, false, poisson)),
            );
            // The theories from the spectrum (Fig. 9): stiffer and softer
            // than the ICM by a constant factor.
            for (model, factor) in [("persson", 1.5), ("gw", 2.5)] {
                inputs.insert(
                    &format!("responses.{label}.{model}"),
                    table(response_at(levels, scale * factor, false, poisson)),
                );
            }
        }
        if wiring.linear {
            inputs.insert(
                &format!("responses.{label}.icm-linear"),
                table(response_at(levels, *scale, true, poisson)),
            );
        }
    }
    inputs
}

/// `inputs` plus a bootstrap band for every sample (T4's reached by no
/// replicate above A/A0 = 0.7) and the fit's `params` with intervals, as
/// a fit and ICM run with `bootstrap` would give them, at [`POISSON`].
pub fn with_bands(mut inputs: Inputs, levels: usize) -> Inputs {
    let table = |t: Table| std::sync::Arc::new(Product::Table(t));
    for (i, (label, _, _, _, scale)) in SAMPLES.iter().enumerate() {
        let reached = if i == 3 { 0.7 } else { 1.0 };
        inputs.insert(
            &format!("bands.{label}.icm"),
            table(band(levels, *scale, reached)),
        );
    }
    if inputs.get("params").is_some() {
        inputs.insert("params", table(params_with_intervals(POISSON)));
    }
    inputs
}

/// The report's parameters as the paper pipeline sets them: the models'
/// order, the summary's models and the load ratios' reference.
pub fn paper_params() -> ReportParams {
    let labels = |l: &[&str]| l.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    ReportParams {
        models: labels(&["icm", "icm-linear", "bem", "bem-linear", "persson", "gw"]),
        fig7_models: labels(&["icm", "icm-linear", "bem", "bem-linear"]),
        fig9_models: labels(&["icm", "icm-linear", "bem", "persson", "gw"]),
        summary_models: labels(&["icm", "icm-linear"]),
        reference_model: Some("bem".into()),
        ..ReportParams::default()
    }
}

/// The report stage's files for `inputs` at the paper pipeline's
/// parameters, with the model labels not wired left out of them.
pub fn run(inputs: &Inputs) -> Files {
    run_with(&wired_params(inputs), inputs).expect("the report renders")
}

/// [`paper_params`] keeping only the labels `inputs` wire.
pub fn wired_params(inputs: &Inputs) -> ReportParams {
    let wired: Vec<String> = inputs
        .nested("responses")
        .into_iter()
        .map(|(_, model, _)| model.to_owned())
        .collect();
    let keep =
        |l: Vec<String>| -> Vec<String> { l.into_iter().filter(|m| wired.contains(m)).collect() };
    let p = paper_params();
    ReportParams {
        models: keep(p.models),
        fig7_models: keep(p.fig7_models),
        fig9_models: keep(p.fig9_models),
        summary_models: keep(p.summary_models),
        reference_model: p.reference_model.filter(|r| wired.contains(r)),
        ..p
    }
}

/// The report stage's files, or its error as text.
pub fn run_with(params: &ReportParams, inputs: &Inputs) -> Result<Files, String> {
    let out = Report
        .run(
            &params.clone().check().unwrap(),
            inputs,
            &Context::new("report"),
        )
        .map_err(|e| e.to_string())?;
    match out.get("report") {
        Some(Product::Files(files)) => Ok(files.clone()),
        other => panic!("no `report` files output: {other:?}"),
    }
}

/// A file of the report as text.
pub fn text(files: &Files, name: &str) -> String {
    String::from_utf8(files.files[name].clone()).expect("UTF-8")
}
