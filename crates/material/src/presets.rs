//! Built-in materials.

use crate::{Hyperelastic, MaterialError, Ogden};

/// The built-in materials, by name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, hypercontact_core::Choice)]
pub enum Preset {
    /// the paper's Table 1: 6-term Ogden EPDM
    #[default]
    PaperEpdm,
}

impl Preset {
    pub fn model(self) -> Box<dyn Hyperelastic> {
        match self {
            Preset::PaperEpdm => Box::new(paper_epdm()),
        }
    }
}

/// Names accepted by [`preset`].
pub const PRESETS: &[&str] = &["paper-epdm"];

/// The paper's Table 1: the 6-term Ogden fit of its EPDM (μ_i given in MPa
/// there, stored here in Pa).
pub fn paper_epdm() -> Ogden {
    const MU_MPA: [f64; 6] = [5025.77, -3862.35, 1442.35, -4644.15, 3119.98, -1079.81];
    const ALPHA: [f64; 6] = [0.635, 0.976, 1.178, 0.259, -0.0488, -0.219];
    Ogden::new(MU_MPA.iter().map(|m| m * 1e6).collect(), ALPHA.to_vec())
        .expect("Table 1 is a valid Ogden model")
}

/// A preset by name.
pub fn preset(name: &str) -> Result<Box<dyn Hyperelastic>, MaterialError> {
    match name {
        "paper-epdm" => Ok(Box::new(paper_epdm())),
        _ => Err(MaterialError::UnknownPreset {
            name: name.to_owned(),
            known: PRESETS.join(", "),
        }),
    }
}
