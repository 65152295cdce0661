//! Stage `contact-compare`: the models judged against the contact
//! experiment (the paper's Figs. 6 and 7). The observed contact maps are
//! registered onto the scanned sample, every model's predicted map is laid
//! over them (overlap per frame), and every model's load–area curve is
//! scored against the measured one (agreement per model).

use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{
    ModelMapIndex, ObservedMapIndex, ResponseTable, area_fraction_label,
};
use hypercontact_core::robust::median_and_sigma;
use hypercontact_labfiles::png::{Pixels, encode_png};
use hypercontact_labfiles::sequence::GrayFrame;
use std::collections::BTreeMap;

use hypercontact_core::{
    Arity, Checked, Choice, Context, Field, Files, InputSpec, Inputs, OutputSpec, Outputs,
    ParamError, Product, Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_interference::CameraGrid;
use hypercontact_labfiles::FileSource;
use ndarray::Array2;

use crate::agreement::{Curve, LogCurve, Range, agreement};
use crate::overlap::{Agreement as Class, classify, overlap};
use crate::register::{
    ObservedMask, PredictedMap, RegisterSettings, Registration, register, sample_predicted,
};

/// The profile-theory prediction's name in the tables: the height map cut
/// at the observed area fraction.
pub const TRUNCATION: &str = "truncation";

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
    /// agreement on the view: whose maps give a response's view area (response label: model_maps label or `truncation`); by default its own label's maps, else the truncation
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
    /// 1 = the best agreement (smallest rms_log_ratio)
    pub rank: Vec<i64>,
}

/// The `load_ratio` table: F_model / F_experiment at equal A/A0.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct LoadRatioTable {
    pub model: Vec<String>,
    pub area_fraction: Vec<f64>,
    /// NaN where a curve does not reach the area fraction
    pub load_ratio: Vec<f64>,
}

/// The `contact-compare` stage.
pub struct ContactCompare;

static INFO: StageInfo = StageInfo {
    kind: "contact-compare",
    version: 3,
    summary: "Models against the contact experiment: registration of the observed contact \
              maps, overlap per frame and agreement of the load-area curves (Figs. 6, 7)",
    doc: "REGISTRATION: the observed map (contact-images' contact_maps) nearest \
          register_at is registered onto the prediction register_with, on the scan's grid: \
          `truncation` (the height map `surface` cut at the observed A/A0: contact where the \
          height is at or above the level that leaves that fraction above it, profile theory) \
          or a model_maps label (a `bem` contact_maps product: contact where the pressure is \
          positive, at its map nearest the observed A/A0); by default the first model_maps \
          label, else the truncation. On the synthetic lab at the quick pipeline's sizes \
          (a 2.2 mm view of 4.3 µm pixels on a 20 µm scan, T1-T4) the BEM maps gave the turn \
          within 0.04° and the shift within 0.26 camera pixel; the truncation, whose map \
          differs more from the observed contact, was 0.56° off on T3 (ZNCC 0.58 against \
          0.73 for BEM). The turn (angle_deg ± \
          angle_range_deg), shift and, with refine_scale, the camera-to-scan scale are found \
          by a coarse search of turns with FFT correlation for the shift, then refined \
          continuously (crate compare, module register); the transform follows the \
          interference crate's convention: the camera pixel at p from the frame's centre sees \
          the scan point R(angle) p + shift from the map's centre. Every other observed map \
          is registered on its own too; the spread of those registrations is the transform's \
          uncertainty (table `transform`, each in `registrations`). OVERLAP: with the adopted \
          transform, each model's map (truncation always; each model_maps label) is sampled on \
          the camera's pixels (bilinear, contact where >= 0.5; pixels off the scan are not \
          counted) and compared with the observed map: Dice, IoU, precision, recall and the \
          counts. AGREEMENT: each `responses` curve against the measured (area_fraction, \
          force_n) of `contact`, over min_area_fraction <= A/A0 <= max_area_fraction: the \
          model's load at each measured A/A0 (log-log interpolation, never extrapolated) over \
          the measured force; rms and mean of the log ratio, rank 1 = smallest rms; \
          `load_ratio` at area_fractions (both curves interpolated). The camera measures A/A0 \
          of its view, the models give it for the whole scan, and the two differ (a free \
          sample's rim lifts off, so its centre carries more contact: on synth-contact's paper \
          samples the whole scan's A/A0 was 0.69-0.74 of the central view's at 0.5). With \
          area_basis `view` (default) each model's A/A0 is converted to its view A/A0 before \
          scoring: its own maps (model_maps of its label, or the label view_maps names; \
          e.g. bem-linear: bem, whose contact sets are the linear solution's) or else the \
          truncation read inside the registered view, linear between the maps' (whole, view) \
          pairs; column `area` says which. On the synthetic lab (T1, quick sizes) this took \
          the lab's own physics from rms 0.207 (whole) to 0.046 (view). FIGURES: per observed map and \
          model, observed.png/predicted.png (contact black) and an overlay (black: both, \
          vermillion: predicted only, sky blue: observed only, white: neither, grey: off the \
          scan), for the maps requested at figure_fractions, subsampled to figure_px, listed in \
          figures.csv.",
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
            "load-area curves of the models, labelled (icm, bem, ...)",
        ),
        InputSpec::files_indexed::<ModelMapIndex>(
            "model_maps",
            Arity::Many,
            "contact models' contact_maps (bem's), labelled (pressure maps, indexed)",
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
        OutputSpec::files(
            "figures",
            "observed, predicted and overlay PNGs with figures.csv",
        ),
    ],
};

