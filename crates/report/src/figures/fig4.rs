//! Fig. 4 of the paper, one row per sample: (a–d) the height map as a colour
//! map with colour bar and scale bar, (e–h) the PSD C(q) along x and (i–l)
//! along y on log–log axes with the power law C ∝ q^(−1−2H), and (m–p) the
//! truncation curve A/A0 against z/σ. Panel letters run down the columns
//! as in the paper. A panel whose input is not wired says so in place.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::colormap::viridis;
use super::fig2::min_max;
use super::fig7::log_range;
use super::plotting::{
    Axis, Figure, HPos, Pos, Raster, Rasters, TextSizes, VPos, dashed_swatch, draw_axes, font,
    sample_colour, solid_swatch, tick_decade, tick_linear,
};
use crate::ReportError;
use crate::gather::{Sample, Series};
use crate::powerlaw::PowerLaw;
use hypercontact_core::{Field, Schema};
use hypercontact_surface::surface_stage::PsdTable;

const WIDTH_PX: u32 = 1600;
const ROW_PX: u32 = 400;
const MAP_COLUMN_PX: u32 = 430;
const PLOT_COLUMN_PX: u32 = 390;
const TICK_PX: f64 = 27.0;

/// The unit of q as the `psd` table declares it.
fn q_unit() -> &'static str {
    PsdTable::COLUMNS
        .iter()
        .find(|c| c.name == "q_per_m")
        .map_or("", |c| c.unit)
}

pub struct Fig4<'a> {
    /// (sample, its colour index).
    pub samples: Vec<(&'a Sample<'a>, usize)>,
}

impl Figure for Fig4<'_> {
    fn name(&self) -> &'static str {
        "fig4"
    }

    fn size_px(&self) -> (u32, u32) {
        (WIDTH_PX, ROW_PX * self.samples.len().max(1) as u32)
    }

    fn draw<'r, DB: DrawingBackend + 'r>(
        &self,
        root: &'r DrawingArea<DB, Shift>,
        rasters: &mut Rasters,
    ) -> Result<(), ReportError> {
        let rows = root.split_evenly((self.samples.len().max(1), 1));
        let n = self.samples.len();
        for (row, ((sample, colour_index), area)) in self.samples.iter().zip(&rows).enumerate() {
            let (map_area, rest) = area.split_horizontally(MAP_COLUMN_PX);
            let (psd_x_area, rest) = rest.split_horizontally(PLOT_COLUMN_PX);
            let (psd_y_area, profile_area) = rest.split_horizontally(PLOT_COLUMN_PX);
            let letter = |column: usize| char::from(b'a' + ((column * n + row) % 26) as u8);
            let colour = sample_colour(*colour_index);
            let label = &sample.label;

            let title = format!("({}) {label}", letter(0));
            match sample.height {
                Some(field) if field.values.iter().any(|h| h.is_finite()) => {
                    draw_map(self.name(), &map_area, rasters, field, &title)?
                }
                Some(_) => missing(
                    self.name(),
                    &map_area,
                    &title,
                    "no measured point in the map",
                )?,
                None => missing(self.name(), &map_area, &title, "no height map wired")?,
            }
            let psd_range = log_range(
                sample
                    .psd_x
                    .iter()
                    .chain(&sample.psd_y)
                    .flat_map(|s| s.y.iter().copied()),
                12.0,
            );
            let stats = sample.stats.as_ref();
            for (column, area, series, hurst, dir) in [
                (1, &psd_x_area, &sample.psd_x, stats.map(|s| s.hurst_x), "x"),
                (2, &psd_y_area, &sample.psd_y, stats.map(|s| s.hurst_y), "y"),
            ] {
                let title = format!("({}) {label}, along {dir}", letter(column));
                match series {
                    Some(s) => draw_psd(self.name(), area, s, hurst, psd_range, colour, &title)?,
                    None => missing(
                        self.name(),
                        area,
                        &title,
                        &format!("no PSD along {dir} wired"),
                    )?,
                }
            }
            let title = format!("({}) {label}", letter(3));
            match &sample.profile {
                Some(p) => draw_profile(self.name(), &profile_area, p, colour, &title)?,
                None => missing(
                    self.name(),
                    &profile_area,
                    &title,
                    "no truncation profile wired",
                )?,
            }
        }
        Ok(())
    }
}

