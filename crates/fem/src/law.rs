//! The material law of the element: a nearly incompressible solid whose
//! energy is split (Flory 1961; Simo, Taylor & Pister 1985) into an
//! isochoric part W(F) and a volumetric part U(θ) = κ/2 (θ − 1)² of a
//! volume ratio θ that the element treats as one constant per element
//! ([`crate::hexahedron`]): the form felupe's `SolidBodyNearlyIncompressible`
//! and Abaqus' hybrid elements use.
//!
//! - [`Law::Hyperelastic`]: finite strain, any family of the material crate
//!   ([`crate::energy`], [`crate::isochoric`]); the volume ratio is
//!   J = det F.
//! - [`Law::LinearElastic`]: small strain, W = μ |dev ε|², ε = sym(F − I),
//!   and "J" = 1 + tr(F − I): linear elasticity with shear modulus μ and bulk
//!   modulus κ, for checks against linear theory (Westergaard).

use crate::FemError;
use crate::energy::IsochoricEnergy;
use crate::isochoric::{self, Response};
use crate::tensor::{Mat3, cofactor, det};

/// The bulk modulus as a multiple of μ0 unless told otherwise (the issue's
/// default; ν = 0.4999 for a linear solid).
pub const DEFAULT_BULK_RATIO: f64 = 5000.0;

/// A material law for the element.
#[derive(Clone, Debug, PartialEq)]
pub enum Law {
    /// Finite-strain hyperelasticity.
    Hyperelastic {
        energy: IsochoricEnergy,
        bulk_modulus_pa: f64,
    },
    /// Small-strain linear elasticity.
    LinearElastic {
        shear_modulus_pa: f64,
        bulk_modulus_pa: f64,
    },
}

/// The volume ratio at a point and its first and second derivatives in F
/// (second as ∂²J/∂F_iI∂F_jJ contracted with two gradients, see
/// [`Law::volume_ratio`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeRatio {
    pub value: f64,
    /// ∂J/∂F.
    pub gradient: Mat3,
    /// Whether J is det F (true) or linear in F (false, no second
    /// derivative).
    pub finite: bool,
}

impl Law {
    /// A hyperelastic law with bulk modulus `bulk_ratio` × μ0.
    pub fn hyperelastic(
        model: &dyn hypercontact_material::Hyperelastic,
        bulk_ratio: f64,
    ) -> Result<Self, FemError> {
        let energy = IsochoricEnergy::from_model(model)?;
        check_bulk_ratio(bulk_ratio)?;
        Ok(Law::Hyperelastic {
            bulk_modulus_pa: bulk_ratio * energy.shear_modulus_pa(),
            energy,
        })
    }

    /// A linear-elastic law with shear modulus μ and bulk modulus
    /// `bulk_ratio` × μ.
    pub fn linear_elastic(shear_modulus_pa: f64, bulk_ratio: f64) -> Result<Self, FemError> {
        check_bulk_ratio(bulk_ratio)?;
        if !(shear_modulus_pa > 0.0 && shear_modulus_pa.is_finite()) {
            return Err(FemError::Material(format!(
                "the shear modulus must be positive and finite, got {shear_modulus_pa:e} Pa"
            )));
        }
        Ok(Law::LinearElastic {
            shear_modulus_pa,
            bulk_modulus_pa: bulk_ratio * shear_modulus_pa,
        })
    }

    /// μ0, Pa.
    pub fn shear_modulus_pa(&self) -> f64 {
        match self {
            Law::Hyperelastic { energy, .. } => energy.shear_modulus_pa(),
            Law::LinearElastic {
                shear_modulus_pa, ..
            } => *shear_modulus_pa,
        }
    }

    /// κ, Pa.
    pub fn bulk_modulus_pa(&self) -> f64 {
        match self {
            Law::Hyperelastic {
                bulk_modulus_pa, ..
            }
            | Law::LinearElastic {
                bulk_modulus_pa, ..
            } => *bulk_modulus_pa,
        }
    }

