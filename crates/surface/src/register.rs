//! Sub-pixel registration of two overlapping patches by phase correlation
//! (Kuglin & Hines 1975): the normalised cross-power spectrum
//! R = A·B*/|A·B*| of two patches whose contents differ by a shift e has the
//! inverse transform δ(u − e). The integer peak is refined to sub-pixel
//! precision by Newton's method on the continuous band-limited correlation
//! r(s) = Σ_k Re(R_k e^{iω_k·s}), whose maximum is at e exactly for a pure
//! shift (Foroosh et al., IEEE TIP 11, 188, 2002, use the same surface).
//!
//! Patches are prepared as heights usually are for registration: gaps
//! filled with the mean, a least-squares plane removed (tiles differ by
//! tilt and piston), and a Hann taper against edge leakage.

use std::f64::consts::TAU;

use hypercontact_numeric::fft2::{Complex64, ComplexFft2, Direction};
use nalgebra::{Matrix5, Vector5};
use ndarray::ArrayView2;

use crate::plane;

/// The shift found between two patches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Registration {
    /// e such that b(u) ≈ a(u + e), pixels.
    pub shift_px: [f64; 2],
    /// Height of the phase-correlation peak, 1 for identical content.
    pub peak: f64,
}

/// Gap-filled, plane-removed, Hann-tapered patch as a complex buffer.
fn prepare(p: ArrayView2<f64>) -> Option<Vec<Complex64>> {
    let (nx, ny) = p.dim();
    let mut h = p.to_owned();
    let plane = plane::fit_plane(&h)?;
    plane::subtract(&mut h, &plane);
    let taper = |i: usize, n: usize| 0.5 - 0.5 * (TAU * (i as f64 + 0.5) / n as f64).cos();
    let wx: Vec<f64> = (0..nx).map(|i| taper(i, nx)).collect();
    let wy: Vec<f64> = (0..ny).map(|j| taper(j, ny)).collect();
    Some(
        h.indexed_iter()
            // After the plane fit the mean of measured points is zero.
            .map(|((i, j), &v)| {
                Complex64::new(if v.is_nan() { 0.0 } else { v * wx[i] * wy[j] }, 0.0)
            })
            .collect(),
    )
}

/// Signed frequency index of FFT bin k on n points; None at the even Nyquist
/// bin, whose sign is ambiguous.
fn signed(k: usize, n: usize) -> Option<f64> {
    if 2 * k == n {
        None
    } else if k > n / 2 {
        Some(k as f64 - n as f64)
    } else {
        Some(k as f64)
    }
}

/// The normalised cross-power spectrum of two patches of one shape.
struct CrossPower {
    nx: usize,
    ny: usize,
    fft: ComplexFft2,
    /// A·B*, unnormalised.
    raw: Vec<Complex64>,
}

impl CrossPower {
    fn new(a: ArrayView2<f64>, b: ArrayView2<f64>) -> Option<Self> {
        let (nx, ny) = a.dim();
        if b.dim() != (nx, ny) || nx < 4 || ny < 4 {
            return None;
        }
        let fft = ComplexFft2::new(nx, ny).ok()?;
        let mut fa = prepare(a)?;
        let mut fb = prepare(b)?;
        fft.process(&mut fa, Direction::Forward).ok()?;
        fft.process(&mut fb, Direction::Forward).ok()?;
        let raw = fa.iter().zip(&fb).map(|(x, y)| x * y.conj()).collect();
        Some(Self { nx, ny, fft, raw })
    }

    /// A·B* / |A·B*|^power.
    fn whitened(&self, power: f64) -> Vec<Complex64> {
        self.raw
            .iter()
            .map(|c| {
                let m = c.norm();
                if m > 0.0 {
                    c / m.powf(power)
                } else {
                    Complex64::default()
                }
            })
            .collect()
    }