/// Space above each panel's plot for its title, pixels.
const TITLE_PX: i32 = 58;

/// The panel's letter and sample, top left, as in the paper.
fn panel_title<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(), ReportError> {
    area.draw(&Text::new(title.to_owned(), (20, 12), font(TICK_PX * 1.1)))
        .map_err(|e| ReportError::plot(figure, e))?;
    Ok(())
}

fn missing<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    title: &str,
    why: &str,
) -> Result<(), ReportError> {
    let (w, h) = area.dim_in_pixel();
    let err = |e| ReportError::plot(figure, e);
    panel_title(figure, area, title)?;
    area.draw(&Text::new(
        why.to_owned(),
        (w as i32 / 2, h as i32 / 2),
        font(TICK_PX)
            .color(&RGBColor(130, 130, 130))
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))
    .map_err(err)?;
    Ok(())
}

/// Block means of the finite heights onto a `w × h` pixel grid (x to the
/// right, y up), NaN where a block holds no measured point.
pub fn resample(field: &Field, w: usize, h: usize) -> Vec<f64> {
    let (nx, ny) = field.values.dim();
    let mut out = vec![f64::NAN; w * h];
    let block = |p: usize, pixels: usize, cells: usize| {
        let lo = p * cells / pixels;
        let hi = ((p + 1) * cells / pixels).max(lo + 1).min(cells);
        lo..hi
    };
    for py in 0..h {
        // Row 0 of the image is the top, i.e. the largest y.
        let ys = block(h - 1 - py, h, ny);
        for px in 0..w {
            let (mut sum, mut count) = (0.0, 0usize);
            for i in block(px, w, nx) {
                for j in ys.clone() {
                    let v = field.values[[i, j]];
                    if v.is_finite() {
                        sum += v;
                        count += 1;
                    }
                }
            }
            if count > 0 {
                out[py * w + px] = sum / count as f64;
            }
        }
    }
    out
}

/// A length of 1 mm when the map is wide enough to show it, otherwise the
/// largest 1–2–5 step below a third of the map width; (metres, label).
pub fn scale_bar_m(map_width_m: f64) -> (f64, String) {
    if map_width_m >= 1.25e-3 {
        return (1e-3, "1 mm".into());
    }
    let target = map_width_m / 3.0;
    let decade = 10f64.powf(target.log10().floor());
    let step = [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s <= target)
        .unwrap_or(decade);
    let um = step * 1e6;
    let label = if um >= 1.0 {
        format!("{} µm", tick_linear(um))
    } else {
        format!("{} nm", tick_linear(um * 1e3))
    };
    (step, label)
}

fn draw_map<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    rasters: &mut Rasters,
    field: &Field,
    title: &str,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let (panel_w, panel_h) = area.dim_in_pixel();
    panel_title(figure, area, title)?;
    let (nx, ny) = field.values.dim();
    let (width_m, height_m) = (nx as f64 * field.dx_m, ny as f64 * field.dy_m);
    // The largest box of the map's aspect ratio inside the free space.
    let (box_w, box_h) = (f64::from(panel_w) - 150.0, f64::from(panel_h) - 110.0);
    let scale = (box_w / width_m).min(box_h / height_m);
    let (w, h) = (
        ((width_m * scale).round() as usize).max(1),
        ((height_m * scale).round() as usize).max(1),
    );
    let (x0, y0) = (20, TITLE_PX + ((box_h - h as f64) / 2.0) as i32);

    let values = resample(field, w, h);
    let lowest = field
        .values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    let (lo, hi) = min_max(values.iter().copied());
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for v in &values {
        let c = viridis((v - lo) / span);
        rgb.extend_from_slice(&[c.0, c.1, c.2]);
    }
    rasters.place(
        figure,
        area,
        x0,
        y0,
        Raster {
            x_px: 0,
            y_px: 0,
            width_px: w as u32,
            height_px: h as u32,
            rgb,
        },
    )?;
    area.draw(&Rectangle::new(
        [(x0 - 1, y0 - 1), (x0 + w as i32, y0 + h as i32)],
        BLACK.stroke_width(1),
    ))
    .map_err(err)?;

    // Scale bar under the map, left-aligned.
    let (bar_m, bar_label) = scale_bar_m(width_m);
    let bar_px = (bar_m * scale).round() as i32;
    let bar_y = y0 + h as i32 + 22;
    area.draw(&Rectangle::new(
        [(x0, bar_y - 3), (x0 + bar_px, bar_y + 3)],
        BLACK.filled(),
    ))
    .map_err(err)?;
    area.draw(&Text::new(
        bar_label,
        (x0 + bar_px + 12, bar_y),
        font(TICK_PX).pos(Pos::new(HPos::Left, VPos::Center)),
    ))
    .map_err(err)?;

    // Colour bar: heights above the lowest measured point, µm.
    let heights_um = ((lo - lowest) * 1e6, (hi - lowest) * 1e6);
    draw_colour_bar(figure, area, (x0, y0), (w, h), heights_um)
}

