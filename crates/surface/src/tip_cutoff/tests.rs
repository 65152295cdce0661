use super::*;
use ndarray::Array2;

/// Spacing along x, metres, and the sinusoid's wavelength ℓ = 256 Δx and
/// amplitude (m) of the analytic maps.
const DX_M: f64 = 1e-8;
const WAVELENGTH_M: f64 = 256.0 * DX_M;
const AMPLITUDE_M: f64 = 1e-8;

/// A cos(2π(x − x₀)/ℓ) along x, the same in every column, crests at
/// x₀ = 128 Δx and every ℓ after: nx × ny points at Δx along x and
/// `dy_m` along y.
fn sinusoid(nx: usize, ny: usize, dy_m: f64) -> Field {
    let k = 2.0 * std::f64::consts::PI / WAVELENGTH_M;
    let values = Array2::from_shape_fn((nx, ny), |(i, _)| {
        AMPLITUDE_M * (k * (i as f64 - 128.0) * DX_M).cos()
    });
    Field::new(values, DX_M, dy_m).unwrap()
}

/// The crest's second difference of span λ, in magnitude (module doc):
/// A·16 sin²(πλ/(2ℓ))/λ².
fn crest_curvature_per_m(lambda_m: f64) -> f64 {
    let u = std::f64::consts::PI * lambda_m / (2.0 * WAVELENGTH_M);
    AMPLITUDE_M * 16.0 * u.sin().powi(2) / (lambda_m * lambda_m)
}

/// The tip radius whose criterion f/R meets the crest at span λ.
fn radius_meeting_at(lambda_m: f64) -> f64 {
    DEFAULT_SAFETY_FACTOR / crest_curvature_per_m(lambda_m)
}

// The cut-off is where the crest's scale-dependent curvature equals f/R:
// chosen at λ = ℓ/4 (64 Δx), found within 1e-3 (the linear interpolation
// between grid points moves it by ~1e-4). The map is 4ℓ long, so the
// search runs up to L̄/2 = 2ℓ where the curvature is zero: one root.
#[test]
fn a_sinusoid_is_cut_where_its_crest_curvature_reaches_f_over_r() {
    let lambda_m = WAVELENGTH_M / 4.0;
    let map = sinusoid(1024, 128, 8.0 * DX_M);
    let cutoff_m = tip_reliability_cutoff_m(&map, radius_meeting_at(lambda_m))
        .unwrap()
        .unwrap();
    assert!(
        (cutoff_m / lambda_m - 1.0).abs() < 1e-3,
        "{cutoff_m} vs {lambda_m}"
    );
    // Twice the radius, the cut-off where the curvature is half: longer.
    let lambda_2_m = WAVELENGTH_M * 0.6;
    let longer = tip_reliability_cutoff_m(&map, radius_meeting_at(lambda_2_m))
        .unwrap()
        .unwrap();
    assert!(
        (longer / lambda_2_m - 1.0).abs() < 1e-3,
        "{longer} vs {lambda_2_m}"
    );
}

// The same sinusoid as a profile, n × 1 or 1 × n: the same cut-off (a line
// scan's bandwidth is its spacing and its length).
#[test]
fn a_profile_along_x_or_y_gives_the_maps_cut_off() {
    let lambda_m = WAVELENGTH_M / 4.0;
    let radius_m = radius_meeting_at(lambda_m);
    let along_x = sinusoid(1024, 1, DX_M);
    let along_y = Field::new(
        along_x.values.clone().reversed_axes(),
        DX_M * 3.0,
        along_x.dx_m,
    )
    .unwrap();
    for profile in [along_x, along_y] {
        let cutoff_m = tip_reliability_cutoff_m(&profile, radius_m)
            .unwrap()
            .unwrap();
        assert!(
            (cutoff_m / lambda_m - 1.0).abs() < 1e-3,
            "{:?}: {cutoff_m}",
            profile.values.dim()
        );
    }
}

