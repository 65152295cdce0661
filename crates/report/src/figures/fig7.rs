//! Fig. 7 of the paper: normalised load F/(E0* A0) against the contact area
//! fraction A/A0, on a logarithmic load axis so the early contact, where the
//! models differ most in relative terms, stays visible.
//!
//! With the models of one family alone (a label and its variants, e.g. a
//! model and its linear law) it is the paper's single panel: every sample
//! in its colour, a nonlinear law solid and a linear law (tangent ratio 1
//! throughout) dashed. Where models of several families or the contact
//! experiment are drawn, one panel per sample on common axes instead
//! (sixteen curves in one panel cannot be told apart), as the paper draws
//! model against experiment: the experiment as circles (Okabe–Ito blue),
//! the models as lines, colour = the model's family (the roster's), stroke
//! = law.
//!
//! A model's bootstrap band, where wired, is shaded under the curves
//! between its 5th and 95th percentiles: in the sample's colour in the
//! single panel, in the model's colour in the per-sample panels, where
//! colour tells the models apart.
//!
//! Fig. 9 (`comparison`) is the same plot for the models chosen to be
//! compared side by side (`fig9_models`), one panel per sample, with the
//! experiment and the models' bands where wired.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plotting::{
    Axis, BAND_LABEL, Figure, LegendEntry, Line, Rasters, TextSizes, band_legend, draw_axes,
    draw_band, draw_curve, draw_legend, model_colour, sample_colour, thin, tick_decade,
    tick_linear,
};
use crate::ReportError;
use crate::band::{Band, runs};
use crate::gather::Response;
use crate::roster::ModelKey;

/// One model's curve on one sample.
#[derive(Clone, Copy)]
pub struct Drawn<'a> {
    pub key: &'a ModelKey,
    pub response: &'a Response,
}

/// One sample's curves: label, colour index, and each drawn model's
/// response where wired.
pub struct SampleResponses<'a> {
    pub label: &'a str,
    pub colour_index: usize,
    /// In the roster's order.
    pub curves: Vec<Drawn<'a>>,
    /// The contact experiment: (A/A0, F/(E0* A0)), positive loads only.
    pub experiment: Option<Response>,
    /// The drawn models' 5–95 % bootstrap bands (Figs. 7 and 8).
    pub bands: Vec<(&'a ModelKey, &'a Band)>,
}

/// A model's stroke in Figs. 7 and 9: dashed for a linear law.
pub fn law_line(key: &ModelKey) -> Line {
    if key.linear {
        Line::Dashed
    } else {
        Line::Solid
    }
}

/// A model's style in the per-sample panels: its colour; black thinner,
/// as it is the darkest.
fn model_style(key: &ModelKey) -> ShapeStyle {
    let width = if key.colour == 0 { 2 } else { 3 };
    model_colour(key.colour).stroke_width(width)
}

/// The axes of Figs. 7, 8 and 9: A/A0 along x (six ticks), `y_desc`
/// with `y_ticks` ticks formatted by `y_fmt` up the side.
pub fn area_axes<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    (name, sizes): (&str, TextSizes),
    y_desc: &str,
    y_fmt: &dyn Fn(&f64) -> String,
    y_ticks: usize,
) -> Result<(), ReportError> {
    draw_axes(
        chart,
        name,
        sizes,
        "contact area fraction A/A₀",
        y_desc,
        &|v| tick_linear(*v),
        y_fmt,
        (6, y_ticks),
    )
}

/// The experiment's symbols (Okabe–Ito blue).
const EXPERIMENT_COLOUR: RGBColor = RGBColor(0, 114, 178);

pub struct Fig7<'a> {
    pub samples: Vec<SampleResponses<'a>>,
    /// The models drawn, in legend order.
    pub models: Vec<&'a ModelKey>,
    /// Drawn as Fig. 9, the contact models compared (always per sample).
    pub comparison: bool,
}

/// Width reserved right of the plot for the legend, pixels.
pub const LEGEND_PX: u32 = 250;

/// Panels per row of the per-sample layout.
const COLUMNS: usize = 2;

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

/// The axes every panel shares: A/A0 up to `x_hi`, F/(E0* A0) between
/// `y_lo` and `y_hi`.
#[derive(Clone, Copy)]
pub struct Ranges {
    pub x_hi: f64,
    pub y_lo: f64,
    pub y_hi: f64,
}

impl Ranges {
    /// log10 of the load range: the y axis as drawn.
    fn decades(self) -> (f64, f64) {
        (self.y_lo.log10(), self.y_hi.log10())
    }
}

