//! The Greenwood–Williamson asperity model of rough contact, with its
//! parameters from the spectral moments of an isotropic Gaussian surface.
//!
//! Conventions:
//! - The rough surface is isotropic and Gaussian; its spectral moments are
//!   the profile moments of Nayak (1971): m0 = ⟨h²⟩, m2 = ⟨(∂h/∂x)²⟩ and
//!   m4 = ⟨(∂²h/∂x²)²⟩ along any one direction (so the rms gradient of the
//!   surface is √(2 m2)).
//! - A rigid flat is pressed onto it; the separation d is measured from the
//!   mean plane of the surface heights (not of the summit heights), positive
//!   away from the surface.
//! - Every summit is a Hertzian sphere of the same radius R, deforming
//!   independently of its neighbours (Greenwood & Williamson 1966); the
//!   pressure is reported over the composite modulus E* of the Hertz law
//!   F = (4/3) E* √R δ^{3/2}, so the model needs no material.
//! - The summit heights are Gaussian with the mean and spread McCool (1986)
//!   gives for a Gaussian surface of Nayak bandwidth α.
//!
//! Sources:
//! - J. A. Greenwood and J. B. P. Williamson, Contact of nominally flat
//!   surfaces, Proc. R. Soc. Lond. A 295, 300–319 (1966): the model and its
//!   integrals over the summit-height distribution.
//! - P. R. Nayak, Random process model of rough surfaces, J. Lubr. Technol.
//!   93, 398–407 (1971): bandwidth α = m0 m4 / m2², summit density
//!   m4 / (6π√3 m2), mean summit curvature (8/3) √(m4/π).
//! - J. I. McCool, Comparison of models for the contact of rough surfaces,
//!   Wear 107, 37–60 (1986): summit radius, summit-height variance and mean
//!   summit height of the GW model from the moments.
//!
//! All of the model reduces to the Gaussian tail moments
//! F_k(u) = ∫_0^∞ t^k φ(u + t) dt ([`gaussian_tail_moment`]).

use std::f64::consts::{FRAC_1_SQRT_2, PI};
use std::sync::OnceLock;

/// McCool's (1986) coefficient of the summit-height variance (1 − 0.8968/α) m0.
const SUMMIT_VARIANCE_COEFFICIENT: f64 = 0.8968;

/// 1/√(2π), the peak of the standard normal density (correctly rounded).
const FRAC_1_SQRT_TAU: f64 = 0.3989422804014327;

/// ln √(2π) (correctly rounded).
const LN_SQRT_TAU: f64 = 0.9189385332046728;

/// Spectral moments of an isotropic surface, profile convention (Nayak 1971):
/// m0 = ⟨h²⟩, m2 = ⟨(∂h/∂x)²⟩, m4 = ⟨(∂²h/∂x²)²⟩ along any direction. m², m⁰, m⁻².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moments {
    pub m0: f64,
    pub m2: f64,
    pub m4: f64,
}

/// The summit statistics of the GW model, from the spectral moments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Asperities {
    pub moments: Moments,
    /// Nayak's bandwidth parameter α = m0 m4 / m2²
    pub nayak_alpha: f64,
    /// summit density η = m4 / (6π√3 m2), per m² (Nayak 1971, isotropic Gaussian surface)
    pub summit_density_per_m2: f64,
    /// mean summit radius R = (3/8) √(π/m4) (McCool 1986, from Nayak's mean summit curvature)
    pub summit_radius_m: f64,
    /// std of summit heights σ_s = √((1 − 0.8968/α) m0) (McCool 1986)
    pub summit_sigma_m: f64,
    /// mean summit height above the mean plane of the surface heights, 4 √(m0/(π α)) (McCool 1986)
    pub summit_mean_m: f64,
}

