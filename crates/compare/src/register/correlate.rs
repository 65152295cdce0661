//! Zero-normalised cross-correlation (ZNCC) of a template known at every
//! cell against each placement inside a larger image that has unmeasured
//! (NaN) cells, for all placements at once by FFT.
//!
//! The ZNCC at a placement is taken over the image cells the template
//! covers that are measured: the masked normalised cross-correlation of
//! Padfield (IEEE Trans. Image Process. 21, 2706, 2012), simplified by the
//! template having no mask. The image's window sums (Σ R, Σ R², the count
//! of measured cells) come from summed-area tables; Σ T R, Σ T and Σ T²
//! over the measured cells are correlations with the zero-filled image and
//! its mask. When the template must lie wholly on measured cells, Σ T = 0
//! (T is centred) and Σ T² is the template's own, so one correlation does.
//!
//! Images are row-major `[y * width + x]`; placement (x, y) puts template
//! cell (0, 0) on image cell (x, y).

use std::sync::Arc;

use hypercontact_core::fft::fast_size;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

use crate::error::CompareError;

/// A window whose measured values vary less than this (variance per cell)
/// has no pattern to correlate.
const FLAT_VARIANCE: f64 = 1e-12;

/// The best placement, refined to a fraction of a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Peak {
    pub x: f64,
    pub y: f64,
    pub zncc: f64,
}

/// A centred template and its spectra on one FFT grid, for images of one
/// size.
pub(crate) struct Correlator {
    template_w: usize,
    template_h: usize,
    image_w: usize,
    image_h: usize,
    fft: Fft2,
    /// F(T − mean T)
    template_spectrum: Vec<Complex64>,
    /// F((T − mean T)²) when windows may reach unmeasured cells
    squares_spectrum: Option<Vec<Complex64>>,
    /// Σ (T − mean T)²
    template_sum_sq: f64,
    /// placements with fewer measured cells under the template are skipped
    min_count: usize,
}

