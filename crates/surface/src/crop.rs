//! Stage `crop`: one window of a height map, optionally coarsened by an
//! integer factor, and its mirror image tiling — the patch that every
//! contact model of a finite-strain comparison solves (issue #33), so that
//! `fem`, `bem`, `truncation`/`icm` and `persson` see the same surface.
//!
//! The mirror extension is the even continuation across x = 0 and
//! x = (nx − 1)dx (and likewise in y): h[2(nx − 1) − i] = h[i], a map of
//! 2(nx − 1) × 2(ny − 1) points that is periodic by construction. A block
//! whose lateral faces are symmetry planes (the `fem` stage's `mirror`
//! boundary) is one cell of exactly this tiling, so a periodic model on the
//! extension solves the same contact problem.

use hypercontact_core::{
    Arity, Checked, Context, Field, InputSpec, Inputs, OutputSpec, Outputs, Stage, StageError,
    StageInfo, params,
};
use ndarray::Array2;

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
}

/// The `crop` stage.
pub struct Crop;

static INFO: StageInfo = StageInfo {
    kind: "crop",
    version: 1,
    summary: "A window of a height map, optionally coarsened, and its mirror-image tiling",
    doc: "Cuts the window of points [x0, x0 + nx) × [y0, y0 + ny) out of the map (axis 0 = x) \
          and, with `coarsen` = k > 1, replaces each k × k block of it by the block's mean \
          (an instrument with k times larger pixels; a block with a missing point is missing; \
          points left over at the window's far edges, fewer than k, are dropped and the note \
          says so), spacing k dx × k dy. `height` is that patch. `mirrored` is its even \
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
            "the window (coarsened), metres, NaN = not measured",
        ),
        OutputSpec::field(
            "mirrored",
            "the window's even (mirror-image) continuation, periodic, 2(nx - 1) x 2(ny - 1) points",
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
        if missing > 0 {
            ctx.note(&format!(
                "{missing} of {} patch points are not measured",
                nx * ny
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
    use super::*;

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
        }
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
}