/// The state of the GW model at one separation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GwPoint {
    /// A/A0
    pub area_fraction: f64,
    /// p̄/E*: mean nominal pressure over the composite modulus (dimensionless)
    pub unit_pressure: f64,
    /// asperities in contact per m²
    pub contacts_per_m2: f64,
    /// mean Hertz contact radius √(R δ) over the touching summits, m (0 when none touch)
    pub mean_contact_radius_m: f64,
}

/// Moments the GW parameters cannot be derived from.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GwError {
    #[error("spectral moment {name} = {value} is not a finite number")]
    NonFiniteMoment { name: &'static str, value: f64 },
    #[error("spectral moment {name} = {value} must be positive: it is the mean square {meaning}")]
    NonPositiveMoment {
        name: &'static str,
        value: f64,
        meaning: &'static str,
    },
    #[error(
        "Nayak's bandwidth α = m0·m4/m2² = {alpha} is at most 0.8968, where McCool's summit-height \
         variance (1 − 0.8968/α)·m0 is not positive; no surface has α < 1 (m2² ≤ m0·m4 by \
         Cauchy–Schwarz), so these moments do not belong together"
    )]
    BandwidthTooNarrow { alpha: f64 },
    #[error(
        "the {what} = {value} from these moments is not a finite positive number: the moments \
         are too far apart in magnitude for double precision"
    )]
    OutOfRange { what: &'static str, value: f64 },
}

