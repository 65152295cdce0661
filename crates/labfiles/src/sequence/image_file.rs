//! A camera's image file as grey samples: grey, colour and palette PNG and
//! TIFF of 8 or 16 bits, and float TIFF, through the `image` crate where it
//! reads the file and the `tiff` crate where `image` 0.25 does not (float
//! grey and palette TIFF). Colour becomes grey by one stated rule
//! ([`LUMA_RULE`]); no value is rescaled here (a 12-bit camera's counts in
//! a 16-bit file stay counts: the reader of the frame knows the camera).

use hypercontact_core::StageError;

/// A decoded grey frame as the camera's integers: row-major
/// (`data[y * width + x]`), `bits` the container's depth (8 or 16; colour
/// files are converted to luma, float TIFFs quantised to 16 bits, see
/// [`GrayFrame::decode`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GrayFrame {
    pub width: usize,
    pub height: usize,
    pub bits: u8,
    pub data: Vec<u16>,
}

/// A decoded image's grey samples before any scaling.
#[derive(Clone, Debug, PartialEq)]
pub enum Samples {
    /// Integer counts in a `bits`-bit container (8 or 16).
    Counts { bits: u8, data: Vec<u16> },
    /// A float TIFF's values, as stored.
    Float(Vec<f64>),
}

/// A decoded image: row-major samples (`[y * width + x]`) and what the
/// file was (`16-bit grey TIFF`), for messages.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedImage {
    pub width: usize,
    pub height: usize,
    pub samples: Samples,
    pub kind: String,
}

/// Colour to grey: Y = 0.2126 R + 0.7152 G + 0.0722 B on the stored
/// (gamma-encoded) values, rounded to the nearest count; alpha ignored.
/// Rec. 709 / sRGB luma weights, the ones the `image` crate converts with.
pub const LUMA_RULE: &str = "Y = 0.2126 R + 0.7152 G + 0.0722 B of the stored values, \
     rounded to the nearest count (Rec. 709 weights), alpha ignored";

/// [`LUMA_RULE`] in exact integer arithmetic (at most 65535 · 10⁴ + 5000,
/// inside u32).
fn luma(r: u16, g: u16, b: u16) -> u16 {
    let y = (2126 * u32::from(r) + 7152 * u32::from(g) + 722 * u32::from(b) + 5000) / 10_000;
    y as u16
}

/// Every `stride`-th pixel's first three samples through [`luma`].
fn luma_of<T: Copy + Into<u16>>(raw: &[T], stride: usize) -> Vec<u16> {
    raw.chunks_exact(stride)
        .map(|p| luma(p[0].into(), p[1].into(), p[2].into()))
        .collect()
}

/// [`luma_of`] for float colour samples, kept as floats.
fn float_luma_of(raw: &[f32], stride: usize) -> Vec<f64> {
    raw.chunks_exact(stride)
        .map(|c| 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]))
        .collect()
}

