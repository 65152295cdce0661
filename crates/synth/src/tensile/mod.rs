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
pub mod open_hole;
pub mod render;
pub mod speckle;

use hypercontact_core::{
    Checked, Context, Files, Inputs, Mode, OutputSpec, Outputs, Schema, Stage, StageError,
    StageInfo, params,
};
use hypercontact_material::presets::Preset;
use hypercontact_material::table::MaterialTable;

use crate::encode_png;
use experiment::{Experiment, Recipe, expose, in_plane_stretches};

/// Parameters of `synth-tensile`.
#[params]
pub struct SynthTensileParams {
    /// the test
    #[param(default = Mode::Uniaxial)]
    pub mode: Mode,
    /// ground-truth material preset
    #[param(default = Preset::PaperEpdm)]
    pub preset: Preset,
    /// final loading stretch, in (1, 10] (default UT 2.5, PT 2, BT 1.5)
    #[param(check = loading_stretch)]
    pub max_stretch: Option<f64>,
    /// number of frames
    #[param(default = 20, range = 2..=100_000)]
    pub frames: usize,
    /// time between frames
    #[param(default = 0.5, unit = "s", positive)]
    pub frame_interval_s: f64,
    /// image width (the paper's camera: 2048)
    #[param(default = 512, unit = "px", range = 64..=16384)]
    pub width_px: usize,
    /// image height
    #[param(default = 512, unit = "px", range = 64..=16384)]
    pub height_px: usize,
    /// 8 or 16
    #[param(default = 16, check = eight_or_sixteen)]
    pub bit_depth: u32,
    /// camera noise std, fraction of full scale
    #[param(default = 0.005, range = 0.0..=0.5)]
    pub noise: f64,
    /// mean speckle radius
    #[param(default = 2.5, unit = "px", range = 0.5..=50.0)]
    pub speckle_radius_px: f64,
    /// sprayed fraction of the surface (before overlaps)
    #[param(default = 0.5, range = 0.01..=5.0)]
    pub speckle_coverage: f64,
    /// sub-samples per pixel side
    #[param(default = 4, range = 1..=16)]
    pub supersample: usize,
    /// paint four marker dots for the `markers` method
    #[param(default = true)]
    pub markers: bool,
    /// marker dot radius
    #[param(default = 6.0, unit = "px", range = 1.0..=100.0)]
    pub marker_radius_px: f64,
    /// object-space pixel size
    #[param(default = 2e-5, unit = "m", positive)]
    pub pixel_m: f64,
    /// gauge width (default: the paper's per mode)
    #[param(unit = "m", positive)]
    pub gauge_width_m: Option<f64>,
    /// gauge length (default: the paper's per mode)
    #[param(unit = "m", positive)]
    pub gauge_length_m: Option<f64>,
    /// thickness (the paper's)
    #[param(default = 1.5e-3, unit = "m", positive)]
    pub thickness_m: f64,
    /// force sensor resolution (default: the paper's, UT 0.01, PT 0.1, BT 0.01)
    #[param(unit = "N", positive)]
    pub force_resolution_n: Option<f64>,
    /// force sampling rate
    #[param(default = 50.0, unit = "Hz", positive)]
    pub force_rate_hz: f64,
    /// random seed
    #[param(default = 1)]
    pub seed: u64,
}

fn eight_or_sixteen(bits: &u32) -> Result<(), String> {
    match bits {
        8 | 16 => Ok(()),
        other => Err(format!("must be 8 or 16, got {other}")),
    }
}

/// (1, 10]: a `range` cannot leave its lower end open. The defaults per mode
/// lie inside.
fn loading_stretch(stretch: &Option<f64>) -> Result<(), String> {
    match *stretch {
        Some(l) if !(l > 1.0 && l <= 10.0) => Err(format!("must lie in (1, 10], got {l}")),
        _ => Ok(()),
    }
}

impl SynthTensileParams {
    pub fn max_stretch(&self) -> f64 {
        self.max_stretch.unwrap_or(match self.mode {
            Mode::Uniaxial => 2.5,
            Mode::Planar => 2.0,
            Mode::Equibiaxial => 1.5,
        })
    }

    /// Gauge width, length and thickness, metres.
    pub fn geometry_m(&self) -> [f64; 3] {
        let paper = experiment::paper_gauge_m(self.mode);
        [
            self.gauge_width_m.unwrap_or(paper[0]),
            self.gauge_length_m.unwrap_or(paper[1]),
            self.thickness_m,
        ]
    }

    /// The force sensor's resolution, newtons: the paper's unless given.
    pub fn force_resolution_n(&self) -> f64 {
        self.force_resolution_n
            .unwrap_or(experiment::paper_force_resolution_n(self.mode))
    }

    pub fn recipe(&self) -> Recipe {
        Recipe {
            mode: self.mode,
            max_stretch: self.max_stretch(),
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
        }
    }
}

/// The `synth-tensile` stage.
pub struct SynthTensile;

/// The `truth` table: one row per frame.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct TruthTable {
    /// frame index
    pub frame: Vec<i64>,
    /// frame time
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// true loading stretch λ (along x)
    pub stretch: Vec<f64>,
    /// true in-plane transverse stretch (along y)
    pub stretch_2: Vec<f64>,
    /// true nominal stress of the preset
    #[column(unit = "Pa")]
    pub nominal_stress_pa: Vec<f64>,
    /// true force (noise-free)
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
    /// UT, PT or BT
    pub mode: Vec<String>,
}

