//! Each prediction laid over each observed map with the adopted
//! registration: the overlap counts per frame and model (table `overlap`)
//! and, for the maps requested at `figure_fractions`, the figures
//! (observed, predicted and overlay PNGs) with their typed index
//! [`FigureIndex`]. Overlay colours are Okabe–Ito's (distinguishable with
//! the common colour-vision deficiencies).

use hypercontact_core::contact::area_fraction_label;
use hypercontact_core::{Files, Schema, StageError};
use hypercontact_interference::CameraGrid;
use hypercontact_labfiles::png::{Pixels, encode_png};

use crate::maps::{ObservedMap, Predictions, predicted};
use crate::overlap::{Agreement as Class, Overlap, classify, overlap};
use crate::register::{Registration, sample_predicted};
use crate::stage::{ContactCompareParams, OverlapTable};

/// The index of `contact-compare`'s `figures`: one row per drawn observed
/// map and prediction.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct FigureIndex {
    /// `truncation` or the model_maps label
    pub model: Vec<String>,
    /// the A/A0 the observed map was asked for (contact-images' map_fractions)
    pub requested_area_fraction: Vec<f64>,
    /// measured A/A0 of the frame
    pub area_fraction: Vec<f64>,
    /// A/A0 of the prediction's map
    pub model_area_fraction: Vec<f64>,
    pub frame: Vec<i64>,
    /// the observed map (contact black)
    pub observed_file: Vec<String>,
    /// the prediction on the camera's pixels (contact black, off the scan grey)
    pub predicted_file: Vec<String>,
    /// both: black both, vermillion predicted only, sky blue observed only
    pub overlay_file: Vec<String>,
    /// the figures' pixel on the sample (the camera's, times the subsampling)
    #[column(unit = "m")]
    pub pixel_m: Vec<f64>,
    #[column(unit = "px")]
    pub width_px: Vec<i64>,
    #[column(unit = "px")]
    pub height_px: Vec<i64>,
}

const GREY: [u8; 3] = [200, 200, 200];

/// Both black, predicted only vermillion, observed only sky blue, neither
/// white, off the scan grey.
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

/// The overlap table and the figures with their index.
pub(crate) fn overlay_all(
    p: &ContactCompareParams,
    observed: &[ObservedMap],
    predictions: &Predictions,
    registration: &Registration,
) -> Result<(OverlapTable, Files), StageError> {
    let names = predictions.names();
    let mut overlaps = OverlapTable::default();
    let mut figures = Files::new();
    let mut index = FigureIndex::default();
    for map in observed {
        let drawn = p
            .figure_fractions
            .iter()
            .any(|f| (f - map.requested).abs() < 1e-9);
        let mut sheet = drawn.then(|| Sheet::new(map, p.figure_px));
        if let Some(sheet) = &sheet {
            let png = sheet
                .figure
                .png(|i| if map.contact[i] { [0; 3] } else { [255; 3] })?;
            figures.files.insert(sheet.observed_file.clone(), png);
        }
        for model in &names {
            let (model_fraction, field) = predictions.map(model, map.area_fraction)?;
            let sampled = sample_predicted(&predicted(&field), registration, &camera_of(map))
                .map_err(|e| StageError::invalid(format!("`{model}` on the camera: {e}")))?;
            let on_camera: Vec<Option<bool>> = sampled
                .iter()
                .map(|v| (!v.is_nan()).then_some(*v >= 0.5))
                .collect();
            let o = overlap(&on_camera, &map.contact).map_err(|e| {
                StageError::invalid(format!("`{model}` at frame {}: {e}", map.frame))
            })?;
            push_overlap(&mut overlaps, model, map, model_fraction, &o);
            if let Some(sheet) = &mut sheet {
                let drawing = Drawing {
                    model,
                    model_fraction,
                    on_camera: &on_camera,
                };
                sheet.draw(&drawing, map, &mut figures, &mut index)?;
            }
        }
    }
    Ok((overlaps, figures.with_index(index)))
}

fn camera_of(map: &ObservedMap) -> CameraGrid {
    CameraGrid {
        width_px: map.width,
        height_px: map.height,
        pixel_m: map.pixel_m,
    }
}

fn push_overlap(
    overlaps: &mut OverlapTable,
    model: &str,
    map: &ObservedMap,
    model_fraction: f64,
    o: &Overlap,
) {
    overlaps.model.push(model.to_owned());
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
}

/// One prediction of one observed map, on the camera's pixels.
struct Drawing<'a> {
    model: &'a str,
    model_fraction: f64,
    on_camera: &'a [Option<bool>],
}

/// The figures of one drawn observed map.
struct Sheet {
    figure: Subsample,
    label: String,
    observed_file: String,
}

impl Sheet {
    fn new(map: &ObservedMap, figure_px: usize) -> Self {
        let label = area_fraction_label(map.requested);
        Sheet {
            figure: Subsample::new(map.width, map.height, figure_px),
            observed_file: format!("observed_{label}.png"),
            label,
        }
    }

    /// The prediction's map and its overlay on the observed one, indexed.
    fn draw(
        &self,
        d: &Drawing,
        map: &ObservedMap,
        figures: &mut Files,
        index: &mut FigureIndex,
    ) -> Result<(), StageError> {
        let (model, label) = (d.model, &self.label);
        let predicted_file = format!("predicted_{model}_{label}.png");
        let overlay_file = format!("overlay_{model}_{label}.png");
        let predicted_png = self.figure.png(|i| match d.on_camera[i] {
            Some(true) => [0; 3],
            Some(false) => [255; 3],
            None => GREY,
        })?;
        figures.files.insert(predicted_file.clone(), predicted_png);
        let overlay_png = self
            .figure
            .png(|i| colour(classify(d.on_camera[i], map.contact[i])))?;
        figures.files.insert(overlay_file.clone(), overlay_png);
        index.model.push(model.to_owned());
        index.requested_area_fraction.push(map.requested);
        index.area_fraction.push(map.area_fraction);
        index.model_area_fraction.push(d.model_fraction);
        index.frame.push(map.frame);
        index.observed_file.push(self.observed_file.clone());
        index.predicted_file.push(predicted_file);
        index.overlay_file.push(overlay_file);
        index.pixel_m.push(map.pixel_m * self.figure.step as f64);
        index.width_px.push(self.figure.width as i64);
        index.height_px.push(self.figure.height as i64);
        Ok(())
    }
}
