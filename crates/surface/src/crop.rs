//! Stage `crop`: one window of a height map, optionally coarsened by an
//! integer factor or refined by band-limited interpolation, and its mirror
//! image tiling — the patch that every contact model of a finite-strain
//! comparison solves (issue #33), so that `fem`, `bem`, `truncation`/`icm`
//! and `persson` see the same surface.
//!
//! The mirror extension is the even continuation across x = 0 and
//! x = (nx − 1)dx (and likewise in y): h[2(nx − 1) − i] = h[i], a map of
//! 2(nx − 1) × 2(ny − 1) points that is periodic by construction. A block
//! whose lateral faces are symmetry planes (the `fem` stage's `mirror`
//! boundary) is one cell of exactly this tiling, so a periodic model on the
//! extension solves the same contact problem.
//!
//! Refinement (`refine` = k > 1, issue #49) puts the same surface on a grid
//! k times finer, so the models can mesh it more finely. The method is the
//! trigonometric interpolation of the mirror extension, the discrete cosine
//! (DCT-I) series of the window: the extension of M = 2(n − 1) points along
//! an axis is transformed, its spectrum is padded with zeros to kM points
//! (the Nyquist bin, m = M/2, is shared half and half between +M/2 and −M/2
//! so that the interpolant stays real and even), and transformed back; the
//! first (n − 1)k + 1 points are the refined window, spacing dx/k. The 2-D
//! padding is the product of the two axes' paddings, so it is done one axis
//! at a time: every line along y, then every line along x. Consequences:
//! the points of the window are reproduced (to round-off); the refined map's
//! own mirror extension is the interpolated extension, so `mirrored` stays
//! the even tiling of `height`; and nothing shorter than the window's
//! Nyquist wavelength 2dx appears — refinement interpolates, it adds no
//! content. A map low-pass filtered at a cut-off λc has λc/dx points per λc;
//! refinement multiplies that by k, which is what a mesh needs, not what the
//! surface has. With `coarsen` > 1 as well, the window is coarsened first
//! and the coarse patch refined.
use std::sync::Arc;

use hypercontact_core::{
    Arity, Checked, Context, Field, InputSpec, Inputs, OutputSpec, Outputs, Stage, StageError,
    StageInfo, params,
};
use hypercontact_numeric::fft1::{self, Complex64, Direction, Fft};
use ndarray::{Array2, ArrayView1, ArrayView2};
use rayon::prelude::*;

/// Parameters of `crop`.
#[params]
pub struct CropParams {
    /// first point of the window along x (axis 0)
    #[param(default = 0, range = 0..=1_000_000_000)]
    pub x0: usize,
    /// first point of the window along y (axis 1)
    #[param(default = 0, range = 0..=1_000_000_000)]
    pub y0: usize,
    /// points of the window along x, before coarsening (default: to the map's end)
    #[param(range = 2..=1_000_000_000)]
    pub nx: Option<usize>,
    /// points of the window along y, before coarsening (default: to the map's end)
    #[param(range = 2..=1_000_000_000)]
    pub ny: Option<usize>,
    /// each block of coarsen × coarsen points becomes one point (their mean), spacing × coarsen
    #[param(default = 1, range = 1..=4096)]
    pub coarsen: usize,
    /// the window (after coarsening) is resampled refine times finer by band-limited (cosine-series) interpolation, spacing / refine, (n − 1) refine + 1 points per axis; adds no content
    #[param(default = 1, range = 1..=16)]
    pub refine: usize,
}

/// The `crop` stage.
pub struct Crop;

