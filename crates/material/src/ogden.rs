//! The Ogden model in the Abaqus convention (the paper's Eq. 1):
//! W = Σ 2 μ_i / α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), μ0 = Σ μ_i.

use crate::{Hyperelastic, MaterialError, Mode, Parameter};

/// An N-term incompressible Ogden solid.
#[derive(Clone, Debug, PartialEq)]
pub struct Ogden {
    /// μ_i, Pa.
    pub mu_pa: Vec<f64>,
    /// α_i, dimensionless, non-zero.
    pub alpha: Vec<f64>,
}

impl Ogden {
    pub fn new(mu_pa: Vec<f64>, alpha: Vec<f64>) -> Result<Self, MaterialError> {
        if mu_pa.len() != alpha.len() || mu_pa.is_empty() {
            return Err(MaterialError::Invalid(format!(
                "Ogden needs as many μ_i as α_i (at least one), got {} and {}",
                mu_pa.len(),
                alpha.len()
            )));
        }
        if let Some(i) = alpha.iter().position(|a| *a == 0.0 || !a.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Ogden α_{} must be finite and non-zero",
                i + 1
            )));
        }
        if let Some(i) = mu_pa.iter().position(|m| !m.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Ogden μ_{} is not finite",
                i + 1
            )));
        }
        Ok(Self { mu_pa, alpha })
    }

    pub fn terms(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.mu_pa.iter().copied().zip(self.alpha.iter().copied())
    }
}

/// The exponent c of the lateral stretch λ^(−c) that carries the load in
/// each test: T = Σ 2μ/α (λ^(α−1) − λ^(−cα−1)).
pub(crate) fn lateral_power(mode: Mode) -> f64 {
    match mode {
        Mode::Uniaxial => 0.5,
        Mode::Planar => 1.0,
        Mode::Equibiaxial => 2.0,
    }
}