/// Decodes a PNG or TIFF file's bytes to grey samples; `name` labels
/// errors. Grey and colour PNG/TIFF of 8 or 16 bits (and 1/2/4-bit grey
/// PNG, widened to 8 bits) come from the `image` crate; palette (indexed)
/// PNGs too, expanded to colour. Two kinds `image` 0.25 refuses are read
/// with the `tiff` crate: grey float TIFFs (32 or 64 bit, kept as floats)
/// and palette TIFFs (8- or 16-bit indices; each pixel becomes its
/// colour-map entry, 16-bit, through [`LUMA_RULE`]). Colour becomes grey by
/// [`LUMA_RULE`]. Both decoders bound their allocations (`image`: 512 MiB,
/// `tiff`: 256 MiB), so a header claiming a huge image is refused.
pub fn decode_image(name: &str, bytes: &[u8]) -> Result<DecodedImage, StageError> {
    // Classic TIFF and BigTIFF (`image` guesses only the first by its
    // signature, but decodes both).
    let tiff = [&b"II*\0"[..], b"MM\0*", b"II+\0", b"MM\0+"]
        .iter()
        .any(|magic| bytes.starts_with(magic));
    if tiff && let Some(decoded) = special_tiff(name, bytes)? {
        return Ok(decoded);
    }
    let decoded = if tiff {
        image::load_from_memory_with_format(bytes, image::ImageFormat::Tiff)
    } else {
        image::load_from_memory(bytes)
    };
    let decoded = decoded
        .map_err(|e| StageError::file(name, format!("not a readable PNG/TIFF image: {e}")))?;
    let (width, height) = (decoded.width() as usize, decoded.height() as usize);
    let kind = format!("{:?} image", decoded.color());
    use image::DynamicImage as D;
    let counts = |bits: u8, data: Vec<u16>| Samples::Counts { bits, data };
    let samples = match decoded {
        D::ImageRgb8(p) => counts(8, luma_of(p.as_raw(), 3)),
        D::ImageRgba8(p) => counts(8, luma_of(p.as_raw(), 4)),
        D::ImageRgb16(p) => counts(16, luma_of(p.as_raw(), 3)),
        D::ImageRgba16(p) => counts(16, luma_of(p.as_raw(), 4)),
        D::ImageRgb32F(p) => Samples::Float(float_luma_of(p.as_raw(), 3)),
        D::ImageRgba32F(p) => Samples::Float(float_luma_of(p.as_raw(), 4)),
        // Grey (with or without alpha): the grey samples.
        D::ImageLuma16(_) | D::ImageLumaA16(_) => counts(16, decoded.into_luma16().into_raw()),
        other => counts(
            8,
            other
                .into_luma8()
                .into_raw()
                .into_iter()
                .map(u16::from)
                .collect(),
        ),
    };
    checked_size(name, width, height, samples, kind)
}

fn checked_size(
    name: &str,
    width: usize,
    height: usize,
    samples: Samples,
    kind: String,
) -> Result<DecodedImage, StageError> {
    let n = match &samples {
        Samples::Counts { data, .. } => data.len(),
        Samples::Float(data) => data.len(),
    };
    if width == 0 || height == 0 || n != width * height {
        return Err(StageError::file(
            name,
            format!("an image of {width} × {height} pixels holding {n} values"),
        ));
    }
    Ok(DecodedImage {
        width,
        height,
        samples,
        kind,
    })
}

/// A grey float or a palette TIFF, which `image` refuses; `None` for any
/// other TIFF (left to `image`).
fn special_tiff(name: &str, bytes: &[u8]) -> Result<Option<DecodedImage>, StageError> {
    use tiff::decoder::{Decoder, DecodingResult};
    use tiff::tags::{PhotometricInterpretation, SampleFormat, Tag};
    let tiff_error =
        |e: tiff::TiffError| StageError::file(name, format!("not a readable TIFF: {e}"));
    if let Some((at, photometric)) = photometric_entry(bytes)
        && photometric == PhotometricInterpretation::RGBPalette.to_u16()
    {
        return palette_tiff(name, bytes, at).map(Some);
    }
    let Ok(mut decoder) = Decoder::new(std::io::Cursor::new(bytes)) else {
        return Ok(None);
    };
    let float = decoder
        .find_tag_unsigned_vec::<u16>(Tag::SampleFormat)
        .ok()
        .flatten()
        .is_some_and(|f| f.first() == Some(&SampleFormat::IEEEFP.to_u16()));
    if !float || !matches!(decoder.colortype(), Ok(tiff::ColorType::Gray(_))) {
        return Ok(None);
    }
    let (width, height) = decoder.dimensions().map_err(tiff_error)?;
    let values: Vec<f64> = match decoder.read_image().map_err(tiff_error)? {
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        _ => {
            return Err(StageError::file(
                name,
                "a float TIFF of other than 32 or 64 bits (read: grey 32/64-bit float)",
            ));
        }
    };
    checked_size(
        name,
        width as usize,
        height as usize,
        Samples::Float(values),
        "float grey TIFF".into(),
    )
    .map(Some)
}

