//! Inverse-compositional Gauss–Newton (IC-GN) subset matching with a
//! first-order (affine) shape function and the ZNSSD criterion.
//!
//! Algorithm of Pan, Li & Tong, "Fast, robust and accurate digital image
//! correlation calculation without redundant computations", Exp. Mech. 53
//! (2013): the Hessian is built once from the reference subset; each
//! iteration interpolates the deformed image (bicubic B-spline) at the warped
//! points and updates W(p) ← W(p) ∘ W(Δp)⁻¹.

use crate::bspline::BSplineImage;
use crate::gray::GrayImage;

/// First-order shape function: a reference offset (dx, dy) maps to
/// (dx + u + ux·dx + uy·dy, dy + v + vx·dx + vy·dy).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Warp {
    pub u: f64,
    pub ux: f64,
    pub uy: f64,
    pub v: f64,
    pub vx: f64,
    pub vy: f64,
}

impl Warp {
    /// A pure translation.
    pub fn translation(u: f64, v: f64) -> Self {
        Self {
            u,
            v,
            ..Self::default()
        }
    }

    /// The warp with translation `(u, v)` and local gradient `a` (∂x/∂X).
    pub fn from_gradient(u: f64, v: f64, a: [[f64; 2]; 2]) -> Self {
        Self {
            u,
            ux: a[0][0] - 1.0,
            uy: a[0][1],
            v,
            vx: a[1][0],
            vy: a[1][1] - 1.0,
        }
    }

    /// ∂x/∂X of the warp.
    pub fn gradient(&self) -> [[f64; 2]; 2] {
        [[1.0 + self.ux, self.uy], [self.vx, 1.0 + self.vy]]
    }

    fn matrix(&self) -> [[f64; 3]; 3] {
        [
            [1.0 + self.ux, self.uy, self.u],
            [self.vx, 1.0 + self.vy, self.v],
            [0.0, 0.0, 1.0],
        ]
    }

    fn from_matrix(m: &[[f64; 3]; 3]) -> Self {
        Self {
            u: m[0][2],
            ux: m[0][0] - 1.0,
            uy: m[0][1],
            v: m[1][2],
            vx: m[1][0],
            vy: m[1][1] - 1.0,
        }
    }

    /// W(self) ∘ W(increment)⁻¹, the inverse-compositional update; None if
    /// the increment is singular.
    pub fn compose_inverse(&self, increment: &Warp) -> Option<Warp> {
        let d = increment.matrix();
        let det = d[0][0] * d[1][1] - d[0][1] * d[1][0];
        if det.abs() < 1e-12 || !det.is_finite() {
            return None;
        }
        let inv_a = [
            [d[1][1] / det, -d[0][1] / det],
            [-d[1][0] / det, d[0][0] / det],
        ];
        let inv_t = [
            -(inv_a[0][0] * d[0][2] + inv_a[0][1] * d[1][2]),
            -(inv_a[1][0] * d[0][2] + inv_a[1][1] * d[1][2]),
        ];
        let inv = [
            [inv_a[0][0], inv_a[0][1], inv_t[0]],
            [inv_a[1][0], inv_a[1][1], inv_t[1]],
            [0.0, 0.0, 1.0],
        ];
        let w = self.matrix();
        let mut out = [[0.0; 3]; 3];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                *cell = (0..3).map(|k| w[i][k] * inv[k][j]).sum();
            }
        }
        Some(Warp::from_matrix(&out))
    }

    /// The image of reference offset (dx, dy), relative to the subset centre.
    #[inline]
    pub fn apply(&self, dx: f64, dy: f64) -> (f64, f64) {
        (
            dx + self.u + self.ux * dx + self.uy * dy,
            dy + self.v + self.vx * dx + self.vy * dy,
        )
    }
}

/// Iteration controls of IC-GN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IcgnSettings {
    /// Subset side, pixels (odd).
    pub subset_px: usize,
    pub max_iterations: usize,
    /// Converged when the increment moves no subset corner by more than
    /// about this many pixels (norm of Δu, Δv and the gradient terms × half).
    pub convergence_px: f64,
}

/// The outcome of matching one subset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Match {
    pub warp: Warp,
    /// Zero-normalised cross-correlation at the final warp, −1 … 1.
    pub zncc: f64,
    pub iterations: usize,
    pub converged: bool,
}