/// A load–area panel of Figs. 7, 9 and 10 with its axes drawn: A/A0 from 0
/// to `x_hi` along x, F/(E0* A0) up the side as log10 on a linear axis (so
/// decade ticks are exact), titled when `title` is given.
pub fn load_area_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (name, sizes): (&str, TextSizes),
    ranges: Ranges,
    title: Option<&str>,
) -> Result<ChartContext<'a, DB, Cartesian2d<Axis, Axis>>, ReportError> {
    let (e_lo, e_hi) = ranges.decades();
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(16)
        .x_label_area_size(sizes.label * 2.9)
        .y_label_area_size(sizes.label * 3.4);
    if let Some(title) = title {
        builder.caption(title, super::plotting::font(sizes.title));
    }
    let mut chart = builder
        .build_cartesian_2d(
            Axis::new(0.0, ranges.x_hi, 6),
            Axis::decades(e_lo, e_hi, 12),
        )
        .map_err(|e| ReportError::plot(name, e))?;
    area_axes(
        &mut chart,
        (name, sizes),
        "normalised load F/(E₀* A₀)",
        &|v| tick_decade(*v),
        (e_hi - e_lo) as usize + 1,
    )?;
    Ok(chart)
}

/// One curve of F/(E0* A0) against A/A0 on a [`load_area_chart`]: points
/// outside `ranges` left off, the rest thinned to steps of 0.6 % of the
/// axes.
pub fn draw_load_curve<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    name: &str,
    (area_fraction, load_norm): (&[f64], &[f64]),
    ranges: Ranges,
    (line, style): (Line, ShapeStyle),
) -> Result<(), ReportError> {
    let (e_lo, e_hi) = ranges.decades();
    let points: Vec<(f64, f64)> = area_fraction
        .iter()
        .zip(load_norm)
        .filter(|&(&a, &f)| a <= ranges.x_hi && f >= ranges.y_lo && f <= ranges.y_hi)
        .map(|(&a, &f)| (a, f.log10()))
        .collect();
    let points = thin(&points, ranges.x_hi, e_hi - e_lo, 0.006);
    draw_curve(chart, name, points, line, style)
}

