//! Bicubic B-spline interpolation of an image, the interpolant of the
//! deformed image in IC-GN.
//!
//! Coefficients come from the recursive prefilter of Unser, Aldroubi & Eden
//! (IEEE Trans. Signal Process. 41, 1993) with the mirror boundary and causal
//! initialisation of Thévenaz, Blu & Unser ("Interpolation revisited", IEEE
//! TMI 19, 2000), so the spline passes exactly through every pixel value.
//! Pixel centres sit at integer coordinates; `x` is the column, `y` the row.

use crate::gray::GrayImage;

/// The pole of the cubic B-spline prefilter, √3 − 2.
const POLE: f64 = -0.267_949_192_431_122_7;

/// Spline coefficients of one image, row-major like the image.
#[derive(Clone, Debug)]
pub struct BSplineImage {
    pub width: usize,
    pub height: usize,
    coefficients: Vec<f64>,
}

/// The four cubic B-spline weights of nodes `i-1 … i+2` at fraction `t` of
/// the way from node `i` to `i+1`.
#[inline(always)]
pub fn weights(t: f64) -> [f64; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    let s = 1.0 - t;
    [
        s * s * s / 6.0,
        (4.0 - 6.0 * t2 + 3.0 * t3) / 6.0,
        (1.0 + 3.0 * t + 3.0 * t2 - 3.0 * t3) / 6.0,
        t3 / 6.0,
    ]
}

impl BSplineImage {
    /// Prefilters `image` (rows, then columns).
    pub fn new(image: &GrayImage) -> Self {
        let (width, height) = (image.width, image.height);
        let mut coefficients = image.pixels.clone();
        for row in coefficients.chunks_exact_mut(width) {
            prefilter_line(row);
        }
        let mut column = vec![0.0; height];
        for x in 0..width {
            for (y, c) in column.iter_mut().enumerate() {
                *c = coefficients[y * width + x];
            }
            prefilter_line(&mut column);
            for (y, c) in column.iter().enumerate() {
                coefficients[y * width + x] = *c;
            }
        }
        Self {
            width,
            height,
            coefficients,
        }
    }

    /// Whether the 4 × 4 support of every point in the box
    /// `[x_min, x_max] × [y_min, y_max]` lies inside the image.
    #[inline]
    pub fn contains_box(&self, x_min: f64, x_max: f64, y_min: f64, y_max: f64) -> bool {
        x_min >= 1.0
            && y_min >= 1.0
            && x_max < (self.width as f64) - 2.0
            && y_max < (self.height as f64) - 2.0
    }

    /// The spline at `(x, y)`; the caller guarantees `contains_box` for it.
    #[inline(always)]
    pub fn value(&self, x: f64, y: f64) -> f64 {
        let xf = x.floor();
        let yf = y.floor();
        let wx = weights(x - xf);
        let wy = weights(y - yf);
        let base = (yf as usize - 1) * self.width + xf as usize - 1;
        let mut sum = 0.0;
        for (j, wyj) in wy.iter().enumerate() {
            let start = base + j * self.width;
            let row = &self.coefficients[start..start + 4];
            sum += wyj * (row[0] * wx[0] + row[1] * wx[1] + row[2] * wx[2] + row[3] * wx[3]);
        }
        sum
    }

    /// The spline's gradient (d/dx, d/dy) at pixel centre `(x, y)`, which
    /// must lie one pixel inside the border.
    #[inline]
    pub fn gradient_at_node(&self, x: usize, y: usize) -> (f64, f64) {
        let w = self.width;
        let c = |xx: usize, yy: usize| self.coefficients[yy * w + xx];
        // At a node the weights are (1, 4, 1)/6 and the derivative weights
        // (-1, 0, 1)/2.
        let dx = |yy: usize| (c(x + 1, yy) - c(x - 1, yy)) * 0.5;
        let dy = |xx: usize| (c(xx, y + 1) - c(xx, y - 1)) * 0.5;
        let gx = (dx(y - 1) + 4.0 * dx(y) + dx(y + 1)) / 6.0;
        let gy = (dy(x - 1) + 4.0 * dy(x) + dy(x + 1)) / 6.0;
        (gx, gy)
    }
}

/// In-place cubic B-spline prefilter of one line with mirror boundaries.
fn prefilter_line(line: &mut [f64]) {
    let n = line.len();
    if n < 2 {
        return;
    }
    let z = POLE;
    let gain = (1.0 - z) * (1.0 - 1.0 / z);
    for v in line.iter_mut() {
        *v *= gain;
    }
    // Causal initialisation: the mirrored sum truncated where z^k < 1e-12.
    let horizon = ((1e-12_f64).ln() / z.abs().ln()).ceil() as usize;
    let mut zk = z;
    let mut sum = line[0];
    if horizon < n {
        for v in &line[1..horizon] {
            sum += zk * v;
            zk *= z;
        }
    } else {
        // Full mirror-symmetric sum for short lines.
        let iz = 1.0 / z;
        let mut z2n = z.powi(n as i32 - 1);
        sum = line[0] + z2n * line[n - 1];
        z2n = z2n * z2n * iz;
        for v in &line[1..n - 1] {
            sum += (zk + z2n) * v;
            zk *= z;
            z2n *= iz;
        }
        sum /= 1.0 - zk * zk;
    }
    line[0] = sum;
    for k in 1..n {
        line[k] += z * line[k - 1];
    }
    line[n - 1] = (z / (z * z - 1.0)) * (z * line[n - 2] + line[n - 1]);
    for k in (0..n - 1).rev() {
        line[k] = z * (line[k + 1] - line[k]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: usize, height: usize, f: impl Fn(f64, f64) -> f64) -> GrayImage {
        let mut pixels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x as f64, y as f64));
            }
        }
        GrayImage::new(width, height, pixels).unwrap()
    }

    #[test]
    fn interpolates_pixel_values_exactly() {
        let img = image(23, 17, |x, y| {
            (0.37 * x).sin() * (0.21 * y).cos() + 0.01 * x * y
        });
        let spline = BSplineImage::new(&img);
        for y in 1..15 {
            for x in 1..20 {
                let v = spline.value(x as f64, y as f64);
                assert!((v - img.pixels[y * 23 + x]).abs() < 1e-10, "{x},{y}");
            }
        }
    }

    #[test]
    fn reproduces_cubic_polynomials_and_their_gradient() {
        // Cubic B-splines reproduce polynomials up to degree 3 away from the
        // border, where the mirror boundary no longer matters.
        let p = |x: f64, y: f64| 0.001 * x * x * x - 0.02 * x * y + 0.3 * y * y + x;
        let img = image(80, 70, p);
        let spline = BSplineImage::new(&img);
        for &(x, y) in &[(40.3, 35.7), (38.91, 30.05), (41.5, 33.5)] {
            assert!((spline.value(x, y) - p(x, y)).abs() < 1e-6, "{x},{y}");
        }
        let (gx, gy) = spline.gradient_at_node(40, 35);
        let (ex, ey) = (
            0.003 * 1600.0 - 0.02 * 35.0 + 1.0,
            -0.02 * 40.0 + 0.6 * 35.0,
        );
        assert!(
            (gx - ex).abs() < 1e-6 && (gy - ey).abs() < 1e-6,
            "{gx} {gy}"
        );
    }
}
