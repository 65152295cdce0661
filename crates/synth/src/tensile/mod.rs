//! Stage `synth-tensile`: what a lab writes during a UT, PT or BT test of the
//! paper's section 2: a speckle image sequence of the gauge section, the
//! frame times, a 50 Hz force log and the specimen's geometry, plus, apart,
//! the ground truth that made them.
//!
//! Files of the `sequence` product (the layout the `dic` stage reads, also
//! from a folder of real data):
//! - `frame_000.png` …: 8- or 16-bit grayscale;
//! - `frames.csv`: `frame, time_s, file`;
//! - `force.csv`: `time_s, force_n`;
//! - `specimen.json`: `mode`, `gauge_width_m`, `gauge_length_m`,
//!   `thickness_m`, `pixel_m`, `roi_px` ([x0, y0, x1, y1], frame-0 pixels).

pub mod experiment;
pub mod render;
pub mod speckle;

use std::io::Cursor;

use hypercontact_core::params::{in_range, positive};
use hypercontact_core::{
    ColumnSpec, Context, Files, Inputs, OutputSpec, Outputs, ParamDoc, ParamError, Params,
    ProductKind, Stage, StageError, StageInfo, Table,
};
use hypercontact_material::{Mode, presets};
use serde::{Deserialize, Serialize};

use experiment::{Experiment, Recipe, expose, in_plane_stretches};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SynthTensileParams {
    /// `UT`, `PT` or `BT`.
    pub mode: String,
    /// Ground-truth material preset.
    pub preset: String,
    /// Final loading stretch; default UT 2.5, PT 2.0, BT 1.5.
    pub max_stretch: Option<f64>,
    pub frames: usize,
    pub frame_interval_s: f64,
    pub width_px: usize,
    pub height_px: usize,
    /// 8 or 16.
    pub bit_depth: u32,
    /// Camera noise, standard deviation as a fraction of full scale.
    pub noise: f64,
    pub speckle_radius_px: f64,
    /// Fraction of the surface the spray covers (before overlaps).
    pub speckle_coverage: f64,
    /// Sub-samples per pixel side.
    pub supersample: usize,
    /// Paint four marker dots for the `markers` method.
    pub markers: bool,
    pub marker_radius_px: f64,
    /// Object-space size of a pixel, metres.
    pub pixel_m: f64,
    /// Gauge width, length and thickness; default the paper's per mode.
    pub gauge_width_m: Option<f64>,
    pub gauge_length_m: Option<f64>,
    pub thickness_m: Option<f64>,
    /// Force sensor resolution; default the paper's per mode.
    pub force_resolution_n: Option<f64>,
    pub force_rate_hz: f64,
    pub seed: u64,
}

impl Default for SynthTensileParams {
    fn default() -> Self {
        Self {
            mode: "UT".into(),
            preset: "paper-epdm".into(),
            max_stretch: None,
            frames: 20,
            frame_interval_s: 0.5,
            width_px: 512,
            height_px: 512,
            bit_depth: 16,
            noise: 0.005,
            speckle_radius_px: 2.5,
            speckle_coverage: 0.5,
            supersample: 4,
            markers: true,
            marker_radius_px: 6.0,
            pixel_m: 2e-5,
            gauge_width_m: None,
            gauge_length_m: None,
            thickness_m: None,
            force_resolution_n: None,
            force_rate_hz: 50.0,
            seed: 1,
        }
    }
}

impl SynthTensileParams {
    pub fn test_mode(&self) -> Result<Mode, ParamError> {
        Mode::from_label(&self.mode).ok_or_else(|| {
            ParamError::new("mode", format!("must be UT, PT or BT, got `{}`", self.mode))
        })
    }

    pub fn max_stretch(&self) -> Result<f64, ParamError> {
        Ok(self.max_stretch.unwrap_or(match self.test_mode()? {
            Mode::Uniaxial => 2.5,
            Mode::Planar => 2.0,
            Mode::Equibiaxial => 1.5,
        }))
    }

    /// Gauge width, length and thickness, metres.
    pub fn geometry_m(&self) -> Result<[f64; 3], ParamError> {
        let paper = experiment::paper_geometry_m(self.test_mode()?);
        Ok([
            self.gauge_width_m.unwrap_or(paper[0]),
            self.gauge_length_m.unwrap_or(paper[1]),
            self.thickness_m.unwrap_or(paper[2]),
        ])
    }

    pub fn recipe(&self) -> Result<Recipe, ParamError> {
        Ok(Recipe {
            mode: self.test_mode()?,
            max_stretch: self.max_stretch()?,
            frames: self.frames,
            frame_interval_s: self.frame_interval_s,
            width_px: self.width_px,
            height_px: self.height_px,
            speckle_radius_px: self.speckle_radius_px,
            speckle_coverage: self.speckle_coverage,
            supersample: self.supersample,
            markers: self.markers,
            marker_radius_px: self.marker_radius_px,
            seed: self.seed,
        })
    }
}