impl Hyperelastic for Ogden {
    fn family(&self) -> &'static str {
        "ogden"
    }

    fn shear_modulus_pa(&self) -> f64 {
        self.mu_pa.iter().sum()
    }

    fn energy_pa(&self, [l1, l2, l3]: [f64; 3]) -> f64 {
        self.terms()
            .map(|(mu, a)| 2.0 * mu / (a * a) * (l1.powf(a) + l2.powf(a) + l3.powf(a) - 3.0))
            .sum()
    }

    fn nominal_stress_pa(&self, mode: Mode, stretch: f64) -> f64 {
        let c = lateral_power(mode);
        self.terms()
            .map(|(mu, a)| 2.0 * mu / a * (stretch.powf(a - 1.0) - stretch.powf(-c * a - 1.0)))
            .sum()
    }

    fn nominal_stress_slope_pa(&self, mode: Mode, stretch: f64) -> f64 {
        let c = lateral_power(mode);
        self.terms()
            .map(|(mu, a)| {
                2.0 * mu / a
                    * ((a - 1.0) * stretch.powf(a - 2.0)
                        + (c * a + 1.0) * stretch.powf(-c * a - 2.0))
            })
            .sum()
    }

    fn log_strain_hessian_pa(&self, [l1, l2, l3]: [f64; 3]) -> [[f64; 2]; 2] {
        // Ŵ = Σ 2μ/α² (e^(α ε1) + e^(α ε2) + e^(−α (ε1 + ε2)) − 3).
        let mut h = [[0.0; 2]; 2];
        for (mu, a) in self.terms() {
            let p3 = l3.powf(a);
            h[0][0] += 2.0 * mu * (l1.powf(a) + p3);
            h[1][1] += 2.0 * mu * (l2.powf(a) + p3);
            h[0][1] += 2.0 * mu * p3;
        }
        h[1][0] = h[0][1];
        h
    }

    fn parameters(&self) -> Vec<Parameter> {
        let mu = (self.mu_pa.iter().zip(1..)).map(|(&m, i)| Parameter::modulus("mu", m).of_term(i));
        let alpha =
            (self.alpha.iter().zip(1..)).map(|(&a, i)| Parameter::number("alpha", a).of_term(i));
        mu.chain(alpha).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets::paper_epdm;

    /// dW/dλ along the test path by central differences, divided by the
    /// number of loaded directions: the nominal stress, independently.
    fn stress_from_energy(m: &dyn Hyperelastic, mode: Mode, stretch: f64) -> f64 {
        let h = 1e-6 * stretch;
        let w = |l: f64| m.energy_pa(mode.stretches(l));
        (w(stretch + h) - w(stretch - h)) / (2.0 * h) / mode.loaded_directions()
    }

    #[test]
    fn stresses_match_the_derivative_of_the_energy() {
        let m = Ogden::new(vec![0.63e6, 0.0012e6, -0.01e6], vec![1.3, 5.0, -2.0]).unwrap();
        for mode in Mode::ALL {
            for stretch in [0.5, 0.9, 1.0, 1.3, 2.0, 3.5] {
                let exact = m.nominal_stress_pa(mode, stretch);
                let fd = stress_from_energy(&m, mode, stretch);
                let scale = m.shear_modulus_pa() + exact.abs();
                assert!(
                    (exact - fd).abs() <= 1e-8 * scale,
                    "{mode} λ={stretch}: {exact} vs {fd}"
                );
                let h = 1e-6;
                let slope_fd = (m.nominal_stress_pa(mode, stretch + h)
                    - m.nominal_stress_pa(mode, stretch - h))
                    / (2.0 * h);
                let slope = m.nominal_stress_slope_pa(mode, stretch);
                assert!((slope - slope_fd).abs() <= 1e-5 * slope.abs().max(1.0));
            }
        }
    }

    #[test]
    fn paper_preset_has_the_published_moduli() {
        let m = paper_epdm();
        // Table 1 sums to μ0 = 1.79 MPa; E0 = 3 μ0 = 5.37 MPa.
        assert!((m.shear_modulus_pa() - 1.79e6).abs() < 0.005e6);
        assert!((crate::youngs_modulus_pa(m.shear_modulus_pa(), 0.5) - 5.37e6).abs() < 0.015e6);
        // Small-strain slopes: UT 3 μ0, BT 6 μ0.
        let mu0 = m.shear_modulus_pa();
        let ut = m.nominal_stress_slope_pa(Mode::Uniaxial, 1.0);
        let bt = m.nominal_stress_slope_pa(Mode::Equibiaxial, 1.0);
        assert!((ut / mu0 - 3.0).abs() < 1e-9, "{}", ut / mu0);
        assert!((bt / mu0 - 6.0).abs() < 1e-9, "{}", bt / mu0);
    }

    #[test]
    fn drucker_hessian_and_small_strain_limits() {
        let m = Ogden::new(vec![0.63e6, 0.0012e6, -0.01e6], vec![1.3, 5.0, -2.0]).unwrap();
        crate::invariants::tests::check_against_energy(&m);
        crate::invariants::tests::check_small_strain(&m);
    }

    #[test]
    fn parameters_know_their_term_and_unit() {
        let m = Ogden::new(vec![0.63e6, 0.0012e6], vec![1.3, 5.0]).unwrap();
        let p = m.parameters();
        let names: Vec<String> = p.iter().map(Parameter::name).collect();
        assert_eq!(names, ["mu_1", "mu_2", "alpha_1", "alpha_2"]);
        let terms: Vec<Option<usize>> = p.iter().map(|p| p.term).collect();
        assert_eq!(terms, [Some(1), Some(2), Some(1), Some(2)]);
        assert_eq!(p[1].unit, crate::ParamUnit::Pa);
        assert_eq!(p[3].unit, crate::ParamUnit::One);
        assert_eq!(p[3].value, 5.0);
    }

    #[test]
    fn zero_alpha_is_rejected() {
        assert!(Ogden::new(vec![1.0], vec![0.0]).is_err());
        assert!(Ogden::new(vec![1.0, 2.0], vec![1.0]).is_err());
    }
}
