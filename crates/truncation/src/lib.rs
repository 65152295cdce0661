//! Profile theory for hypercontact: truncate a height map with a plane and
//! read off the touched area A(z), the number of patches N(z) and their
//! equivalent radius r(z) (the paper's section 4, Eq. 3).
//!
//! - [`profile`]: the one-sweep union–find truncation (pure, on ndarray);
//! - [`plane_order`]: the measured pixels grouped by the plane that first touches them;
//! - [`sweep`]: the descent adding them to patches;
//! - [`union_find`]: the disjoint sets it uses;
//! - [`levels`]: the `levels` and `connectivity` parameters;
//! - [`stage`]: the `truncation` stage;
//! - [`flood_fill`]: brute-force per-plane labelling (test reference, benchmark baseline).
//!
//! Benchmarks and examples draw self-affine maps from `hypercontact-synth`'s
//! generator (a dev-dependency: the stage itself needs none).

pub mod flood_fill;
pub mod levels;
pub mod plane_order;
pub mod profile;
pub mod stage;
pub mod sweep;
pub mod union_find;

pub use levels::{Connectivity, Levels};
pub use profile::{PatchSnapshot, Profile, TruncationOptions, truncate};

/// Why a map cannot be truncated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TruncationError {
    #[error("the height map has no measured point (every value is NaN)")]
    NothingMeasured,
    #[error(
        "the height map is flat (every measured height is equal): no plane separates \
         contact from non-contact"
    )]
    Flat,
    #[error("the height map holds an infinite value {value} at pixel [{ix}, {iy}]")]
    NonFinite { ix: usize, iy: usize, value: f64 },
    #[error(
        "the height map is too large ({nx} × {ny} pixels): (nx + 2)·(ny + 2) must stay \
         below 2^32 − 1"
    )]
    TooLarge { nx: usize, ny: usize },
}

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::Truncation);
}