// A tip sharper than the crest at the smallest scale (2Δ̄) sees everything:
// no cut-off. A tip so blunt that the curvature at L̄/2 still exceeds f/R
// leaves nothing reliable: the cut-off is L̄ (the mean side).
#[test]
fn a_sharp_tip_has_no_cut_off_and_a_blunt_one_cuts_everything() {
    let map = sinusoid(1024, 128, 8.0 * DX_M);
    let smallest_m = 2.0 * 0.5 * (DX_M + 8.0 * DX_M);
    let sharp = 0.9 * radius_meeting_at(smallest_m);
    assert_eq!(tip_reliability_cutoff_m(&map, sharp), Ok(None));
    let just_blunt = 1.1 * radius_meeting_at(smallest_m);
    assert!(
        tip_reliability_cutoff_m(&map, just_blunt)
            .unwrap()
            .is_some()
    );

    // One wavelength long, its crest in the middle: the search stops at
    // ℓ/2, where the crest still curves.
    let short = sinusoid(256, 32, 8.0 * DX_M);
    let mean_side_m = 0.5 * (256.0 * DX_M + 32.0 * (8.0 * DX_M));
    let blunt = 2.0 * radius_meeting_at(WAVELENGTH_M / 2.0);
    assert_eq!(
        tip_reliability_cutoff_m(&short, blunt),
        Ok(Some(mean_side_m))
    );
}

// NaN points take no part: a hole on one crest leaves the other crests,
// and the cut-off, as they were.
#[test]
fn missing_points_take_no_part() {
    let lambda_m = WAVELENGTH_M / 4.0;
    let radius_m = radius_meeting_at(lambda_m);
    let mut map = sinusoid(1024, 128, 8.0 * DX_M);
    let whole = tip_reliability_cutoff_m(&map, radius_m).unwrap().unwrap();
    for j in 0..128 {
        map.values[[384, j]] = f64::NAN;
    }
    map.values[[640, 7]] = f64::NAN;
    let holed = tip_reliability_cutoff_m(&map, radius_m).unwrap().unwrap();
    assert!((holed / whole - 1.0).abs() < 1e-6, "{holed} vs {whole}");
}

#[test]
fn bad_radius_safety_factor_and_tiny_maps_are_errors() {
    let map = sinusoid(64, 8, DX_M);
    for r in [0.0, -1e-8, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            tip_reliability_cutoff_m(&map, r),
            Err(TipCutoffError::BadRadius(_))
        ));
    }
    assert!(matches!(
        tip_reliability_cutoff_with(&map, 1e-8, 0.0),
        Err(TipCutoffError::BadSafetyFactor(_))
    ));
    let tiny = sinusoid(4, 8, DX_M);
    let e = tip_reliability_cutoff_m(&tiny, 1e-8).unwrap_err();
    assert_eq!(e, TipCutoffError::TooSmall { nx: 4, ny: 8 });
    assert!(e.to_string().contains("4 × 8"), "{e}");
}

#[test]
fn brent_finds_a_cube_root_to_its_tolerance() {
    let mut calls = 0;
    let root = brent_root(
        |x| {
            calls += 1;
            x * x * x - 2.0
        },
        (0.0, -2.0),
        (2.0, 6.0),
    );
    assert!((root - 2f64.cbrt()).abs() < 1e-8, "{root}");
    assert!(calls < 30, "{calls} evaluations");
}

// The minimum over rows is order-independent: one or two threads give the
// same bits.
#[test]
fn one_or_two_threads_give_the_same_bits() {
    let mut map = sinusoid(512, 64, 8.0 * DX_M);
    for (n, v) in map.values.iter_mut().enumerate() {
        *v += 1e-10 * ((n * 7919 % 1009) as f64 / 1009.0 - 0.5);
    }
    let radius_m = radius_meeting_at(WAVELENGTH_M / 4.0);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| tip_reliability_cutoff_m(&map, radius_m).unwrap().unwrap())
    };
    assert_eq!(on(1).to_bits(), on(2).to_bits());
}
