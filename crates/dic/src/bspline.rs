//! Bicubic B-spline interpolation of an image, the interpolant of the
//! deformed image in IC-GN.
//!
//! Coefficients come from the recursive prefilter of Unser, Aldroubi & Eden
//! (IEEE Trans. Signal Process. 41, 1993) with the mirror boundary and causal
//! initialisation of Thévenaz, Blu & Unser ("Interpolation revisited", IEEE
//! TMI 19, 2000), so the spline passes exactly through every pixel value.
//! Pixel centres sit at integer coordinates; `x` is the column, `y` the row.

use rayon::prelude::*;

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
/// the way from node `i` to `i+1`: (1 − t)³/6, (4 − 6t² + 3t³)/6,
/// (1 + 3t + 3t² − 3t³)/6 and t³/6, written with multiplications only since
/// this runs twice per warped point.
#[inline(always)]
pub fn weights(t: f64) -> [f64; 4] {
    const SIXTH: f64 = 1.0 / 6.0;
    let t2 = t * t;
    let t3 = t2 * t;
    let s = 1.0 - t;
    [
        s * s * s * SIXTH,
        (2.0 / 3.0) - t2 + 0.5 * t3,
        SIXTH + 0.5 * (t + t2 - t3),
        t3 * SIXTH,
    ]
}

/// Points per block of `BSplineImage::values_on_grid`: their nodes and
/// weights are computed first, together.
const BLOCK: usize = 16;

/// Points interpolated side by side, one per lane of a 256-bit vector.
const LANES: usize = 4;

/// Adding and removing 1.5 · 2⁵² rounds to an integer (round to nearest,
/// the only mode Rust code runs in), and the integer sits in the low bits.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// A position `p` ≥ 1 as node `i` and fraction `t = p − i` ∈ [0, 1]: `i` is
/// ⌊p⌋, or ⌊p⌋ − 1 when p is an integer (then t = 1, which the spline
/// weights treat as well as t = 0). Float arithmetic only, unlike `floor`
/// (a library call on baseline x86-64) or a saturating `as` cast, so a loop
/// of it vectorises.
#[inline(always)]
fn split(p: f64) -> (u64, f64) {
    let shifted = (p - 0.5) + ROUND;
    let node = shifted - ROUND;
    (shifted.to_bits() & 0xffff_ffff, p - node)
}

impl BSplineImage {
    /// Prefilters `image`: rows in parallel, then all columns together.
    pub fn new(image: &GrayImage) -> Self {
        let (width, height) = (image.width, image.height);
        let mut coefficients = image.pixels.clone();
        coefficients
            .par_chunks_exact_mut(width)
            .for_each(prefilter_line);
        prefilter_columns(&mut coefficients, width, height);
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
        // Truncation is the floor here since `contains_box` keeps x, y ≥ 1,
        // and `f64::floor` is a library call on baseline x86-64.
        let xi = x as usize;
        let yi = y as usize;
        let wx = weights(x - xi as f64);
        let wy = weights(y - yi as f64);
        let w = self.width;
        let base = (yi - 1) * w + xi - 1;
        // One slice for the whole 4 × 4 support: the row reads below are
        // then checked against its length only.
        let support = &self.coefficients[base..base + 3 * w + 4];
        let row = |j: usize| -> f64 {
            let r = &support[j * w..j * w + 4];
            r[0] * wx[0] + r[1] * wx[1] + r[2] * wx[2] + r[3] * wx[3]
        };
        wy[0] * row(0) + wy[1] * row(1) + wy[2] * row(2) + wy[3] * row(3)
    }