impl Params for SynthTensileParams {
    fn check(&self) -> Result<(), ParamError> {
        self.test_mode()?;
        presets::preset(&self.preset).map_err(|e| ParamError::new("preset", e.to_string()))?;
        let max_stretch = self.max_stretch()?;
        if !(max_stretch > 1.0 && max_stretch <= 10.0) {
            return Err(ParamError::new(
                "max_stretch",
                format!("must lie in (1, 10], got {max_stretch}"),
            ));
        }
        if !(2..=100_000).contains(&self.frames) {
            return Err(ParamError::new(
                "frames",
                format!("must be 2 … 100000, got {}", self.frames),
            ));
        }
        positive("frame_interval_s", self.frame_interval_s)?;
        for (name, v) in [("width_px", self.width_px), ("height_px", self.height_px)] {
            if !(64..=16384).contains(&v) {
                return Err(ParamError::new(
                    name,
                    format!("must be 64 … 16384, got {v}"),
                ));
            }
        }
        if self.bit_depth != 8 && self.bit_depth != 16 {
            return Err(ParamError::new(
                "bit_depth",
                format!("must be 8 or 16, got {}", self.bit_depth),
            ));
        }
        in_range("noise", self.noise, 0.0, 0.5)?;
        in_range("speckle_radius_px", self.speckle_radius_px, 0.5, 50.0)?;
        in_range("speckle_coverage", self.speckle_coverage, 0.01, 5.0)?;
        if !(1..=16).contains(&self.supersample) {
            return Err(ParamError::new(
                "supersample",
                format!("must be 1 … 16, got {}", self.supersample),
            ));
        }
        in_range("marker_radius_px", self.marker_radius_px, 1.0, 100.0)?;
        positive("pixel_m", self.pixel_m)?;
        let [w, l, t] = self.geometry_m()?;
        positive("gauge_width_m", w)?;
        positive("gauge_length_m", l)?;
        positive("thickness_m", t)?;
        if let Some(r) = self.force_resolution_n {
            positive("force_resolution_n", r)?;
        }
        positive("force_rate_hz", self.force_rate_hz)
    }
}

/// The `synth-tensile` stage.
pub struct SynthTensile;

const TRUTH_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::i64("frame", "", "frame index"),
    ColumnSpec::f64("time_s", "s", "frame time"),
    ColumnSpec::f64("stretch", "", "true loading stretch λ (along x)"),
    ColumnSpec::f64(
        "stretch_2",
        "",
        "true in-plane transverse stretch (along y)",
    ),
    ColumnSpec::f64(
        "nominal_stress_pa",
        "Pa",
        "true nominal stress of the preset",
    ),
    ColumnSpec::f64("force_n", "N", "true force (noise-free)"),
    ColumnSpec::str("mode", "UT, PT or BT"),
];