    /// The correlation surface: real part of the inverse transform of the
    /// spectrum whitened to `power` (1: phase correlation, 1 at a perfect
    /// match; 0: plain cross-correlation). (None only if the plan refused
    /// the spectrum, which has the patches' shape.)
    fn surface(&self, power: f64) -> Option<Vec<f64>> {
        let mut cross = self.whitened(power);
        self.fft.process(&mut cross, Direction::Inverse).ok()?;
        let n = (self.nx * self.ny) as f64;
        Some(cross.iter().map(|v| v.re / n).collect())
    }
}

/// Index k of an FFT of n points as a shift in (−n/2, n/2].
fn wrap(k: usize, n: usize) -> i64 {
    if k > n / 2 {
        k as i64 - n as i64
    } else {
        k as i64
    }
}

/// The `count` highest local maxima of the phase-correlation surface of two
/// patches, highest first: integer shifts e (b(u) ≈ a(u + e)) in
/// (−n/2, n/2] per axis, with their heights. A shift is only known modulo
/// the patch size; the caller may try e ± n where that is plausible.
/// Checking several peaks against the overlap's correlation is what makes
/// registration robust when the true peak is not the highest (Preibisch,
/// Saalfeld & Tomancak, Bioinformatics 25, 1463, 2009, do the same).
pub fn correlation_peaks(
    a: ArrayView2<f64>,
    b: ArrayView2<f64>,
    count: usize,
) -> Vec<([i64; 2], f64)> {
    let Some(cross) = CrossPower::new(a, b) else {
        return Vec::new();
    };
    let (nx, ny) = (cross.nx, cross.ny);
    // Half whitening: full whitening gives the many wavevectors beyond the
    // surface's short cut-off, where only noise and dropouts live, as much
    // say as those with signal, and the true peak can drown among theirs.
    let Some(r) = cross.surface(0.5) else {
        return Vec::new();
    };
    let at = |i: usize, j: usize| r[i * ny + j];
    let mut peaks: Vec<([i64; 2], f64)> = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            let v = at(i, j);
            let is_max = [
                (nx - 1, ny - 1),
                (nx - 1, 0),
                (nx - 1, 1),
                (0, ny - 1),
                (0, 1),
                (1, ny - 1),
                (1, 0),
                (1, 1),
            ]
            .iter()
            .all(|&(di, dj)| at((i + di) % nx, (j + dj) % ny) <= v);
            if is_max {
                peaks.push(([wrap(i, nx), wrap(j, ny)], v));
            }
        }
    }
    peaks.sort_by(|x, y| y.1.total_cmp(&x.1));
    peaks.truncate(count);
    peaks
}

