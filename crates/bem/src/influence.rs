//! The elastic half-space as an influence operator: surface displacement u
//! from a pixel-wise constant surface pressure p, for a unit composite
//! modulus E* = 1 (so p is in units of E* and u in metres; the linear
//! problem scales with E*).
//!
//! - `periodic`: the map repeats; u and p as Fourier series,
//!   û(q) = 2 p̂(q) / (E* |q|) (q in rad/m), the mean of u set to zero (a
//!   periodic load on a half-space has no finite rigid displacement, so the
//!   reference is the mean surface and a prescribed approach is a prescribed
//!   mean gap).
//! - `free`: the map is a finite sample of an infinite half-space loaded
//!   nowhere else; u is the exact superposition of uniformly loaded
//!   rectangles (Love's closed form below), evaluated as a cyclic convolution
//!   on a grid of at least 2N × 2N with the kernel's coordinates wrapped and
//!   the pressure zero in the padding (Hockney, "The potential calculation and
//!   some applications", Methods Comput. Phys. 9, 1970), which is exactly
//!   the aperiodic sum over the map. u → 0 far away.
//!
//! Love's rectangle: a uniform pressure p on |ξ| ≤ a, |η| ≤ b displaces the
//! surface point (x, y) by (Boussinesq's point load integrated over the
//! rectangle)
//!
//!   u(x, y) = p / (π E*) ∬ dξ dη / √((x − ξ)² + (y − η)²).
//!
//! F(X, Y) = X ln(Y + R) + Y ln(X + R), R = √(X² + Y²), has
//! ∂²F/∂X∂Y = 1/R, so the integral is the corner sum
//! F(x+a, y+b) − F(x+a, y−b) − F(x−a, y+b) + F(x−a, y−b). Writing
//! ln(Y + R) = ln|X| + asinh(Y/|X|), the X ln|X| and Y ln|Y| parts cancel
//! between corners, leaving G(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|) (each
//! term 0 where its factor is 0), which has no 0·∞ at the pixel's own edges.
//! This is the form of A. E. H. Love, "The stress produced in a
//! semi-infinite solid by pressure on part of the boundary", Phil. Trans.
//! R. Soc. A 228 (1929) 377–420, quoted in K. L. Johnson, Contact Mechanics
//! (1985), §3.9; at a square pixel's centre it gives 8a·asinh(1)/π =
//! 2.24 a p/E*, Johnson's value.

use hypercontact_numeric::fft2::fast_even_size;
use rayon::prelude::*;

use crate::fft2::{self, Factor, Fft2};

/// How the map continues beyond its edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, hypercontact_core::Choice)]
pub enum Boundary {
    /// a finite sample of an infinite half-space (zero-padded, Love's kernel)
    #[default]
    Free,
    /// the map repeats (û = 2 p̂ / (E* |q|))
    Periodic,
}

/// The displacement-from-pressure operator of one map grid.
pub struct Influence {
    nx: usize,
    ny: usize,
    boundary: Boundary,
    fft: Fft2,
    /// The kernel's spectrum, scaled for [`Fft2::convolve`].
    spectrum: Vec<f64>,
    /// u everywhere under a unit pressure on pixel [0, 0]: K at every
    /// offset (the kernel is even in x and in y), m.
    response_m: Vec<f64>,
    /// Free boundary: the preconditioner's own grid, the map's size
    /// rounded up to a fast one, with Love's kernel wrapped on it (a
    /// quarter of the padded grid's transforms).
    pre: Option<(Fft2, Vec<f64>)>,
}

/// Buffers the operator and its preconditioner need, kept between calls.
pub struct Workspace {
    main: fft2::Workspace,
    pre: Option<fft2::Workspace>,
}

