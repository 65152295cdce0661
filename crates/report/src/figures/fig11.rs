//! Fig. 11, the refinement study: F_fem / F_bem against the points per
//! shortest wavelength, one line per comparison point (colour = the A/A0
//! it is read at; solid = equal approach, dashed = equal area; the legend
//! says "approach" and "area"), a circle
//! at every level, and a grey line at 1, where the two models agree.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::fig7::LEGEND_PX;
use super::plotting::{
    Axis, Figure, LegendEntry, Line, Rasters, TextSizes, draw_axes, draw_curve, draw_legend,
    sample_colour, tick_linear,
};
use crate::ReportError;
use crate::refinement::{Comparison, Measure};

pub struct Fig11<'a> {
    pub comparisons: &'a [Comparison],
    /// Points per shortest wavelength at k = 1.
    pub points_per_wavelength: f64,
}

/// One drawn line: its legend label, stroke, colour and points.
struct Series {
    label: String,
    line: Line,
    colour: RGBColor,
    points: Vec<(f64, f64)>,
}

impl Fig11<'_> {
    fn series(&self) -> Vec<Series> {
        let fractions: Vec<f64> = {
            let mut f: Vec<f64> = Vec::new();
            for c in self.comparisons {
                if !f.contains(&c.area_fraction) {
                    f.push(c.area_fraction);
                }
            }
            f
        };
        self.comparisons
            .iter()
            .map(|c| {
                let colour_index = fractions
                    .iter()
                    .position(|a| *a == c.area_fraction)
                    .unwrap_or(0);
                let (what, line) = match c.measure {
                    Measure::Approach => ("approach", Line::Solid),
                    Measure::Area => ("area", Line::Dashed),
                };
                Series {
                    label: format!("{what}, A/A₀ = {}", c.area_fraction),
                    line,
                    colour: sample_colour(colour_index),
                    points: c
                        .levels
                        .iter()
                        .filter_map(|l| {
                            let x = self.points_per_wavelength * f64::from(l.refine);
                            l.ratio().map(|r| (x, r))
                        })
                        .collect(),
                }
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    }

    /// x from 0 past the finest level; y around every ratio and 1.
    fn ranges(series: &[Series]) -> (f64, f64, f64) {
        let points = series.iter().flat_map(|s| &s.points);
        let x_hi = points.clone().map(|p| p.0).fold(1.0f64, f64::max);
        let (lo, hi) = points.fold((1.0f64, 1.0f64), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
        let pad = 0.1 * (hi - lo).max(0.01);
        (x_hi * 1.15, lo - pad, hi + pad)
    }
}

impl Figure for Fig11<'_> {
    fn name(&self) -> &'static str {
        "fig11"
    }

    fn size_px(&self) -> (u32, u32) {
        (1000, 620)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let name = self.name();
        let err = |e| ReportError::plot(name, e);
        let sizes = TextSizes::for_width(self.size_px().0);
        let series = self.series();
        let (x_hi, y_lo, y_hi) = Self::ranges(&series);
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .margin_right(LEGEND_PX as i32 + 90)
            .x_label_area_size(sizes.label * 2.9)
            .y_label_area_size(sizes.label * 3.4)
            .build_cartesian_2d(Axis::new(0.0, x_hi, 6), Axis::new(y_lo, y_hi, 8))
            .map_err(err)?;
        draw_axes(
            &mut chart,
            name,
            sizes,
            "points per shortest wavelength",
            "load ratio F_fem / F_bem",
            &|v| tick_linear(*v),
            &|v| tick_linear(*v),
            (6, 8),
        )?;
        let grey = RGBColor(150, 150, 150).stroke_width(2);
        draw_curve(
            &mut chart,
            name,
            vec![(0.0, 1.0), (x_hi, 1.0)],
            Line::Dotted,
            grey,
        )?;
        let mut legend = Vec::new();
        for s in &series {
            let style = s.colour.stroke_width(3);
            draw_curve(&mut chart, name, s.points.clone(), s.line, style)?;
            draw_curve(&mut chart, name, s.points.clone(), Line::Circles, style)?;
            legend.push(LegendEntry {
                label: s.label.clone(),
                style,
                line: s.line,
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
