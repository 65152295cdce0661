//! The isochoric strain energy of every family of the material crate,
//! written once as a function Ψ(m₁, …, m_K) of *power traces*
//! m_k = tr C̄^(p_k) of the isochoric right Cauchy–Green tensor
//! C̄ = J^(−2/3) C (Flory's split, as Abaqus and felupe use it):
//!
//! - Ogden (Abaqus convention, the paper's Eq. 1): p_k = α_k / 2 and
//!   Ψ = Σ 2μ_k/α_k² (m_k − 3), since tr C̄^(α/2) = Σ λ̄_a^α;
//! - neo-Hookean, Mooney–Rivlin, Yeoh, Arruda–Boyce: m = (Ī1, Ī2) with
//!   p = (1, −1), since Ī2 = tr C̄⁻¹ when det C̄ = 1, and Ψ is the family's
//!   W(I1, I2) of [`hypercontact_material`].
//!
//! Ψ is generic over num-dual's [`DualNum`], so its gradient and Hessian in m
//! come from forward-mode automatic differentiation (hyper-dual numbers, one
//! evaluation per pair (k, l)) and one code path serves every family; the
//! matrix calculus from m to C is closed form in [`crate::isochoric`].

// Abaqus' five-term Arruda–Boyce series, the same C_i the material fits with.
use hypercontact_material::arruda_boyce::SERIES as ARRUDA_BOYCE_SERIES;
use hypercontact_material::{Hyperelastic, Parameter};
use num_dual::{DualNum, HyperDual64};

use crate::FemError;

/// Most power traces a family may use (an Ogden solid of up to this many
/// terms); fixed so that the constitutive routine allocates nothing.
pub const MAX_TRACES: usize = 8;

/// An isochoric strain energy Ψ(m) of power traces m_k = tr C̄^(p_k).
#[derive(Clone, Debug, PartialEq)]
pub enum IsochoricEnergy {
    /// Ψ = Σ 2μ_k/α_k² (m_k − 3), p_k = α_k / 2.
    Ogden { mu_pa: Vec<f64>, alpha: Vec<f64> },
    /// Ψ = C10 (Ī1 − 3).
    NeoHookean { c10_pa: f64 },
    /// Ψ = C10 (Ī1 − 3) + C01 (Ī2 − 3).
    MooneyRivlin { c10_pa: f64, c01_pa: f64 },
    /// Ψ = C10 x + C20 x² + C30 x³, x = Ī1 − 3.
    Yeoh {
        c10_pa: f64,
        c20_pa: f64,
        c30_pa: f64,
    },
    /// Ψ = μ Σ C_i / λm^(2i−2) (Ī1^i − 3^i), i = 1…5.
    ArrudaBoyce { mu_pa: f64, lambda_m: f64 },
}

/// Ψ and its first and second derivatives in the traces, Pa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceDerivatives {
    pub energy_pa: f64,
    pub gradient_pa: [f64; MAX_TRACES],
    pub hessian_pa: [[f64; MAX_TRACES]; MAX_TRACES],
}

impl IsochoricEnergy {
    /// The energy of a material-crate model, read from its family name and
    /// parameters (the `material` table's rows).
    pub fn from_model(model: &dyn Hyperelastic) -> Result<Self, FemError> {
        let parameters = model.parameters();
        let family = model.family();
        let get = |name: &str| -> Result<f64, FemError> {
            parameters
                .iter()
                .find(|p| p.name() == name)
                .map(|p| p.value)
                .ok_or_else(|| FemError::Material(format!("`{family}` has no parameter `{name}`")))
        };
        let energy = match family {
            "ogden" => {
                let terms = parameters
                    .iter()
                    .filter(|p| p.name().starts_with("mu_"))
                    .count();
                let by_term = |prefix: &str| -> Result<Vec<f64>, FemError> {
                    (1..=terms).map(|i| get(&format!("{prefix}_{i}"))).collect()
                };
                IsochoricEnergy::Ogden {
                    mu_pa: by_term("mu")?,
                    alpha: by_term("alpha")?,
                }
            }
            "neo-hookean" => IsochoricEnergy::NeoHookean {
                c10_pa: get("c10")?,
            },
            "mooney-rivlin" => IsochoricEnergy::MooneyRivlin {
                c10_pa: get("c10")?,
                c01_pa: get("c01")?,
            },
            "yeoh" => IsochoricEnergy::Yeoh {
                c10_pa: get("c10")?,
                c20_pa: get("c20")?,
                c30_pa: get("c30")?,
            },
            "arruda-boyce" => IsochoricEnergy::ArrudaBoyce {
                mu_pa: get("mu")?,
                lambda_m: get("lambda_m")?,
            },
            other => {
                return Err(FemError::Material(format!(
                    "model family `{other}` has no finite-strain energy here (known: ogden, \
                     neo-hookean, mooney-rivlin, yeoh, arruda-boyce)"
                )));
            }
        };
        energy.check()?;
        Ok(energy)
    }