/// A palette TIFF: the `tiff` crate (0.11) refuses palette images, so the
/// indices are read as grey from a copy whose PhotometricInterpretation
/// (at byte `at`) says BlackIsZero (TIFF 6.0, section 5: indices are stored
/// as grey samples are), then looked up in the ColorMap.
fn palette_tiff(name: &str, bytes: &[u8], at: usize) -> Result<DecodedImage, StageError> {
    use tiff::decoder::{Decoder, DecodingResult};
    use tiff::tags::Tag;
    let error = |what: String| StageError::file(name, format!("palette TIFF: {what}"));
    let mut patched = bytes.to_vec();
    let one = if bytes.starts_with(b"II") {
        1u16.to_le_bytes()
    } else {
        1u16.to_be_bytes()
    };
    patched[at..at + 2].copy_from_slice(&one);
    let mut grey = Decoder::new(std::io::Cursor::new(patched)).map_err(|e| error(e.to_string()))?;
    let map = grey
        .get_tag_u16_vec(Tag::ColorMap)
        .map_err(|e| error(format!("no readable ColorMap tag ({e})")))?;
    let (width, height) = grey.dimensions().map_err(|e| error(e.to_string()))?;
    let bits = grey.colortype().map_err(|e| error(e.to_string()))?;
    let indices: Vec<usize> = match (bits, grey.read_image().map_err(|e| error(e.to_string()))?) {
        (tiff::ColorType::Gray(8), DecodingResult::U8(v)) => {
            v.into_iter().map(usize::from).collect()
        }
        (tiff::ColorType::Gray(16), DecodingResult::U16(v)) => {
            v.into_iter().map(usize::from).collect()
        }
        (bits, _) => {
            return Err(error(format!(
                "indices of {} bits (read: 8 or 16)",
                bits.bit_depth()
            )));
        }
    };
    let entries = map.len() / 3;
    if entries == 0 || map.len() % 3 != 0 {
        return Err(error(format!(
            "a ColorMap of {} values (expected 3 × the number of colours)",
            map.len()
        )));
    }
    let mut data = Vec::with_capacity(indices.len());
    for (k, &i) in indices.iter().enumerate() {
        if i >= entries {
            return Err(error(format!(
                "pixel (x {}, y {}) has index {i} but the ColorMap holds {entries} colours",
                k % (width as usize).max(1),
                k / (width as usize).max(1)
            )));
        }
        data.push(luma(map[i], map[entries + i], map[2 * entries + i]));
    }
    checked_size(
        name,
        width as usize,
        height as usize,
        Samples::Counts { bits: 16, data },
        "palette TIFF".into(),
    )
}

/// Where the first image directory's PhotometricInterpretation value sits
/// (byte offset) and what it says, read from the raw bytes (classic TIFF
/// and BigTIFF layouts, TIFF 6.0 section 2 and the BigTIFF design note);
/// `None` if the directory or the entry lies outside the file.
fn photometric_entry(bytes: &[u8]) -> Option<(usize, u16)> {
    let little = bytes.starts_with(b"II");
    let take = |at: usize, n: usize| -> Option<u64> {
        let b = bytes.get(at..at.checked_add(n)?)?;
        let mut v = 0u64;
        for k in 0..n {
            let byte = if little { b[n - 1 - k] } else { b[k] };
            v = (v << 8) | u64::from(byte);
        }
        Some(v)
    };
    let big = take(2, 2)? == 43;
    // (first entry, entry count, entry size, value offset in an entry)
    let (first, count, entry, value) = if big {
        let ifd = usize::try_from(take(8, 8)?).ok()?;
        (ifd.checked_add(8)?, take(ifd, 8)?, 20, 12)
    } else {
        let ifd = usize::try_from(take(4, 4)?).ok()?;
        (ifd.checked_add(2)?, take(ifd, 2)?, 12, 8)
    };
    // Entries are sorted by tag; stop at the first one past 262.
    for k in 0..count.min(4096) as usize {
        let at = first.checked_add(k * entry)?;
        let tag = take(at, 2)?;
        if tag == 262 {
            // A SHORT value sits in the entry's first value bytes.
            let at = at.checked_add(value)?;
            return Some((at, take(at, 2)? as u16));
        }
        if tag > 262 {
            return None;
        }
    }
    None
}