    /// The small-strain plane-strain modulus E* = E/(1 − ν²) = 2μ/(1 − ν)
    /// of the linearised law, with ν = (3κ − 2μ)/(2(3κ + μ)), Pa.
    pub fn plane_strain_modulus_pa(&self) -> f64 {
        let (mu, kappa) = (self.shear_modulus_pa(), self.bulk_modulus_pa());
        let nu = (3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu));
        2.0 * mu / (1.0 - nu)
    }

    /// The isochoric W, P and (`with_tangent`) A at F; `None` at an
    /// inverted point.
    pub fn isochoric(&self, f: &Mat3, with_tangent: bool) -> Option<Response> {
        match self {
            Law::Hyperelastic { energy, .. } => isochoric::response(energy, f, with_tangent),
            Law::LinearElastic {
                shear_modulus_pa, ..
            } => Some(linear_isochoric(*shear_modulus_pa, f)),
        }
    }

    /// The pointwise volume ratio and its gradient in F.
    pub fn volume_ratio(&self, f: &Mat3) -> VolumeRatio {
        match self {
            Law::Hyperelastic { .. } => VolumeRatio {
                value: det(f),
                gradient: cofactor(f),
                finite: true,
            },
            Law::LinearElastic { .. } => VolumeRatio {
                value: f[0][0] + f[1][1] + f[2][2] - 2.0,
                gradient: crate::tensor::IDENTITY,
                finite: false,
            },
        }
    }

    /// U(θ) = κ/2 (θ − 1)², U′ (the pressure) and U″.
    pub fn volumetric(&self, theta: f64) -> (f64, f64, f64) {
        let kappa = self.bulk_modulus_pa();
        let d = theta - 1.0;
        (0.5 * kappa * d * d, kappa * d, kappa)
    }
}

fn check_bulk_ratio(bulk_ratio: f64) -> Result<(), FemError> {
    if bulk_ratio > 0.0 && bulk_ratio.is_finite() {
        Ok(())
    } else {
        Err(FemError::Material(format!(
            "bulk_ratio must be positive and finite, got {bulk_ratio}"
        )))
    }
}

/// W = μ |dev ε|², P = 2μ dev ε, A = μ (δ_ij δ_IJ + δ_iJ δ_jI) − (2μ/3) δ_iI δ_jJ.
fn linear_isochoric(mu: f64, f: &Mat3) -> Response {
    let mut strain = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let identity = if i == j { 1.0 } else { 0.0 };
            strain[i][j] = 0.5 * (f[i][j] + f[j][i]) - identity;
        }
    }
    let mean = (strain[0][0] + strain[1][1] + strain[2][2]) / 3.0;
    let mut stress = [[0.0; 3]; 3];
    let mut energy = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let deviator = strain[i][j] - if i == j { mean } else { 0.0 };
            stress[i][j] = 2.0 * mu * deviator;
            energy += mu * deviator * deviator;
        }
    }
    let mut tangent = [[0.0; 9]; 9];
    let delta = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
    for (iu, row) in tangent.iter_mut().enumerate() {
        for (ju, entry) in row.iter_mut().enumerate() {
            let (i, big_i, j, big_j) = (iu / 3, iu % 3, ju / 3, ju % 3);
            *entry = mu * (delta(i, j) * delta(big_i, big_j) + delta(i, big_j) * delta(j, big_i))
                - 2.0 * mu / 3.0 * delta(i, big_i) * delta(j, big_j);
        }
    }
    Response {
        energy_pa: energy,
        stress_pa: stress,
        tangent_pa: tangent,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_modulus_is_four_mu_when_incompressible() {
        let law = Law::linear_elastic(1.0e6, 1e12).unwrap();
        assert!((law.plane_strain_modulus_pa() / 4.0e6 - 1.0).abs() < 1e-11);
        // ν = 1/4 at κ = 5μ/3: E* = 2μ/(3/4).
        let law = Law::linear_elastic(1.0e6, 5.0 / 3.0).unwrap();
        assert!((law.plane_strain_modulus_pa() / (2.0e6 / 0.75) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn linear_stress_is_the_derivative_of_its_energy() {
        let law = Law::linear_elastic(1.0e6, 5000.0).unwrap();
        let f = [
            [1.001, 0.002, 0.0],
            [-0.001, 0.999, 0.0005],
            [0.0003, 0.0, 1.0002],
        ];
        let r = law.isochoric(&f, true).unwrap();
        let h = 1e-7;
        for iu in 0..9 {
            let mut plus = f;
            let mut minus = f;
            plus[iu / 3][iu % 3] += h;
            minus[iu / 3][iu % 3] -= h;
            let fd = (law.isochoric(&plus, true).unwrap().energy_pa
                - law.isochoric(&minus, true).unwrap().energy_pa)
                / (2.0 * h);
            assert!(
                (fd - r.stress_pa[iu / 3][iu % 3]).abs() < 1e-3,
                "{iu}: {fd}"
            );
        }
    }

    #[test]
    fn bad_moduli_are_errors() {
        assert!(Law::linear_elastic(-1.0, 10.0).is_err());
        assert!(Law::linear_elastic(1.0, f64::NAN).is_err());
    }
}
