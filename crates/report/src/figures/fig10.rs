//! Fig. 10, the finite-strain comparison: per sample, F/(E0* A0) against
//! A/A0 on one patch, the finite-element reference thick and black, every
//! other model in its family's colour with its law's stroke (the label's
//! suffix: none = the paper's equibiaxial tangent, solid; `-uniaxial`
//! dashed; `-linear` dotted; anything else long-dashed), on a log load
//! axis over the reference's range of A/A0, where the ratios are read.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::fig7::{LEGEND_PX, Ranges, draw_load_curve, load_area_chart, log_range};
use super::plotting::{Figure, LegendEntry, Line, Rasters, TextSizes, draw_legend, model_colour};
use crate::ReportError;
use crate::gather::{PatchCurve, PatchCurves};
use crate::roster::{LabelLaw, label_law};

pub struct Fig10<'a> {
    pub patches: &'a [PatchCurves],
    /// The reference's label (black, thick).
    pub reference: &'a str,
}

/// Panels per row.
const COLUMNS: usize = 2;

/// The family of a label: its text before the first `-`.
fn family(label: &str) -> &str {
    label.split('-').next().unwrap_or(label)
}

/// A label's stroke, from its suffix.
fn stroke(label: &str) -> Line {
    match label_law(label) {
        LabelLaw::Equibiaxial => Line::Solid,
        LabelLaw::Uniaxial => Line::Dashed,
        LabelLaw::Linear => Line::Dotted,
        LabelLaw::Other => Line::LongDashed,
    }
}

impl Fig10<'_> {
    /// The families in first-seen order, the reference's first (black).
    fn families(&self) -> Vec<&str> {
        let mut families = vec![family(self.reference)];
        for (label, _) in self.patches.iter().flat_map(|p| &p.curves) {
            if !families.contains(&family(label)) {
                families.push(family(label));
            }
        }
        families
    }

    /// Every label in first-seen order, the reference first.
    fn labels(&self) -> Vec<&str> {
        let mut labels = vec![self.reference];
        for (label, _) in self.patches.iter().flat_map(|p| &p.curves) {
            if !labels.contains(&label.as_str()) {
                labels.push(label);
            }
        }
        labels
    }

    fn style(&self, label: &str) -> ShapeStyle {
        let index = self
            .families()
            .iter()
            .position(|f| *f == family(label))
            .unwrap_or(0);
        let width = if label == self.reference { 4 } else { 2 };
        model_colour(index).stroke_width(width)
    }

    fn rows(&self) -> usize {
        self.patches.len().div_ceil(COLUMNS).max(1)
    }

    /// A/A0 up to the reference's largest (every model's otherwise), and
    /// the loads of every curve up to there.
    fn ranges(&self) -> Ranges {
        let reference_top = self
            .patches
            .iter()
            .flat_map(|p| &p.curves)
            .filter(|(l, _)| l == self.reference)
            .flat_map(|(_, c)| c.area_fraction.iter().copied())
            .fold(0.0f64, f64::max);
        let x_hi = if reference_top > 0.0 {
            reference_top
        } else {
            let all = self.patches.iter().flat_map(|p| &p.curves);
            all.flat_map(|(_, c)| c.area_fraction.iter().copied())
                .fold(0.0f64, f64::max)
        }
        .clamp(0.05, 1.0);
        let loads = self
            .patches
            .iter()
            .flat_map(|p| &p.curves)
            .flat_map(|(_, c)| {
                c.area_fraction
                    .iter()
                    .zip(&c.load_norm)
                    .filter(move |(a, _)| **a <= x_hi)
                    .map(|(_, f)| *f)
            });
        let (y_lo, y_hi) = log_range(loads, 4.0);
        Ranges { x_hi, y_lo, y_hi }
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        patch: &PatchCurves,
        ranges: Ranges,
    ) -> Result<(), ReportError> {
        let name = self.name();
        let sizes = TextSizes::panel(20.0);
        let mut chart = load_area_chart(area, (name, sizes), ranges, Some(&patch.sample))?;
        // The reference last, on top.
        let mut curves: Vec<&(String, PatchCurve)> = patch.curves.iter().collect();
        curves.sort_by_key(|(l, _)| l == self.reference);
        for (label, c) in curves {
            let xy = (&c.area_fraction[..], &c.load_norm[..]);
            let style = (stroke(label), self.style(label));
            draw_load_curve(&mut chart, name, xy, ranges, style)?;
        }
        Ok(())
    }
}

impl Figure for Fig10<'_> {
    fn name(&self) -> &'static str {
        "fig10"
    }

    fn size_px(&self) -> (u32, u32) {
        let width = if self.patches.len() == 1 { 900 } else { 1300 };
        (width, 40 + 460 * self.rows() as u32)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let (width, _) = self.size_px();
        let (plot, key) = root.split_horizontally(width - LEGEND_PX);
        let ranges = self.ranges();
        if self.patches.len() == 1 {
            self.panel(&plot, &self.patches[0], ranges)?;
        } else {
            let panels = plot.split_evenly((self.rows(), COLUMNS));
            for (area, patch) in panels.iter().zip(self.patches) {
                self.panel(area, patch, ranges)?;
            }
        }
        let legend: Vec<LegendEntry> = self
            .labels()
            .into_iter()
            .map(|label| LegendEntry {
                label: label.to_owned(),
                style: self.style(label),
                line: stroke(label),
            })
            .collect();
        let sizes = TextSizes::for_width(1000);
        draw_legend(self.name(), &key, (5, 30), &legend, sizes.legend)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strokes_and_families_come_from_the_labels() {
        assert_eq!(stroke("icm"), Line::Solid);
        assert_eq!(stroke("bem-uniaxial"), Line::Dashed);
        assert_eq!(stroke("persson-linear"), Line::Dotted);
        assert_eq!(stroke("fem-small"), Line::LongDashed);
        assert_eq!(family("persson-linear"), "persson");
    }
}
