//! Figs. 4d and 4e: every sample in its colour on shared axes. 4d: (a) the
//! rms slope and (b) the rms curvature against scale, log–log (variable
//! bandwidth); 4e: the probability densities of (a) the height about the
//! mean plane and (b) the slope |∇h|.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::fig2::min_max;
use super::fig4b::{TICK_PX, boxed_legend, letter, missing_panel, panel_chart, panel_title};
use super::fig7::log_range;
use super::plotting::{
    Axis, Figure, LegendEntry, Line, Rasters, TextSizes, draw_axes, draw_curve, sample_colour,
    tick_decade, tick_linear,
};
use crate::ReportError;
use crate::gather::{Sample, Series};
use crate::surface_stats::Density;

const WIDTH_PX: u32 = 1200;
const HEIGHT_PX: u32 = 500;

/// A sample's legend line in its colour.
fn sample_entry(sample: &Sample<'_>, colour_index: usize) -> LegendEntry {
    LegendEntry {
        label: sample.label.clone(),
        style: sample_colour(colour_index).stroke_width(3),
        line: Line::Solid,
    }
}

/// Fig. 4d: rms slope and rms curvature against scale.
pub struct Fig4d<'a> {
    /// (sample, its colour index), samples with the scale-dependent table.
    pub samples: Vec<(&'a Sample<'a>, usize)>,
}

impl Fig4d<'_> {
    fn series(&self, curvature: bool) -> Vec<(&Series, usize, &Sample<'_>)> {
        self.samples
            .iter()
            .filter_map(|(s, c)| {
                let curves = s.extras.scale_dependent.as_ref()?;
                let series = if curvature {
                    &curves.curvature_per_m
                } else {
                    &curves.slope
                };
                (!series.x.is_empty()).then_some((series, *c, *s))
            })
            .collect()
    }
}

impl Figure for Fig4d<'_> {
    fn name(&self) -> &'static str {
        "fig4d"
    }

    fn size_px(&self) -> (u32, u32) {
        (WIDTH_PX, HEIGHT_PX)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let (left, right) = root.split_horizontally(WIDTH_PX / 2);
        let scales = self
            .series(false)
            .into_iter()
            .chain(self.series(true))
            .flat_map(|(s, _, _)| s.x.iter().copied())
            .collect::<Vec<_>>();
        let x_range = log_range(scales.into_iter(), 8.0);
        for (k, (area, curvature, y_desc)) in [
            (&left, false, "rms slope"),
            (&right, true, "rms curvature ∇²h/2 (1/m)"),
        ]
        .into_iter()
        .enumerate()
        {
            let title = format!(
                "({}) {}",
                letter(k),
                if curvature { "curvature" } else { "slope" }
            );
            let series = self.series(curvature);
            if series.is_empty() {
                missing_panel(self.name(), area, &title, "no values at any scale")?;
                continue;
            }
            log_log_panel(self.name(), area, &title, &series, x_range, y_desc)?;
        }
        Ok(())
    }
}

/// Curves of several samples on log–log axes (drawn as log10 on linear
/// axes, so the ticks sit on decades), circles at the computed scales.
fn log_log_panel<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    series: &[(&Series, usize, &Sample<'_>)],
    (x_lo, x_hi): (f64, f64),
    y_desc: &str,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let sizes = TextSizes::panel(TICK_PX);
    let (y_lo, y_hi) = log_range(series.iter().flat_map(|(s, _, _)| s.y.iter().copied()), 8.0);
    let (xe, ye) = ((x_lo.log10(), x_hi.log10()), (y_lo.log10(), y_hi.log10()));
    panel_title(figure, area, title)?;
    let mut chart = panel_chart(
        figure,
        area,
        Axis::decades(xe.0, xe.1, 9),
        Axis::decades(ye.0, ye.1, 9),
        sizes.label * 2.9,
    )?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        "scale (m)",
        y_desc,
        &|v| tick_decade(*v),
        &|v| tick_decade(*v),
        (
            ((xe.1 - xe.0) as usize + 1).min(9),
            ((ye.1 - ye.0) as usize + 1).min(9),
        ),
    )?;
    let mut legend = Vec::new();
    for (s, colour_index, sample) in series {
        let colour = sample_colour(*colour_index);
        let points: Vec<(f64, f64)> =
            s.x.iter()
                .zip(&s.y)
                .map(|(x, y)| (x.log10(), y.log10()))
                .collect();
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 5, colour.filled())))
            .map_err(err)?;
        draw_curve(
            &mut chart,
            figure,
            points,
            Line::Solid,
            colour.stroke_width(2),
        )?;
        legend.push(sample_entry(sample, *colour_index));
    }
    boxed_legend(figure, area, &chart, &legend)
}

