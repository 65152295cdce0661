//! A grey camera frame at the camera's bit depth, its histogram, and the
//! mask of its dark (contact) pixels.
//!
//! The bit depth is the camera's, not the container's: a 12-bit sensor whose
//! frames are stored in 16-bit words (as TIFF and PNG readers return them)
//! keeps values below 4096 and `bits = 12`. Nothing is rescaled, so the
//! histogram has exactly `2^bits` bins and Otsu searches exactly the levels
//! the camera can produce.

use crate::{ImageError, Mask, pixel_count};

/// A row-major grey frame of `width × height` pixels with values below `2^bits`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    width: usize,
    height: usize,
    bits: u8,
    data: Vec<u16>,
}

impl Frame {
    /// A frame of `width × height` pixels in row-major order (pixel (x, y) at
    /// `y * width + x`), each below `2^bits`, `bits` in 1..=16.
    pub fn new(width: usize, height: usize, bits: u8, data: Vec<u16>) -> Result<Self, ImageError> {
        if !(1..=16).contains(&bits) {
            return Err(ImageError::BitDepth { bits });
        }
        let expected = pixel_count(width, height)?;
        if data.len() != expected {
            return Err(ImageError::WrongLength {
                width,
                height,
                expected,
                actual: data.len(),
            });
        }
        let limit = 1_u32 << bits;
        if let Some(i) = data.iter().position(|&v| u32::from(v) >= limit) {
            return Err(ImageError::ValueOutOfRange {
                x: i % width,
                y: i / width,
                value: data[i],
                bits,
                limit,
            });
        }
        Ok(Self {
            width,
            height,
            bits,
            data,
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// The camera's bit depth.
    pub fn bits(&self) -> u8 {
        self.bits
    }

    /// The pixel values, row-major.
    pub fn data(&self) -> &[u16] {
        &self.data
    }

    /// Number of grey levels the camera can produce, `2^bits`.
    pub fn levels(&self) -> usize {
        1 << self.bits
    }

    /// Pixel count of every level: `2^bits` bins, bin `v` counting value `v`.
    pub fn histogram(&self) -> Vec<u64> {
        let mut counts = vec![0_u64; self.levels()];
        for &v in &self.data {
            counts[usize::from(v)] += 1;
        }
        counts
    }

    /// The contact mask at an inclusive threshold: pixels with value `<= threshold`.
    pub fn dark_mask(&self, threshold: u16) -> Mask {
        Mask::from_checked(
            self.width,
            self.height,
            self.data.iter().map(|&v| v <= threshold).collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructor_refuses_bad_input() {
        assert_eq!(
            Frame::new(2, 2, 0, vec![0; 4]),
            Err(ImageError::BitDepth { bits: 0 })
        );
        assert_eq!(
            Frame::new(2, 2, 17, vec![0; 4]),
            Err(ImageError::BitDepth { bits: 17 })
        );
        assert_eq!(
            Frame::new(0, 0, 8, vec![]),
            Err(ImageError::Empty {
                width: 0,
                height: 0
            })
        );
        assert!(matches!(
            Frame::new(3, 2, 8, vec![0; 5]),
            Err(ImageError::WrongLength {
                expected: 6,
                actual: 5,
                ..
            })
        ));
        // A 12-bit camera's value 4096 is out of range at (x = 1, y = 1).
        assert_eq!(
            Frame::new(2, 2, 12, vec![0, 4095, 7, 4096]),
            Err(ImageError::ValueOutOfRange {
                x: 1,
                y: 1,
                value: 4096,
                bits: 12,
                limit: 4096
            })
        );
        assert!(Frame::new(1, 1, 16, vec![u16::MAX]).is_ok());
        assert!(Frame::new(1, 1, 1, vec![1]).is_ok());
        assert!(Frame::new(1, 1, 1, vec![2]).is_err());
    }

    #[test]
    fn histogram_has_one_bin_per_camera_level() {
        let f = Frame::new(3, 2, 12, vec![0, 4095, 7, 7, 7, 0]).unwrap();
        let h = f.histogram();
        assert_eq!(h.len(), 4096);
        assert_eq!((h[0], h[7], h[4095]), (2, 3, 1));
        assert_eq!(h.iter().sum::<u64>(), 6);
        assert_eq!(
            Frame::new(1, 1, 16, vec![9]).unwrap().histogram().len(),
            65536
        );
    }

    #[test]
    fn dark_mask_is_inclusive() {
        let f = Frame::new(4, 1, 8, vec![3, 4, 5, 255]).unwrap();
        assert_eq!(f.dark_mask(4).pixels(), &[true, true, false, false]);
        assert_eq!(f.dark_mask(255).count(), 4);
    }
}
