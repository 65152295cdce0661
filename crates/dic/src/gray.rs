//! Grayscale frames as floating-point intensities, 0 … 1 of full scale.
//!
//! Counts are divided by the camera's full scale 2^bits − 1: `bits` is the
//! `bit_depth` given (parameter or specimen.json), else the container's
//! depth (8 or 16). A 12-bit camera in 16-bit files therefore maps to
//! fractions of 4095 only when told so; the depth is never guessed from the
//! values (a dark first frame of a 16-bit camera would look 12-bit, and a
//! brighter later frame would then overflow). The subset method does not
//! depend on it (ZNCC and IC-GN are blind to an intensity scale); marker
//! thresholds, fractions of full scale, do. Float TIFFs hold fractions
//! already (0 … 1), or counts of a `bit_depth`-bit camera when one is given.

use hypercontact_labfiles::sequence::{DecodedImage, GrayFrame, Samples};

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
    /// Colour images are converted to grey by
    /// [`hypercontact_labfiles::sequence::LUMA_RULE`].
    pub fn decode(name: &str, bytes: &[u8]) -> Result<Self, DicError> {
        let decoded = hypercontact_labfiles::sequence::decode_image(name, bytes)
            .map_err(DicError::from_stage)?;
        Self::from_decoded(&decoded, None).map_err(|e| DicError::file(name, e.to_string()))
    }

    /// A decoded frame as fractions of its container's full scale.
    pub fn from_frame(frame: &GrayFrame) -> Result<Self, DicError> {
        let full = frame.full_scale();
        let pixels = frame.data.iter().map(|&v| f64::from(v) / full).collect();
        Self::new(frame.width, frame.height, pixels)
    }

    /// A decoded file as fractions of full scale, the camera having
    /// `bit_depth` bits if given (see the module doc). A count or value
    /// beyond the full scale is an error naming the pixel (`Invalid`: the
    /// caller adds the file).
    pub fn from_decoded(decoded: &DecodedImage, bit_depth: Option<u8>) -> Result<Self, DicError> {
        let at = |k: usize| format!("pixel (x {}, y {})", k % decoded.width, k / decoded.width);
        let pixels = match (&decoded.samples, bit_depth) {
            (Samples::Counts { bits, data }, depth) => {
                let bits_used = depth.unwrap_or(*bits);
                if bits_used > *bits {
                    return Err(DicError::Invalid(format!(
                        "is a {bits}-bit {} but `bit_depth` is {bits_used}",
                        decoded.kind
                    )));
                }
                let full = f64::from((1u32 << bits_used) - 1);
                if depth.is_some()
                    && let Some(k) = data.iter().position(|&v| f64::from(v) > full)
                {
                    return Err(DicError::Invalid(format!(
                        "{} is {} but a {bits_used}-bit camera counts to {full} (check `bit_depth`)",
                        at(k),
                        data[k]
                    )));
                }
                data.iter().map(|&v| f64::from(v) / full).collect()
            }
            (Samples::Float(values), depth) => {
                let full = depth.map_or(1.0, |b| f64::from((1u32 << b) - 1));
                if let Some(k) = values
                    .iter()
                    .position(|v| !(v.is_finite() && (0.0..=full).contains(v)))
                {
                    let expected = match depth {
                        Some(b) => format!("counts of a {b}-bit camera (0 … {full}, `bit_depth`)"),
                        None => "fractions of full scale, 0 … 1 (or set `bit_depth` for \
                                 counts)"
                            .to_owned(),
                    };
                    return Err(DicError::Invalid(format!(
                        "a float TIFF holds {expected}, but {} is {}",
                        at(k),
                        values[k]
                    )));
                }
                values.iter().map(|v| v / full).collect()
            }
        };
        Self::new(decoded.width, decoded.height, pixels)
    }
}

/// The largest count of a 16-bit file when it stays below 4096 (a 12-bit
/// camera, or a dark frame): the stage then notes that `bit_depth` may be
/// wanted.
pub fn shallow_sixteen_bit(decoded: &DecodedImage) -> Option<u16> {
    match &decoded.samples {
        Samples::Counts { bits: 16, data } => data.iter().copied().max().filter(|&m| m < 4096),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(bits: u8, data: Vec<u16>) -> DecodedImage {
        DecodedImage {
            width: data.len(),
            height: 1,
            samples: Samples::Counts { bits, data },
            kind: "grey TIFF".into(),
        }
    }

    #[test]
    fn counts_map_to_the_cameras_full_scale() {
        let twelve = counts(16, vec![0, 4095, 2048, 1]);
        let container = GrayImage::from_decoded(&twelve, None).unwrap();
        assert_eq!(
            container.pixels,
            [0.0, 4095.0 / 65535.0, 2048.0 / 65535.0, 1.0 / 65535.0]
        );
        let camera = GrayImage::from_decoded(&twelve, Some(12)).unwrap();
        assert_eq!(camera.pixels, [0.0, 1.0, 2048.0 / 4095.0, 1.0 / 4095.0]);
        assert_eq!(shallow_sixteen_bit(&twelve), Some(4095));
        assert_eq!(shallow_sixteen_bit(&counts(16, vec![4096])), None);
        assert_eq!(shallow_sixteen_bit(&counts(8, vec![4])), None);
        let eight = GrayImage::from_decoded(&counts(8, vec![255, 51]), None).unwrap();
        assert_eq!(eight.pixels, [1.0, 0.2]);

        let e = GrayImage::from_decoded(&counts(16, vec![0, 4096]), Some(12))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("pixel (x 1, y 0) is 4096 but a 12-bit camera counts to 4095"),
            "{e}"
        );
        let e = GrayImage::from_decoded(&counts(8, vec![0]), Some(12))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("is a 8-bit grey TIFF but `bit_depth` is 12"),
            "{e}"
        );
    }

    #[test]
    fn floats_are_fractions_or_counts_when_told() {
        let float = |values: Vec<f64>| DecodedImage {
            width: values.len(),
            height: 1,
            samples: Samples::Float(values),
            kind: "float grey TIFF".into(),
        };
        let image = GrayImage::from_decoded(&float(vec![0.0, 0.25, 1.0]), None).unwrap();
        assert_eq!(image.pixels, [0.0, 0.25, 1.0]);
        let image = GrayImage::from_decoded(&float(vec![0.0, 4095.0, 819.0]), Some(12)).unwrap();
        assert_eq!(image.pixels, [0.0, 1.0, 0.2]);
        for bad in [1.5, -0.1, f64::NAN, f64::INFINITY] {
            let e = GrayImage::from_decoded(&float(vec![0.5, bad]), None)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("fractions of full scale") && e.contains("pixel (x 1, y 0)"),
                "{e}"
            );
        }
        let e = GrayImage::from_decoded(&float(vec![5000.0]), Some(12))
            .unwrap_err()
            .to_string();
        assert!(e.contains("counts of a 12-bit camera (0 … 4095"), "{e}");
    }
}
