//! Distributions of a map's heights, slopes and curvatures, and their rms
//! as a function of scale.
//!
//! - Histograms: equal-width bins from the smallest to the largest value.
//!   Slope |∇h| and curvature κ = ∇²h/2 (the mean curvature in the
//!   small-slope approximation) use central differences,
//!   ∂h/∂x ≈ (h[i+1, j] − h[i−1, j])/(2Δx),
//!   ∂²h/∂x² ≈ (h[i+1, j] − 2h[i, j] + h[i−1, j])/Δx², at the points whose
//!   four neighbours and themselves are measured (the map's edge is left
//!   out).
//! - Scale-dependent statistics follow SurfaceTopography's
//!   `scale_dependent_statistical_property` with integer scale factors k
//!   (Sanner et al., Appl. Surf. Sci. Adv. 7, 100190, 2022): derivatives by
//!   its default stencils stretched to a lag of k pixels, rms over the map
//!   where the stencil lies on measured points inside it:
//!   - slope: upwind differences gx = (h[i+k, j] − h[i, j])/(kΔx), gy =
//!     (h[i, j+k] − h[i, j])/(kΔy) at the points i < nx − k, j < ny − k,
//!     value ⟨gx² + gy²⟩^½ (at k = 1 its `rms_gradient`), scale k·Δ;
//!   - curvature: central second differences with step k, value
//!     ⟨((∂²h/∂x² + ∂²h/∂y²)/2)²⟩^½ (at k = 1 its `rms_curvature_from_area`),
//!     scale 2k·Δ (the stencil's length);
//!
//!   with Δ = (Δx + Δy)/2, SurfaceTopography's distance of a scale factor.
//!   A lag with fewer than four values gives NaN (its `threshold`).

use ndarray::Array2;

use super::{MIN_MEASURED, check_spacing, checked_heights, measured_mean};
use crate::SurfaceError;

/// Counts of values in equal-width bins.
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    /// bins + 1 edges, from the smallest value to the largest (the last bin
    /// holds its upper edge); all equal when the values are.
    pub edges: Vec<f64>,
    pub counts: Vec<u64>,
}

/// A statistic at a ladder of scales.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaleSeries {
    /// The lags in pixels.
    pub lags: Vec<usize>,
    /// The scale of each lag, m.
    pub scale_m: Vec<f64>,
    /// The statistic at each scale (units in the function's doc).
    pub value: Vec<f64>,
}

/// The most bins a histogram is given.
pub const MAX_BINS: usize = 1 << 20;

fn histogram(
    values: &[f64],
    bins: usize,
    quantity: &'static str,
) -> Result<Histogram, SurfaceError> {
    if bins == 0 || bins > MAX_BINS {
        return Err(SurfaceError::Areal {
            quantity,
            message: format!("{bins} bins: a histogram has 1 … {MAX_BINS}"),
        });
    }
    if values.is_empty() {
        return Err(SurfaceError::Areal {
            quantity,
            message: "no point has its four neighbours measured".into(),
        });
    }
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if !(hi - lo).is_finite() {
        return Err(SurfaceError::Areal {
            quantity,
            message: format!("the values span {lo:e} … {hi:e}, beyond f64"),
        });
    }
    let width = (hi - lo) / bins as f64;
    let edges = (0..=bins).map(|k| lo + width * k as f64).collect();
    let mut counts = vec![0u64; bins];
    for &v in values {
        let k = if width > 0.0 {
            ((v - lo) / width) as usize
        } else {
            bins - 1
        };
        counts[k.min(bins - 1)] += 1;
    }
    Ok(Histogram { edges, counts })
}

/// The histogram of the measured heights about their mean, `bins` bins, m.
pub fn height_histogram(h: &Array2<f64>, bins: usize) -> Result<Histogram, SurfaceError> {
    const QUANTITY: &str = "the height histogram";
    let heights = checked_heights(h, QUANTITY)?;
    let mean = measured_mean(&heights.values);
    let z: Vec<f64> = heights
        .values
        .iter()
        .filter(|v| !v.is_nan())
        .map(|v| v - mean)
        .collect();
    histogram(&z, bins, QUANTITY)
}

