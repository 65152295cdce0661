//! The region of a height map that is analysed: a rectangular window cut
//! out of it ([`crop`]), and a mask that sets points outside (or inside) a
//! shape to NaN ([`apply_mask`]), each with a one-line account of what was
//! removed.
//!
//! Coordinates in metres are measured from the map's first point: point
//! (i, j) sits at x = i·dx, y = j·dy (axis 0 = x), as in the rest of the
//! crate. A point stands for the pixel [i·dx, (i + 1)·dx) of width dx (the
//! SurfaceTopography convention, physical size = points × spacing), so a
//! window of length L holds L/dx points.

use hypercontact_core::StageError;
use ndarray::Array2;

/// Errors of the region routines; each names the parameter to change.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RegionError {
    #[error("{parameter} = {value}: {problem}")]
    Parameter {
        parameter: &'static str,
        value: String,
        problem: String,
    },
    #[error("the mask has shape {found:?} but the map has {expected:?}: they must match")]
    MaskShape {
        found: (usize, usize),
        expected: (usize, usize),
    },
}

impl From<RegionError> for StageError {
    fn from(e: RegionError) -> Self {
        StageError::other(e)
    }
}

fn parameter(
    parameter: &'static str,
    value: impl ToString,
    problem: impl Into<String>,
) -> RegionError {
    RegionError::Parameter {
        parameter,
        value: value.to_string(),
        problem: problem.into(),
    }
}

/// A rectangular window of a map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Window {
    /// Points [x0, x0 + nx) × [y0, y0 + ny).
    Points {
        x0: usize,
        y0: usize,
        nx: usize,
        ny: usize,
    },
    /// The window [x0_m, x0_m + lx_m) × [y0_m, y0_m + ly_m), from the map's
    /// first point. Its first point is round(x0_m/dx) and its end (one past
    /// the last point) round((x0_m + lx_m)/dx), rounding halves away from
    /// zero (likewise in y): a window of the whole map's size, nx·dx, keeps
    /// every point, and adjacent windows share no point.
    Metres {
        x0_m: f64,
        y0_m: f64,
        lx_m: f64,
        ly_m: f64,
    },
}

/// A map cut down or masked, and what that removed.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    pub height_m: Array2<f64>,
    /// Points of the input map not in `height_m` (crop) or set to NaN by the
    /// mask (not counting points that were NaN already).
    pub removed: usize,
    /// One line for the stage's note, e.g. `crop: x 2..6, y 3..9 of 8 × 9
    /// points kept, 48 points (66.7 %) removed`.
    pub description: String,
}

/// The window in points, [x0, x0 + nx) × [y0, y0 + ny), that `window` names
/// on a map of `dim` points at spacings `dx_m`, `dy_m`; refused naming the
/// parameter if it leaves the map or holds fewer than 2 × 2 points.
pub fn window_points(
    window: &Window,
    dim: (usize, usize),
    dx_m: f64,
    dy_m: f64,
) -> Result<[usize; 4], RegionError> {
    let (x0, nx, y0, ny) = match *window {
        Window::Points { x0, y0, nx, ny } => (x0, nx, y0, ny),
        Window::Metres {
            x0_m,
            y0_m,
            lx_m,
            ly_m,
        } => {
            let (x0, nx) = metres_to_points(("x0_m", x0_m), ("lx_m", lx_m), ("dx_m", dx_m))?;
            let (y0, ny) = metres_to_points(("y0_m", y0_m), ("ly_m", ly_m), ("dy_m", dy_m))?;
            (x0, nx, y0, ny)
        }
    };
    // Errors quote the value the caller gave, and for metres the point it
    // rounded to.
    let quote = |given: f64, point: usize| format!("{given} m (point {point})");
    let [sx, cx, sy, cy] = match *window {
        Window::Points { .. } => [x0, nx, y0, ny].map(|v| v.to_string()),
        Window::Metres {
            x0_m,
            y0_m,
            lx_m,
            ly_m,
        } => [
            quote(x0_m, x0),
            format!("{lx_m} m ({nx} points)"),
            quote(y0_m, y0),
            format!("{ly_m} m ({ny} points)"),
        ],
    };
    let [nsx, ncx, nsy, ncy] = match window {
        Window::Points { .. } => ["x0", "nx", "y0", "ny"],
        Window::Metres { .. } => ["x0_m", "lx_m", "y0_m", "ly_m"],
    };
    check_along([(nsx, sx), (ncx, cx)], "x", x0, nx, dim.0)?;
    check_along([(nsy, sy), (ncy, cy)], "y", y0, ny, dim.1)?;
    Ok([x0, nx, y0, ny])
}

