//! The hybrid parameters of ISO 25178-2 §4.3: the root mean square gradient
//! Sdq and the developed interfacial area ratio Sdr.
//!
//! Sdq = ⟨(∂z/∂x)² + (∂z/∂y)²⟩^½ with the convention of
//! [`crate::stats::rms_slope`]: forward differences (z[i+1, j] − z[i, j])/Δx
//! and (z[i, j+1] − z[i, j])/Δy, each squared and averaged over the pairs
//! whose two points are measured, the two means added. (SurfaceTopography's
//! `rms_gradient` on a non-periodic map takes the same differences but
//! averages gx² + gy² over the (nx − 1)(ny − 1) points where both exist;
//! the two differ by O(1/n).)
//!
//! Sdr = (A_developed − A_projected)/A_projected · 100 % over the grid
//! cells whose four corners are measured. The developed area of a cell is
//! the mean of its two triangulations (along either diagonal), four right
//! triangles in all, each weighing a quarter of the cell: a triangle with
//! legs Δx, Δy and height rises a (along its x leg) and b (along its y leg)
//! has area ½ΔxΔy·√(1 + g²), g² = (a/Δx)² + (b/Δy)², exactly (the cross
//! product of its legs), so a tilted plane of slope s gives
//! Sdr = (√(1 + s²) − 1)·100 % exactly. The excess √(1 + g²) − 1 is
//! computed as g²/(√(1 + g²) + 1), without cancellation for small slopes.
//! (Gwyddion's surface area splits each cell into four triangles about its
//! centre instead; the two agree to O(Δx²) on smooth surfaces.
//! SurfaceTopography has no Sdr.)

use ndarray::Array2;

use super::{check_spacing, checked_heights};
use crate::SurfaceError;

/// Sdq, the root mean square gradient (dimensionless) of the convention in
/// the module doc; an error when the map has no pair of measured neighbours
/// along x or none along y.
pub fn sdq(h: &Array2<f64>, dx_m: f64, dy_m: f64) -> Result<f64, SurfaceError> {
    const QUANTITY: &str = "Sdq";
    check_spacing(dx_m, dy_m, QUANTITY)?;
    let heights = checked_heights(h, QUANTITY)?;
    let z = &heights.values[..];
    let (nx, ny) = heights.shape;
    let [pairs_x, sum_x, pairs_y, sum_y] = hypercontact_numeric::reduce::sums(z.len(), |k| {
        let (i, j) = (k / ny, k % ny);
        let mut terms = [0.0; 4];
        if i + 1 < nx {
            let d = (z[k + ny] - z[k]) / dx_m;
            if !d.is_nan() {
                terms[0] = 1.0;
                terms[1] = d * d;
            }
        }
        if j + 1 < ny {
            let d = (z[k + 1] - z[k]) / dy_m;
            if !d.is_nan() {
                terms[2] = 1.0;
                terms[3] = d * d;
            }
        }
        terms
    });
    if pairs_x == 0.0 || pairs_y == 0.0 {
        return Err(SurfaceError::Areal {
            quantity: QUANTITY,
            message: format!(
                "the map has {pairs_x} pairs of measured neighbours along x and {pairs_y} \
                 along y; it needs at least one along each"
            ),
        });
    }
    Ok((sum_x / pairs_x + sum_y / pairs_y).sqrt())
}

