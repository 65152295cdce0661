//! Zero-normalised cross-correlation (ZNCC) of a template known at every
//! cell against each placement inside a larger image that may have
//! unmeasured (NaN) cells, for all placements at once by FFT.
//!
//! At placement d the ZNCC is taken over the n image cells under the
//! template that are measured (M):
//!
//!   ZNCC(d) = cov / √(var_T var_R),  cov = Σ_M T R − Σ_M T Σ_M R / n,
//!   var_T = Σ_M T² − (Σ_M T)² / n,  var_R = Σ_M R² − (Σ_M R)² / n,
//!
//! with T centred on its mean over all its cells and R the image under it:
//! the masked normalised cross-correlation of Padfield (IEEE Trans. Image
//! Process. 21, 2706, 2012), simplified by the template having no mask. The
//! image's window sums (Σ R, Σ R², n) come from summed-area tables (Lewis,
//! "Fast normalized cross-correlation", Vision Interface 1995); Σ T R,
//! Σ_M T and Σ_M T² are correlations of T and T² with the zero-filled image
//! and its mask, by [`RealFft2`] on a fast-size grid at least the image's
//! (no wrap-around reaches a placement inside the image). When every cell
//! under the template must be measured, Σ_M T = 0 and Σ_M T² is the
//! template's own, so one correlation does.
//!
//! Images are row-major `[y · width + x]`; placement (x, y) puts template
//! cell (0, 0) on image cell (x, y). Windows whose measured values vary
//! less than [`FLAT_VARIANCE`] per cell have no pattern and no ZNCC.

mod summed_area;

use crate::NumericError;
use crate::fft2::{Complex64, RealFft2, fast_size};
use summed_area::SummedArea;

/// A window (or template) whose values vary less than this (variance per
/// cell) has no pattern to correlate.
pub const FLAT_VARIANCE: f64 = 1e-12;

/// The best placement, refined to a fraction of a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// the placement of the largest ZNCC, (x, y) in cells
    pub cell: (usize, usize),
    /// `cell` refined by a parabola through each axis' neighbours, cells
    pub x: f64,
    pub y: f64,
    /// the ZNCC at `cell`
    pub zncc: f64,
}

/// A centred template and its spectra on one FFT grid, for images of one
/// size.
pub struct Correlator {
    template_w: usize,
    template_h: usize,
    image_w: usize,
    image_h: usize,
    fft: RealFft2,
    /// F(T − mean T)
    template_spectrum: Vec<Complex64>,
    /// F((T − mean T)²), when windows may reach unmeasured cells
    squares_spectrum: Option<Vec<Complex64>>,
    /// Σ (T − mean T)²
    template_sum_sq: f64,
    /// placements with fewer measured cells under the template are skipped
    min_count: usize,
}

/// The image's sums the normalisation needs, for one image.
struct Windows {
    sums: SummedArea,
    squares: SummedArea,
    counts: SummedArea,
    /// Σ T R at every placement
    cross: Vec<f64>,
    /// Σ_M T and Σ_M T² at every placement, when cells may be unmeasured
    masked: Option<(Vec<f64>, Vec<f64>)>,
}

impl Correlator {
    /// `None` when the template is empty or larger than the image either
    /// way. `min_overlap` ∈ (0, 1] is the share of the template's cells
    /// that must fall on measured image cells (below 1, the template's
    /// sums over the measured cells are correlated too).
    pub fn new(
        template: &[f64],
        (template_w, template_h): (usize, usize),
        (image_w, image_h): (usize, usize),
        min_overlap: f64,
    ) -> Result<Option<Self>, NumericError> {
        if template_w == 0 || template_h == 0 || template_w > image_w || template_h > image_h {
            return Ok(None);
        }
        let cells = template_w * template_h;
        if template.len() != cells {
            return Err(NumericError::Length {
                what: "correlation template",
                expected: cells,
                got: template.len(),
            });
        }
        let mean = template.iter().sum::<f64>() / cells as f64;
        let centred: Vec<f64> = template.iter().map(|t| t - mean).collect();
        let template_sum_sq = centred.iter().map(|t| t * t).sum();
        let fft = RealFft2::new(fast_size(image_h), fast_size(image_w))?;
        let template_size = (template_h, template_w);
        let template_spectrum = spectrum(&fft, &centred, template_size)?;
        let squares_spectrum = if min_overlap < 1.0 {
            let squares: Vec<f64> = centred.iter().map(|t| t * t).collect();
            Some(spectrum(&fft, &squares, template_size)?)
        } else {
            None
        };
        let min_count = ((min_overlap * cells as f64).ceil() as usize).clamp(2, cells.max(2));
        Ok(Some(Self {
            template_w,
            template_h,
            image_w,
            image_h,
            fft,
            template_spectrum,
            squares_spectrum,
            template_sum_sq,
            min_count,
        }))
    }

    /// Placements in x and y: (image − template + 1) each way.
    pub fn placements(&self) -> (usize, usize) {
        (
            self.image_w - self.template_w + 1,
            self.image_h - self.template_h + 1,
        )
    }

    /// The fewest measured cells a placement needs.
    pub fn min_count(&self) -> usize {
        self.min_count
    }

