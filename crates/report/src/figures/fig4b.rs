//! Figs. 4b and 4c: per sample, the material-ratio (Abbott–Firestone)
//! curve with the ISO 13565-2 core band, and the autocorrelation against
//! lag with the 1/e and s = 0.2 levels. One panel per sample, two panels a
//! row, panel letters in sample order; the helpers shared with Figs. 4d and
//! 4e (panel grid, titles, legends in a box) are here too.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::fig2::min_max;
use super::plotting::{
    Axis, Figure, LegendEntry, Line, Rasters, TextSizes, draw_axes, draw_curve, draw_legend, font,
    sample_colour, tick_linear,
};
use crate::ReportError;
use crate::gather::{Sample, Series};
use crate::surface_stats::AcfCurves;

/// One panel of a per-sample grid, pixels.
const PANEL_W_PX: u32 = 600;
const PANEL_H_PX: u32 = 470;
/// Tick labels, pixels (labels and legends scale from it).
pub(crate) const TICK_PX: f64 = 21.0;
/// Space above a panel's plot for its title, pixels.
pub(crate) const TITLE_PX: i32 = 46;
/// Lags drawn in Fig. 4c: up to this many correlation lengths.
pub const ACF_LAGS_SHOWN: f64 = 6.0;

/// Columns and rows of a grid of `n` panels: two a row (one alone).
fn grid(n: usize) -> (usize, usize) {
    let cols = n.clamp(1, 2);
    (cols, n.max(1).div_ceil(cols))
}

fn grid_size(n: usize) -> (u32, u32) {
    let (cols, rows) = grid(n);
    (PANEL_W_PX * cols as u32, PANEL_H_PX * rows as u32)
}

/// `root` split into the grid's panels, row by row.
fn panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    n: usize,
) -> Vec<DrawingArea<DB, Shift>> {
    let (cols, rows) = grid(n);
    root.split_evenly((rows, cols))
}

/// The panel's letter and title, top left.
pub(crate) fn panel_title<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(), ReportError> {
    area.draw(&Text::new(title.to_owned(), (16, 10), font(TICK_PX * 1.1)))
        .map_err(|e| ReportError::plot(figure, e))
}

/// The letter of panel `k`: a, b, c, …
pub(crate) fn letter(k: usize) -> char {
    char::from(b'a' + (k % 26) as u8)
}

/// A chart on `area` below its title, with room for the axis labels.
pub(crate) fn panel_chart<'a, DB: DrawingBackend>(
    figure: &str,
    area: &'a DrawingArea<DB, Shift>,
    x: Axis,
    y: Axis,
    y_label_px: f64,
) -> Result<ChartContext<'a, DB, Cartesian2d<Axis, Axis>>, ReportError> {
    let sizes = TextSizes::panel(TICK_PX);
    ChartBuilder::on(area)
        .margin(10)
        .margin_top(TITLE_PX)
        .margin_right(24)
        .x_label_area_size(sizes.label * 2.7)
        .y_label_area_size(y_label_px)
        .build_cartesian_2d(x, y)
        .map_err(|e| ReportError::plot(figure, e))
}

/// A legend in a white box whose top-right corner sits `inset` pixels in
/// from the top-right corner of the chart's plotting area.
pub(crate) fn boxed_legend<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    entries: &[LegendEntry],
) -> Result<(), ReportError> {
    let size = TextSizes::panel(TICK_PX).legend;
    let lines: usize = entries.iter().map(|e| e.label.split('\n').count()).sum();
    let longest = entries
        .iter()
        .flat_map(|e| e.label.split('\n'))
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0);
    // DejaVu Sans averages about 0.55 em a character.
    let width = (size * (2.6 + 0.56 * longest as f64)) as i32;
    let height = (size * 1.5 * lines as f64) as i32 + 8;
    let (px, py) = chart.plotting_area().get_base_pixel();
    let (pw, _) = chart.plotting_area().dim_in_pixel();
    let (ax, ay) = area.get_base_pixel();
    let (x, y) = (px - ax + pw as i32 - width - 8, py - ay + 8);
    area.draw(&Rectangle::new(
        [(x - 6, y - 2), (x + width, y + height)],
        WHITE.mix(0.85).filled(),
    ))
    .map_err(|e| ReportError::plot(figure, e))?;
    draw_legend(figure, area, (x, y + 2), entries, size)
}