/// Sdr in percent, the discretisation of the module doc; an error when no
/// grid cell has its four corners measured.
pub fn sdr_percent(h: &Array2<f64>, dx_m: f64, dy_m: f64) -> Result<f64, SurfaceError> {
    const QUANTITY: &str = "Sdr";
    check_spacing(dx_m, dy_m, QUANTITY)?;
    let heights = checked_heights(h, QUANTITY)?;
    let z = &heights.values[..];
    let (nx, ny) = heights.shape;
    let (cells_x, cells_y) = (nx.saturating_sub(1), ny.saturating_sub(1));
    // excess of √(1 + g²) over 1, without cancellation
    let excess = |gx: f64, gy: f64| {
        let g2 = gx * gx + gy * gy;
        g2 / ((1.0 + g2).sqrt() + 1.0)
    };
    let [cells, sum] = hypercontact_numeric::reduce::sums(cells_x * cells_y, |c| {
        let (i, j) = (c / cells_y, c % cells_y);
        let k = i * ny + j;
        let (z00, z01, z10, z11) = (z[k], z[k + 1], z[k + ny], z[k + ny + 1]);
        let (bottom, top) = ((z10 - z00) / dx_m, (z11 - z01) / dx_m);
        let (left, right) = ((z01 - z00) / dy_m, (z11 - z10) / dy_m);
        // the four right triangles, named by their right-angle corner
        let area = excess(bottom, right) // at (1, 0): 00-10-11
            + excess(top, left) // at (0, 1): 00-01-11
            + excess(bottom, left) // at (0, 0): 00-10-01
            + excess(top, right); // at (1, 1): 10-11-01
        if area.is_nan() {
            [0.0, 0.0]
        } else {
            [1.0, area / 4.0]
        }
    });
    if cells == 0.0 {
        return Err(SurfaceError::Areal {
            quantity: QUANTITY,
            message: "no grid cell has its four corners measured".into(),
        });
    }
    if !sum.is_finite() {
        return Err(SurfaceError::Areal {
            quantity: QUANTITY,
            message: "the slopes overflow f64 (are the map and its spacings in metres?)".into(),
        });
    }
    Ok(100.0 * sum / cells)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use super::*;

    #[test]
    fn a_tilted_plane_has_its_slope_and_exact_area() {
        let (dx, dy, sx, sy) = (1e-6, 2e-6, 0.3, -0.1);
        let h = Array2::from_shape_fn((30, 20), |(i, j)| sx * i as f64 * dx + sy * j as f64 * dy);
        let s2: f64 = sx * sx + sy * sy;
        assert!((sdq(&h, dx, dy).unwrap() - s2.sqrt()).abs() < 1e-12);
        let sdr = sdr_percent(&h, dx, dy).unwrap();
        assert!((sdr / (100.0 * ((1.0 + s2).sqrt() - 1.0)) - 1.0).abs() < 1e-12);
        // a level plane: no excess at all
        assert_eq!(sdr_percent(&Array2::zeros((4, 4)), dx, dy).unwrap(), 0.0);
        assert_eq!(sdq(&Array2::zeros((4, 4)), dx, dy).unwrap(), 0.0);
    }

    /// h = A sin(2πx/L): Sdq = 2πA/(L√2) times the forward difference's
    /// factor sinc(πΔx/L); Sdr against the area of the continuous sinusoid,
    /// (1/L)∫₀ᴸ √(1 + (kA cos kx)²) dx − 1, by Simpson's rule on 20 000
    /// intervals (an independent quadrature of the exact surface).
    #[test]
    fn a_sinusoid_has_its_rms_gradient_and_developed_area() {
        let (amplitude, period, dx) = (3e-6, 64usize, 1e-6);
        let length = period as f64 * dx;
        let h = Array2::from_shape_fn((4 * period + 1, 6), |(i, _)| {
            amplitude * (TAU * i as f64 / period as f64).sin()
        });
        let k = TAU / length;
        let half = std::f64::consts::PI * dx / length;
        let expected = k * amplitude / 2f64.sqrt() * half.sin() / half;
        assert!((sdq(&h, dx, dx).unwrap() / expected - 1.0).abs() < 1e-4);
        let n = 20_000;
        let f = |x: f64| (1.0 + (k * amplitude * (k * x).cos()).powi(2)).sqrt();
        let simpson: f64 = (0..=n)
            .map(|m| {
                let w = if m == 0 || m == n {
                    1.0
                } else if m % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(length * m as f64 / n as f64)
            })
            .sum::<f64>()
            / (3.0 * n as f64);
        let exact_percent = 100.0 * (simpson - 1.0);
        let sdr = sdr_percent(&h, dx, dx).unwrap();
        assert!(
            (sdr / exact_percent - 1.0).abs() < 2e-3,
            "{sdr} vs {exact_percent}"
        );
    }

    #[test]
    fn gaps_leave_out_their_pairs_and_cells_and_empty_maps_are_refused() {
        let (dx, s) = (1e-6, 0.2);
        let mut h = Array2::from_shape_fn((5, 5), |(i, _)| s * i as f64 * dx);
        h[[2, 2]] = f64::NAN;
        // the x pairs all have slope s, the y pairs 0, whatever is missing
        assert!((sdq(&h, dx, dx).unwrap() - s).abs() < 1e-12);
        let expected = 100.0 * ((1.0 + s * s).sqrt() - 1.0);
        assert!((sdr_percent(&h, dx, dx).unwrap() / expected - 1.0).abs() < 1e-12);
        // a checkerboard of gaps: no cell and no pair is complete
        let board = Array2::from_shape_fn(
            (4, 4),
            |(i, j)| {
                if (i + j) % 2 == 0 { 1.0 } else { f64::NAN }
            },
        );
        assert!(
            sdr_percent(&board, dx, dx)
                .unwrap_err()
                .to_string()
                .contains("no grid cell")
        );
        assert!(
            sdq(&board, dx, dx)
                .unwrap_err()
                .to_string()
                .contains("0 pairs")
        );
        assert!(
            sdq(&h, 0.0, dx)
                .unwrap_err()
                .to_string()
                .contains("dx_m = 0")
        );
        assert!(sdr_percent(&h, dx, f64::NAN).is_err());
    }

    #[test]
    fn sdq_is_the_stats_modules_rms_slope() {
        let mut h = Array2::from_shape_fn((37, 23), |(i, j)| {
            ((i * 7 + j * 13) % 11) as f64 * 1e-7 + (i as f64 * 0.3).sin() * 1e-6
        });
        h[[5, 5]] = f64::NAN;
        h[[36, 0]] = f64::NAN;
        let (dx, dy) = (1e-6, 1.5e-6);
        let a = sdq(&h, dx, dy).unwrap();
        let b = crate::stats::rms_slope(&h, dx, dy);
        assert!((a / b - 1.0).abs() < 1e-13, "{a} vs {b}");
    }
}
