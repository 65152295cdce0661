//! Scalar statistics of a height map, NaN-aware: σ is the areal rms height
//! Sq about the mean of the measured points (not the profile-wise Rq), and
//! the rms slope is √⟨|∇h|²⟩ with forward differences over pairs of measured
//! neighbours (SurfaceTopography's `rms_gradient` on a non-periodic map).

use ndarray::Array2;

/// Areal rms height about the mean of the measured points; NaN if none.
pub fn sigma(h: &Array2<f64>) -> f64 {
    let (mut n, mut sum) = (0usize, 0.0);
    for &v in h.iter().filter(|v| !v.is_nan()) {
        n += 1;
        sum += v;
    }
    let mean = sum / n as f64;
    let sq: f64 = h
        .iter()
        .filter(|v| !v.is_nan())
        .map(|v| (v - mean).powi(2))
        .sum();
    (sq / n as f64).sqrt()
}

/// rms of the gradient: ⟨(∂h/∂x)²⟩ + ⟨(∂h/∂y)²⟩, each mean over the
/// forward differences whose two points are measured.
pub fn rms_slope(h: &Array2<f64>, dx_m: f64, dy_m: f64) -> f64 {
    let (nx, ny) = h.dim();
    let mean_sq = |pairs: &mut dyn Iterator<Item = (f64, f64)>, d: f64| {
        let (mut n, mut s) = (0usize, 0.0);
        for (a, b) in pairs {
            if !a.is_nan() && !b.is_nan() {
                n += 1;
                s += ((b - a) / d).powi(2);
            }
        }
        if n == 0 { 0.0 } else { s / n as f64 }
    };
    let gx = mean_sq(
        &mut (0..nx.saturating_sub(1))
            .flat_map(|i| (0..ny).map(move |j| (i, j)))
            .map(|(i, j)| (h[[i, j]], h[[i + 1, j]])),
        dx_m,
    );
    let gy = mean_sq(
        &mut (0..nx)
            .flat_map(|i| (0..ny.saturating_sub(1)).map(move |j| (i, j)))
            .map(|(i, j)| (h[[i, j]], h[[i, j + 1]])),
        dy_m,
    );
    (gx + gy).sqrt()
}

/// The height a map is measured from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reference {
    /// The lowest measured point (the paper's choice): every z ≥ 0.
    Lowest,
    /// The given percentile (0…100) of the measured heights.
    Percentile(f64),
}

/// The reference height of the measured points (linear interpolation
/// between order statistics for percentiles, numpy's default).
pub fn reference_height(h: &Array2<f64>, reference: Reference) -> f64 {
    let mut v: Vec<f64> = h.iter().copied().filter(|v| !v.is_nan()).collect();
    match reference {
        Reference::Lowest => v.iter().copied().fold(f64::INFINITY, f64::min),
        Reference::Percentile(p) => {
            v.sort_by(f64::total_cmp);
            let rank = p / 100.0 * (v.len() as f64 - 1.0);
            let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
            v[lo] + (v[hi] - v[lo]) * (rank - lo as f64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigma_slope_and_reference_of_known_maps() {
        // A ramp h = s·x·dx has rms slope |s| and σ of a uniform spread.
        let (n, dx, s) = (101, 1e-6, 0.02);
        let ramp = Array2::from_shape_fn((n, 7), |(i, _)| s * i as f64 * dx);
        assert!((rms_slope(&ramp, dx, dx) - s).abs() < 1e-12);
        // σ of n equally spaced values over a span: span·√((n²−1)/12)/(n−1).
        let span = s * (n - 1) as f64 * dx;
        let expected = span * (((n * n - 1) as f64) / 12.0).sqrt() / (n - 1) as f64;
        assert!((sigma(&ramp) / expected - 1.0).abs() < 1e-12);
        assert_eq!(reference_height(&ramp, Reference::Lowest), 0.0);
        let median = reference_height(&ramp, Reference::Percentile(50.0));
        assert!((median - span / 2.0).abs() < 1e-15);
    }

    #[test]
    fn nan_points_are_left_out() {
        let mut h =
            Array2::from_shape_fn((4, 4), |(i, j)| if (i + j) % 2 == 0 { 1.0 } else { -1.0 });
        h[[0, 0]] = f64::NAN;
        h[[0, 1]] = f64::NAN;
        assert!((sigma(&h) - 1.0).abs() < 1e-12);
        assert_eq!(reference_height(&h, Reference::Lowest), -1.0);
    }
}