/// The colour bar right of a map drawn at `(x0, y0)`, `w` × `h` pixels:
/// viridis over the heights `lo_um`…`hi_um` with their ticks.
fn draw_colour_bar<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    (x0, y0): (i32, i32),
    (w, h): (usize, usize),
    (lo_um, hi_um): (f64, f64),
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let (panel_w, _) = area.dim_in_pixel();
    let cbar_x = x0 + w as i32 + 18;
    let cbar = area.clone().shrink(
        (cbar_x, y0 - (TICK_PX * 0.5) as i32),
        (
            panel_w.saturating_sub(cbar_x as u32),
            h as u32 + TICK_PX as u32,
        ),
    );
    let mut chart = ChartBuilder::on(&cbar)
        .margin_top((TICK_PX * 0.5) as i32)
        .margin_bottom((TICK_PX * 0.5) as i32)
        .set_label_area_size(LabelAreaPosition::Right, TICK_PX * 3.2)
        .build_cartesian_2d(0.0..1.0, Axis::new(lo_um, hi_um.max(lo_um + 1e-9), 6))
        .map_err(err)?;
    let steps = 64;
    chart
        .draw_series((0..steps).map(|k| {
            let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
            let c = viridis((a + b) / 2.0);
            Rectangle::new(
                [
                    (0.0, lo_um + a * (hi_um - lo_um)),
                    (1.0, lo_um + b * (hi_um - lo_um)),
                ],
                c.filled(),
            )
        }))
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_formatter(&|v| tick_linear(*v))
        .label_style(font(TICK_PX * 0.9))
        .axis_style(BLACK.stroke_width(1))
        .draw()
        .map_err(err)?;
    area.draw(&Text::new(
        "µm".to_owned(),
        (cbar_x, y0 - 10),
        font(TICK_PX * 0.9).pos(Pos::new(HPos::Left, VPos::Bottom)),
    ))
    .map_err(err)?;
    Ok(())
}

fn draw_psd<'r, DB: DrawingBackend + 'r>(
    figure: &str,
    area: &'r DrawingArea<DB, Shift>,
    psd: &Series,
    hurst: Option<f64>,
    (c_lo, c_hi): (f64, f64),
    colour: RGBColor,
    title: &str,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let sizes = TextSizes::panel(TICK_PX);
    let (q_lo, q_hi) = log_range(psd.x.iter().copied(), 12.0);
    // Log–log axes drawn as log10 on linear axes, so ticks sit on decades.
    let (qe_lo, qe_hi) = (q_lo.log10(), q_hi.log10());
    let (ce_lo, ce_hi) = (c_lo.log10(), c_hi.log10());
    panel_title(figure, area, title)?;
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_top(TITLE_PX)
        .margin_right(22)
        .x_label_area_size(sizes.label * 2.6)
        .y_label_area_size(sizes.label * 3.3)
        .build_cartesian_2d(
            Axis::decades(qe_lo, qe_hi, 8),
            Axis::decades(ce_lo, ce_hi, 8),
        )
        .map_err(err)?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        &format!("q ({})", q_unit()),
        // The x and y PSDs drawn here are 1-D: C in m³.
        "C(q) (m³)",
        &|v| tick_decade(*v),
        &|v| tick_decade(*v),
        (
            ((qe_hi - qe_lo) as usize + 1).min(8),
            ((ce_hi - ce_lo) as usize + 1).min(8),
        ),
    )?;
    let data = colour.stroke_width(2);
    chart
        .draw_series(LineSeries::new(
            psd.x
                .iter()
                .zip(&psd.y)
                .map(|(q, c)| (q.log10(), c.log10())),
            data,
        ))
        .map_err(err)?
        .label("C(q)")
        .legend(move |p| solid_swatch(p, 30, data));
    if let Some(law) = PowerLaw::fit(&psd.x, &psd.y, hurst) {
        let (a, b) = (psd.x[0], psd.x[psd.x.len() - 1]);
        // Clip the line to the axes so it never runs over the labels.
        let points: Vec<(f64, f64)> = (0..=50)
            .map(|k| a * (b / a).powf(f64::from(k) / 50.0))
            .map(|q| (q, law.eval(q)))
            .filter(|&(_, c)| c >= c_lo && c <= c_hi)
            .map(|(q, c)| (q.log10(), c.log10()))
            .collect();
        let line = BLACK.stroke_width(2);
        chart
            .draw_series(DashedLineSeries::new(points, 8, 6, line))
            .map_err(err)?
            .label(format!("fit, H = {:.2}", law.hurst()))
            .legend(move |p| dashed_swatch(p, 30, line));
    }
    chart
        .configure_series_labels()
        // Spectra fall from upper left to lower right: lower left is free.
        .position(SeriesLabelPosition::LowerLeft)
        .margin(8)
        .legend_area_size(40)
        .label_font(font(sizes.legend))
        .background_style(WHITE.mix(0.9))
        .border_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    Ok(())
}