static INFO: StageInfo = StageInfo {
    kind: "crop",
    version: 2,
    summary: "A window of a height map, optionally coarsened or refined, and its mirror-image tiling",
    doc: "Cuts the window of points [x0, x0 + nx) × [y0, y0 + ny) out of the map (axis 0 = x) \
          and, with `coarsen` = k > 1, replaces each k × k block of it by the block's mean \
          (an instrument with k times larger pixels; a block with a missing point is missing; \
          points left over at the window's far edges, fewer than k, are dropped and the note \
          says so), spacing k dx × k dy. With `refine` = r > 1 the patch (coarsened first, \
          if asked) is then resampled r times finer by band-limited interpolation: the \
          trigonometric (cosine, DCT-I) series of its mirror extension, evaluated at spacing \
          dx/r × dy/r on (nx - 1) r + 1 x (ny - 1) r + 1 points (FFT of the extension, \
          spectrum padded with zeros, the Nyquist bin split half and half between the \
          positive and negative frequency, inverse FFT). The window's points are reproduced \
          to round-off and nothing shorter than its Nyquist wavelength 2 dx appears: \
          refinement interpolates and adds no content. A map filtered at a cut-off λc has \
          λc/dx points per λc; refine multiplies that, so a model's mesh can resolve the same \
          surface more finely. A window with a missing point is refused when refine > 1. \
          `height` is that patch. `mirrored` is its even \
          continuation across the patch's edges, h[2(nx - 1) - i] = h[i] (likewise in y): \
          2(nx - 1) x 2(ny - 1) points, periodic by construction. A solid whose lateral faces \
          are symmetry planes (`fem` with `boundary: mirror`) is one cell of that tiling, so \
          `bem` with `boundary: periodic` and `surface` with `periodic: true` on `mirrored` \
          solve and describe the same contact problem as `fem` on `height`. A window that \
          leaves the map or leaves fewer than 2 x 2 points is refused naming the parameter.",
    inputs: &[InputSpec::field(
        "surface",
        Arity::One,
        "height map, metres, NaN = not measured",
    )],
    outputs: &[
        OutputSpec::field(
            "height",
            "the window (coarsened, refined), metres, NaN = not measured",
        ),
        OutputSpec::field(
            "mirrored",
            "the patch's even (mirror-image) continuation, periodic, 2(nx - 1) x 2(ny - 1) points \
             for a patch of nx x ny",
        ),
    ],
};

impl Stage for Crop {
    type Params = CropParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<CropParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.areal_field("surface", "crop")?;
        let window = Window::of(p, surface.values.dim())?;
        let patch = window.cut(surface)?;
        let (nx, ny) = patch.values.dim();
        ctx.note(&format!(
            "window x {}..{}, y {}..{} of {} × {}: {nx} × {ny} points at {:.3e} × {:.3e} m{}",
            window.x0,
            window.x0 + window.nx,
            window.y0,
            window.y0 + window.ny,
            surface.values.dim().0,
            surface.values.dim().1,
            patch.dx_m,
            patch.dy_m,
            window.dropped_note(),
        ));
        let missing = patch.values.iter().filter(|h| h.is_nan()).count();
        if missing > 0 && p.refine > 1 {
            return Err(StageError::invalid(format!(
                "{missing} of {} window points are not measured (NaN); refine = {} interpolates \
                 a spectrum of the whole window and needs every point: choose a window without \
                 missing points, or refine = 1",
                nx * ny,
                p.refine
            )));
        }
        if missing > 0 {
            ctx.note(&format!(
                "{missing} of {} patch points are not measured",
                nx * ny
            ));
        }
        let patch = refine(&patch, p.refine)?;
        if p.refine > 1 {
            let (rx, ry) = patch.values.dim();
            ctx.note(&format!(
                "refined {} times by band-limited interpolation: {rx} × {ry} points at \
                 {:.3e} × {:.3e} m",
                p.refine, patch.dx_m, patch.dy_m
            ));
        }
        let mirrored = mirror_extension(&patch)?;
        Ok(Outputs::new()
            .field("height", patch)
            .field("mirrored", mirrored))
    }
}

/// The window in points of the input, and the coarsening factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    pub x0: usize,
    pub y0: usize,
    pub nx: usize,
    pub ny: usize,
    pub coarsen: usize,
}

