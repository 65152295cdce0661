//! Piecewise-linear interpolation of a sampled curve, used to read
//! F/(E0* A0) at a given A/A0 for the summary table.

/// y(x_at) by linear interpolation between the bracketing samples of a
/// curve sorted by x (ascending). Outside the sampled range it returns None
/// rather than extrapolating: a summary number must come from the data.
/// Where x repeats (a plateau of A/A0 over several levels), the first
/// sample with that x wins, which is the smallest load on the plateau.
pub fn interpolate(xs: &[f64], ys: &[f64], x_at: f64) -> Option<f64> {
    let n = xs.len().min(ys.len());
    if n == 0 || !x_at.is_finite() || x_at < xs[0] || x_at > xs[n - 1] {
        return None;
    }
    // First index with xs[i] >= x_at.
    let hi = xs[..n].partition_point(|&x| x < x_at);
    if xs[hi] == x_at {
        return Some(ys[hi]);
    }
    let lo = hi - 1;
    let t = (x_at - xs[lo]) / (xs[hi] - xs[lo]);
    Some(ys[lo] + t * (ys[hi] - ys[lo]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_linear_function_between_samples() {
        let xs = [0.0, 0.3, 0.7, 1.0];
        let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x + 1.0).collect();
        for x in [0.0, 0.1, 0.5, 0.95, 1.0] {
            assert!((interpolate(&xs, &ys, x).unwrap() - (2.0 * x + 1.0)).abs() < 1e-12);
        }
    }

    #[test]
    fn outside_the_range_is_none() {
        let xs = [0.2, 0.4];
        let ys = [1.0, 2.0];
        assert_eq!(interpolate(&xs, &ys, 0.1), None);
        assert_eq!(interpolate(&xs, &ys, 0.5), None);
        assert_eq!(interpolate(&[], &[], 0.5), None);
        assert_eq!(interpolate(&xs, &ys, f64::NAN), None);
    }

    #[test]
    fn a_plateau_takes_its_first_sample() {
        let xs = [0.0, 0.5, 0.5, 1.0];
        let ys = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(interpolate(&xs, &ys, 0.5), Some(1.0));
        // Just above the plateau, the segment from its last sample is used.
        assert!((interpolate(&xs, &ys, 0.75).unwrap() - 2.5).abs() < 1e-12);
    }
}