impl Asperities {
    /// The GW summit statistics of an isotropic Gaussian surface with these moments.
    pub fn from_moments(m: Moments) -> Result<Self, GwError> {
        for (name, value, meaning) in [
            ("m0", m.m0, "of the heights ⟨h²⟩"),
            ("m2", m.m2, "of the slopes ⟨(∂h/∂x)²⟩"),
            ("m4", m.m4, "of the curvatures ⟨(∂²h/∂x²)²⟩"),
        ] {
            if !value.is_finite() {
                return Err(GwError::NonFiniteMoment { name, value });
            }
            if value <= 0.0 {
                return Err(GwError::NonPositiveMoment {
                    name,
                    value,
                    meaning,
                });
            }
        }
        // Nayak (1971): α = m0 m4 / m2², written to keep the product in range.
        let alpha = (m.m0 / m.m2) * (m.m4 / m.m2);
        if alpha <= SUMMIT_VARIANCE_COEFFICIENT {
            return Err(GwError::BandwidthTooNarrow { alpha });
        }
        // Nayak (1971): summit density m4 / (6π√3 m2) of an isotropic Gaussian surface.
        let density = m.m4 / (6.0 * PI * 3f64.sqrt() * m.m2);
        // McCool (1986): R is the reciprocal of Nayak's mean summit curvature (8/3) √(m4/π).
        let radius = 0.375 * (PI / m.m4).sqrt();
        // McCool (1986): summit-height variance (1 − 0.8968/α) m0 and mean 4 √(m0/(π α)).
        let sigma = ((1.0 - SUMMIT_VARIANCE_COEFFICIENT / alpha) * m.m0).sqrt();
        let mean = 4.0 * (m.m0 / (PI * alpha)).sqrt();
        for (what, value) in [
            ("bandwidth α", alpha),
            ("summit density", density),
            ("summit radius", radius),
            ("summit-height spread", sigma),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(GwError::OutOfRange { what, value });
            }
        }
        Ok(Self {
            moments: m,
            nayak_alpha: alpha,
            summit_density_per_m2: density,
            summit_radius_m: radius,
            summit_sigma_m: sigma,
            summit_mean_m: mean,
        })
    }

    /// The GW state at separation `d_m` of the rigid flat from the MEAN PLANE OF THE SURFACE HEIGHTS
    /// (summit heights Gaussian, mean summit_mean_m, std summit_sigma_m; every summit a Hertz sphere of radius R;
    /// u = (d − summit_mean)/σ_s):
    ///   contacts/A0 = η F0(u),  A/A0 = π η R σ_s F1(u),  p̄/E* = (4/3) η √R σ_s^{3/2} F_{3/2}(u)
    /// with F_k(u) = ∫_0^∞ t^k φ(u + t) dt, φ the standard normal pdf. E* is the composite modulus (Hertz F = 4/3 E* √R δ^{3/2}).
    ///
    /// The model is not capped: at loads where A/A0 approaches 1 it is far
    /// outside its validity (it neglects the interaction of the summits),
    /// but the numbers stay finite. A NaN separation gives NaN.
    pub fn at_separation(&self, d_m: f64) -> GwPoint {
        let (eta, r, sigma) = (
            self.summit_density_per_m2,
            self.summit_radius_m,
            self.summit_sigma_m,
        );
        let u = (d_m - self.summit_mean_m) / sigma;
        let contacts = eta * gaussian_tail_moment(0.0, u);
        // Greenwood & Williamson (1966): one contact of interference δ has
        // area π R δ and load (4/3) E* √R δ^{3/2}; averaged over the summit
        // heights z = mean + σ_s x with δ = σ_s (x − u).
        let area = PI * eta * r * sigma * gaussian_tail_moment(1.0, u);
        let pressure = self.pressure_coefficient() * gaussian_tail_moment(1.5, u);
        // ⟨√(R δ)⟩ over the touching summits is √(R σ_s) F_{1/2}/F_0; both
        // integrals carry the same scale, which cancels where F itself underflows.
        let radius = if contacts == 0.0 {
            0.0
        } else {
            let [half, zero] = scaled_tail_moments([0.5, 0.0], u);
            (r * sigma).sqrt() * (half / zero)
        };
        GwPoint {
            area_fraction: area,
            unit_pressure: pressure,
            contacts_per_m2: contacts,
            mean_contact_radius_m: radius,
        }
    }

    /// The separation at which p̄/E* equals `unit_pressure` (> 0): bisection/safeguarded Newton on the
    /// monotone p̄/E*(d); deterministic, accurate to ~1e-12 relative in p̄.
    ///
    /// The equation is solved for ln F_{3/2}(u), which is concave and
    /// decreasing in u and does not underflow at light loads. A pressure of
    /// 0 gives +∞ (no finite separation is that light), +∞ gives −∞, and a
    /// negative or NaN pressure gives NaN.
    pub fn separation_at_unit_pressure(&self, unit_pressure: f64) -> f64 {
        if unit_pressure.is_nan() || unit_pressure < 0.0 {
            return f64::NAN;
        }
        if unit_pressure == 0.0 {
            return f64::INFINITY;
        }
        if unit_pressure == f64::INFINITY {
            return f64::NEG_INFINITY;
        }
        let log_target = unit_pressure.ln() - self.pressure_coefficient().ln();
        let u = solve_log_pressure_integral(log_target);
        self.summit_mean_m + self.summit_sigma_m * u
    }

    /// (4/3) η √R σ_s^{3/2}: p̄/E* = this × F_{3/2}(u) (Greenwood & Williamson 1966).
    fn pressure_coefficient(&self) -> f64 {
        4.0 / 3.0
            * self.summit_density_per_m2
            * self.summit_radius_m.sqrt()
            * self.summit_sigma_m.powf(1.5)
    }
}

/// GW as a load–area theory: A/A0 at p̄/E* (0 at no load).
impl crate::curve::Theory for Asperities {
    fn area_fraction(&self, unit_pressure: f64) -> f64 {
        if unit_pressure > 0.0 {
            let d = self.separation_at_unit_pressure(unit_pressure);
            self.at_separation(d).area_fraction
        } else {
            0.0
        }
    }
}

