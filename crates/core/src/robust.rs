//! Robust location and scale of a sample: the median, and the standard
//! deviation estimated from the median absolute deviation (MAD), neither
//! thrown by a few wild values.

/// The median (the mean of the middle two for an even count); NaN for an
/// empty sample.
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// (median, 1.4826 × MAD): 1.4826 scales the MAD to σ for Gaussian scatter
/// (1 / Φ⁻¹(3/4); Rousseeuw & Croux, JASA 88, 1993).
pub fn median_and_sigma(values: &[f64]) -> (f64, f64) {
    let centre = median(values);
    let deviations: Vec<f64> = values.iter().map(|v| (v - centre).abs()).collect();
    (centre, 1.4826 * median(&deviations))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_mad_sigma_by_hand() {
        assert_eq!(median(&[3.0, 1.0, 2.0, 10.0]), 2.5);
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert!(median(&[]).is_nan());
        // ±1 about 0: MAD 1; one wild value among five moves neither.
        assert_eq!(
            median_and_sigma(&[-1.0, 1.0, 0.0, -1.0, 1.0]),
            (0.0, 1.4826)
        );
        assert_eq!(
            median_and_sigma(&[-1.0, 1.0, 0.0, -1.0, 100.0]),
            (0.0, 1.4826)
        );
    }
}