impl GrayFrame {
    /// Decodes a PNG or TIFF file's bytes ([`decode_image`]); `name`
    /// labels errors. A float TIFF's values must be fractions of full
    /// scale (0 … 1, finite) and are quantised to 16 bits.
    pub fn decode(name: &str, bytes: &[u8]) -> Result<Self, StageError> {
        let decoded = decode_image(name, bytes)?;
        let (bits, data) = match decoded.samples {
            Samples::Counts { bits, data } => (bits, data),
            Samples::Float(values) => {
                let mut data = Vec::with_capacity(values.len());
                for (k, v) in values.into_iter().enumerate() {
                    if !(0.0..=1.0).contains(&v) {
                        return Err(StageError::file(
                            name,
                            format!(
                                "a float TIFF holds fractions of full scale (0 … 1), but pixel \
                                 (x {}, y {}) is {v}",
                                k % decoded.width,
                                k / decoded.width
                            ),
                        ));
                    }
                    data.push((v * 65535.0).round() as u16);
                }
                (16, data)
            }
        };
        Ok(GrayFrame {
            width: decoded.width,
            height: decoded.height,
            bits,
            data,
        })
    }

    /// The container's full scale, 2^bits − 1.
    pub fn full_scale(&self) -> f64 {
        f64::from((1u32 << self.bits) - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{DynamicImage, ImageBuffer, ImageFormat, Luma, Rgb, Rgba};
    use std::io::Cursor;
    use tiff::encoder::{TiffEncoder, colortype};
    use tiff::tags::{PhotometricInterpretation, SampleFormat, Tag};

    fn written(image: DynamicImage, format: ImageFormat) -> Vec<u8> {
        let mut bytes = Cursor::new(Vec::new());
        image.write_to(&mut bytes, format).unwrap();
        bytes.into_inner()
    }

    fn counts(bytes: &[u8]) -> (u8, Vec<u16>) {
        match decode_image("f", bytes).unwrap().samples {
            Samples::Counts { bits, data } => (bits, data),
            other => panic!("{other:?}"),
        }
    }

    /// 8-bit palette indices, for writing a palette TIFF with `tiff`.
    struct Palette8;
    impl colortype::ColorType for Palette8 {
        type Inner = u8;
        const TIFF_VALUE: PhotometricInterpretation = PhotometricInterpretation::RGBPalette;
        const BITS_PER_SAMPLE: &'static [u16] = &[8];
        const SAMPLE_FORMAT: &'static [SampleFormat] = &[SampleFormat::Uint];
        fn horizontal_predict(_: &[u8], _: &mut Vec<u8>) {}
    }

    fn palette_tiff(big: bool, indices: &[u8], map: &[u16]) -> Vec<u8> {
        let mut bytes = Cursor::new(Vec::new());
        macro_rules! write {
            ($encoder:expr) => {{
                let mut encoder = $encoder.unwrap();
                let mut image = encoder.new_image::<Palette8>(3, 2).unwrap();
                image.encoder().write_tag(Tag::ColorMap, map).unwrap();
                image.write_data(indices).unwrap();
            }};
        }
        if big {
            write!(TiffEncoder::new_big(&mut bytes));
        } else {
            write!(TiffEncoder::new(&mut bytes));
        }
        bytes.into_inner()
    }

    #[test]
    fn grey_files_keep_their_counts_and_container() {
        let values: Vec<u16> = vec![0, 1, 200, 4095, 4000, 17];
        let grey8 = ImageBuffer::from_fn(3, 2, |x, y| Luma([values[(y * 3 + x) as usize] as u8]));
        let grey16 = ImageBuffer::from_fn(3, 2, |x, y| Luma([values[(y * 3 + x) as usize]]));
        let as8: Vec<u16> = values.iter().map(|&v| u16::from(v as u8)).collect();
        for format in [ImageFormat::Png, ImageFormat::Tiff] {
            let bytes = written(DynamicImage::ImageLuma8(grey8.clone()), format);
            assert_eq!(counts(&bytes), (8, as8.clone()), "{format:?}");
            // A 12-bit camera's counts in a 16-bit file: unchanged.
            let bytes = written(DynamicImage::ImageLuma16(grey16.clone()), format);
            assert_eq!(counts(&bytes), (16, values.clone()), "{format:?}");
        }
    }

    #[test]
    fn colour_becomes_rec_709_luma_rounded() {
        let rgb = [[255u8, 0, 0], [0, 255, 0], [0, 0, 255], [10, 20, 30]];
        // 0.2126 R + 0.7152 G + 0.0722 B by hand: 54.213, 182.376, 18.411,
        // 18.596, rounded.
        let expected = [54u16, 182, 18, 19];
        let image = ImageBuffer::from_fn(4, 1, |x, _| Rgb(rgb[x as usize]));
        let bytes = written(DynamicImage::ImageRgb8(image), ImageFormat::Png);
        assert_eq!(counts(&bytes), (8, expected.to_vec()));
        // Alpha is ignored.
        let image = ImageBuffer::from_fn(4, 1, |x, _| {
            let [r, g, b] = rgb[x as usize];
            Rgba([r, g, b, 7])
        });
        let bytes = written(DynamicImage::ImageRgba8(image), ImageFormat::Tiff);
        assert_eq!(counts(&bytes), (8, expected.to_vec()));
        let rgb16 = ImageBuffer::from_fn(1, 1, |_, _| Rgb([1000u16, 2000, 40000]));
        let bytes = written(DynamicImage::ImageRgb16(rgb16), ImageFormat::Tiff);
        assert_eq!(
            counts(&bytes),
            // 212.6 + 1430.4 + 2888.0 = 4531.0
            (16, vec![4531])
        );
    }

    #[test]
    fn palette_png_is_its_colours() {
        // Index i → grey 3 i, except index 2 → pure green.
        let mut palette = Vec::new();
        for i in 0..4u8 {
            palette.extend_from_slice(&if i == 2 { [0, 255, 0] } else { [3 * i; 3] });
        }
        let mut bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut bytes, 4, 1);
            encoder.set_color(png::ColorType::Indexed);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_palette(palette);
            let mut writer = encoder.write_header().unwrap();
            writer.write_image_data(&[3, 2, 1, 0]).unwrap();
        }
        assert_eq!(counts(&bytes), (8, vec![9, 182, 3, 0]));
    }

