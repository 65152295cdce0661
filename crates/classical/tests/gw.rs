//! The Greenwood–Williamson model: its parameters from the moments, the
//! summit density against a synthetic surface, and the model's load curves.

use hypercontact_classical::gw::{Asperities, GwError, Moments, gaussian_tail_moment};
use hypercontact_synth::surface::self_affine::SelfAffine;
use ndarray::Array2;
use std::f64::consts::{PI, TAU};

fn relative_error(value: f64, reference: f64) -> f64 {
    ((value - reference) / reference).abs()
}

/// A surface of 1 µm rms height with α = 4 (the numbers of the hand check).
fn moments() -> Moments {
    Moments {
        m0: 1e-12,
        m2: 1e-2,
        m4: 4e8,
    }
}

fn asperities() -> Asperities {
    Asperities::from_moments(moments()).unwrap()
}

/// Separations from `from`·√m0 to `to`·√m0 in `n` equal steps.
fn separations(from: f64, to: f64, n: usize) -> Vec<f64> {
    let sigma = moments().m0.sqrt();
    (0..=n)
        .map(|i| sigma * (from + (to - from) * i as f64 / n as f64))
        .collect()
}

#[test]
fn parameters_from_moments_match_the_hand_computation() {
    // m0 = 1e-12 m², m2 = 1e-2, m4 = 4e8 m⁻²:
    // α = m0 m4 / m2² = 1e-12 · 4e8 / 1e-4 = 4
    // η = m4 / (6π√3 m2) = 4e8 / (32.648388556 · 1e-2) = 1.2251753232e9 m⁻²
    // R = (3/8) √(π/m4) = 0.375 · 8.8622692545e-5 = 3.3233509704e-5 m
    // σ_s = √((1 − 0.8968/4) m0) = √(0.7758e-12) = 8.8079509535e-7 m
    // mean = 4 √(m0/(π α)) = 4 · √(1e-12/(4π)) = 2 µm/√π = 1.1283791671e-6 m
    let a = asperities();
    assert_eq!(a.moments, moments());
    assert!(relative_error(a.nayak_alpha, 4.0) < 1e-15);
    assert!(relative_error(a.summit_density_per_m2, 1.2251753232e9) < 1e-10);
    assert!(relative_error(a.summit_radius_m, 3.3233509704e-5) < 1e-10);
    assert!(relative_error(a.summit_sigma_m, 8.8079509535e-7) < 1e-10);
    assert!(relative_error(a.summit_mean_m, 1.1283791671e-6) < 1e-10);
}

#[test]
fn moments_without_a_summit_distribution_are_refused() {
    let with = |m0: f64, m2: f64, m4: f64| Asperities::from_moments(Moments { m0, m2, m4 });
    // α = 0.8 and exactly the limit 0.8968: (1 − 0.8968/α) m0 ≤ 0
    for m4 in [0.8, 0.8968] {
        let error = with(1.0, 1.0, m4).unwrap_err();
        assert_eq!(error, GwError::BandwidthTooNarrow { alpha: m4 });
        let message = error.to_string();
        assert!(
            message.contains(&format!("α = m0·m4/m2² = {m4}")),
            "{message}"
        );
        assert!(message.contains("0.8968"), "{message}");
    }
    // just above the limit the summit spread is small but defined
    let narrow = with(1.0, 1.0, 0.9).unwrap();
    assert!(narrow.summit_sigma_m > 0.0 && narrow.summit_sigma_m < 0.07);

    let error = with(1e-12, 0.0, 4e8).unwrap_err();
    assert!(matches!(
        error,
        GwError::NonPositiveMoment { name: "m2", .. }
    ));
    assert!(error.to_string().contains("m2 = 0"), "{error}");
    let error = with(1e-12, 1e-2, -4e8).unwrap_err();
    assert!(error.to_string().contains("m4 = -400000000"), "{error}");
    assert!(error.to_string().contains("must be positive"), "{error}");
    let error = with(f64::NAN, 1e-2, 4e8).unwrap_err();
    assert!(matches!(error, GwError::NonFiniteMoment { name: "m0", .. }));
    assert!(error.to_string().contains("m0 = NaN"), "{error}");
    let error = with(1e-12, f64::INFINITY, 4e8).unwrap_err();
    assert!(matches!(error, GwError::NonFiniteMoment { name: "m2", .. }));
    // α overflows when m2 is tiny next to m0 and m4
    let error = with(1e300, 1e-300, 1e300).unwrap_err();
    assert!(matches!(error, GwError::OutOfRange { .. }), "{error}");
}

