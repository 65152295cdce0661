//! Stage `contact-compare`: the models judged against the contact
//! experiment (the paper's Figs. 6 and 7). The observed contact maps are
//! registered onto the scanned sample, every model's predicted map is laid
//! over them (overlap per frame), and every model's load–area curve is
//! scored against the measured one (agreement per model).

use std::collections::BTreeMap;

use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{ModelMapIndex, ObservedMapIndex, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Choice, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamError, Schema,
    Stage, StageError, StageInfo, params,
};
use hypercontact_interference::CameraGrid;

use crate::belong::{
    check_labels, check_model_grids, check_observed_in_table, check_view_within_scan, quality_notes,
};
pub use crate::maps::TRUNCATION;
use crate::maps::{Predictions, Truncation, read_model_maps, read_observed};
pub use crate::overlays::FigureIndex;
use crate::overlays::overlay_all;
use crate::registration::register_observed;
use crate::scoring::score_responses;

/// On what area the models' A/A0 is compared with the measured one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum AreaBasis {
    /// the camera's view, as measured: each model's A/A0 converted to what its own contact map shows inside the registered view
    #[default]
    View,
    /// the models' A/A0 of the whole scan as they give it
    Whole,
}

/// Parameters of `contact-compare`.
#[params(check = consistent)]
pub struct ContactCompareParams {
    /// A/A0 of the observed map the adopted transform is found at (the map nearest it)
    #[param(default = 0.5, positive, range = ..=1.0)]
    pub register_at: f64,
    /// the prediction registered against: `truncation` (the height map cut at the observed A/A0) or a label of `model_maps` (default: the first model_maps label, else truncation)
    pub register_with: Option<String>,
    /// maps with less measured contact are not registered (a handful of spots pins no turn); they are still scored
    #[param(default = 0.02, range = 0.0..=1.0)]
    pub min_register_fraction: f64,
    /// the camera's expected turn against the scan
    #[param(default = 0.0, unit = "deg", range = -180.0..=180.0)]
    pub angle_deg: f64,
    /// turns searched: angle_deg ± this (180: every turn)
    #[param(default = 10.0, unit = "deg", range = 0.0..=180.0)]
    pub angle_range_deg: f64,
    /// refine the camera's pixel on the sample (the scale between camera and scan)
    #[param(default = true)]
    pub refine_scale: bool,
    /// the scale is sought within 1 ± this
    #[param(default = 0.05, range = 0.0..=0.5)]
    pub scale_range: f64,
    /// agreement: the smallest measured A/A0 scored
    #[param(default = 0.01, range = 0.0..=1.0)]
    pub min_area_fraction: f64,
    /// agreement: the largest measured A/A0 scored (the paper's range: 0.9)
    #[param(default = 0.9, positive, range = ..=1.0)]
    pub max_area_fraction: f64,
    /// agreement: the models' A/A0 over the camera's view (`view`: from each model's own maps in the registered view) or over the whole scan (`whole`)
    #[param(default = AreaBasis::View)]
    pub area_basis: AreaBasis,
    /// agreement on the view: whose maps give a response's view area (response label: model_maps label or `truncation`; other keys or values are refused); by default its own label's maps, else the truncation
    #[param(default = BTreeMap::new())]
    pub view_maps: BTreeMap<String, String>,
    /// A/A0 at which the load ratio F_model / F_experiment is reported
    #[param(default = vec![0.1, 0.5, 0.9], positive, range = ..=1.0)]
    pub area_fractions: Vec<f64>,
    /// the observed maps drawn as figures, by their requested A/A0 (contact-images' map_fractions); every map is scored
    #[param(default = vec![0.1, 0.5, 0.9], range = 0.0..=1.0)]
    pub figure_fractions: Vec<f64>,
    /// the figures' longest side (the camera's maps are subsampled to it)
    #[param(default = 1024, unit = "px", range = 16..=16384)]
    pub figure_px: usize,
    /// responses (labels) whose physics is the experiment's, e.g. `bem-linear` against synth-contact's `model: linear`: they agree by construction, so their rows are marked `by_construction` and not ranked (a label that is not wired is refused)
    #[param(default = Vec::new())]
    pub same_physics: Vec<String>,
}

fn consistent(p: &ContactCompareParams) -> Result<(), ParamError> {
    if p.min_area_fraction >= p.max_area_fraction {
        return Err(ParamError::new(
            "min_area_fraction",
            format!(
                "{} is not below max_area_fraction ({})",
                p.min_area_fraction, p.max_area_fraction
            ),
        ));
    }
    Ok(())
}

