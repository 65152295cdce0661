//! The synthetic laboratory: stages that write the raw files a lab would
//! from a known ground truth, which they emit separately so tests can score
//! the stages that read those files.
//!
//! - [`surface`]: `synth-surface`, interferometer tiles of a self-affine
//!   surface;
//! - [`tensile`]: `synth-tensile`, speckle image sequences and the force log
//!   of a tensile test;
//! - [`contact`]: `synth-contact`, contact-interference frames and a force
//!   log of the sample pressed onto glass.

pub mod contact;
pub mod surface;
pub mod tensile;

use hypercontact_core::{Registry, StageError};
use hypercontact_labfiles::png::Pixels;

/// Registers this crate's stage kinds.
pub fn register(registry: &mut Registry) {
    registry.add(contact::SynthContact);
    registry.add(surface::SynthSurface);
    registry.add(tensile::SynthTensile);
}

/// A grayscale PNG of camera counts: 8-bit (counts above 255 saturate) or
/// 16-bit (a camera of 9–16 bits writes its counts unscaled), through the
/// workspace's one encoder.
pub fn encode_png(
    width: usize,
    height: usize,
    bit_depth: u32,
    counts: Vec<u16>,
) -> Result<Vec<u8>, StageError> {
    let pixels = if bit_depth == 8 {
        Pixels::Gray8(counts.into_iter().map(|c| c.min(255) as u8).collect())
    } else {
        Pixels::Gray16(counts)
    };
    let side = |n: usize| {
        u32::try_from(n).map_err(|_| {
            StageError::invalid(format!("an image side of {n} px is beyond PNG's limit"))
        })
    };
    hypercontact_labfiles::png::encode_png(side(width)?, side(height)?, pixels)
        .map_err(StageError::invalid)
}