impl Correlator {
    /// `None` when the template is larger than the image either way.
    /// `min_overlap` ∈ (0, 1] is the share of the template's cells that
    /// must fall on measured image cells.
    pub(crate) fn new(
        template: &[f64],
        (template_w, template_h): (usize, usize),
        (image_w, image_h): (usize, usize),
        min_overlap: f64,
    ) -> Result<Option<Self>, CompareError> {
        if template_w == 0 || template_h == 0 || template_w > image_w || template_h > image_h {
            return Ok(None);
        }
        let cells = template_w * template_h;
        let mean = template.iter().sum::<f64>() / cells as f64;
        let centred: Vec<f64> = template.iter().map(|t| t - mean).collect();
        let template_sum_sq = centred.iter().map(|t| t * t).sum();
        let fft = Fft2::new(fast_size(image_w), fast_size(image_h));
        let template_spectrum = fft.forward(&fft.pad(&centred, template_w, template_h))?;
        let partial = min_overlap < 1.0;
        let squares_spectrum = if partial {
            let squares: Vec<f64> = centred.iter().map(|t| t * t).collect();
            Some(fft.forward(&fft.pad(&squares, template_w, template_h))?)
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
    pub(crate) fn placements(&self) -> (usize, usize) {
        (
            self.image_w - self.template_w + 1,
            self.image_h - self.template_h + 1,
        )
    }

    /// The ZNCC at every placement, row-major over [`Self::placements`];
    /// NaN where too few measured cells lie under the template or the
    /// measured window is flat.
    pub(crate) fn zncc_map(&self, image: &[f64]) -> Result<Vec<f64>, CompareError> {
        let (w, h) = (self.image_w, self.image_h);
        if image.len() != w * h {
            return Err(CompareError::Length {
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
        let sums = SummedArea::new(&zero_filled, w, h);
        let squares = SummedArea::new(&zero_filled.iter().map(|v| v * v).collect::<Vec<_>>(), w, h);
        let counts = SummedArea::new(&mask, w, h);

        let image_spectrum = self.fft.forward(&self.fft.pad(&zero_filled, w, h))?;
        let cross = self.correlate(&self.template_spectrum, &image_spectrum)?;
        let masked = match &self.squares_spectrum {
            Some(squares_spectrum) => {
                let mask_spectrum = self.fft.forward(&self.fft.pad(&mask, w, h))?;
                Some((
                    self.correlate(&self.template_spectrum, &mask_spectrum)?,
                    self.correlate(squares_spectrum, &mask_spectrum)?,
                ))
            }
            None => None,
        };

        let (px, py) = self.placements();
        let (tw, th) = (self.template_w, self.template_h);
        let fft_w = self.fft.width;
        let mut out = vec![f64::NAN; px * py];
        for y in 0..py {
            for x in 0..px {
                let n = counts.window(x, y, tw, th);
                if n < self.min_count as f64 - 0.5 {
                    continue;
                }
                let k = y * fft_w + x;
                let (sum_t, sum_tt) = match &masked {
                    Some((t, tt)) => (t[k], tt[k]),
                    None => (0.0, self.template_sum_sq),
                };
                let sum_r = sums.window(x, y, tw, th);
                let sum_rr = squares.window(x, y, tw, th);
                let var_t = sum_tt - sum_t * sum_t / n;
                let var_r = sum_rr - sum_r * sum_r / n;
                if var_t <= FLAT_VARIANCE * n || var_r <= FLAT_VARIANCE * n {
                    continue;
                }
                let cov = cross[k] - sum_t * sum_r / n;
                out[y * px + x] = (cov / (var_t * var_r).sqrt()).clamp(-1.0, 1.0);
            }
        }
        Ok(out)
    }

    /// The placement of the largest ZNCC (the first in row-major order on a
    /// tie), refined by a parabola through it and its two neighbours along
    /// each axis; `None` when no placement qualifies.
    pub(crate) fn best(&self, image: &[f64]) -> Result<Option<Peak>, CompareError> {
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
            x: x as f64 + dx,
            y: y as f64 + dy,
            zncc,
        }))
    }

    /// Σ_u T[u] I[u + d] for every d, from the spectra of T and I.
    fn correlate(
        &self,
        template: &[Complex64],
        image: &[Complex64],
    ) -> Result<Vec<f64>, CompareError> {
        let product: Vec<Complex64> = template
            .iter()
            .zip(image)
            .map(|(t, i)| t.conj() * i)
            .collect();
        self.fft.inverse(product)
    }
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

/// Box sums in O(1) each, by a summed-area table.
struct SummedArea {
    width: usize,
    /// (width + 1) × (height + 1); entry (x, y) sums [0, x) × [0, y)
    table: Vec<f64>,
}

impl SummedArea {
    fn new(values: &[f64], width: usize, height: usize) -> Self {
        let stride = width + 1;
        let mut table = vec![0.0; stride * (height + 1)];
        for y in 0..height {
            let mut row = 0.0;
            for x in 0..width {
                row += values[y * width + x];
                table[(y + 1) * stride + x + 1] = table[y * stride + x + 1] + row;
            }
        }
        Self { width, table }
    }

    /// Σ over [x, x + w) × [y, y + h).
    fn window(&self, x: usize, y: usize, w: usize, h: usize) -> f64 {
        let s = self.width + 1;
        let t = &self.table;
        t[(y + h) * s + x + w] - t[y * s + x + w] - t[(y + h) * s + x] + t[y * s + x]
    }
}

/// A 2-D FFT of real, row-major arrays: real FFTs along the rows, complex
/// FFTs down the columns of the half spectrum, kept transposed
/// (`[kx * height + y]`) so the columns are contiguous.
struct Fft2 {
    width: usize,
    height: usize,
    rows_forward: Arc<dyn RealToComplex<f64>>,
    rows_inverse: Arc<dyn ComplexToReal<f64>>,
    columns_forward: Arc<dyn Fft<f64>>,
    columns_inverse: Arc<dyn Fft<f64>>,
}

impl Fft2 {
    fn new(width: usize, height: usize) -> Self {
        let mut real = RealFftPlanner::<f64>::new();
        let mut complex = FftPlanner::<f64>::new();
        Self {
            width,
            height,
            rows_forward: real.plan_fft_forward(width),
            rows_inverse: real.plan_fft_inverse(width),
            columns_forward: complex.plan_fft_forward(height),
            columns_inverse: complex.plan_fft_inverse(height),
        }
    }

    fn half(&self) -> usize {
        self.width / 2 + 1
    }

    /// A w × h row-major array zero-padded to the FFT grid.
    fn pad(&self, values: &[f64], w: usize, h: usize) -> Vec<f64> {
        let mut out = vec![0.0; self.width * self.height];
        for (row, src) in out.chunks_mut(self.width).zip(values.chunks(w)).take(h) {
            row[..w].copy_from_slice(src);
        }
        out
    }

    fn forward(&self, real: &[f64]) -> Result<Vec<Complex64>, CompareError> {
        let (w, h, half) = (self.width, self.height, self.half());
        let mut spectrum = vec![Complex64::default(); half * h];
        let mut input = vec![0.0; w];
        let mut output = vec![Complex64::default(); half];
        let mut scratch = self.rows_forward.make_scratch_vec();
        for (y, row) in real.chunks(w).enumerate() {
            input.copy_from_slice(row);
            self.rows_forward
                .process_with_scratch(&mut input, &mut output, &mut scratch)
                .map_err(fft_error)?;
            for (kx, v) in output.iter().enumerate() {
                spectrum[kx * h + y] = *v;
            }
        }
        let mut scratch =
            vec![Complex64::default(); self.columns_forward.get_inplace_scratch_len()];
        for column in spectrum.chunks_mut(h) {
            self.columns_forward
                .process_with_scratch(column, &mut scratch);
        }
        Ok(spectrum)
    }

    /// The inverse of [`Self::forward`], normalised.
    fn inverse(&self, mut spectrum: Vec<Complex64>) -> Result<Vec<f64>, CompareError> {
        let (w, h, half) = (self.width, self.height, self.half());
        let mut scratch =
            vec![Complex64::default(); self.columns_inverse.get_inplace_scratch_len()];
        for column in spectrum.chunks_mut(h) {
            self.columns_inverse
                .process_with_scratch(column, &mut scratch);
        }
        let norm = 1.0 / (w * h) as f64;
        let mut out = vec![0.0; w * h];
        let mut input = vec![Complex64::default(); half];
        let mut scratch = self.rows_inverse.make_scratch_vec();
        for (y, row) in out.chunks_mut(w).enumerate() {
            for (kx, v) in input.iter_mut().enumerate() {
                *v = spectrum[kx * h + y];
            }
            // a real signal's DC and Nyquist terms are real; rounding leaves
            // a trace the real inverse refuses
            input[0].im = 0.0;
            if w.is_multiple_of(2) {
                input[half - 1].im = 0.0;
            }
            self.rows_inverse
                .process_with_scratch(&mut input, row, &mut scratch)
                .map_err(fft_error)?;
            for v in row.iter_mut() {
                *v *= norm;
            }
        }
        Ok(out)
    }
}

fn fft_error(e: realfft::FftError) -> CompareError {
    CompareError::Internal(format!("the FFT refused its buffers: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The definition: ZNCC over the measured cells under the template.
    fn brute_force(
        template: &[f64],
        (tw, th): (usize, usize),
        image: &[f64],
        (iw, ih): (usize, usize),
        min_count: usize,
    ) -> Vec<f64> {
        let (px, py) = (iw - tw + 1, ih - th + 1);
        let mean_t = template.iter().sum::<f64>() / template.len() as f64;
        let mut out = vec![f64::NAN; px * py];
        for y in 0..py {
            for x in 0..px {
                let pairs: Vec<(f64, f64)> = (0..th)
                    .flat_map(|v| (0..tw).map(move |u| (u, v)))
                    .map(|(u, v)| (template[v * tw + u] - mean_t, image[(y + v) * iw + x + u]))
                    .filter(|(_, r)| !r.is_nan())
                    .collect();
                let n = pairs.len() as f64;
                if pairs.len() < min_count {
                    continue;
                }
                let (mt, mr) = (
                    pairs.iter().map(|p| p.0).sum::<f64>() / n,
                    pairs.iter().map(|p| p.1).sum::<f64>() / n,
                );
                let (mut c, mut vt, mut vr) = (0.0, 0.0, 0.0);
                for (t, r) in &pairs {
                    c += (t - mt) * (r - mr);
                    vt += (t - mt) * (t - mt);
                    vr += (r - mr) * (r - mr);
                }
                if vt <= FLAT_VARIANCE * n || vr <= FLAT_VARIANCE * n {
                    continue;
                }
                out[y * px + x] = c / (vt * vr).sqrt();
            }
        }
        out
    }

    fn random_field(w: usize, h: usize, nan_share: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
        (0..w * h)
            .map(|_| {
                if rng.random::<f64>() < nan_share {
                    f64::NAN
                } else {
                    rng.random::<f64>()
                }
            })
            .collect()
    }

    #[test]
    fn an_embedded_template_is_found_where_it_was_cut() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (iw, ih, tw, th) = (61, 47, 19, 13);
        let image = random_field(iw, ih, 0.0, &mut rng);
        let (x0, y0) = (23, 17);
        let template: Vec<f64> = (0..th)
            .flat_map(|v| (0..tw).map(move |u| (u, v)))
            .map(|(u, v)| 0.5 * image[(y0 + v) * iw + x0 + u] + 0.2)
            .collect();
        let c = Correlator::new(&template, (tw, th), (iw, ih), 1.0)
            .unwrap()
            .unwrap();
        let peak = c.best(&image).unwrap().unwrap();
        // a gain and offset do not change the ZNCC
        assert!((peak.zncc - 1.0).abs() < 1e-12, "{peak:?}");
        assert!((peak.x - x0 as f64).abs() < 0.5 && (peak.y - y0 as f64).abs() < 0.5);
    }

    #[test]
    fn a_smooth_peak_is_located_between_cells() {
        // a Gaussian blob at a fractional position, a template of the same
        // blob centred: the parabola refines the placement towards it
        let (iw, ih, tw, th) = (64, 64, 21, 21);
        let blob = |x: f64, y: f64, cx: f64, cy: f64| {
            (-((x - cx).powi(2) + (y - cy).powi(2)) / 18.0).exp()
        };
        let (cx, cy) = (30.3, 25.7);
        let image: Vec<f64> = (0..iw * ih)
            .map(|k| blob((k % iw) as f64, (k / iw) as f64, cx, cy))
            .collect();
        let template: Vec<f64> = (0..tw * th)
            .map(|k| blob((k % tw) as f64, (k / tw) as f64, 10.0, 10.0))
            .collect();
        let c = Correlator::new(&template, (tw, th), (iw, ih), 1.0)
            .unwrap()
            .unwrap();
        let peak = c.best(&image).unwrap().unwrap();
        assert!((peak.x - (cx - 10.0)).abs() < 0.1, "{peak:?}");
        assert!((peak.y - (cy - 10.0)).abs() < 0.1, "{peak:?}");
    }

    #[test]
    fn too_large_templates_and_wrong_images_are_refused() {
        assert!(
            Correlator::new(&[0.0; 6], (3, 2), (2, 5), 1.0)
                .unwrap()
                .is_none()
        );
        let c = Correlator::new(&[0.0, 1.0, 1.0, 0.0], (2, 2), (4, 4), 1.0)
            .unwrap()
            .unwrap();
        assert!(matches!(
            c.zncc_map(&[0.0; 15]),
            Err(CompareError::Length { .. })
        ));
        // all unmeasured: no placement
        assert_eq!(c.best(&[f64::NAN; 16]).unwrap(), None);
    }

    proptest! {
        #![proptest_config(hypercontact_fuzz::config(40))]

        /// The FFT and summed-area evaluation equals the definition at every
        /// placement, with unmeasured cells skipped (not read as 0).
        #[test]
        fn fft_zncc_equals_the_definition(
            tw in 1usize..9,
            th in 1usize..9,
            extra_w in 0usize..12,
            extra_h in 0usize..12,
            nan_share in 0.0f64..0.3,
            min_overlap in prop_oneof![Just(1.0), 0.3f64..1.0],
            seed in 0u64..1000,
        ) {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (iw, ih) = (tw + extra_w, th + extra_h);
            let template = random_field(tw, th, 0.0, &mut rng);
            let image = random_field(iw, ih, nan_share, &mut rng);
            let c = Correlator::new(&template, (tw, th), (iw, ih), min_overlap).unwrap().unwrap();
            let fast = c.zncc_map(&image).unwrap();
            let slow = brute_force(&template, (tw, th), &image, (iw, ih), c.min_count);
            prop_assert_eq!(fast.len(), slow.len());
            for (k, (a, b)) in fast.iter().zip(&slow).enumerate() {
                prop_assert!(
                    (a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-9,
                    "placement {}: fft {} vs definition {}", k, a, b
                );
            }
        }
    }
}