/// The `transform` table: one row, the adopted registration.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct TransformTable {
    /// the prediction registered against
    pub against: Vec<String>,
    /// frame of the observed map registered
    pub frame: Vec<i64>,
    /// its measured A/A0
    pub area_fraction: Vec<f64>,
    /// turn of the camera's x axis in the scan's axes
    #[column(unit = "deg")]
    pub angle_deg: Vec<f64>,
    /// scan point under the camera frame's centre, from the scan's centre, x
    #[column(unit = "m")]
    pub shift_x_m: Vec<f64>,
    /// the same, y
    #[column(unit = "m")]
    pub shift_y_m: Vec<f64>,
    /// camera pixel on the sample relative to the nominal pixel_m
    pub scale: Vec<f64>,
    /// ZNCC of the observed map and the registered prediction
    pub zncc: Vec<f64>,
    /// maps registered independently (for the spreads below)
    pub registrations: Vec<i64>,
    /// robust standard deviation (1.4826 MAD) of the angle over the independent registrations (NaN for one)
    #[column(unit = "deg")]
    pub angle_sd_deg: Vec<f64>,
    /// the same for shift_x_m
    #[column(unit = "m")]
    pub shift_x_sd_m: Vec<f64>,
    /// the same for shift_y_m
    #[column(unit = "m")]
    pub shift_y_sd_m: Vec<f64>,
    /// the same for scale
    pub scale_sd: Vec<f64>,
}

/// The `registrations` table: each observed map registered on its own.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct RegistrationsTable {
    pub frame: Vec<i64>,
    pub area_fraction: Vec<f64>,
    #[column(unit = "deg")]
    pub angle_deg: Vec<f64>,
    #[column(unit = "m")]
    pub shift_x_m: Vec<f64>,
    #[column(unit = "m")]
    pub shift_y_m: Vec<f64>,
    pub scale: Vec<f64>,
    pub zncc: Vec<f64>,
    /// 1 for the registration adopted for every frame
    pub adopted: Vec<i64>,
}

/// The `overlap` table: one row per observed map and model.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct OverlapTable {
    /// `truncation` or the model_maps label
    pub model: Vec<String>,
    pub frame: Vec<i64>,
    /// measured A/A0 of the frame
    pub area_fraction: Vec<f64>,
    /// A/A0 of the model's map (the truncation's equals the measured one; a model's map is its nearest)
    pub model_area_fraction: Vec<f64>,
    /// 2TP / (2TP + FP + FN)
    pub dice: Vec<f64>,
    /// TP / (TP + FP + FN)
    pub iou: Vec<f64>,
    /// TP / (TP + FP)
    pub precision: Vec<f64>,
    /// TP / (TP + FN)
    pub recall: Vec<f64>,
    /// camera pixels in contact in both
    pub true_positive: Vec<i64>,
    /// predicted but not observed
    pub false_positive: Vec<i64>,
    /// observed but not predicted
    pub false_negative: Vec<i64>,
    /// in contact in neither
    pub true_negative: Vec<i64>,
}

/// The `agreement` table: one row per model response.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct AgreementTable {
    /// the responses label
    pub model: Vec<String>,
    /// sqrt(mean ln²(F_model / F_experiment)) at equal A/A0 over the measured frames in range
    pub rms_log_ratio: Vec<f64>,
    /// mean ln(F_model / F_experiment): > 0 when the model needs more load for the area
    pub mean_log_ratio: Vec<f64>,
    /// measured frames scored
    pub points: Vec<i64>,
    /// measured frames in range beyond the model's curve (not scored)
    pub outside_model: Vec<i64>,
    /// the model's A/A0 as compared: `view (<maps>)` or `whole`
    pub area: Vec<String>,
    /// 1 = the best agreement (smallest rms_log_ratio) among the models not by construction; 0 = by construction, not ranked
    pub rank: Vec<i64>,
    /// 1 = the model's physics is the experiment's (parameter same_physics): it agrees by construction; 0 = judged
    pub by_construction: Vec<i64>,
    /// the experiment's physics (the `truth` input's column physics; empty when no truth is wired)
    pub experiment_physics: Vec<String>,
}

/// The `load_ratio` table: F_model / F_experiment at equal A/A0.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct LoadRatioTable {
    pub model: Vec<String>,
    pub area_fraction: Vec<f64>,
    /// NaN where a curve does not reach the area fraction
    pub load_ratio: Vec<f64>,
    /// 1 = the model's physics is the experiment's (parameter same_physics); 0 = judged
    pub by_construction: Vec<i64>,
    /// the experiment's physics (the `truth` input's column physics; empty when no truth is wired)
    pub experiment_physics: Vec<String>,
}

/// What contact-compare reads of the experiment's `truth` (synth-contact's
/// truth table): the physics that rendered it, one string per row.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ExperimentPhysicsTable {
    /// the physics that rendered the frames (the same on every row)
    pub physics: Vec<String>,
}

