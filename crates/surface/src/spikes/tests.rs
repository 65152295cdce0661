use std::f64::consts::TAU;

use ndarray::Array2;

use super::*;

/// A smooth rough map: a few sines of wavelengths 13 to 40 points (what an
/// interferometer resolves), heights of about 1 um, plus a little
/// pseudo-random roughness (±5 nm, a fixed sequence).
fn smooth_rough(nx: usize, ny: usize) -> Array2<f64> {
    let mut state = 12345u64;
    Array2::from_shape_fn((nx, ny), |(i, j)| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let jitter = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let (x, y) = (i as f64, j as f64);
        1e-6 * ((x / 40.0 * TAU).sin() + 0.5 * (y / 23.0 * TAU + 1.0).sin())
            + 0.2e-6 * ((x + 2.0 * y) / 30.0 * TAU).sin()
            + 10e-9 * jitter
    })
}

#[test]
fn medians_of_odd_and_even_counts() {
    assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
    assert!(median(&mut []).is_nan());
    // 1.4826 is 1/Φ⁻¹(3/4), Φ⁻¹(3/4) = 0.6744897501960817 (scipy.stats.norm.ppf(0.75)).
    assert!((MAD_TO_SIGMA * 0.674_489_750_196_081_7 - 1.0).abs() < 1e-15);
}

#[test]
fn planted_spikes_are_all_found_and_nothing_else() {
    let mut h = smooth_rough(80, 70);
    // Up and down, single and in a pair side by side, on an edge and in a
    // corner, next to a hole: each 0.3 um, under a third of the map's
    // height range, so only the local rule can tell them.
    let planted = [
        (10, 10),
        (40, 41),
        (40, 42),
        (0, 35),
        (79, 69),
        (55, 5),
        (20, 60),
    ];
    for (k, &p) in planted.iter().enumerate() {
        h[p] += if k % 2 == 0 { 0.3e-6 } else { -0.3e-6 };
    }
    h[[56, 5]] = f64::NAN;
    let found = remove_spikes(&h, &LocalRule::default()).unwrap();
    let mut expected = planted.to_vec();
    expected.sort();
    assert_eq!(found.points, expected, "{}", found.description);
    for p in &planted {
        assert!(found.height_m[*p].is_nan());
    }
    let measured = |a: &Array2<f64>| a.iter().filter(|v| !v.is_nan()).count();
    assert_eq!(measured(&found.height_m), measured(&h) - planted.len());
    assert!(
        found
            .description
            .starts_with("spikes: 7 of 5599 points set to NaN"),
        "{}",
        found.description
    );
    assert!(found.description.contains("(0, 35)"));
    // The same map without spikes: nothing found.
    let clean = remove_spikes(&smooth_rough(80, 70), &LocalRule::default()).unwrap();
    assert!(clean.points.is_empty(), "{}", clean.description);
}

#[test]
fn a_three_by_three_cluster_needs_the_five_by_five_rule() {
    let mut h = smooth_rough(60, 60);
    for i in 29..32 {
        for j in 29..32 {
            h[[i, j]] += 0.4e-6;
        }
    }
    let narrow = remove_spikes(&h, &LocalRule::default()).unwrap();
    // The centre's 8 neighbours are all raised: it is not found.
    assert!(!narrow.points.contains(&(30, 30)));
    let wide = remove_spikes(
        &h,
        &LocalRule {
            radius: 2,
            ..LocalRule::default()
        },
    )
    .unwrap();
    let cluster: Vec<_> = (29..32)
        .flat_map(|i| (29..32).map(move |j| (i, j)))
        .collect();
    assert_eq!(wide.points, cluster, "{}", wide.description);
}

#[test]
fn the_global_rule_cuts_heights_far_from_the_median() {
    // Heights 0, 1, …, 9 repeated (median 4.5, MAD 2.5, σ = 3.7065), and
    // two far points.
    let mut h = Array2::from_shape_fn((10, 10), |(i, _)| i as f64);
    h[[3, 3]] = 100.0;
    h[[7, 2]] = -40.0;
    let found = remove_outliers(&h, 5.0).unwrap();
    assert_eq!(found.points, vec![(3, 3), (7, 2)]);
    assert!((found.sigma_m - 2.5 * MAD_TO_SIGMA).abs() < 1e-12);
    // Nothing of 0..9 is beyond 5σ = 18.5 from 4.5.
    assert_eq!(
        remove_outliers(&h, 5.0)
            .unwrap()
            .height_m
            .iter()
            .filter(|v| v.is_nan())
            .count(),
        2
    );
    // k = 1 cuts 0 and 9 as well (|0 − 4.5| = 4.5 > 3.7).
    let tight = remove_outliers(&h, 1.0).unwrap();
    assert!(tight.points.contains(&(0, 0)) && tight.points.contains(&(9, 5)));
    assert!(!tight.points.contains(&(1, 0)));
}

#[test]
fn bad_parameters_and_maps_without_spread_are_refused() {
    let h = smooth_rough(10, 10);
    let rule = |k, radius, min_estimates| LocalRule {
        k,
        radius,
        min_estimates,
    };
    let e = remove_spikes(&h, &rule(0.0, 1, 3)).unwrap_err();
    assert!(e.to_string().starts_with("k = 0"));
    let e = remove_spikes(&h, &rule(5.0, 4, 3)).unwrap_err();
    assert!(e.to_string().starts_with("radius = 4"));
    let e = remove_spikes(&h, &rule(5.0, 1, 5)).unwrap_err();
    assert!(e.to_string().starts_with("min_estimates = 5"));
    let flat = Array2::from_elem((6, 6), 1.0);
    assert!(matches!(
        remove_spikes(&flat, &LocalRule::default()),
        Err(SpikeError::NoSpread { .. })
    ));
    assert!(matches!(
        remove_outliers(&flat, 5.0),
        Err(SpikeError::NoSpread { .. })
    ));
    let empty = Array2::from_elem((4, 4), f64::NAN);
    assert!(matches!(
        remove_outliers(&empty, 5.0),
        Err(SpikeError::NothingToJudge { .. })
    ));
    assert!(remove_spikes(&Array2::zeros((0, 3)), &LocalRule::default()).is_err());
}