/// A reference subset with everything IC-GN precomputes from it.
#[derive(Clone, Debug)]
pub struct ReferenceSubset {
    pub x0: usize,
    pub y0: usize,
    half: usize,
    /// Per point: f̃ = (f − f̄)/‖f − f̄‖, then the six steepest-descent terms
    /// J̃ = ∇f̃ · ∂W/∂p.
    points: Vec<[f64; 7]>,
    sum_j_f: [f64; 6],
    sum_j: [f64; 6],
    /// Cholesky factor of the Gauss–Newton Hessian Σ J̃ᵀ J̃.
    hessian_chol: [[f64; 6]; 6],
}

impl ReferenceSubset {
    /// The subset of side `2 half + 1` centred on pixel `(x0, y0)`; None if
    /// it does not fit inside the image (with the gradient's one-pixel
    /// margin) or holds no texture.
    pub fn new(
        image: &GrayImage,
        spline: &BSplineImage,
        x0: usize,
        y0: usize,
        half: usize,
    ) -> Option<Self> {
        if x0 < half + 1
            || y0 < half + 1
            || x0 + half + 1 >= image.width
            || y0 + half + 1 >= image.height
        {
            return None;
        }
        let side = 2 * half + 1;
        let n = (side * side) as f64;
        let mut mean = 0.0;
        for y in y0 - half..=y0 + half {
            mean += image.pixels[y * image.width + x0 - half..=y * image.width + x0 + half]
                .iter()
                .sum::<f64>();
        }
        mean /= n;
        let mut ss = 0.0;
        for y in y0 - half..=y0 + half {
            for x in x0 - half..=x0 + half {
                let d = image.get(x, y) - mean;
                ss += d * d;
            }
        }
        let norm = ss.sqrt();
        if norm.is_nan() || norm <= 1e-9 {
            return None;
        }
        let mut points = Vec::with_capacity(side * side);
        let mut hessian = [[0.0; 6]; 6];
        let mut sum_j_f = [0.0; 6];
        let mut sum_j = [0.0; 6];
        for y in y0 - half..=y0 + half {
            let dy = y as f64 - y0 as f64;
            for x in x0 - half..=x0 + half {
                let dx = x as f64 - x0 as f64;
                let f = (image.get(x, y) - mean) / norm;
                let (gx, gy) = spline.gradient_at_node(x, y);
                let (gx, gy) = (gx / norm, gy / norm);
                let j = [gx, gx * dx, gx * dy, gy, gy * dx, gy * dy];
                for a in 0..6 {
                    sum_j_f[a] += j[a] * f;
                    sum_j[a] += j[a];
                    for b in 0..=a {
                        hessian[a][b] += j[a] * j[b];
                    }
                }
                points.push([f, j[0], j[1], j[2], j[3], j[4], j[5]]);
            }
        }
        let hessian_chol = cholesky(&hessian)?;
        Some(Self {
            x0,
            y0,
            half,
            points,
            sum_j_f,
            sum_j,
            hessian_chol,
        })
    }

    pub fn half(&self) -> usize {
        self.half
    }

    /// Whether the warped subset's interpolation support stays in `target`.
    fn fits(&self, target: &BSplineImage, warp: &Warp) -> bool {
        let h = self.half as f64;
        let (mut x_min, mut x_max, mut y_min, mut y_max) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for (dx, dy) in [(-h, -h), (h, -h), (-h, h), (h, h)] {
            let (x, y) = warp.apply(dx, dy);
            x_min = x_min.min(x);
            x_max = x_max.max(x);
            y_min = y_min.min(y);
            y_max = y_max.max(y);
        }
        let (cx, cy) = (self.x0 as f64, self.y0 as f64);
        x_min.is_finite()
            && y_min.is_finite()
            && target.contains_box(cx + x_min, cx + x_max, cy + y_min, cy + y_max)
    }

