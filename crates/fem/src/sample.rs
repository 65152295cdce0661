//! A deterministic rough test surface, written so that another code (the
//! felupe comparison) can rebuild it exactly: a sum of cosines over the
//! wave vectors q = 2π (m, n)/L of the patch (0 < |m|, |n| ≤ `modes`,
//! one of each ±q pair), amplitudes ∝ |q|^(−(1 + H)) (a self-affine
//! spectrum C(q) ∝ q^(−2(1+H)), Persson's 2-D convention), phases from
//! Knuth's MMIX linear congruential generator, scaled to the rms height
//! asked for.

/// The surface's recipe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleSurface {
    pub nx: usize,
    pub ny: usize,
    pub pixel_m: f64,
    pub rms_m: f64,
    pub hurst: f64,
    /// Largest |m|, |n|: the shortest wavelength is the patch size / modes.
    pub modes: usize,
    pub seed: u64,
}

/// MMIX: state ← 6364136223846793005 state + 1442695040888963407 (mod 2⁶⁴);
/// a phase is the top 53 bits as a fraction of 2π.
fn next_phase(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*state >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU
}

impl SampleSurface {
    /// `heights_m` (these heights, or an edit of them) on this surface's
    /// grid of square pixels.
    pub fn on_grid<'a>(&self, heights_m: &'a [f64]) -> crate::HeightMap<'a> {
        crate::HeightMap {
            heights_m,
            nx: self.nx,
            ny: self.ny,
            dx_m: self.pixel_m,
            dy_m: self.pixel_m,
        }
    }

    /// Heights at `i * ny + j`, m, with zero mean over the modes.
    pub fn heights_m(&self) -> Vec<f64> {
        let (lx, ly) = (self.nx as f64 * self.pixel_m, self.ny as f64 * self.pixel_m);
        let modes = self.modes as i64;
        let mut state = self.seed;
        let mut waves = Vec::new();
        for m in 0..=modes {
            for n in -modes..=modes {
                if m == 0 && n <= 0 {
                    continue;
                }
                let (qx, qy) = (
                    std::f64::consts::TAU * m as f64 / lx,
                    std::f64::consts::TAU * n as f64 / ly,
                );
                let q = qx.hypot(qy);
                waves.push((qx, qy, q.powf(-(1.0 + self.hurst)), next_phase(&mut state)));
            }
        }
        let power: f64 = waves.iter().map(|w| 0.5 * w.2 * w.2).sum();
        let scale = self.rms_m / power.sqrt();
        let mut heights = Vec::with_capacity(self.nx * self.ny);
        for i in 0..self.nx {
            for j in 0..self.ny {
                let (x, y) = (i as f64 * self.pixel_m, j as f64 * self.pixel_m);
                heights.push(
                    waves
                        .iter()
                        .map(|(qx, qy, a, phase)| scale * a * (qx * x + qy * y + phase).cos())
                        .sum(),
                );
            }
        }
        heights
    }
}

/// The rms slope √⟨|∇h|²⟩ of heights at `i * ny + j` on a periodic grid of
/// square pixels, the gradient by central differences (wrapping at the
/// edges: a [`SampleSurface`] is periodic over nx × ny pixels).
pub fn rms_slope(heights_m: &[f64], nx: usize, ny: usize, pixel_m: f64) -> f64 {
    let at = |i: usize, j: usize| heights_m[(i % nx) * ny + j % ny];
    let mut sum = 0.0;
    for i in 0..nx {
        for j in 0..ny {
            let gx = (at(i + 1, j) - at(i + nx - 1, j)) / (2.0 * pixel_m);
            let gy = (at(i, j + 1) - at(i, j + ny - 1)) / (2.0 * pixel_m);
            sum += gx * gx + gy * gy;
        }
    }
    (sum / (nx * ny) as f64).sqrt()
}

impl SampleSurface {
    /// This surface with `rms_m` scaled so that its [`rms_slope`] is
    /// `slope` (heights are linear in `rms_m`).
    pub fn with_rms_slope(self, slope: f64) -> Self {
        let unit = Self { rms_m: 1.0, ..self };
        let measured = rms_slope(&unit.heights_m(), self.nx, self.ny, self.pixel_m);
        Self {
            rms_m: slope / measured,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rms_and_determinism() {
        let s = SampleSurface {
            nx: 64,
            ny: 64,
            pixel_m: 20e-6,
            rms_m: 5e-6,
            hurst: 0.8,
            modes: 8,
            seed: 7,
        };
        let h = s.heights_m();
        // On the full periodic grid the cosines are orthogonal: rms exact.
        let rms = (h.iter().map(|v| v * v).sum::<f64>() / h.len() as f64).sqrt();
        assert!((rms / 5e-6 - 1.0).abs() < 1e-12, "{rms}");
        assert_eq!(h, s.heights_m());
        assert_ne!(h, SampleSurface { seed: 8, ..s }.heights_m());
    }

    #[test]
    fn rms_slope_of_a_cosine_is_its_central_difference_amplitude() {
        // h = a cos(q x), q = 2π m / (n dx): the central difference of the
        // cosine is −a sin(q dx)/dx · sin(q x), whose mean square over whole
        // periods is half its amplitude squared.
        let (n, dx, a, m) = (16, 2e-6, 3e-7, 3.0);
        let q = std::f64::consts::TAU * m / (n as f64 * dx);
        let h: Vec<f64> = (0..n)
            .flat_map(|i| (0..n).map(move |_| a * (q * i as f64 * dx).cos()))
            .collect();
        let expected = a * (q * dx).sin() / dx / 2f64.sqrt();
        let slope = rms_slope(&h, n, n, dx);
        assert!(
            (slope / expected - 1.0).abs() < 1e-12,
            "{slope} vs {expected}"
        );
    }

    #[test]
    fn scaled_to_an_rms_slope() {
        let s = SampleSurface {
            nx: 10,
            ny: 12,
            pixel_m: 20e-6,
            rms_m: 1e-6,
            hurst: 0.8,
            modes: 3,
            seed: 5,
        }
        .with_rms_slope(0.3);
        let slope = rms_slope(&s.heights_m(), 10, 12, 20e-6);
        assert!((slope / 0.3 - 1.0).abs() < 1e-12, "{slope}");
    }
}
