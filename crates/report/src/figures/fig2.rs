//! Fig. 2 of the paper: measured and fitted nominal stress against stretch
//! for the UT, PT and BT tests, drawn as the paper's caption says ("the
//! experimental data are shown as lines and the fitting data as symbols"):
//! the measured curve a line, the model at the measured stretches symbols.
//! Each mode's R² is in the legend, and the fitted model's Drucker stability
//! limits inside the plotted range are marked (dashed vertical line in the
//! mode's colour, listed in the legend).

use std::collections::BTreeMap;

use hypercontact_core::Mode;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::plotting::{
    Axis, Figure, Rasters, TextSizes, dashed_swatch, draw_axes, font, mode_colour, tick_linear,
};
use crate::ReportError;
use crate::gather::{ModeCurve, StabilityRange};

/// At most this many fitted symbols per mode; denser ones would hide the
/// measured line.
const MAX_SYMBOLS: usize = 30;

pub struct Fig2<'a> {
    pub curves: &'a [ModeCurve],
    pub r2_by_mode: &'a BTreeMap<String, f64>,
    pub stability: Option<&'a [StabilityRange]>,
}

/// Fig. 2's axes: stretch from `x_min` to `x_max`, stress (MPa) from
/// `y_min` to `y_max`.
#[derive(Clone, Copy)]
struct Ranges {
    x_min: f64,
    x_max: f64,
    y_min: f64,
    y_max: f64,
}

type Chart<'c, DB> = ChartContext<'c, DB, Cartesian2d<Axis, Axis>>;

impl Fig2<'_> {
    fn ranges(&self) -> Ranges {
        let all = |f: fn(&ModeCurve) -> &Vec<f64>| self.curves.iter().flat_map(f).copied();
        let (x_min, x_max) = min_max(all(|c| &c.stretch));
        let (y_min, y_max) = min_max(all(|c| &c.measured_pa).chain(all(|c| &c.fitted_pa)));
        let x_min = x_min.min(1.0);
        let pad = 0.03 * (x_max - x_min).max(1e-3);
        // Stress in MPa, from zero (the unstrained state) unless compressive.
        let (y_min, y_max) = (y_min.min(0.0) / 1e6, y_max / 1e6);
        let y_pad = 0.05 * (y_max - y_min).max(1e-9);
        Ranges {
            x_min: x_min - pad,
            x_max: x_max + pad,
            y_min: if y_min < 0.0 { y_min - y_pad } else { 0.0 },
            y_max: y_max + y_pad,
        }
    }

    /// One mode: the measured line, its legend swatch and the fitted
    /// symbols (at most [`MAX_SYMBOLS`]).
    fn draw_mode<'c, DB: DrawingBackend + 'c>(
        &self,
        chart: &mut Chart<'c, DB>,
        sizes: TextSizes,
        curve: &ModeCurve,
        i: usize,
    ) -> Result<(), ReportError> {
        let err = |e| ReportError::plot(self.name(), e);
        let colour = mode_colour(&curve.mode, i);
        let line = colour.stroke_width(3);
        let label = match self.r2_by_mode.get(&curve.mode) {
            Some(r2) if r2.is_finite() => format!("{}  (R² = {r2:.4})", curve.mode),
            _ => curve.mode.clone(),
        };
        let r = (sizes.tick * 0.32) as i32;
        let series = chart
            .draw_series(LineSeries::new(
                curve
                    .stretch
                    .iter()
                    .zip(&curve.measured_pa)
                    .map(|(&s, &m)| (s, m / 1e6)),
                line,
            ))
            .map_err(err)?;
        series.label(label);
        // Swatch: the measured line with the fitted symbol on it.
        let stroke = colour.stroke_width(2);
        let fill = WHITE.filled();
        let swatch = move |(x, y): (i32, i32)| {
            EmptyElement::at((x, y)) + PathElement::new(vec![(0, 0), (44, 0)], line)
        };
        match Symbol::of(&curve.mode) {
            Symbol::Circle => series.legend(move |p| {
                swatch(p) + Circle::new((22, 0), r, fill) + Circle::new((22, 0), r, stroke)
            }),
            Symbol::Square => series.legend(move |p| {
                swatch(p)
                    + Rectangle::new([(22 - r, -r), (22 + r, r)], fill)
                    + Rectangle::new([(22 - r, -r), (22 + r, r)], stroke)
            }),
            Symbol::Triangle => series.legend(move |p| {
                swatch(p)
                    + Polygon::new(triangle((22, 0), r), fill)
                    + PathElement::new(triangle((22, 0), r), stroke)
            }),
        };
        let step = curve.stretch.len().div_ceil(MAX_SYMBOLS).max(1);
        let symbols: Vec<(f64, f64)> = curve
            .stretch
            .iter()
            .zip(&curve.fitted_pa)
            .step_by(step)
            .map(|(&s, &f)| (s, f / 1e6))
            .collect();
        match Symbol::of(&curve.mode) {
            Symbol::Circle => chart.draw_series(symbols.into_iter().map(|at| {
                EmptyElement::at(at) + Circle::new((0, 0), r, fill) + Circle::new((0, 0), r, stroke)
            })),
            Symbol::Square => chart.draw_series(symbols.into_iter().map(|at| {
                EmptyElement::at(at)
                    + Rectangle::new([(-r, -r), (r, r)], fill)
                    + Rectangle::new([(-r, -r), (r, r)], stroke)
            })),
            Symbol::Triangle => chart.draw_series(symbols.into_iter().map(|at| {
                EmptyElement::at(at)
                    + Polygon::new(triangle((0, 0), r), fill)
                    + PathElement::new(triangle((0, 0), r), stroke)
            })),
        }
        .map_err(err)?;
        Ok(())
    }

    /// The Drucker stability limits inside the plotted range, dashed in
    /// their mode's colour and listed in the legend.
    fn draw_stability<'c, DB: DrawingBackend + 'c>(
        &self,
        chart: &mut Chart<'c, DB>,
        ranges: Ranges,
    ) -> Result<(), ReportError> {
        let err = |e| ReportError::plot(self.name(), e);
        let Some(stability) = self.stability else {
            return Ok(());
        };
        for range in stability {
            let index = self
                .curves
                .iter()
                .position(|c| c.mode == range.mode)
                .unwrap_or(3);
            let colour = mode_colour(&range.mode, index);
            for (limit, side) in [(range.lambda_max, "≤"), (range.lambda_min, "≥")] {
                if !(limit.is_finite() && limit > ranges.x_min && limit < ranges.x_max) {
                    continue;
                }
                let style = colour.stroke_width(2);
                chart
                    .draw_series(DashedLineSeries::new(
                        [(limit, ranges.y_min), (limit, ranges.y_max)],
                        7,
                        6,
                        style,
                    ))
                    .map_err(err)?
                    .label(format!(
                        "{} Drucker-stable for λ {side} {limit:.3}",
                        range.mode
                    ))
                    .legend(move |p| dashed_swatch(p, 44, style));
            }
        }
        Ok(())
    }
}