/// A grey note in the middle of a panel whose data are missing.
pub(crate) fn missing_panel<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    why: &str,
) -> Result<(), ReportError> {
    panel_title(figure, area, title)?;
    let (w, h) = area.dim_in_pixel();
    area.draw(&Text::new(
        why.to_owned(),
        (w as i32 / 2, h as i32 / 2),
        font(TICK_PX)
            .color(&RGBColor(130, 130, 130))
            .pos(super::plotting::Pos::new(
                super::plotting::HPos::Center,
                super::plotting::VPos::Center,
            )),
    ))
    .map_err(|e| ReportError::plot(figure, e))?;
    Ok(())
}

/// y at `x` on the piecewise-linear `series` (x ascending), clamped to its
/// ends; NaN for an empty series.
pub fn interpolate(series: &Series, x: f64) -> f64 {
    let (xs, ys) = (&series.x, &series.y);
    match xs.iter().position(|&v| v >= x) {
        None => ys.last().copied().unwrap_or(f64::NAN),
        Some(0) => ys[0],
        Some(i) => {
            let t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
            ys[i - 1] + t * (ys[i] - ys[i - 1])
        }
    }
}

/// Fig. 4b: the Abbott–Firestone curve of each sample with its core.
pub struct Fig4b<'a> {
    /// (sample, its colour index), samples with a curve.
    pub samples: Vec<(&'a Sample<'a>, usize)>,
}

/// The core of ISO 13565-2 as drawn: the equivalence line from (0 %, c1)
/// to (100 %, c2), c1 − c2 = Sk, c1 the curve's height at Smr1; heights m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Core {
    pub c1_m: f64,
    pub c2_m: f64,
    pub smr1_percent: f64,
    pub smr2_percent: f64,
}

impl Core {
    /// The core of `curve` from the areal parameters Sk, Smr1 and Smr2;
    /// `None` when any is not finite.
    pub fn of(curve: &Series, sk_m: f64, smr1_percent: f64, smr2_percent: f64) -> Option<Core> {
        let c1_m = interpolate(curve, smr1_percent);
        let core = Core {
            c1_m,
            c2_m: c1_m - sk_m,
            smr1_percent,
            smr2_percent,
        };
        [c1_m, sk_m, smr1_percent, smr2_percent]
            .iter()
            .all(|v| v.is_finite())
            .then_some(core)
    }
}

impl Figure for Fig4b<'_> {
    fn name(&self) -> &'static str {
        "fig4b"
    }

    fn size_px(&self) -> (u32, u32) {
        grid_size(self.samples.len())
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        for (k, ((sample, colour), area)) in self
            .samples
            .iter()
            .zip(panels(root, self.samples.len()))
            .enumerate()
        {
            let title = format!("({}) {}", letter(k), sample.label);
            let Some(curve) = &sample.extras.material_ratio else {
                missing_panel(self.name(), &area, &title, "no material-ratio curve")?;
                continue;
            };
            let core = sample
                .extras
                .areal
                .as_ref()
                .and_then(|a| Core::of(curve, a.sk_m[0], a.smr1_percent[0], a.smr2_percent[0]));
            draw_material_ratio(self.name(), &area, &title, curve, core, *colour)?;
        }
        Ok(())
    }
}