    /// The spline on an affine grid of points, row by row into `out`
    /// (`columns` per row): point (r, c) = origin + c·step_column + r·step_row.
    /// The caller guarantees `contains_box` for the grid's corners with a
    /// margin of 1e-6 px. Equal to `value` at each point up to rounding;
    /// done in blocks along a row: first the nodes and weights of a block's
    /// points, in a loop the compiler vectorises, then the coefficient reads.
    /// Always inlined: IC-GN calls it from code compiled for a wider
    /// instruction set (`vector_isa`), which then covers it too.
    #[inline(always)]
    pub fn values_on_grid(
        &self,
        origin: (f64, f64),
        step_column: (f64, f64),
        step_row: (f64, f64),
        columns: usize,
        out: &mut [f64],
    ) {
        let mut node_x = [0u64; BLOCK];
        let mut node_y = [0u64; BLOCK];
        let mut wx = [[0.0; BLOCK]; 4];
        let mut wy = [[0.0; BLOCK]; 4];
        for (r, out_row) in out.chunks_exact_mut(columns).enumerate() {
            let x = origin.0 + r as f64 * step_row.0;
            let y = origin.1 + r as f64 * step_row.1;
            let mut first = 0.0;
            for out_block in out_row.chunks_mut(BLOCK) {
                for k in 0..BLOCK {
                    let c = first + k as f64;
                    let (nx, tx) = split(x + c * step_column.0);
                    let (ny, ty) = split(y + c * step_column.1);
                    node_x[k] = nx;
                    node_y[k] = ny;
                    let (ax, ay) = (weights(tx), weights(ty));
                    for j in 0..4 {
                        wx[j][k] = ax[j];
                        wy[j][k] = ay[j];
                    }
                }
                let valid = out_block.len();
                for (lanes, out_lanes) in out_block.chunks_mut(LANES).enumerate() {
                    let values = self.lane_values(&node_x, &node_y, &wx, &wy, lanes * LANES, valid);
                    // A fixed-size copy where the row allows it: a copy of
                    // variable length is a call to memmove.
                    match <&mut [f64; LANES]>::try_from(&mut *out_lanes) {
                        Ok(full) => *full = values,
                        Err(_) => out_lanes.copy_from_slice(&values[..out_lanes.len()]),
                    }
                }
                first += BLOCK as f64;
            }
        }
    }

