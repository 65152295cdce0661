//! Persson's theory against closed forms and independent evaluations.

use hypercontact_classical::persson::{Persson, Variant};
use hypercontact_classical::spectrum::Spectrum;
use std::f64::consts::PI;

const H: f64 = 0.7;
const Q0: f64 = 2e3;
const Q1: f64 = 2e6;
/// C = C0 q^−(2+2H), C0 such that h'rms = 0.3.
fn c0() -> f64 {
    let slope2: f64 = 0.09;
    // h'rms² = 2π ∫ q³ C dq = 2π C0 (q1^(2−2H) − q0^(2−2H)) / (2 − 2H).
    let e = 2.0 - 2.0 * H;
    slope2 / (2.0 * PI * (Q1.powf(e) - Q0.powf(e)) / e)
}

fn spectrum(points: usize) -> Spectrum {
    let q: Vec<f64> = (0..points)
        .map(|i| Q0 * (Q1 / Q0).powf(i as f64 / (points - 1) as f64))
        .collect();
    let c = q.iter().map(|q| c0() * q.powf(-2.0 - 2.0 * H)).collect();
    Spectrum::new(q, c).unwrap()
}

const YP: Variant = Variant::YangPersson { gamma: 0.45 };

#[test]
fn small_load_slopes_are_persson_and_yang_perssons() {
    let s = spectrum(31);
    let slope = s.moments().rms_slope();
    assert!((slope / 0.3 - 1.0).abs() < 1e-12);
    let kappa = |variant, pu: f64| Persson::new(&s, variant).area_fraction(pu) / (pu / slope);
    // A/A0 → √(8/π) p̄/(E* h'rms) = 1.596 p̄/(E* h'rms) (the slope).
    let original = kappa(Variant::Original, 1e-6);
    assert!((original - (8.0 / PI).sqrt()).abs() < 1e-9, "{original}");
    assert!((original - 1.596).abs() < 1e-3);
    // Corrected: the diffusion runs at γ once contact is partial, → 1.596/√γ.
    let corrected = kappa(YP, 1e-6);
    let expected = (8.0 / PI).sqrt() / 0.45f64.sqrt();
    assert!(
        (corrected / expected - 1.0).abs() < 1e-4,
        "{corrected} vs {expected}"
    );
}

#[test]
fn corrected_lies_above_original_at_mid_loads_and_both_reach_full_contact() {
    let s = spectrum(31);
    let (original, corrected) = (Persson::new(&s, Variant::Original), Persson::new(&s, YP));
    for pu in [0.01, 0.03, 0.1, 0.2] {
        let (a, b) = (original.area_fraction(pu), corrected.area_fraction(pu));
        let margin = if pu <= 0.1 { 1.05 } else { 1.0 };
        assert!(b > a * margin, "p/E* = {pu}: corrected {b} vs original {a}");
    }
    for p in [&original, &corrected] {
        assert!(p.area_fraction(2.0) > 1.0 - 1e-9);
        assert!(p.area_fraction(0.5) > 0.99);
    }
}

/// The corrected march depends on the spectrum only through V(q1): it must
/// not depend on how the spectrum is tabulated or shaped.
#[test]
fn the_corrected_march_depends_on_the_spectrum_only_through_its_variance() {
    let coarse = Persson::new(&spectrum(4), YP);
    let fine = Persson::new(&spectrum(301), YP);
    // A band of white noise scaled to the same V.
    let white = Spectrum::new(vec![1e4, 3e4, 1e5], vec![1.0, 1.0, 1.0]).unwrap();
    let scale = coarse.variance() / Persson::new(&white, YP).variance();
    let white = Spectrum::new(vec![1e4, 3e4, 1e5], vec![scale; 3]).unwrap();
    let white = Persson::new(&white, YP);
    for pu in [1e-4, 1e-2, 0.05, 0.15, 0.4] {
        let a = coarse.area_fraction(pu);
        for other in [&fine, &white] {
            let b = other.area_fraction(pu);
            assert!((a / b - 1.0).abs() < 1e-7, "p/E* = {pu}: {a} vs {b}");
        }
    }
}

/// Independent method: Yang & Persson's march as they state it, an implicit
/// (backward Euler) step A_i = erf(p/√(2 V_p,i)), V_p,i = V_p,i−1 + S(A_i) ΔV,
/// on 200 000 steps in q, each solved by bisection.
#[test]
fn the_corrected_area_matches_a_fine_implicit_march() {
    let s = spectrum(31);
    let ours = Persson::new(&s, YP);
    let n = 200_000;
    let implicit = |pu: f64| {
        let (mut vp, mut area) = (0.0, 1.0);
        let mut q_prev = Q0;
        for i in 1..=n {
            let q = Q0 * (Q1 / Q0).powf(i as f64 / n as f64);
            let dv = 0.5 * PI * s.integral_between(3.0, q_prev, q);
            q_prev = q;
            let f = |a: f64| a - libm::erf(pu / (2.0 * (vp + (0.45 + 0.55 * a * a) * dv)).sqrt());
            let (mut lo, mut hi) = (0.0, area);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if f(mid) > 0.0 { hi = mid } else { lo = mid }
            }
            area = 0.5 * (lo + hi);
            vp += (0.45 + 0.55 * area * area) * dv;
        }
        area
    };
    for pu in [0.005, 0.05, 0.2] {
        let (a, b) = (ours.area_fraction(pu), implicit(pu));
        assert!(
            (a / b - 1.0).abs() < 2e-4,
            "p/E* = {pu}: {a} vs implicit {b}"
        );
    }
}