/// F_k(u) = ∫_0^∞ t^k φ(u + t) dt for k ≥ 0 (k = 0, 1, 3/2 used), φ the
/// standard normal density: the moments of (X − u)⁺ for a standard normal X.
///
/// Accurate to ~1e-13 relative wherever the value is a normal double (u up
/// to ≈ 37.5, and any u below); past that it is subnormal, loses relative
/// precision gradually and is 0 from u ≈ 38.6 on.
///
/// - k = 0: Q(u) = erfc(u/√2)/2.
/// - k = 1: φ(u) − u Q(u) for u < 2; from u = 2 on the same function as
///   φ(u)/(1 + u w(u)), w from Laplace's continued fraction of the Mills
///   ratio, because the difference φ − uQ loses about 2 log₁₀ u digits.
/// - other k: composite Gauss–Legendre quadrature after t = s² (integrand
///   2 s^{2k+1} φ(u + s²), smooth at s = 0 for any k ≥ 0), over the s where
///   the integrand is above e^{−(50 + 3k)} of its peak (near t ~ 1/u for
///   large positive u, near t ≈ −u for negative u). For u > 0 it
///   integrates φ(u + s²)/φ(u) = e^{−u s² − s⁴/2} and multiplies by φ(u) at
///   the end; for u < −2V (V ≈ 10, past which φ is negligible) it
///   integrates (v − u)^k φ(v) over v = u + t ∈ [−V, V] instead, which
///   avoids forming u + s² from two large numbers.
///
/// Checked against the parabolic-cylinder closed form for k ≤ 3. NaN for a
/// negative or NaN k and for a NaN u.
pub fn gaussian_tail_moment(k: f64, u: f64) -> f64 {
    if k.is_nan() || k < 0.0 || u.is_nan() {
        return f64::NAN;
    }
    if k == 0.0 {
        upper_tail(u)
    } else if k == 1.0 {
        first_tail_moment(u)
    } else {
        tail_moment_by_quadrature(k, u)
    }
}

/// Q(u) = P(X > u) for a standard normal X: erfc(u/√2)/2.
fn upper_tail(u: f64) -> f64 {
    0.5 * libm::erfc(u * FRAC_1_SQRT_2)
}

/// Below this u the first tail moment is φ(u) − u Q(u) directly.
const CONTINUED_FRACTION_FROM: f64 = 2.0;

/// Terms of Laplace's continued fraction kept at u = [`CONTINUED_FRACTION_FROM`].
const CONTINUED_FRACTION_TERMS: usize = 200;

/// F_1(u) = ∫_0^∞ t φ(u + t) dt = φ(u) − u Q(u) (since φ'(v) = −v φ(v)).
fn first_tail_moment(u: f64) -> f64 {
    if u < CONTINUED_FRACTION_FROM {
        return normal_pdf(u) - u * upper_tail(u);
    }
    // Laplace's continued fraction of the Mills ratio (e.g. Abramowitz &
    // Stegun 26.2.14): Q/φ = 1/(u + 1/(u + 2/(u + 3/(u + …)))). With
    // w = u + 2/(u + 3/(u + …)), Q/φ = w/(u w + 1), so
    // F_1 = φ (1 − u Q/φ) = φ/(1 + u w), free of cancellation. Evaluated
    // from the tail back; it converges faster the larger u is.
    let terms = ((CONTINUED_FRACTION_TERMS as f64) * (CONTINUED_FRACTION_FROM / u).powi(2)).ceil();
    let terms = (terms as usize).max(12);
    let mut w = u;
    for j in (2..=terms + 1).rev() {
        w = u + j as f64 / w;
    }
    normal_pdf(u) / (1.0 + u * w)
}

/// φ(x) = e^{−x²/2}/√(2π), with x² split so that the exponent is exact:
/// x = hi + lo with hi of 26 significant bits, x² = hi² + lo (hi + x), hi²
/// exact. Plain exp(−x²/2) would carry the rounding of x²/2 (≈ 700 ulp at
/// x = 38) as a relative error.
fn normal_pdf(x: f64) -> f64 {
    let x = x.abs();
    if x.is_nan() {
        return f64::NAN;
    }
    if x > 40.0 {
        return 0.0;
    }
    let hi = f64::from_bits(x.to_bits() & !((1u64 << 27) - 1));
    let lo = x - hi;
    (-0.5 * (hi * hi)).exp() * (-0.5 * lo * (hi + x)).exp() * FRAC_1_SQRT_TAU
}