impl Window {
    /// The window `p` asks for on a map of `(nx, ny)` points, checked.
    pub fn of(p: &CropParams, (map_nx, map_ny): (usize, usize)) -> Result<Self, StageError> {
        let along = |axis: &str, start: usize, count: Option<usize>, size: usize| {
            if start >= size {
                return Err(StageError::invalid(format!(
                    "{axis}0 = {start} lies outside the map ({size} points along {axis})"
                )));
            }
            let count = count.unwrap_or(size - start);
            if start + count > size {
                return Err(StageError::invalid(format!(
                    "n{axis} = {count} from {axis}0 = {start} reaches point {} of a map of {size} \
                     points along {axis}",
                    start + count
                )));
            }
            if count / p.coarsen < 2 {
                return Err(StageError::invalid(format!(
                    "n{axis} = {count} points coarsened by {} leave fewer than 2 along {axis}",
                    p.coarsen
                )));
            }
            Ok(count)
        };
        Ok(Self {
            x0: p.x0,
            y0: p.y0,
            nx: along("x", p.x0, p.nx, map_nx)?,
            ny: along("y", p.y0, p.ny, map_ny)?,
            coarsen: p.coarsen,
        })
    }

    /// The patch of `surface` this window cuts.
    pub fn cut(&self, surface: &Field) -> Result<Field, StageError> {
        let k = self.coarsen;
        let (nx, ny) = (self.nx / k, self.ny / k);
        let values = Array2::from_shape_fn((nx, ny), |(i, j)| {
            // Summed in a fixed order (i, then j) so the mean is the same on
            // every run.
            let mut sum = 0.0;
            for a in 0..k {
                for b in 0..k {
                    sum += surface.values[[self.x0 + i * k + a, self.y0 + j * k + b]];
                }
            }
            sum / (k * k) as f64
        });
        Field::new(values, surface.dx_m * k as f64, surface.dy_m * k as f64)
            .map_err(StageError::other)
    }

    fn dropped_note(&self) -> String {
        let (rx, ry) = (self.nx % self.coarsen, self.ny % self.coarsen);
        if rx == 0 && ry == 0 {
            String::new()
        } else {
            format!(
                "; coarsening by {} dropped the last {rx} point(s) along x and {ry} along y",
                self.coarsen
            )
        }
    }
}

/// `patch` resampled `k` times finer by band-limited interpolation (the
/// module doc): spacing dx/k × dy/k, (nx − 1)k + 1 × (ny − 1)k + 1 points,
/// the original points at every k-th. `k` = 1 returns the patch unchanged.
/// The patch must have no missing point (a NaN would spread over its whole
/// line and column).
pub fn refine(patch: &Field, k: usize) -> Result<Field, StageError> {
    if k == 1 {
        return Ok(patch.clone());
    }
    // One axis at a time (the 2-D zero padding is the product of the two
    // 1-D ones): the lines along y (rows, axis 1) first, then along x.
    let along_y = refine_rows(patch.values.view(), k);
    let along_x = refine_rows(along_y.t(), k);
    let values = along_x.reversed_axes().as_standard_layout().into_owned();
    Field::new(values, patch.dx_m / k as f64, patch.dy_m / k as f64).map_err(StageError::other)
}

/// Every row of `values` (n points) refined `k` times: (n − 1)k + 1 points.
/// Each row is transformed whole by one thread, so the bits do not depend
/// on the number of threads.
fn refine_rows(values: ArrayView2<f64>, k: usize) -> Array2<f64> {
    let (rows, n) = values.dim();
    let line = LineRefiner::new(n, k);
    let len = line.refined_len();
    let mut out = vec![0.0; rows * len];
    out.par_chunks_mut(len).enumerate().for_each_init(
        || line.buffers(),
        |buffers, (r, refined)| line.refine(values.row(r), refined, buffers),
    );
    Array2::from_shape_vec((rows, len), out).expect("rows × len values")
}

