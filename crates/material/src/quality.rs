//! How well a model reproduces tensile data, per mode and over all points:
//! R² of the stresses, and RMS and largest relative error (relative to
//! max(|T|, 1 % of the mode's largest |T|), as the fit measures it).

use crate::tensile::TensileData;
use crate::{Hyperelastic, Mode};

/// The quality of a model on one mode (or all modes when `mode` is None).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    pub mode: Option<Mode>,
    pub r2: f64,
    pub rms_rel_err: f64,
    pub max_rel_err: f64,
    pub n_points: usize,
}

impl Quality {
    pub fn label(&self) -> &'static str {
        self.mode.map_or("all", Mode::label)
    }
}

#[derive(Default)]
struct Sums {
    n: usize,
    rel2: f64,
    max_rel: f64,
    measured: Vec<f64>,
    squared_error: f64,
}

impl Sums {
    fn finish(self, mode: Option<Mode>) -> Quality {
        let n = self.n as f64;
        let mean = self.measured.iter().sum::<f64>() / n;
        let total: f64 = self.measured.iter().map(|t| (t - mean).powi(2)).sum();
        Quality {
            mode,
            r2: 1.0 - self.squared_error / total,
            rms_rel_err: (self.rel2 / n).sqrt(),
            max_rel_err: self.max_rel,
            n_points: self.n,
        }
    }
}

/// Per-mode quality (modes present in the data, in the order UT, PT, BT)
/// followed by the quality over all points.
pub fn quality(model: &dyn Hyperelastic, data: &TensileData) -> Vec<Quality> {
    let mut all = Sums::default();
    let mut out = Vec::new();
    for curve in &data.curves {
        let mut sums = Sums::default();
        let scales = curve.relative_scales_pa();
        for ((&stretch, &measured), scale) in curve.stretch.iter().zip(&curve.stress_pa).zip(scales)
        {
            let fitted = model.nominal_stress_pa(curve.mode, stretch);
            let rel = ((fitted - measured) / scale).abs();
            for s in [&mut sums, &mut all] {
                s.n += 1;
                s.rel2 += rel * rel;
                s.max_rel = s.max_rel.max(rel);
                s.measured.push(measured);
                s.squared_error += (fitted - measured).powi(2);
            }
        }
        out.push(sums.finish(Some(curve.mode)));
    }
    out.push(all.finish(None));
    out
}

/// The RMS relative error over all points.
pub fn total_rms_rel_err(model: &dyn Hyperelastic, data: &TensileData) -> f64 {
    quality(model, data)
        .last()
        .map_or(f64::NAN, |q| q.rms_rel_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NeoHookean;
    use crate::tensile::TensileCurve;

    #[test]
    fn a_known_misfit_gives_known_numbers() {
        let m = NeoHookean::new(0.5e6).unwrap();
        let stretch = vec![1.5, 2.0];
        let exact: Vec<f64> = stretch
            .iter()
            .map(|&l| m.nominal_stress_pa(Mode::Uniaxial, l))
            .collect();
        // Measured 10 % above and 10 % below the model.
        let measured = vec![exact[0] / 0.9, exact[1] / 1.1];
        let data = TensileData {
            curves: vec![TensileCurve {
                mode: Mode::Uniaxial,
                stretch,
                stress_pa: measured.clone(),
            }],
        };
        let q = quality(&m, &data);
        assert_eq!(q.len(), 2);
        assert_eq!(q[0].label(), "UT");
        assert!((q[0].max_rel_err - 0.1).abs() < 1e-12);
        assert!((q[0].rms_rel_err - 0.1).abs() < 1e-12);
        let mean = (measured[0] + measured[1]) / 2.0;
        let r2 = 1.0
            - ((exact[0] - measured[0]).powi(2) + (exact[1] - measured[1]).powi(2))
                / ((measured[0] - mean).powi(2) + (measured[1] - mean).powi(2));
        assert!((q[0].r2 - r2).abs() < 1e-12);
        assert_eq!(q[1].label(), "all");
        assert_eq!(q[1].n_points, 2);
    }
}