fn draw_material_ratio<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    curve: &Series,
    core: Option<Core>,
    colour_index: usize,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let sizes = TextSizes::panel(TICK_PX);
    let um = |v: f64| v * 1e6;
    let (lo, hi) = min_max(curve.y.iter().map(|&v| um(v)));
    let pad = 0.06 * (hi - lo).max(1e-9);
    panel_title(figure, area, title)?;
    let mut chart = panel_chart(
        figure,
        area,
        Axis::new(0.0, 100.0, 6),
        Axis::new(lo - pad, hi + pad, 7),
        sizes.label * 3.2,
    )?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        "material ratio Smr (%)",
        "height about mean plane (µm)",
        &|v| tick_linear(*v),
        &|v| tick_linear(*v),
        (6, 7),
    )?;
    let colour = sample_colour(colour_index);
    let grey = RGBColor(90, 90, 90);
    let mut legend = vec![LegendEntry {
        label: "Abbott–Firestone curve".into(),
        style: colour.stroke_width(3),
        line: Line::Solid,
    }];
    if let Some(c) = core {
        let (c1, c2) = (um(c.c1_m), um(c.c2_m));
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(0.0, c2), (100.0, c1)],
                colour.mix(0.16).filled(),
            )))
            .map_err(err)?;
        let y0 = lo - pad;
        for (mr, c) in [(c.smr1_percent, c1), (c.smr2_percent, c2)] {
            draw_curve(
                &mut chart,
                figure,
                vec![(mr, y0), (mr, c)],
                Line::Dotted,
                grey.stroke_width(2),
            )?;
        }
        draw_curve(
            &mut chart,
            figure,
            vec![(0.0, c1), (100.0, c2)],
            Line::Dashed,
            BLACK.stroke_width(2),
        )?;
        legend.push(LegendEntry {
            label: "core band, height Sk".into(),
            style: colour.mix(0.16).filled(),
            line: Line::Band,
        });
        legend.push(LegendEntry {
            label: "equivalence line\n(40 % secant)".into(),
            style: BLACK.stroke_width(2),
            line: Line::Dashed,
        });
        legend.push(LegendEntry {
            label: "Smr1, Smr2".into(),
            style: grey.stroke_width(2),
            line: Line::Dotted,
        });
    }
    let points: Vec<(f64, f64)> = curve
        .x
        .iter()
        .zip(&curve.y)
        .map(|(&x, &y)| (x, um(y)))
        .collect();
    draw_curve(
        &mut chart,
        figure,
        points,
        Line::Solid,
        colour.stroke_width(3),
    )?;
    boxed_legend(figure, area, &chart, &legend)
}

/// Fig. 4c: the autocorrelation of each sample against lag.
pub struct Fig4c<'a> {
    /// (sample, its colour index), samples with an ACF.
    pub samples: Vec<(&'a Sample<'a>, usize)>,
}

/// Where `series` (y falling from 1) first falls to `level`, linearly
/// interpolated; NaN if it does not.
pub fn first_fall(series: &Series, level: f64) -> f64 {
    let (xs, ys) = (&series.x, &series.y);
    (1..ys.len())
        .find(|&k| ys[k] <= level)
        .map_or(f64::NAN, |k| {
            let t = (ys[k - 1] - level) / (ys[k - 1] - ys[k]);
            xs[k - 1] + t * (xs[k] - xs[k - 1])
        })
}

impl Figure for Fig4c<'_> {
    fn name(&self) -> &'static str {
        "fig4c"
    }

    fn size_px(&self) -> (u32, u32) {
        grid_size(self.samples.len())
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        for (k, ((sample, colour), area)) in self
            .samples
            .iter()
            .zip(panels(root, self.samples.len()))
            .enumerate()
        {
            let title = format!("({}) {}", letter(k), sample.label);
            match &sample.extras.acf {
                Some(acf) if !acf.radial.x.is_empty() => {
                    draw_acf(self.name(), &area, &title, acf, *colour)?
                }
                _ => missing_panel(self.name(), &area, &title, "no autocorrelation")?,
            }
        }
        Ok(())
    }
}

/// The lag where the radial average falls to 1/e (NaN if it does not) and
/// the longest lag drawn: [`ACF_LAGS_SHOWN`] times that, at most the
/// longest lag held (all of them when it does not fall to 1/e), m.
fn acf_extent(acf: &AcfCurves) -> (f64, f64) {
    let xi_m = first_fall(&acf.radial, (-1.0f64).exp());
    let longest = [&acf.radial, &acf.x, &acf.y]
        .iter()
        .filter_map(|s| s.x.last().copied())
        .fold(0.0, f64::max);
    let x_hi = if xi_m.is_finite() {
        (ACF_LAGS_SHOWN * xi_m).min(longest)
    } else {
        longest
    };
    (xi_m, x_hi)
}