/// The signed wavevector (rad/m) of FFT index `i` on `n` points over `l`,
/// as the synthetic surfaces are generated.
fn wavevector(i: usize, n: usize, l: f64) -> f64 {
    let k = if i <= n / 2 {
        i as f64
    } else {
        i as f64 - n as f64
    };
    TAU * k / l
}

/// Strict local maxima of a periodic map: higher than all 8 neighbours.
fn local_maxima(h: &Array2<f64>) -> usize {
    let (nx, ny) = h.dim();
    let mut count = 0;
    for i in 0..nx {
        for j in 0..ny {
            let centre = h[[i, j]];
            let highest = [nx - 1, 0, 1].iter().all(|di| {
                [ny - 1, 0, 1]
                    .iter()
                    .all(|dj| (*di == 0 && *dj == 0) || h[[(i + di) % nx, (j + dj) % ny]] < centre)
            });
            count += usize::from(highest);
        }
    }
    count
}

#[test]
fn summit_density_matches_the_local_maxima_of_a_synthetic_surface() {
    // Band-limited at λ_min = 12 pixels (a sharp cut-off), so the summits
    // are resolved on the grid; roll-off at a quarter of the map.
    let (n, pixel_m) = (1024, 1e-6);
    let surface = SelfAffine {
        hurst: 0.8,
        rms_m: 1e-6,
        lambda_min_m: 12.0 * pixel_m,
        lambda_max_m: 256.0 * pixel_m,
    };
    // The profile moments of exactly this discrete spectrum: ⟨h²⟩ = Σ C/(Lx Ly)
    // over the grid's wavevectors, and m2, m4 the sums of qx² C, qx⁴ C.
    let l = n as f64 * pixel_m;
    let c0 = surface.prefactor(n, n, pixel_m);
    let (mut m0, mut m2, mut m4) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let qx = wavevector(i, n, l);
        for j in 0..n {
            let c = c0 * surface.shape(qx.hypot(wavevector(j, n, l))) / (l * l);
            m0 += c;
            m2 += qx * qx * c;
            m4 += qx.powi(4) * c;
        }
    }
    let asperities = Asperities::from_moments(Moments { m0, m2, m4 }).unwrap();
    assert!(relative_error(m0, 1e-12) < 1e-12, "m0 = {m0:e}");
    let expected = asperities.summit_density_per_m2 * l * l;

    // Measured (expected η·A = 1495.9 summits): counted 1428, 1525, 1409,
    // 1501 for seeds 1–4 (−4.5, +1.9, −5.8, +0.3 %), together −2.0 %.
    // Where the scatter comes from (found by Fourier-interpolating each
    // realisation, which is band-limited, onto grids 2× and 4× finer and by
    // the moments of each realisation's own spectrum):
    // - the 8-neighbour count on the 12-pixel grid misses ~2 % of the
    //   summits of the continuous surface (4× grid: 1463, 1549, 1443, 1522);
    //   ~1 % at λ_min = 16 pixels;
    // - each realisation's own η differs from the expected by −3…+2 %
    //   (1453.9, 1525.1, 1468.0, 1503.9): m2 has much of its weight at
    //   long wavelengths, of which the map holds few;
    // - the continuous count scatters ±1.5 % about the realisation's η.
    // One seed alone can therefore miss by more than 5 %; four do not.
    let seeds = 1..=4u64;
    let counts: Vec<usize> = seeds
        .clone()
        .map(|seed| local_maxima(&surface.periodic(n, n, pixel_m, seed)))
        .collect();
    let mean = counts.iter().sum::<usize>() as f64 / counts.len() as f64;
    assert!(
        relative_error(mean, expected) < 0.05,
        "GW summits η·A = {expected:.1}, local maxima per seed {counts:?} (mean {mean:.1})"
    );
}

