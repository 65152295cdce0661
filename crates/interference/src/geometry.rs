//! Where the camera looks on the sample: a similarity transform from camera
//! pixel centres to the gap field's grid, and bilinear resampling of the gap
//! field onto the camera's pixels.
//!
//! Coordinates. The gap field follows the workspace's `Field` convention:
//! `gap_m[[ix, iy]]`, axis 0 along x (SurfaceTopography's layout); its
//! point (ix, iy) sits at X = (ix − (nx − 1)/2) dx, Y = (iy − (ny − 1)/2) dy
//! from the field's centre. The camera frame is an image, row-major
//! `[y * width + x]`; its pixel (x, y) is centred at
//! p = ((x − (W − 1)/2) P, (y − (H − 1)/2) P) from the frame's centre,
//! P the pixel pitch on the sample (sensor pitch / magnification). The
//! camera sees the sample point
//!
//! (X, Y) = R(θ) p + (shift_x, shift_y),  R(θ) = [[cos θ, −sin θ], [sin θ, cos θ]],
//!
//! so the shift is the field point under the frame's centre and θ turns the
//! camera's x axis to (cos θ, sin θ) in the field's axes. In pixel indices
//! this is a similarity of scale P/dx (P/dx and P/dy for rectangular scan
//! pixels), the camera-pixel / scan-pixel ratio.
//!
//! Resampling is bilinear inside the hull of the field's pixel centres;
//! outside it, or where a node with non-zero weight is NaN, the result is
//! NaN (not measured, rendered as the background by the lookup table).

use ndarray::ArrayView2;
use rayon::prelude::*;

use crate::error::{InterferenceError, positive};

/// A transformed coordinate within this many pixels of a grid node is taken
/// at the node: cos(π/2) is 6e-17, not 0, and that should not blend a
/// NaN neighbour into an exact 90° turn.
const SNAP_PX: f64 = 1e-9;
/// The largest camera frame accepted (2 GB of f64 gaps).
const MAX_PIXELS: usize = 1 << 28;

/// A gap field on its grid, m; NaN where not measured.
#[derive(Clone, Copy, Debug)]
pub struct GapMap<'a> {
    /// `[[ix, iy]]`, axis 0 along x
    pub gap_m: ArrayView2<'a, f64>,
    pub dx_m: f64,
    pub dy_m: f64,
}

impl<'a> GapMap<'a> {
    /// A map on square pixels of side `pixel_m`.
    pub fn square(gap_m: ArrayView2<'a, f64>, pixel_m: f64) -> Self {
        Self {
            gap_m,
            dx_m: pixel_m,
            dy_m: pixel_m,
        }
    }

    /// A non-empty grid with positive spacings; values finite or NaN.
    pub fn check(&self) -> Result<(), InterferenceError> {
        let (nx, ny) = self.gap_m.dim();
        if nx == 0 || ny == 0 {
            return Err(InterferenceError::Empty {
                what: "gap map",
                detail: format!("{nx} × {ny} points"),
            });
        }
        positive("gap map dx_m", self.dx_m)?;
        positive("gap map dy_m", self.dy_m)?;
        if let Some((index, &value)) = self.gap_m.iter().enumerate().find(|(_, g)| g.is_infinite())
        {
            return Err(InterferenceError::Value {
                what: "gap map (logical order, ix * ny + iy)",
                index,
                value,
                message: "a gap must be finite, or NaN where not measured",
            });
        }
        Ok(())
    }
}

/// The camera's pixel grid on the sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraGrid {
    pub width_px: usize,
    pub height_px: usize,
    /// pixel pitch on the sample (sensor pitch / magnification), m
    pub pixel_m: f64,
}

impl Default for CameraGrid {
    /// A 2048 × 2048 sensor of 6.5 µm pixels at unit magnification.
    fn default() -> Self {
        Self {
            width_px: 2048,
            height_px: 2048,
            pixel_m: 6.5e-6,
        }
    }
}

impl CameraGrid {
    /// A square sensor of `side_px` × `side_px` pixels.
    pub fn square(side_px: usize, pixel_m: f64) -> Self {
        Self {
            width_px: side_px,
            height_px: side_px,
            pixel_m,
        }
    }