    /// The ZNCC at every placement, row-major over [`Self::placements`];
    /// NaN where too few measured cells lie under the template or the
    /// template or the measured window is flat.
    pub fn zncc_map(&self, image: &[f64]) -> Result<Vec<f64>, NumericError> {
        let windows = self.windows(image)?;
        let (px, py) = self.placements();
        let (tw, th) = (self.template_w, self.template_h);
        let mut out = vec![f64::NAN; px * py];
        for y in 0..py {
            for x in 0..px {
                let n = windows.counts.window(x, y, tw, th);
                if n < self.min_count as f64 - 0.5 {
                    continue;
                }
                let k = y * px + x;
                let (sum_t, sum_tt) = match &windows.masked {
                    Some((t, tt)) => (t[k], tt[k]),
                    None => (0.0, self.template_sum_sq),
                };
                let sum_r = windows.sums.window(x, y, tw, th);
                let sum_rr = windows.squares.window(x, y, tw, th);
                let var_t = sum_tt - sum_t * sum_t / n;
                let var_r = sum_rr - sum_r * sum_r / n;
                if var_t <= FLAT_VARIANCE * n || var_r <= FLAT_VARIANCE * n {
                    continue;
                }
                let cov = windows.cross[k] - sum_t * sum_r / n;
                out[k] = (cov / (var_t * var_r).sqrt()).clamp(-1.0, 1.0);
            }
        }
        Ok(out)
    }

    /// The placement of the largest ZNCC (the first in row-major order on a
    /// tie), refined by a parabola through it and its two neighbours along
    /// each axis; `None` when no placement qualifies.
    pub fn best(&self, image: &[f64]) -> Result<Option<Peak>, NumericError> {
        let map = self.zncc_map(image)?;
        let (px, py) = self.placements();
        let mut best: Option<(usize, f64)> = None;
        for (k, &v) in map.iter().enumerate() {
            if !v.is_nan() && best.is_none_or(|(_, b)| v > b) {
                best = Some((k, v));
            }
        }
        let Some((k, zncc)) = best else {
            return Ok(None);
        };
        let (x, y) = (k % px, k / px);
        let at = |x: usize, y: usize| map[y * px + x];
        let dx = if x > 0 && x + 1 < px {
            vertex(at(x - 1, y), zncc, at(x + 1, y))
        } else {
            0.0
        };
        let dy = if y > 0 && y + 1 < py {
            vertex(at(x, y - 1), zncc, at(x, y + 1))
        } else {
            0.0
        };
        Ok(Some(Peak {
            cell: (x, y),
            x: x as f64 + dx,
            y: y as f64 + dy,
            zncc,
        }))
    }

    /// The summed-area tables of `image` and its correlations with the
    /// template (and, when cells may be unmeasured, with T and T² over the
    /// mask).
    fn windows(&self, image: &[f64]) -> Result<Windows, NumericError> {
        let (w, h) = (self.image_w, self.image_h);
        if image.len() != w * h {
            return Err(NumericError::Length {
                what: "correlation image",
                expected: w * h,
                got: image.len(),
            });
        }
        let zero_filled: Vec<f64> = image
            .iter()
            .map(|&v| if v.is_nan() { 0.0 } else { v })
            .collect();
        let mask: Vec<f64> = image
            .iter()
            .map(|v| if v.is_nan() { 0.0 } else { 1.0 })
            .collect();
        let squares: Vec<f64> = zero_filled.iter().map(|v| v * v).collect();
        let image_spectrum = spectrum(&self.fft, &zero_filled, (h, w))?;
        let cross = self.correlate(&self.template_spectrum, &image_spectrum)?;
        let masked = match &self.squares_spectrum {
            Some(squares_spectrum) => {
                let mask_spectrum = spectrum(&self.fft, &mask, (h, w))?;
                Some((
                    self.correlate(&self.template_spectrum, &mask_spectrum)?,
                    self.correlate(squares_spectrum, &mask_spectrum)?,
                ))
            }
            None => None,
        };
        Ok(Windows {
            sums: SummedArea::new(&zero_filled, w, h),
            squares: SummedArea::new(&squares, w, h),
            counts: SummedArea::new(&mask, w, h),
            cross,
            masked,
        })
    }

    /// Σ_u T[u] I[u + d] at every placement d, from the spectra of T and I.
    fn correlate(
        &self,
        template: &[Complex64],
        image: &[Complex64],
    ) -> Result<Vec<f64>, NumericError> {
        let mut product: Vec<Complex64> = template
            .iter()
            .zip(image)
            .map(|(t, i)| t.conj() * i)
            .collect();
        let (px, py) = self.placements();
        let (rows, cols) = self.fft.grid();
        let mut out = vec![0.0; px * py];
        let scale = 1.0 / (cols * rows) as f64;
        self.fft.inverse(&mut product, (py, px), &mut out, scale)?;
        Ok(out)
    }
}

/// The half spectrum of a `(rows, cols)` map on `fft`'s grid.
fn spectrum(
    fft: &RealFft2,
    map: &[f64],
    size: (usize, usize),
) -> Result<Vec<Complex64>, NumericError> {
    let mut out = vec![Complex64::ZERO; fft.spectrum_len()];
    fft.forward(map, size, &mut out, &mut fft.workspace())?;
    Ok(out)
}

/// The offset (within ±½) of the top of the parabola through three
/// equally spaced values around a maximum; 0 when a neighbour is missing or
/// the three do not bend down.
fn vertex(before: f64, centre: f64, after: f64) -> f64 {
    let bend = before - 2.0 * centre + after;
    if before.is_nan() || after.is_nan() || bend >= 0.0 {
        return 0.0;
    }
    (0.5 * (before - after) / bend).clamp(-0.5, 0.5)
}

#[cfg(test)]
mod tests;