    fn check(&self) -> Result<(), FemError> {
        let all_finite = |values: &[f64]| values.iter().all(|v| v.is_finite());
        let ok = match self {
            IsochoricEnergy::Ogden { mu_pa, alpha } => {
                if mu_pa.is_empty() || mu_pa.len() > MAX_TRACES || mu_pa.len() != alpha.len() {
                    return Err(FemError::Material(format!(
                        "an Ogden solid needs 1 to {MAX_TRACES} terms with as many μ_i as α_i, \
                         got {} and {}",
                        mu_pa.len(),
                        alpha.len()
                    )));
                }
                all_finite(mu_pa) && all_finite(alpha) && alpha.iter().all(|a| *a != 0.0)
            }
            IsochoricEnergy::NeoHookean { c10_pa } => c10_pa.is_finite(),
            IsochoricEnergy::MooneyRivlin { c10_pa, c01_pa } => all_finite(&[*c10_pa, *c01_pa]),
            IsochoricEnergy::Yeoh {
                c10_pa,
                c20_pa,
                c30_pa,
            } => all_finite(&[*c10_pa, *c20_pa, *c30_pa]),
            IsochoricEnergy::ArrudaBoyce { mu_pa, lambda_m } => {
                mu_pa.is_finite() && lambda_m.is_finite() && *lambda_m > 0.0
            }
        };
        if !ok {
            return Err(FemError::Material(format!("invalid parameters: {self:?}")));
        }
        let mu0 = self.shear_modulus_pa();
        if mu0.is_nan() || mu0 <= 0.0 {
            return Err(FemError::Material(format!(
                "the initial shear modulus μ0 = {:e} Pa must be positive",
                self.shear_modulus_pa()
            )));
        }
        Ok(())
    }

    /// The exponents p_k of the traces m_k = tr C̄^(p_k), and their number.
    pub fn powers(&self) -> ([f64; MAX_TRACES], usize) {
        let mut p = [0.0; MAX_TRACES];
        match self {
            IsochoricEnergy::Ogden { alpha, .. } => {
                for (pk, a) in p.iter_mut().zip(alpha) {
                    *pk = 0.5 * a;
                }
                (p, alpha.len())
            }
            _ => {
                p[0] = 1.0;
                p[1] = -1.0;
                (p, 2)
            }
        }
    }

    /// The initial shear modulus μ0 = 2 (∂Ψ/∂Ī1 + ∂Ψ/∂Ī2) at the reference
    /// state (for Ogden Σ μ_k), Pa: from the energy's own derivatives, so
    /// that it is μ0 for every family by one formula.
    pub fn shear_modulus_pa(&self) -> f64 {
        let (powers, count) = self.powers();
        let derivatives = self.derivatives(&[3.0; MAX_TRACES][..count], false);
        // At C̄ = I + 2ε with det C̄ = 1 (so tr ε = |ε|² to second order),
        // tr C̄^p = 3 + 2p tr ε + 2p(p − 1)|ε|² = 3 + 2p²|ε|², so
        // Ψ ≈ Σ_k Ψ_k 2p_k² |ε|², which is μ0 |ε|² of linear elasticity.
        2.0 * (0..count)
            .map(|k| derivatives.gradient_pa[k] * powers[k] * powers[k])
            .sum::<f64>()
    }

    /// Ψ at traces `m` (m.len() = [`IsochoricEnergy::powers`]' count).
    pub fn energy<D: DualNum<Primitive = f64> + Copy>(&self, m: &[D]) -> D {
        match self {
            IsochoricEnergy::Ogden { mu_pa, alpha } => mu_pa
                .iter()
                .zip(alpha)
                .zip(m)
                .map(|((mu, a), mk)| (*mk - 3.0) * (2.0 * mu / (a * a)))
                .sum(),
            IsochoricEnergy::NeoHookean { c10_pa } => (m[0] - 3.0) * *c10_pa,
            IsochoricEnergy::MooneyRivlin { c10_pa, c01_pa } => {
                (m[0] - 3.0) * *c10_pa + (m[1] - 3.0) * *c01_pa
            }
            IsochoricEnergy::Yeoh {
                c10_pa,
                c20_pa,
                c30_pa,
            } => {
                let x = m[0] - 3.0;
                x * ((x * ((x * *c30_pa) + *c20_pa)) + *c10_pa)
            }
            IsochoricEnergy::ArrudaBoyce { mu_pa, lambda_m } => {
                let beta = 1.0 / (lambda_m * lambda_m);
                let mut total = D::from(0.0);
                let mut scale = *mu_pa;
                let mut power = D::from(1.0);
                for (c, i) in ARRUDA_BOYCE_SERIES.iter().zip(1..) {
                    power *= m[0];
                    total += (power - 3f64.powi(i)) * (c * scale);
                    scale *= beta;
                }
                total
            }
        }
    }

