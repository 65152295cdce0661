//! An open-hole tension image set as a lab's camera leaves it: a folder of
//! 16-bit TIFFs holding 12-bit counts, named so that only natural order is
//! frame order (`oht_2.tif` … `oht_100.tif`), no frames.csv, no force.csv,
//! and a `mask.png` cutting out the hole. The specimen is stretched along
//! the image's y axis (λ_y to 1.08, λ_x = λ_y^−½, incompressible uniaxial)
//! about the image centre, where a hole of radius [`HOLE_PX`] shows an
//! even bright background. The tests of `dic` check against [`STRETCH_Y`];
//! `data/samples/open-hole-tiff/` is this set, written by the example
//! `cargo run -p hypercontact-synth --example open_hole_sample`.

use hypercontact_core::{Files, StageError};

use super::render::{AxisMap, render};
use super::speckle::SpecklePattern;

/// Side of the square frames, pixels.
pub const SIZE: usize = 256;
/// The stretch centre and hole centre, pixels (x and y).
pub const CENTRE: f64 = 128.0;
/// The hole's radius in frame 0, pixels.
pub const HOLE_PX: f64 = 30.0;
/// The loading stretch of each frame, along y.
pub const STRETCH_Y: [f64; 5] = [1.0, 1.02, 1.04, 1.06, 1.08];
/// The number in each frame's file name (`oht_{n}.tif`), in frame order.
pub const FILE_NUMBERS: [i64; 5] = [2, 10, 11, 30, 100];

/// The transverse stretch of an incompressible uniaxial test.
pub fn stretch_x(stretch_y: f64) -> f64 {
    stretch_y.powf(-0.5)
}

/// A 16-bit grey TIFF of `SIZE`² counts (uncompressed, as many cameras
/// write).
fn tiff16(counts: &[u16]) -> Result<Vec<u8>, StageError> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    let fail = |e: tiff::TiffError| StageError::invalid(format!("writing a TIFF: {e}"));
    tiff::encoder::TiffEncoder::new(&mut bytes)
        .map_err(fail)?
        .write_image::<tiff::encoder::colortype::Gray16>(SIZE as u32, SIZE as u32, counts)
        .map_err(fail)?;
    Ok(bytes.into_inner())
}

/// The frames and the mask (the hole and a 3 px margin at 0, the rest 255).
pub fn files() -> Result<Files, StageError> {
    let pattern = SpecklePattern::random([-30.0, -30.0, 290.0, 290.0], 2.5, 0.5, Vec::new(), 7);
    let mut files = Files::new();
    for (k, &l) in STRETCH_Y.iter().enumerate() {
        let map = AxisMap {
            stretch: [stretch_x(l), l],
            ..AxisMap::identity([CENTRE; 2])
        };
        let pixels = render(&pattern, &map, SIZE, SIZE, 2);
        let counts: Vec<u16> = pixels
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                // Inside the hole (material at radius < HOLE_PX in frame 0)
                // the camera sees the bright, even background.
                let x = map.to_reference(0, (i % SIZE) as f64);
                let y = map.to_reference(1, (i / SIZE) as f64);
                let value = if (x - CENTRE).hypot(y - CENTRE) < HOLE_PX {
                    0.95
                } else {
                    p
                };
                (value * 4095.0).round() as u16
            })
            .collect();
        files = files.with(&format!("oht_{}.tif", FILE_NUMBERS[k]), tiff16(&counts)?);
    }
    let mask: Vec<u16> = (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = ((i % SIZE) as f64, (i / SIZE) as f64);
            if (x - CENTRE).hypot(y - CENTRE) < HOLE_PX + 3.0 {
                0
            } else {
                255
            }
        })
        .collect();
    Ok(files.with("mask.png", crate::encode_png(SIZE, SIZE, 8, mask)?))
}