/// Finds e with b(u) ≈ a(u + e) for two patches of one shape (NaN allowed).
/// None if a patch has fewer than three measured points.
pub fn phase_correlate(a: ArrayView2<f64>, b: ArrayView2<f64>) -> Option<Registration> {
    let cross = CrossPower::new(a, b)?;
    let (nx, ny) = (cross.nx, cross.ny);
    // The sub-pixel step weights each frequency by √|A·B*|: full whitening
    // gives the wavevectors without signal (beyond the surface's short
    // cut-off, or below the noise) as much say as the rest, and their random
    // phases would steer Newton's steps. Any positive weighting peaks at the
    // true shift of a pure translation.
    let spectrum = cross.whitened(0.5);
    let (best, peak) = cross
        .surface(1.0)?
        .into_iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(&y.1))?;
    let mut s = [wrap(best / ny, nx) as f64, wrap(best % ny, ny) as f64];

    // Newton on r(s) = Σ Re(R e^{i(ωx sx + ωy sy)}); the phasor factorises
    // per axis, so each iteration costs one pass over the spectrum.
    let omega_x: Vec<Option<f64>> = (0..nx)
        .map(|i| signed(i, nx).map(|k| TAU * k / nx as f64))
        .collect();
    let omega_y: Vec<Option<f64>> = (0..ny)
        .map(|j| signed(j, ny).map(|k| TAU * k / ny as f64))
        .collect();
    for _ in 0..20 {
        let phasor = |w: &Option<f64>, s: f64| w.map(|w| Complex64::from_polar(1.0, w * s));
        let px: Vec<Option<Complex64>> = omega_x.iter().map(|w| phasor(w, s[0])).collect();
        let py: Vec<Option<Complex64>> = omega_y.iter().map(|w| phasor(w, s[1])).collect();
        let mut grad = [0.0; 2];
        let mut hess = [[0.0; 2]; 2];
        for i in 0..nx {
            let (Some(wx), Some(ex)) = (omega_x[i], px[i]) else {
                continue;
            };
            for j in 0..ny {
                let (Some(wy), Some(ey)) = (omega_y[j], py[j]) else {
                    continue;
                };
                let v = spectrum[i * ny + j] * ex * ey;
                grad[0] -= v.im * wx;
                grad[1] -= v.im * wy;
                hess[0][0] -= v.re * wx * wx;
                hess[0][1] -= v.re * wx * wy;
                hess[1][1] -= v.re * wy * wy;
            }
        }
        hess[1][0] = hess[0][1];
        let det = hess[0][0] * hess[1][1] - hess[0][1] * hess[1][0];
        // Only a maximum (negative definite Hessian) is worth stepping to.
        if !(det > 0.0 && hess[0][0] < 0.0) {
            break;
        }
        let step = [
            -(hess[1][1] * grad[0] - hess[0][1] * grad[1]) / det,
            -(-hess[1][0] * grad[0] + hess[0][0] * grad[1]) / det,
        ];
        let step = step.map(|d| d.clamp(-0.5, 0.5));
        s = [s[0] + step[0], s[1] + step[1]];
        if step[0].abs().max(step[1].abs()) < 1e-6 {
            break;
        }
    }
    Some(Registration { shift_px: s, peak })
}

/// Cubic convolution kernel of Keys (IEEE TASSP 29, 1153, 1981), a = −½:
/// interpolates exactly through the samples and reproduces quadratics.
#[inline(always)]
fn keys(t: f64) -> f64 {
    let t = t.abs();
    if t < 1.0 {
        (1.5 * t - 2.5) * t * t + 1.0
    } else if t < 2.0 {
        ((-0.5 * t + 2.5) * t - 4.0) * t + 2.0
    } else {
        0.0
    }
}

/// The four weights `keys(t − k)` of the nodes k = first … first + 3.
/// Inlined by force: this is the hot loop of tile registration, and left to
/// itself the compiler sometimes keeps it out of line (+15 % per stage).
#[inline(always)]
fn keys_weights(t: f64, first: usize) -> [f64; 4] {
    [
        keys(t - first as f64),
        keys(t - (first + 1) as f64),
        keys(t - (first + 2) as f64),
        keys(t - (first + 3) as f64),
    ]
}

/// A cubic-convolution stencil along one axis: its first node and the four
/// weights.
type Stencil = (usize, [f64; 4]);

/// The cubic-convolution stencil along an axis of `n` points at position
/// `t`: its first node and the four weights; None when it leaves the axis
/// (NaN included: `NaN as usize - 1` once wrapped around and indexed out of
/// bounds).
#[inline(always)]
fn stencil(t: f64, n: usize) -> Option<Stencil> {
    let t0 = t.floor();
    if !(t0 >= 1.0 && t0 + 2.0 < n as f64) {
        return None;
    }
    let first = t0 as usize - 1;
    Some((first, keys_weights(t, first)))
}

/// `h` by cubic convolution over the stencils along x and y; None when
/// either left the patch or the 4 × 4 points touch a missing one.
#[inline(always)]
fn interpolate_at(h: &ArrayView2<f64>, x: Option<Stencil>, y: Option<Stencil>) -> Option<f64> {
    let ((i0, wx), (j0, wy)) = (x?, y?);
    let mut sum = 0.0;
    for (di, wxi) in wx.iter().enumerate() {
        for (dj, wyj) in wy.iter().enumerate() {
            sum += wxi * wyj * h[[i0 + di, j0 + dj]];
        }
    }
    (!sum.is_nan()).then_some(sum)
}

