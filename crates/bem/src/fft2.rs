//! Cyclic 2-D convolution of a real map with a real, even kernel by FFTs, on
//! a transform grid at least as large as the map (the rest zero: Hockney's
//! padding for the free surface, none for a periodic one), on the
//! workspace's one FFT ([`hypercontact_numeric::fft2::RealFft2`]).
//!
//! Layout: maps are row-major with axis 1 (y) contiguous, as `Field` holds
//! them: the real transforms run along y, the complex ones along x. An even
//! kernel (k[i, j] = k[−i, −j] cyclically) has a real spectrum, which is
//! kept real and divided by mx · my once, so a convolution is a forward
//! transform, one real factor per frequency (applied a strip of columns at
//! a time while it is in cache) and an inverse transform with no further
//! scaling. The same bits on any number of threads (see the FFT's module).

use hypercontact_numeric::fft2::{Complex64, RealFft2, RealWorkspace};

/// The FFT plans for one map size and one transform size.
pub struct Fft2 {
    nx: usize,
    ny: usize,
    fft: RealFft2,
}

/// How a convolution uses the kernel's spectrum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factor {
    /// by the kernel: `kernel ⊛ input`
    Multiply,
    /// by its inverse (0 where the spectrum is 0): the kernel's
    /// (pseudo-)inverse applied to the input
    Divide,
}

/// Buffers one convolution needs, kept between calls.
pub struct Workspace(RealWorkspace);

impl Fft2 {
    /// Plans for an `nx × ny` map on an `mx × my` transform grid
    /// (`mx ≥ nx`, `my ≥ ny`).
    pub fn new(nx: usize, ny: usize, mx: usize, my: usize) -> Self {
        assert!(nx >= 1 && ny >= 1 && mx >= nx && my >= ny);
        let fft = RealFft2::new(mx, my).expect("the grid is at least 1 × 1");
        Self { nx, ny, fft }
    }

    /// The transform grid, (mx, my).
    pub fn transform_size(&self) -> (usize, usize) {
        self.fft.grid()
    }

    /// Points of a spectrum (see [`Fft2::spectrum`]): (my / 2 + 1) · mx.
    pub fn spectrum_len(&self) -> usize {
        self.fft.spectrum_len()
    }

    pub fn workspace(&self) -> Workspace {
        Workspace(self.fft.workspace())
    }

    /// The real part of the DFT of a full `mx × my` real array, divided by
    /// mx · my so that [`Fft2::convolve`] needs no further scaling; index
    /// `jy · mx + ix`. For an even kernel the imaginary part is zero up to
    /// rounding.
    pub fn spectrum(&self, full: Vec<f64>) -> Vec<f64> {
        let (mx, my) = self.fft.grid();
        assert_eq!(full.len(), mx * my);
        let mut spectrum = vec![Complex64::ZERO; self.spectrum_len()];
        let mut work = self.fft.workspace();
        self.fft
            .forward(&full, (mx, my), &mut spectrum, &mut work)
            .expect("the kernel fills the grid");
        // At 4096² each buffer is 134 MB: freed before the real part is made.
        drop((full, work));
        let scale = 1.0 / (mx * my) as f64;
        spectrum.iter().map(|c| c.re * scale).collect()
    }