    /// Ψ, ∂Ψ/∂m_k and (`with_hessian`, else zero) ∂²Ψ/∂m_k∂m_l at `m`.
    pub fn derivatives(&self, m: &[f64], with_hessian: bool) -> TraceDerivatives {
        match self {
            IsochoricEnergy::Ogden { mu_pa, alpha } => ogden_derivatives(mu_pa, alpha, m),
            _ => self.dual_derivatives(m, with_hessian),
        }
    }

    /// [`IsochoricEnergy::derivatives`] by hyper-dual numbers: one
    /// evaluation per pair k ≤ l, or per k.
    pub fn dual_derivatives(&self, m: &[f64], with_hessian: bool) -> TraceDerivatives {
        let count = m.len();
        let mut out = TraceDerivatives {
            energy_pa: 0.0,
            gradient_pa: [0.0; MAX_TRACES],
            hessian_pa: [[0.0; MAX_TRACES]; MAX_TRACES],
        };
        let mut seeded = [HyperDual64::from_re(0.0); MAX_TRACES];
        for k in 0..count {
            let last = if with_hessian { count } else { k + 1 };
            for l in k..last {
                for (j, s) in seeded[..count].iter_mut().enumerate() {
                    let eps1 = if j == k { 1.0 } else { 0.0 };
                    let eps2 = if j == l { 1.0 } else { 0.0 };
                    *s = HyperDual64::new(m[j], eps1, eps2, 0.0);
                }
                let value = self.energy(&seeded[..count]);
                out.energy_pa = value.re;
                out.hessian_pa[k][l] = value.eps1eps2;
                out.hessian_pa[l][k] = value.eps1eps2;
                if k == l {
                    out.gradient_pa[k] = value.eps1;
                }
            }
        }
        out
    }
}

/// Ψ of an Ogden solid is linear in its traces: the gradient is the
/// constant 2μ_k/α_k² and the Hessian zero, here in closed form (the
/// hyper-dual evaluation spent one energy per pair (k, l) to find that). The
/// sums are formed as num-dual forms them (from +0, in term order), so the
/// bits are the same as [`IsochoricEnergy::dual_derivatives`]'.
fn ogden_derivatives(mu_pa: &[f64], alpha: &[f64], m: &[f64]) -> TraceDerivatives {
    let mut out = TraceDerivatives {
        energy_pa: 0.0,
        gradient_pa: [0.0; MAX_TRACES],
        hessian_pa: [[0.0; MAX_TRACES]; MAX_TRACES],
    };
    for (k, ((mu, a), mk)) in mu_pa.iter().zip(alpha).zip(m).enumerate() {
        let coefficient = 2.0 * mu / (a * a);
        out.energy_pa += (mk - 3.0) * coefficient;
        out.gradient_pa[k] = 0.0 + coefficient;
    }
    out
}

