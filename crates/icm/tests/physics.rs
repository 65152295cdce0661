//! The ICM against analytic contact results and the paper's findings, on
//! maps truncated by the `truncation` crate (the pipeline's path).

use std::sync::Arc;

use crate::common;

use hypercontact_icm::{Model, Scheme, Solution};
use hypercontact_material::presets::paper_epdm;
use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::{Levels, Profile, TruncationOptions, truncate};
use ndarray::Array2;

fn profile_of(h: &Array2<f64>, pixel_m: f64, levels: Levels) -> Profile {
    let options = TruncationOptions {
        levels,
        ..Default::default()
    };
    truncate(h.view(), pixel_m, pixel_m, &options, &mut |_| {}).unwrap()
}

fn run(p: &Profile, model: Model, scheme: Scheme) -> (Solution, f64) {
    common::solve_profile(p, Arc::new(paper_epdm()), model, scheme)
}

/// F/(E0* A0) at A/A0 = `fraction`, linear in A/A0 between planes.
fn load_norm_at(p: &Profile, s: &Solution, e0_star: f64, fraction: f64) -> f64 {
    let k = p.area_fraction.iter().position(|&f| f >= fraction).unwrap();
    assert!(k > 0);
    let (f0, f1) = (p.area_fraction[k - 1], p.area_fraction[k]);
    let t = (fraction - f0) / (f1 - f0);
    let load = s.load_n[k - 1] + t * (s.load_n[k] - s.load_n[k - 1]);
    load / (e0_star * p.nominal_area_m2)
}

#[test]
fn sampled_flat_punch_gives_sneddons_load_exactly() {
    // A flat-topped cylinder of 25 px radius standing 10 µm above a base.
    let (n, pixel_m, height_m) = (81, 4e-6, 1e-5);
    let h = Array2::from_shape_fn((n, n), |(i, j)| {
        let (x, y) = (i as f64 - 40.0, j as f64 - 40.0);
        if x.hypot(y) <= 25.0 { height_m } else { 0.0 }
    });
    let p = profile_of(&h, pixel_m, Levels::Count(40));
    let area_m2 = p.area_m2[0];
    let a_m = (area_m2 / std::f64::consts::PI).sqrt();
    for scheme in [Scheme::Euler, Scheme::Heun] {
        let (s, e0_star) = run(&p, Model::Linear, scheme);
        // Every plane above the base (z > 0) cuts the cylinder only.
        for k in 0..p.z_m.len() - 1 {
            assert_eq!(p.area_m2[k], area_m2);
            let exact = 2.0 * e0_star * a_m * (p.z_m[0] - p.z_m[k]);
            assert!(
                (s.load_n[k] - exact).abs() <= 1e-12 * exact.max(1e-300),
                "{scheme:?} plane {k}: {} vs {exact}",
                s.load_n[k]
            );
        }
    }
}

/// Largest relative error of the linear ICM against profile theory's
/// paraboloid, F = (4√2/3) E* R^½ d^{3/2}, for 0.3 H ≤ d ≤ 0.9 H.
fn paraboloid_error(pixel_m: f64) -> f64 {
    let (radius_m, cap_m) = (1e-3, 2e-5);
    let half = (2.2e-4 / pixel_m).round() as usize;
    let n = 2 * half + 1; // odd, so the apex is a pixel centre
    let h = Array2::from_shape_fn((n, n), |(i, j)| {
        let rho = pixel_m * (i as f64 - half as f64).hypot(j as f64 - half as f64);
        (cap_m - rho * rho / (2.0 * radius_m)).max(0.0)
    });
    let p = profile_of(&h, pixel_m, Levels::Count(4000));
    let (s, e0_star) = run(&p, Model::Linear, Scheme::Heun);
    let mut worst: f64 = 0.0;
    for (k, &z) in p.z_m.iter().enumerate() {
        let d = cap_m - z;
        if (0.3 * cap_m..=0.9 * cap_m).contains(&d) {
            let exact = 4.0 * 2f64.sqrt() / 3.0 * e0_star * radius_m.sqrt() * d.powf(1.5);
            worst = worst.max((s.load_n[k] / exact - 1.0).abs());
        }
    }
    worst
}