static INFO: StageInfo = StageInfo {
    kind: "synth-tensile",
    version: 1,
    summary: "Synthetic UT/PT/BT tensile test: speckle images, frame times, force log, specimen",
    doc: "Renders a sprayed speckle pattern (Gaussian blobs, saturating optical density, four \
          painted marker dots) at each homogeneously deformed state, evaluating the pattern at \
          the inverse-mapped reference coordinate of sub-samples of every pixel (no image \
          interpolation), then adds camera noise and quantises to 8 or 16 bits. Loading is \
          along x about the image centre: UT (λ, λ^-1/2), PT (λ, 1), BT (λ, λ), λ linear in \
          time. The force log (default 50 Hz) is the preset's nominal stress × the undeformed \
          cross-section (gauge width × thickness) plus sensor noise, quantised to the paper's \
          resolutions (UT 0.01 N, PT 0.1 N, BT 0.01 N). The ground truth goes to separate \
          outputs the dic stage never reads.",
    params: &[
        ParamDoc {
            name: "mode",
            unit: "",
            doc: "UT, PT or BT",
        },
        ParamDoc {
            name: "preset",
            unit: "",
            doc: "ground-truth material preset (paper-epdm)",
        },
        ParamDoc {
            name: "max_stretch",
            unit: "",
            doc: "final stretch (default UT 2.5, PT 2.0, BT 1.5)",
        },
        ParamDoc {
            name: "frames",
            unit: "",
            doc: "number of frames (20)",
        },
        ParamDoc {
            name: "frame_interval_s",
            unit: "s",
            doc: "time between frames (0.5)",
        },
        ParamDoc {
            name: "width_px",
            unit: "",
            doc: "image width (512; the paper's camera: 2048)",
        },
        ParamDoc {
            name: "height_px",
            unit: "",
            doc: "image height (512)",
        },
        ParamDoc {
            name: "bit_depth",
            unit: "",
            doc: "8 or 16 (16)",
        },
        ParamDoc {
            name: "noise",
            unit: "",
            doc: "camera noise std, fraction of full scale (0.005)",
        },
        ParamDoc {
            name: "speckle_radius_px",
            unit: "",
            doc: "mean speckle radius, pixels (2.5)",
        },
        ParamDoc {
            name: "speckle_coverage",
            unit: "",
            doc: "sprayed fraction of the surface (0.5)",
        },
        ParamDoc {
            name: "supersample",
            unit: "",
            doc: "sub-samples per pixel side (4)",
        },
        ParamDoc {
            name: "markers",
            unit: "",
            doc: "paint four marker dots (true)",
        },
        ParamDoc {
            name: "marker_radius_px",
            unit: "",
            doc: "marker dot radius, pixels (6)",
        },
        ParamDoc {
            name: "pixel_m",
            unit: "m",
            doc: "object-space pixel size (2e-5)",
        },
        ParamDoc {
            name: "gauge_width_m",
            unit: "m",
            doc: "gauge width (paper's per mode)",
        },
        ParamDoc {
            name: "gauge_length_m",
            unit: "m",
            doc: "gauge length (paper's per mode)",
        },
        ParamDoc {
            name: "thickness_m",
            unit: "m",
            doc: "thickness (1.5e-3)",
        },
        ParamDoc {
            name: "force_resolution_n",
            unit: "N",
            doc: "force resolution (paper's per mode)",
        },
        ParamDoc {
            name: "force_rate_hz",
            unit: "Hz",
            doc: "force sampling rate (50)",
        },
        ParamDoc {
            name: "seed",
            unit: "",
            doc: "random seed",
        },
    ],
    inputs: &[],
    outputs: &[
        OutputSpec {
            name: "sequence",
            kind: ProductKind::Files,
            columns: &[],
            doc: "frame_NNN.png, frames.csv, force.csv, specimen.json",
        },
        OutputSpec {
            name: "truth",
            kind: ProductKind::Table,
            columns: TRUTH_COLUMNS,
            doc: "the true stretches and stress per frame",
        },
        OutputSpec {
            name: "material",
            kind: ProductKind::Table,
            columns: &[],
            doc: "the generating material (material table: model, param, value)",
        },
    ],
};

impl Stage for SynthTensile {
    type Params = SynthTensileParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &SynthTensileParams,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let invalid = |e: ParamError| StageError::invalid(e.to_string());
        let mode = p.test_mode().map_err(invalid)?;
        let material =
            presets::preset(&p.preset).map_err(|e| StageError::invalid(e.to_string()))?;
        let [width_m, length_m, thickness_m] = p.geometry_m().map_err(invalid)?;
        let area_m2 = width_m * thickness_m;
        let experiment = Experiment::new(&p.recipe().map_err(invalid)?);

        let digits = (p.frames.saturating_sub(1)).to_string().len().max(3);
        let mut files = Files::new();
        let mut frames_csv = String::from("frame,time_s,file\n");
        let progress = ctx.progress(p.frames as u64, "rendering frames");
        for k in 0..p.frames {
            let pixels = experiment.render_frame(k);
            let counts = expose(
                &pixels,
                p.noise,
                p.bit_depth,
                p.seed.wrapping_mul(1_000_003).wrapping_add(k as u64),
            );
            let name = format!("frame_{k:0digits$}.png");
            let png = encode_png(p.width_px, p.height_px, p.bit_depth, counts)?;
            files = files.with(&name, png);
            frames_csv.push_str(&format!("{k},{},{name}\n", experiment.times_s[k]));
            progress.inc(1);
        }
        drop(progress);

        let resolution = p
            .force_resolution_n
            .unwrap_or(experiment::paper_force_resolution_n(mode));
        let mut force_csv = String::from("time_s,force_n\n");
        for (t, f) in experiment.force_log(
            material.as_ref(),
            area_m2,
            p.force_rate_hz,
            resolution,
            p.seed,
        ) {
            // Enough digits for the resolution, no binary noise in the file.
            force_csv.push_str(&format!("{t:.6},{f:.4}\n"));
        }
        let specimen = serde_json::json!({
            "mode": mode.label(),
            "gauge_width_m": width_m,
            "gauge_length_m": length_m,
            "thickness_m": thickness_m,
            "pixel_m": p.pixel_m,
            "roi_px": experiment.roi_px,
            "bit_depth": p.bit_depth,
        });
        let specimen = serde_json::to_vec_pretty(&specimen)
            .map_err(|e| StageError::invalid(format!("specimen.json: {e}")))?;
        files = files
            .with("frames.csv", frames_csv.into_bytes())
            .with("force.csv", force_csv.into_bytes())
            .with("specimen.json", specimen);