/// Band-limited interpolation of a line of n points onto (n − 1)k + 1.
///
/// The even extension e (M = 2(n − 1) points, e[M − i] = e[i]) has a real,
/// even DFT E[m], so its trigonometric interpolant is the cosine series
/// e(t) = (1/M) Σ_m E[m] cos(2π m t / M), the DCT-I of the line. Sampling it
/// at t = j/k is an inverse DFT of kM points of E padded with zeros: E[m]
/// at m and kM − m for 0 < m < M/2, and the Nyquist term E[M/2] halved at
/// both ±M/2 (all at M/2 would make the interpolant complex, and dropping
/// it would lose a cosine the samples carry). See Trefethen, "Spectral
/// Methods in MATLAB" (SIAM 2000), ch. 3 (band-limited interpolation and
/// the halved Nyquist term), and Press et al., "Numerical Recipes" (3rd
/// ed., 2007), § 12.4 (the cosine transform as the FFT of the even
/// extension).
struct LineRefiner {
    /// points of the line
    n: usize,
    k: usize,
    /// M = 2(n − 1) points
    forward: Arc<dyn Fft<f64>>,
    /// kM points
    inverse: Arc<dyn Fft<f64>>,
}

/// One thread's buffers for [`LineRefiner::refine`].
struct LineBuffers {
    extension: Vec<Complex64>,
    padded: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

impl LineRefiner {
    fn new(n: usize, k: usize) -> Self {
        let m = 2 * (n - 1);
        Self {
            n,
            k,
            forward: fft1::complex(m, Direction::Forward),
            inverse: fft1::complex(k * m, Direction::Inverse),
        }
    }

    fn refined_len(&self) -> usize {
        (self.n - 1) * self.k + 1
    }

    fn buffers(&self) -> LineBuffers {
        let m = 2 * (self.n - 1);
        let scratch =
            (self.forward.get_inplace_scratch_len()).max(self.inverse.get_inplace_scratch_len());
        LineBuffers {
            extension: vec![Complex64::ZERO; m],
            padded: vec![Complex64::ZERO; self.k * m],
            scratch: vec![Complex64::ZERO; scratch],
        }
    }

    /// `line` (n points) interpolated into `refined` ((n − 1)k + 1 points).
    fn refine(&self, line: ArrayView1<f64>, refined: &mut [f64], b: &mut LineBuffers) {
        let (n, m) = (self.n, 2 * (self.n - 1));
        let half = m / 2;
        for (i, &h) in line.iter().enumerate() {
            b.extension[i] = Complex64::new(h, 0.0);
            if i > 0 && i < n - 1 {
                b.extension[m - i] = Complex64::new(h, 0.0);
            }
        }
        self.forward
            .process_with_scratch(&mut b.extension, &mut b.scratch);
        let big = self.k * m;
        b.padded.fill(Complex64::ZERO);
        // Frequencies 0 … M/2 − 1 stay where they are; −(M/2 − 1) … −1 move
        // from M/2 + 1 … M − 1 to kM − M/2 + 1 … kM − 1.
        b.padded[..half].copy_from_slice(&b.extension[..half]);
        b.padded[big - half + 1..].copy_from_slice(&b.extension[half + 1..]);
        let nyquist = b.extension[half] * 0.5;
        b.padded[half] = nyquist;
        b.padded[big - half] = nyquist;
        self.inverse
            .process_with_scratch(&mut b.padded, &mut b.scratch);
        let scale = 1.0 / m as f64;
        for (r, y) in refined.iter_mut().zip(&b.padded) {
            *r = y.re * scale;
        }
    }
}

/// The even continuation of `patch` across its far edges: 2(nx − 1) ×
/// 2(ny − 1) points, h[2(nx − 1) − i] = h[i], periodic.
pub fn mirror_extension(patch: &Field) -> Result<Field, StageError> {
    let (nx, ny) = patch.values.dim();
    let fold = |i: usize, n: usize| if i < n { i } else { 2 * (n - 1) - i };
    let values = Array2::from_shape_fn((2 * (nx - 1), 2 * (ny - 1)), |(i, j)| {
        patch.values[[fold(i, nx), fold(j, ny)]]
    });
    Field::new(values, patch.dx_m, patch.dy_m).map_err(StageError::other)
}

#[cfg(test)]
mod tests {
    use hypercontact_core::{Params, Product};