/// (gx, gy, ∂²h/∂x², ∂²h/∂y²) by central differences at every interior
/// point whose stencil is measured.
fn central_derivatives(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    quantity: &'static str,
) -> Result<Vec<[f64; 4]>, SurfaceError> {
    check_spacing(dx_m, dy_m, quantity)?;
    let heights = checked_heights(h, quantity)?;
    let z = &heights.values[..];
    let (nx, ny) = heights.shape;
    let mut out = Vec::new();
    for i in 1..nx.saturating_sub(1) {
        for j in 1..ny.saturating_sub(1) {
            let k = i * ny + j;
            let (c, xm, xp, ym, yp) = (z[k], z[k - ny], z[k + ny], z[k - 1], z[k + 1]);
            let d = [
                (xp - xm) / (2.0 * dx_m),
                (yp - ym) / (2.0 * dy_m),
                (xp - 2.0 * c + xm) / (dx_m * dx_m),
                (yp - 2.0 * c + ym) / (dy_m * dy_m),
            ];
            if d.iter().all(|v| !v.is_nan()) {
                out.push(d);
            }
        }
    }
    Ok(out)
}

/// The histogram of the slope |∇h| (dimensionless), `bins` bins.
pub fn slope_histogram(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    bins: usize,
) -> Result<Histogram, SurfaceError> {
    const QUANTITY: &str = "the slope histogram";
    let slopes: Vec<f64> = central_derivatives(h, dx_m, dy_m, QUANTITY)?
        .iter()
        .map(|d| d[0].hypot(d[1]))
        .collect();
    histogram(&slopes, bins, QUANTITY)
}

/// The histogram of the curvature ∇²h/2, 1/m, `bins` bins.
pub fn curvature_histogram(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    bins: usize,
) -> Result<Histogram, SurfaceError> {
    const QUANTITY: &str = "the curvature histogram";
    let curvatures: Vec<f64> = central_derivatives(h, dx_m, dy_m, QUANTITY)?
        .iter()
        .map(|d| (d[2] + d[3]) / 2.0)
        .collect();
    histogram(&curvatures, bins, QUANTITY)
}

/// [`slope_histogram`] and [`curvature_histogram`] from one pass of the
/// central differences over the map.
pub fn slope_and_curvature_histograms(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    bins: usize,
) -> Result<(Histogram, Histogram), SurfaceError> {
    const QUANTITY: &str = "the slope and curvature histograms";
    let derivatives = central_derivatives(h, dx_m, dy_m, QUANTITY)?;
    let slopes: Vec<f64> = derivatives.iter().map(|d| d[0].hypot(d[1])).collect();
    let slope = histogram(&slopes, bins, "the slope histogram")?;
    drop(slopes);
    let curvatures: Vec<f64> = derivatives.iter().map(|d| (d[2] + d[3]) / 2.0).collect();
    drop(derivatives);
    let curvature = histogram(&curvatures, bins, "the curvature histogram")?;
    Ok((slope, curvature))
}

impl Histogram {
    /// The probability density of each bin, count / (total count · bin
    /// width), in 1 over the values' unit (it integrates to 1); NaN for a
    /// bin of zero width (all values equal).
    pub fn density(&self) -> Vec<f64> {
        let total: u64 = self.counts.iter().sum();
        self.counts
            .iter()
            .zip(self.edges.windows(2))
            .map(|(&count, edge)| {
                let width = edge[1] - edge[0];
                if width > 0.0 && total > 0 {
                    count as f64 / (total as f64 * width)
                } else {
                    f64::NAN
                }
            })
            .collect()
    }
}

/// The lags 1, 2, 4, … up to ⌊(min(nx, ny) − 1)/2⌋ pixels: a ladder at which
/// both scale-dependent statistics have points.
pub fn lag_ladder(nx: usize, ny: usize) -> Vec<usize> {
    let top = (nx.min(ny).saturating_sub(1)) / 2;
    std::iter::successors(Some(1usize), |k| k.checked_mul(2))
        .take_while(|&k| k <= top)
        .collect()
}

/// Which scale-dependent statistic.
#[derive(Clone, Copy)]
enum Derivative {
    Slope,
    Curvature,
}