/// The rows of a model's parameters, for messages.
pub fn describe(parameters: &[Parameter]) -> String {
    parameters
        .iter()
        .map(|p| format!("{} = {}", p.name(), p.value))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use hypercontact_material::presets::paper_epdm;
    use hypercontact_material::{ArrudaBoyce, MooneyRivlin, NeoHookean, Yeoh};

    pub(crate) fn every_family() -> Vec<Box<dyn Hyperelastic>> {
        vec![
            Box::new(paper_epdm()),
            Box::new(
                hypercontact_material::Ogden::new(
                    vec![0.63e6, 0.0012e6, -0.01e6],
                    vec![1.3, 5.0, -2.0],
                )
                .unwrap(),
            ),
            Box::new(NeoHookean::new(0.2e6).unwrap()),
            Box::new(MooneyRivlin::new(0.18e6, 0.05e6).unwrap()),
            Box::new(Yeoh::new(0.2e6, -0.01e6, 0.002e6).unwrap()),
            Box::new(ArrudaBoyce::new(0.3e6, 2.5).unwrap()),
        ]
    }

    #[test]
    fn energy_equals_the_material_crate_at_incompressible_stretches() {
        for model in every_family() {
            let energy = IsochoricEnergy::from_model(model.as_ref()).unwrap();
            let (powers, count) = energy.powers();
            for stretches in [[1.3, 0.9, 1.0 / 1.17], [0.7, 0.7, 1.0 / 0.49], [1.0; 3]] {
                let m: Vec<f64> = powers[..count]
                    .iter()
                    .map(|p| stretches.iter().map(|l: &f64| l.powf(2.0 * p)).sum())
                    .collect();
                let ours = energy.energy(&m);
                let theirs = model.energy_pa(stretches);
                let scale = model.shear_modulus_pa();
                assert!(
                    (ours - theirs).abs() <= 1e-9 * scale.max(theirs.abs()),
                    "{}: {ours} vs {theirs}",
                    model.family()
                );
            }
            let mu0 = energy.shear_modulus_pa();
            assert!(
                (mu0 / model.shear_modulus_pa() - 1.0).abs() < 1e-9,
                "{}: μ0 {mu0} vs {}",
                model.family(),
                model.shear_modulus_pa()
            );
        }
    }

    #[test]
    fn hyper_dual_derivatives_match_central_differences() {
        for model in every_family() {
            let energy = IsochoricEnergy::from_model(model.as_ref()).unwrap();
            let (_, count) = energy.powers();
            let m: Vec<f64> = (0..count).map(|k| 3.1 + 0.05 * k as f64).collect();
            let d = energy.derivatives(&m, true);
            let h = 1e-5;
            for k in 0..count {
                let shifted = |delta: f64| {
                    let mut x = m.clone();
                    x[k] += delta;
                    energy.derivatives(&x, true)
                };
                let (plus, minus) = (shifted(h), shifted(-h));
                let gradient = (plus.energy_pa - minus.energy_pa) / (2.0 * h);
                let scale = d.gradient_pa[k].abs() + model.shear_modulus_pa();
                assert!((gradient - d.gradient_pa[k]).abs() < 1e-6 * scale);
                for l in 0..count {
                    let second = (plus.gradient_pa[l] - minus.gradient_pa[l]) / (2.0 * h);
                    assert!(
                        (second - d.hessian_pa[k][l]).abs()
                            < 1e-6 * (scale + d.hessian_pa[k][l].abs())
                    );
                }
            }
        }
    }

    /// The closed-form Ogden derivatives are the hyper-dual ones, bit for
    /// bit, on the paper pipeline's fitted Ogden-6 (terms of ±1e10 Pa that
    /// cancel) and a one-term solid, near and far from the reference state.
    #[test]
    fn ogden_closed_form_is_the_hyper_dual_result_to_the_bit() {
        let paper_fit = IsochoricEnergy::Ogden {
            mu_pa: vec![
                -13044509309.24517,
                17813351253.285015,
                -10034129992.640257,
                6430021265.584249,
                -1312272874.8025985,
                149329913.8379448,
            ],
            alpha: vec![
                -0.18522899162256595,
                -0.14285866016046844,
                0.13750083541697503,
                0.37450537455814864,
                0.8469519590261161,
                1.4318589532633343,
            ],
        };
        let one_term = IsochoricEnergy::Ogden {
            mu_pa: vec![-2.5e5],
            alpha: vec![-3.0],
        };
        for energy in [paper_fit, one_term] {
            let (_, count) = energy.powers();
            for base in [3.0, 3.0 + 1e-13, 2.97, 4.5] {
                let m: Vec<f64> = (0..count).map(|k| base + 1e-3 * k as f64).collect();
                for with_hessian in [false, true] {
                    let closed = energy.derivatives(&m, with_hessian);
                    let dual = energy.dual_derivatives(&m, with_hessian);
                    let bits = |d: &TraceDerivatives| {
                        std::iter::once(d.energy_pa)
                            .chain(d.gradient_pa)
                            .chain(d.hessian_pa.into_iter().flatten())
                            .map(f64::to_bits)
                            .collect::<Vec<u64>>()
                    };
                    assert_eq!(bits(&closed), bits(&dual), "m = {m:?}");
                }
            }
        }
    }

    #[test]
    fn unknown_families_and_bad_parameters_are_errors() {
        let bad = IsochoricEnergy::Ogden {
            mu_pa: vec![1.0e6; 9],
            alpha: vec![2.0; 9],
        };
        assert!(
            bad.check()
                .unwrap_err()
                .to_string()
                .contains("1 to 8 terms")
        );
        let negative = IsochoricEnergy::NeoHookean { c10_pa: -1.0 };
        assert!(negative.check().unwrap_err().to_string().contains("μ0"));
    }
}