#[test]
fn contacts_area_pressure_and_contact_radius_fall_with_separation() {
    let a = asperities();
    let points: Vec<_> = separations(-4.0, 6.0, 200)
        .into_iter()
        .map(|d| a.at_separation(d))
        .collect();
    for pair in points.windows(2) {
        let (near, far) = (pair[0], pair[1]);
        assert!(
            far.contacts_per_m2 < near.contacts_per_m2,
            "{near:?} {far:?}"
        );
        assert!(far.area_fraction < near.area_fraction, "{near:?} {far:?}");
        assert!(far.unit_pressure < near.unit_pressure, "{near:?} {far:?}");
        assert!(
            far.mean_contact_radius_m < near.mean_contact_radius_m,
            "{near:?} {far:?}"
        );
    }
    // every summit touches when the flat is far below them
    let deep = a.at_separation(-20.0 * a.summit_sigma_m);
    assert!(relative_error(deep.contacts_per_m2, a.summit_density_per_m2) < 1e-15);
}

#[test]
fn area_per_load_falls_as_the_load_rises() {
    // κ = (A/A0) / (p̄/(E* h'rms)), h'rms = √(2 m2) the rms gradient of the
    // surface, from d = 3σ down to d = −σ (σ = √m0).
    let a = asperities();
    let slope = (2.0 * moments().m2).sqrt();
    let kappa: Vec<f64> = separations(3.0, -1.0, 40)
        .into_iter()
        .map(|d| {
            let point = a.at_separation(d);
            point.area_fraction / (point.unit_pressure / slope)
        })
        .collect();
    for pair in kappa.windows(2) {
        assert!(pair[1] < pair[0], "κ rose from {} to {}", pair[0], pair[1]);
    }
    assert!(kappa.iter().all(|k| k.is_finite() && *k > 0.0));
}

/// Σ_n a_n with a_0 = 1, a_n = a_{n−1} · (−1/2)/n · (k + 2n − 1)(k + 2n)/u²:
/// the series of F_k(u) u^{k+1} / (φ(u) Γ(k+1)) at large u, from expanding
/// e^{−t²/2} in F_k(u) = φ(u) ∫_0^∞ t^k e^{−u t − t²/2} dt term by term
/// (∫ t^{k+2n} e^{−ut} dt = Γ(k+2n+1)/u^{k+2n+1}). Summed up to its
/// smallest term (it is asymptotic).
fn asymptotic_series(k: f64, u: f64) -> f64 {
    let (mut term, mut sum) = (1.0_f64, 1.0);
    for n in 1..200 {
        let next =
            term * -0.5 / n as f64 * (k + 2.0 * n as f64 - 1.0) * (k + 2.0 * n as f64) / (u * u);
        if next.abs() >= term.abs() || next.abs() < 1e-18 {
            break;
        }
        term = next;
        sum += term;
    }
    sum
}

