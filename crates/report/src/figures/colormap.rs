//! The viridis colour map (perceptually uniform, readable in grey and by
//! colour-blind readers), for height maps. Anchors every 0.1 are the sRGB
//! values of matplotlib's viridis; in between, linear interpolation.

use plotters::style::RGBColor;

const VIRIDIS: [(u8, u8, u8); 11] = [
    (68, 1, 84),
    (72, 36, 117),
    (65, 68, 135),
    (53, 95, 141),
    (42, 120, 142),
    (33, 145, 140),
    (34, 168, 132),
    (68, 191, 112),
    (122, 209, 81),
    (189, 223, 38),
    (253, 231, 37),
];

/// Colour of missing (NaN) points.
pub const MISSING: RGBColor = RGBColor(200, 200, 200);

/// The colour of `t` in [0, 1] (clamped); NaN gives [`MISSING`].
pub fn viridis(t: f64) -> RGBColor {
    if t.is_nan() {
        return MISSING;
    }
    let pos = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (pos.floor() as usize).min(VIRIDIS.len() - 2);
    let f = pos - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_anchors_and_missing() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(0.5), RGBColor(33, 145, 140));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), MISSING);
        // Halfway between two anchors is their mean.
        assert_eq!(viridis(0.95), RGBColor(221, 227, 38));
    }

    #[test]
    fn lightness_increases_monotonically() {
        let luma = |c: RGBColor| 0.299 * c.0 as f64 + 0.587 * c.1 as f64 + 0.114 * c.2 as f64;
        let mut last = -1.0;
        for i in 0..=100 {
            let l = luma(viridis(i as f64 / 100.0));
            assert!(l >= last, "lightness drops at {i}");
            last = l;
        }
    }
}