/// ln φ(u) for u > 0, the logarithm of the scale of [`scaled_tail_moments`].
fn log_tail_scale(u: f64) -> f64 {
    if u > 0.0 {
        -0.5 * u * u - LN_SQRT_TAU
    } else {
        0.0
    }
}

/// The scale of [`scaled_tail_moments`]: φ(u) for u > 0, else 1.
fn tail_scale(u: f64) -> f64 {
    if u > 0.0 { normal_pdf(u) } else { 1.0 }
}

/// F_k(u) by quadrature for any k ≥ 0 (for k = 0 and 1 the tests check it
/// against the closed forms).
fn tail_moment_by_quadrature(k: f64, u: f64) -> f64 {
    let [integral] = scaled_tail_moments([k], u);
    tail_scale(u) * integral
}

/// Gauss–Legendre nodes per panel.
const NODES: usize = 16;

/// Panels over the integration interval.
const PANELS: usize = 12;

/// The tail moments F_k(u) / [`tail_scale`](u) for several k at one u, by
/// composite Gauss–Legendre quadrature on one set of nodes.
///
/// The integration range leaves out the parts where the integrand is below
/// e^{−L} of its largest value, L = 50 + 3k (a margin for the factor t^k):
/// - u > 0: t = s², s² ≤ 2L/(√(u² + 2L) + u), i.e. u s² + s⁴/2 ≤ L;
/// - −2V ≤ u ≤ 0 (V = √(2L)): t = s², v = u + s² ∈ [−V, V];
/// - u < −2V: v = u + t ∈ [−V, V] directly, where t^k is smooth.
fn scaled_tail_moments<const M: usize>(ks: [f64; M], u: f64) -> [f64; M] {
    let mut sums = [0.0; M];
    if u.is_nan() || ks.iter().any(|k| k.is_nan() || *k < 0.0) {
        return [f64::NAN; M];
    }
    if u == f64::INFINITY {
        // the range below shrinks to nothing, and e^{−u s²} at s = 0 is NaN
        return sums;
    }
    let k_max = ks.iter().fold(0.0, |a: f64, b| a.max(*b));
    let l = 50.0 + 3.0 * k_max;
    let v = (2.0 * l).sqrt();
    let rule = gauss_legendre();
    if u > 0.0 {
        // φ(u + s²) = φ(u) e^{−u s² − s⁴/2}
        let s_max = (2.0 * l / ((u * u + 2.0 * l).sqrt() + u)).sqrt();
        composite(rule, 0.0, s_max, |s, w| {
            let s2 = s * s;
            let weight = w * 2.0 * s * (-(u * s2) - 0.5 * s2 * s2).exp();
            add_powers(&mut sums, &ks, s2, weight);
        });
    } else if u >= -2.0 * v {
        let s_min = (-v - u).max(0.0).sqrt();
        let s_max = (v - u).sqrt();
        composite(rule, s_min, s_max, |s, w| {
            let s2 = s * s;
            let weight = w * 2.0 * s * normal_pdf(u + s2);
            add_powers(&mut sums, &ks, s2, weight);
        });
    } else {
        composite(rule, -v, v, |x, w| {
            add_powers(&mut sums, &ks, x - u, w * normal_pdf(x));
        });
    }
    sums
}

/// sums[i] += t^{k_i} · weight (t^0 = 1, also at t = 0).
fn add_powers<const M: usize>(sums: &mut [f64; M], ks: &[f64; M], t: f64, weight: f64) {
    for (sum, k) in sums.iter_mut().zip(ks) {
        let power = if *k == 0.0 { 1.0 } else { t.powf(*k) };
        *sum += power * weight;
    }
}

