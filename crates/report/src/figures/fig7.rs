//! Fig. 7 of the paper: normalised load F/(E0* A0) against the contact area
//! fraction A/A0 for every sample, hyperelastic ICM solid and linear
//! (Wang's original) ICM dashed, on a logarithmic load axis so the early
//! contact, where the two models differ most in relative terms, stays visible.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plotting::{
    Axis, Figure, LegendEntry, Rasters, TextSizes, draw_axes, draw_legend, sample_colour, thin,
    tick_decade, tick_linear,
};
use crate::ReportError;
use crate::gather::Response;

/// One sample's curves: (label, colour index, hyperelastic, linear).
pub struct SampleResponses<'a> {
    pub label: &'a str,
    pub colour_index: usize,
    pub hyperelastic: Option<&'a Response>,
    pub linear: Option<&'a Response>,
}

pub struct Fig7<'a> {
    pub samples: Vec<SampleResponses<'a>>,
}

/// Width reserved right of the plot for the legend, pixels.
pub const LEGEND_PX: u32 = 250;

/// Decade bounds around the positive values, at most `max_decades` deep.
pub fn log_range(values: impl Iterator<Item = f64>, max_decades: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (1e-3, 1.0);
    }
    let top = hi.log10().ceil();
    let bottom = lo.log10().floor().max(top - max_decades);
    let bottom = if bottom >= top { top - 1.0 } else { bottom };
    (10f64.powf(bottom), 10f64.powf(top))
}

impl Figure for Fig7<'_> {
    fn name(&self) -> &'static str {
        "fig7"
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
        let responses = || {
            self.samples
                .iter()
                .flat_map(|s| s.hyperelastic.into_iter().chain(s.linear))
        };
        let (y_lo, y_hi) = log_range(responses().flat_map(|r| r.load_norm.iter().copied()), 5.0);
        let x_hi = responses()
            .flat_map(|r| r.area_fraction.iter().copied())
            .fold(0.0f64, f64::max)
            .clamp(0.05, 1.0);
        let (e_lo, e_hi) = (y_lo.log10(), y_hi.log10());
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .margin_right(LEGEND_PX as i32)
            .x_label_area_size(sizes.label * 2.9)
            .y_label_area_size(sizes.label * 3.4)
            .build_cartesian_2d(Axis::new(0.0, x_hi, 6), Axis::decades(e_lo, e_hi, 12))
            .map_err(err)?;
        draw_axes(
            &mut chart,
            name,
            sizes,
            "contact area fraction A/A₀",
            "normalised load F/(E₀* A₀)",
            &|v| tick_linear(*v),
            &|v| tick_decade(*v),
            (6, (e_hi - e_lo) as usize + 1),
        )?;

        // Drawn as log10 on a linear axis, so decade ticks are exact.
        let visible = |r: &Response| -> Vec<(f64, f64)> {
            let points: Vec<(f64, f64)> = r
                .area_fraction
                .iter()
                .zip(&r.load_norm)
                .filter(|&(_, &f)| f >= y_lo && f <= y_hi)
                .map(|(&a, &f)| (a, f.log10()))
                .collect();
            thin(&points, x_hi, e_hi - e_lo, 0.006)
        };
        let mut legend = Vec::new();
        for s in &self.samples {
            let colour = sample_colour(s.colour_index);
            let style = colour.stroke_width(3);
            if let Some(r) = s.hyperelastic {
                chart
                    .draw_series(LineSeries::new(visible(r), style))
                    .map_err(err)?;
            }
            if let Some(r) = s.linear {
                chart
                    .draw_series(DashedLineSeries::new(visible(r), 12, 8, style))
                    .map_err(err)?;
            }
            legend.push(LegendEntry {
                label: s.label.to_owned(),
                style,
                dashed: s.hyperelastic.is_none(),
            });
        }
        // Line-style key in black, after the colour key.
        let key = BLACK.stroke_width(3);
        if self.samples.iter().any(|s| s.hyperelastic.is_some()) {
            legend.push(LegendEntry {
                label: "hyperelastic ICM".into(),
                style: key,
                dashed: false,
            });
        }
        if self.samples.iter().any(|s| s.linear.is_some()) {
            legend.push(LegendEntry {
                label: "linear ICM".into(),
                style: key,
                dashed: true,
            });
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_range_spans_whole_decades_and_caps_depth() {
        let (lo, hi) = log_range([0.0, 2e-4, 0.03, 0.5].into_iter(), 5.0);
        assert!((lo - 1e-4).abs() < 1e-18 && (hi - 1.0).abs() < 1e-12);
        let (lo, _) = log_range([1e-12, 0.5].into_iter(), 3.0);
        assert!((lo - 1e-3).abs() < 1e-15);
        assert_eq!(log_range(std::iter::empty(), 5.0), (1e-3, 1.0));
    }
}