    use super::*;

    impl CropParams {
        fn refine_by(self, refine: usize) -> Self {
            Self { refine, ..self }
        }
    }

    fn ramp(nx: usize, ny: usize) -> Field {
        Field::new(
            Array2::from_shape_fn((nx, ny), |(i, j)| (10 * i + j) as f64),
            2.0,
            3.0,
        )
        .unwrap()
    }

    fn params(x0: usize, y0: usize, nx: Option<usize>, ny: Option<usize>, k: usize) -> CropParams {
        CropParams {
            x0,
            y0,
            nx,
            ny,
            coarsen: k,
            refine: 1,
        }
    }

    fn refined(refine: usize) -> CropParams {
        CropParams {
            refine,
            ..params(0, 0, None, None, 1)
        }
    }

    /// The stage on `map`: (height, mirrored, notes), or the error as text.
    fn run(map: &Field, p: CropParams) -> Result<(Field, Field, Vec<String>), String> {
        let inputs = Inputs::new().with("surface", Product::Field(map.clone()));
        let ctx = Context::new("crop");
        let out = Crop
            .run(&p.check().unwrap(), &inputs, &ctx)
            .map_err(|e| e.to_string())?;
        let field = |name| match out.get(name) {
            Some(Product::Field(f)) => f.clone(),
            _ => panic!("no {name}"),
        };
        Ok((field("height"), field("mirrored"), ctx.notes()))
    }

    /// Uniform numbers in [−1, 1) from a fixed seed (a 64-bit LCG).
    fn noise(nx: usize, ny: usize, seed: u64) -> Array2<f64> {
        let mut state = seed;
        Array2::from_shape_simple_fn((nx, ny), || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        })
    }

    fn max_abs(values: &Array2<f64>) -> f64 {
        values.iter().fold(0.0, |m, v| m.max(v.abs()))
    }

    /// The largest |refined[k i, k j] − original[i, j]|.
    fn decimation_error(refined: &Field, original: &Field, k: usize) -> f64 {
        let (nx, ny) = original.values.dim();
        let mut worst: f64 = 0.0;
        for i in 0..nx {
            for j in 0..ny {
                let d = refined.values[[k * i, k * j]] - original.values[[i, j]];
                worst = worst.max(d.abs());
            }
        }
        worst
    }

    /// Σ a cos(π m x / Lx) cos(π n y / Ly) over `terms` (m, n, a), on the
    /// grid of nx × ny points at spacing dx × dy.
    fn cosines(nx: usize, ny: usize, (dx, dy): (f64, f64), (lx, ly): (f64, f64)) -> Field {
        const TERMS: [(f64, f64, f64); 5] = [
            (0.0, 0.0, 0.3),
            (1.0, 2.0, 1.0),
            (3.0, 1.0, -0.7),
            (7.0, 5.0, 0.4),
            (2.0, 4.0, 0.25),
        ];
        let pi = std::f64::consts::PI;
        let values = Array2::from_shape_fn((nx, ny), |(i, j)| {
            let (x, y) = (i as f64 * dx, j as f64 * dy);
            TERMS
                .iter()
                .map(|&(m, n, a)| a * (pi * m * x / lx).cos() * (pi * n * y / ly).cos())
                .sum()
        });
        Field::new(values, dx, dy).unwrap()
    }