    /// The spline at the `LANES` points `first …` of a block of
    /// `values_on_grid` from their nodes and weights, `value`'s operations
    /// in `value`'s order for each point. Written lane by lane (the points
    /// side by side, as in the weight arrays) so that the compiler keeps
    /// the points in the lanes of one vector instead of summing each
    /// point's products across a vector. Points at or past `valid` (the end
    /// of a row) read the support of the last valid point, which is inside
    /// the image, and are discarded by the caller.
    #[inline(always)]
    fn lane_values(
        &self,
        node_x: &[u64; BLOCK],
        node_y: &[u64; BLOCK],
        wx: &[[f64; BLOCK]; 4],
        wy: &[[f64; BLOCK]; 4],
        first: usize,
        valid: usize,
    ) -> [f64; LANES] {
        let w = self.width;
        let mut supports = [[[0.0; 4]; LANES]; 4];
        for lane in 0..LANES {
            let k = (first + lane).min(valid - 1);
            let b = (node_y[k] as usize - 1) * w + node_x[k] as usize - 1;
            let support = &self.coefficients[b..b + 3 * w + 4];
            for (j, rows) in supports.iter_mut().enumerate() {
                rows[lane].copy_from_slice(&support[j * w..j * w + 4]);
            }
        }
        let mut sums = [0.0; LANES];
        for (j, rows) in supports.iter().enumerate() {
            for (lane, (sum, r)) in sums.iter_mut().zip(rows).enumerate() {
                let k = first + lane;
                let row = r[0] * wx[0][k] + r[1] * wx[1][k] + r[2] * wx[2][k] + r[3] * wx[3][k];
                // j = 0 starts the sum: 0 + x would turn −0 into +0.
                *sum = if j == 0 {
                    wy[0][k] * row
                } else {
                    *sum + wy[j][k] * row
                };
            }
        }
        sums
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

    /// `gradient_at_node` at every pixel centre, row-major like the image:
    /// (d/dx image, d/dy image), zero on the one-pixel border where the node
    /// stencil has no neighbours. Rows are computed in parallel.
    pub fn node_gradients(&self) -> (Vec<f64>, Vec<f64>) {
        let (w, h) = (self.width, self.height);
        let mut gradient_x = vec![0.0; w * h];
        let mut gradient_y = vec![0.0; w * h];
        if w < 3 || h < 3 {
            return (gradient_x, gradient_y);
        }
        let c = &self.coefficients;
        gradient_x
            .par_chunks_exact_mut(w)
            .zip(gradient_y.par_chunks_exact_mut(w))
            .enumerate()
            .filter(|(y, _)| *y >= 1 && *y + 1 < h)
            .for_each(|(y, (gx_row, gy_row))| {
                let above = &c[(y - 1) * w..y * w];
                let here = &c[y * w..(y + 1) * w];
                let below = &c[(y + 1) * w..(y + 2) * w];
                // The stencils of `gradient_at_node`, in the same order of
                // operations, so both give identical numbers.
                let dx = |r: &[f64], x: usize| (r[x + 1] - r[x - 1]) * 0.5;
                let dy = |x: usize| (below[x] - above[x]) * 0.5;
                for x in 1..w - 1 {
                    gx_row[x] = (dx(above, x) + 4.0 * dx(here, x) + dx(below, x)) / 6.0;
                    gy_row[x] = (dy(x - 1) + 4.0 * dy(x) + dy(x + 1)) / 6.0;
                }
            });
        (gradient_x, gradient_y)
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

/// `prefilter_line` applied to every column of a row-major `width × height`
/// array at once: each step of the recursion updates a whole row, so memory
/// is read in order instead of with a stride of one row per element.
fn prefilter_columns(c: &mut [f64], width: usize, height: usize) {
    let n = height;
    if n < 2 {
        return;
    }
    let z = POLE;
    let gain = (1.0 - z) * (1.0 - 1.0 / z);
    for v in c.iter_mut() {
        *v *= gain;
    }
    let row = |k: usize| k * width..(k + 1) * width;
    let horizon = ((1e-12_f64).ln() / z.abs().ln()).ceil() as usize;
    let mut first = c[row(0)].to_vec();
    if horizon < n {
        let mut zk = z;
        for k in 1..horizon {
            for (s, v) in first.iter_mut().zip(&c[row(k)]) {
                *s += zk * v;
            }
            zk *= z;
        }
    } else {
        let iz = 1.0 / z;
        let mut zk = z;
        let mut z2n = z.powi(n as i32 - 1);
        for (s, v) in first.iter_mut().zip(&c[row(n - 1)]) {
            *s += z2n * v;
        }
        z2n = z2n * z2n * iz;
        for k in 1..n - 1 {
            for (s, v) in first.iter_mut().zip(&c[row(k)]) {
                *s += (zk + z2n) * v;
            }
            zk *= z;
            z2n *= iz;
        }
        for s in first.iter_mut() {
            *s /= 1.0 - zk * zk;
        }
    }
    c[row(0)].copy_from_slice(&first);
    for k in 1..n {
        let (done, rest) = c.split_at_mut(k * width);
        for (v, p) in rest[..width].iter_mut().zip(&done[row(k - 1)]) {
            *v += z * p;
        }
    }
    let (done, last) = c.split_at_mut((n - 1) * width);
    for (v, p) in last.iter_mut().zip(&done[row(n - 2)]) {
        *v = (z / (z * z - 1.0)) * (z * p + *v);
    }
    for k in (0..n - 1).rev() {
        let (head, tail) = c.split_at_mut((k + 1) * width);
        for (v, q) in head[row(k)].iter_mut().zip(&tail[..width]) {
            *v = z * (q - *v);
        }
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

    #[test]
    fn gradient_images_and_grid_values_match_the_pointwise_forms() {
        let img = image(40, 33, |x, y| {
            (0.41 * x).sin() * (0.27 * y).cos() + 0.02 * x
        });
        let spline = BSplineImage::new(&img);
        let (gx, gy) = spline.node_gradients();
        for y in 1..32 {
            for x in 1..39 {
                let (ex, ey) = spline.gradient_at_node(x, y);
                assert_eq!((gx[y * 40 + x], gy[y * 40 + x]), (ex, ey), "{x},{y}");
            }
        }
        // A sheared, stretched 21 × 3 grid whose rows cross a block edge,
        // including points that land exactly on nodes (t = 0 or 1).
        let (origin, step_column, step_row) = ((3.0, 4.0), (1.25, 0.125), (0.5, 7.0));
        let mut out = vec![0.0; 21 * 3];
        spline.values_on_grid(origin, step_column, step_row, 21, &mut out);
        for (k, v) in out.iter().enumerate() {
            let (r, c) = ((k / 21) as f64, (k % 21) as f64);
            let x = origin.0 + c * step_column.0 + r * step_row.0;
            let y = origin.1 + c * step_column.1 + r * step_row.1;
            assert!((v - spline.value(x, y)).abs() < 1e-12, "{x},{y}");
        }
    }

    #[test]
    fn grid_rows_ending_at_the_border_read_no_further() {
        // 19 columns (a block of 16 and a partial one of 3) whose last point
        // is the last the support allows (x, y < size − 2), 1.9 px apart:
        // on the last row, the unused lanes of the partial block lie past
        // the image's last pixel, where a read would go out of bounds.
        let img = image(40, 12, |x, y| (0.3 * x).cos() + 0.1 * y);
        let spline = BSplineImage::new(&img);
        let (origin, step_column, step_row) = ((37.99 - 18.0 * 1.9, 6.99), (1.9, 0.0), (0.0, 3.0));
        let mut out = vec![0.0; 19 * 2];
        spline.values_on_grid(origin, step_column, step_row, 19, &mut out);
        for (k, v) in out.iter().enumerate() {
            let (r, c) = ((k / 19) as f64, (k % 19) as f64);
            let (x, y) = (origin.0 + c * step_column.0, origin.1 + r * step_row.1);
            assert!((v - spline.value(x, y)).abs() < 1e-12, "{x},{y}");
        }
    }
}