/// Fig. 4e: height and slope densities.
pub struct Fig4e<'a> {
    /// (sample, its colour index), samples with the distributions table.
    pub samples: Vec<(&'a Sample<'a>, usize)>,
}

impl Fig4e<'_> {
    fn densities(&self, slope: bool) -> Vec<(&Density, usize, &Sample<'_>)> {
        self.samples
            .iter()
            .filter_map(|(s, c)| {
                let d = s.extras.distributions.as_ref()?;
                let density = if slope { &d.slope } else { &d.height };
                Some((density.as_ref()?, *c, *s))
            })
            .collect()
    }
}

impl Figure for Fig4e<'_> {
    fn name(&self) -> &'static str {
        "fig4e"
    }

    fn size_px(&self) -> (u32, u32) {
        (WIDTH_PX, HEIGHT_PX)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let (left, right) = root.split_horizontally(WIDTH_PX / 2);
        // Heights in µm, densities per µm; slopes are dimensionless.
        for (k, (area, slope, scale, x_desc, y_desc)) in [
            (
                &left,
                false,
                1e6,
                "height about mean plane (µm)",
                "probability density (1/µm)",
            ),
            (&right, true, 1.0, "slope |∇h|", "probability density"),
        ]
        .into_iter()
        .enumerate()
        {
            let title = format!("({}) {}", letter(k), if slope { "slope" } else { "height" });
            let densities = self.densities(slope);
            if densities.is_empty() {
                missing_panel(self.name(), area, &title, "no histogram")?;
                continue;
            }
            density_panel(
                self.name(),
                area,
                &title,
                &densities,
                scale,
                (x_desc, y_desc),
            )?;
        }
        Ok(())
    }
}

/// The outline of a histogram's bars: (x, density) corners, values scaled
/// by `scale` (densities by its inverse), starting and ending at zero.
pub fn steps(d: &Density, scale: f64) -> Vec<(f64, f64)> {
    let mut points = Vec::with_capacity(2 * d.lo.len() + 2);
    for k in 0..d.lo.len() {
        let y = d.density[k] / scale;
        if k == 0 {
            points.push((d.lo[k] * scale, 0.0));
        }
        points.push((d.lo[k] * scale, y));
        points.push((d.hi[k] * scale, y));
    }
    if let Some(&hi) = d.hi.last() {
        points.push((hi * scale, 0.0));
    }
    points
}

fn density_panel<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    densities: &[(&Density, usize, &Sample<'_>)],
    scale: f64,
    (x_desc, y_desc): (&str, &str),
) -> Result<(), ReportError> {
    let sizes = TextSizes::panel(TICK_PX);
    let outlines: Vec<Vec<(f64, f64)>> =
        densities.iter().map(|(d, _, _)| steps(d, scale)).collect();
    let (x_lo, x_hi) = min_max(outlines.iter().flatten().map(|p| p.0));
    let (_, y_hi) = min_max(outlines.iter().flatten().map(|p| p.1));
    let pad = 0.03 * (x_hi - x_lo).max(1e-12);
    panel_title(figure, area, title)?;
    let mut chart = panel_chart(
        figure,
        area,
        Axis::new(x_lo - pad, x_hi + pad, 6),
        Axis::new(0.0, y_hi.max(1e-300) * 1.08, 6),
        sizes.label * 3.3,
    )?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        x_desc,
        y_desc,
        &|v| tick_linear(*v),
        &|v| tick_linear(*v),
        (6, 6),
    )?;
    let mut legend = Vec::new();
    for (points, (_, colour_index, sample)) in outlines.into_iter().zip(densities) {
        let colour = sample_colour(*colour_index);
        draw_curve(
            &mut chart,
            figure,
            points,
            Line::Solid,
            colour.stroke_width(2),
        )?;
        legend.push(sample_entry(sample, *colour_index));
    }
    boxed_legend(figure, area, &chart, &legend)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_histogram_is_drawn_as_the_outline_of_its_bars() {
        let d = Density {
            lo: vec![0.0, 1e-6],
            hi: vec![1e-6, 2e-6],
            density: vec![2e5, 8e5],
        };
        // µm and per µm: bars of 0.2 and 0.8 over 0 … 1 and 1 … 2.
        let p = steps(&d, 1e6);
        let expected = [
            (0.0, 0.0),
            (0.0, 0.2),
            (1.0, 0.2),
            (1.0, 0.8),
            (2.0, 0.8),
            (2.0, 0.0),
        ];
        assert_eq!(p.len(), expected.len());
        for (a, b) in p.iter().zip(expected) {
            assert!(
                (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
                "{p:?}"
            );
        }
    }
}
