//! What the camera sees of a solved contact: the gap field as it is drawn
//! onto the camera's pixels, and the true contact map on the same pixels.
//!
//! The boundary-element solution is pixel-wise constant (a solve point in
//! contact stands for its whole cell), so the true contact on the camera is
//! the contact set sampled at the nearest solve point. Plain bilinear
//! interpolation of the gap would shrink every patch by half a cell (the
//! gap is zero only on the hull of the contact nodes). Before
//! interpolating, a contact node at a patch's edge is therefore given a
//! virtual negative gap, minus the mean gap of its open 4-neighbours, so
//! the interpolated gap crosses zero about half-way to them (at the edge of
//! its cell) and rises to the neighbour's gap at the neighbour; the
//! interpolated gap is clamped at zero, and set to zero on every pixel of
//! the true contact (near a cell's corners the open diagonal neighbour
//! would otherwise lift it), so the drawn contact is the true contact and
//! only the near-contact rim around it is added.

use hypercontact_interference::{CameraGrid, InterferenceError, Placement, Similarity};

/// The gap with edge contact nodes given their virtual negative gap (see
/// the module docs); row-major `[ix * ny + iy]` as the height map.
pub fn drawing_gap(gap_m: &[f64], in_contact: &[bool], nx: usize, ny: usize) -> Vec<f64> {
    let mut out = gap_m.to_vec();
    for ix in 0..nx {
        for iy in 0..ny {
            let k = ix * ny + iy;
            if !in_contact[k] {
                continue;
            }
            let mut sum = 0.0;
            let mut open = 0;
            let mut visit = |j: usize| {
                if !in_contact[j] && gap_m[j].is_finite() {
                    sum += gap_m[j];
                    open += 1;
                }
            };
            if ix > 0 {
                visit(k - ny);
            }
            if ix + 1 < nx {
                visit(k + ny);
            }
            if iy > 0 {
                visit(k - 1);
            }
            if iy + 1 < ny {
                visit(k + 1);
            }
            out[k] = if open > 0 { -sum / open as f64 } else { 0.0 };
        }
    }
    out
}

/// The true contact on the camera's pixels (row-major `[y * width + x]`):
/// each pixel centre takes its nearest solve point; pixels off the solved
/// map or on an unmeasured point are `None`.
pub fn true_view(
    in_contact: &[bool],
    measured: &[bool],
    (nx, ny): (usize, usize),
    (dx_m, dy_m): (f64, f64),
    placement: &Placement,
    grid: &CameraGrid,
) -> Result<Vec<Option<bool>>, InterferenceError> {
    let similarity = Similarity::new(placement, grid, (nx, ny), dx_m, dy_m)?;
    let mut out = Vec::with_capacity(grid.width_px * grid.height_px);
    for y in 0..grid.height_px {
        for x in 0..grid.width_px {
            let (ix, iy) = similarity.apply(x as f64, y as f64);
            let (i, j) = (ix + 0.5, iy + 0.5);
            let inside = i >= 0.0 && j >= 0.0 && i < nx as f64 && j < ny as f64;
            out.push(if inside {
                let k = i as usize * ny + j as usize;
                measured[k].then_some(in_contact[k])
            } else {
                None
            });
        }
    }
    Ok(out)
}

/// Contact pixels / seen pixels of a true view (0 if none is seen).
pub fn view_fraction(view: &[Option<bool>]) -> f64 {
    let seen = view.iter().filter(|v| v.is_some()).count();
    let contact = view.iter().filter(|v| **v == Some(true)).count();
    if seen == 0 {
        0.0
    } else {
        contact as f64 / seen as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_nodes_carry_minus_their_open_neighbours_mean() {
        // 3 × 3, centre in contact, neighbours open at 1, 2, 3, 4 nm
        let mut gap = vec![9.0; 9];
        gap[1] = 1.0; // (0, 1)
        gap[3] = 2.0; // (1, 0)
        gap[5] = 3.0; // (1, 2)
        gap[7] = 4.0; // (2, 1)
        gap[4] = 0.0;
        let mut contact = vec![false; 9];
        contact[4] = true;
        let drawn = drawing_gap(&gap, &contact, 3, 3);
        assert_eq!(drawn[4], -2.5);
        // half-way to a neighbour the bilinear gap is zero at equal gaps
        assert_eq!(drawn[0], 9.0);
        // an interior node (all neighbours in contact) stays at zero
        let drawn = drawing_gap(&[0.0; 9], &[true; 9], 3, 3);
        assert!(drawn.iter().all(|g| *g == 0.0));
    }

    #[test]
    fn the_true_view_samples_the_nearest_point_and_marks_the_outside() {
        // 4 × 2 map of 10 µm, contact at ix = 1; a 6 × 3 camera of 10 µm
        // pixels on the same centre, unrotated: camera x → map ix.
        let contact = [false, false, true, true, false, false, false, false];
        let view = true_view(
            &contact,
            &[true; 8],
            (4, 2),
            (10e-6, 10e-6),
            &Placement::default(),
            &CameraGrid {
                width_px: 6,
                height_px: 3,
                pixel_m: 10e-6,
            },
        )
        .unwrap();
        // camera centre (2.5, 1) ↔ map centre (1.5, 0.5): ix = x − 1, iy = y − 0.5
        let row: Vec<Option<bool>> = view[6..12].to_vec();
        assert_eq!(
            row,
            [
                None,
                Some(false),
                Some(true),
                Some(false),
                Some(false),
                None
            ]
        );
        assert!(
            (view_fraction(&view) - 4.0 / 16.0).abs() < 1e-12,
            "{view:?}"
        );
    }
}
