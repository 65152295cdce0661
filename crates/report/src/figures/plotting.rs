//! What every figure shares: the bundled font, colours per sample and per
//! mode, text sizes, axis styling, tick formatting, and rendering one
//! drawing to both PNG and SVG.
//!
//! Text is laid out with the bundled DejaVu Sans (`assets/`, Bitstream Vera
//! licence), so the PNGs look the same on any machine; in the SVGs the
//! family is named with a `sans-serif` fallback. Raster images (the height
//! maps) are painted pixel by pixel into the PNG and embedded as a PNG data
//! URI `<image>` in the SVG, so a 500 × 500 map does not become 250 000
//! rectangles.

use std::sync::OnceLock;

use base64::Engine;
use hypercontact_core::Mode;
use hypercontact_labfiles::png::Pixels;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{KeyPointHint, Ranged, ValueFormatter};
use plotters::element::DashedPathElement;
use plotters::prelude::*;
pub use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::ReportError;
use crate::band::BandRun;

/// The font family name plotters looks the bundled font up by; it is also
/// written verbatim as the SVG `font-family`, hence the CSS fallback list.
pub const FONT: &str = "DejaVu Sans, sans-serif";

static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Registers the bundled font with plotters once per process.
pub fn register_font() -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(ReportError::plot(
            "font",
            "the bundled DejaVu Sans is not a valid font",
        ))
    }
}

/// Text sizes in pixels for a figure rendered `width_px` wide and shown at
/// about 160 mm (A4 text width): ticks ≈ 8 pt, labels ≈ 9.5 pt.
#[derive(Clone, Copy, Debug)]
pub struct TextSizes {
    pub tick: f64,
    pub label: f64,
    pub legend: f64,
    pub title: f64,
}

impl TextSizes {
    pub fn for_width(width_px: u32) -> Self {
        let scale = f64::from(width_px) / 1000.0;
        TextSizes {
            tick: 24.0 * scale,
            label: 28.0 * scale,
            legend: 23.0 * scale,
            title: 28.0 * scale,
        }
    }

    /// Sizes for a panel of a multi-panel figure (absolute pixels).
    pub fn panel(tick: f64) -> Self {
        TextSizes {
            tick,
            label: tick * 1.15,
            legend: tick * 0.95,
            title: tick * 1.15,
        }
    }
}

pub fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// Colour of sample number `index` (0 = T1): Okabe–Ito's colour-blind-safe
/// palette, so T1…T4 keep one colour across Figs. 4, 7 and 8.
pub fn sample_colour(index: usize) -> RGBColor {
    const PALETTE: [RGBColor; 7] = [
        RGBColor(0, 114, 178),   // blue
        RGBColor(213, 94, 0),    // vermillion
        RGBColor(0, 158, 115),   // bluish green
        RGBColor(204, 121, 167), // reddish purple
        RGBColor(230, 159, 0),   // orange
        RGBColor(86, 180, 233),  // sky blue
        RGBColor(120, 120, 120), // grey
    ];
    PALETTE[index % PALETTE.len()]
}

/// Colour of contact-model family number `index` in the per-sample panels
/// (the report's roster order): black, then Okabe–Ito's colours without
/// the blue the experiment's symbols take.
pub fn model_colour(index: usize) -> RGBColor {
    // The samples' palette after its blue, behind black.
    match index % 7 {
        0 => RGBColor(0, 0, 0),
        k => sample_colour(k),
    }
}

/// Colour of a tensile mode in Fig. 2 (a label that is no mode gets a
/// sample colour).
pub fn mode_colour(mode: &str, index: usize) -> RGBColor {
    match Mode::from_label(mode) {
        Some(Mode::Uniaxial) => RGBColor(0, 114, 178),
        Some(Mode::Planar) => RGBColor(213, 94, 0),
        Some(Mode::Equibiaxial) => RGBColor(0, 158, 115),
        None => sample_colour(index + 3),
    }
}

pub const AXIS_GREY: RGBColor = RGBColor(225, 225, 225);