/// The `contact-compare` stage.
pub struct ContactCompare;

static INFO: StageInfo = StageInfo {
    kind: "contact-compare",
    version: 5,
    summary: "Models against the contact experiment: registration of the observed contact \
              maps, overlap per frame and agreement of the load-area curves (Figs. 6, 7)",
    doc: "CHECKS (the index tables name no sample or run, so belonging is judged from \
          grids and values): model maps on another grid than `surface`, a camera view larger \
          than the scan, observed maps of different cameras, observed maps whose frame is not \
          in `contact` or whose A/A0 is more than 0.01 + 25 % off the table's, a model_maps \
          label `truncation` (reserved), and view_maps keys or values that are not wired are \
          refused. Noted as warnings: the adopted turn or scale within 2 % of its search \
          range from a bound, ZNCC below 0.5 (the paper pipeline's reach 0.78-0.81), and \
          even the best model's rms log ratio above 1 (the paper pipeline's best: \
          0.08-0.10). REGISTRATION: the observed map (contact-images' contact_maps) nearest \
          register_at is registered onto the prediction register_with, on the scan's grid: \
          `truncation` (the height map `surface` cut at the observed A/A0: contact where the \
          height is at or above the level that leaves that fraction above it, profile theory) \
          or a model_maps label (any contact model's contact_maps: contact where the pressure \
          is positive, at its map nearest the observed A/A0); by default the first model_maps \
          label, else the truncation (a model's map is closer to the contact a camera sees \
          than a cut through the heights). The turn (angle_deg ± angle_range_deg), shift \
          and, with refine_scale, the camera-to-scan scale are found by a coarse search of \
          turns with FFT correlation for the shift, then refined continuously (crate compare, \
          module register); the transform follows the interference crate's convention: the \
          camera pixel at p from the frame's centre sees the scan point R(angle) p + shift \
          from the map's centre. Every other observed map is registered on its own too; the \
          spread of those registrations (1.4826 MAD) is the transform's uncertainty (table \
          `transform`, each in `registrations`). OVERLAP: with the adopted transform, each \
          model's map (truncation always; each model_maps label) is sampled on the camera's \
          pixels (bilinear, contact where >= 0.5; pixels off the scan are not counted) and \
          compared with the observed map: Dice, IoU, precision, recall and the counts. \
          AGREEMENT: each `responses` curve against the measured (area_fraction, force_n) of \
          `contact`, over min_area_fraction <= A/A0 <= max_area_fraction: the model's load \
          at each measured A/A0 (log-log interpolation, never extrapolated) over the \
          measured force; rms and mean of the log ratio, rank 1 = smallest rms; `load_ratio` \
          at area_fractions (both curves interpolated). BY CONSTRUCTION: a synthetic \
          experiment has a physics (synth-contact's truth names it, e.g. the hyperelastic BEM \
          with the equibiaxial tangent); a model of the same physics agrees with it by \
          construction, whatever the physics is worth. The responses listed in same_physics \
          are marked (by_construction = 1 in `agreement` and `load_ratio`), scored as the \
          others but ranked 0 (not ranked) and left out of the best agreement noted; the \
          others rank 1, 2, ... among themselves. With `truth` wired, its physics string is \
          carried into both tables (column experiment_physics; empty without it). Without \
          same_physics every row is 0 and the ranks are as before. The camera measures A/A0 of its view, \
          the models give it for the whole scan, and on a free sample the two differ (its rim \
          lifts off, so its centre carries more contact). With area_basis `view` (default) \
          each model's A/A0 is converted to its view A/A0 before scoring: its own maps \
          (model_maps of its label, or the label view_maps names, e.g. a linear model's \
          response read on the maps of the model whose contact sets it shares) or else the \
          truncation read inside the registered view, linear between the maps' (whole, view) \
          pairs; column `area` says which. FIGURES: per observed map and model, \
          observed.png/predicted.png (contact black) and an overlay (black: both, \
          vermillion: predicted only, sky blue: observed only, white: neither, grey: off the \
          scan), for the maps requested at figure_fractions, subsampled to figure_px, with \
          the index `figures.parquet` (FigureIndex).",
    inputs: &[
        InputSpec::table::<ContactTable>("contact", Arity::One, "contact-images' contact table"),
        InputSpec::files_indexed::<ObservedMapIndex>(
            "observed_maps",
            Arity::One,
            "contact-images' contact_maps (mask PNGs, indexed)",
        ),
        InputSpec::field(
            "surface",
            Arity::One,
            "the sample's height map, metres (the stitched scan)",
        ),
        InputSpec::table::<ResponseTable>(
            "responses",
            Arity::Many,
            "load-area curves of the contact models, labelled by model",
        ),
        InputSpec::files_indexed::<ModelMapIndex>(
            "model_maps",
            Arity::Many,
            "contact models' contact_maps, labelled by model (pressure maps, indexed)",
        ),
        InputSpec::table::<ExperimentPhysicsTable>(
            "truth",
            Arity::Optional,
            "the experiment's truth (synth-contact's truth): its physics is named in the tables",
        ),
    ],
    outputs: &[
        OutputSpec::table::<TransformTable>("transform", "the adopted registration and its spread"),
        OutputSpec::table::<RegistrationsTable>(
            "registrations",
            "each observed map registered on its own",
        ),
        OutputSpec::table::<OverlapTable>("overlap", "per observed map and model"),
        OutputSpec::table::<AgreementTable>("agreement", "per model response"),
        OutputSpec::table::<LoadRatioTable>("load_ratio", "per model and area fraction"),
        OutputSpec::files_indexed::<FigureIndex>(
            "figures",
            "observed, predicted and overlay PNGs, indexed",
        ),
    ],
};

