//! Persson's theory of contact between a rigid, randomly rough surface and an
//! elastic half-space, from the height spectrum alone.
//!
//! Persson (J. Chem. Phys. 115, 3840, 2001) follows the distribution of
//! contact stress as the magnification ζ = q/q0 grows: a diffusion in stress
//! with "time" V(q) = (π/2) E*² ∫_{q0}^{q} q'³ C(q') dq' (the variance of the
//! stress under full contact) and an absorbing boundary at zero stress. The
//! contact area at magnification q is then
//!
//!   P(q) = A(q)/A0 = erf(p̄ / √(2 V(q))),
//!
//! and A/A0 = P(q1) at the largest wavevector. V(q1) = E*² h'rms² / 4, so at
//! small load A/A0 ≈ √(8/π) p̄/(E* h'rms): κ = 1.596.
//!
//! Yang & Persson (J. Phys.: Condens. Matter 20, 215214, 2008) correct the
//! elastic energy for partial contact with S(q) = γ + (1 − γ) P(q)², which
//! they also let slow the diffusion: the stress variance grows as
//! dV_p = S(P) dV, P = erf(p̄/√(2 V_p)), marched from q0 (where P = 1) to q1.
//! With γ ≈ 0.42–0.45 (fitted to numerical contact mechanics) this raises
//! the small-load area by 1/√γ: κ → 1.596/√γ.
//!
//! The march is done here in the reduced variables x = V_p/p̄², y = V/p̄²,
//! dx/dy = S(erf(1/√(2x))), with classical Runge–Kutta steps no longer than
//! 5 % of x (or 10⁻³), so its accuracy does not depend on how finely the
//! spectrum is tabulated; the energy integral below is summed on the same
//! steps (trapezoid in V, q²C dq spread evenly in V over each ≤ 2 % step in
//! q), which resolves the fall of P(q) from 1 however narrow it is at small
//! load. Between tabulated points C is a power law.
//!
//! Mean interfacial separation (Persson, PRL 99, 125502, 2007): the applied
//! pressure is the derivative of the elastic energy stored at the interface
//! with respect to the separation, p̄ = −dU_el/dū, with
//!
//!   U_el/A0 = (π/2) E* ∫ q² C(q) P(q) S(q) dq,
//!
//! S = 1 for the original theory and γ + (1 − γ)P² for the corrected one;
//! ū → 0 at full contact. Hence ū(p̄) = ∫_{p̄}^∞ (1/p) dU_el/dp dp, which is
//! evaluated as ∫_{t}^∞ (U(t') − U(t)) e^{−t'} dt' in t = ln(p̄/E*), every
//! term non-negative, on a grid in t of spacing ≤ 0.01 with U piecewise
//! linear in t, up to the load that flattens every wavelength.
//!
//! All pressures here are p̄/E* (dimensionless); energies U/(E* A0) in m.

use libm::erf;

use crate::spectrum::Spectrum;

/// Which form of the theory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// Persson 2001: free diffusion of the stress, S = 1
    Original,
    /// Yang & Persson 2008: S = γ + (1 − γ) P² slows the diffusion and weights the energy
    YangPersson { gamma: f64 },
}

impl Variant {
    /// S(P).
    fn factor(self, area_fraction: f64) -> f64 {
        match self {
            Variant::Original => 1.0,
            Variant::YangPersson { gamma } => gamma + (1.0 - gamma) * area_fraction * area_fraction,
        }
    }
}

/// The theory on one spectrum.
#[derive(Clone, Debug)]
pub struct Persson {
    variant: Variant,
    /// Nodes in q (rad/m): the spectrum's points, each piece cut into steps
    /// of at most 2 % in q.
    q_per_m: Vec<f64>,
    /// V/E*² at each node: (π/2) ∫_{q0}^{q} q³ C dq, m⁰.
    variance: Vec<f64>,
    /// (π/2) ∫ q² C dq over each step between nodes, m.
    energy_weight_m: Vec<f64>,
}

/// The state after marching to the largest wavevector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State {
    /// A/A0 at q1
    pub area_fraction: f64,
    /// U_el/(E* A0), m
    pub energy_m: f64,
}

/// One point of the load–area–separation curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerssonPoint {
    /// p̄/E*
    pub unit_pressure: f64,
    pub area_fraction: f64,
    /// ū, m
    pub mean_separation_m: f64,
}