/// First point and number of points of the interval [start_m, start_m +
/// length_m) at `spacing_m` (the rounding rule of [`Window::Metres`]).
fn metres_to_points(
    (start_name, start_m): (&'static str, f64),
    (length_name, length_m): (&'static str, f64),
    (spacing_name, spacing_m): (&'static str, f64),
) -> Result<(usize, usize), RegionError> {
    if !(spacing_m.is_finite() && spacing_m > 0.0) {
        return Err(parameter(
            spacing_name,
            spacing_m,
            "the spacing must be finite and positive",
        ));
    }
    if !(start_m.is_finite() && start_m >= 0.0) {
        return Err(parameter(
            start_name,
            start_m,
            "the window must start at or after the map's first point (0 m)",
        ));
    }
    if !(length_m.is_finite() && length_m > 0.0) {
        return Err(parameter(
            length_name,
            length_m,
            "the window's length must be finite and positive",
        ));
    }
    let first = (start_m / spacing_m).round();
    let end = ((start_m + length_m) / spacing_m).round();
    // Beyond 2^52 points the conversion is meaningless; it is refused by the
    // bounds check that follows (no map is that large).
    let to_points = |v: f64| if v < 1e15 { v as usize } else { usize::MAX / 4 };
    let first = to_points(first);
    Ok((first, to_points(end).saturating_sub(first)))
}

fn check_along(
    [(start_name, start_value), (count_name, count_value)]: [(&'static str, String); 2],
    axis: &str,
    start: usize,
    count: usize,
    size: usize,
) -> Result<(), RegionError> {
    if start >= size {
        return Err(parameter(
            start_name,
            start_value,
            format!(
                "the window starts at point {start}, outside the map ({size} points along {axis})"
            ),
        ));
    }
    if count < 2 {
        return Err(parameter(
            count_name,
            count_value,
            format!("the window holds {count} point(s) along {axis}, fewer than 2"),
        ));
    }
    if start.checked_add(count).is_none_or(|end| end > size) {
        return Err(parameter(
            count_name,
            count_value,
            format!(
                "the window reaches past the map's end along {axis} (point {start} + {count} \
                 points, of {size})"
            ),
        ));
    }
    Ok(())
}

/// Cuts `window` out of `height_m` (axis 0 = x, spacings `dx_m`, `dy_m`).
pub fn crop(
    height_m: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    window: &Window,
) -> Result<Region, RegionError> {
    let (nx_map, ny_map) = height_m.dim();
    let [x0, nx, y0, ny] = window_points(window, (nx_map, ny_map), dx_m, dy_m)?;
    let cut = Array2::from_shape_fn((nx, ny), |(i, j)| height_m[[x0 + i, y0 + j]]);
    let total = nx_map * ny_map;
    let removed = total - nx * ny;
    let description = format!(
        "crop: x {x0}..{}, y {y0}..{} of {nx_map} × {ny_map} points kept ({nx} × {ny}), \
         {removed} points ({:.1} %) removed",
        x0 + nx,
        y0 + ny,
        percent(removed, total)
    );
    Ok(Region {
        height_m: cut,
        removed,
        description,
    })
}

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// A shape on the map; a point belongs to it if its position (i·dx, j·dy)
/// does (boundaries included).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Per point, in the map's shape: true = in the shape.
    Points(Array2<bool>),
    /// x0_m ≤ x ≤ x1_m and y0_m ≤ y ≤ y1_m.
    Rectangle {
        x0_m: f64,
        y0_m: f64,
        x1_m: f64,
        y1_m: f64,
    },
    /// (x − xc_m)² + (y − yc_m)² ≤ radius_m².
    Circle { xc_m: f64, yc_m: f64, radius_m: f64 },
}

/// What a mask keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keep {
    /// The shape's points; the rest become NaN.
    Inside,
    /// The points outside the shape; the shape's points become NaN.
    Outside,
}

impl Shape {
    fn check(&self, dim: (usize, usize)) -> Result<(), RegionError> {
        let finite = |name: &'static str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(parameter(name, v, "must be finite"))
            }
        };
        match self {
            Shape::Points(mask) => {
                if mask.dim() != dim {
                    return Err(RegionError::MaskShape {
                        found: mask.dim(),
                        expected: dim,
                    });
                }
            }
            Shape::Rectangle {
                x0_m,
                y0_m,
                x1_m,
                y1_m,
            } => {
                for (name, v) in [
                    ("x0_m", x0_m),
                    ("y0_m", y0_m),
                    ("x1_m", x1_m),
                    ("y1_m", y1_m),
                ] {
                    finite(name, *v)?;
                }
                if x1_m < x0_m {
                    return Err(parameter(
                        "x1_m",
                        x1_m,
                        format!("must not be below x0_m = {x0_m}"),
                    ));
                }
                if y1_m < y0_m {
                    return Err(parameter(
                        "y1_m",
                        y1_m,
                        format!("must not be below y0_m = {y0_m}"),
                    ));
                }
            }
            Shape::Circle {
                xc_m,
                yc_m,
                radius_m,
            } => {
                finite("xc_m", *xc_m)?;
                finite("yc_m", *yc_m)?;
                if !(radius_m.is_finite() && *radius_m >= 0.0) {
                    return Err(parameter(
                        "radius_m",
                        radius_m,
                        "must be finite and not negative",
                    ));
                }
            }
        }
        Ok(())
    }

    fn contains(&self, i: usize, j: usize, dx_m: f64, dy_m: f64) -> bool {
        let (x, y) = (i as f64 * dx_m, j as f64 * dy_m);
        match self {
            Shape::Points(mask) => mask[[i, j]],
            Shape::Rectangle {
                x0_m,
                y0_m,
                x1_m,
                y1_m,
            } => (*x0_m..=*x1_m).contains(&x) && (*y0_m..=*y1_m).contains(&y),
            Shape::Circle {
                xc_m,
                yc_m,
                radius_m,
            } => (x - xc_m).powi(2) + (y - yc_m).powi(2) <= radius_m * radius_m,
        }
    }

    fn name(&self) -> String {
        match self {
            Shape::Points(_) => "the given mask".into(),
            Shape::Rectangle {
                x0_m,
                y0_m,
                x1_m,
                y1_m,
            } => format!("rectangle x {x0_m:e}..{x1_m:e} m, y {y0_m:e}..{y1_m:e} m"),
            Shape::Circle {
                xc_m,
                yc_m,
                radius_m,
            } => format!("circle of radius {radius_m:e} m at ({xc_m:e}, {yc_m:e}) m"),
        }
    }
}

/// Sets to NaN the points of `height_m` that `keep` excludes from `shape`.
pub fn apply_mask(
    height_m: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    shape: &Shape,
    keep: Keep,
) -> Result<Region, RegionError> {
    for (name, v) in [("dx_m", dx_m), ("dy_m", dy_m)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(parameter(
                name,
                v,
                "the spacing must be finite and positive",
            ));
        }
    }
    shape.check(height_m.dim())?;
    let mut out = height_m.clone();
    let mut removed = 0;
    for ((i, j), h) in out.indexed_iter_mut() {
        let kept = shape.contains(i, j, dx_m, dy_m) == (keep == Keep::Inside);
        if !kept && !h.is_nan() {
            *h = f64::NAN;
            removed += 1;
        }
    }
    let total = height_m.len();
    let side = match keep {
        Keep::Inside => "outside",
        Keep::Outside => "inside",
    };
    let description = format!(
        "mask: {removed} of {total} points ({:.1} %) {side} {} set to NaN",
        percent(removed, total),
        shape.name()
    );
    Ok(Region {
        height_m: out,
        removed,
        description,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// h = 100 i + j: every value names its point.
    fn labelled(nx: usize, ny: usize) -> Array2<f64> {
        Array2::from_shape_fn((nx, ny), |(i, j)| (100 * i + j) as f64)
    }

    #[test]
    fn a_window_in_points_keeps_exactly_those_points() {
        let h = labelled(8, 9);
        let w = Window::Points {
            x0: 2,
            y0: 3,
            nx: 4,
            ny: 6,
        };
        let r = crop(&h, 1e-6, 2e-6, &w).unwrap();
        assert_eq!(r.height_m.dim(), (4, 6));
        assert_eq!(r.height_m[[0, 0]], 203.0);
        assert_eq!(r.height_m[[3, 5]], 508.0);
        assert_eq!(r.removed, 72 - 24);
        assert!(
            r.description.contains("x 2..6, y 3..9"),
            "{}",
            r.description
        );
        assert!(
            r.description.contains("48 points (66.7 %)"),
            "{}",
            r.description
        );
    }

    #[test]
    fn a_window_in_metres_follows_the_rounding_rule() {
        let h = labelled(10, 12);
        // dx = 0.1 um: x0 = 0.2 um → point 2 (0.2/0.1 is 2.0000000000000004 in
        // floating point, which must not matter); end (0.2 + 0.5) um → point 7.
        // dy = 0.25 um: y0 = 0.3 um → 1.2 → 1; end 1.3 um → 5.2 → 5.
        let w = Window::Metres {
            x0_m: 0.2e-6,
            y0_m: 0.3e-6,
            lx_m: 0.5e-6,
            ly_m: 1.0e-6,
        };
        let r = crop(&h, 0.1e-6, 0.25e-6, &w).unwrap();
        assert_eq!(r.height_m.dim(), (5, 4));
        assert_eq!(r.height_m[[0, 0]], 201.0);
        assert_eq!(r.height_m[[4, 3]], 604.0);
        // Halves round away from zero: 0.25/0.5 = 0.5 → point 1.
        let w = Window::Metres {
            x0_m: 0.25,
            y0_m: 0.0,
            lx_m: 1.0,
            ly_m: 6.0,
        };
        let r = crop(&h, 0.5, 0.5, &w).unwrap();
        assert_eq!(r.height_m.dim(), (2, 12));
        assert_eq!(r.height_m[[0, 0]], 100.0);
        // The whole map's size keeps every point.
        let w = Window::Metres {
            x0_m: 0.0,
            y0_m: 0.0,
            lx_m: 10.0 * 0.3,
            ly_m: 12.0 * 0.7,
        };
        let r = crop(&h, 0.3, 0.7, &w).unwrap();
        assert_eq!(r.height_m, h);
        assert_eq!(r.removed, 0);
    }

    #[test]
    fn bad_windows_are_refused_naming_the_parameter() {
        let h = labelled(8, 9);
        let points = |x0, y0, nx, ny| Window::Points { x0, y0, nx, ny };
        let err = |w: Window| crop(&h, 1.0, 1.0, &w).unwrap_err().to_string();
        assert!(err(points(8, 0, 2, 2)).starts_with("x0 = 8"));
        assert!(err(points(0, 3, 2, 7)).starts_with("ny = 7"));
        assert!(err(points(0, 0, 1, 5)).starts_with("nx = 1"));
        let metres = |x0_m, y0_m, lx_m, ly_m| Window::Metres {
            x0_m,
            y0_m,
            lx_m,
            ly_m,
        };
        assert!(err(metres(-1.0, 0.0, 2.0, 2.0)).starts_with("x0_m = -1"));
        assert!(err(metres(0.0, 0.0, 2.0, f64::NAN)).starts_with("ly_m = NaN"));
        // 1.2 m at 1 m spacing is one point: refused as too few.
        assert!(err(metres(0.0, 0.0, 1.2, 3.0)).starts_with("lx_m = 1.2 m (1 points)"));
        assert!(err(metres(0.0, 9.4, 3.0, 1.0)).starts_with("y0_m = 9.4 m (point 9)"));
        assert!(err(points(1, 0, usize::MAX, 2)).starts_with("nx = 18446744073709551615"));
        assert!(err(metres(0.0, 0.0, 3.0, 1e300)).starts_with("ly_m"));
        let e = crop(&h, 0.0, 1.0, &metres(0.0, 0.0, 2.0, 2.0)).unwrap_err();
        assert!(e.to_string().starts_with("dx_m = 0"));
    }

    #[test]
    fn masks_by_points_rectangle_and_circle() {
        let mut h = labelled(6, 5);
        h[[0, 0]] = f64::NAN;
        // Points: keep where the mask is true.
        let mask = Array2::from_shape_fn((6, 5), |(i, j)| i + j >= 3);
        let r = apply_mask(&h, 1.0, 1.0, &Shape::Points(mask.clone()), Keep::Inside).unwrap();
        // Points with i + j < 3: (0,0) (0,1) (0,2) (1,0) (1,1) (2,0); (0,0) was NaN.
        assert_eq!(r.removed, 5);
        for ((i, j), v) in r.height_m.indexed_iter() {
            assert_eq!(v.is_nan(), i + j < 3, "({i}, {j})");
        }
        assert!(
            r.description
                .starts_with("mask: 5 of 30 points (16.7 %) outside")
        );
        // Rectangle in metres at dx = 0.5, dy = 2: x in [0.5, 1.5] → i = 1..=3,
        // y in [2, 4] → j = 1..=2, boundaries included; excluded.
        let rect = Shape::Rectangle {
            x0_m: 0.5,
            y0_m: 2.0,
            x1_m: 1.5,
            y1_m: 4.0,
        };
        let r = apply_mask(&h, 0.5, 2.0, &rect, Keep::Outside).unwrap();
        assert_eq!(r.removed, 6);
        for ((i, j), v) in r.height_m.indexed_iter() {
            let inside = (1..=3).contains(&i) && (1..=2).contains(&j);
            assert_eq!(v.is_nan(), inside || (i, j) == (0, 0), "({i}, {j})");
        }
        // Circle of radius 2 at (2, 2), unit spacing: the 13 points with
        // (i − 2)² + (j − 2)² ≤ 4 are kept.
        let circle = Shape::Circle {
            xc_m: 2.0,
            yc_m: 2.0,
            radius_m: 2.0,
        };
        let r = apply_mask(&h, 1.0, 1.0, &circle, Keep::Inside).unwrap();
        let kept = r.height_m.iter().filter(|v| !v.is_nan()).count();
        assert_eq!(kept, 13);
        assert_eq!(r.removed, 30 - 13 - 1);
        assert!(!r.height_m[[4, 2]].is_nan() && r.height_m[[4, 3]].is_nan());
    }

    #[test]
    fn bad_masks_are_refused() {
        let h = labelled(6, 5);
        let e = apply_mask(
            &h,
            1.0,
            1.0,
            &Shape::Points(Array2::from_elem((5, 6), true)),
            Keep::Inside,
        );
        assert_eq!(
            e.unwrap_err(),
            RegionError::MaskShape {
                found: (5, 6),
                expected: (6, 5)
            }
        );
        let circle = Shape::Circle {
            xc_m: 0.0,
            yc_m: 0.0,
            radius_m: -1.0,
        };
        let e = apply_mask(&h, 1.0, 1.0, &circle, Keep::Inside).unwrap_err();
        assert!(e.to_string().starts_with("radius_m = -1"));
        let rect = Shape::Rectangle {
            x0_m: 1.0,
            y0_m: 0.0,
            x1_m: 0.0,
            y1_m: 1.0,
        };
        let e = apply_mask(&h, 1.0, 1.0, &rect, Keep::Inside).unwrap_err();
        assert!(e.to_string().starts_with("x1_m = 0"));
    }
}
