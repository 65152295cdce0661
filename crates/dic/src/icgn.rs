//! Inverse-compositional Gauss–Newton (IC-GN) subset matching with a
//! first-order (affine) shape function and the ZNSSD criterion.
//!
//! Algorithm of Pan, Li & Tong, "Fast, robust and accurate digital image
//! correlation calculation without redundant computations", Exp. Mech. 53
//! (2013): the Hessian is built once from the reference subset; each
//! iteration interpolates the deformed image (bicubic B-spline) at the warped
//! points and updates W(p) ← W(p) ∘ W(Δp)⁻¹.

use nalgebra::{Cholesky, Matrix6, U6, Vector6};

use crate::bspline::BSplineImage;
use crate::gray::GrayImage;
use crate::vector_isa::{self, InstructionSet};

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
    #[inline(always)]
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

/// A reference frame prepared for IC-GN once per reference update: its
/// pixels and its B-spline's gradient at every pixel centre. A subset of the
/// frame then reads these images instead of evaluating the spline, so the
/// per-POI setup is one pass of sums and a 6 × 6 Cholesky factorisation.
#[derive(Clone, Debug)]
pub struct ReferenceFrame {
    image: GrayImage,
    /// ∂f/∂x and ∂f/∂y of the reference spline at each pixel, row-major.
    gradient_x: Vec<f64>,
    gradient_y: Vec<f64>,
}

impl ReferenceFrame {
    /// Prefilters `image` and takes its gradients.
    pub fn new(image: GrayImage) -> Self {
        let spline = BSplineImage::new(&image);
        Self::with_spline(image, &spline)
    }

    /// As `new`, reusing the spline already built from `image` (a target
    /// frame that becomes the reference).
    ///
    /// # Panics
    /// If `spline` is not the size of `image`.
    pub fn with_spline(image: GrayImage, spline: &BSplineImage) -> Self {
        assert_eq!(
            (image.width, image.height),
            (spline.width, spline.height),
            "reference spline and image differ in size"
        );
        let (gradient_x, gradient_y) = spline.node_gradients();
        Self {
            image,
            gradient_x,
            gradient_y,
        }
    }

    pub fn image(&self) -> &GrayImage {
        &self.image
    }

    /// The subset of side `2 half + 1` centred on pixel `(x0, y0)`; None if
    /// it does not fit inside the image (with the gradient's one-pixel
    /// margin) or holds no texture.
    pub fn subset(&self, x0: usize, y0: usize, half: usize) -> Option<ReferenceSubset<'_>> {
        vector_isa::prepare_subset(InstructionSet::Widest, self, (x0, y0), half)
    }
}

/// A reference subset with everything IC-GN precomputes from it. With
/// f̃ = (f − f̄)/‖f − f̄‖ and J̃ = ∇f̃ · ∂W/∂p = (∇f/‖f − f̄‖) · ∂W/∂p, the
/// subset keeps Σ J̃ f̃, Σ J̃ and the Cholesky factor of Σ J̃ᵀ J̃; per point
/// it reads f and ∇f from its `ReferenceFrame`.
#[derive(Clone, Debug)]
pub struct ReferenceSubset<'a> {
    pub x0: usize,
    pub y0: usize,
    half: usize,
    frame: &'a ReferenceFrame,
    /// f̄ and 1/‖f − f̄‖.
    mean: f64,
    inv_norm: f64,
    sum_j_f: [f64; 6],
    sum_j: [f64; 6],
    /// Cholesky factor of the Gauss–Newton Hessian Σ J̃ᵀ J̃.
    hessian_chol: Cholesky<f64, U6>,
}