/// The stencils at t, t + ½ and t − ½ along an axis of n points (the
/// position and the two legs of the central difference).
fn stencils(t: f64, n: usize) -> [Option<Stencil>; 3] {
    [stencil(t, n), stencil(t + 0.5, n), stencil(t - 0.5, n)]
}

/// Most points one refinement uses: beyond this the overlap is subsampled
/// on a regular stride (the shift is a global parameter; 60 000 points fix
/// it far below the interpolation error).
const REFINE_POINTS: usize = 60_000;

/// Sub-pixel shift e with b(u) ≈ a(u + e) + c₀ + c₁x + c₂y for two patches
/// already aligned to the nearest pixel, by Gauss–Newton on the heights
/// themselves (Lucas & Kanade, IJCAI 1981), `a` interpolated by cubic
/// convolution; the plane absorbs the tiles' different tilt and piston.
/// Unlike the phase-correlation peak, which a taper common to both patches
/// pulls toward zero shift, this is unbiased for a pure translation.
/// None with too few valid points, a singular system, or a shift that
/// wanders beyond ±1.5 px (the integer alignment was wrong).
pub fn refine_shift(a: ArrayView2<f64>, b: ArrayView2<f64>, start: [f64; 2]) -> Option<[f64; 2]> {
    let (nx, ny) = a.dim();
    if b.dim() != (nx, ny) || nx < 8 || ny < 8 {
        return None;
    }
    let (cx, cy) = ((nx as f64 - 1.0) / 2.0, (ny as f64 - 1.0) / 2.0);
    let scale = nx.max(ny) as f64;
    let margin = 4;
    let inner = (nx - 2 * margin) * (ny - 2 * margin);
    let stride = ((inner as f64 / REFINE_POINTS as f64).sqrt().ceil() as usize).max(1);
    let mut e = start;
    for _ in 0..30 {
        // A NaN step (heights so large the normal equations overflow) is
        // a wandering shift too.
        if !(e[0].abs() <= 1.5 && e[1].abs() <= 1.5) {
            return None;
        }
        let mut m = Matrix5::zeros();
        let mut r = Vector5::zeros();
        let mut count = 0usize;
        // A stencil's weights depend on one coordinate only: made once per
        // row and per column of the pass instead of at every point.
        let columns: Vec<(usize, [Option<Stencil>; 3])> = (margin..ny - margin)
            .step_by(stride)
            .map(|j| (j, stencils(j as f64 + e[1], ny)))
            .collect();
        for i in (margin..nx - margin).step_by(stride) {
            let [x, xp, xm] = stencils(i as f64 + e[0], nx);
            for &(j, [y, yp, ym]) in &columns {
                let hb = b[[i, j]];
                if hb.is_nan() {
                    continue;
                }
                let (Some(ha), Some(xp), Some(xm), Some(yp), Some(ym)) = (
                    interpolate_at(&a, x, y),
                    interpolate_at(&a, xp, y),
                    interpolate_at(&a, xm, y),
                    interpolate_at(&a, x, yp),
                    interpolate_at(&a, x, ym),
                ) else {
                    continue;
                };
                // Residual hb − (ha + plane); unknowns δe and the plane.
                let jac = Vector5::new(
                    xp - xm,
                    yp - ym,
                    1.0,
                    (i as f64 - cx) / scale,
                    (j as f64 - cy) / scale,
                );
                r += jac * (hb - ha);
                m += jac * jac.transpose();
                count += 1;
            }
        }
        if count < 50 {
            return None;
        }
        let step = m.lu().solve(&r)?;
        e = [e[0] + step[0], e[1] + step[1]];
        if step[0].abs().max(step[1].abs()) < 1e-5 {
            return Some(e);
        }
    }
    Some(e)
}