    /// `output = (kernel ⊛ input)` (or the inverse operation, see
    /// [`Factor`]) restricted to the map, where `input` and `output` are
    /// `nx × ny` maps (zero beyond them on the transform grid) and `spectrum`
    /// comes from [`Fft2::spectrum`].
    pub fn convolve(
        &self,
        input: &[f64],
        spectrum: &[f64],
        factor: Factor,
        output: &mut [f64],
        work: &mut Workspace,
    ) {
        assert_eq!(spectrum.len(), self.spectrum_len());
        let (mx, my) = self.fft.grid();
        // The spectrum carries 1/(mx my) once; its inverse must too.
        let inverse_scale = ((mx * my) as f64).powi(-2);
        let apply = |offset: usize, strip: &mut [Complex64]| {
            let spectrum = &spectrum[offset..offset + strip.len()];
            match factor {
                Factor::Multiply => {
                    for (c, &s) in strip.iter_mut().zip(spectrum) {
                        *c *= s;
                    }
                }
                Factor::Divide => {
                    for (c, &s) in strip.iter_mut().zip(spectrum) {
                        *c *= if s > 0.0 { inverse_scale / s } else { 0.0 };
                    }
                }
            }
        };
        self.fft
            .convolve(input, (self.nx, self.ny), output, 1.0, &mut work.0, apply)
            .expect("input and output are nx × ny maps");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A direct cyclic convolution on the transform grid, cut to the map.
    fn direct(
        kernel: &[f64],
        input: &[f64],
        (nx, ny): (usize, usize),
        (mx, my): (usize, usize),
    ) -> Vec<f64> {
        let mut out = vec![0.0; nx * ny];
        for i in 0..nx {
            for j in 0..ny {
                let mut s = 0.0;
                for k in 0..nx {
                    for l in 0..ny {
                        let di = (i + mx - k) % mx;
                        let dj = (j + my - l) % my;
                        s += kernel[di * my + dj] * input[k * ny + l];
                    }
                }
                out[i * ny + j] = s;
            }
        }
        out
    }

    /// An even kernel on the transform grid: a function of the wrapped
    /// distances.
    fn even_kernel(mx: usize, my: usize) -> Vec<f64> {
        let wrap = |i: usize, m: usize| {
            if i <= m / 2 {
                i as f64
            } else {
                i as f64 - m as f64
            }
        };
        (0..mx * my)
            .map(|k| {
                let (x, y) = (wrap(k / my, mx), wrap(k % my, my));
                1.0 / (1.0 + x * x + 0.5 * y * y) + 0.1 * (x * y).cos()
            })
            .collect()
    }

    #[test]
    fn convolution_matches_the_direct_sum_padded_and_periodic() {
        for (nx, ny, mx, my) in [(5, 7, 10, 14), (6, 4, 12, 10), (5, 7, 5, 7), (8, 6, 8, 6)] {
            let kernel = even_kernel(mx, my);
            let input: Vec<f64> = (0..nx * ny).map(|k| ((k * 37) % 11) as f64 - 4.0).collect();
            let fft = Fft2::new(nx, ny, mx, my);
            let spectrum = fft.spectrum(kernel.clone());
            let mut out = vec![0.0; nx * ny];
            let mut work = fft.workspace();
            fft.convolve(&input, &spectrum, Factor::Multiply, &mut out, &mut work);
            let expected = direct(&kernel, &input, (nx, ny), (mx, my));
            for (a, b) in out.iter().zip(&expected) {
                assert!(
                    (a - b).abs() < 1e-12 * 100.0,
                    "{nx}×{ny} on {mx}×{my}: {a} vs {b}"
                );
            }
            // A second call with the same workspace gives the same bits.
            let mut again = vec![0.0; nx * ny];
            fft.convolve(&input, &spectrum, Factor::Multiply, &mut again, &mut work);
            assert_eq!(out, again);
            // On a periodic grid, dividing by a positive spectrum undoes
            // multiplying by it: 2 + ½ cos qx + ½ cos qy ≥ 1.
            if mx == nx && my == ny {
                let mut positive = vec![0.0; mx * my];
                positive[0] = 2.0;
                for k in [my, (mx - 1) * my, 1, my - 1] {
                    positive[k] += 0.25;
                }
                let spectrum = fft.spectrum(positive);
                let (mut there, mut back) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
                fft.convolve(&input, &spectrum, Factor::Multiply, &mut there, &mut work);
                fft.convolve(&there, &spectrum, Factor::Divide, &mut back, &mut work);
                for (a, b) in back.iter().zip(&input) {
                    assert!((a - b).abs() < 1e-12, "{a} vs {b}");
                }
            }
        }
    }
}
