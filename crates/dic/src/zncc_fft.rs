//! Integer-pixel initial guess by zero-normalised cross-correlation over a
//! search window, computed with FFTs.
//!
//! The numerator Σ (T − T̄) S is a cross-correlation (FFT, rustfft); the
//! window means and norms under every shift come from summed-area tables
//! (Lewis, "Fast normalized cross-correlation", Vision Interface 1995).

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::gray::GrayImage;

/// The best integer match of a template.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegerMatch {
    /// Displacement of the template centre, pixels.
    pub dx: i64,
    pub dy: i64,
    pub zncc: f64,
}

/// Finds the integer displacement of the `2 half + 1` square around
/// `(x0, y0)` in `reference` within ±`radius` pixels of `(cx, cy)` in
/// `target`; None if the template is flat or the window empty.
#[allow(clippy::too_many_arguments)]
pub fn integer_search(
    reference: &GrayImage,
    x0: usize,
    y0: usize,
    half: usize,
    target: &GrayImage,
    cx: i64,
    cy: i64,
    radius: usize,
) -> Option<IntegerMatch> {
    let side = 2 * half + 1;
    if x0 < half || y0 < half || x0 + half >= reference.width || y0 + half >= reference.height {
        return None;
    }
    let reach = (radius + half) as i64;
    let wx0 = (cx - reach).max(0) as usize;
    let wy0 = (cy - reach).max(0) as usize;
    let wx1 = ((cx + reach) as usize).min(target.width.saturating_sub(1));
    let wy1 = ((cy + reach) as usize).min(target.height.saturating_sub(1));
    if cx + reach < 0 || cy + reach < 0 || wx1 < wx0 + side - 1 || wy1 < wy0 + side - 1 {
        return None;
    }
    let (mx, my) = (wx1 - wx0 + 1, wy1 - wy0 + 1);

    let n = (side * side) as f64;
    let mut template = Vec::with_capacity(side * side);
    for y in y0 - half..=y0 + half {
        for x in x0 - half..=x0 + half {
            template.push(reference.get(x, y));
        }
    }
    let t_mean = template.iter().sum::<f64>() / n;
    let t_norm = template
        .iter()
        .map(|t| (t - t_mean) * (t - t_mean))
        .sum::<f64>()
        .sqrt();
    if t_norm.is_nan() || t_norm <= 1e-12 {
        return None;
    }

    let mut window = vec![Complex::new(0.0, 0.0); mx * my];
    let mut padded = vec![Complex::new(0.0, 0.0); mx * my];
    for y in 0..my {
        for x in 0..mx {
            window[y * mx + x].re = target.get(wx0 + x, wy0 + y);
        }
    }
    for j in 0..side {
        for i in 0..side {
            padded[j * mx + i].re = template[j * side + i] - t_mean;
        }
    }
    let mut planner = FftPlanner::new();
    fft_2d(&mut planner, &mut window, mx, my, false);
    fft_2d(&mut planner, &mut padded, mx, my, false);
    for (w, t) in window.iter_mut().zip(&padded) {
        *w *= t.conj();
    }
    fft_2d(&mut planner, &mut window, mx, my, true);
    let scale = 1.0 / (mx * my) as f64;

    // Summed-area tables of the window and its square.
    let stride = mx + 1;
    let mut sum = vec![0.0; stride * (my + 1)];
    let mut sum_sq = vec![0.0; stride * (my + 1)];
    for y in 0..my {
        for x in 0..mx {
            let v = target.get(wx0 + x, wy0 + y);
            let i = (y + 1) * stride + x + 1;
            sum[i] = v + sum[i - 1] + sum[i - stride] - sum[i - stride - 1];
            sum_sq[i] = v * v + sum_sq[i - 1] + sum_sq[i - stride] - sum_sq[i - stride - 1];
        }
    }
    let box_sum = |table: &[f64], x: usize, y: usize| {
        table[(y + side) * stride + x + side]
            - table[y * stride + x + side]
            - table[(y + side) * stride + x]
            + table[y * stride + x]
    };

    let mut best: Option<IntegerMatch> = None;
    for sy in 0..=my - side {
        for sx in 0..=mx - side {
            let s = box_sum(&sum, sx, sy);
            let ss = box_sum(&sum_sq, sx, sy);
            let var = ss - s * s / n;
            if var.is_nan() || var <= 1e-12 {
                continue;
            }
            let zncc = window[sy * mx + sx].re * scale / (t_norm * var.sqrt());
            if best.is_none_or(|b| zncc > b.zncc) {
                best = Some(IntegerMatch {
                    dx: (wx0 + sx + half) as i64 - x0 as i64,
                    dy: (wy0 + sy + half) as i64 - y0 as i64,
                    zncc,
                });
            }
        }
    }
    best
}

/// In-place 2-D FFT of a row-major `mx × my` array.
fn fft_2d(
    planner: &mut FftPlanner<f64>,
    data: &mut [Complex<f64>],
    mx: usize,
    my: usize,
    inverse: bool,
) {
    let row_fft = if inverse {
        planner.plan_fft_inverse(mx)
    } else {
        planner.plan_fft_forward(mx)
    };
    for row in data.chunks_exact_mut(mx) {
        row_fft.process(row);
    }
    let column_fft = if inverse {
        planner.plan_fft_inverse(my)
    } else {
        planner.plan_fft_forward(my)
    };
    let mut column = vec![Complex::new(0.0, 0.0); my];
    for x in 0..mx {
        for (y, c) in column.iter_mut().enumerate() {
            *c = data[y * mx + x];
        }
        column_fft.process(&mut column);
        for (y, c) in column.iter().enumerate() {
            data[y * mx + x] = *c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_an_integer_shift_and_matches_direct_zncc() {
        // A pseudo-random texture shifted by (7, -4) pixels.
        let (w, h) = (96, 80);
        let texture = |x: i64, y: i64| {
            let k = (x * 73_856_093) ^ (y * 19_349_663);
            ((k.wrapping_mul(2_654_435_761) >> 7) & 1023) as f64 / 1023.0
        };
        let mut a = Vec::new();
        let mut b = Vec::new();
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                a.push(texture(x, y));
                b.push(texture(x - 7, y + 4));
            }
        }
        let a = GrayImage::new(w, h, a).unwrap();
        let b = GrayImage::new(w, h, b).unwrap();
        let m = integer_search(&a, 40, 40, 7, &b, 40, 40, 12).unwrap();
        assert_eq!((m.dx, m.dy), (7, -4));
        assert!((m.zncc - 1.0).abs() < 1e-9, "{}", m.zncc);
    }
}