impl Fig7<'_> {
    fn per_sample(&self) -> bool {
        let families = |k: &&ModelKey| k.colour != self.models[0].colour;
        self.comparison
            || self.samples.iter().any(|s| s.experiment.is_some())
            || self.models.iter().any(families)
    }

    /// Panels per row: [`COLUMNS`], or fewer when there are fewer samples
    /// (one sample is one full-width panel, not a half-width one in a
    /// corner with the legend far from it).
    fn columns(&self) -> usize {
        self.samples.len().clamp(1, COLUMNS)
    }

    fn rows(&self) -> usize {
        self.samples.len().div_ceil(self.columns()).max(1)
    }

    fn ranges(&self) -> Ranges {
        let responses = || {
            self.samples.iter().flat_map(|s| {
                s.curves
                    .iter()
                    .map(|d| d.response)
                    .chain(s.experiment.as_ref())
            })
        };
        let bands = || {
            self.samples
                .iter()
                .flat_map(|s| s.bands.iter().map(|b| b.1))
        };
        let loads = responses()
            .flat_map(|r| r.load_norm.iter().copied())
            .chain(bands().flat_map(|b| b.load_norm_p05.iter().chain(&b.load_norm_p95).copied()));
        let (y_lo, y_hi) = log_range(loads, 5.0);
        let x_hi = responses()
            .flat_map(|r| r.area_fraction.iter().copied())
            .chain(bands().flat_map(|b| b.area_fraction.iter().copied()))
            .fold(0.0f64, f64::max)
            .clamp(0.05, 1.0);
        Ranges { x_hi, y_lo, y_hi }
    }

    /// One panel: axes (titled `title` when given), `bands` shaded in their
    /// colours, and over them `curves`, each with its stroke style and line
    /// kind.
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        sizes: TextSizes,
        ranges: Ranges,
        title: Option<&str>,
        bands: &[(&Band, RGBColor)],
        curves: &[(&Response, ShapeStyle, Line)],
    ) -> Result<(), ReportError> {
        let name = self.name();
        let (e_lo, e_hi) = ranges.decades();
        let mut chart = load_area_chart(area, (name, sizes), ranges, title)?;
        // Drawn as log10 on a linear axis, so decade ticks are exact; a
        // band edge at or below zero cannot be, and splits the band there.
        let on_axis = |f: f64| (f > 0.0).then(|| f.clamp(ranges.y_lo, ranges.y_hi).log10());
        for &(band, colour) in bands {
            let x = &band.area_fraction;
            for run in runs(x, &band.load_norm_p05, &band.load_norm_p95, on_axis) {
                let spans = (ranges.x_hi, e_hi - e_lo, 0.006);
                draw_band(&mut chart, name, &run, spans, colour)?;
            }
        }
        for &(r, style, line) in curves {
            let xy = (&r.area_fraction[..], &r.load_norm[..]);
            draw_load_curve(&mut chart, name, xy, ranges, (line, style))?;
        }
        Ok(())
    }

    /// The paper's layout: one panel, a colour per sample.
    fn draw_single<DB: DrawingBackend>(
        &self,
        plot: &DrawingArea<DB, Shift>,
        sizes: TextSizes,
    ) -> Result<Vec<LegendEntry>, ReportError> {
        let mut curves = Vec::new();
        let mut legend = Vec::new();
        let bands: Vec<(&Band, RGBColor)> = self
            .samples
            .iter()
            .flat_map(|s| s.bands.iter().map(|b| (b.1, sample_colour(s.colour_index))))
            .collect();
        for s in &self.samples {
            let style = sample_colour(s.colour_index).stroke_width(3);
            for d in &s.curves {
                curves.push((d.response, style, law_line(d.key)));
            }
            legend.push(LegendEntry {
                label: s.label.to_owned(),
                style,
                line: s.curves.first().map_or(Line::Solid, |d| law_line(d.key)),
            });
        }
        self.panel(plot, sizes, self.ranges(), None, &bands, &curves)?;
        // Line-style key in black, after the colour key.
        for key in &self.models {
            legend.push(LegendEntry {
                label: key.label.clone(),
                style: BLACK.stroke_width(3),
                line: law_line(key),
            });
        }
        if !bands.is_empty() {
            // One key for every sample's band: grey, as the line-style key.
            legend.push(band_legend(BLACK));
        }
        Ok(legend)
    }

    /// One panel per sample on common axes, a colour per model family.
    fn draw_per_sample<DB: DrawingBackend>(
        &self,
        plot: &DrawingArea<DB, Shift>,
    ) -> Result<Vec<LegendEntry>, ReportError> {
        // One panel is drawn at the single-panel figure's sizes.
        let sizes = match self.columns() {
            1 => TextSizes::for_width(1000),
            _ => TextSizes::panel(20.0),
        };
        let ranges = self.ranges();
        let panels = plot.split_evenly((self.rows(), self.columns()));
        let measured = EXPERIMENT_COLOUR.stroke_width(2);
        for (area, s) in panels.iter().zip(&self.samples) {
            let mut curves: Vec<_> = s
                .curves
                .iter()
                .map(|d| (d.response, model_style(d.key), law_line(d.key)))
                .collect();
            curves.extend(s.experiment.as_ref().map(|e| (e, measured, Line::Circles)));
            let bands: Vec<(&Band, RGBColor)> = s
                .bands
                .iter()
                .map(|&(key, band)| (band, model_colour(key.colour)))
                .collect();
            self.panel(area, sizes, ranges, Some(s.label), &bands, &curves)?;
        }
        let mut legend: Vec<LegendEntry> = self
            .models
            .iter()
            .map(|key| LegendEntry {
                label: key.label.clone(),
                style: model_style(key),
                line: law_line(key),
            })
            .collect();
        if self.samples.iter().any(|s| s.experiment.is_some()) {
            legend.push(LegendEntry {
                label: "experiment".into(),
                style: measured,
                line: Line::Circles,
            });
        }
        let mut banded: Vec<usize> = Vec::new();
        for (key, _) in self.samples.iter().flat_map(|s| &s.bands) {
            if !banded.contains(&key.colour) {
                banded.push(key.colour);
            }
        }
        // One key for the bands: in their model's colour when one model has
        // them, grey and said so when several do (a key per colour would
        // repeat one label).
        match banded[..] {
            [] => {}
            [colour] => legend.push(band_legend(model_colour(colour))),
            _ => legend.push(LegendEntry {
                label: format!("{BAND_LABEL}\nin model colour"),
                ..band_legend(BLACK)
            }),
        }
        Ok(legend)
    }
}

impl Figure for Fig7<'_> {
    fn name(&self) -> &'static str {
        if self.comparison { "fig9" } else { "fig7" }
    }

    /// The single panel's size, also for one sample drawn per sample; two
    /// panels a row otherwise.
    fn size_px(&self) -> (u32, u32) {
        if self.per_sample() && self.columns() > 1 {
            (1300, 40 + 460 * self.rows() as u32)
        } else {
            (1000, 680)
        }
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let (width, _) = self.size_px();
        let (plot, key) = root.split_horizontally(width - LEGEND_PX);
        let sizes = TextSizes::for_width(1000);
        let legend = if self.per_sample() {
            self.draw_per_sample(&plot)?
        } else {
            self.draw_single(&plot, sizes)?
        };
        draw_legend(self.name(), &key, (5, 30), &legend, sizes.legend)
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
