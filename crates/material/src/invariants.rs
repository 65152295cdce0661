//! Stresses, slopes and the Drucker stiffness of strain energies written in
//! the invariants I1 = Σ λ_i², I2 = Σ λ_i⁻² of an incompressible solid
//! (neo-Hookean, Mooney–Rivlin, Yeoh, Arruda–Boyce).
//!
//! Along a test path λ ↦ (λ1, λ2, λ3) the nominal stress is
//! T = (W1 dI1/dλ + W2 dI2/dλ) / k (k loaded directions), and its slope adds
//! the second derivatives of W. The Drucker stiffness is the Hessian of
//! Ŵ(ε1, ε2) = W at log strains (ε1, ε2, −ε1 − ε2), as in [`crate::stability`].

use std::fmt;

use crate::{Hyperelastic, Mode, Parameter};

/// W's partial derivatives with respect to I1 and I2 at one state, Pa.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InvariantSlopes {
    pub w1: f64,
    pub w2: f64,
    pub w11: f64,
    pub w12: f64,
    pub w22: f64,
}

/// A strain energy W(I1, I2): a family implements this and is a
/// [`Hyperelastic`] material through the blanket impl below, with stresses
/// and Drucker stiffness in closed form from the invariant derivatives.
pub trait InvariantEnergy: fmt::Debug + Send + Sync {
    /// W(I1, I2), Pa.
    fn energy_at(&self, i1: f64, i2: f64) -> f64;
    /// First and second partial derivatives of W, Pa.
    fn slopes_at(&self, i1: f64, i2: f64) -> InvariantSlopes;
    /// The family's name in the `material` table.
    fn family_name(&self) -> &'static str;
    /// Initial shear modulus μ0, Pa.
    fn initial_shear_modulus_pa(&self) -> f64;
    /// The parameters in SI units, in the order of the `material` table.
    fn named_parameters(&self) -> Vec<Parameter>;
}

impl<T: InvariantEnergy> Hyperelastic for T {
    fn family(&self) -> &'static str {
        self.family_name()
    }

    fn shear_modulus_pa(&self) -> f64 {
        self.initial_shear_modulus_pa()
    }

    fn energy_pa(&self, stretches: [f64; 3]) -> f64 {
        let (i1, i2) = invariants(stretches);
        self.energy_at(i1, i2)
    }

    fn nominal_stress_pa(&self, mode: Mode, stretch: f64) -> f64 {
        nominal_stress(self, mode, stretch)
    }

    fn nominal_stress_slope_pa(&self, mode: Mode, stretch: f64) -> f64 {
        nominal_stress_slope(self, mode, stretch)
    }

    fn parameters(&self) -> Vec<Parameter> {
        self.named_parameters()
    }

    fn log_strain_hessian_pa(&self, stretches: [f64; 3]) -> [[f64; 2]; 2] {
        log_strain_hessian(self, stretches)
    }
}

/// I1 = Σ λ², I2 = Σ λ⁻².
pub fn invariants([l1, l2, l3]: [f64; 3]) -> (f64, f64) {
    (
        l1 * l1 + l2 * l2 + l3 * l3,
        1.0 / (l1 * l1) + 1.0 / (l2 * l2) + 1.0 / (l3 * l3),
    )
}

/// (I, dI/dλ, d²I/dλ²) for I1 and I2 along a test path.
fn path_invariants(mode: Mode, l: f64) -> ([f64; 3], [f64; 3]) {
    match mode {
        // (λ, λ^-½, λ^-½)
        Mode::Uniaxial => (
            [
                l * l + 2.0 / l,
                2.0 * l - 2.0 / (l * l),
                2.0 + 4.0 / l.powi(3),
            ],
            [
                2.0 * l + 1.0 / (l * l),
                2.0 - 2.0 / l.powi(3),
                6.0 / l.powi(4),
            ],
        ),
        // (λ, 1, 1/λ): I1 = I2
        Mode::Planar => {
            let i = [
                l * l + 1.0 + 1.0 / (l * l),
                2.0 * l - 2.0 / l.powi(3),
                2.0 + 6.0 / l.powi(4),
            ];
            (i, i)
        }
        // (λ, λ, λ^-2)
        Mode::Equibiaxial => (
            [
                2.0 * l * l + l.powi(-4),
                4.0 * l - 4.0 * l.powi(-5),
                4.0 + 20.0 * l.powi(-6),
            ],
            [
                2.0 / (l * l) + l.powi(4),
                -4.0 / l.powi(3) + 4.0 * l.powi(3),
                12.0 / l.powi(4) + 12.0 * l * l,
            ],
        ),
    }
}

/// Nominal stress T = dW/dλ / k along `mode`, Pa.
pub fn nominal_stress(energy: &dyn InvariantEnergy, mode: Mode, stretch: f64) -> f64 {
    let ([i1, d1, _], [i2, d2, _]) = path_invariants(mode, stretch);
    let s = energy.slopes_at(i1, i2);
    (s.w1 * d1 + s.w2 * d2) / mode.loaded_directions()
}

