//! Model against experiment (issue #15): the predicted contact map of a
//! model set beside the contact the camera observed.
//!
//! - [`register`]: finds where the camera looked on the scanned sample — the
//!   rotation, shift and scale that map the predicted contact map onto the
//!   observed binary mask (the paper's Fig. 6 alignment, done by hand there).

pub mod error;
pub mod register;

pub use error::CompareError;
pub use register::{
    ObservedMask, PredictedMap, RegisterSettings, Registration, register, sample_predicted, zncc,
};