/// One observed contact map.
struct ObservedMap {
    requested: f64,
    area_fraction: f64,
    frame: i64,
    pixel_m: f64,
    width: usize,
    height: usize,
    contact: Vec<bool>,
}

/// A model's contact maps on the scan's grid, with their A/A0.
struct ModelMaps {
    label: String,
    maps: Vec<(f64, Field)>,
}

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
        let contact: ContactTable = inputs.read("contact")?;
        let surface = inputs.field("surface")?;
        let observed = read_observed(inputs)?;
        let models = read_model_maps(inputs)?;
        // The default: the first model map wired (closer to the contact a
        // camera sees than a cut through the heights), else the truncation.
        let against = p
            .register_with
            .as_deref()
            .or(models.first().map(|m| m.label.as_str()))
            .unwrap_or(TRUNCATION);
        if against != TRUNCATION && !models.iter().any(|m| m.label == against) {
            return Err(StageError::invalid(format!(
                "parameter `register_with` = {against}: not `{TRUNCATION}` nor a label of \
                 `model_maps` ({})",
                labels(&models)
            )));
        }
        let truncation = Truncation::new(surface);
        let predicted_for = |model: &str, fraction: f64| -> Result<(f64, Field), StageError> {
            if model == TRUNCATION {
                Ok(truncation.cut(fraction))
            } else {
                let maps = models.iter().find(|m| m.label == model).ok_or_else(|| {
                    StageError::invalid(format!("no model_maps labelled `{model}`"))
                })?;
                Ok(nearest(&maps.maps, fraction).clone())
            }
        };

        // Register every observed map; adopt the one nearest register_at.
        let settings = RegisterSettings {
            angle_centre_deg: p.angle_deg,
            angle_range_deg: p.angle_range_deg,
            refine_scale: p.refine_scale,
            scale_range: p.scale_range,
            ..RegisterSettings::default()
        };
        let registered: Vec<&ObservedMap> = observed
            .iter()
            .filter(|m| m.area_fraction >= p.min_register_fraction)
            .collect();
        if registered.is_empty() {
            return Err(StageError::invalid(format!(
                "no observed map has A/A0 >= min_register_fraction ({}): the largest is {:.4}; \
                 map frames with more contact (contact-images' map_fractions)",
                p.min_register_fraction,
                observed.iter().map(|m| m.area_fraction).fold(0.0, f64::max)
            )));
        }
        let progress = ctx.progress(registered.len() as u64, "registrations");
        let mut found = Vec::with_capacity(registered.len());
        for map in &registered {
            let (_, field) = predicted_for(against, map.area_fraction)?;
            let registration = register(&predicted(&field), &mask(map), &settings)
                .map_err(|e| {
                    StageError::invalid(format!(
                        "registering the observed map of frame {} (A/A0 = {:.4}) onto `{against}`: {e}",
                        map.frame, map.area_fraction
                    ))
                })?;
            found.push(registration);
            progress.inc(1);
        }
        drop(progress);
        let adopted = (0..registered.len())
            .min_by(|&i, &j| {
                let d = |k: usize| (registered[k].area_fraction - p.register_at).abs();
                d(i).total_cmp(&d(j))
            })
            .expect("refused above when empty");
        let transform = transform_table(against, &registered, &found, adopted);
        let registrations = RegistrationsTable {
            frame: registered.iter().map(|m| m.frame).collect(),
            area_fraction: registered.iter().map(|m| m.area_fraction).collect(),
            angle_deg: found
                .iter()
                .map(|r| r.placement.angle_rad.to_degrees())
                .collect(),
            shift_x_m: found.iter().map(|r| r.placement.shift_x_m).collect(),
            shift_y_m: found.iter().map(|r| r.placement.shift_y_m).collect(),
            scale: found.iter().map(|r| r.scale).collect(),
            zncc: found.iter().map(|r| r.score).collect(),
            adopted: (0..found.len()).map(|k| i64::from(k == adopted)).collect(),
        };
        let registration = found[adopted];

        // Overlap of every model's map with every observed map.
        let mut model_names = vec![TRUNCATION.to_owned()];
        model_names.extend(models.iter().map(|m| m.label.clone()));
        let mut overlaps = OverlapTable::default();
        let mut figures = Files::new();
        let mut figures_csv = String::from(
            "model,requested_area_fraction,area_fraction,model_area_fraction,frame,observed_file,\
             predicted_file,overlay_file,pixel_m,width_px,height_px\n",
        );
        for map in &observed {
            let label = area_fraction_label(map.requested);
            let observed_file = format!("observed_{label}.png");
            let camera = CameraGrid {
                width_px: map.width,
                height_px: map.height,
                pixel_m: map.pixel_m,
            };
            let figure = Subsample::new(map.width, map.height, p.figure_px);
            let drawn = p
                .figure_fractions
                .iter()
                .any(|f| (f - map.requested).abs() < 1e-9);
            if drawn {
                figures.files.insert(
                    observed_file.clone(),
                    figure.png(|i| if map.contact[i] { [0; 3] } else { [255; 3] })?,
                );
            }
            for model in &model_names {
                let (model_fraction, field) = predicted_for(model, map.area_fraction)?;
                let sampled = sample_predicted(&predicted(&field), &registration, &camera)
                    .map_err(|e| StageError::invalid(format!("`{model}` on the camera: {e}")))?;
                let predicted: Vec<Option<bool>> = sampled
                    .iter()
                    .map(|v| (!v.is_nan()).then_some(*v >= 0.5))
                    .collect();
                let o = overlap(&predicted, &map.contact).map_err(|e| {
                    StageError::invalid(format!("`{model}` at frame {}: {e}", map.frame))
                })?;
                overlaps.model.push(model.clone());
                overlaps.frame.push(map.frame);
                overlaps.area_fraction.push(map.area_fraction);
                overlaps.model_area_fraction.push(model_fraction);
                overlaps.dice.push(o.dice);
                overlaps.iou.push(o.iou);
                overlaps.precision.push(o.precision);
                overlaps.recall.push(o.recall);
                overlaps.true_positive.push(o.true_positive as i64);
                overlaps.false_positive.push(o.false_positive as i64);
                overlaps.false_negative.push(o.false_negative as i64);
                overlaps.true_negative.push(o.true_negative as i64);

                if !drawn {
                    continue;
                }
                let predicted_file = format!("predicted_{model}_{label}.png");
                let overlay_file = format!("overlay_{model}_{label}.png");
                figures.files.insert(
                    predicted_file.clone(),
                    figure.png(|i| match predicted[i] {
                        Some(true) => [0; 3],
                        Some(false) => [255; 3],
                        None => GREY,
                    })?,
                );
                figures.files.insert(
                    overlay_file.clone(),
                    figure.png(|i| colour(classify(predicted[i], map.contact[i])))?,
                );
                figures_csv.push_str(&format!(
                    "{model},{},{},{model_fraction},{},{observed_file},{predicted_file},\
                     {overlay_file},{},{},{}\n",
                    map.requested,
                    map.area_fraction,
                    map.frame,
                    map.pixel_m * figure.step as f64,
                    figure.width,
                    figure.height
                ));
            }
        }
        figures
            .files
            .insert("figures.csv".into(), figures_csv.into_bytes());

        // Agreement of the load-area curves.
        let experiment = Curve {
            area_fraction: &contact.area_fraction,
            load_n: &contact.force_n,
        };
        let range = Range {
            min_area_fraction: p.min_area_fraction,
            max_area_fraction: p.max_area_fraction,
        };
        let camera = CameraGrid {
            width_px: observed[0].width,
            height_px: observed[0].height,
            pixel_m: observed[0].pixel_m,
        };
        let mut view_relations: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        let mut scores = Vec::new();
        let mut bases = Vec::new();
        let mut ratios = LoadRatioTable::default();
        for (label, product) in inputs.labelled("responses") {
            let Product::Table(table) = product else {
                return Err(StageError::invalid(format!(
                    "input `responses.{label}` is not a table"
                )));
            };
            let response = ResponseTable::from_table(table)
                .map_err(|e| StageError::invalid(format!("input `responses.{label}`: {e}")))?;
            let (area_fractions, basis) = match p.area_basis {
                AreaBasis::Whole => (response.area_fraction.clone(), "whole".to_owned()),
                AreaBasis::View => {
                    let maps_label = p.view_maps.get(label).cloned().unwrap_or_else(|| {
                        if models.iter().any(|m| m.label == label) {
                            label.to_owned()
                        } else {
                            TRUNCATION.to_owned()
                        }
                    });
                    if !view_relations.contains_key(&maps_label) {
                        let relation = match models.iter().find(|m| m.label == maps_label) {
                            Some(m) => view_relation_of_maps(&m.maps, &registration, &camera),
                            None if maps_label == TRUNCATION => {
                                view_relation_of_truncation(&truncation, &registration, &camera)
                            }
                            None => Err(StageError::invalid(format!(
                                "parameter `view_maps.{label}` = {maps_label}: not `{TRUNCATION}` \
                                 nor a label of `model_maps` ({})",
                                labels(&models)
                            ))),
                        }?;
                        view_relations.insert(maps_label.clone(), relation);
                    }
                    let relation = &view_relations[&maps_label];
                    (
                        response
                            .area_fraction
                            .iter()
                            .map(|&a| on_relation(relation, a))
                            .collect(),
                        format!("view ({maps_label})"),
                    )
                }
            };
            let curve = LogCurve::new(
                Curve {
                    area_fraction: &area_fractions,
                    load_n: &response.load_n,
                },
                &format!("`responses.{label}`"),
            )
            .map_err(|e| StageError::invalid(e.to_string()))?;
            let a = agreement(&curve, experiment, range, &p.area_fractions)
                .map_err(|e| StageError::invalid(format!("`responses.{label}`: {e}")))?;
            bases.push(basis);
            for (&at, &ratio) in p.area_fractions.iter().zip(&a.ratio_at) {
                ratios.model.push(label.to_owned());
                ratios.area_fraction.push(at);
                ratios.load_ratio.push(ratio);
            }
            scores.push((label.to_owned(), a));
        }
        let mut agreement_table = agreement_table(&scores);
        agreement_table.area = bases;
        ctx.note(&format!(
            "registered onto `{against}`: turn {:.3}° ± {:.3}°, shift ({:.1}, {:.1}) µm, scale \
             {:.4}, ZNCC {:.3}; best agreement: {}",
            transform.angle_deg[0],
            transform.angle_sd_deg[0],
            transform.shift_x_m[0] * 1e6,
            transform.shift_y_m[0] * 1e6,
            transform.scale[0],
            transform.zncc[0],
            agreement_table.rank.iter().position(|&r| r == 1).map_or(
                "no responses".to_owned(),
                |k| format!(
                    "{} (rms log ratio {:.3})",
                    agreement_table.model[k], agreement_table.rms_log_ratio[k]
                )
            )
        ));
        Ok(Outputs::new()
            .table("transform", transform.into_table())
            .table("registrations", registrations.into_table())
            .table("overlap", overlaps.into_table())
            .table("agreement", agreement_table.into_table())
            .table("load_ratio", ratios.into_table())
            .files("figures", figures))
    }
}