/// A number for a linear axis tick: no trailing zeros, no `1.0000001`.
pub fn tick_linear(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let magnitude = v.abs();
    if !(1e-3..1e5).contains(&magnitude) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// A tick of a log axis: powers of ten as 10ⁿ with superscripts, other ticks
/// left blank so the decades stay readable.
pub fn tick_log(v: f64) -> String {
    if v <= 0.0 || !v.is_finite() {
        return String::new();
    }
    tick_decade(v.log10())
}

/// A tick of an axis that holds log10 of the quantity (how log axes are
/// drawn here, so ticks fall exactly on decades): "10ⁿ" at integers, blank
/// elsewhere.
pub fn tick_decade(exponent: f64) -> String {
    let rounded = exponent.round();
    if (exponent - rounded).abs() > 1e-6 {
        return String::new();
    }
    format!("10{}", superscript(rounded as i64))
}

/// Points of a dense curve thinned to steps of at least `min_step` of the
/// axis spans (plus the last point): a 1000-level response drawn as a
/// thick line otherwise turns hairy at the joints.
pub fn thin(points: &[(f64, f64)], x_span: f64, y_span: f64, min_step: f64) -> Vec<(f64, f64)> {
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(points.len().min(1024));
    for &p in points {
        match kept.last() {
            Some(&(x, y))
                if ((p.0 - x) / x_span).abs() < min_step
                    && ((p.1 - y) / y_span).abs() < min_step => {}
            _ => kept.push(p),
        }
    }
    if let (Some(&last), Some(&kept_last)) = (points.last(), kept.last())
        && last != kept_last
    {
        kept.push(last);
    }
    kept
}

/// How a curve is stroked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Line {
    Solid,
    Dashed,
    Dotted,
    /// Long dashes, short gaps: a fourth stroke where models share a colour.
    LongDashed,
    /// Short dashes: a fifth.
    ShortDashed,
    /// Not a line: a circle at every point (measured data).
    Circles,
    /// Not a line: the points outline a shaded area (an uncertainty band),
    /// drawn in the style's colour and opacity.
    Band,
}

/// Opacity of a shaded band: light enough that the curves and the other
/// samples' bands show through.
pub const BAND_OPACITY: f64 = 0.2;

/// The legend label of the bootstrap bands of Figs. 7 and 8, in lines
/// that fit the legend's width.
pub const BAND_LABEL: &str = "5–95 % bootstrap\n(tensile scatter)";

/// Radius of [`Line::Circles`]' symbols, pixels.
const CIRCLE_PX: i32 = 5;

impl Line {
    /// (dash, gap) in pixels along the curve; `None` when solid (or not a line).
    pub fn pattern(self) -> Option<(u32, u32)> {
        match self {
            Line::Solid | Line::Circles | Line::Band => None,
            Line::Dashed => Some((12, 8)),
            Line::Dotted => Some((2, 6)),
            Line::LongDashed => Some((24, 5)),
            Line::ShortDashed => Some((8, 3)),
        }
    }
}

/// Draws `points` as one curve of `chart` in `line`'s pattern.
pub fn draw_curve<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    figure: &str,
    points: Vec<(f64, f64)>,
    line: Line,
    style: ShapeStyle,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    if line == Line::Band {
        return chart
            .draw_series(std::iter::once(Polygon::new(points, style.filled())))
            .map(|_| ())
            .map_err(err);
    }
    if line == Line::Circles {
        return chart
            .draw_series(
                points
                    .into_iter()
                    .map(|p| Circle::new(p, CIRCLE_PX, style.stroke_width(2))),
            )
            .map(|_| ())
            .map_err(err);
    }
    match line.pattern() {
        None => chart
            .draw_series(LineSeries::new(points, style))
            .map(|_| ())
            .map_err(err),
        Some((dash, gap)) => chart
            .draw_series(DashedLineSeries::new(points, dash, gap, style))
            .map(|_| ())
            .map_err(err),
    }
}

/// Shades one run of a band in `colour` at [`BAND_OPACITY`], each edge
/// thinned like a curve to steps of `min_step` of the axis spans.
pub fn draw_band<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    figure: &str,
    run: &BandRun,
    (x_span, y_span, min_step): (f64, f64, f64),
    colour: RGBColor,
) -> Result<(), ReportError> {
    let edge = |e: &[(f64, f64)]| thin(e, x_span, y_span, min_step);
    let outline: Vec<(f64, f64)> = edge(&run.lower)
        .into_iter()
        .chain(edge(&run.upper).into_iter().rev())
        .collect();
    draw_curve(
        chart,
        figure,
        outline,
        Line::Band,
        colour.mix(BAND_OPACITY).filled(),
    )
}

