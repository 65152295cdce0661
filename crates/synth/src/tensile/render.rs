//! Analytic rendering of a deformed speckle image.
//!
//! A pixel's value is the mean of the pattern over the pixel's area (s × s
//! sub-samples), each sub-sample evaluated at its reference coordinate
//! X = c + (x − c − t)/λ: no image is ever interpolated, so the deformation
//! of every frame is known exactly. Because the homogeneous tests load along
//! the image axes the map is separable, which lets each Gaussian blob be
//! splatted as an outer product of two 1-D profiles instead of evaluating
//! every blob at every sub-sample.

use rayon::prelude::*;

use super::speckle::{CUTOFF_RADII, SpecklePattern};

/// x = c + λ (X − c) + t along each image axis (x = column, y = row).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisMap {
    pub centre: [f64; 2],
    pub stretch: [f64; 2],
    pub shift: [f64; 2],
}

impl AxisMap {
    /// The identity map about `centre`.
    pub fn identity(centre: [f64; 2]) -> Self {
        Self {
            centre,
            stretch: [1.0, 1.0],
            shift: [0.0, 0.0],
        }
    }

    /// Reference coordinate of image coordinate `x` along `axis`.
    #[inline]
    pub fn to_reference(&self, axis: usize, x: f64) -> f64 {
        self.centre[axis] + (x - self.centre[axis] - self.shift[axis]) / self.stretch[axis]
    }

    /// Image coordinate of reference coordinate `x` along `axis`.
    #[inline]
    pub fn to_image(&self, axis: usize, x: f64) -> f64 {
        self.centre[axis] + self.stretch[axis] * (x - self.centre[axis]) + self.shift[axis]
    }
}

/// Renders `width × height` pixels (row-major, 0 … 1 of full scale) with
/// `supersample²` sub-samples per pixel.
pub fn render(
    pattern: &SpecklePattern,
    map: &AxisMap,
    width: usize,
    height: usize,
    supersample: usize,
) -> Vec<f64> {
    const STRIP_ROWS: usize = 8;
    let s = supersample.max(1);
    let mut pixels = vec![0.0; width * height];
    pixels
        .par_chunks_mut(STRIP_ROWS * width)
        .enumerate()
        .for_each(|(strip, out)| {
            let row0 = strip * STRIP_ROWS;
            let rows = out.len() / width;
            render_strip(pattern, map, width, row0, rows, s, out);
        });
    pixels
}

/// Coordinate of sub-sample `k` (pixel centres at integers).
#[inline]
fn sub_coordinate(k: usize, s: usize) -> f64 {
    (k as f64 + 0.5) / s as f64 - 0.5
}

fn render_strip(
    pattern: &SpecklePattern,
    map: &AxisMap,
    width: usize,
    row0: usize,
    rows: usize,
    s: usize,
    out: &mut [f64],
) {
    let (nsx, nsy) = (width * s, rows * s);
    let ky0 = row0 * s;
    // Reference coordinates of the sub-sample grid: affine in the index.
    let x_ref0 = map.to_reference(0, sub_coordinate(0, s));
    let dx_ref = 1.0 / (s as f64 * map.stretch[0]);
    let y_ref0 = map.to_reference(1, sub_coordinate(ky0, s));
    let dy_ref = 1.0 / (s as f64 * map.stretch[1]);
    let y_ref_end = y_ref0 + dy_ref * (nsy as f64 - 1.0);

    let mut density = vec![0.0; nsx * nsy];
    let mut profile_x = Vec::new();
    let mut profile_y = Vec::new();
    let reach = CUTOFF_RADII * pattern.max_radius;
    for sp in pattern.speckles_in_rows(y_ref0.min(y_ref_end) - reach, y_ref0.max(y_ref_end) + reach)
    {
        let cut = CUTOFF_RADII * sp.radius;
        let Some((ix0, ix1)) = index_range(sp.x - cut, sp.x + cut, x_ref0, dx_ref, nsx) else {
            continue;
        };
        let Some((iy0, iy1)) = index_range(sp.y - cut, sp.y + cut, y_ref0, dy_ref, nsy) else {
            continue;
        };
        let inv_r2 = 1.0 / (sp.radius * sp.radius);
        profile_x.clear();
        profile_x.extend((ix0..ix1).map(|i| {
            let d = x_ref0 + dx_ref * i as f64 - sp.x;
            (-d * d * inv_r2).exp()
        }));
        profile_y.clear();
        profile_y.extend((iy0..iy1).map(|j| {
            let d = y_ref0 + dy_ref * j as f64 - sp.y;
            sp.density * (-d * d * inv_r2).exp()
        }));
        for (j, wy) in (iy0..iy1).zip(&profile_y) {
            let row = &mut density[j * nsx + ix0..j * nsx + ix1];
            for (cell, wx) in row.iter_mut().zip(&profile_x) {
                *cell += wy * wx;
            }
        }
    }

    let norm = 1.0 / (s * s) as f64;
    for r in 0..rows {
        for c in 0..width {
            let mut sum = 0.0;
            for j in r * s..(r + 1) * s {
                let y_ref = y_ref0 + dy_ref * j as f64;
                for i in c * s..(c + 1) * s {
                    let x_ref = x_ref0 + dx_ref * i as f64;
                    sum += pattern.intensity(density[j * nsx + i], x_ref, y_ref);
                }
            }
            out[r * width + c] = sum * norm;
        }
    }
}

/// Sub-sample indices `[i0, i1)` whose coordinate `start + step·i` lies in
/// `[lo, hi]`, clipped to `[0, n)`.
fn index_range(lo: f64, hi: f64, start: f64, step: f64, n: usize) -> Option<(usize, usize)> {
    let first = ((lo - start) / step).ceil().max(0.0);
    let last = ((hi - start) / step).floor().min(n as f64 - 1.0);
    if last < first {
        return None;
    }
    Some((first as usize, last as usize + 1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensile::speckle::Marker;

    #[test]
    fn splatting_matches_direct_evaluation_of_the_pattern() {
        let pattern = SpecklePattern::random(
            [-20.0, -20.0, 80.0, 80.0],
            2.5,
            0.5,
            vec![Marker {
                x: 30.0,
                y: 28.0,
                radius: 5.0,
            }],
            7,
        );
        let map = AxisMap {
            centre: [32.0, 24.0],
            stretch: [1.7, 0.8],
            shift: [0.3, -0.2],
        };
        let s = 3;
        let image = render(&pattern, &map, 64, 48, s);
        for &(c, r) in &[(10usize, 7usize), (33, 20), (50, 40), (31, 24)] {
            let mut expected = 0.0;
            for j in 0..s {
                for i in 0..s {
                    let x = c as f64 + sub_coordinate(i, s);
                    let y = r as f64 + sub_coordinate(j, s);
                    expected += pattern.value(map.to_reference(0, x), map.to_reference(1, y));
                }
            }
            expected /= (s * s) as f64;
            assert!((image[r * 64 + c] - expected).abs() < 1e-12, "{c},{r}");
        }
        // The pattern has contrast: speckles, white coat and a marker.
        let min = image.iter().cloned().fold(1.0, f64::min);
        let max = image.iter().cloned().fold(0.0, f64::max);
        assert!(min < 0.1 && max > 0.7, "{min} {max}");
    }
}