const GREY: [u8; 3] = [200, 200, 200];

/// Okabe–Ito colours (distinguishable with the common colour-vision
/// deficiencies): both black, predicted only vermillion, observed only
/// sky blue.
fn colour(class: Class) -> [u8; 3] {
    match class {
        Class::TruePositive => [0, 0, 0],
        Class::FalsePositive => [213, 94, 0],
        Class::FalseNegative => [86, 180, 233],
        Class::TrueNegative => [255, 255, 255],
        Class::Unknown => GREY,
    }
}

/// A camera map shown at most `max_px` on its longer side: every
/// `step`-th pixel (the centre of each block), so classes are not blended.
struct Subsample {
    step: usize,
    width: usize,
    height: usize,
    source_width: usize,
    source_height: usize,
}

impl Subsample {
    fn new(width: usize, height: usize, max_px: usize) -> Self {
        let step = width.max(height).div_ceil(max_px).max(1);
        Self {
            step,
            width: width.div_ceil(step),
            height: height.div_ceil(step),
            source_width: width,
            source_height: height,
        }
    }

    /// An RGB PNG of `rgb(source pixel index)`.
    fn png(&self, rgb: impl Fn(usize) -> [u8; 3]) -> Result<Vec<u8>, StageError> {
        let mut pixels = Vec::with_capacity(3 * self.width * self.height);
        for y in 0..self.height {
            for x in 0..self.width {
                // The last block may be partial: its centre clamped inside.
                let sx = (x * self.step + self.step / 2).min(self.source_width - 1);
                let sy = (y * self.step + self.step / 2).min(self.source_height - 1);
                pixels.extend_from_slice(&rgb(sy * self.source_width + sx));
            }
        }
        encode_png(self.width as u32, self.height as u32, Pixels::Rgb8(pixels))
            .map_err(StageError::invalid)
    }
}