fn scale_dependent(
    h: &Array2<f64>,
    (dx_m, dy_m): (f64, f64),
    lags: &[usize],
    derivative: Derivative,
    quantity: &'static str,
) -> Result<ScaleSeries, SurfaceError> {
    check_spacing(dx_m, dy_m, quantity)?;
    let heights = checked_heights(h, quantity)?;
    if let Some(0) = lags.iter().find(|&&k| k == 0) {
        return Err(SurfaceError::Areal {
            quantity,
            message: "a lag of 0 pixels has no difference; lags start at 1".into(),
        });
    }
    let z = &heights.values[..];
    let (nx, ny) = heights.shape;
    let pixel_m = (dx_m + dy_m) / 2.0;
    let mut series = ScaleSeries {
        lags: lags.to_vec(),
        scale_m: Vec::with_capacity(lags.len()),
        value: Vec::with_capacity(lags.len()),
    };
    for &k in lags {
        let (value, order) = match derivative {
            Derivative::Slope => (rms_upwind_gradient(z, (nx, ny), k, dx_m, dy_m), 1.0),
            Derivative::Curvature => (rms_half_laplacian(z, (nx, ny), k, dx_m, dy_m), 2.0),
        };
        series.scale_m.push(order * k as f64 * pixel_m);
        series.value.push(value);
    }
    Ok(series)
}

/// ⟨gx² + gy²⟩^½ with upwind differences at lag k (NaN for < 4 values).
fn rms_upwind_gradient(z: &[f64], (nx, ny): (usize, usize), k: usize, dx_m: f64, dy_m: f64) -> f64 {
    let (rows, cols) = (nx.saturating_sub(k), ny.saturating_sub(k));
    let (sx, sy) = (k as f64 * dx_m, k as f64 * dy_m);
    let [n, sum] = hypercontact_numeric::reduce::sums(rows * cols, |p| {
        let q = (p / cols) * ny + p % cols;
        let gx = (z[q + k * ny] - z[q]) / sx;
        let gy = (z[q + k] - z[q]) / sy;
        let g2 = gx * gx + gy * gy;
        if g2.is_nan() { [0.0, 0.0] } else { [1.0, g2] }
    });
    if n < MIN_MEASURED as f64 {
        f64::NAN
    } else {
        (sum / n).sqrt()
    }
}

/// ⟨(∇²h/2)²⟩^½ with central second differences at step k (NaN for < 4
/// values).
fn rms_half_laplacian(z: &[f64], (nx, ny): (usize, usize), k: usize, dx_m: f64, dy_m: f64) -> f64 {
    let (rows, cols) = (
        nx.saturating_sub(k.saturating_mul(2)),
        ny.saturating_sub(k.saturating_mul(2)),
    );
    let (sx2, sy2) = ((k as f64 * dx_m).powi(2), (k as f64 * dy_m).powi(2));
    let [n, sum] = hypercontact_numeric::reduce::sums(rows * cols, |p| {
        let q = (p / cols + k) * ny + p % cols + k;
        let d2x = (z[q + k * ny] - 2.0 * z[q] + z[q - k * ny]) / sx2;
        let d2y = (z[q + k] - 2.0 * z[q] + z[q - k]) / sy2;
        let kappa = (d2x + d2y) / 2.0;
        if kappa.is_nan() {
            [0.0, 0.0]
        } else {
            [1.0, kappa * kappa]
        }
    });
    if n < MIN_MEASURED as f64 {
        f64::NAN
    } else {
        (sum / n).sqrt()
    }
}

/// The rms slope (dimensionless) at each lag of `lags` (pixels), scale
/// k·(Δx + Δy)/2; see the module doc.
pub fn scale_dependent_slope(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    lags: &[usize],
) -> Result<ScaleSeries, SurfaceError> {
    scale_dependent(
        h,
        (dx_m, dy_m),
        lags,
        Derivative::Slope,
        "the scale-dependent slope",
    )
}

