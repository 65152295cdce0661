//! The strain-energy interface shared by every model family.

use std::fmt;

pub use hypercontact_core::Mode;
use hypercontact_core::param::{ParamRange, TypeDoc, check_range};
use hypercontact_core::{InputPath, ParamError, ParamValue};

/// Poisson's ratio ν of the linear moduli, as a parameter: its range
/// 0 ≤ ν ≤ ½ and its usual value, ½ (incompressible, the paper's), are
/// declared here once for every stage that takes one.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct Poisson(pub f64);

impl Poisson {
    /// ½: an incompressible solid (the paper's rubber).
    pub const INCOMPRESSIBLE: Poisson = Poisson(0.5);
    const RANGE: ParamRange = ParamRange {
        lo: std::ops::Bound::Included(0.0),
        hi: std::ops::Bound::Included(0.5),
    };
}

impl ParamValue for Poisson {
    fn type_doc() -> TypeDoc {
        TypeDoc::Custom(format!("number in {}", Poisson::RANGE))
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        check_range(prefix, &self.0, &Poisson::RANGE)
    }

    fn visit_paths(&mut self, _: &str, _: &mut dyn FnMut(&str, &mut InputPath)) {}
}

use crate::Parameter;
use crate::compensated_sum::CompensatedSum;

/// The initial Young's modulus E0 = 2 μ0 (1 + ν) (SPEC, "Ogden model"), Pa.
/// ν = ½ gives 3 μ0.
pub fn youngs_modulus_pa(shear_modulus_pa: f64, poisson: f64) -> f64 {
    2.0 * shear_modulus_pa * (1.0 + poisson)
}

/// The initial composite modulus E0* = E0 / (1 − ν²), Pa: with
/// [`youngs_modulus_pa`] the one place where ν enters the linear moduli, so
/// every stage normalising by E0* agrees. ν = ½ gives 4 μ0.
pub fn composite_modulus_pa(shear_modulus_pa: f64, poisson: f64) -> f64 {
    youngs_modulus_pa(shear_modulus_pa, poisson) / (1.0 - poisson * poisson)
}

/// An incompressible isotropic hyperelastic material.
///
/// Nominal (first Piola–Kirchhoff) stresses are in pascals and follow from
/// the reduced energy along each test path, T = (dW/dλ) / k with k loaded
/// directions; implementations give them in closed form where one exists.
pub trait Hyperelastic: fmt::Debug + Send + Sync {
    /// The model family's name in the `material` table (`ogden`, ...).
    fn family(&self) -> &'static str;

    /// Initial shear modulus μ0, Pa.
    fn shear_modulus_pa(&self) -> f64;

    /// Strain energy density W(λ1, λ2, λ3) for λ1 λ2 λ3 = 1, Pa.
    fn energy_pa(&self, stretches: [f64; 3]) -> f64;

    /// Nominal stress in `mode` at loading stretch λ, Pa.
    fn nominal_stress_pa(&self, mode: Mode, stretch: f64) -> f64;

    /// dT/dλ in `mode` at loading stretch λ, Pa.
    fn nominal_stress_slope_pa(&self, mode: Mode, stretch: f64) -> f64;

    /// The parameters in SI units, in the order of the `material` table.
    fn parameters(&self) -> Vec<Parameter>;

    /// The Drucker stiffness at principal stretches (λ1, λ2, λ3), Pa: the
    /// Hessian of Ŵ(ε1, ε2) = W(e^ε1, e^ε2, e^(−ε1−ε2)) in the log strains,
    /// whose gradient is (σ1 − σ3, σ2 − σ3). Drucker's condition
    /// dσ:dε > 0 holds where it is positive definite (see
    /// [`crate::stability`]). The default differentiates
    /// [`Hyperelastic::energy_pa`] numerically; families override it in
    /// closed form.
    fn log_strain_hessian_pa(&self, stretches: [f64; 3]) -> [[f64; 2]; 2] {
        log_strain_hessian_by_differences(self, stretches)
    }

    /// The trace and determinant of [`Hyperelastic::log_strain_hessian_pa`]
    /// at principal stretches (λ1, λ2, λ3), from which Drucker's condition
    /// is decided ([`crate::stability::is_stable`]). The default forms them
    /// from the Hessian's entries ([`DruckerStiffness::from_hessian`]),
    /// which cancels where the entries are many orders of magnitude larger
    /// than the determinant; families override it with an expanded form
    /// whose terms do not cancel for a stable material ([`crate::Ogden`]'s
    /// impl, and [`crate::invariants::drucker_stiffness`] for the invariant
    /// families), each saying how accurate it is.
    fn drucker_stiffness(&self, stretches: [f64; 3]) -> DruckerStiffness {
        DruckerStiffness::from_hessian(self.log_strain_hessian_pa(stretches))
    }
}

/// The two invariants of the 2 × 2 Drucker stiffness H (the log-strain
/// Hessian, [`Hyperelastic::log_strain_hessian_pa`]): H is positive
/// definite, and Drucker's condition holds, exactly where both are
/// positive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerStiffness {
    /// H11 + H22, Pa.
    pub trace_pa: f64,
    /// H11 H22 − H12², Pa².
    pub determinant_pa2: f64,
}

impl DruckerStiffness {
    /// From the Hessian's entries: the default for families without an
    /// expanded form. H11 H22 − H12² is formed with fused multiply–adds,
    /// correctly rounded for the entries given, but the entries' own
    /// rounding errors, multiplied by the other entries, remain: where the
    /// entries share a term much larger than the determinant, it is lost.
    pub fn from_hessian([[h11, h12], [_, h22]]: [[f64; 2]; 2]) -> Self {
        let mut determinant = CompensatedSum::default();
        determinant.add_product(h11, h22);
        determinant.add_product(-h12, h12);
        Self {
            trace_pa: h11 + h22,
            determinant_pa2: determinant.value(),
        }
    }

    /// Drucker's condition: H positive definite. For a symmetric 2 × 2
    /// matrix that is det > 0 and trace > 0: with det > 0, H11 and H22 share
    /// the trace's sign, and the trace, |H11| + |H22|, is the safest of the
    /// three to read it from.
    pub fn is_positive_definite(&self) -> bool {
        self.determinant_pa2 > 0.0 && self.trace_pa > 0.0
    }
}

/// [`Hyperelastic::log_strain_hessian_pa`] by central second differences of
/// the energy (step 1e-4 in log strain): the default, and an independent
/// check of the closed forms.
pub fn log_strain_hessian_by_differences<M: Hyperelastic + ?Sized>(
    model: &M,
    [l1, l2, l3]: [f64; 3],
) -> [[f64; 2]; 2] {
    let h = 1e-4;
    let w =
        |d1: f64, d2: f64| model.energy_pa([l1 * d1.exp(), l2 * d2.exp(), l3 * (-d1 - d2).exp()]);
    let w0 = w(0.0, 0.0);
    let h11 = (w(h, 0.0) - 2.0 * w0 + w(-h, 0.0)) / (h * h);
    let h22 = (w(0.0, h) - 2.0 * w0 + w(0.0, -h)) / (h * h);
    let h12 = (w(h, h) - w(h, -h) - w(-h, h) + w(-h, -h)) / (4.0 * h * h);
    [[h11, h12], [h12, h22]]
}