#[test]
fn sampled_paraboloid_converges_to_profile_theorys_load() {
    let coarse = paraboloid_error(1e-5);
    let fine = paraboloid_error(2.5e-6);
    println!("paraboloid: max relative error {coarse:.3e} at 10 µm, {fine:.3e} at 2.5 µm");
    assert!(coarse < 2e-3, "coarse grid error {coarse}");
    assert!(fine < 5e-4, "fine grid error {fine}");
    assert!(
        fine < 0.5 * coarse,
        "refining 4× must shrink the error: {coarse} → {fine}"
    );
}

fn sample_map(n: usize) -> Array2<f64> {
    // The shipped sample's statistics: H = 0.8, rms 10 µm, 20 µm pixels.
    SelfAffine::whole_band(n, 2e-5).periodic(n, n, 2e-5, 2024)
}

#[test]
fn hyperelastic_tangent_starts_at_two_and_rises_with_stress() {
    let p = profile_of(&sample_map(128), 2e-5, Levels::Count(500));
    let (hyper, _) = run(&p, Model::Hyperelastic, Scheme::Heun);
    let (linear, e0_star) = run(&p, Model::Linear, Scheme::Heun);
    let ratio: Vec<f64> = hyper.modulus_pa.iter().map(|e| e / e0_star).collect();
    assert!((ratio[0] - 2.0).abs() < 1e-9, "first contact: {}", ratio[0]);
    assert!(ratio.iter().all(|&r| r > 1.0));
    let mut by_stress: Vec<(f64, f64)> = hyper
        .mean_stress_pa
        .iter()
        .copied()
        .zip(ratio.iter().copied())
        .collect();
    by_stress.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in by_stress.windows(2) {
        assert!(
            w[1].1 >= w[0].1 - 1e-12,
            "E_t* falls from {:?} to {:?}",
            w[0],
            w[1]
        );
    }
    assert!(
        by_stress.last().unwrap().1 > 2.0,
        "the ratio must rise above 2"
    );
    assert!(linear.modulus_pa.iter().all(|&e| e == e0_star));
}

#[test]
fn both_schemes_converge_to_the_same_curve() {
    let h = sample_map(512);
    let levels = 2000;
    let coarse = profile_of(&h, 2e-5, Levels::Count(levels));
    let fine = profile_of(&h, 2e-5, Levels::Count(2 * levels));
    let mut at_half = Vec::new();
    for scheme in [Scheme::Euler, Scheme::Heun] {
        let (sc, e0) = run(&coarse, Model::Hyperelastic, scheme);
        let (sf, _) = run(&fine, Model::Hyperelastic, scheme);
        let (lc, lf) = (
            load_norm_at(&coarse, &sc, e0, 0.5),
            load_norm_at(&fine, &sf, e0, 0.5),
        );
        let change = (lf / lc - 1.0).abs();
        println!(
            "{scheme:?}: load_norm(0.5) = {lc:.6e} ({levels} levels), {lf:.6e} (×2): {change:.2e}"
        );
        assert!(
            change < 1e-3,
            "{scheme:?}: halving the spacing changes load_norm by {change}"
        );
        at_half.push(lf);
    }
    let gap = (at_half[0] / at_half[1] - 1.0).abs();
    assert!(gap < 1e-3, "Euler and Heun differ by {gap} at A/A0 = 0.5");
}

#[test]
fn self_affine_map_shows_the_papers_qualitative_findings() {
    let p = profile_of(&sample_map(256), 2e-5, Levels::Count(2000));
    let (hyper, e0_star) = run(&p, Model::Hyperelastic, Scheme::Heun);
    let (linear, _) = run(&p, Model::Linear, Scheme::Heun);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
    for k in 1..p.z_m.len() {
        let f = p.area_fraction[k];
        if f > 0.0 && f < 0.9 {
            let ratio = hyper.modulus_pa[k] / e0_star;
            lo = lo.min(ratio);
            hi = hi.max(ratio);
            assert!(
                hyper.load_n[k] > linear.load_n[k],
                "plane {k}: hyperelastic {} ≤ linear {}",
                hyper.load_n[k],
                linear.load_n[k]
            );
        }
    }
    println!("E_t*/E0* over 0 < A/A0 < 0.9: {lo:.4} … {hi:.4}");
    assert!(lo >= 2.0 - 1e-9 && hi <= 3.0, "E_t*/E0* spans {lo} … {hi}");
}