    #[test]
    fn palette_tiff_is_its_colour_map_in_16_bits() {
        // A grey map (v · 257, as 8-bit software writes it) and one red entry.
        let mut map = vec![0u16; 768];
        for i in 0..256 {
            for c in 0..3 {
                map[c * 256 + i] = i as u16 * 257;
            }
        }
        map[5] = 65535;
        map[256 + 5] = 0;
        map[512 + 5] = 0;
        for big in [false, true] {
            let bytes = palette_tiff(big, &[0, 1, 2, 200, 255, 5], &map);
            let decoded = decode_image("p.tif", &bytes).unwrap();
            assert_eq!(decoded.kind, "palette TIFF");
            assert_eq!(
                decoded.samples,
                Samples::Counts {
                    bits: 16,
                    // red: 0.2126 · 65535 = 13932.74
                    data: vec![0, 257, 514, 200 * 257, 65535, 13933]
                },
                "BigTIFF {big}"
            );
        }
        // An index beyond a short map names the pixel.
        let bytes = palette_tiff(false, &[0, 1, 2, 3, 4, 9], &map[..]);
        let short: Vec<u16> = (0..3).flat_map(|_| 0..8u16).collect();
        let bad = palette_tiff(false, &[0, 1, 2, 3, 4, 9], &short);
        assert!(decode_image("p.tif", &bytes).is_ok());
        let e = decode_image("p.tif", &bad).unwrap_err().to_string();
        assert!(
            e.contains("p.tif: palette TIFF: pixel (x 2, y 1) has index 9")
                && e.contains("8 colours"),
            "{e}"
        );
    }

    #[test]
    fn float_tiff_keeps_its_values() {
        let values = [0.0f32, 0.25, 0.5, 1.0, 0.123_456_79, 1.5];
        let mut bytes = Cursor::new(Vec::new());
        TiffEncoder::new(&mut bytes)
            .unwrap()
            .write_image::<colortype::Gray32Float>(3, 2, &values)
            .unwrap();
        let bytes = bytes.into_inner();
        let decoded = decode_image("f.tif", &bytes).unwrap();
        assert_eq!((decoded.width, decoded.height), (3, 2));
        assert_eq!(
            decoded.samples,
            Samples::Float(values.iter().map(|&v| f64::from(v)).collect())
        );
        // As camera counts: fractions of full scale only.
        let e = GrayFrame::decode("f.tif", &bytes).unwrap_err().to_string();
        assert!(
            e.contains("f.tif") && e.contains("pixel (x 2, y 1) is 1.5"),
            "{e}"
        );
        let mut bytes = Cursor::new(Vec::new());
        TiffEncoder::new(&mut bytes)
            .unwrap()
            .write_image::<colortype::Gray64Float>(2, 1, &[0.5f64, 1.0 / 3.0])
            .unwrap();
        let bytes = bytes.into_inner();
        assert_eq!(
            decode_image("f.tif", &bytes).unwrap().samples,
            Samples::Float(vec![0.5, 1.0 / 3.0])
        );
        let frame = GrayFrame::decode("f.tif", &bytes).unwrap();
        assert_eq!((frame.bits, frame.data), (16, vec![32768, 21845]));
    }