impl<'a> ReferenceSubset<'a> {
    /// `ReferenceFrame::subset`; inlined into `vector_isa`'s dispatch.
    #[inline(always)]
    pub(crate) fn new_inline(
        frame: &'a ReferenceFrame,
        x0: usize,
        y0: usize,
        half: usize,
    ) -> Option<Self> {
        let image = &frame.image;
        if x0 < half + 1
            || y0 < half + 1
            || x0 + half + 1 >= image.width
            || y0 + half + 1 >= image.height
        {
            return None;
        }
        let side = 2 * half + 1;
        let n = (side * side) as f64;
        let rows = |values: &'a [f64]| subset_rows(values, image.width, x0, y0, half);
        let mean = rows(&image.pixels).flatten().sum::<f64>() / n;
        let moments = SubsetMoments::sum(
            rows(&image.pixels),
            rows(&frame.gradient_x),
            rows(&frame.gradient_y),
            mean,
            half,
        );
        let norm = moments.ss.sqrt();
        if norm.is_nan() || norm <= 1e-9 {
            return None;
        }
        let inv_norm = 1.0 / norm;
        let inv_norm_sq = inv_norm * inv_norm;
        // Cholesky reads the lower triangle only.
        let hessian_chol = Cholesky::new(moments.hessian_lower(inv_norm_sq))?;
        Some(Self {
            x0,
            y0,
            half,
            frame,
            mean,
            inv_norm,
            sum_j_f: moments.sum_j_f.map(|s| s * inv_norm_sq),
            sum_j: moments.sum_j.map(|s| s * inv_norm),
            hessian_chol,
        })
    }

    pub fn half(&self) -> usize {
        self.half
    }

    /// Whether the warped subset's interpolation support stays in `target`,
    /// with a margin of 1e-6 px for the rounding of the stepped positions
    /// in `solve`.
    #[inline(always)]
    fn fits(&self, target: &BSplineImage, warp: &Warp) -> bool {
        const MARGIN_PX: f64 = 1e-6;
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
            && target.contains_box(
                cx + x_min - MARGIN_PX,
                cx + x_max + MARGIN_PX,
                cy + y_min - MARGIN_PX,
                cy + y_max + MARGIN_PX,
            )
    }

    /// Refines `guess` by IC-GN against the deformed image `target`.
    pub fn solve(&self, target: &BSplineImage, guess: Warp, settings: &IcgnSettings) -> Match {
        vector_isa::solve(InstructionSet::Widest, self, target, guess, settings)
    }

