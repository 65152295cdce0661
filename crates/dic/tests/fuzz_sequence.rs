//! Property tests of a tensile test's raw files: valid 8- and 16-bit PNG and
//! TIFF frames (and colour PNG) with bytes overwritten, inserted or cut,
//! alone and as a frame of a small sequence through the `dic` stage; and the
//! sequence's logs (`frames.csv`, `force.csv`) and `specimen.json` edited.
//! Never a panic; every error names the file.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property (a few
//! dozen through the stage); `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen
//! or move the search.

use crate::common;

use std::io::Cursor;
use std::sync::OnceLock;

use hypercontact_core::Files;
use hypercontact_dic::{DicParams, GrayImage};
use hypercontact_fuzz::{byte_edits, config, splice};
use hypercontact_synth::encode_png;
use image::{DynamicImage, ImageBuffer, ImageFormat, Luma, Rgb};
use proptest::prelude::*;

#[derive(Clone, Copy, Debug)]
enum Format {
    Png8,
    Png16,
    PngRgb,
    Tiff8,
    Tiff16,
}

fn encode(format: Format, width: u32, height: u32, counts: &[u16]) -> Vec<u8> {
    let n = (width * height) as usize;
    let written = |image: DynamicImage, as_format: ImageFormat| {
        let mut bytes = Cursor::new(Vec::new());
        image.write_to(&mut bytes, as_format).unwrap();
        bytes.into_inner()
    };
    match format {
        Format::Png8 => {
            encode_png(width as usize, height as usize, 8, counts[..n].to_vec()).unwrap()
        }
        Format::Png16 => {
            encode_png(width as usize, height as usize, 16, counts[..n].to_vec()).unwrap()
        }
        Format::PngRgb => written(
            DynamicImage::ImageRgb8(ImageBuffer::from_fn(width, height, |x, y| {
                let c = counts[(y * width + x) as usize];
                Rgb([c as u8, (c >> 8) as u8, (c >> 4) as u8])
            })),
            ImageFormat::Png,
        ),
        Format::Tiff8 => written(
            DynamicImage::ImageLuma8(ImageBuffer::from_fn(width, height, |x, y| {
                Luma([counts[(y * width + x) as usize] as u8])
            })),
            ImageFormat::Tiff,
        ),
        Format::Tiff16 => written(
            DynamicImage::ImageLuma16(ImageBuffer::from_fn(width, height, |x, y| {
                Luma([counts[(y * width + x) as usize]])
            })),
            ImageFormat::Tiff,
        ),
    }
}

/// A valid image of 1…24 × 1…24 pixels in one of the formats.
fn valid_image() -> impl Strategy<Value = (Vec<u8>, (usize, usize), &'static str)> {
    (
        prop_oneof![
            Just(Format::Png8),
            Just(Format::Png16),
            Just(Format::PngRgb),
            Just(Format::Tiff8),
            Just(Format::Tiff16),
        ],
        1u32..=24,
        1u32..=24,
        prop::collection::vec(any::<u16>(), 576),
    )
        .prop_map(|(format, width, height, counts)| {
            let name = match format {
                Format::Tiff8 | Format::Tiff16 => "frame_001.tif",
                _ => "frame_001.png",
            };
            (
                encode(format, width, height, &counts),
                (width as usize, height as usize),
                name,
            )
        })
}

/// CRC-32 (IEEE, as PNG uses it), bit by bit: test code, a few bytes.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Rewrites the CRC of every PNG chunk that is still whole, so an edit
/// reaches the decoder's parsing instead of stopping at the checksum.
fn fix_png_crcs(mut bytes: Vec<u8>) -> Vec<u8> {
    let mut at = 8;
    while at + 12 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let Some(end) = (at + 8).checked_add(len).filter(|&e| e + 4 <= bytes.len()) else {
            break;
        };
        let crc = crc32(&bytes[at + 4..end]);
        bytes[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
    bytes
}

/// Decodes `bytes` as file `name`: an image with its pixels in 0…1, or an
/// error naming the file.
fn decode(name: &str, bytes: &[u8]) -> Option<GrayImage> {
    match GrayImage::decode(name, bytes) {
        Ok(image) => {
            assert_eq!(image.pixels.len(), image.width * image.height);
            assert!(image.pixels.iter().all(|p| (0.0..=1.0).contains(p)));
            Some(image)
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.contains(name),
                "the error does not name the file: {message}"
            );
            None
        }
    }
}

