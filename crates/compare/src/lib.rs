//! Model against experiment (issue #15): the predicted contact map of a
//! model set beside the contact the camera observed, and the models'
//! load–area curves against the measured one.
//!
//! - [`register`]: finds where the camera looked on the scanned sample — the
//!   rotation, shift and scale that map the predicted contact map onto the
//!   observed binary mask (the paper's Fig. 6 alignment, done by hand there);
//! - [`overlap`]: confusion counts and Dice/IoU/precision/recall of a
//!   predicted and an observed map;
//! - [`agreement`]: a model's load at the measured contact areas against the
//!   measured load;
//! - [`stage`]: the `contact-compare` stage, whose `run` reads the maps
//!   (`maps`), checks that they belong together (`belong`), registers the observed ones (`registration`), lays every
//!   prediction over them (`overlays`, with the figures' [`stage::FigureIndex`])
//!   and scores the responses (`scoring`, on the camera's view: `view`).

pub mod agreement;
mod belong;
pub mod error;
mod maps;
pub mod overlap;
mod overlays;
pub mod register;
mod registration;
mod scoring;
pub mod stage;
mod view;

pub use error::CompareError;
pub use register::{
    ObservedMask, PredictedMap, RegisterSettings, Registration, sample_predicted, zncc,
};

/// Adds this crate's stage to the registry.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::ContactCompare);
}
