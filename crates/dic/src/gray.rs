//! Grayscale frames as floating-point intensities, 0 … 1 of full scale.
//!
//! 8- and 16-bit files are both mapped to fractions of their full scale, so
//! thresholds (markers, noise) mean the same thing for either bit depth.

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
        let decoded = image::load_from_memory(bytes).map_err(|e| DicError::File {
            file: name.to_owned(),
            message: format!("not a readable PNG/TIFF image: {e}"),
        })?;
        let (width, height) = (decoded.width() as usize, decoded.height() as usize);
        let sixteen_bit = matches!(
            decoded.color(),
            image::ColorType::L16
                | image::ColorType::La16
                | image::ColorType::Rgb16
                | image::ColorType::Rgba16
                | image::ColorType::Rgb32F
                | image::ColorType::Rgba32F
        );
        let pixels: Vec<f64> = if sixteen_bit {
            decoded
                .into_luma16()
                .into_raw()
                .into_iter()
                .map(|v| f64::from(v) / 65535.0)
                .collect()
        } else {
            decoded
                .into_luma8()
                .into_raw()
                .into_iter()
                .map(|v| f64::from(v) / 255.0)
                .collect()
        };
        Self::new(width, height, pixels).map_err(|e| DicError::File {
            file: name.to_owned(),
            message: e.to_string(),
        })
    }
}