/// The legend line of a band drawn in `colour`.
pub fn band_legend(colour: RGBColor) -> LegendEntry {
    LegendEntry {
        label: BAND_LABEL.into(),
        style: colour.mix(BAND_OPACITY).filled(),
        line: Line::Band,
    }
}

/// One line of a hand-drawn legend.
#[derive(Clone, Debug)]
pub struct LegendEntry {
    pub label: String,
    pub style: ShapeStyle,
    pub line: Line,
}

/// Draws a legend as a column of swatches and labels with its top-left
/// corner at `(x, y)` of `area` (plotters' own legend lives inside the
/// plotting area, where it would cover curves).
pub fn draw_legend<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    entries: &[LegendEntry],
    size: f64,
) -> Result<(), ReportError> {
    let line_px = (size * 1.5) as i32;
    let swatch_px = (size * 1.8) as i32;
    // A label of several lines (split at '\n') takes a row per line, its
    // swatch beside the first.
    let mut row = 0;
    for e in entries {
        let yy = y + row * line_px + line_px / 2;
        match e.line {
            Line::Solid => area.draw(&solid_swatch((x, yy), swatch_px, e.style)),
            Line::Dashed => area.draw(&dashed_swatch((x, yy), swatch_px, e.style)),
            Line::Band => area.draw(&Rectangle::new(
                [(x, yy - line_px / 3), (x + swatch_px, yy + line_px / 3)],
                e.style.filled(),
            )),
            Line::Circles => area.draw(&Circle::new(
                (x + swatch_px / 2, yy),
                CIRCLE_PX,
                e.style.stroke_width(2),
            )),
            Line::Dotted | Line::LongDashed | Line::ShortDashed => {
                let (dash, gap) = e.line.pattern().unwrap_or((1, 0));
                area.draw(&DashedPathElement::new(
                    vec![(x, yy), (x + swatch_px, yy)],
                    dash as i32,
                    gap as i32,
                    e.style,
                ))
            }
        }
        .map_err(|err| ReportError::plot(figure, err))?;
        for text in e.label.split('\n') {
            area.draw(&Text::new(
                text.to_owned(),
                (
                    x + swatch_px + (size * 0.5) as i32,
                    y + row * line_px + line_px / 2,
                ),
                font(size).pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(|err| ReportError::plot(figure, err))?;
            row += 1;
        }
    }
    Ok(())
}

/// An integer in Unicode superscript digits (DejaVu Sans has them all).
pub fn superscript(n: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if n < 0 {
        s.push('⁻');
    }
    for d in n.unsigned_abs().to_string().bytes() {
        s.push(DIGITS[usize::from(d - b'0')]);
    }
    s
}

/// Tick values at a 1–2–5 step between `lo` and `hi`, at most `max_n` of
/// them, computed as integer multiples of the step (plotters' own tick
/// search drops the last tick of some ranges, e.g. 3.0 in 2.42…3.04).
pub fn nice_ticks(lo: f64, hi: f64, max_n: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) || max_n == 0 {
        return vec![lo];
    }
    let magnitude = 10f64.powf((span / max_n as f64).log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0, 20.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|&step| ((span / step).floor() as usize) < max_n)
        .unwrap_or(span);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// A linear f64 axis whose ticks are [`nice_ticks`].
#[derive(Clone, Debug)]
pub struct Axis {
    lo: f64,
    hi: f64,
    ticks: Vec<f64>,
}

impl Axis {
    pub fn new(lo: f64, hi: f64, max_ticks: usize) -> Self {
        let hi = if hi > lo { hi } else { lo + 1.0 };
        Axis {
            lo,
            hi,
            ticks: nice_ticks(lo, hi, max_ticks),
        }
    }
}

impl Axis {
    /// An axis holding log10 of a quantity: ticks on whole decades only.
    pub fn decades(lo: f64, hi: f64, max_ticks: usize) -> Self {
        let mut axis = Axis::new(lo, hi, max_ticks);
        axis.ticks.retain(|t| (t - t.round()).abs() < 1e-9);
        axis
    }
}

impl Ranged for Axis {
    type FormatOption = plotters::coord::ranged1d::NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = (value - self.lo) / (self.hi - self.lo);
        limit.0 + (t * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(value: &f64) -> String {
        tick_linear(*value)
    }
}

/// Draws a chart's frame, ticks and axis titles in the house style: light
/// grid at the major ticks only, black frame, tick labels from the given
/// formatters.
#[allow(clippy::too_many_arguments)]
pub fn draw_axes<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    figure: &str,
    sizes: TextSizes,
    x_desc: &str,
    y_desc: &str,
    x_fmt: &dyn Fn(&X::ValueType) -> String,
    y_fmt: &dyn Fn(&Y::ValueType) -> String,
    n_ticks: (usize, usize),
) -> Result<(), ReportError>
where
    DB: DrawingBackend,
    X: Ranged + ValueFormatter<X::ValueType>,
    Y: Ranged + ValueFormatter<Y::ValueType>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(n_ticks.0)
        .y_labels(n_ticks.1)
        .x_label_formatter(x_fmt)
        .y_label_formatter(y_fmt)
        .label_style(font(sizes.tick))
        .axis_desc_style(font(sizes.label))
        .bold_line_style(AXIS_GREY.stroke_width(1))
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK.stroke_width(2))
        .set_all_tick_mark_size((sizes.tick * 0.3) as i32)
        .draw()
        .map_err(|e| ReportError::plot(figure, e))?;
    Ok(())
}