#[test]
fn area_over_load_follows_the_asymptotic_tail_moments() {
    // A/A0 ÷ p̄/E* = (3π/4) √(R/σ_s) F_1/F_{3/2}; at large u with the series
    // above and Γ(2)/Γ(5/2) = 4/(3√π) this is √(π R u/σ_s) · S_1/S_{3/2}.
    let a = asperities();
    let (r, sigma) = (a.summit_radius_m, a.summit_sigma_m);
    for u in [12.0, 20.0, 30.0, 36.0] {
        let point = a.at_separation(a.summit_mean_m + sigma * u);
        let ratio = point.area_fraction / point.unit_pressure;
        let series =
            (PI * r * u / sigma).sqrt() * asymptotic_series(1.0, u) / asymptotic_series(1.5, u);
        assert!(
            relative_error(ratio, series) < 1e-12,
            "u = {u}: A/p̄ = {ratio:e}, asymptotics {series:e}"
        );
    }
    // and at any u the same ratio from the tail moments directly
    for u in [-3.0, -0.5, 0.0, 1.0, 4.0] {
        let point = a.at_separation(a.summit_mean_m + sigma * u);
        let ratio = point.area_fraction / point.unit_pressure;
        let moments = 0.75 * PI * (r / sigma).sqrt() * gaussian_tail_moment(1.0, u)
            / gaussian_tail_moment(1.5, u);
        assert!(relative_error(ratio, moments) < 1e-12, "u = {u}");
    }
}

#[test]
fn separation_at_unit_pressure_inverts_at_separation() {
    let a = asperities();
    for d in separations(-3.0, 5.0, 64) {
        let pressure = a.at_separation(d).unit_pressure;
        let back = a.separation_at_unit_pressure(pressure);
        assert!(
            (back - d).abs() < 1e-10 * a.summit_sigma_m,
            "d = {d:e}: p̄/E* = {pressure:e} gives back {back:e}"
        );
        let again = a.at_separation(back).unit_pressure;
        assert!(relative_error(again, pressure) < 1e-10, "d = {d:e}");
    }
    // down to pressures far below any contact and up to full compression
    for pressure in [1e-300, 1e-30, 1e-8, 1e-3, 0.1, 10.0, 1e6] {
        let d = a.separation_at_unit_pressure(pressure);
        let again = a.at_separation(d).unit_pressure;
        assert!(
            relative_error(again, pressure) < 1e-10,
            "p̄/E* = {pressure:e} at d = {d:e} gives {again:e}"
        );
    }
    assert_eq!(a.separation_at_unit_pressure(0.0), f64::INFINITY);
    assert_eq!(
        a.separation_at_unit_pressure(f64::INFINITY),
        f64::NEG_INFINITY
    );
    assert!(a.separation_at_unit_pressure(-1.0).is_nan());
    assert!(a.separation_at_unit_pressure(f64::NAN).is_nan());
}

#[test]
fn extreme_separations_give_finite_values_and_zero_without_contact() {
    let a = asperities();
    let sigma = moments().m0.sqrt();
    let far = a.at_separation(1e3 * sigma);
    assert_eq!(
        (
            far.area_fraction,
            far.unit_pressure,
            far.contacts_per_m2,
            far.mean_contact_radius_m
        ),
        (0.0, 0.0, 0.0, 0.0)
    );
    let deep = a.at_separation(-1e3 * sigma);
    for value in [
        deep.area_fraction,
        deep.unit_pressure,
        deep.contacts_per_m2,
        deep.mean_contact_radius_m,
    ] {
        assert!(value.is_finite() && value > 0.0, "{deep:?}");
    }
    // every summit touches, each pressed ≈ 1e3 σ − its height
    assert_eq!(deep.contacts_per_m2, a.summit_density_per_m2);
    let depth = 1e3 * sigma + a.summit_mean_m;
    assert!(
        relative_error(
            deep.mean_contact_radius_m,
            (a.summit_radius_m * depth).sqrt()
        ) < 1e-5
    );
    // nothing panics at the ends of the number line either
    let _ = a.at_separation(f64::INFINITY);
    let _ = a.at_separation(f64::NEG_INFINITY);
    let nan = a.at_separation(f64::NAN);
    assert!(nan.unit_pressure.is_nan() && nan.area_fraction.is_nan());
}