impl Stage for ContactCompare {
    type Params = ContactCompareParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<ContactCompareParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.areal_field("surface", INFO.kind)?;
        let contact: ContactTable = inputs.read("contact")?;
        let observed = read_observed(inputs)?;
        let predictions = Predictions {
            truncation: Truncation::new(surface),
            models: read_model_maps(inputs)?,
        };
        check_labels(p, inputs, &predictions)?;
        check_model_grids(surface, &predictions.models)?;
        check_view_within_scan(surface, &observed)?;
        check_observed_in_table(&observed, &contact)?;
        let against = p
            .register_with
            .as_deref()
            .or(predictions.models.first().map(|m| m.label.as_str()))
            .unwrap_or(TRUNCATION);
        predictions.check_name("register_with", against)?;
        let registered = register_observed(p, &observed, &predictions, against, ctx)?;
        let registration = registered.registration;
        let (overlaps, figures) = overlay_all(p, &observed, &predictions, &registration)?;
        let camera = CameraGrid {
            width_px: observed[0].width,
            height_px: observed[0].height,
            pixel_m: observed[0].pixel_m,
        };
        let physics = experiment_physics(inputs)?;
        let (agreement, ratios) = score_responses(
            p,
            inputs,
            &contact,
            &predictions,
            &registration,
            camera,
            &physics,
        )?;
        ctx.note(&note(against, &registered.transform, &agreement));
        for warning in quality_notes(p, &registered.transform, &agreement) {
            ctx.note(&warning);
        }
        Ok(Outputs::new()
            .table("transform", registered.transform.into_table())
            .table("registrations", registered.registrations.into_table())
            .table("overlap", overlaps.into_table())
            .table("agreement", agreement.into_table())
            .table("load_ratio", ratios.into_table())
            .files("figures", figures))
    }
}

/// The physics of the experiment named by the optional `truth` input:
/// empty when it is not wired or has no rows; refused when its rows differ.
fn experiment_physics(inputs: &Inputs) -> Result<String, StageError> {
    if inputs.get("truth").is_none() {
        return Ok(String::new());
    }
    let truth: ExperimentPhysicsTable = inputs.read("truth")?;
    let Some(first) = truth.physics.first() else {
        return Ok(String::new());
    };
    if let Some(other) = truth.physics.iter().find(|p| *p != first) {
        return Err(StageError::invalid(format!(
            "input `truth`: its rows name two physics, `{first}` and `{other}`: one experiment \
             has one"
        )));
    }
    Ok(first.clone())
}

/// The run's one line: the adopted registration and the best agreement
/// (of the models not by construction).
fn note(against: &str, transform: &TransformTable, agreement: &AgreementTable) -> String {
    let best =
        agreement
            .rank
            .iter()
            .position(|&r| r == 1)
            .map_or("no response judged".to_owned(), |k| {
                format!(
                    "{} (rms log ratio {:.3})",
                    agreement.model[k], agreement.rms_log_ratio[k]
                )
            });
    let marked: Vec<&str> = (0..agreement.model.len())
        .filter(|&k| agreement.by_construction[k] != 0)
        .map(|k| agreement.model[k].as_str())
        .collect();
    let best = if marked.is_empty() {
        best
    } else {
        format!(
            "{best}; by construction (not ranked): {}",
            marked.join(", ")
        )
    };
    format!(
        "registered onto `{against}`: turn {:.3}° ± {:.3}°, shift ({:.1}, {:.1}) µm, scale \
         {:.4}, ZNCC {:.3}; best agreement: {best}",
        transform.angle_deg[0],
        transform.angle_sd_deg[0],
        transform.shift_x_m[0] * 1e6,
        transform.shift_y_m[0] * 1e6,
        transform.scale[0],
        transform.zncc[0],
    )
}