impl Influence {
    /// The operator for an `nx × ny` map of pixels `dx_m × dy_m`.
    pub fn new(nx: usize, ny: usize, dx_m: f64, dy_m: f64, boundary: Boundary) -> Self {
        let (mx, my) = match boundary {
            Boundary::Free => (fast_even_size(2 * nx), fast_even_size(2 * ny)),
            Boundary::Periodic => (nx, ny),
        };
        let fft = Fft2::new(nx, ny, mx, my);
        let spectrum = match boundary {
            Boundary::Free => fft.spectrum(love_kernel(mx, my, dx_m, dy_m)),
            Boundary::Periodic => periodic_spectrum(mx, my, dx_m, dy_m),
        };
        let pre = match boundary {
            Boundary::Free => {
                let (px, py) = (fast_even_size(nx), fast_even_size(ny));
                let fft = Fft2::new(nx, ny, px, py);
                let spectrum = fft.spectrum(love_kernel(px, py, dx_m, dy_m));
                Some((fft, spectrum))
            }
            Boundary::Periodic => None,
        };
        let mut influence = Self {
            nx,
            ny,
            boundary,
            fft,
            spectrum,
            response_m: Vec::new(),
            pre,
        };
        let mut unit = vec![0.0; nx * ny];
        unit[0] = 1.0;
        let mut u = vec![0.0; nx * ny];
        influence.apply(&unit, &mut u, &mut influence.workspace());
        influence.response_m = u;
        influence
    }