/// E1(x) = ∫_x^∞ e^{−t}/t dt: series below 1, continued fraction above.
fn exp_integral(x: f64) -> f64 {
    if x < 1.0 {
        let mut sum = -0.577_215_664_901_532_9 - x.ln();
        let mut term = 1.0;
        for k in 1..60 {
            term *= -x / k as f64;
            sum -= term / k as f64;
        }
        sum
    } else {
        // Lentz's evaluation of e^{−x} / (x + 1 − 1²/(x + 3 − 2²/(x + 5 − …))).
        let mut b = x + 1.0;
        let mut c = 1e300;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..200 {
            let a = -((i * i) as f64);
            b += 2.0;
            d = 1.0 / (a * d + b);
            c = b + a / c;
            let delta = c * d;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        h * (-x).exp()
    }
}

/// Independent method for the original theory: Persson's (2007) closed
/// inner integral, ū = √π ∫ q² C w ½E1((w p)²) dq with
/// w = (π ∫_{q0}^{q} q'³ C dq')^{−1/2}, by a fine trapezoid in ln q.
#[test]
fn original_mean_separation_matches_the_exponential_integral_form() {
    let s = spectrum(31);
    let ours = Persson::new(&s, Variant::Original);
    let loads = [1e-4, 1e-3, 0.01, 0.05, 0.2];
    let curve = ours.curve(&loads);
    let e = 2.0 - 2.0 * H;
    let reference = |pu: f64| {
        let n = 400_000;
        let mut sum = 0.0;
        let mut last = 0.0;
        for i in 0..=n {
            let q = Q0 * (Q1 / Q0).powf(i as f64 / n as f64);
            let cumulative = c0() * (q.powf(e) - Q0.powf(e)) / e;
            let value = if i == 0 {
                0.0
            } else {
                let w = (PI * cumulative).powf(-0.5);
                // dq = q d(ln q).
                q * q * q * c0() * q.powf(-2.0 - 2.0 * H) * w * 0.5 * exp_integral((w * pu).powi(2))
            };
            if i > 0 {
                sum += 0.5 * (value + last) * (Q1 / Q0).ln() / n as f64;
            }
            last = value;
        }
        PI.sqrt() * sum
    };
    let h_rms = s.moments().rms_height_m();
    for point in &curve {
        let expected = reference(point.unit_pressure);
        assert!(
            (point.mean_separation_m / expected - 1.0).abs() < 3e-4,
            "p/E* = {}: {} vs {expected} (h_rms {h_rms})",
            point.unit_pressure,
            point.mean_separation_m
        );
    }
    // ū falls with load, towards 0 at full contact.
    assert!(
        curve
            .windows(2)
            .all(|w| w[1].mean_separation_m < w[0].mean_separation_m)
    );
    let full = ours.curve(&[3.0]);
    assert!(full[0].mean_separation_m < 1e-6 * h_rms, "{full:?}");
}

#[test]
fn corrected_mean_separation_falls_with_load_and_lies_below_the_originals() {
    let s = spectrum(31);
    let loads: Vec<f64> = (0..40).map(|i| 1e-4 * 1.25f64.powi(i)).collect();
    let original = Persson::new(&s, Variant::Original).curve(&loads);
    let corrected = Persson::new(&s, YP).curve(&loads);
    for (a, b) in original.iter().zip(&corrected) {
        assert!(b.mean_separation_m > 0.0 && b.mean_separation_m.is_finite());
        // More contact at the same load, less stored energy per area of
        // contact: the surfaces come closer.
        assert!(b.area_fraction >= a.area_fraction);
    }
    assert!(
        corrected
            .windows(2)
            .all(|w| w[1].mean_separation_m < w[0].mean_separation_m)
    );
    // Persson (2007): at small load p ∝ exp(−ū/u0): ū linear in ln p.
    let slope = |k: usize| {
        (corrected[k + 1].mean_separation_m - corrected[k].mean_separation_m) / 1.25f64.ln()
    };
    assert!(
        (slope(1) / slope(5) - 1.0).abs() < 0.02,
        "{} {}",
        slope(1),
        slope(5)
    );
}
