//! Image-analysis cores of the `contact-images` stage: from one
//! contact-interference camera frame (rubber pressed against glass, the
//! paper's Fig. 3 rig) to a binary contact map and its patches.
//!
//! Conventions, shared by every module:
//! - **Dark is contact.** The half-wave loss at the air–rubber interface
//!   makes touching regions (almost) black, so every method returns the dark
//!   side of a threshold.
//! - **Thresholds are inclusive.** A pixel is contact when its value is
//!   `<= threshold`. Integer thresholds are always the brightest *occupied*
//!   level of the darker class, so a threshold found on a 12-bit frame is
//!   exactly 1/16 of the one found on the same frame scaled to 16 bits.
//! - **Bit depth is the camera's**, not the container's: a 12-bit camera
//!   stored in 16-bit words keeps values below 4096 and `bits = 12`; the
//!   histograms have `2^bits` bins.
//! - **Patches are 8-connected** (diagonal neighbours touch), as the
//!   `truncation` stage and MATLAB's `bwlabel` default count them.
//!
//! Modules:
//! - [`frame`]: the grey frame, its histogram and its thresholded mask;
//! - [`mask`]: the binary contact map;
//! - [`mod@otsu`]: global Otsu on the full `2^bits`-bin histogram (the paper's);
//! - [`mod@multi_otsu`]: Otsu with 2 to 5 classes on a re-binned histogram;
//! - [`calibrated`]: flat-field, a threshold calibrated between the contact
//!   and background levels, hysteresis and a minimum patch size (the lab's);
//! - [`mod@label`]: 8-connected components, ordered by first pixel;
//! - [`sync`]: the camera-to-force-log clock offset from first contact;
//! - `listing`: each frame and file listed once, a given offset inside the log;
//! - `reference`: whether the calibrated method's reference frame is in contact;
//! - [`stage`]: the `contact-images` stage, and `analysis`: its run over the
//!   frames and the clock.
//!
//! The cores run on one thread, so results are identical bytes whatever the
//! machine's thread count.

mod analysis;
pub mod calibrated;
mod error;
mod exact;
pub mod frame;
pub mod label;
mod listing;
pub mod mask;
pub mod multi_otsu;
pub mod otsu;
mod percentile;
mod reference;
pub mod stage;
pub mod sync;

pub use calibrated::{Calibrated, CalibratedSegmentation, Level, segment_calibrated};
pub use error::ImageError;
pub use frame::Frame;
pub use label::{Labels, label};
pub use mask::Mask;
pub use multi_otsu::{MultiOtsu, MultiOtsuThresholds, multi_otsu};
pub use otsu::{Otsu, otsu};

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::ContactImages);
}

/// The largest number of pixels a frame or mask may have: labels and patch
/// indices are `u32`, as in the `truncation` stage's union–find.
pub const MAX_PIXELS: usize = u32::MAX as usize;

/// Pixel count of a `width × height` image, refused when zero or too large.
pub(crate) fn pixel_count(width: usize, height: usize) -> Result<usize, ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::Empty { width, height });
    }
    match width.checked_mul(height) {
        Some(pixels) if pixels <= MAX_PIXELS => Ok(pixels),
        _ => Err(ImageError::TooManyPixels {
            width,
            height,
            max: MAX_PIXELS,
        }),
    }
}
