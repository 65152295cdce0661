//! Built-in materials.

use hypercontact_core::param::Choice;

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

/// The paper's Table 1: the 6-term Ogden fit of its EPDM (μ_i given in MPa
/// there, stored here in Pa).
pub fn paper_epdm() -> Ogden {
    const MU_MPA: [f64; 6] = [5025.77, -3862.35, 1442.35, -4644.15, 3119.98, -1079.81];
    const ALPHA: [f64; 6] = [0.635, 0.976, 1.178, 0.259, -0.0488, -0.219];
    Ogden::new(MU_MPA.iter().map(|m| m * 1e6).collect(), ALPHA.to_vec())
        .expect("Table 1 is a valid Ogden model")
}

/// A preset by name (the names of [`Preset`]).
pub fn preset(name: &str) -> Result<Box<dyn Hyperelastic>, MaterialError> {
    let preset = Preset::from_name(name).ok_or_else(|| MaterialError::UnknownPreset {
        name: name.to_owned(),
        known: (Preset::VARIANTS.iter().map(|v| v.name))
            .collect::<Vec<_>>()
            .join(", "),
    })?;
    Ok(preset.model())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_found_by_their_choice_name() {
        let m = preset("paper-epdm").unwrap();
        assert_eq!(m.parameters(), paper_epdm().parameters());
        let e = preset("nitrile").unwrap_err().to_string();
        assert!(e.contains("`nitrile`") && e.contains("paper-epdm"), "{e}");
    }
}
