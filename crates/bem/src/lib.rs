//! Boundary-element contact model: a rough, linearly elastic half-space
//! pressed against a rigid plane, solved on the pixels of the height map with
//! FFTs, so the elastic coupling between asperities and the deformation of
//! the surface between them (which profile theory leaves out, the paper's
//! stated limitation) are in. The reference the `icm` is compared with.
//!
//! - [`influence`]: the half-space's pressure-to-displacement operator
//!   (periodic, or free with Love's pixel kernel and Hockney's padding);
//! - [`fft2`]: the convolution with an even kernel it runs on (on the
//!   workspace's FFT, `hypercontact_numeric::fft2`);
//! - [`polonsky_keer`]: the constrained conjugate-gradient contact solver;
//! - [`complement`]: its preconditioner's correction on a contact set;
//! - [`curve`]: the load steps from first contact to a top area fraction;
//! - [`shared`]: one solve of a curve for the stages that ask for the same;
//! - [`stage`]: the `bem` stage.
//!
//! Sums over a map run in the fixed order of `hypercontact_numeric::reduce`,
//! so every product is the same on any number of threads.

pub mod complement;
pub mod curve;
pub mod fft2;
pub mod influence;
pub mod polonsky_keer;
pub mod shared;
pub mod stage;

pub use curve::{CurveError, CurveOptions, Step, solve_curve};
pub use influence::{Boundary, Influence};
pub use polonsky_keer::{Control, Problem, Solution, SolveError, SolverOptions};

/// Errors of the `bem` stage.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BemError {
    #[error("input `surface`: {0}")]
    Surface(String),
    #[error("input `material`: {0}")]
    Material(hypercontact_material::MaterialError),
    #[error(
        "step {step} of {steps} (plane z = {z_m:.6e} m, load ≈ {load_n:.6e} N at E0*): no \
         convergence after {iterations} iterations, residual {residual:.3e} > tolerance \
         {tolerance:.1e}; raise `max_iterations` or `tolerance`"
    )]
    NotConverged {
        step: usize,
        steps: usize,
        z_m: f64,
        load_n: f64,
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    #[error(transparent)]
    Curve(#[from] CurveError),
    #[error(transparent)]
    Tangent(#[from] hypercontact_icm::tangent::TangentError),
}

// Not `#[from]`: the message holds the cause, so it is not also the source.
impl From<hypercontact_material::MaterialError> for BemError {
    fn from(e: hypercontact_material::MaterialError) -> Self {
        BemError::Material(e)
    }
}

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::Bem);
}
