//! The contact models the report was given, as a role: every label wired
//! under `responses` (sample → model label → response table), in one
//! order, each with the colour and line it keeps in every figure and
//! table. Nothing here knows a model by name: the order is the `models`
//! parameter's (then label order), a label's colour is that of its family
//! (the text before its first `-`, so `x` and `x-linear` share one), and
//! its line is read from the data: a model whose every response has
//! E_t*/E0* = 1 throughout is linear (dashed), any other solid.

use crate::ReportError;
use crate::gather::{Response, Sample};

/// One model of the roster.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelKey {
    pub label: String,
    /// Index into the model palette, by family in order of first label.
    pub colour: usize,
    /// Every response of this label has tangent_ratio 1 everywhere.
    pub linear: bool,
}

/// The wired models in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Roster {
    pub models: Vec<ModelKey>,
}

/// Whether a response is that of a linear law: E_t*/E0* is 1 on every row.
pub fn is_linear(response: &Response) -> bool {
    response.tangent_ratio.iter().all(|&t| t == 1.0)
}

fn family(label: &str) -> &str {
    label.split('-').next().unwrap_or(label)
}

/// A model's law as its label names it where the data cannot (a patch
/// curve has no tangent ratio): no suffix = the paper's equibiaxial tangent
/// modulus (every contact model's default), `-uniaxial`, `-linear`, or
/// another suffix. Fig. 10's strokes and the findings read it alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LabelLaw {
    Equibiaxial,
    Uniaxial,
    Linear,
    Other,
}

/// The law of `label`, from its suffix.
pub fn label_law(label: &str) -> LabelLaw {
    match label.split_once('-').map(|(_, law)| law) {
        None => LabelLaw::Equibiaxial,
        Some("uniaxial") => LabelLaw::Uniaxial,
        Some("linear") => LabelLaw::Linear,
        Some(_) => LabelLaw::Other,
    }
}

impl Roster {
    /// The labels of `samples`' responses: those named in `order` first, in
    /// its order, then the rest in label order.
    pub fn new(order: &[String], samples: &[Sample<'_>]) -> Self {
        let mut labels: Vec<&str> = Vec::new();
        let mut wired: Vec<&str> = samples
            .iter()
            .flat_map(|s| s.models.iter().map(|m| m.label.as_str()))
            .collect();
        wired.sort_unstable();
        wired.dedup();
        labels.extend(
            order
                .iter()
                .map(String::as_str)
                .filter(|l| wired.contains(l)),
        );
        labels.extend(wired.iter().filter(|l| !order.iter().any(|o| o == *l)));
        let mut families: Vec<&str> = Vec::new();
        let models = labels
            .into_iter()
            .map(|label| {
                let f = family(label);
                let colour = families.iter().position(|g| *g == f).unwrap_or_else(|| {
                    families.push(f);
                    families.len() - 1
                });
                let linear = samples
                    .iter()
                    .filter_map(|s| s.response(label))
                    .all(is_linear);
                ModelKey {
                    label: label.to_owned(),
                    colour,
                    linear,
                }
            })
            .collect();
        Roster { models }
    }

    /// The place of `label` in the order (past the end when not wired).
    pub fn position(&self, label: &str) -> usize {
        self.models
            .iter()
            .position(|m| m.label == label)
            .unwrap_or(self.models.len())
    }

    pub fn get(&self, label: &str) -> Option<&ModelKey> {
        self.models.iter().find(|m| m.label == label)
    }

    /// The wired labels, comma-separated, for messages.
    pub fn labels(&self) -> String {
        if self.models.is_empty() {
            return "none".to_owned();
        }
        let labels: Vec<&str> = self.models.iter().map(|m| m.label.as_str()).collect();
        labels.join(", ")
    }

    /// The models parameter `param` lists (every wired one when it lists
    /// none), in roster order; a label not wired is an error naming the
    /// parameter, the label and the wired ones.
    pub fn select(&self, param: &str, wanted: &[String]) -> Result<Vec<&ModelKey>, ReportError> {
        self.check(param, wanted)?;
        Ok(self
            .models
            .iter()
            .filter(|m| wanted.is_empty() || wanted.contains(&m.label))
            .collect())
    }

    /// Refuses a label of `wanted` that no response is wired under.
    pub fn check(&self, param: &str, wanted: &[String]) -> Result<(), ReportError> {
        match wanted.iter().find(|w| self.get(w).is_none()) {
            Some(unknown) => Err(ReportError::Param {
                param: param.to_owned(),
                message: format!(
                    "`{unknown}` is not a model label of `responses` (wired: {})",
                    self.labels()
                ),
            }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gather::ModelResponse;

    fn sample(labels: &[(&str, f64)]) -> Sample<'static> {
        Sample {
            label: "T1".into(),
            models: labels
                .iter()
                .map(|&(label, ratio)| ModelResponse {
                    label: label.into(),
                    response: Response {
                        area_fraction: vec![0.1, 0.2],
                        load_norm: vec![0.01, 0.02],
                        tangent_ratio: vec![1.0, ratio],
                        ..Default::default()
                    },
                })
                .collect(),
            ..Default::default()
        }
    }

    #[test]
    fn order_families_and_laws_come_from_the_parameter_and_the_data() {
        let s = sample(&[("b", 2.0), ("a-lin", 1.0), ("a", 2.5), ("c", 1.0)]);
        let roster = Roster::new(&["a".into(), "a-lin".into()], &[s]);
        let got: Vec<(&str, usize, bool)> = roster
            .models
            .iter()
            .map(|m| (m.label.as_str(), m.colour, m.linear))
            .collect();
        assert_eq!(
            got,
            [
                ("a", 0, false),
                ("a-lin", 0, true),
                ("b", 1, false),
                ("c", 2, true)
            ]
        );
    }

    #[test]
    fn an_unknown_label_names_the_parameter_and_the_wired_ones() {
        let roster = Roster::new(&[], &[sample(&[("x", 2.0), ("y", 1.0)])]);
        assert_eq!(roster.select("fig7_models", &[]).unwrap().len(), 2);
        let e = roster
            .select("fig7_models", &["x".into(), "z".into()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("fig7_models") && e.contains("`z`") && e.contains("wired: x, y"),
            "{e}"
        );
    }
}