    #[test]
    fn window_cuts_the_points_it_names() {
        let map = ramp(8, 9);
        let w = Window::of(&params(2, 3, Some(4), None, 1), (8, 9)).unwrap();
        let patch = w.cut(&map).unwrap();
        assert_eq!(patch.values.dim(), (4, 6));
        assert_eq!(patch.values[[0, 0]], 23.0);
        assert_eq!(patch.values[[3, 5]], 58.0);
        assert_eq!((patch.dx_m, patch.dy_m), (2.0, 3.0));
    }

    #[test]
    fn coarsening_averages_blocks_and_scales_spacing() {
        let map = ramp(8, 9);
        let w = Window::of(&params(0, 0, None, None, 2), (8, 9)).unwrap();
        let patch = w.cut(&map).unwrap();
        // 9 points along y in blocks of 2: the last is dropped.
        assert_eq!(patch.values.dim(), (4, 4));
        // Block (1, 2): points x 2..4, y 4..6, mean (24 + 25 + 34 + 35)/4.
        assert_eq!(patch.values[[1, 2]], 29.5);
        assert_eq!((patch.dx_m, patch.dy_m), (4.0, 6.0));
        assert!(w.dropped_note().contains("1 along y"));
    }

    #[test]
    fn mirror_extension_is_even_and_periodic() {
        let patch = ramp(4, 3);
        let m = mirror_extension(&patch).unwrap();
        assert_eq!(m.values.dim(), (6, 4));
        for i in 0..6 {
            for j in 0..4 {
                // Even about the far edges: h(2(n−1) − i) = h(i) …
                let (ri, rj) = ((6 - i) % 6, (4 - j) % 4);
                assert_eq!(m.values[[i, j]], m.values[[ri, rj]], "({i}, {j})");
            }
        }
        // … and the patch itself is the first cell.
        assert_eq!(m.values[[3, 2]], patch.values[[3, 2]]);
        assert_eq!(m.values[[4, 1]], patch.values[[2, 1]]);
        assert_eq!(m.values[[5, 3]], patch.values[[1, 1]]);
    }

    #[test]
    fn bad_windows_name_the_parameter() {
        let err = |p: CropParams| Window::of(&p, (8, 9)).unwrap_err().to_string();
        assert!(err(params(8, 0, None, None, 1)).contains("x0 = 8"));
        assert!(err(params(0, 4, None, Some(6), 1)).contains("ny = 6"));
        assert!(err(params(0, 0, Some(3), None, 2)).contains("fewer than 2 along x"));
    }

    #[test]
    fn refine_reproduces_a_cosine_series_below_nyquist() {
        // 9 × 7 points: the window's Nyquist is m = 8 along x, n = 6 along y;
        // every term lies below it, so the refined grid samples the same
        // series exactly.
        let (dx, dy, lx, ly) = (2.0, 3.0, 16.0, 18.0);
        let coarse = cosines(9, 7, (dx, dy), (lx, ly));
        for k in [2, 3, 5] {
            let (height, _, notes) = run(&coarse, refined(k)).unwrap();
            let (nx, ny) = (8 * k + 1, 6 * k + 1);
            assert_eq!(height.values.dim(), (nx, ny));
            assert_eq!(height.dx_m, dx / k as f64);
            assert_eq!(height.dy_m, dy / k as f64);
            let exact = cosines(nx, ny, (height.dx_m, height.dy_m), (lx, ly));
            let scale = max_abs(&exact.values);
            for (r, e) in height.values.iter().zip(&exact.values) {
                assert!((r - e).abs() <= 1e-12 * scale, "k = {k}: {r} vs {e}");
            }
            assert!(
                notes
                    .iter()
                    .any(|n| n.contains(&format!("refined {k} times"))),
                "{notes:?}"
            );
        }
    }

