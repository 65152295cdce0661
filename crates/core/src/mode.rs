//! The homogeneous tensile tests of the paper's section 2, shared by the
//! stages that make, measure and fit them.

use crate::Choice;

/// A tensile test mode, written `UT`, `PT` or `BT` in parameters and tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Choice)]
pub enum Mode {
    /// Uniaxial tension: stretches (λ, λ^-½, λ^-½).
    #[choice(name = "UT")]
    Uniaxial,
    /// Planar tension (pure shear): stretches (λ, 1, λ^-1).
    #[choice(name = "PT")]
    Planar,
    /// Equibiaxial tension: stretches (λ, λ, λ^-2).
    #[choice(name = "BT")]
    Equibiaxial,
}

impl Mode {
    pub const ALL: [Mode; 3] = [Mode::Uniaxial, Mode::Planar, Mode::Equibiaxial];

    /// The label used in tables: `UT`, `PT` or `BT`.
    pub fn label(self) -> &'static str {
        crate::param::Choice::name(&self)
    }

    /// A label as labs write it: `UT`, `PT`/`PS`, `BT`/`ET`/`EB`, any case.
    pub fn from_label(label: &str) -> Option<Mode> {
        match label.trim().to_ascii_uppercase().as_str() {
            "UT" => Some(Mode::Uniaxial),
            "PT" | "PS" => Some(Mode::Planar),
            "BT" | "ET" | "EB" => Some(Mode::Equibiaxial),
            _ => None,
        }
    }

    /// Principal stretches (λ1, λ2, λ3) of an incompressible solid in this
    /// test at loading stretch λ.
    pub fn stretches(self, stretch: f64) -> [f64; 3] {
        match self {
            Mode::Uniaxial => [stretch, stretch.powf(-0.5), stretch.powf(-0.5)],
            Mode::Planar => [stretch, 1.0, 1.0 / stretch],
            Mode::Equibiaxial => [stretch, stretch, stretch.powi(-2)],
        }
    }

    /// How many loaded directions share the work dW/dλ: the nominal stress is
    /// dW/dλ divided by this (2 for equibiaxial, 1 otherwise).
    pub fn loaded_directions(self) -> f64 {
        match self {
            Mode::Equibiaxial => 2.0,
            _ => 1.0,
        }
    }
}