static INFO: StageInfo = StageInfo {
    kind: "synth-tensile",
    version: 1,
    summary: "Synthetic UT/PT/BT tensile test: speckle images, frame times, force log, specimen",
    doc: "Renders a sprayed speckle pattern (Gaussian blobs, saturating optical density, four \
          painted marker dots) at each homogeneously deformed state, evaluating the pattern at \
          the inverse-mapped reference coordinate of sub-samples of every pixel (no image \
          interpolation), then adds camera noise and quantises to 8 or 16 bits. Loading is \
          along x about the image centre: UT (λ, λ^-1/2), PT (λ, 1), BT (λ, λ), λ linear in \
          time. The force log (sampled at force_rate_hz) is the preset's nominal stress × the \
          undeformed cross-section (gauge width × thickness) plus sensor noise, quantised to \
          force_resolution_n. The ground truth goes to separate outputs the dic stage never \
          reads.",
    inputs: &[],
    outputs: &[
        OutputSpec::files(
            "sequence",
            "frame_NNN.png, frames.csv, force.csv, specimen.json",
        ),
        OutputSpec::table::<TruthTable>("truth", "the true stretches and stress per frame"),
        OutputSpec::table::<MaterialTable>("material", "the generating material"),
    ],
};

impl Stage for SynthTensile {
    type Params = SynthTensileParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<SynthTensileParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let mode = p.mode;
        let material = p.preset.model();
        let [width_m, length_m, thickness_m] = p.geometry_m();
        let area_m2 = width_m * thickness_m;
        let experiment = Experiment::new(&p.recipe());

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

        let mut force_csv = String::from("time_s,force_n\n");
        for (t, f) in experiment.force_log(
            material.as_ref(),
            area_m2,
            p.force_rate_hz,
            p.force_resolution_n(),
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

        let stretches = &experiment.stretches;
        let stress: Vec<f64> = stretches
            .iter()
            .map(|&l| material.nominal_stress_pa(mode, l))
            .collect();
        let truth = TruthTable {
            frame: (0..p.frames as i64).collect(),
            time_s: experiment.times_s.clone(),
            stretch: stretches.clone(),
            stretch_2: stretches
                .iter()
                .map(|&l| in_plane_stretches(mode, l)[1])
                .collect(),
            force_n: stress.iter().map(|s| s * area_m2).collect(),
            nominal_stress_pa: stress,
            mode: vec![mode.label().to_owned(); p.frames],
        };
        Ok(Outputs::new()
            .files("sequence", files)
            .table("truth", truth.into_table())
            .table(
                "material",
                hypercontact_material::table::to_table(material.as_ref()),
            ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params};
    use hypercontact_material::presets;

    #[test]
    fn writes_the_lab_files_and_a_consistent_truth() {
        let p = SynthTensileParams {
            mode: Mode::Planar,
            frames: 3,
            width_px: 96,
            height_px: 80,
            supersample: 2,
            ..Default::default()
        }
        .check()
        .unwrap();
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
        let names: Vec<&str> = TruthTable::COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(truth.column_names(), names);
        assert_eq!(TruthTable::from_table(truth).unwrap().mode, ["PT"; 3]);
        let Some(hypercontact_core::Product::Table(table)) = out.get("material") else {
            panic!("no material")
        };
        table.conform(MaterialTable::COLUMNS).unwrap();
        let stretch = truth.f64("stretch").unwrap();
        assert_eq!(stretch, &[1.0, 1.5, 2.0]);
        assert_eq!(truth.f64("stretch_2").unwrap(), &[1.0, 1.0, 1.0]);
        let material = presets::preset("paper-epdm").unwrap();
        let expected = material.nominal_stress_pa(Mode::Planar, 2.0);
        assert_eq!(truth.f64("nominal_stress_pa").unwrap()[2], expected);

        // The force log is the true force within half a resolution step plus
        // the noise (4 σ), at 50 Hz over the whole test.
        let lab = hypercontact_labfiles::sequence::Sequence::open(
            hypercontact_labfiles::FileSource::Files {
                files,
                input: "sequence".into(),
            },
        )
        .unwrap();
        let rows = &lab.force;
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
    fn per_mode_defaults_in_the_docs_match_the_code() {
        let spec = SynthTensileParams::spec();
        let doc = |name: &str| spec.iter().find(|s| s.name == name).unwrap().doc;
        for mode in Mode::ALL {
            let p = SynthTensileParams {
                mode,
                ..Default::default()
            };
            let label = mode.label();
            let stretch = format!("{label} {}", p.max_stretch());
            assert!(doc("max_stretch").contains(&stretch), "{stretch}");
            let resolution = format!("{label} {}", p.force_resolution_n());
            assert!(
                doc("force_resolution_n").contains(&resolution),
                "{resolution}"
            );
        }
    }

    #[test]
    fn eight_bit_counts_saturate_and_a_wrong_size_is_an_error() {
        let png = encode_png(3, 1, 8, vec![0, 200, 4000]).unwrap();
        let back = image::load_from_memory(&png).unwrap();
        assert_eq!(back.color(), image::ColorType::L8);
        assert_eq!(back.into_luma8().into_raw(), [0, 200, 255]);
        assert!(encode_png(3, 2, 16, vec![0; 5]).is_err());
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = |p: SynthTensileParams| p.check().unwrap_err().param;
        let parse_error = |json| {
            SynthTensile
                .params_from_json(json, std::path::Path::new("."))
                .unwrap_err()
                .param
        };
        assert_eq!(parse_error(serde_json::json!({"mode": "XT"})), "mode");
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
            parse_error(serde_json::json!({"preset": "steel"})),
            "preset"
        );
    }
}