    /// `solve`; inlined into `vector_isa`'s dispatch.
    #[inline(always)]
    pub(crate) fn solve_inline(
        &self,
        target: &BSplineImage,
        guess: Warp,
        settings: &IcgnSettings,
    ) -> Match {
        let mut warp = guess;
        let mut zncc = f64::NAN;
        let h = self.half as f64;
        let side = 2 * self.half + 1;
        // The deformed image at the warped subset; allocated once per solve.
        let mut g = vec![0.0; side * side];
        for iteration in 1..=settings.max_iterations {
            if !self.fits(target, &warp) {
                return failed(warp, iteration);
            }
            let sums = self.target_sums(target, &warp, &mut g);
            let Some((correlation, d)) = self.gauss_newton_step(&sums) else {
                return failed(warp, iteration);
            };
            zncc = correlation;
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

    /// Interpolates `target` at the subset warped by `warp` into `g`, then
    /// one pass for Σg, Σg², Σfg and Σ J g.
    #[inline(always)]
    fn target_sums(&self, target: &BSplineImage, warp: &Warp, g: &mut [f64]) -> TargetSums {
        let h = self.half as f64;
        let side = 2 * self.half + 1;
        let width = self.frame.image.width;
        let first = (self.y0 - self.half) * width + self.x0 - self.half;
        let (ox, oy) = warp.apply(-h, -h);
        target.values_on_grid(
            (self.x0 as f64 + ox, self.y0 as f64 + oy),
            (1.0 + warp.ux, warp.vx),
            (warp.uy, 1.0 + warp.vy),
            side,
            g,
        );
        let (mut sum_g, mut sum_gg, mut sum_fg) = (0.0, 0.0, 0.0);
        let mut sum_j_g = [0.0; 6];
        for (row, g_row) in g.chunks_exact(side).enumerate() {
            let dy = row as f64 - h;
            let start = first + row * width;
            let f_row = &self.frame.image.pixels[start..start + side];
            let gx_row = &self.frame.gradient_x[start..start + side];
            let gy_row = &self.frame.gradient_y[start..start + side];
            // Σ gx·g, Σ gx·g·dx, Σ gy·g, Σ gy·g·dx along the row.
            let mut r = [0.0; 4];
            let mut dx = -h;
            for (((&f, &gx), &gy), &g) in f_row.iter().zip(gx_row).zip(gy_row).zip(g_row) {
                sum_g += g;
                sum_gg += g * g;
                sum_fg += f * g;
                let gx_g = gx * g;
                let gy_g = gy * g;
                r[0] += gx_g;
                r[1] += gx_g * dx;
                r[2] += gy_g;
                r[3] += gy_g * dx;
                dx += 1.0;
            }
            sum_j_g[0] += r[0];
            sum_j_g[1] += r[1];
            sum_j_g[2] += dy * r[0];
            sum_j_g[3] += r[2];
            sum_j_g[4] += r[3];
            sum_j_g[5] += dy * r[2];
        }
        TargetSums {
            sum_g,
            sum_gg,
            sum_fg,
            sum_j_g,
        }
    }

    /// The ZNCC at the current warp and the Gauss–Newton solution d of
    /// H d = b (the increment is Δp = −d); None where the deformed subset
    /// holds no texture.
    #[inline(always)]
    fn gauss_newton_step(&self, sums: &TargetSums) -> Option<(f64, Vector6<f64>)> {
        let side = 2 * self.half + 1;
        let n = (side * side) as f64;
        let g_mean = sums.sum_g / n;
        let g_ss = sums.sum_gg - n * g_mean * g_mean;
        if g_ss.is_nan() || g_ss <= 1e-18 {
            return None;
        }
        let g_norm = g_ss.sqrt();
        // Σ f̃ g = (Σ f g − f̄ Σ g)/‖f − f̄‖.
        let zncc = (sums.sum_fg - self.mean * sums.sum_g) * self.inv_norm / g_norm;
        let b = Vector6::from_fn(|a, _| {
            self.sum_j_f[a] - (sums.sum_j_g[a] * self.inv_norm - g_mean * self.sum_j[a]) / g_norm
        });
        Some((zncc, self.hessian_chol.solve(&b)))
    }
}

/// The rows of the subset of side `2 half + 1` centred on pixel `(x0, y0)`
/// of a row-major image `width` pixels wide.
#[inline(always)]
fn subset_rows(
    values: &[f64],
    width: usize,
    x0: usize,
    y0: usize,
    half: usize,
) -> impl Iterator<Item = &[f64]> {
    let side = 2 * half + 1;
    (y0 - half..=y0 + half).map(move |y| {
        let start = y * width + x0 - half;
        &values[start..start + side]
    })
}

/// The sums over a reference subset that IC-GN's Hessian and right-hand
/// side are made of, before scaling by 1/‖f − f̄‖.
struct SubsetMoments {
    /// Σ (f − f̄)².
    ss: f64,
    /// Moments (1, dx, dx², dy, dx·dy, dy²) of gx², gx·gy, gy².
    m: [[f64; 6]; 3],
    /// Σ J.
    sum_j: [f64; 6],
    /// Σ J (f − f̄).
    sum_j_f: [f64; 6],
}

impl SubsetMoments {
    /// One pass over the subset's pixels and gradients, row by row.
    #[inline(always)]
    fn sum<'r>(
        f_rows: impl Iterator<Item = &'r [f64]>,
        gx_rows: impl Iterator<Item = &'r [f64]>,
        gy_rows: impl Iterator<Item = &'r [f64]>,
        mean: f64,
        half: usize,
    ) -> Self {
        let h = half as f64;
        // J = (gx, gx·dx, gx·dy, gy, gy·dx, gy·dy) makes every entry of
        // Σ J Jᵀ a moment Σ p·dxⁱ·dyʲ (i + j ≤ 2) of p ∈ {gx², gx·gy, gy²}:
        // sum each row over dx first, then weight the row sums by dy.
        let mut ss = 0.0;
        let mut m = [[0.0; 6]; 3];
        let mut sum_j = [0.0; 6];
        let mut sum_j_f = [0.0; 6];
        for (row, ((f_row, gx_row), gy_row)) in f_rows.zip(gx_rows).zip(gy_rows).enumerate() {
            let dy = row as f64 - h;
            let mut r = [[0.0; 3]; 3];
            // Σ gx, Σ gx·dx, Σ gy, Σ gy·dx and the same times (f − f̄).
            let mut g = [0.0; 4];
            let mut gf = [0.0; 4];
            let mut dx = -h;
            for ((&f, &gx), &gy) in f_row.iter().zip(gx_row).zip(gy_row) {
                let fc = f - mean;
                ss += fc * fc;
                for (moments, p) in r.iter_mut().zip([gx * gx, gx * gy, gy * gy]) {
                    moments[0] += p;
                    moments[1] += p * dx;
                    moments[2] += p * dx * dx;
                }
                g[0] += gx;
                g[1] += gx * dx;
                g[2] += gy;
                g[3] += gy * dx;
                gf[0] += gx * fc;
                gf[1] += gx * dx * fc;
                gf[2] += gy * fc;
                gf[3] += gy * dx * fc;
                dx += 1.0;
            }
            for (total, row_sums) in m.iter_mut().zip(&r) {
                total[0] += row_sums[0];
                total[1] += row_sums[1];
                total[2] += row_sums[2];
                total[3] += dy * row_sums[0];
                total[4] += dy * row_sums[1];
                total[5] += dy * dy * row_sums[0];
            }
            for (total, s) in [(&mut sum_j, &g), (&mut sum_j_f, &gf)] {
                total[0] += s[0];
                total[1] += s[1];
                total[2] += dy * s[0];
                total[3] += s[2];
                total[4] += s[3];
                total[5] += dy * s[2];
            }
        }
        Self {
            ss,
            m,
            sum_j,
            sum_j_f,
        }
    }

    /// The lower triangle of Σ J̃ J̃ᵀ = Σ J Jᵀ / ‖f − f̄‖² from the moments.
    #[inline(always)]
    fn hessian_lower(&self, inv_norm_sq: f64) -> Matrix6<f64> {
        // For the x-block rows a, b ∈ {1, dx, dy}: moment index of a·b.
        const PRODUCT: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [3, 4, 5]];
        let m = &self.m;
        let mut hessian = Matrix6::zeros();
        for a in 0..3 {
            for b in 0..3 {
                let k = PRODUCT[a][b];
                if b <= a {
                    hessian[(a, b)] = m[0][k] * inv_norm_sq;
                    hessian[(a + 3, b + 3)] = m[2][k] * inv_norm_sq;
                }
                hessian[(a + 3, b)] = m[1][k] * inv_norm_sq;
            }
        }
        hessian
    }
}