/// The rms curvature ∇²h/2 (1/m) at each lag of `lags` (pixels), scale
/// 2k·(Δx + Δy)/2; see the module doc.
pub fn scale_dependent_curvature(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    lags: &[usize],
) -> Result<ScaleSeries, SurfaceError> {
    scale_dependent(
        h,
        (dx_m, dy_m),
        lags,
        Derivative::Curvature,
        "the scale-dependent curvature",
    )
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use super::*;

    /// h = A sin(qx): at lag k the upwind difference's rms is
    /// A·q·|sinc(qkΔx/2)|/√2 and the half Laplacian's is
    /// A·(2 sin(qkΔx/2)/(kΔx))²/2/√2 (the stencils' transfer functions),
    /// over whole periods.
    #[test]
    fn a_sinusoid_at_every_lag_has_the_stencils_transfer_function() {
        let (amplitude, period, dx, dy) = (1e-6, 48usize, 0.5e-6, 0.7e-6);
        let q = TAU / (period as f64 * dx);
        // the x range after trimming is whole periods for these lags
        let lags = [1usize, 2, 3, 4, 6, 8, 12];
        for &k in &lags {
            let rows = 4 * period + k;
            let h = Array2::from_shape_fn((rows, k + 3), |(i, _)| {
                amplitude * (q * i as f64 * dx).sin()
            });
            let slope = scale_dependent_slope(&h, dx, dy, &[k]).unwrap();
            let half = q * k as f64 * dx / 2.0;
            let expected = amplitude * q * (half.sin() / half).abs() / 2f64.sqrt();
            assert!((slope.value[0] / expected - 1.0).abs() < 1e-10, "{k}");
            assert!((slope.scale_m[0] - k as f64 * (dx + dy) / 2.0).abs() < 1e-18);
            let h = Array2::from_shape_fn((4 * period + 2 * k, 2 * k + 3), |(i, _)| {
                amplitude * (q * i as f64 * dx).sin()
            });
            let curvature = scale_dependent_curvature(&h, dx, dy, &[k]).unwrap();
            let laplacian = (2.0 * half.sin() / (k as f64 * dx)).powi(2);
            let expected = amplitude * laplacian / 2.0 / 2f64.sqrt();
            assert!((curvature.value[0] / expected - 1.0).abs() < 1e-9, "{k}");
            assert!((curvature.scale_m[0] - 2.0 * k as f64 * (dx + dy) / 2.0).abs() < 1e-18);
        }
    }

    /// A paraboloid h = (x² + y²)/2 has ∇²h/2 = 1 everywhere and
    /// |∇h| = r: the curvature histogram is one spike, the slope histogram
    /// spans the radii of the interior points.
    #[test]
    fn histograms_of_a_paraboloid_and_of_heights() {
        let d = 0.1;
        let h = Array2::from_shape_fn((21, 21), |(i, j)| {
            let (x, y) = ((i as f64 - 10.0) * d, (j as f64 - 10.0) * d);
            (x * x + y * y) / 2.0
        });
        let curvature = curvature_histogram(&h, d, d, 5).unwrap();
        assert_eq!(curvature.counts.iter().sum::<u64>(), 19 * 19);
        assert!(curvature.edges.iter().all(|e| (e - 1.0).abs() < 1e-9));
        let slope = slope_histogram(&h, d, d, 4).unwrap();
        assert_eq!(slope.counts.iter().sum::<u64>(), 19 * 19);
        assert!(slope.edges[0].abs() < 1e-12);
        assert!((slope.edges[4] - (0.9f64 * 0.9 * 2.0).sqrt()).abs() < 1e-12);
        // heights −1, 0, 0, 1 around their mean 0, three bins
        let flat = Array2::from_shape_vec((2, 2), vec![-1.0, 0.0, 0.0, 1.0]).unwrap();
        let heights = height_histogram(&flat, 3).unwrap();
        assert_eq!(heights.counts, vec![1, 2, 1]);
        assert_eq!(heights.edges.len(), 4);
        assert!(height_histogram(&flat, 0).is_err());
        assert!(
            slope_histogram(&flat, d, d, 3).is_err(),
            "no interior point"
        );
    }

    #[test]
    fn ladders_and_bad_lags() {
        assert_eq!(lag_ladder(100, 40), vec![1, 2, 4, 8, 16]);
        assert!(lag_ladder(2, 2).is_empty());
        let h = Array2::from_shape_fn((8, 8), |(i, j)| (i * j) as f64);
        assert!(scale_dependent_slope(&h, 1.0, 1.0, &[0]).is_err());
        let far = scale_dependent_slope(&h, 1.0, 1.0, &[7, 8]).unwrap();
        assert!(far.value.iter().all(|v| v.is_nan()), "fewer than 4 values");
        let far = scale_dependent_curvature(&h, 1.0, 1.0, &[4, usize::MAX]).unwrap();
        assert!(far.value.iter().all(|v| v.is_nan()));
        let far = scale_dependent_slope(&h, 1.0, 1.0, &[usize::MAX]).unwrap();
        assert!(far.value[0].is_nan());
        let e = height_histogram(&h, usize::MAX).unwrap_err().to_string();
        assert!(e.contains("bins: a histogram has 1 … 1048576"), "{e}");
    }
}
