//! Grayscale frames as floating-point intensities, 0 … 1 of full scale.
//!
//! 8- and 16-bit files are both mapped to fractions of their full scale, so
//! thresholds (markers, noise) mean the same thing for either bit depth.

use hypercontact_core::sequence::GrayFrame;

use crate::DicError;

/// A grayscale image, row-major (`pixels[y * width + x]`), x = column.
#[derive(Clone, Debug, PartialEq)]
pub struct GrayImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<f64>,
}

impl GrayImage {
    pub fn new(width: usize, height: usize, pixels: Vec<f64>) -> Result<Self, DicError> {
        if width == 0 || height == 0 || pixels.len() != width * height {
            return Err(DicError::Invalid(format!(
                "an image of {width} × {height} pixels cannot hold {} values",
                pixels.len()
            )));
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    #[inline]
    pub fn get(&self, x: usize, y: usize) -> f64 {
        self.pixels[y * self.width + x]
    }

    /// Decodes a PNG or TIFF file's bytes; `name` only labels errors.
    /// Colour images are converted to luma.
    pub fn decode(name: &str, bytes: &[u8]) -> Result<Self, DicError> {
        let frame = GrayFrame::decode(name, bytes).map_err(DicError::from_stage)?;
        Self::from_frame(&frame).map_err(|e| DicError::file(name, e.to_string()))
    }

    /// A decoded frame as fractions of its container's full scale.
    pub fn from_frame(frame: &GrayFrame) -> Result<Self, DicError> {
        let full = frame.full_scale();
        let pixels = frame.data.iter().map(|&v| f64::from(v) / full).collect();
        Self::new(frame.width, frame.height, pixels)
    }
}