fn draw_profile<DB: DrawingBackend>(
    figure: &str,
    area: &DrawingArea<DB, Shift>,
    profile: &Series,
    colour: RGBColor,
    title: &str,
) -> Result<(), ReportError> {
    let err = |e| ReportError::plot(figure, e);
    let sizes = TextSizes::panel(TICK_PX);
    let (z_lo, z_hi) = min_max(profile.x.iter().copied());
    let pad = 0.02 * (z_hi - z_lo).max(1e-9);
    panel_title(figure, area, title)?;
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_top(TITLE_PX)
        .margin_right(22)
        .x_label_area_size(sizes.label * 2.6)
        .y_label_area_size(sizes.label * 2.8)
        .build_cartesian_2d(
            Axis::new(z_lo - pad, z_hi + pad, 7),
            Axis::new(0.0, 1.02, 6),
        )
        .map_err(err)?;
    draw_axes(
        &mut chart,
        figure,
        sizes,
        "z/σ",
        "A/A₀",
        &|v| tick_linear(*v),
        &|v| tick_linear(*v),
        (6, 6),
    )?;
    chart
        .draw_series(LineSeries::new(
            profile.x.iter().copied().zip(profile.y.iter().copied()),
            colour.stroke_width(3),
        ))
        .map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    #[test]
    fn the_q_axis_has_the_psd_tables_unit() {
        // Empty if the surface stage renamed its column.
        assert!(!q_unit().is_empty());
    }

    #[test]
    fn block_means_keep_the_mean_and_put_y_up() {
        // h(i, j) = i + 10 j on a 4 × 4 grid, down to 2 × 2 pixels.
        let values = Array2::from_shape_fn((4, 4), |(i, j)| (i + 10 * j) as f64);
        let field = Field::new(values, 1.0, 1.0).unwrap();
        let px = resample(&field, 2, 2);
        // Top-left pixel = low x, high y: i ∈ {0,1}, j ∈ {2,3}.
        assert_eq!(px[0], 0.5 + 25.0);
        assert_eq!(px[3], 2.5 + 5.0);
    }

    #[test]
    fn missing_blocks_are_nan_and_nan_is_skipped() {
        let mut values = Array2::from_elem((2, 2), 1.0);
        values[[0, 0]] = f64::NAN;
        values[[0, 1]] = f64::NAN;
        values[[1, 1]] = 3.0;
        let field = Field::new(values, 1.0, 1.0).unwrap();
        let px = resample(&field, 2, 1);
        assert!(px[0].is_nan());
        assert_eq!(px[1], 2.0);
    }

    #[test]
    fn scale_bar_is_one_millimetre_on_wide_maps() {
        assert_eq!(scale_bar_m(10e-3), (1e-3, "1 mm".into()));
        let (m, label) = scale_bar_m(0.8e-3);
        assert!((m - 2e-4).abs() < 1e-12, "{m}");
        assert_eq!(label, "200 µm");
    }
}