    /// Refines `guess` by IC-GN against the deformed image `target`.
    pub fn solve(&self, target: &BSplineImage, guess: Warp, settings: &IcgnSettings) -> Match {
        let mut warp = guess;
        let mut zncc = f64::NAN;
        let h = self.half as f64;
        let side = 2 * self.half + 1;
        let n = (side * side) as f64;
        for iteration in 1..=settings.max_iterations {
            if !self.fits(target, &warp) {
                return failed(warp, iteration);
            }
            // One pass: Σg, Σg², Σf̃g and Σ J̃ g.
            let mut sums = [0.0; 9];
            let step_x = (1.0 + warp.ux, warp.vx);
            for row in 0..side {
                let dy = row as f64 - h;
                let (ox, oy) = warp.apply(-h, dy);
                let mut x = self.x0 as f64 + ox;
                let mut y = self.y0 as f64 + oy;
                let points = &self.points[row * side..(row + 1) * side];
                for p in points {
                    let g = target.value(x, y);
                    sums[0] += g;
                    sums[1] += g * g;
                    sums[2] += p[0] * g;
                    sums[3] += p[1] * g;
                    sums[4] += p[2] * g;
                    sums[5] += p[3] * g;
                    sums[6] += p[4] * g;
                    sums[7] += p[5] * g;
                    sums[8] += p[6] * g;
                    x += step_x.0;
                    y += step_x.1;
                }
            }
            let g_mean = sums[0] / n;
            let g_ss = sums[1] - n * g_mean * g_mean;
            if g_ss.is_nan() || g_ss <= 1e-18 {
                return failed(warp, iteration);
            }
            let g_norm = g_ss.sqrt();
            zncc = sums[2] / g_norm;
            let mut b = [0.0; 6];
            for a in 0..6 {
                b[a] = self.sum_j_f[a] - (sums[3 + a] - g_mean * self.sum_j[a]) / g_norm;
            }
            let d = cholesky_solve(&self.hessian_chol, &b);
            let increment = Warp {
                u: -d[0],
                ux: -d[1],
                uy: -d[2],
                v: -d[3],
                vx: -d[4],
                vy: -d[5],
            };
            let Some(next) = warp.compose_inverse(&increment) else {
                return failed(warp, iteration);
            };
            warp = next;
            let size = (d[0] * d[0]
                + d[3] * d[3]
                + h * h * (d[1] * d[1] + d[2] * d[2] + d[4] * d[4] + d[5] * d[5]))
                .sqrt();
            if !size.is_finite() {
                return failed(warp, iteration);
            }
            if size < settings.convergence_px {
                return Match {
                    warp,
                    zncc,
                    iterations: iteration,
                    converged: true,
                };
            }
        }
        Match {
            warp,
            zncc,
            iterations: settings.max_iterations,
            converged: false,
        }
    }
}

fn failed(warp: Warp, iterations: usize) -> Match {
    Match {
        warp,
        zncc: f64::NAN,
        iterations,
        converged: false,
    }
}

/// Lower Cholesky factor of a symmetric positive-definite 6 × 6 matrix whose
/// lower triangle is filled; None if it is not positive definite.
fn cholesky(a: &[[f64; 6]; 6]) -> Option<[[f64; 6]; 6]> {
    let mut l = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..=i {
            let mut s = a[i][j];
            for (lik, ljk) in l[i][..j].iter().zip(&l[j][..j]) {
                s -= lik * ljk;
            }
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    Some(l)
}

fn cholesky_solve(l: &[[f64; 6]; 6], b: &[f64; 6]) -> [f64; 6] {
    let mut y = [0.0; 6];
    for i in 0..6 {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i][k] * y[k];
        }
        y[i] = s / l[i][i];
    }
    let mut x = [0.0; 6];
    for i in (0..6).rev() {
        let mut s = y[i];
        for k in i + 1..6 {
            s -= l[k][i] * x[k];
        }
        x[i] = s / l[i][i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_composition_undoes_a_warp() {
        let w = Warp {
            u: 1.5,
            ux: 0.1,
            uy: -0.05,
            v: -2.0,
            vx: 0.02,
            vy: 0.3,
        };
        let id = w.compose_inverse(&w).unwrap();
        for value in [id.u, id.ux, id.uy, id.v, id.vx, id.vy] {
            assert!(value.abs() < 1e-12);
        }
    }

    #[test]
    fn cholesky_solves_a_spd_system() {
        let a: [[f64; 6]; 6] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                1.0 / (1.0 + (i as f64 - j as f64).abs()) + if i == j { 2.0 } else { 0.0 }
            })
        });
        let x_true = [1.0, -2.0, 0.5, 3.0, -1.0, 0.25];
        let mut b = [0.0; 6];
        for i in 0..6 {
            b[i] = (0..6).map(|j| a[i][j] * x_true[j]).sum();
        }
        let x = cholesky_solve(&cholesky(&a).unwrap(), &b);
        for i in 0..6 {
            assert!((x[i] - x_true[i]).abs() < 1e-12);
        }
    }
}