    #[test]
    fn unreadable_files_name_the_file() {
        for bytes in [
            &b"II*\0\x08\0\0\0"[..],
            b"MM\0*",
            b"\x89PNG\r\n\x1a\n",
            b"plain text",
        ] {
            let e = decode_image("x.tif", bytes).unwrap_err().to_string();
            assert!(e.starts_with("x.tif: "), "{e}");
        }
    }

    fn float_tiff() -> Vec<u8> {
        let mut bytes = Cursor::new(Vec::new());
        TiffEncoder::new(&mut bytes)
            .unwrap()
            .write_image::<colortype::Gray32Float>(3, 2, &[0.5f32; 6])
            .unwrap();
        bytes.into_inner()
    }

    fn grey_map() -> Vec<u16> {
        (0..3).flat_map(|_| (0..256u16).map(|i| i * 257)).collect()
    }

    /// Sets a classic little-endian TIFF's first-IFD entry `tag` to the
    /// LONG `value`.
    fn set_long(mut bytes: Vec<u8>, tag: u16, value: u32) -> Vec<u8> {
        let ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
        let count = u16::from_le_bytes(bytes[ifd..ifd + 2].try_into().unwrap()) as usize;
        for k in 0..count {
            let at = ifd + 2 + 12 * k;
            if u16::from_le_bytes(bytes[at..at + 2].try_into().unwrap()) == tag {
                bytes[at + 2..at + 4].copy_from_slice(&4u16.to_le_bytes());
                bytes[at + 4..at + 8].copy_from_slice(&1u32.to_le_bytes());
                bytes[at + 8..at + 12].copy_from_slice(&value.to_le_bytes());
                return bytes;
            }
        }
        panic!("no tag {tag}")
    }

    #[test]
    fn a_header_claiming_a_huge_image_is_refused_before_allocating() {
        let palette = palette_tiff(false, &[0; 6], &grey_map());
        for bytes in [float_tiff(), palette] {
            let huge = set_long(set_long(bytes, 256, 1_000_000_000), 257, 1_000_000_000);
            let e = decode_image("h.tif", &huge).unwrap_err().to_string();
            assert!(e.starts_with("h.tif: "), "{e}");
        }
    }

    proptest::proptest! {
        #![proptest_config(hypercontact_fuzz::config(256))]

        /// Edited float and palette TIFFs (the readers written here) and
        /// arbitrary bytes behind a TIFF signature: an error naming the
        /// file, never a panic.
        #[test]
        fn edited_tiffs_never_panic(
            palette in proptest::bool::ANY,
            edits in hypercontact_fuzz::byte_edits(),
        ) {
            let bytes = if palette {
                palette_tiff(false, &[0, 1, 2, 3, 4, 5], &grey_map())
            } else {
                float_tiff()
            };
            if let Err(e) = decode_image("e.tif", &hypercontact_fuzz::splice(bytes, &edits)) {
                proptest::prop_assert!(e.to_string().starts_with("e.tif: "));
            }
        }

        #[test]
        fn arbitrary_bytes_never_panic(
            magic in 0usize..4,
            tail in proptest::collection::vec(proptest::num::u8::ANY, 0..600),
        ) {
            let mut bytes = [&b"II*\0"[..], b"MM\0*", b"II+\0", b"MM\0+"][magic].to_vec();
            bytes.extend_from_slice(&tail);
            let _ = decode_image("a.tif", &bytes);
            let _ = GrayFrame::decode("a.tif", &bytes);
        }
    }
}