/// A raster image placed at absolute pixel coordinates of the figure.
#[derive(Clone, Debug)]
pub struct Raster {
    pub x_px: i32,
    pub y_px: i32,
    pub width_px: u32,
    pub height_px: u32,
    /// Row-major RGB, top row first.
    pub rgb: Vec<u8>,
}

/// Where a figure's rasters go: painted at once into a bitmap (so later
/// drawing lies on top), or collected to be embedded in the SVG.
pub struct Rasters {
    paint: bool,
    placed: Vec<Raster>,
}

impl Rasters {
    /// Places `raster` with its top-left corner at `(x, y)` of `area`.
    pub fn place<DB: DrawingBackend>(
        &mut self,
        figure: &str,
        area: &DrawingArea<DB, Shift>,
        x: i32,
        y: i32,
        mut raster: Raster,
    ) -> Result<(), ReportError> {
        if self.paint {
            let w = raster.width_px as usize;
            for (i, px) in raster.rgb.chunks_exact(3).enumerate() {
                let (col, row) = ((i % w) as i32, (i / w) as i32);
                area.draw_pixel((x + col, y + row), &RGBColor(px[0], px[1], px[2]))
                    .map_err(|e| ReportError::plot(figure, e))?;
            }
        }
        let (base_x, base_y) = area.get_base_pixel();
        raster.x_px = base_x + x;
        raster.y_px = base_y + y;
        self.placed.push(raster);
        Ok(())
    }
}

/// A figure that can draw itself on any plotters backend.
pub trait Figure {
    /// The file stem: `fig2`, `fig4`, ...
    fn name(&self) -> &'static str;
    fn size_px(&self) -> (u32, u32);
    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        rasters: &mut Rasters,
    ) -> Result<(), ReportError>;
}

/// One figure in both formats.
#[derive(Clone, Debug)]
pub struct Rendered {
    pub name: &'static str,
    pub png: Vec<u8>,
    pub svg: String,
}

/// Draws `figure` twice, into an RGB bitmap (encoded as PNG) and into SVG.
pub fn render(figure: &impl Figure) -> Result<Rendered, ReportError> {
    register_font()?;
    let name = figure.name();
    let (w, h) = figure.size_px();
    let mut rgb = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| ReportError::plot(name, e))?;
        let mut rasters = Rasters {
            paint: true,
            placed: Vec::new(),
        };
        figure.draw(&root, &mut rasters)?;
        root.present().map_err(|e| ReportError::plot(name, e))?;
    }
    let png = encode_png(&format!("{name}.png"), w, h, rgb)?;

    let mut svg = String::new();
    let placed = {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| ReportError::plot(name, e))?;
        let mut rasters = Rasters {
            paint: false,
            placed: Vec::new(),
        };
        figure.draw(&root, &mut rasters)?;
        root.present().map_err(|e| ReportError::plot(name, e))?;
        rasters.placed
    };
    let svg = embed_rasters(name, svg, &placed)?;
    Ok(Rendered { name, png, svg })
}

