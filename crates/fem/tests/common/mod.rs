//! Shared by the integration tests: one model of every material family.

use hypercontact_material::presets::paper_epdm;
use hypercontact_material::{ArrudaBoyce, Hyperelastic, MooneyRivlin, NeoHookean, Ogden, Yeoh};

/// The paper's 6-term Ogden EPDM, Ogden's 1972 3-term rubber, and one of
/// each invariant family.
pub fn every_family() -> Vec<Box<dyn Hyperelastic>> {
    vec![
        Box::new(paper_epdm()),
        Box::new(Ogden::new(vec![0.63e6, 0.0012e6, -0.01e6], vec![1.3, 5.0, -2.0]).unwrap()),
        Box::new(NeoHookean::new(0.2e6).unwrap()),
        Box::new(MooneyRivlin::new(0.18e6, 0.05e6).unwrap()),
        Box::new(Yeoh::new(0.2e6, -0.01e6, 0.002e6).unwrap()),
        Box::new(ArrudaBoyce::new(0.3e6, 2.5).unwrap()),
    ]
}