/// Largest step of the march in q, as a ratio.
const Q_STEP: f64 = 1.02;
/// Largest step in ln(p̄/E*) of the separation integral.
const T_STEP: f64 = 0.01;
/// erf(5.5) = 1 − 7·10⁻¹⁵: at p̄ = 5.5 √(2V) every wavelength is flat.
const FULL_CONTACT: f64 = 5.5;

impl Persson {
    pub fn new(spectrum: &Spectrum, variant: Variant) -> Self {
        let q = spectrum.q_per_m();
        let mut nodes = vec![q[0]];
        for pair in q.windows(2) {
            let steps = ((pair[1] / pair[0]).ln() / Q_STEP.ln()).ceil().max(1.0) as usize;
            for k in 1..=steps {
                nodes.push(if k == steps {
                    pair[1]
                } else {
                    pair[0] * (pair[1] / pair[0]).powf(k as f64 / steps as f64)
                });
            }
        }
        let half_pi = 0.5 * std::f64::consts::PI;
        let mut variance = vec![0.0];
        let mut energy_weight_m = Vec::with_capacity(nodes.len() - 1);
        for pair in nodes.windows(2) {
            let last = variance[variance.len() - 1];
            variance.push(last + half_pi * spectrum.integral_between(3.0, pair[0], pair[1]));
            energy_weight_m.push(half_pi * spectrum.integral_between(2.0, pair[0], pair[1]));
        }
        Self {
            variant,
            q_per_m: nodes,
            variance,
            energy_weight_m,
        }
    }

    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// V(q1)/E*² = h'rms²/4.
    pub fn variance(&self) -> f64 {
        self.variance[self.variance.len() - 1]
    }

    /// The march from q0 to q1 at p̄/E* = `unit_pressure` (> 0).
    pub fn march(&self, unit_pressure: f64) -> State {
        self.march_with(unit_pressure, &mut |_, _| {})
    }

    /// P(q) at every node of the march (for inspection and tests).
    pub fn area_profile(&self, unit_pressure: f64) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.q_per_m.len());
        self.march_with(unit_pressure, &mut |q, p| out.push((q, p)));
        out
    }

    fn march_with(&self, unit_pressure: f64, visit: &mut dyn FnMut(f64, f64)) -> State {
        let p2 = unit_pressure * unit_pressure;
        let area = |x: f64| {
            if x > 0.0 {
                erf(1.0 / (2.0 * x).sqrt())
            } else {
                1.0
            }
        };
        let rate = |x: f64| self.variant.factor(area(x));
        let weight = |p: f64| p * self.variant.factor(p);
        let (mut x, mut y): (f64, f64) = (0.0, 0.0);
        let mut w = weight(1.0);
        let mut energy = 0.0;
        visit(self.q_per_m[0], 1.0);
        for (j, pair) in self.variance.windows(2).enumerate() {
            let (y0, target) = (pair[0] / p2, pair[1] / p2);
            // Energy per unit of y over the step (q varies by ≤ 2 % in it).
            let density = self.energy_weight_m[j] / (target - y0);
            while y < target {
                // Steps ≤ 5 % of x; S is 1 to 10⁻¹² below x = 0.02 (A = erf(5)).
                let remaining = target - y;
                let h = remaining.min(0.05 * x.max(0.02));
                x += match self.variant {
                    Variant::Original => h,
                    Variant::YangPersson { .. } => {
                        let k1 = rate(x);
                        let k2 = rate(x + 0.5 * h * k1);
                        let k3 = rate(x + 0.5 * h * k2);
                        let k4 = rate(x + h * k3);
                        h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
                    }
                };
                y = if h == remaining { target } else { y + h };
                let w_next = weight(area(x));
                energy += density * h * 0.5 * (w + w_next);
                w = w_next;
            }
            visit(self.q_per_m[j + 1], area(x));
        }
        State {
            area_fraction: area(x),
            energy_m: energy,
        }
    }

    /// A/A0 at p̄/E* (0 at no load).
    pub fn area_fraction(&self, unit_pressure: f64) -> f64 {
        if unit_pressure > 0.0 {
            self.march(unit_pressure).area_fraction
        } else {
            0.0
        }
    }

    /// A/A0 and ū at each of `unit_pressures` (ascending, > 0).
    pub fn curve(&self, unit_pressures: &[f64]) -> Vec<PerssonPoint> {
        assert!(unit_pressures.windows(2).all(|w| w[0] < w[1]));
        let Some(&first) = unit_pressures.first() else {
            return Vec::new();
        };
        assert!(first > 0.0);
        // Grid in t = ln(p̄/E*): each row interval cut into steps ≤ T_STEP,
        // then on to full contact.
        let t_rows: Vec<f64> = unit_pressures.iter().map(|p| p.ln()).collect();
        let t_full = (FULL_CONTACT * (2.0 * self.variance()).sqrt()).ln();
        let mut t = vec![t_rows[0]];
        let mut row_node = vec![0];
        let extend_to = |t: &mut Vec<f64>, end: f64| {
            let start = t[t.len() - 1];
            let steps = ((end - start) / T_STEP).ceil().max(1.0) as usize;
            for k in 1..=steps {
                t.push(if k == steps {
                    end
                } else {
                    start + (end - start) * k as f64 / steps as f64
                });
            }
        };
        for &tr in &t_rows[1..] {
            extend_to(&mut t, tr);
            row_node.push(t.len() - 1);
        }
        if t_full > t[t.len() - 1] {
            extend_to(&mut t, t_full);
        }
        let states: Vec<State> = t.iter().map(|t| self.march(t.exp())).collect();
        let energy: Vec<f64> = states.iter().map(|s| s.energy_m).collect();
        row_node
            .iter()
            .zip(unit_pressures)
            .map(|(&r, &unit_pressure)| PerssonPoint {
                unit_pressure,
                area_fraction: states[r].area_fraction,
                mean_separation_m: separation_from(&t[r..], &energy[r..]),
            })
            .collect()
    }
}