    pub fn check(&self) -> Result<(), InterferenceError> {
        if self.width_px == 0 || self.height_px == 0 {
            return Err(InterferenceError::Empty {
                what: "camera grid",
                detail: format!("{} × {} pixels", self.width_px, self.height_px),
            });
        }
        if self.width_px.saturating_mul(self.height_px) > MAX_PIXELS {
            return Err(InterferenceError::param(
                "camera grid",
                format!("{} × {}", self.width_px, self.height_px),
                format!("at most {MAX_PIXELS} pixels"),
            ));
        }
        positive("pixel_m", self.pixel_m)
    }
}

/// How the sample sits in the camera's view (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Placement {
    /// turn of the camera's x axis in the field's axes, rad
    pub angle_rad: f64,
    /// the field point under the frame's centre, from the field's centre, m
    pub shift_x_m: f64,
    pub shift_y_m: f64,
}

impl Placement {
    pub fn check(&self) -> Result<(), InterferenceError> {
        for (param, v) in [
            ("angle_rad", self.angle_rad),
            ("shift_x_m", self.shift_x_m),
            ("shift_y_m", self.shift_y_m),
        ] {
            if !v.is_finite() {
                return Err(InterferenceError::param(param, v, "must be finite"));
            }
        }
        Ok(())
    }
}

/// Camera pixel (x, y) → fractional field indices (ix, iy).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// ∂(ix, iy)/∂(x, y)
    matrix: [[f64; 2]; 2],
    /// (ix, iy) at the frame's centre
    centre_index: [f64; 2],
    /// the frame's centre, camera pixels
    camera_centre: [f64; 2],
}

impl Similarity {
    pub fn new(
        placement: &Placement,
        camera: &CameraGrid,
        field: (usize, usize),
        dx_m: f64,
        dy_m: f64,
    ) -> Result<Self, InterferenceError> {
        placement.check()?;
        camera.check()?;
        positive("dx_m", dx_m)?;
        positive("dy_m", dy_m)?;
        let (sin, cos) = placement.angle_rad.sin_cos();
        let (sx, sy) = (camera.pixel_m / dx_m, camera.pixel_m / dy_m);
        Ok(Self {
            matrix: [[sx * cos, -sx * sin], [sy * sin, sy * cos]],
            centre_index: [
                placement.shift_x_m / dx_m + (field.0 as f64 - 1.0) / 2.0,
                placement.shift_y_m / dy_m + (field.1 as f64 - 1.0) / 2.0,
            ],
            camera_centre: [
                (camera.width_px as f64 - 1.0) / 2.0,
                (camera.height_px as f64 - 1.0) / 2.0,
            ],
        })
    }

    /// Field indices (ix, iy) seen by the centre of camera pixel (x, y).
    #[inline]
    pub fn apply(&self, x: f64, y: f64) -> (f64, f64) {
        let (u, v) = (x - self.camera_centre[0], y - self.camera_centre[1]);
        let m = &self.matrix;
        (
            m[0][0] * u + m[0][1] * v + self.centre_index[0],
            m[1][0] * u + m[1][1] * v + self.centre_index[1],
        )
    }

    /// Camera pixel / scan pixel along the field's x and y.
    pub fn scale(&self) -> (f64, f64) {
        let m = &self.matrix;
        (m[0][0].hypot(m[0][1]), m[1][0].hypot(m[1][1]))
    }
}

/// The gap field resampled at the camera's pixel centres, row-major
/// `[y * width + x]`, m; NaN outside the field and next to NaN nodes.
pub fn resample(
    gap: &GapMap,
    placement: &Placement,
    camera: &CameraGrid,
) -> Result<Vec<f64>, InterferenceError> {
    gap.check()?;
    let (nx, ny) = gap.gap_m.dim();
    let similarity = Similarity::new(placement, camera, (nx, ny), gap.dx_m, gap.dy_m)?;
    let standard = gap.gap_m.as_standard_layout();
    let values = standard
        .as_slice()
        .ok_or_else(|| InterferenceError::Empty {
            what: "gap map",
            detail: "not contiguous after copying".into(),
        })?;
    let (width, height) = (camera.width_px, camera.height_px);
    let mut out = vec![0.0; width * height];
    out.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
        for (x, v) in row.iter_mut().enumerate() {
            let (ix, iy) = similarity.apply(x as f64, y as f64);
            *v = bilinear(values, nx, ny, ix, iy);
        }
    });
    Ok(out)
}