/// Calls `visit(x, w)` at the nodes x of [`PANELS`] equal Gauss–Legendre
/// panels over [a, b], w the node's weight: Σ w f(x) ≈ ∫_a^b f.
fn composite(rule: &GaussLegendre, a: f64, b: f64, mut visit: impl FnMut(f64, f64)) {
    let half_width = 0.5 * (b - a) / PANELS as f64;
    for panel in 0..PANELS {
        let centre = a + (2 * panel + 1) as f64 * half_width;
        for (x, w) in rule.nodes.iter().zip(&rule.weights) {
            visit(centre + half_width * x, half_width * w);
        }
    }
}

/// An n-point Gauss–Legendre rule on [−1, 1].
struct GaussLegendre {
    nodes: [f64; NODES],
    weights: [f64; NODES],
}

/// The rule, computed once: the nodes are the roots of the Legendre
/// polynomial P_n, found by Newton's method from Tricomi's estimate
/// cos(π (i − 1/4)/(n + 1/2)), P_n by the three-term recurrence
/// (j + 1) P_{j+1} = (2j + 1) x P_j − j P_{j−1}, and the weights
/// 2 / ((1 − x²) P_n'(x)²) with P_n' = n (x P_n − P_{n−1}) / (x² − 1)
/// (Gauss' formula and the Legendre recurrences, Abramowitz & Stegun
/// §25.4 and §22.7–22.8).
fn gauss_legendre() -> &'static GaussLegendre {
    static RULE: OnceLock<GaussLegendre> = OnceLock::new();
    RULE.get_or_init(|| {
        let n = NODES;
        let mut nodes = [0.0; NODES];
        let mut weights = [0.0; NODES];
        for i in 0..n {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let step = legendre_newton_step(n, x);
                x -= step;
                if step.abs() <= 1e-16 {
                    break;
                }
            }
            let (p, p_prev) = legendre(n, x);
            let derivative = n as f64 * (x * p - p_prev) / (x * x - 1.0);
            nodes[i] = x;
            weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
        }
        GaussLegendre { nodes, weights }
    })
}

/// P_n(x) / P_n'(x).
fn legendre_newton_step(n: usize, x: f64) -> f64 {
    let (p, p_prev) = legendre(n, x);
    p * (x * x - 1.0) / (n as f64 * (x * p - p_prev))
}

/// (P_n(x), P_{n−1}(x)) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p_prev, mut p) = (1.0, x);
    for j in 1..n {
        let next = ((2 * j + 1) as f64 * x * p - j as f64 * p_prev) / (j + 1) as f64;
        p_prev = p;
        p = next;
    }
    (p, p_prev)
}