impl crate::curve::Theory for Persson {
    fn area_fraction(&self, unit_pressure: f64) -> f64 {
        Persson::area_fraction(self, unit_pressure)
    }
}

/// ∫_{t0}^∞ (U(t) − U(t0)) e^{−t} dt with U piecewise linear on the nodes
/// `t` (t[0] = t0) and constant beyond the last; every term ≥ 0 when U rises.
fn separation_from(t: &[f64], energy: &[f64]) -> f64 {
    let base = energy[0];
    let mut sum = 0.0;
    for j in 0..t.len() - 1 {
        let h = t[j + 1] - t[j];
        let decay = (-t[j]).exp();
        // ∫_0^h e^{−s} ds and ∫_0^h (s/h) e^{−s} ds.
        let flat = -(-h).exp_m1();
        let ramp = (flat - h * (-h).exp()) / h;
        sum += decay * ((energy[j] - base) * flat + (energy[j + 1] - energy[j]) * ramp);
    }
    let last = t.len() - 1;
    sum + (energy[last] - base) * (-t[last]).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Self-affine: C ∝ q^−(2+2H) on q0…q1, h'rms = `slope`.
    fn self_affine(h: f64, q0: f64, q1: f64, slope: f64) -> Spectrum {
        let n = 31;
        let q: Vec<f64> = (0..n)
            .map(|i| q0 * (q1 / q0).powf(i as f64 / (n - 1) as f64))
            .collect();
        let shape: Vec<f64> = q.iter().map(|q| q.powf(-2.0 - 2.0 * h)).collect();
        let unit = Spectrum::new(q.clone(), shape.clone()).unwrap();
        let scale = slope * slope / unit.moments().rms_slope().powi(2);
        Spectrum::new(q, shape.iter().map(|c| c * scale).collect()).unwrap()
    }

    #[test]
    fn the_variance_is_a_quarter_of_the_squared_slope() {
        let s = self_affine(0.7, 2e3, 2e6, 0.3);
        let p = Persson::new(&s, Variant::Original);
        assert!((p.variance() / (0.3f64.powi(2) / 4.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn original_area_is_the_closed_form() {
        let s = self_affine(0.7, 2e3, 2e6, 0.3);
        let p = Persson::new(&s, Variant::Original);
        for pu in [1e-4, 0.01, 0.1, 0.5] {
            let exact = erf(pu / (2.0 * p.variance()).sqrt());
            assert!((p.area_fraction(pu) / exact - 1.0).abs() < 1e-14, "{pu}");
        }
    }
}