/// Profile theory's contact maps of one height map: its measured heights
/// sorted once, highest first, and cut at any area fraction.
struct Truncation<'a> {
    surface: &'a Field,
    descending: Vec<f64>,
}

impl<'a> Truncation<'a> {
    fn new(surface: &'a Field) -> Self {
        let mut descending: Vec<f64> = surface
            .values
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .collect();
        descending.sort_by(|a, b| b.total_cmp(a));
        Self {
            surface,
            descending,
        }
    }

    /// The height map cut at area fraction `fraction`: 1 where the height
    /// is at or above the level with that share of the measured points
    /// above it (profile theory's contact), 0 below, NaN where not
    /// measured; with the map's own A/A0.
    fn cut(&self, fraction: f64) -> (f64, Field) {
        let n = self.descending.len();
        let k = ((fraction * n as f64).round() as usize).min(n);
        let level = if k == 0 {
            f64::INFINITY
        } else {
            self.descending[k - 1]
        };
        let values = self.surface.values.mapv(|h| {
            if h.is_nan() {
                f64::NAN
            } else if h >= level {
                1.0
            } else {
                0.0
            }
        });
        let inside = values.iter().filter(|v| **v == 1.0).count();
        let field = Field {
            values,
            dx_m: self.surface.dx_m,
            dy_m: self.surface.dy_m,
        };
        (inside as f64 / n.max(1) as f64, field)
    }
}