/// Sums over the deformed image at the warped subset: Σg, Σg², Σfg and
/// Σ J g (raw f and ∇f, scaled by the caller).
struct TargetSums {
    sum_g: f64,
    sum_gg: f64,
    sum_fg: f64,
    sum_j_g: [f64; 6],
}

fn failed(warp: Warp, iterations: usize) -> Match {
    Match {
        warp,
        zncc: f64::NAN,
        iterations,
        converged: false,
    }
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
    fn subset_hessian_equals_the_direct_sum() {
        // Σ J̃ᵀ J̃ over the points, J̃ = ∇f/‖f − f̄‖ · ∂W/∂p, summed directly
        // from the spline, against the factor built from moments.
        let (width, height) = (48, 44);
        let pixels = (0..width * height)
            .map(|i| {
                let (x, y) = ((i % width) as f64, (i / width) as f64);
                (0.5 * x).sin() * (0.3 * y).cos() + 0.1 * (0.7 * x + 0.4 * y).sin()
            })
            .collect();
        let image = GrayImage::new(width, height, pixels).unwrap();
        let spline = BSplineImage::new(&image);
        let frame = ReferenceFrame::with_spline(image.clone(), &spline);
        let (x0, y0, half) = (23, 20, 7);
        let subset = frame.subset(x0, y0, half).unwrap();
        let points: Vec<(usize, usize)> = (y0 - half..=y0 + half)
            .flat_map(|y| (x0 - half..=x0 + half).map(move |x| (x, y)))
            .collect();
        let mean = points.iter().map(|&(x, y)| image.get(x, y)).sum::<f64>() / 225.0;
        let norm = points
            .iter()
            .map(|&(x, y)| (image.get(x, y) - mean).powi(2))
            .sum::<f64>()
            .sqrt();
        let mut direct = [[0.0; 6]; 6];
        for &(x, y) in &points {
            let (gx, gy) = spline.gradient_at_node(x, y);
            let (dx, dy) = (x as f64 - x0 as f64, y as f64 - y0 as f64);
            let j = [gx, gx * dx, gx * dy, gy, gy * dx, gy * dy].map(|v| v / norm);
            for a in 0..6 {
                for b in 0..6 {
                    direct[a][b] += j[a] * j[b];
                }
            }
        }
        let l = subset.hessian_chol.l();
        for a in 0..6 {
            for b in 0..6 {
                let product: f64 = (0..6).map(|k| l[(a, k)] * l[(b, k)]).sum();
                assert!(
                    (product - direct[a][b]).abs() < 1e-10 * direct[a][a].max(direct[b][b]),
                    "H[{a}][{b}] {product} vs {}",
                    direct[a][b]
                );
            }
        }
    }
}