/// The u at which ln F_{3/2}(u) = `log_target`. ln F_{3/2} is concave
/// (F_k is log-concave: the convolution of the log-concave t^k on t ≥ 0
/// with φ) and strictly decreasing, with (ln F_{3/2})' = −(3/2) F_{1/2}/F_{3/2}
/// (differentiate F_k(u) = ∫_u^∞ (v − u)^k φ(v) dv). Bracketed by doubling
/// from [−1, 1], then Newton steps kept inside the bracket (a step that
/// would leave it is replaced by bisection). On a concave decreasing
/// function Newton's iterates approach the root from the right, quadratically.
fn solve_log_pressure_integral(log_target: f64) -> f64 {
    // g(u) = ln F_{3/2}(u) − log_target and g'(u), from one quadrature.
    let residual = |u: f64| {
        let [three_halves, half] = scaled_tail_moments([1.5, 0.5], u);
        (
            log_tail_scale(u) + three_halves.ln() - log_target,
            -1.5 * half / three_halves,
        )
    };
    // Doubling reaches u = ∓∞, where g = ±∞ for a finite target, within
    // 1100 steps; the loops end long before (F_{3/2}(u) ≈ |u|^{3/2} for
    // u ≪ 0 and ≈ e^{−u²/2} for u ≫ 0).
    let (mut lo, mut hi) = (-1.0_f64, 1.0_f64);
    for _ in 0..1100 {
        if residual(lo).0 >= 0.0 {
            break;
        }
        hi = lo;
        lo *= 2.0;
    }
    for _ in 0..1100 {
        if residual(hi).0 <= 0.0 {
            break;
        }
        lo = hi;
        hi *= 2.0;
    }
    let mut u = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (g, slope) = residual(u);
        if g == 0.0 {
            return u;
        }
        if g > 0.0 {
            lo = u;
        } else {
            hi = u;
        }
        let newton = u - g / slope;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let converged = (next - u).abs() <= 1e-15 * u.abs().max(1.0);
        u = next;
        if converged || hi - lo <= 1e-15 * lo.abs().max(hi.abs()).max(1.0) {
            break;
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    fn relative_error(value: f64, reference: f64) -> f64 {
        ((value - reference) / reference).abs()
    }

    /// u from `from` to `to` in steps of `step`.
    fn grid(from: f64, to: f64, step: f64) -> impl Iterator<Item = f64> {
        let n = ((to - from) / step).round() as usize;
        (0..=n).map(move |i| from + step * i as f64)
    }

    #[test]
    fn gauss_legendre_rule_integrates_polynomials_of_degree_up_to_2n_minus_1() {
        let rule = gauss_legendre();
        for degree in 0..2 * NODES {
            let sum: f64 = rule
                .nodes
                .iter()
                .zip(&rule.weights)
                .map(|(x, w)| w * x.powi(degree as i32))
                .sum();
            // ∫_{−1}^{1} x^j dx = 2/(j + 1) for even j, 0 for odd j
            let exact = if degree % 2 == 0 {
                2.0 / (degree as f64 + 1.0)
            } else {
                0.0
            };
            assert!(
                (sum - exact).abs() < 1e-15,
                "degree {degree}: {sum} vs {exact}"
            );
        }
    }

    #[test]
    fn normal_pdf_is_accurate_far_in_the_tail() {
        // φ(37) = e^{−684.5}/√(2π), from mpmath at 40 digits
        assert!(relative_error(normal_pdf(37.0), 2.1200065515246056e-298) < 4e-16);
        assert!(relative_error(normal_pdf(-1.5), 0.12951759566589174) < 4e-16);
        assert_eq!(normal_pdf(0.0), FRAC_1_SQRT_TAU);
        assert_eq!(normal_pdf(41.0), 0.0);
        assert!(normal_pdf(f64::NAN).is_nan());
    }

    #[test]
    fn quadrature_matches_the_closed_forms_for_k_0_and_1() {
        for u in grid(-8.0, 10.0, 0.05).chain([-1e-9, 1e-9, 1.999_999, 2.0]) {
            for k in [0.0, 1.0] {
                let closed = gaussian_tail_moment(k, u);
                let quadrature = tail_moment_by_quadrature(k, u);
                assert!(
                    relative_error(quadrature, closed) < 1e-11,
                    "F_{k}({u}): quadrature {quadrature:e}, closed form {closed:e}"
                );
            }
        }
    }

    #[test]
    fn three_halves_moment_matches_brute_force_simpson_in_t() {
        // Composite Simpson in t itself over [0, T], T where φ(u + t) is
        // below e^{−72}; the t^{3/2} cusp at t = 0 limits it to O(h^{5/2}).
        let simpson = |u: f64| {
            let t_max = (-u).max(0.0) + 12.0;
            let n = 2_000_000;
            let h = t_max / n as f64;
            let f = |t: f64| t.powf(1.5) * (-0.5 * (u + t) * (u + t)).exp() * FRAC_1_SQRT_TAU;
            let inner: f64 = (1..n)
                .map(|i| f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
                .sum();
            (f(0.0) + inner + f(t_max)) * h / 3.0
        };
        for u in [-8.0, -4.0, -1.5, -0.3, 0.0, 0.7, 2.0, 5.0, 10.0] {
            let brute = simpson(u);
            let value = gaussian_tail_moment(1.5, u);
            assert!(
                relative_error(value, brute) < 1e-7,
                "F_3/2({u}) = {value:e}, Simpson {brute:e}"
            );
        }
    }

    #[test]
    fn tail_moments_match_the_parabolic_cylinder_function() {
        // F_k(u) = Γ(k+1) e^{−u²/4} D_{−k−1}(u)/√(2π) (DLMF 12.5.1 with
        // U(a, z) = D_{−a−1/2}(z)), evaluated with mpmath at 60 digits.
        let reference = [
            (-30.0, 164.38524685803847, 5.476464054531876),
            (-8.0, 22.760397260058124, 2.8228183535700078),
            (-2.0, 3.111292885687599, 1.3566405981393808),
            (0.0, 0.4300199936622598, 0.4110894793312293),
            (1.0, 0.07566817739097507, 0.1041536753078577),
            (3.0, 0.0002639675542694673, 0.0006418504393485508),
            (10.0, 3.101206508673169e-25, 2.117479299141611e-24),
            (25.0, 3.2333284049509563e-140, 5.410317004946347e-139),
            (35.0, 7.202113670874815e-271, 1.6839130324341382e-269),
        ];
        for (u, three_halves, half) in reference {
            for (k, exact) in [(1.5, three_halves), (0.5, half)] {
                let value = gaussian_tail_moment(k, u);
                assert!(
                    relative_error(value, exact) < 1e-13,
                    "F_{k}({u}) = {value:e}, reference {exact:e}"
                );
            }
        }
    }

    #[test]
    fn tail_moments_obey_the_recurrence_and_the_derivative_rule() {
        // Integrating by parts with φ'(v) = −v φ(v):
        // u F_k + F_{k+1} = ∫ t^k (u + t) φ(u + t) dt = k F_{k−1}, so
        // F_{5/2} = (3/2) F_{1/2} − u F_{3/2}; and ∂F_k/∂u = −k F_{k−1}.
        for u in grid(-8.0, 4.0, 0.25) {
            let [f52, f32, f12] = [2.5, 1.5, 0.5].map(|k| gaussian_tail_moment(k, u));
            let right = 1.5 * f12 - u * f32;
            let scale = 1.5 * f12 + u.abs() * f32;
            assert!(
                (f52 - right).abs() < 1e-13 * scale,
                "u = {u}: F_5/2 = {f52:e}, (3/2) F_1/2 − u F_3/2 = {right:e}"
            );
            let h = 1e-4;
            let derivative =
                (gaussian_tail_moment(1.5, u + h) - gaussian_tail_moment(1.5, u - h)) / (2.0 * h);
            assert!(
                relative_error(derivative, -1.5 * f12) < 1e-7,
                "u = {u}: ∂F_3/2/∂u ≈ {derivative:e}, −(3/2) F_1/2 = {:e}",
                -1.5 * f12
            );
        }
    }

    #[test]
    fn tail_moments_at_the_ends_of_the_range() {
        for k in [0.0, 0.5, 1.0, 1.5] {
            assert_eq!(gaussian_tail_moment(k, 40.0), 0.0, "k = {k}");
            assert_eq!(gaussian_tail_moment(k, f64::INFINITY), 0.0, "k = {k}");
            assert!(gaussian_tail_moment(k, f64::NAN).is_nan(), "k = {k}");
            // far on the negative side F_k(u) = E[(X − u)^k] → |u|^k (1 + …)
            let value = gaussian_tail_moment(k, -1e4);
            assert!(
                relative_error(value, 1e4f64.powf(k)) < 1e-7,
                "k = {k}: {value}"
            );
            assert!(gaussian_tail_moment(k, 37.0) > 0.0, "k = {k}");
        }
        assert_eq!(gaussian_tail_moment(0.0, f64::NEG_INFINITY), 1.0);
        assert_eq!(gaussian_tail_moment(1.5, f64::NEG_INFINITY), f64::INFINITY);
        assert!(gaussian_tail_moment(-0.5, 0.0).is_nan());
        assert!(gaussian_tail_moment(f64::NAN, 0.0).is_nan());
    }
}
