//! The synthetic contact experiment (issue #14, work in progress): the
//! sample's contact with the glass at each camera frame's penetration, as
//! the `synth-contact` stage will render it into interference images.
//! Here: the contact solve per frame ([`solve`]); the rig (camera, force
//! sensor, clocks) and the stage come next.

pub mod solve;