/// [`common::small_sequence`], made once.
fn sequence() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(common::small_sequence)
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn valid_images_decode_with_their_size((bytes, (width, height), name) in valid_image()) {
        let image = decode(name, &bytes).unwrap();
        prop_assert_eq!((image.width, image.height), (width, height));
    }

    #[test]
    fn edited_images_never_panic(
        (bytes, _, name) in valid_image(),
        edits in byte_edits(),
        fix_crcs in any::<bool>(),
    ) {
        let mut bytes = splice(bytes, &edits);
        if fix_crcs && name.ends_with(".png") {
            bytes = fix_png_crcs(bytes);
        }
        decode(name, &bytes);
    }

    #[test]
    fn arbitrary_bytes_behind_an_image_signature_never_panic(
        tiff in any::<bool>(),
        tail in prop::collection::vec(any::<u8>(), 0..400),
    ) {
        let mut bytes = if tiff { b"II*\0".to_vec() } else { b"\x89PNG\r\n\x1a\n".to_vec() };
        bytes.extend_from_slice(&tail);
        decode("frame_009.png", &bytes);
    }
}

proptest! {
    #![proptest_config(config(24))]

    /// A frame edited inside a sequence: the stage errors naming the frame,
    /// or (the edit hit nothing that matters) runs.
    #[test]
    fn an_edited_frame_never_panics_the_stage(edits in byte_edits()) {
        let mut files = sequence().clone();
        let frame = files.files["frame_001.png"].clone();
        files
            .files
            .insert("frame_001.png".into(), fix_png_crcs(splice(frame, &edits)));
        if let Err(e) = common::dic(&files, &DicParams::default()) {
            let message = e.to_string();
            prop_assert!(message.contains("frame_001.png"), "{}", message);
        }
    }
}

/// Values that break a log line.
fn bad_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("NaN".into()),
        Just("inf".into()),
        Just("-1".into()),
        Just("1e300".into()),
        Just("-1e300".into()),
        Just("9223372036854775808".into()),
        Just("0".into()),
        Just("frame_000.png".into()),
        Just("frame_404.png".into()),
        Just("../frame_001.png".into()),
        Just("\"".into()),
        "[ -~]{0,6}",
    ]
}

/// A line-level edit of one of the sequence's text files.
fn text_edits() -> impl Strategy<Value = Vec<(usize, usize, usize, String, bool)>> {
    // (file, line, cell, token, delete the line instead)
    prop::collection::vec(
        (
            0usize..3,
            any::<usize>(),
            0usize..6,
            bad_token(),
            prop::bool::weighted(0.2),
        ),
        1..4,
    )
}

fn edit_text(text: &str, line: usize, cell: usize, token: &str, delete: bool) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    if lines.is_empty() {
        return token.to_owned();
    }
    let at = line % lines.len();
    if delete {
        lines.remove(at);
    } else {
        let mut cells: Vec<String> = lines[at].split(',').map(str::to_owned).collect();
        let c = cell % cells.len();
        cells[c] = token.to_owned();
        lines[at] = cells.join(",");
    }
    lines.join("\n") + "\n"
}

proptest! {
    #![proptest_config(config(64))]

    /// frames.csv, force.csv and specimen.json edited: the stage errors
    /// naming one of them (or a frame they point at), or runs.
    #[test]
    fn edited_logs_never_panic_the_stage(edits in text_edits()) {
        let mut files = sequence().clone();
        let names = ["frames.csv", "force.csv", "specimen.json"];
        for (file, line, cell, token, delete) in &edits {
            let name = names[*file];
            let text = String::from_utf8_lossy(&files.files[name]).into_owned();
            files
                .files
                .insert(name.into(), edit_text(&text, *line, *cell, token, *delete).into_bytes());
        }
        if let Err(e) = common::dic(&files, &DicParams::default()) {
            let message = e.to_string();
            prop_assert!(
                names.iter().any(|n| message.contains(n))
                    || message.contains("frame_")
                    || message.contains("frames.csv lists it")
                    || message.contains("roi_px")
                    || message.contains("gauge_width_m")
                    || message.contains("thickness_m")
                    || message.contains("pixel_m")
                    || message.contains("mode"),
                "{}",
                message
            );
        }
    }
}
