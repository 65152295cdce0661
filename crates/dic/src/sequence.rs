//! The tensile test's raw files: the lab sequence of
//! [`hypercontact_labfiles::sequence`] (`frames.csv` or the images' names or a
//! frame rate, the images, an optional `force.csv`) and, optionally,
//! `specimen.json` (`mode`, `gauge_width_m`, `thickness_m`, `pixel_m`,
//! `roi_px`, `bit_depth`), in the layout `synth-tensile` writes.

use hypercontact_labfiles::FileSource;
pub use hypercontact_labfiles::sequence::FrameEntry;
use hypercontact_labfiles::sequence::{
    DecodedImage, FrameRate, Layout, Sequence as LabSequence, decode_image,
};
use serde::Deserialize;

use crate::DicError;
use crate::gray::GrayImage;

/// `specimen.json`; every field may be overridden by a parameter.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct Specimen {
    pub mode: Option<String>,
    pub gauge_width_m: Option<f64>,
    pub gauge_length_m: Option<f64>,
    pub thickness_m: Option<f64>,
    pub pixel_m: Option<f64>,
    pub roi_px: Option<[usize; 4]>,
    pub bit_depth: Option<u32>,
}

/// The opened test.
pub struct Sequence<'a> {
    lab: LabSequence<'a>,
    pub specimen: Specimen,
}

impl<'a> Sequence<'a> {
    /// Opens the test's files: force.csv optional (a strain-only
    /// analysis); without frames.csv, `frame_rate_hz` (if given) times the
    /// frames in the natural order of their names; `mask` (a file name) is
    /// not a frame.
    pub fn open(
        source: FileSource<'a>,
        frame_rate_hz: Option<f64>,
        mask: Option<&str>,
    ) -> Result<Self, DicError> {
        let layout = Layout {
            force_optional: true,
            frame_rate: Some(FrameRate {
                param: "frame_rate_hz",
                hz: frame_rate_hz,
            }),
            not_frames: mask.map(str::to_owned).into_iter().collect(),
        };
        let lab = LabSequence::open_with(source, &layout).map_err(DicError::from_stage)?;
        // A mask left beside frames found by their names would be read as a
        // frame: say so rather than fail on its size or depth.
        if mask.is_none()
            && !lab.exists("frames.csv")
            && let Some(entry) = lab.frames.iter().find(|e| {
                e.file
                    .rsplit_once('.')
                    .is_some_and(|(stem, _)| stem.eq_ignore_ascii_case("mask"))
            })
        {
            return Err(DicError::file(
                &lab.display(&entry.file),
                format!(
                    "would be read as a frame: name it in the parameter `mask` (mask: {}) or \
                     move it out of the folder",
                    entry.file
                ),
            ));
        }
        let mut specimen = Specimen::default();
        if lab.exists("specimen.json") {
            let bytes = lab.read("specimen.json").map_err(DicError::from_stage)?;
            specimen = serde_json::from_slice(&bytes).map_err(|e| {
                DicError::file(
                    &lab.display("specimen.json"),
                    format!("not a valid specimen description: {e}"),
                )
            })?;
        }
        Ok(Sequence { lab, specimen })
    }

    /// The frames as frames.csv lists them.
    pub fn frames(&self) -> &[FrameEntry] {
        &self.lab.frames
    }

    /// Whether force.csv was there.
    pub fn has_force(&self) -> bool {
        self.lab.has_force()
    }

    /// Decodes frame `k` (index into `frames`) as stored.
    pub fn decoded(&self, k: usize) -> Result<DecodedImage, DicError> {
        self.lab.decoded(k).map_err(DicError::from_stage)
    }

    /// Frame `k` as fractions of the camera's full scale (`bit_depth` bits
    /// if given, see [`GrayImage::from_decoded`]).
    pub fn image(&self, k: usize, bit_depth: Option<u8>) -> Result<GrayImage, DicError> {
        self.gray(&self.decoded(k)?, k, bit_depth)
    }

    /// A decoded frame `k` as [`Sequence::image`] gives it.
    pub fn gray(
        &self,
        decoded: &DecodedImage,
        k: usize,
        bit_depth: Option<u8>,
    ) -> Result<GrayImage, DicError> {
        GrayImage::from_decoded(decoded, bit_depth).map_err(|e| match e {
            DicError::Invalid(message) => {
                DicError::file(&self.lab.display(&self.frames()[k].file), message)
            }
            other => other,
        })
    }

    /// File `name` of the sequence decoded as an image (a mask).
    pub fn read_image(&self, name: &str) -> Result<DecodedImage, DicError> {
        let bytes = self.lab.read(name).map_err(DicError::from_stage)?;
        decode_image(&self.lab.display(name), &bytes).map_err(DicError::from_stage)
    }

    /// How errors name file `name`.
    pub fn display(&self, name: &str) -> String {
        self.lab.display(name)
    }

    /// The force at `t_s` by linear interpolation of the log; an error names
    /// the frame if the log does not cover it.
    pub fn force_at(&self, t_s: f64, frame: &FrameEntry) -> Result<f64, DicError> {
        self.lab.force_at(t_s, frame).map_err(DicError::from_stage)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Files;

    #[test]
    fn specimen_and_images_come_through_the_lab_sequence() {
        let f = Files::new()
            .with(
                "frames.csv",
                b"frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n".to_vec(),
            )
            .with("force.csv", b"time_s,force_n\n0,0\n1,1\n".to_vec())
            .with(
                "specimen.json",
                b"{\"mode\": \"UT\", \"pixel_m\": 1e-5}".to_vec(),
            )
            .with("a.png", b"not a png".to_vec());
        let source = FileSource::Files {
            files: &f,
            input: "sequence".into(),
        };
        let s = Sequence::open(source, None, None).unwrap();
        assert_eq!(s.specimen.mode.as_deref(), Some("UT"));
        assert_eq!(s.frames().len(), 2);
        let e = s.image(0, None).unwrap_err().to_string();
        assert!(
            e.contains("a.png") && e.contains("not a readable PNG/TIFF"),
            "{e}"
        );
        let e = s.image(1, None).unwrap_err().to_string();
        assert!(
            e.contains("b.png: missing (frames.csv lists it on line 3)"),
            "{e}"
        );
        let bad = Files::new()
            .with(
                "frames.csv",
                b"frame,time_s,file\n0,0.0,a.png\n1,0.5,b.png\n".to_vec(),
            )
            .with("force.csv", b"time_s,force_n\n0,0\n".to_vec())
            .with("specimen.json", b"{".to_vec());
        let source = FileSource::Files {
            files: &bad,
            input: "sequence".into(),
        };
        let e = Sequence::open(source, None, None)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("specimen.json") && e.contains("not a valid specimen"),
            "{e}"
        );
    }
}
