//! The contact maps `contact-compare` sets side by side: the observed
//! masks (contact-images' or synth-contact's, read through their
//! [`ObservedMapIndex`]), every labelled model's pressure maps (through
//! [`ModelMapIndex`]: contact where the pressure is positive), and profile
//! theory's prediction, the height map cut at an area fraction
//! ([`Truncation`]). [`Predictions`] hands any of them out by name.

use hypercontact_core::contact::{ModelMapIndex, ObservedMapIndex};
use hypercontact_core::{Field, Inputs, StageError};
use hypercontact_labfiles::FileSource;
use hypercontact_labfiles::sequence::GrayFrame;
use ndarray::Array2;

use crate::register::{ObservedMask, PredictedMap};

/// The profile-theory prediction's name in the tables: the height map cut
/// at the observed area fraction.
pub const TRUNCATION: &str = "truncation";

/// One observed contact map.
pub(crate) struct ObservedMap {
    pub requested: f64,
    pub area_fraction: f64,
    pub frame: i64,
    pub pixel_m: f64,
    pub width: usize,
    pub height: usize,
    pub contact: Vec<bool>,
}

impl ObservedMap {
    pub fn mask(&self) -> ObservedMask<'_> {
        ObservedMask {
            contact: &self.contact,
            width_px: self.width,
            height_px: self.height,
            pixel_m: self.pixel_m,
        }
    }
}

/// A model's contact maps on the scan's grid, with their A/A0.
pub(crate) struct ModelMaps {
    pub label: String,
    pub maps: Vec<(f64, Field)>,
}

/// Profile theory's contact maps of one height map: its measured heights
/// sorted once, highest first, and cut at any area fraction.
pub(crate) struct Truncation<'a> {
    surface: &'a Field,
    descending: Vec<f64>,
}

impl<'a> Truncation<'a> {
    pub fn new(surface: &'a Field) -> Self {
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
    pub fn cut(&self, fraction: f64) -> (f64, Field) {
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
            short_cutoff_m: None,
        };
        (inside as f64 / n.max(1) as f64, field)
    }
}

/// Every prediction of a contact map: the truncation and each labelled
/// model's maps.
pub(crate) struct Predictions<'a> {
    pub truncation: Truncation<'a>,
    pub models: Vec<ModelMaps>,
}

impl Predictions<'_> {
    /// The labelled model `label`'s maps, if wired.
    pub fn model(&self, label: &str) -> Option<&ModelMaps> {
        self.models.iter().find(|m| m.label == label)
    }

    /// `truncation` first, then the model_maps labels in label order.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec![TRUNCATION.to_owned()];
        names.extend(self.models.iter().map(|m| m.label.clone()));
        names
    }

    /// The prediction `name` registers against or is scored with at the
    /// observed A/A0 `fraction`: the truncation cut there, or the model's
    /// nearest map; with its own A/A0.
    pub fn map(&self, name: &str, fraction: f64) -> Result<(f64, Field), StageError> {
        if name == TRUNCATION {
            return Ok(self.truncation.cut(fraction));
        }
        let maps = self
            .model(name)
            .ok_or_else(|| StageError::invalid(format!("no model_maps labelled `{name}`")))?;
        Ok(nearest(&maps.maps, fraction).clone())
    }

    /// Refuses a name that is neither `truncation` nor a model_maps label,
    /// naming parameter `param` and the labels wired.
    pub fn check_name(&self, param: &str, name: &str) -> Result<(), StageError> {
        if name == TRUNCATION || self.model(name).is_some() {
            return Ok(());
        }
        let wired = if self.models.is_empty() {
            "none connected".to_owned()
        } else {
            let labels: Vec<&str> = self.models.iter().map(|m| m.label.as_str()).collect();
            labels.join(", ")
        };
        Err(StageError::invalid(format!(
            "parameter `{param}` = {name}: not `{TRUNCATION}` nor a label of `model_maps` \
             ({wired})"
        )))
    }
}

/// The map whose A/A0 is nearest `fraction` (the first of equals).
fn nearest(maps: &[(f64, Field)], fraction: f64) -> &(f64, Field) {
    maps.iter()
        .min_by(|a, b| (a.0 - fraction).abs().total_cmp(&(b.0 - fraction).abs()))
        .expect("read_model_maps refuses a product without maps")
}

/// A contact map (1 = contact) as the registration reads it.
pub(crate) fn predicted(field: &Field) -> PredictedMap<'_> {
    PredictedMap {
        fraction: field.values.view(),
        dx_m: field.dx_m,
        dy_m: field.dy_m,
    }
}

/// contact-images' maps: the masks its index lists.
pub(crate) fn read_observed(inputs: &Inputs) -> Result<Vec<ObservedMap>, StageError> {
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
pub(crate) fn read_model_maps(inputs: &Inputs) -> Result<Vec<ModelMaps>, StageError> {
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
            maps.push((index.area_fraction[k], contact_of(&pressure)));
        }
        models.push(ModelMaps {
            label: label.to_owned(),
            maps,
        });
    }
    Ok(models)
}

/// 1 where the pressure is positive, 0 where not, NaN where not measured.
fn contact_of(pressure: &Field) -> Field {
    let values: Array2<f64> = pressure.values.mapv(|p| {
        if p.is_nan() {
            f64::NAN
        } else if p > 0.0 {
            1.0
        } else {
            0.0
        }
    });
    Field {
        values,
        dx_m: pressure.dx_m,
        dy_m: pressure.dy_m,
        short_cutoff_m: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
