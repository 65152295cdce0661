//! The tensile test's raw files: the lab sequence of
//! [`hypercontact_core::sequence`] (`frames.csv`, the images, `force.csv`)
//! and, optionally, `specimen.json` (`mode`, `gauge_width_m`, `thickness_m`,
//! `pixel_m`, `roi_px`), in the layout `synth-tensile` writes.

use hypercontact_core::FileSource;
pub use hypercontact_core::sequence::FrameEntry;
use hypercontact_core::sequence::Sequence as LabSequence;
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
    pub fn open(source: FileSource<'a>) -> Result<Self, DicError> {
        let lab = LabSequence::open(source).map_err(DicError::from_stage)?;
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

    /// Decodes frame `k` (index into `frames`).
    pub fn image(&self, k: usize) -> Result<GrayImage, DicError> {
        let frame = self.lab.frame(k).map_err(DicError::from_stage)?;
        GrayImage::from_frame(&frame).map_err(|e| match e {
            DicError::Invalid(message) => {
                DicError::file(&self.lab.display(&self.frames()[k].file), message)
            }
            other => other,
        })
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
        let s = Sequence::open(source).unwrap();
        assert_eq!(s.specimen.mode.as_deref(), Some("UT"));
        assert_eq!(s.frames().len(), 2);
        let e = s.image(0).unwrap_err().to_string();
        assert!(
            e.contains("a.png") && e.contains("not a readable PNG/TIFF"),
            "{e}"
        );
        let e = s.image(1).unwrap_err().to_string();
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
        let e = Sequence::open(source).err().unwrap().to_string();
        assert!(
            e.contains("specimen.json") && e.contains("not a valid specimen"),
            "{e}"
        );
    }
}
