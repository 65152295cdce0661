//! Finite-strain finite-element contact of a rough, nearly incompressible
//! hyperelastic block pressed by a rigid, flat, frictionless plane: the
//! numerical core of the `fem` stage (issue #33), the reference that judges
//! the tangent-modulus contact models.
//!
//! - [`mesh`]: the mapped hexahedral mesh of a height-map patch and its
//!   boundary sets, optionally coarsened laterally with depth (hanging
//!   nodes tied to the coarse faces, issue #48); the stage refuses a mesh
//!   whose elements are more than [`MAX_FLATNESS`] (10) times wider than
//!   thick (width over the layer's thickness in the lowest column);
//! - [`energy`], [`isochoric`], [`law`]: the strain energy of every material
//!   family (automatic differentiation in the invariants, closed-form
//!   spectral calculus to C), the isochoric/volumetric split, and a
//!   small-strain linear law for checks;
//! - [`hexahedron`]: the locking-free Q1/P0 mixed hexahedron, condensed;
//! - [`dofs`], [`assembly`], [`ordering`], [`linear_solver`]: boundary
//!   conditions (base clamped, lateral faces mirror or periodic) and
//!   hanging-node ties as (unknown, weight) terms, fixed-order sparse
//!   assembly, nested dissection, and faer's sparse Cholesky with its
//!   symbolic analysis reused;
//! - [`contact`], [`newton`], [`curve`]: exact active-set contact with the
//!   plane, Newton with line search, approach-controlled steps;
//! - [`cause`]: the likely cause a failed solve names (unstable material,
//!   a contact area that stopped growing, a first step too large);
//! - [`vtk`]: the deformed mesh for ParaView;
//! - [`stage`]: the pipeline stage `fem`.

pub mod assembly;
pub mod cause;
pub mod contact;
pub mod curve;
pub mod dofs;
pub mod energy;
pub mod hexahedron;
pub mod isochoric;
pub mod law;
pub mod linear_solver;
pub mod mesh;
pub mod newton;
pub mod ordering;
pub mod sample;
pub mod stage;
mod tensor;
pub mod vtk;

pub use contact::{ContactProblem, NewtonOptions, Step};
pub use curve::{
    AreaSteps, Curve, CurveOptions, Snapshot, bearing_approach_m, solve_area_steps, solve_curve,
};
pub use law::{DEFAULT_BULK_RATIO, Law};
pub use mesh::{Flatness, HeightMap, Lateral, MAX_FLATNESS, Mesh, MeshOptions};

/// Errors of the fem core.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FemError {
    #[error("material: {0}")]
    Material(String),
    #[error("height map: {0}")]
    HeightMap(String),
    #[error("mesh option `{option}` = {value}: {message}")]
    MeshOption {
        option: &'static str,
        value: String,
        message: String,
    },
    #[error(
        "step {step} (approach {approach_m:.6e} m): Newton did not converge in {iterations} \
         iterations, residual {residual_n:.3e} N against tolerance {tolerance_n:.3e} N \
         ({contact_nodes} nodes in contact){detail}"
    )]
    NotConverged {
        step: usize,
        approach_m: f64,
        iterations: usize,
        residual_n: f64,
        tolerance_n: f64,
        contact_nodes: usize,
        detail: String,
    },
    #[error("sparse solver: {0}")]
    Solver(String),
    #[error("curve option `{option}`: {message}")]
    CurveOption {
        option: &'static str,
        message: String,
    },
    #[error("writing VTK: {0}")]
    Io(String),
}

/// Registers this crate's stage kind.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::Fem);
}
