//! The Ogden model in the Abaqus convention (the paper's Eq. 1):
//! W = Σ 2 μ_i / α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), μ0 = Σ μ_i.

use crate::compensated_sum::CompensatedSum;
use crate::model::DruckerStiffness;
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

    /// s_j = Σ_i μ_i λ_j^α_i for j = 1, 2, 3, Pa, each summed without
    /// rounding beyond that of the powers (the accuracy is discussed at
    /// `drucker_stiffness` in the [`Hyperelastic`] impl below).
    fn power_sums(&self, stretches: [f64; 3]) -> [CompensatedSum; 3] {
        stretches.map(|stretch| {
            let mut s = CompensatedSum::default();
            for (mu, a) in self.terms() {
                s.add_product(mu, stretch.powf(a));
            }
            s
        })
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

    fn log_strain_hessian_pa(&self, stretches: [f64; 3]) -> [[f64; 2]; 2] {
        // Ŵ = Σ 2μ/α² (e^(α ε1) + e^(α ε2) + e^(−α (ε1 + ε2)) − 3), so
        // H11 = 2 (s1 + s3), H22 = 2 (s2 + s3), H12 = 2 s3.
        let [s1, s2, s3] = self.power_sums(stretches);
        let twice = |parts: &[&CompensatedSum]| {
            let mut h = CompensatedSum::default();
            for part in parts {
                h.add_multiple_of(2.0, part);
            }
            h.value()
        };
        let h12 = twice(&[&s3]);
        [[twice(&[&s1, &s3]), h12], [h12, twice(&[&s2, &s3])]]
    }

    /// The expanded form. With the Hessian above,
    ///
    /// det H = 4 [(s1 + s3)(s2 + s3) − s3²] = 4 (s1 s2 + s1 s3 + s2 s3),
    /// trace H = 2 (s1 + s2 + 2 s3):
    ///
    /// the s3² that dominates both products of H11 H22 − H12² cancels
    /// algebraically instead of in floating point. In equibiaxial
    /// compression at λ = 0.125, λ3 = 64 and a term with α = 16 makes s3
    /// 10²⁹ times its μ while s1 = s2 stay of the order of the other μ_i:
    /// s1 is lost in H11 = 2 (s1 + s3), and H11 H22 − H12² comes out 0 or
    /// noise where det H ≈ 8 s1 s3 > 0. If every μ_i ≥ 0 every s_j is > 0
    /// and so is every term: such a model is stable at any stretch, and is
    /// reported so.
    ///
    /// Accuracy: each s_j is a compensated sum of the exact products
    /// μ_i · λ_j^α_i, and the determinant and trace are compensated sums of
    /// the exact partial products of those (TwoSum and fused multiply–add
    /// error terms carried along), so the only error left that matters is
    /// the rounding of the powers λ_j^α_i themselves (`powf`, within about
    /// one ulp): |δs_j| ≲ u Σ_i |μ_i λ_j^α_i| (u = 2⁻⁵³), and
    /// |δdet| ≲ 4 Σ_j |s_k + s_l| |δs_j| ({j, k, l} = {1, 2, 3}). For
    /// μ_i ≥ 0 that is a few u relative. For an unconstrained fit whose μ_i
    /// cancel (±10¹⁵ Pa summing to 10⁵ Pa) the s_j themselves are that
    /// ill-conditioned, Σ |μ_i λ^α_i| / |s_j| up to 10¹², so they, and the
    /// determinant, keep about 4 to 10 digits: far from the 0 that sets the
    /// sign unless the model is at a Drucker limit, but only powers in
    /// extended precision would do better.
    fn drucker_stiffness(&self, stretches: [f64; 3]) -> DruckerStiffness {
        let [s1, s2, s3] = self.power_sums(stretches);
        let mut determinant = CompensatedSum::default();
        determinant.add_product_of(&s1, &s2);
        determinant.add_product_of(&s1, &s3);
        determinant.add_product_of(&s2, &s3);
        let mut trace = CompensatedSum::default();
        trace.add_multiple_of(2.0, &s1);
        trace.add_multiple_of(2.0, &s2);
        trace.add_multiple_of(4.0, &s3);
        DruckerStiffness {
            trace_pa: trace.value(),
            determinant_pa2: 4.0 * determinant.value(),
        }
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
