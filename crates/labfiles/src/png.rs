//! PNG files a stage writes (camera frames of the synthetic lab, report
//! figures): one encoder, on the `image` crate's.

use std::io::Cursor;

/// Pixels, row-major, of one of the layouts stages write.
#[derive(Clone, Debug, PartialEq)]
pub enum Pixels {
    Gray8(Vec<u8>),
    /// 16-bit gray, as scientific cameras save.
    Gray16(Vec<u16>),
    /// 8-bit RGB, three bytes per pixel.
    Rgb8(Vec<u8>),
}

/// The PNG bytes of a `width` × `height` image; an error says why (a
/// buffer that does not match the size).
pub fn encode_png(width: u32, height: u32, pixels: Pixels) -> Result<Vec<u8>, String> {
    let mismatch = || format!("the pixel buffer does not match {width} × {height}");
    let image = match pixels {
        Pixels::Gray8(p) => {
            image::GrayImage::from_raw(width, height, p).map(image::DynamicImage::ImageLuma8)
        }
        Pixels::Gray16(p) => image::ImageBuffer::<image::Luma<u16>, _>::from_raw(width, height, p)
            .map(image::DynamicImage::ImageLuma16),
        Pixels::Rgb8(p) => {
            image::RgbImage::from_raw(width, height, p).map(image::DynamicImage::ImageRgb8)
        }
    }
    .ok_or_else(mismatch)?;
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| format!("PNG encoding failed: {e}"))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_layout_round_trips_through_a_decoder() {
        let gray16: Vec<u16> = (0..12).map(|i| i * 5000).collect();
        let png = encode_png(4, 3, Pixels::Gray16(gray16.clone())).unwrap();
        let back = image::load_from_memory(&png).unwrap().into_luma16();
        assert_eq!(back.into_raw(), gray16);
        let rgb: Vec<u8> = (0..36).collect();
        let png = encode_png(4, 3, Pixels::Rgb8(rgb.clone())).unwrap();
        assert_eq!(
            image::load_from_memory(&png)
                .unwrap()
                .into_rgb8()
                .into_raw(),
            rgb
        );
        let png = encode_png(2, 1, Pixels::Gray8(vec![0, 255])).unwrap();
        assert_eq!(
            image::load_from_memory(&png)
                .unwrap()
                .into_luma8()
                .into_raw(),
            [0, 255]
        );
        assert!(encode_png(4, 4, Pixels::Gray8(vec![0; 3])).is_err());
    }
}