    #[test]
    fn refine_keeps_a_cosine_at_nyquist_by_splitting_its_bin() {
        // (−1)^i (−1)^j, the Nyquist cosine on both axes: half its bin at
        // +Nyquist and half at −Nyquist give cos(π x / dx) cos(π y / dy)
        // between the points too (dropping the bin would lose it all).
        let (dx, dy) = (1.0, 2.0);
        let pi = std::f64::consts::PI;
        let at = |x: f64, y: f64| (pi * x / dx).cos() * (pi * y / dy).cos();
        let coarse = Field::new(
            Array2::from_shape_fn((6, 5), |(i, j)| at(i as f64 * dx, j as f64 * dy)),
            dx,
            dy,
        )
        .unwrap();
        let fine = refine(&coarse, 4).unwrap();
        assert_eq!(fine.values.dim(), (21, 17));
        for ((i, j), r) in fine.values.indexed_iter() {
            let e = at(i as f64 * fine.dx_m, j as f64 * fine.dy_m);
            assert!((r - e).abs() <= 1e-12, "({i}, {j}): {r} vs {e}");
        }
    }

    #[test]
    fn refine_reproduces_the_original_points() {
        // Rough (white) noise: not band-limited below its Nyquist, yet the
        // interpolant passes through every point.
        let coarse = Field::new(noise(13, 10, 7), 1e-6, 2e-6).unwrap();
        for k in [2, 3] {
            let fine = refine(&coarse, k).unwrap();
            assert_eq!(fine.values.dim(), (12 * k + 1, 9 * k + 1));
            let error = decimation_error(&fine, &coarse, k);
            assert!(
                error <= 1e-13 * max_abs(&coarse.values),
                "k = {k}: {error:e}"
            );
            // … and the points between are new values, not copies.
            assert_ne!(fine.values[[1, 1]], coarse.values[[0, 0]]);
        }
    }