/// Bilinear interpolation of `values[ix * ny + iy]` at fractional (ix, iy).
#[inline]
fn bilinear(values: &[f64], nx: usize, ny: usize, ix: f64, iy: f64) -> f64 {
    let (Some((i, tx)), Some((j, ty))) = (cell(ix, nx), cell(iy, ny)) else {
        return f64::NAN;
    };
    let mut sum = values[i * ny + j] * ((1.0 - tx) * (1.0 - ty));
    // zero weights are skipped so that a NaN node only spreads where it counts
    if tx != 0.0 {
        sum += values[(i + 1) * ny + j] * (tx * (1.0 - ty));
    }
    if ty != 0.0 {
        sum += values[i * ny + j + 1] * ((1.0 - tx) * ty);
        if tx != 0.0 {
            sum += values[(i + 1) * ny + j + 1] * (tx * ty);
        }
    }
    sum
}

/// The cell's lower node and the fraction t ∈ [0, 1) into it, for a
/// coordinate in [0, n − 1] (within [`SNAP_PX`]); `None` outside.
/// Truncating casts instead of `floor`/`round`, which are library calls on
/// baseline x86-64 and would double the cost of a frame.
#[inline]
fn cell(coordinate: f64, n: usize) -> Option<(usize, f64)> {
    let last = (n - 1) as f64;
    // NaN fails both comparisons
    if !(coordinate >= -SNAP_PX && coordinate <= last + SNAP_PX) {
        return None;
    }
    let c = coordinate.clamp(0.0, last);
    let lower = c as usize;
    let t = c - lower as f64;
    if t < SNAP_PX {
        Some((lower, 0.0))
    } else if t > 1.0 - SNAP_PX {
        // c ≤ n − 1, so lower + 1 is a node; at the last node t = 0 and the
        // next node is never read
        Some((lower + 1, 0.0))
    } else {
        Some((lower, t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;
    use proptest::prelude::*;

    fn field(nx: usize, ny: usize) -> Array2<f64> {
        // distinct values, some NaN
        Array2::from_shape_fn((nx, ny), |(i, j)| {
            if (i * 7 + j * 3) % 11 == 5 {
                f64::NAN
            } else {
                1e-6 * (i as f64 + 0.37 * j as f64) + 1e-9 * ((i * j) % 5) as f64
            }
        })
    }

    fn same(a: f64, b: f64) -> bool {
        (a.is_nan() && b.is_nan()) || a == b
    }

    #[test]
    fn identity_reproduces_the_field() {
        let (nx, ny) = (23, 17);
        let f = field(nx, ny);
        let gap = GapMap::square(f.view(), 2e-5);
        let camera = CameraGrid {
            width_px: nx,
            height_px: ny,
            pixel_m: 2e-5,
        };
        let out = resample(&gap, &Placement::default(), &camera).unwrap();
        for y in 0..ny {
            for x in 0..nx {
                assert!(same(out[y * nx + x], f[[x, y]]), "({x}, {y})");
            }
        }
        let s = Similarity::new(&Placement::default(), &camera, (nx, ny), 2e-5, 2e-5).unwrap();
        assert_eq!(s.scale(), (1.0, 1.0));
    }

    #[test]
    fn whole_pixel_shift_shifts_the_field() {
        let (nx, ny) = (20, 14);
        let f = field(nx, ny);
        let dx = 1.5e-5;
        let gap = GapMap::square(f.view(), dx);
        let camera = CameraGrid {
            width_px: nx,
            height_px: ny,
            pixel_m: dx,
        };
        let (kx, ky) = (3i64, -2i64);
        let placement = Placement {
            angle_rad: 0.0,
            shift_x_m: kx as f64 * dx,
            shift_y_m: ky as f64 * dx,
        };
        let out = resample(&gap, &placement, &camera).unwrap();
        for y in 0..ny as i64 {
            for x in 0..nx as i64 {
                let (i, j) = (x + kx, y + ky);
                let want = if (0..nx as i64).contains(&i) && (0..ny as i64).contains(&j) {
                    f[[i as usize, j as usize]]
                } else {
                    f64::NAN
                };
                assert!(same(out[(y * nx as i64 + x) as usize], want), "({x}, {y})");
            }
        }
    }

    #[test]
    fn quarter_turns_transpose_and_flip() {
        let n = 16;
        let f = field(n, n);
        let gap = GapMap::square(f.view(), 1e-5);
        let camera = CameraGrid::square(n, 1e-5);
        let turn = |angle_rad: f64| {
            resample(
                &gap,
                &Placement {
                    angle_rad,
                    ..Placement::default()
                },
                &camera,
            )
            .unwrap()
        };
        let (quarter, back, half) = (
            turn(std::f64::consts::FRAC_PI_2),
            turn(-std::f64::consts::FRAC_PI_2),
            turn(std::f64::consts::PI),
        );
        for y in 0..n {
            for x in 0..n {
                // (X, Y) = R(90°) p: ix = n − 1 − y, iy = x
                assert!(
                    same(quarter[y * n + x], f[[n - 1 - y, x]]),
                    "90° ({x}, {y})"
                );
                assert!(same(back[y * n + x], f[[y, n - 1 - x]]), "−90° ({x}, {y})");
                assert!(
                    same(half[y * n + x], f[[n - 1 - x, n - 1 - y]]),
                    "180° ({x}, {y})"
                );
            }
        }
    }

    #[test]
    fn nan_spreads_only_to_the_cells_it_touches() {
        let mut f = Array2::from_elem((5, 5), 1e-6);
        f[[2, 2]] = f64::NAN;
        let gap = GapMap::square(f.view(), 1e-5);
        // half-pixel camera: pixel centres at half steps of the field
        let camera = CameraGrid::square(9, 0.5e-5);
        let out = resample(&gap, &Placement::default(), &camera).unwrap();
        for y in 0..9 {
            for x in 0..9 {
                // camera (x, y) sits at field (x/2, y/2)
                let near = (x as f64 / 2.0 - 2.0).abs() < 1.0 && (y as f64 / 2.0 - 2.0).abs() < 1.0;
                assert_eq!(out[y * 9 + x].is_nan(), near, "({x}, {y})");
                if !near {
                    assert!((out[y * 9 + x] - 1e-6).abs() < 1e-20);
                }
            }
        }
    }

    #[test]
    fn one_point_axes_and_bad_inputs() {
        let f = Array2::from_elem((1, 1), 3e-7);
        let gap = GapMap::square(f.view(), 1e-5);
        let camera = CameraGrid {
            width_px: 3,
            height_px: 1,
            pixel_m: 1e-5,
        };
        let out = resample(&gap, &Placement::default(), &camera).unwrap();
        assert!(out[0].is_nan() && out[1] == 3e-7 && out[2].is_nan());

        let empty = Array2::<f64>::zeros((0, 4));
        let bad_gap = GapMap {
            gap_m: empty.view(),
            ..gap
        };
        assert!(matches!(
            resample(&bad_gap, &Placement::default(), &camera),
            Err(InterferenceError::Empty { .. })
        ));
        let inf = Array2::from_elem((2, 2), f64::INFINITY);
        let inf_gap = GapMap {
            gap_m: inf.view(),
            ..gap
        };
        assert!(matches!(
            resample(&inf_gap, &Placement::default(), &camera),
            Err(InterferenceError::Value { index: 0, .. })
        ));
        assert!(resample(&GapMap { dx_m: 0.0, ..gap }, &Placement::default(), &camera).is_err());
        assert!(
            resample(
                &GapMap {
                    dy_m: f64::NAN,
                    ..gap
                },
                &Placement::default(),
                &camera
            )
            .is_err()
        );
        for bad in [
            CameraGrid {
                width_px: 0,
                ..camera
            },
            CameraGrid {
                pixel_m: -1.0,
                ..camera
            },
            CameraGrid {
                width_px: 1 << 20,
                height_px: 1 << 20,
                ..camera
            },
        ] {
            assert!(
                resample(&gap, &Placement::default(), &bad).is_err(),
                "{bad:?}"
            );
        }
        let bad_place = Placement {
            angle_rad: f64::NAN,
            ..Placement::default()
        };
        assert!(resample(&gap, &bad_place, &camera).is_err());
    }

    #[test]
    fn transposed_views_are_read_by_their_logical_index() {
        let f = field(6, 4);
        let t = f.t().to_owned(); // [[iy, ix]]
        let gap = GapMap {
            gap_m: t.t(), // a non-standard-layout view of the same field
            dx_m: 1e-5,
            dy_m: 1e-5,
        };
        let camera = CameraGrid {
            width_px: 6,
            height_px: 4,
            pixel_m: 1e-5,
        };
        let out = resample(&gap, &Placement::default(), &camera).unwrap();
        for y in 0..4 {
            for x in 0..6 {
                assert!(same(out[y * 6 + x], f[[x, y]]));
            }
        }
    }

    #[test]
    fn rotated_and_scaled_ramp_on_a_frame_inside_the_field() {
        // every camera pixel lands inside the field: all must match the ramp
        let (n, dx) = (40, 1e-5);
        let half = (n as f64 - 1.0) / 2.0;
        let f = Array2::from_shape_fn((n, n), |(i, j)| {
            2e-6 + 0.01 * (i as f64 - half) * dx - 0.02 * (j as f64 - half) * dx
        });
        let gap = GapMap::square(f.view(), dx);
        let camera = CameraGrid {
            width_px: 50,
            height_px: 50,
            pixel_m: 0.5 * dx,
        };
        let placement = Placement {
            angle_rad: 0.3,
            shift_x_m: 2.2 * dx,
            shift_y_m: -1.7 * dx,
        };
        let out = resample(&gap, &placement, &camera).unwrap();
        let (sin, cos) = 0.3f64.sin_cos();
        for y in 0..50 {
            for x in 0..50 {
                let (px, py) = ((x as f64 - 24.5) * 0.5 * dx, (y as f64 - 24.5) * 0.5 * dx);
                let (xm, ym) = (
                    cos * px - sin * py + 2.2 * dx,
                    sin * px + cos * py - 1.7 * dx,
                );
                let want = 2e-6 + 0.01 * xm - 0.02 * ym;
                assert!((out[y * 50 + x] - want).abs() < 1e-17, "({x}, {y})");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// h = a + bX + cY is reproduced to rounding wherever the camera
        /// sees the field, and NaN exactly where it does not.
        #[test]
        fn linear_ramp_is_exact_under_any_transform(
            angle_rad in -7.0f64..7.0,
            shift_x in -3.0f64..3.0,
            shift_y in -3.0f64..3.0,
            scale in 0.2f64..3.0,
            aspect in 0.5f64..2.0,
            nx in 2usize..30,
            ny in 2usize..30,
            width in 1usize..40,
            height in 1usize..40,
            b in -1.0f64..1.0,
            c in -1.0f64..1.0,
        ) {
            let (dx, dy) = (1e-5, 1e-5 * aspect);
            let pixel = scale * dx;
            let (half_x, half_y) = ((nx as f64 - 1.0) / 2.0, (ny as f64 - 1.0) / 2.0);
            let ramp = |x_m: f64, y_m: f64| 1e-6 + b * x_m + c * y_m;
            let f = Array2::from_shape_fn((nx, ny), |(i, j)| {
                ramp((i as f64 - half_x) * dx, (j as f64 - half_y) * dy)
            });
            let placement = Placement {
                angle_rad,
                shift_x_m: shift_x * nx as f64 * dx / 4.0,
                shift_y_m: shift_y * ny as f64 * dy / 4.0,
            };
            let camera = CameraGrid { width_px: width, height_px: height, pixel_m: pixel };
            let gap = GapMap { gap_m: f.view(), dx_m: dx, dy_m: dy };
            let out = resample(&gap, &placement, &camera).unwrap();
            let (sin, cos) = angle_rad.sin_cos();
            for y in 0..height {
                for x in 0..width {
                    let px = (x as f64 - (width as f64 - 1.0) / 2.0) * pixel;
                    let py = (y as f64 - (height as f64 - 1.0) / 2.0) * pixel;
                    let (xm, ym) = (cos * px - sin * py + placement.shift_x_m, sin * px + cos * py + placement.shift_y_m);
                    // distance outside the hull of centres, in field pixels
                    let out_x = xm.abs() / dx - half_x;
                    let out_y = ym.abs() / dy - half_y;
                    let v = out[y * width + x];
                    if out_x < -1e-6 && out_y < -1e-6 {
                        prop_assert!((v - ramp(xm, ym)).abs() < 1e-15, "({x}, {y}): {v} vs {}", ramp(xm, ym));
                    } else if out_x > 1e-6 || out_y > 1e-6 {
                        prop_assert!(v.is_nan(), "({x}, {y}) outside but {v}");
                    }
                }
            }
        }
    }
}