/// dT/dλ along `mode`, Pa.
pub fn nominal_stress_slope(energy: &dyn InvariantEnergy, mode: Mode, stretch: f64) -> f64 {
    let ([i1, d1, dd1], [i2, d2, dd2]) = path_invariants(mode, stretch);
    let s = energy.slopes_at(i1, i2);
    (s.w11 * d1 * d1 + 2.0 * s.w12 * d1 * d2 + s.w22 * d2 * d2 + s.w1 * dd1 + s.w2 * dd2)
        / mode.loaded_directions()
}

/// The Hessian of Ŵ(ε1, ε2) = W(e^ε1, e^ε2, e^(−ε1−ε2)), Pa.
pub fn log_strain_hessian(energy: &dyn InvariantEnergy, stretches: [f64; 3]) -> [[f64; 2]; 2] {
    let [l1, l2, l3] = stretches;
    let (i1, i2) = invariants(stretches);
    let s = energy.slopes_at(i1, i2);
    let (a1, a2, a3) = (l1 * l1, l2 * l2, l3 * l3);
    let (b1, b2, b3) = (1.0 / a1, 1.0 / a2, 1.0 / a3);
    // ∂I/∂ε_j and ∂²I/∂ε_j∂ε_k with ε3 = −ε1 − ε2.
    let g1 = [2.0 * (a1 - a3), 2.0 * (a2 - a3)];
    let g2 = [2.0 * (b3 - b1), 2.0 * (b3 - b2)];
    let h1 = [[4.0 * (a1 + a3), 4.0 * a3], [4.0 * a3, 4.0 * (a2 + a3)]];
    let h2 = [[4.0 * (b1 + b3), 4.0 * b3], [4.0 * b3, 4.0 * (b2 + b3)]];
    let mut h = [[0.0; 2]; 2];
    for j in 0..2 {
        for k in 0..2 {
            h[j][k] = s.w1 * h1[j][k]
                + s.w2 * h2[j][k]
                + s.w11 * g1[j] * g1[k]
                + s.w12 * (g1[j] * g2[k] + g2[j] * g1[k])
                + s.w22 * g2[j] * g2[k];
        }
    }
    h
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Checks a model's path stresses and slopes against central
    /// differences of its energy, and its Drucker Hessian against second
    /// differences of the energy in log strains.
    pub(crate) fn check_against_energy(m: &dyn crate::Hyperelastic) {
        for mode in Mode::ALL {
            for stretch in [0.4, 0.8, 1.0, 1.3, 2.0, 3.0] {
                let h = 1e-6 * stretch;
                let w = |l: f64| m.energy_pa(mode.stretches(l));
                let fd = (w(stretch + h) - w(stretch - h)) / (2.0 * h) / mode.loaded_directions();
                let exact = m.nominal_stress_pa(mode, stretch);
                let scale = m.shear_modulus_pa() + exact.abs();
                assert!(
                    (exact - fd).abs() <= 1e-7 * scale,
                    "{} {mode} λ={stretch}: {exact} vs {fd}",
                    m.family()
                );
                let slope_fd = (m.nominal_stress_pa(mode, stretch + h)
                    - m.nominal_stress_pa(mode, stretch - h))
                    / (2.0 * h);
                let slope = m.nominal_stress_slope_pa(mode, stretch);
                assert!(
                    (slope - slope_fd).abs() <= 1e-6 * (slope.abs() + m.shear_modulus_pa()),
                    "{} {mode} λ={stretch}: slope {slope} vs {slope_fd}",
                    m.family()
                );
                let hess = m.log_strain_hessian_pa(mode.stretches(stretch));
                let fd_hess =
                    crate::model::log_strain_hessian_by_differences(m, mode.stretches(stretch));
                for j in 0..2 {
                    for k in 0..2 {
                        assert!(
                            (hess[j][k] - fd_hess[j][k]).abs()
                                <= 1e-5 * (hess[j][k].abs() + m.shear_modulus_pa()),
                            "{} {mode} λ={stretch}: H[{j}][{k}] {} vs {}",
                            m.family(),
                            hess[j][k],
                            fd_hess[j][k]
                        );
                    }
                }
            }
        }
    }

    /// Small-strain limit shared by every family: UT slope 3 μ0, PT 4 μ0,
    /// BT 6 μ0 at λ = 1, and zero stress there.
    pub(crate) fn check_small_strain(m: &dyn crate::Hyperelastic) {
        let mu0 = m.shear_modulus_pa();
        for (mode, factor) in [
            (Mode::Uniaxial, 3.0),
            (Mode::Planar, 4.0),
            (Mode::Equibiaxial, 6.0),
        ] {
            let slope = m.nominal_stress_slope_pa(mode, 1.0);
            assert!(
                (slope / mu0 - factor).abs() < 1e-9,
                "{} {mode}: slope/μ0 = {}",
                m.family(),
                slope / mu0
            );
            assert!(m.nominal_stress_pa(mode, 1.0).abs() < 1e-9 * mu0);
        }
    }
}