    pub fn dim(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    pub fn boundary(&self) -> Boundary {
        self.boundary
    }

    /// The transform grid (2N × 2N or larger when free, N × N when periodic).
    pub fn transform_size(&self) -> (usize, usize) {
        self.fft.transform_size()
    }

    /// The displacement of a loaded pixel under its own unit pressure, m
    /// (for E* = 1); for a periodic map, relative to the mean.
    pub fn self_displacement_m(&self) -> f64 {
        self.response_m[0]
    }

    /// `displacement += K · loads` for a few point loads (pixel index,
    /// pressure), summed directly: for a handful of points cheaper than a
    /// convolution.
    pub fn add_point_loads(&self, loads: &[(usize, f64)], displacement: &mut [f64]) {
        let (nx, ny) = (self.nx, self.ny);
        let periodic = self.boundary == Boundary::Periodic;
        displacement
            .par_chunks_mut(ny)
            .enumerate()
            .for_each(|(i, row)| {
                for &(k, load) in loads {
                    let (ki, kj) = (k / ny, k % ny);
                    let di = if periodic {
                        (i + nx - ki) % nx
                    } else {
                        i.abs_diff(ki)
                    };
                    let kernel = &self.response_m[di * ny..(di + 1) * ny];
                    // Offsets j − kj for j ≥ kj, then the ones before.
                    for (u, &k) in row[kj..].iter_mut().zip(kernel) {
                        *u += load * k;
                    }
                    if periodic {
                        for (u, &k) in row[..kj].iter_mut().zip(&kernel[ny - kj..]) {
                            *u += load * k;
                        }
                    } else {
                        for (u, &k) in row[..kj].iter_mut().zip(kernel[1..=kj].iter().rev()) {
                            *u += load * k;
                        }
                    }
                }
            });
    }

    pub fn workspace(&self) -> Workspace {
        Workspace {
            main: self.fft.workspace(),
            pre: self.pre.as_ref().map(|(fft, _)| fft.workspace()),
        }
    }

    /// `displacement = K * pressure` on the map (E* = 1).
    pub fn apply(&self, pressure: &[f64], displacement: &mut [f64], work: &mut Workspace) {
        self.fft.convolve(
            pressure,
            &self.spectrum,
            Factor::Multiply,
            displacement,
            &mut work.main,
        );
    }

    /// `pressure ≈ K⁻¹ gap`: the inverse of the operator on the transform
    /// grid (the pseudo-inverse for a periodic map: zero at q = 0), the
    /// solver's preconditioner.
    pub fn precondition(&self, gap: &[f64], pressure: &mut [f64], work: &mut Workspace) {
        match (&self.pre, &mut work.pre) {
            (Some((fft, spectrum)), Some(w)) => {
                fft.convolve(gap, spectrum, Factor::Divide, pressure, w)
            }
            _ => self.fft.convolve(
                gap,
                &self.spectrum,
                Factor::Divide,
                pressure,
                &mut work.main,
            ),
        }
    }
}

/// Love's G(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|), terms 0 at a 0 factor.
fn love_g(x: f64, y: f64) -> f64 {
    let term = |a: f64, b: f64| {
        if a == 0.0 {
            0.0
        } else {
            a * (b / a.abs()).asinh()
        }
    };
    term(x, y) + term(y, x)
}

/// Displacement at offset (x, y) from the centre of a `dx × dy` pixel under
/// unit pressure, E* = 1, m.
pub fn love_pixel(x_m: f64, y_m: f64, dx_m: f64, dy_m: f64) -> f64 {
    let (a, b) = (0.5 * dx_m, 0.5 * dy_m);
    (love_g(x_m + a, y_m + b) - love_g(x_m + a, y_m - b) - love_g(x_m - a, y_m + b)
        + love_g(x_m - a, y_m - b))
        / std::f64::consts::PI
}

/// Love's kernel on the `mx × my` transform grid, coordinates wrapped at
/// half the grid (index i is the offset i for i ≤ m/2, i − m beyond), so the
/// kernel is even and its spectrum real.
fn love_kernel(mx: usize, my: usize, dx_m: f64, dy_m: f64) -> Vec<f64> {
    let offset = |i: usize, m: usize| {
        if i <= m / 2 {
            i as f64
        } else {
            i as f64 - m as f64
        }
    };
    let mut kernel = vec![0.0; mx * my];
    kernel.par_chunks_mut(my).enumerate().for_each(|(i, row)| {
        let x = offset(i, mx) * dx_m;
        for (j, k) in row.iter_mut().enumerate() {
            *k = love_pixel(x, offset(j, my) * dy_m, dx_m, dy_m);
        }
    });
    kernel
}

/// 2 / |q| on the periodic grid (zero at q = 0), scaled for
/// [`Fft2::convolve`]; index jy · mx + ix over the half-spectrum.
fn periodic_spectrum(mx: usize, my: usize, dx_m: f64, dy_m: f64) -> Vec<f64> {
    let hy = my / 2 + 1;
    let wavevector = |i: usize, m: usize, d: f64| {
        let k = if i <= m / 2 {
            i as f64
        } else {
            i as f64 - m as f64
        };
        std::f64::consts::TAU * k / (m as f64 * d)
    };
    let scale = 1.0 / (mx * my) as f64;
    let mut spectrum = vec![0.0; hy * mx];
    for j in 0..hy {
        let qy = wavevector(j, my, dy_m);
        for i in 0..mx {
            let q = wavevector(i, mx, dx_m).hypot(qy);
            spectrum[j * mx + i] = if q > 0.0 { 2.0 / q * scale } else { 0.0 };
        }
    }
    spectrum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn love_matches_the_square_centre_and_the_point_load_far_away() {
        // Centre of a square of side 2a: 8 a asinh(1) / π (Johnson: 2.24 a).
        let a = 0.5;
        let centre = love_pixel(0.0, 0.0, 1.0, 1.0);
        assert!((centre - 8.0 * a * 1f64.asinh() / std::f64::consts::PI).abs() < 1e-15);
        assert!((centre / a - 2.24).abs() < 5e-3);
        // Far away: Boussinesq's point load, P / (π E* r) with P = dx dy.
        for (x, y) in [(40.0, 0.0), (30.0, 40.0), (-7.0, 90.0)] {
            let r = f64::hypot(x, y);
            let point = 2.0 * 3.0 / (std::f64::consts::PI * r);
            let u = love_pixel(x, y, 2.0, 3.0);
            assert!(
                (u / point - 1.0).abs() < 2e-3 * (50.0 / r).powi(2),
                "{x} {y}: {u} vs {point}"
            );
        }
        // Even in both coordinates, finite at the pixel's edges and corners.
        let (u, mirrored) = (
            love_pixel(3.0, -2.0, 1.0, 2.0),
            love_pixel(-3.0, 2.0, 1.0, 2.0),
        );
        assert!((u - mirrored).abs() < 1e-14 * u);
        assert!(love_pixel(0.5, 0.5, 1.0, 1.0).is_finite());
    }

    #[test]
    fn free_operator_is_the_direct_sum_of_love_pixels() {
        let (nx, ny, dx, dy) = (6, 5, 1e-3, 2e-3);
        let influence = Influence::new(nx, ny, dx, dy, Boundary::Free);
        let p: Vec<f64> = (0..nx * ny).map(|k| ((k * 7) % 5) as f64).collect();
        let mut u = vec![0.0; nx * ny];
        influence.apply(&p, &mut u, &mut influence.workspace());
        for i in 0..nx {
            for j in 0..ny {
                let mut direct = 0.0;
                for k in 0..nx {
                    for l in 0..ny {
                        let (x, y) = ((i as f64 - k as f64) * dx, (j as f64 - l as f64) * dy);
                        direct += love_pixel(x, y, dx, dy) * p[k * ny + l];
                    }
                }
                assert!((u[i * ny + j] - direct).abs() < 1e-12 * direct, "{i} {j}");
            }
        }
        assert_eq!(influence.self_displacement_m(), {
            let mut unit = vec![0.0; nx * ny];
            unit[0] = 1.0;
            let mut u = vec![0.0; nx * ny];
            influence.apply(&unit, &mut u, &mut influence.workspace());
            u[0]
        });
    }

    #[test]
    fn point_loads_add_what_the_convolution_gives() {
        for boundary in [Boundary::Free, Boundary::Periodic] {
            let (nx, ny) = (9, 7);
            let influence = Influence::new(nx, ny, 1e-3, 2e-3, boundary);
            let loads = [
                (0, 1.5),
                (3 * ny + 5, -0.5),
                (nx * ny - 1, 2.0),
                (4 * ny, 0.25),
            ];
            let mut p = vec![0.0; nx * ny];
            for &(k, load) in &loads {
                p[k] += load;
            }
            let mut u = vec![0.0; nx * ny];
            influence.apply(&p, &mut u, &mut influence.workspace());
            let mut direct = vec![1.0; nx * ny];
            influence.add_point_loads(&loads, &mut direct);
            for (a, b) in u.iter().zip(&direct) {
                assert!((a + 1.0 - b).abs() < 1e-15, "{boundary:?}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn periodic_operator_gives_two_over_q_for_a_cosine() {
        let (nx, ny, dx, dy) = (16, 8, 1e-3, 1.5e-3);
        let influence = Influence::new(nx, ny, dx, dy, Boundary::Periodic);
        let (kx, ky) = (3.0, 1.0);
        let (lx, ly) = (nx as f64 * dx, ny as f64 * dy);
        let q = std::f64::consts::TAU * f64::hypot(kx / lx, ky / ly);
        let phase = |i: usize, j: usize| {
            std::f64::consts::TAU * (kx * i as f64 / nx as f64 + ky * j as f64 / ny as f64)
        };
        let p: Vec<f64> = (0..nx * ny).map(|k| phase(k / ny, k % ny).cos()).collect();
        let mut u = vec![0.0; nx * ny];
        influence.apply(&p, &mut u, &mut influence.workspace());
        for (k, u) in u.iter().enumerate() {
            let exact = 2.0 / q * phase(k / ny, k % ny).cos();
            assert!((u - exact).abs() < 1e-14, "{k}: {u} vs {exact}");
        }
    }
}