        let n = p.frames;
        let stress: Vec<f64> = experiment
            .stretches
            .iter()
            .map(|&l| material.nominal_stress_pa(mode, l))
            .collect();
        let truth = Table::new()
            .with("frame", (0..n as i64).collect::<Vec<_>>())
            .with("time_s", experiment.times_s.clone())
            .with("stretch", experiment.stretches.clone())
            .with(
                "stretch_2",
                experiment
                    .stretches
                    .iter()
                    .map(|&l| in_plane_stretches(mode, l)[1])
                    .collect::<Vec<_>>(),
            )
            .with(
                "force_n",
                stress.iter().map(|s| s * area_m2).collect::<Vec<_>>(),
            )
            .with("nominal_stress_pa", stress)
            .with("mode", vec![mode.label(); n]);
        Ok(Outputs::new()
            .files("sequence", files)
            .table("truth", truth)
            .table(
                "material",
                hypercontact_material::table::to_table(material.as_ref()),
            ))
    }
}

/// A grayscale PNG of 8- or 16-bit counts.
pub fn encode_png(
    width: usize,
    height: usize,
    bit_depth: u32,
    counts: Vec<u16>,
) -> Result<Vec<u8>, StageError> {
    let (w, h) = (width as u32, height as u32);
    let image = if bit_depth == 8 {
        let bytes: Vec<u8> = counts.into_iter().map(|c| c.min(255) as u8).collect();
        image::ImageBuffer::<image::Luma<u8>, _>::from_raw(w, h, bytes)
            .map(image::DynamicImage::ImageLuma8)
    } else {
        image::ImageBuffer::<image::Luma<u16>, _>::from_raw(w, h, counts)
            .map(image::DynamicImage::ImageLuma16)
    }
    .ok_or_else(|| StageError::invalid("image buffer size does not match width × height"))?;
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| StageError::invalid(format!("PNG encoding failed: {e}")))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_the_lab_files_and_a_consistent_truth() {
        let p = SynthTensileParams {
            mode: "PT".into(),
            frames: 3,
            width_px: 96,
            height_px: 80,
            supersample: 2,
            ..Default::default()
        };
        p.check().unwrap();
        let out = SynthTensile
            .run(&p, &Inputs::new(), &Context::new("t"))
            .unwrap();
        let Some(hypercontact_core::Product::Files(files)) = out.get("sequence") else {
            panic!("no sequence")
        };
        for name in [
            "frame_000.png",
            "frame_002.png",
            "frames.csv",
            "force.csv",
            "specimen.json",
        ] {
            assert!(files.files.contains_key(name), "{name}");
        }
        let png = image::load_from_memory(&files.files["frame_001.png"]).unwrap();
        assert_eq!((png.width(), png.height()), (96, 80));
        assert_eq!(png.color(), image::ColorType::L16);

        let Some(hypercontact_core::Product::Table(truth)) = out.get("truth") else {
            panic!("no truth")
        };
        let stretch = truth.f64("stretch").unwrap();
        assert_eq!(stretch, &[1.0, 1.5, 2.0]);
        assert_eq!(truth.f64("stretch_2").unwrap(), &[1.0, 1.0, 1.0]);
        let material = presets::preset("paper-epdm").unwrap();
        let expected = material.nominal_stress_pa(Mode::Planar, 2.0);
        assert_eq!(truth.f64("nominal_stress_pa").unwrap()[2], expected);

        // The force log is the true force within half a resolution step plus
        // the noise (4 σ), at 50 Hz over the whole test.
        let force = String::from_utf8(files.files["force.csv"].clone()).unwrap();
        let rows: Vec<(f64, f64)> = force
            .lines()
            .skip(1)
            .map(|l| {
                let (t, f) = l.split_once(',').unwrap();
                (t.parse().unwrap(), f.parse().unwrap())
            })
            .collect();
        assert_eq!(rows.len(), 51);
        let area = 40e-3 * 1.5e-3;
        let (t_end, f_end) = rows[50];
        assert!((t_end - 1.0).abs() < 1e-9);
        assert!(
            (f_end - expected * area).abs() <= 0.05 + 4.0 * 0.05,
            "{f_end}"
        );
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = |p: SynthTensileParams| p.check().unwrap_err().param;
        assert_eq!(
            bad(SynthTensileParams {
                mode: "XT".into(),
                ..Default::default()
            }),
            "mode"
        );
        assert_eq!(
            bad(SynthTensileParams {
                bit_depth: 12,
                ..Default::default()
            }),
            "bit_depth"
        );
        assert_eq!(
            bad(SynthTensileParams {
                max_stretch: Some(0.9),
                ..Default::default()
            }),
            "max_stretch"
        );
        assert_eq!(
            bad(SynthTensileParams {
                preset: "steel".into(),
                ..Default::default()
            }),
            "preset"
        );
    }
}