fn draw_acf<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    acf: &AcfCurves,
    colour_index: usize,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let sizes = TextSizes::panel(TICK_PX);
    let um = |v: f64| v * 1e6;
    let e_level = (-1.0f64).exp();
    let (xi_m, x_hi) = acf_extent(acf);
    let shown = |s: &Series| -> Vec<(f64, f64)> {
        s.x.iter()
            .zip(&s.y)
            .filter(|(x, _)| **x <= x_hi * (1.0 + 1e-12))
            .map(|(&x, &y)| (um(x), y))
            .collect()
    };
    let curves = [
        (shown(&acf.x), Line::Dashed, "along x"),
        (shown(&acf.y), Line::Dotted, "along y"),
        (shown(&acf.radial), Line::Solid, "radial average"),
    ];
    let (lo, _) = min_max(curves.iter().flat_map(|c| c.0.iter().map(|p| p.1)));
    let y_lo = lo.min(0.0) - 0.05;
    panel_title(figure, area, title)?;
    let mut chart = panel_chart(
        figure,
        area,
        Axis::new(0.0, um(x_hi).max(1e-9), 6),
        Axis::new(y_lo, 1.05, 7),
        sizes.label * 2.9,
    )?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        "lag τ (µm)",
        "autocorrelation ACF(τ)",
        &|v| tick_linear(*v),
        &|v| tick_linear(*v),
        (6, 7),
    )?;
    let levels = [
        (e_level, Line::LongDashed, "1/e: correlation length"),
        (0.2, Line::ShortDashed, "s = 0.2: Sal"),
    ];
    let grey = RGBColor(110, 110, 110);
    for (level, line, _) in levels {
        draw_curve(
            &mut chart,
            figure,
            vec![(0.0, level), (um(x_hi), level)],
            line,
            grey.stroke_width(2),
        )?;
    }
    let colour = sample_colour(colour_index);
    let mut legend = Vec::new();
    for (points, line, label) in curves {
        if points.is_empty() {
            continue;
        }
        let style = match line {
            Line::Solid => colour.stroke_width(3),
            _ => BLACK.mix(0.75).stroke_width(2),
        };
        draw_curve(&mut chart, figure, points, line, style)?;
        legend.push(LegendEntry {
            label: label.into(),
            style,
            line,
        });
    }
    if xi_m.is_finite() {
        chart
            .draw_series(std::iter::once(Circle::new(
                (um(xi_m), e_level),
                6,
                BLACK.stroke_width(2),
            )))
            .map_err(err)?;
    }
    for (_, line, label) in levels {
        legend.push(LegendEntry {
            label: label.into(),
            style: grey.stroke_width(2),
            line,
        });
    }
    boxed_legend(figure, area, &chart, &legend)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_hold_two_panels_a_row() {
        assert_eq!(grid(1), (1, 1));
        assert_eq!(grid(2), (2, 1));
        assert_eq!(grid(3), (2, 2));
        assert_eq!(grid(4), (2, 2));
        assert_eq!(grid(0), (1, 1));
    }

    /// A line from (0, 1) to (10, 0): it falls to 0.2 at 8 and to 1/e at
    /// 10(1 − 1/e); the core's c1 is the curve at Smr1.
    #[test]
    fn levels_and_the_core_are_read_off_the_curves() {
        let line = Series {
            x: vec![0.0, 5.0, 10.0],
            y: vec![1.0, 0.5, 0.0],
        };
        assert!((first_fall(&line, 0.2) - 8.0).abs() < 1e-12);
        let e = (-1.0f64).exp();
        assert!((first_fall(&line, e) - 10.0 * (1.0 - e)).abs() < 1e-12);
        assert!(first_fall(&line, -0.5).is_nan());
        assert_eq!(interpolate(&line, 2.5), 0.75);
        assert_eq!(interpolate(&line, 20.0), 0.0);
        let core = Core::of(&line, 0.4, 2.5, 80.0).unwrap();
        assert_eq!((core.c1_m, core.c2_m), (0.75, 0.75 - 0.4));
        assert_eq!(Core::of(&line, f64::NAN, 2.5, 80.0), None);
    }
}