/// RGB pixels as PNG (the core's encoder); an error names the file.
fn encode_png(name: &str, w: u32, h: u32, rgb: Vec<u8>) -> Result<Vec<u8>, ReportError> {
    hypercontact_labfiles::png::encode_png(w, h, Pixels::Rgb8(rgb)).map_err(|message| {
        ReportError::Encode {
            name: name.to_owned(),
            message,
        }
    })
}

/// Inserts the rasters as `<image>` elements right after the background
/// rectangle, so everything plotters drew afterwards stays on top.
fn embed_rasters(name: &str, svg: String, rasters: &[Raster]) -> Result<String, ReportError> {
    if rasters.is_empty() {
        return Ok(svg);
    }
    let background_end = svg
        .find("<rect")
        .and_then(|start| svg[start..].find("/>").map(|end| start + end + 2))
        .ok_or_else(|| ReportError::plot(name, "no background rectangle in the SVG"))?;
    let mut images = String::new();
    for (i, r) in rasters.iter().enumerate() {
        let png = encode_png(
            &format!("{name}.svg raster {i}"),
            r.width_px,
            r.height_px,
            r.rgb.clone(),
        )?;
        let data = base64::engine::general_purpose::STANDARD.encode(png);
        images.push_str(&format!(
            "\n<image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" \
             preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" \
             href=\"data:image/png;base64,{data}\"/>",
            r.x_px, r.y_px, r.width_px, r.height_px
        ));
    }
    let mut out = String::with_capacity(svg.len() + images.len());
    out.push_str(&svg[..background_end]);
    out.push_str(&images);
    out.push_str(&svg[background_end..]);
    Ok(out)
}

/// A legend swatch for a dashed line (plotters' legend draws solid ones).
pub fn dashed_swatch(
    (x, y): (i32, i32),
    length_px: i32,
    style: ShapeStyle,
) -> DashedPathElement<std::vec::IntoIter<(i32, i32)>, i32> {
    let dash = length_px * 3 / 8;
    DashedPathElement::new(
        vec![(x, y), (x + length_px, y)],
        dash,
        length_px - 2 * dash,
        style,
    )
}

/// A legend swatch for a solid line.
pub fn solid_swatch(
    (x, y): (i32, i32),
    length_px: i32,
    style: ShapeStyle,
) -> PathElement<(i32, i32)> {
    PathElement::new(vec![(x, y), (x + length_px, y)], style)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_ends_and_drops_close_points() {
        let dense: Vec<(f64, f64)> = (0..=1000).map(|k| (k as f64 / 1000.0, 0.0)).collect();
        let kept = thin(&dense, 1.0, 1.0, 0.01);
        assert_eq!(kept.first(), Some(&(0.0, 0.0)));
        assert_eq!(kept.last(), Some(&(1.0, 0.0)));
        assert!(kept.len() > 90 && kept.len() < 110, "{}", kept.len());
    }

    #[test]
    fn log_ticks_label_only_decades() {
        assert_eq!(tick_log(1e-3), "10⁻³");
        assert_eq!(tick_log(100.0), "10²");
        assert_eq!(tick_log(1.0), "10⁰");
        assert_eq!(tick_log(3e-3), "");
        assert_eq!(tick_log(0.0), "");
    }

    #[test]
    fn nice_ticks_include_both_ends_when_they_are_multiples() {
        let t = nice_ticks(2.42, 3.04, 8);
        assert_eq!(t.len(), 6, "{t:?}");
        assert!(
            (t[0] - 2.5).abs() < 1e-12 && (t[5] - 3.0).abs() < 1e-12,
            "{t:?}"
        );
        assert_eq!(
            nice_ticks(0.0, 1.0, 6),
            vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        assert_eq!(nice_ticks(-12.0, -3.0, 8).len(), 5); // step 2 over 9 decades
    }

    #[test]
    fn linear_ticks_are_short() {
        assert_eq!(tick_linear(0.30000000000000004), "0.3");
        assert_eq!(tick_linear(2.0), "2");
        assert_eq!(tick_linear(-0.0), "0");
        assert_eq!(tick_linear(1.25), "1.25");
    }
}