impl Figure for Fig2<'_> {
    fn name(&self) -> &'static str {
        "fig2"
    }

    fn size_px(&self) -> (u32, u32) {
        (1000, 720)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        _: &mut Rasters,
    ) -> Result<(), ReportError> {
        let name = self.name();
        let err = |e| ReportError::plot(name, e);
        let sizes = TextSizes::for_width(self.size_px().0);
        let ranges = self.ranges();
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .margin_right(35)
            .x_label_area_size(sizes.label * 2.9)
            .y_label_area_size(sizes.label * 3.6)
            .build_cartesian_2d(
                Axis::new(ranges.x_min, ranges.x_max, 9),
                Axis::new(ranges.y_min, ranges.y_max, 8),
            )
            .map_err(err)?;
        draw_axes(
            &mut chart,
            name,
            sizes,
            "stretch λ",
            "nominal stress (MPa)",
            &|v| tick_linear(*v),
            &|v| tick_linear(*v),
            (8, 8),
        )?;
        for (i, curve) in self.curves.iter().enumerate() {
            self.draw_mode(&mut chart, sizes, curve, i)?;
        }
        self.draw_stability(&mut chart, ranges)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .margin(15)
            .legend_area_size(60)
            .label_font(font(sizes.legend))
            .background_style(WHITE.mix(0.92))
            .border_style(BLACK.stroke_width(1))
            .draw()
            .map_err(err)?;
        Ok(())
    }
}

/// The fitted-model symbol of a mode: UT circle, PT square, BT triangle,
/// hollow (white-filled) so the measured line stays visible through them.
enum Symbol {
    Circle,
    Square,
    Triangle,
}

impl Symbol {
    fn of(mode: &str) -> Symbol {
        match Mode::from_label(mode) {
            Some(Mode::Planar) => Symbol::Square,
            Some(Mode::Equibiaxial) => Symbol::Triangle,
            _ => Symbol::Circle,
        }
    }
}

/// A closed upward triangle around `(x, y)` pixel offsets, half-size `r`.
fn triangle((x, y): (i32, i32), r: i32) -> Vec<(i32, i32)> {
    let t = r + 2;
    vec![(x, y - t), (x + t, y + r), (x - t, y + r), (x, y - t)]
}

/// (min, max) of finite values; (0, 1) for none.
pub fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi { (0.0, 1.0) } else { (lo, hi) }
}
