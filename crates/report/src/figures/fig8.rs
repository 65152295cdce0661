//! Fig. 8 of the paper: the composite tangent modulus ratio E_t*/E0*
//! against the contact area fraction A/A0 for every sample (the paper
//! reports 2.2–3 for the hyperelastic ICM), of every model whose ratio is
//! not 1 throughout: a linear law's ratio is 1 by construction and is not
//! drawn (it would squeeze the nonlinear range). Colour = sample; the
//! models are told apart by stroke (solid, dotted, dashed, long and short
//! dashes, in the roster's order). Where a drawn model's bootstrap band is wired, its 5–95 % range
//! of E_t*/E0* (each replicate over its own E0*) is shaded under the
//! curves in the sample's colour.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::fig2::min_max;
use super::fig7::{LEGEND_PX, SampleResponses, area_axes};
use super::plotting::{
    Axis, Figure, LegendEntry, Line, Rasters, TextSizes, band_legend, draw_band, draw_curve,
    draw_legend, sample_colour, thin, tick_linear,
};
use crate::ReportError;
use crate::band::{Band, runs};
use crate::roster::ModelKey;

/// The strokes that tell Fig. 8's models apart, in order.
const STROKES: [Line; 5] = [
    Line::Solid,
    Line::Dotted,
    Line::Dashed,
    Line::LongDashed,
    Line::ShortDashed,
];

pub struct Fig8<'a> {
    pub samples: Vec<SampleResponses<'a>>,
    /// The models drawn (those with a ratio other than 1), in order.
    pub models: Vec<&'a ModelKey>,
}

/// The plotted ranges: A/A0 up to `x_hi`, E_t*/E0* from `y_lo` to `y_hi`.
struct Ranges {
    x_hi: f64,
    y_lo: f64,
    y_hi: f64,
}

impl Fig8<'_> {
    /// A model's line and width: the strokes in turn, thinner on each
    /// round, so a fourth model is not drawn as the first.
    fn stroke(&self, key: &ModelKey) -> (Line, u32) {
        let k = self.models.iter().position(|m| m.label == key.label);
        let k = k.unwrap_or(0);
        let round = (k / STROKES.len()) as u32;
        (
            STROKES[k % STROKES.len()],
            3u32.saturating_sub(round).max(1),
        )
    }

    fn bands(&self) -> impl Iterator<Item = &Band> {
        self.samples
            .iter()
            .flat_map(|s| s.bands.iter().map(|b| b.1))
    }

    fn ranges(&self) -> Ranges {
        let curves = || {
            self.samples
                .iter()
                .flat_map(|s| s.curves.iter().map(|d| d.response))
        };
        let (lo, hi) = min_max(
            curves()
                .flat_map(|r| r.tangent_ratio.iter().copied())
                .chain(self.bands().flat_map(|b| {
                    b.tangent_ratio_p05
                        .iter()
                        .chain(&b.tangent_ratio_p95)
                        .copied()
                })),
        );
        let pad = 0.08 * (hi - lo).max(0.1);
        let x_hi = curves()
            .flat_map(|r| r.area_fraction.iter().copied())
            .chain(self.bands().flat_map(|b| b.area_fraction.iter().copied()))
            .fold(0.0f64, f64::max)
            .clamp(0.05, 1.0);
        Ranges {
            x_hi,
            y_lo: (lo - pad).max(0.0),
            y_hi: hi + pad,
        }
    }

    /// The samples' colour key, then the models' stroke key (when more
    /// than one model is drawn) and the band's.
    fn legend(&self) -> Vec<LegendEntry> {
        let mut legend: Vec<LegendEntry> = self
            .samples
            .iter()
            .map(|s| LegendEntry {
                label: s.label.to_owned(),
                style: sample_colour(s.colour_index).stroke_width(3),
                line: s
                    .curves
                    .first()
                    .map_or(Line::Solid, |d| self.stroke(d.key).0),
            })
            .collect();
        if self.models.len() > 1 {
            for key in &self.models {
                legend.push(LegendEntry {
                    label: key.label.clone(),
                    style: BLACK.stroke_width(self.stroke(key).1),
                    line: self.stroke(key).0,
                });
            }
        }
        if self.bands().next().is_some() {
            legend.push(band_legend(BLACK));
        }
        legend
    }
}

impl Figure for Fig8<'_> {
    fn name(&self) -> &'static str {
        "fig8"
    }

    fn size_px(&self) -> (u32, u32) {
        (1000, 680)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let name = self.name();
        let err = |e| ReportError::plot(name, e);
        let sizes = TextSizes::for_width(self.size_px().0);
        let Ranges { x_hi, y_lo, y_hi } = self.ranges();
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .margin_right(LEGEND_PX as i32)
            .x_label_area_size(sizes.label * 2.9)
            .y_label_area_size(sizes.label * 3.4)
            .build_cartesian_2d(Axis::new(0.0, x_hi, 6), Axis::new(y_lo, y_hi, 8))
            .map_err(err)?;
        area_axes(
            &mut chart,
            (name, sizes),
            "tangent modulus ratio Eₜ*/E₀*",
            &|v| tick_linear(*v),
            8,
        )?;
        // Every band first, so no sample's shading covers another's curve.
        let finite = |v: f64| v.is_finite().then_some(v);
        for s in &self.samples {
            for (_, band) in &s.bands {
                let (x, lower, upper) = (
                    &band.area_fraction,
                    &band.tangent_ratio_p05,
                    &band.tangent_ratio_p95,
                );
                for run in runs(x, lower, upper, finite) {
                    let spans = (x_hi, y_hi - y_lo, 0.006);
                    draw_band(&mut chart, name, &run, spans, sample_colour(s.colour_index))?;
                }
            }
        }
        for s in &self.samples {
            let colour = sample_colour(s.colour_index);
            for d in &s.curves {
                let r = d.response;
                let points: Vec<(f64, f64)> = r
                    .area_fraction
                    .iter()
                    .copied()
                    .zip(r.tangent_ratio.iter().copied())
                    .collect();
                let points = thin(&points, x_hi, y_hi - y_lo, 0.006);
                let (line, width) = self.stroke(d.key);
                draw_curve(&mut chart, name, points, line, colour.stroke_width(width))?;
            }
        }
        let legend = self.legend();
        let (plot_x, plot_y) = chart.plotting_area().get_base_pixel();
        let plot_w = chart.plotting_area().dim_in_pixel().0 as i32;
        let (root_x, root_y) = root.get_base_pixel();
        draw_legend(
            name,
            root,
            (plot_x - root_x + plot_w + 25, plot_y - root_y + 10),
            &legend,
            sizes.legend,
        )
    }
}
