//! A binary contact map: `true` is contact, row-major, `width × height`.

use crate::{ImageError, pixel_count};

/// A row-major boolean image; `true` marks contact.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mask {
    width: usize,
    height: usize,
    pixels: Vec<bool>,
}

impl Mask {
    /// A mask of `width × height` pixels in row-major order (pixel (x, y) at
    /// `y * width + x`).
    pub fn new(width: usize, height: usize, pixels: Vec<bool>) -> Result<Self, ImageError> {
        let expected = pixel_count(width, height)?;
        if pixels.len() != expected {
            return Err(ImageError::WrongLength {
                width,
                height,
                expected,
                actual: pixels.len(),
            });
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// Builds a mask from sizes already checked by a [`crate::Frame`] or another mask.
    pub(crate) fn from_checked(width: usize, height: usize, pixels: Vec<bool>) -> Self {
        debug_assert_eq!(pixels.len(), width * height);
        Self {
            width,
            height,
            pixels,
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// The pixels, row-major.
    pub fn pixels(&self) -> &[bool] {
        &self.pixels
    }

    /// Number of contact pixels.
    pub fn count(&self) -> usize {
        self.pixels.iter().filter(|&&p| p).count()
    }

    /// Contact pixels over all pixels (A/A0 of the frame).
    pub fn area_fraction(&self) -> f64 {
        self.count() as f64 / self.pixels.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked() {
        assert_eq!(
            Mask::new(0, 3, vec![]),
            Err(ImageError::Empty {
                width: 0,
                height: 3
            })
        );
        assert!(matches!(
            Mask::new(2, 2, vec![true; 3]),
            Err(ImageError::WrongLength {
                expected: 4,
                actual: 3,
                ..
            })
        ));
        assert!(matches!(
            Mask::new(usize::MAX, 2, vec![]),
            Err(ImageError::TooManyPixels { .. })
        ));
        let m = Mask::new(2, 2, vec![true, false, false, true]).unwrap();
        assert_eq!(m.count(), 2);
        assert_eq!(m.area_fraction(), 0.5);
    }
}