/// The share of the camera's pixels on the scan that `field` (1 =
/// contact) puts in contact under `registration`.
fn view_fraction(
    field: &Field,
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<f64, StageError> {
    let sampled = sample_predicted(&predicted(field), registration, camera)
        .map_err(|e| StageError::invalid(format!("a model map on the camera: {e}")))?;
    let (inside, seen) = sampled
        .iter()
        .filter(|v| !v.is_nan())
        .fold((0usize, 0usize), |(i, n), v| {
            (i + usize::from(*v >= 0.5), n + 1)
        });
    if seen == 0 {
        return Err(StageError::invalid(
            "no camera pixel lands on the scan: no view area can be read",
        ));
    }
    Ok(inside as f64 / seen as f64)
}

/// (A/A0 of the whole scan, A/A0 in the view) of each of a model's maps,
/// with (0, 0) and (1, 1), sorted.
fn view_relation_of_maps(
    maps: &[(f64, Field)],
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<Vec<(f64, f64)>, StageError> {
    let mut relation = vec![(0.0, 0.0), (1.0, 1.0)];
    for (whole, field) in maps {
        relation.push((*whole, view_fraction(field, registration, camera)?));
    }
    relation.sort_by(|a, b| a.0.total_cmp(&b.0));
    relation.dedup_by(|a, b| a.0 == b.0);
    Ok(relation)
}

/// Profile theory's relation: the height map cut at A/A0 = 0.01 … 0.99 and
/// read in the view.
fn view_relation_of_truncation(
    truncation: &Truncation,
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<Vec<(f64, f64)>, StageError> {
    let levels = [
        0.005, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99,
    ];
    let maps: Vec<(f64, Field)> = levels.iter().map(|&a| truncation.cut(a)).collect();
    view_relation_of_maps(&maps, registration, camera)
}

/// The view A/A0 at whole-scan A/A0 `a`, linear between the relation's
/// points.
fn on_relation(relation: &[(f64, f64)], a: f64) -> f64 {
    let i = relation.partition_point(|p| p.0 < a);
    if i == 0 {
        return relation[0].1;
    }
    if i >= relation.len() {
        return relation[relation.len() - 1].1;
    }
    let (x0, y0) = relation[i - 1];
    let (x1, y1) = relation[i];
    if x1 == x0 {
        y1
    } else {
        y0 + (y1 - y0) * (a - x0) / (x1 - x0)
    }
}

/// The map whose A/A0 is nearest `fraction` (the first of equals).
fn nearest(maps: &[(f64, Field)], fraction: f64) -> &(f64, Field) {
    maps.iter()
        .min_by(|a, b| (a.0 - fraction).abs().total_cmp(&(b.0 - fraction).abs()))
        .expect("read_model_maps refuses a product without maps")
}

fn predicted(field: &Field) -> PredictedMap<'_> {
    PredictedMap {
        fraction: field.values.view(),
        dx_m: field.dx_m,
        dy_m: field.dy_m,
    }
}

fn mask(map: &ObservedMap) -> ObservedMask<'_> {
    ObservedMask {
        contact: &map.contact,
        width_px: map.width,
        height_px: map.height,
        pixel_m: map.pixel_m,
    }
}

fn labels(models: &[ModelMaps]) -> String {
    if models.is_empty() {
        "none connected".to_owned()
    } else {
        models
            .iter()
            .map(|m| m.label.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// contact-images' maps: the masks its index lists.
fn read_observed(inputs: &Inputs) -> Result<Vec<ObservedMap>, StageError> {
    let (files, index) = inputs.indexed_files::<ObservedMapIndex>("observed_maps")?;
    let source = FileSource::Files {
        files,
        input: "observed_maps".into(),
    };
    if index.file.is_empty() {
        return Err(StageError::invalid(
            "input `observed_maps`: its index lists no map",
        ));
    }
    let mut maps = Vec::with_capacity(index.file.len());
    for (k, file) in index.file.iter().enumerate() {
        let image = GrayFrame::decode(&source.display(file), &source.read(file)?)?;
        let half = image.full_scale() / 2.0;
        maps.push(ObservedMap {
            requested: index.requested_area_fraction[k],
            area_fraction: index.area_fraction[k],
            frame: index.frame[k],
            pixel_m: index.pixel_m[k],
            width: image.width,
            height: image.height,
            contact: image.data.iter().map(|&v| f64::from(v) > half).collect(),
        });
    }
    Ok(maps)
}

/// Each labelled model's contact maps: the pressure maps its index lists
/// (contact where the pressure is positive).
fn read_model_maps(inputs: &Inputs) -> Result<Vec<ModelMaps>, StageError> {
    let mut models = Vec::new();
    for (label, _) in inputs.labelled("model_maps") {
        let input = format!("model_maps.{label}");
        let (files, index) = inputs.indexed_files::<ModelMapIndex>(&input)?;
        let source = FileSource::Files {
            files,
            input: input.clone(),
        };
        if index.pressure_file.is_empty() {
            return Err(StageError::invalid(format!(
                "input `{input}`: its index lists no map"
            )));
        }
        let mut maps = Vec::with_capacity(index.pressure_file.len());
        for (k, name) in index.pressure_file.iter().enumerate() {
            let bytes = source.read(name)?;
            let pressure = Field::read_npy(&bytes[..], index.dx_m[k], index.dy_m[k])
                .map_err(|e| StageError::file(source.display(name), e.to_string()))?;
            let values: Array2<f64> = pressure.values.mapv(|p| {
                if p.is_nan() {
                    f64::NAN
                } else if p > 0.0 {
                    1.0
                } else {
                    0.0
                }
            });
            maps.push((
                index.area_fraction[k],
                Field {
                    values,
                    dx_m: index.dx_m[k],
                    dy_m: index.dy_m[k],
                },
            ));
        }
        models.push(ModelMaps {
            label: label.to_owned(),
            maps,
        });
    }
    Ok(models)
}

/// A robust standard deviation: 1.4826 × the median absolute deviation
/// from the median (equal to σ for Gaussian scatter, and not thrown by one
/// map that registers badly); NaN for fewer than two values.
fn robust_sd(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return f64::NAN;
    }
    median_and_sigma(values).1
}

fn transform_table(
    against: &str,
    observed: &[&ObservedMap],
    found: &[Registration],
    adopted: usize,
) -> TransformTable {
    let r = &found[adopted];
    let of = |f: fn(&Registration) -> f64| robust_sd(&found.iter().map(f).collect::<Vec<_>>());
    TransformTable {
        against: vec![against.to_owned()],
        frame: vec![observed[adopted].frame],
        area_fraction: vec![observed[adopted].area_fraction],
        angle_deg: vec![r.placement.angle_rad.to_degrees()],
        shift_x_m: vec![r.placement.shift_x_m],
        shift_y_m: vec![r.placement.shift_y_m],
        scale: vec![r.scale],
        zncc: vec![r.score],
        registrations: vec![found.len() as i64],
        angle_sd_deg: vec![of(|r| r.placement.angle_rad.to_degrees())],
        shift_x_sd_m: vec![of(|r| r.placement.shift_x_m)],
        shift_y_sd_m: vec![of(|r| r.placement.shift_y_m)],
        scale_sd: vec![of(|r| r.scale)],
    }
}

/// Ranks by rms log ratio (1 = best; ties keep the label order).
fn agreement_table(scores: &[(String, crate::agreement::Agreement)]) -> AgreementTable {
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by(|&i, &j| {
        scores[i]
            .1
            .rms_log_ratio
            .total_cmp(&scores[j].1.rms_log_ratio)
    });
    let mut rank = vec![0i64; scores.len()];
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r as i64 + 1;
    }
    AgreementTable {
        model: scores.iter().map(|s| s.0.clone()).collect(),
        rms_log_ratio: scores.iter().map(|s| s.1.rms_log_ratio).collect(),
        mean_log_ratio: scores.iter().map(|s| s.1.mean_log_ratio).collect(),
        points: scores.iter().map(|s| s.1.points as i64).collect(),
        outside_model: scores.iter().map(|s| s.1.outside_model as i64).collect(),
        area: vec!["whole".to_owned(); scores.len()],
        rank,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_is_not_thrown_by_one_bad_registration() {
        // 1.4826 × MAD: for ±1 about 0 (MAD 1) it is 1.4826; one wild
        // value among five moves it little, where the plain sd explodes.
        assert!((robust_sd(&[-1.0, 1.0, 0.0, -1.0, 1.0]) - 1.4826).abs() < 1e-12);
        assert!((robust_sd(&[-1.0, 1.0, 0.0, -1.0, 100.0]) - 1.4826).abs() < 1e-12);
        assert!(robust_sd(&[2.5]).is_nan());
    }

    #[test]
    fn truncation_keeps_the_highest_points_and_skips_unmeasured_ones() {
        let values =
            ndarray::Array2::from_shape_vec((2, 3), vec![1.0, 5.0, f64::NAN, 3.0, 4.0, 2.0])
                .unwrap();
        let surface = Field::new(values, 1e-5, 1e-5).unwrap();
        let truncation = Truncation::new(&surface);
        let (fraction, cut) = truncation.cut(0.4);
        assert_eq!(fraction, 0.4);
        let got: Vec<f64> = cut.values.iter().copied().collect();
        assert_eq!(got[..2], [0.0, 1.0]);
        assert!(got[2].is_nan());
        assert_eq!(got[3..], [0.0, 1.0, 0.0]);
        let (none, _) = truncation.cut(0.0);
        assert_eq!(none, 0.0);
    }
}