    #[test]
    fn refine_one_is_the_unrefined_path_bit_for_bit() {
        let map = Field::new(noise(20, 17, 3), 1e-6, 1.5e-6).unwrap();
        for p in [
            params(2, 3, Some(11), Some(9), 1),
            params(1, 0, None, Some(14), 2),
        ] {
            assert_eq!(p.refine, 1);
            let (height, mirrored, _) = run(&map, p.clone()).unwrap();
            // The path without refinement: the window, then its mirror.
            let window = Window::of(&p, map.values.dim()).unwrap();
            let patch = window.cut(&map).unwrap();
            let mirror = mirror_extension(&patch).unwrap();
            let bits = |f: &Field| f.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&height), bits(&patch));
            assert_eq!(bits(&mirrored), bits(&mirror));
            assert_eq!((height.dx_m, height.dy_m), (patch.dx_m, patch.dy_m));
            assert_eq!((mirrored.dx_m, mirrored.dy_m), (mirror.dx_m, mirror.dy_m));
        }
        // Without coarsening, the window's points are the map's own.
        let (height, _, _) = run(&map, params(2, 3, Some(11), Some(9), 1)).unwrap();
        assert_eq!(
            height.values[[4, 5]].to_bits(),
            map.values[[6, 8]].to_bits()
        );
        // The default is 1.
        assert_eq!(CropParams::default().refine, 1);
    }

    #[test]
    fn mirrored_of_a_refined_patch_is_its_mirror_extension() {
        let map = Field::new(noise(16, 12, 11), 1e-6, 1e-6).unwrap();
        let k = 3;
        let (height, mirrored, _) =
            run(&map, params(2, 1, Some(9), Some(7), 1).refine_by(k)).unwrap();
        assert_eq!(height.values.dim(), (8 * k + 1, 6 * k + 1));
        assert_eq!(mirrored.values.dim(), (2 * 8 * k, 2 * 6 * k));
        assert_eq!((mirrored.dx_m, mirrored.dy_m), (height.dx_m, height.dy_m));
        let expected = mirror_extension(&height).unwrap();
        assert_eq!(mirrored.values, expected.values);
    }

    #[test]
    fn the_interpolated_extension_is_the_mirror_of_the_refined_line() {
        // The whole kM-point interpolant of the even extension is even about
        // t = 0 and t = k(n − 1): the refined line's own mirror extension is
        // the interpolated extension, so `mirrored` stays consistent.
        let (n, k) = (11, 3);
        let line = noise(1, n, 5);
        let refiner = LineRefiner::new(n, k);
        let mut buffers = refiner.buffers();
        let mut out = vec![0.0; refiner.refined_len()];
        refiner.refine(line.row(0), &mut out, &mut buffers);
        let full: Vec<f64> = buffers
            .padded
            .iter()
            .map(|y| y.re * (1.0 / (2 * (n - 1)) as f64))
            .collect();
        let big = full.len();
        assert_eq!(big, 2 * (n - 1) * k);
        for t in 1..big {
            assert!((full[t] - full[big - t]).abs() <= 1e-13, "t = {t}");
        }
        for (t, r) in out.iter().enumerate() {
            assert_eq!(full[t], *r);
        }
        // The imaginary part is round-off: the spectrum was kept even.
        assert!(
            buffers
                .padded
                .iter()
                .all(|y| y.im.abs() <= 1e-12 * (2 * (n - 1)) as f64)
        );
    }

    #[test]
    fn a_missing_point_is_refused_when_refining() {
        let mut values = noise(8, 8, 1);
        values[[3, 4]] = f64::NAN;
        let map = Field::new(values, 1.0, 1.0).unwrap();
        let e = run(&map, refined(2)).unwrap_err();
        assert!(
            e.contains("1 of 64 window points") && e.contains("refine = 2"),
            "{e}"
        );
        // Without refinement the gap is kept and noted.
        let (height, _, notes) = run(&map, refined(1)).unwrap();
        assert!(height.values[[3, 4]].is_nan());
        assert!(
            notes.iter().any(|n| n.contains("1 of 64 patch points")),
            "{notes:?}"
        );
        // A window that leaves the gap out refines.
        assert!(run(&map, params(4, 0, None, None, 1).refine_by(2)).is_ok());
    }

    #[test]
    fn refining_a_smooth_field_then_taking_every_kth_point_returns_it() {
        // A smooth random field: random amplitudes and phases of a few
        // wavelengths that are not harmonics of the window (so not a cosine
        // series of it).
        let (nx, ny) = (23, 18);
        let amplitudes = noise(6, 4, 42);
        let pi = std::f64::consts::PI;
        let values = Array2::from_shape_fn((nx, ny), |(i, j)| {
            let (x, y) = (i as f64, j as f64);
            (0..6)
                .map(|w| {
                    let a = amplitudes.row(w);
                    a[0] * (2.0 * pi * (x * a[1] + y * a[2]) / 9.7 + pi * a[3]).sin()
                })
                .sum()
        });
        let coarse = Field::new(values, 0.5e-6, 0.5e-6).unwrap();
        for k in [2, 4, 7] {
            let (fine, _, _) = run(&coarse, refined(k)).unwrap();
            let error = decimation_error(&fine, &coarse, k);
            assert!(
                error <= 1e-13 * max_abs(&coarse.values),
                "k = {k}: {error:e}"
            );
        }
    }

    #[test]
    fn coarsening_comes_before_refining() {
        let map = Field::new(noise(17, 13, 9), 1.0, 2.0).unwrap();
        let p = params(0, 0, None, None, 2).refine_by(2);
        let (height, mirrored, _) = run(&map, p.clone()).unwrap();
        let coarse = Window::of(&p, (17, 13)).unwrap().cut(&map).unwrap();
        assert_eq!(coarse.values.dim(), (8, 6));
        assert_eq!(height.values.dim(), (15, 11));
        assert_eq!((height.dx_m, height.dy_m), (1.0, 2.0));
        assert_eq!(mirrored.values.dim(), (28, 20));
        let error = decimation_error(&height, &coarse, 2);
        assert!(error <= 1e-13 * max_abs(&coarse.values), "{error:e}");
    }
}