/// Pearson correlation of the points measured in both patches (views, so
/// the stitcher's many candidate overlaps are never copied).
pub fn correlation(a: ArrayView2<f64>, b: ArrayView2<f64>) -> f64 {
    // Row-major, as the points were once gathered into a list and summed:
    // the same sums in the same order, from the start `Sum` uses.
    let start: f64 = std::iter::empty::<f64>().sum();
    let rows = || a.rows().into_iter().zip(b.rows());
    let (mut count, mut sum_x, mut sum_y) = (0usize, start, start);
    for (ra, rb) in rows() {
        for (&x, &y) in ra.iter().zip(rb) {
            if !x.is_nan() && !y.is_nan() {
                count += 1;
                sum_x += x;
                sum_y += y;
            }
        }
    }
    let n = count as f64;
    if n < 2.0 {
        return 0.0;
    }
    let (mx, my) = (sum_x / n, sum_y / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (ra, rb) in rows() {
        for (&x, &y) in ra.iter().zip(rb) {
            if !x.is_nan() && !y.is_nan() {
                sxy += (x - mx) * (y - my);
                sxx += (x - mx) * (x - mx);
                syy += (y - my) * (y - my);
            }
        }
    }
    if sxx > 0.0 && syy > 0.0 {
        sxy / (sxx * syy).sqrt()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_synth::surface::SelfAffine;
    use ndarray::Array2;

    fn surface(n: usize, seed: u64) -> Array2<f64> {
        SelfAffine {
            hurst: 0.8,
            rms_m: 1e-6,
            lambda_min_m: 4e-6,
            lambda_max_m: 100e-6,
        }
        .periodic(n, n, 1e-6, seed)
    }

    /// Fourier-shifts a periodic map: out(u) = h(u + e), exact for a
    /// band-limited periodic map.
    fn shifted(h: &Array2<f64>, e: [f64; 2]) -> Array2<f64> {
        let (nx, ny) = h.dim();
        let mut data: Vec<Complex64> = h.iter().map(|v| Complex64::new(*v, 0.0)).collect();
        let fft = ComplexFft2::new(nx, ny).unwrap();
        fft.process(&mut data, Direction::Forward).unwrap();
        for i in 0..nx {
            for j in 0..ny {
                let (kx, ky) = (signed(i, nx).unwrap_or(0.0), signed(j, ny).unwrap_or(0.0));
                let phase = TAU * (kx * e[0] / nx as f64 + ky * e[1] / ny as f64);
                data[i * ny + j] *= Complex64::from_polar(1.0, phase);
            }
        }
        fft.process(&mut data, Direction::Inverse).unwrap();
        Array2::from_shape_fn((nx, ny), |(i, j)| data[i * ny + j].re / (nx * ny) as f64)
    }

    #[test]
    fn finds_integer_and_sub_pixel_shifts() {
        let h = surface(256, 5);
        for e in [[3.0, -2.0], [0.3, 0.7], [-4.45, 2.2]] {
            let moved = shifted(&h, e);
            // Non-periodic patches: interior crops of both maps.
            let crop = |m: &Array2<f64>, d: [i64; 2]| {
                Array2::from_shape_fn((60, 200), |(i, j)| {
                    m[[
                        (40 + i as i64 - d[0]) as usize,
                        (20 + j as i64 - d[1]) as usize,
                    ]]
                })
            };
            // As the stitcher does: the integer shift first, then the
            // sub-pixel rest on patches re-cut at that shift.
            let coarse =
                phase_correlate(crop(&h, [0, 0]).view(), crop(&moved, [0, 0]).view()).unwrap();
            let d = coarse.shift_px.map(|v| v.round() as i64);
            assert_eq!(d, e.map(|v: f64| v.round() as i64));
            let fine = phase_correlate(crop(&h, [0, 0]).view(), crop(&moved, d).view()).unwrap();
            for a in 0..2 {
                let found = d[a] as f64 + fine.shift_px[a];
                assert!((found - e[a]).abs() < 0.05, "{e:?}: {found} along {a}");
            }
            assert!(fine.peak > 0.2, "peak {}", fine.peak);
        }
    }

    #[test]
    fn nan_positions_and_shifts_are_refused_not_indexed() {
        let h = surface(32, 3);
        assert_eq!(stencil(f64::NAN, 32), None);
        let at = |x: f64, y: f64| interpolate_at(&h.view(), stencil(x, 32), stencil(y, 32));
        assert_eq!(at(f64::NAN, 5.0), None);
        assert_eq!(at(5.0, f64::NAN), None);
        assert_eq!(refine_shift(h.view(), h.view(), [f64::NAN, 0.0]), None);
    }

    /// Cubic convolution at one point as registration once did it, the
    /// weights made afresh at every point (#35 keeps its bits).
    fn interpolate_reference(h: &Array2<f64>, x: f64, y: f64) -> Option<f64> {
        let (nx, ny) = h.dim();
        let (x0, y0) = (x.floor(), y.floor());
        if !(x0 >= 1.0 && y0 >= 1.0 && x0 + 2.0 < nx as f64 && y0 + 2.0 < ny as f64) {
            return None;
        }
        let (i0, j0) = (x0 as usize - 1, y0 as usize - 1);
        let mut sum = 0.0;
        for di in 0..4 {
            for dj in 0..4 {
                let wx = keys(x - (i0 + di) as f64);
                let wy = keys(y - (j0 + dj) as f64);
                sum += wx * wy * h[[i0 + di, j0 + dj]];
            }
        }
        (!sum.is_nan()).then_some(sum)
    }

    #[test]
    fn stencils_made_per_axis_keep_the_bits_of_pointwise_interpolation() {
        let mut h = surface(32, 4);
        h[[10, 12]] = f64::NAN;
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut seen = [0usize; 2];
        for _ in 0..20_000 {
            let (x, y) = (next() * 34.0 - 1.0, next() * 34.0 - 1.0);
            let [sx, sxp, sxm] = stencils(x, 32);
            let [sy, syp, sym] = stencils(y, 32);
            for ((px, py), (stx, sty)) in [
                ((x, y), (sx, sy)),
                ((x + 0.5, y), (sxp, sy)),
                ((x - 0.5, y), (sxm, sy)),
                ((x, y + 0.5), (sx, syp)),
                ((x, y - 0.5), (sx, sym)),
            ] {
                let got = interpolate_at(&h.view(), stx, sty);
                let expected = interpolate_reference(&h, px, py);
                assert_eq!(
                    got.map(f64::to_bits),
                    expected.map(f64::to_bits),
                    "({px}, {py})"
                );
                seen[usize::from(got.is_some())] += 1;
            }
        }
        // Inside, outside and on the hole all met.
        assert!(seen[0] > 1000 && seen[1] > 50_000, "{seen:?}");
    }

    /// The Pearson correlation as it once was: the points measured in both
    /// gathered into a list, then summed (#35 keeps its bits).
    fn correlation_reference(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
        let pairs: Vec<(f64, f64)> = a
            .iter()
            .zip(b.iter())
            .filter(|(x, y)| !x.is_nan() && !y.is_nan())
            .map(|(x, y)| (*x, *y))
            .collect();
        let n = pairs.len() as f64;
        if n < 2.0 {
            return 0.0;
        }
        let mx = pairs.iter().map(|p| p.0).sum::<f64>() / n;
        let my = pairs.iter().map(|p| p.1).sum::<f64>() / n;
        let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
        for (x, y) in pairs {
            sxy += (x - mx) * (y - my);
            sxx += (x - mx) * (x - mx);
            syy += (y - my) * (y - my);
        }
        if sxx > 0.0 && syy > 0.0 {
            sxy / (sxx * syy).sqrt()
        } else {
            0.0
        }
    }

    #[test]
    fn correlation_of_views_keeps_the_bits_of_the_gathered_list() {
        let h = surface(64, 8);
        let mut g = surface(64, 9);
        g[[3, 4]] = f64::NAN;
        // Sub-blocks of whole maps (strided views), as the stitcher takes them.
        fn block(m: &Array2<f64>, i0: usize, j0: usize) -> ArrayView2<'_, f64> {
            let mut v = m.view();
            v.slice_each_axis_inplace(|axis| match axis.axis.index() {
                0 => ndarray::Slice::from(i0..i0 + 40),
                _ => ndarray::Slice::from(j0..j0 + 23),
            });
            v
        }
        for (i0, j0) in [(0, 0), (3, 17), (20, 40)] {
            let (a, b) = (block(&h, i0, j0), block(&g, i0 / 2, j0 + 1));
            let got = correlation(a, b);
            let expected = correlation_reference(&a.to_owned(), &b.to_owned());
            assert_eq!(got.to_bits(), expected.to_bits(), "{i0} {j0}");
            assert!(got.abs() < 0.999, "{got}");
        }
        let self_correlation = correlation(block(&h, 1, 2), block(&h, 1, 2));
        assert!((self_correlation - 1.0).abs() < 1e-12);
        // Signed zeros only, and too few points: the same edge answers.
        let zeros = Array2::from_elem((3, 3), -0.0);
        assert_eq!(
            correlation(zeros.view(), zeros.view()).to_bits(),
            correlation_reference(&zeros, &zeros).to_bits()
        );
        let nan = Array2::from_elem((3, 3), f64::NAN);
        assert_eq!(correlation(nan.view(), zeros.view()), 0.0);
    }

    #[test]
    fn refinement_recovers_sub_pixel_shifts_under_a_plane() {
        let h = surface(256, 3);
        for e in [[0.3, -0.45], [-0.12, 0.07], [0.5, 0.5]] {
            let moved = shifted(&h, e);
            let a = Array2::from_shape_fn((60, 200), |(i, j)| h[[40 + i, 20 + j]]);
            // b(u) = a(u + e) plus a tilt and piston of its own, one gap.
            let mut b = Array2::from_shape_fn((60, 200), |(i, j)| {
                moved[[40 + i, 20 + j]] + 2e-6 + 3e-9 * i as f64 - 1e-9 * j as f64
            });
            b[[30, 100]] = f64::NAN;
            let found = refine_shift(a.view(), b.view(), [0.0, 0.0]).unwrap();
            for k in 0..2 {
                assert!((found[k] - e[k]).abs() < 0.01, "{e:?}: found {found:?}");
            }
        }
    }

    #[test]
    fn tolerates_tilt_piston_noise_and_gaps() {
        let h = surface(256, 9);
        let e = [2.0, 1.0];
        let crop =
            |i0: usize, j0: usize| Array2::from_shape_fn((50, 180), |(i, j)| h[[i0 + i, j0 + j]]);
        let a = crop(30, 30);
        let mut b = crop(32, 31);
        let mut state = 1u64;
        for ((i, j), v) in b.indexed_iter_mut() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            *v += 5e-6 + 1e-4 * i as f64 * 1e-6 - 2e-4 * j as f64 * 1e-6;
            if state >> 60 == 0 {
                *v = f64::NAN;
            }
        }
        let r = phase_correlate(a.view(), b.view()).unwrap();
        assert!(
            (r.shift_px[0] - e[0]).abs() < 0.1 && (r.shift_px[1] - e[1]).abs() < 0.1,
            "{:?}",
            r.shift_px
        );
        let aligned = Array2::from_shape_fn((48, 179), |(i, j)| h[[32 + i, 31 + j]]);
        let b_aligned = Array2::from_shape_fn((48, 179), |(i, j)| b[[i, j]]);
        assert!(correlation(aligned.view(), b_aligned.view()) > 0.99);
    }
}
