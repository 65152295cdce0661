//! Points of interest on a regular grid inside the region of interest.

use crate::DicError;

/// POIs at `step_px` inside a rectangle, index `iy * nx + ix`, each with
/// its whole subset (and the one-pixel gradient margin) inside the ROI and
/// the image.
#[derive(Clone, Debug, PartialEq)]
pub struct PoiGrid {
    pub nx: usize,
    pub ny: usize,
    pub step_px: usize,
    /// Frame-0 positions, pixels.
    pub points: Vec<[f64; 2]>,
}

impl PoiGrid {
    /// `roi_px = [x0, y0, x1, y1]` (inclusive pixel bounds); `roi_name`
    /// names where it came from in errors.
    pub fn new(
        roi_px: [usize; 4],
        roi_name: &str,
        step_px: usize,
        subset_px: usize,
        width: usize,
        height: usize,
    ) -> Result<Self, DicError> {
        let [x0, y0, x1, y1] = roi_px;
        if x1 <= x0 || y1 <= y0 {
            return Err(DicError::param(
                roi_name,
                format!("the region of interest {roi_px:?} is empty (need x0 < x1 and y0 < y1)"),
            ));
        }
        if x1 >= width || y1 >= height {
            return Err(DicError::param(
                roi_name,
                format!("the region of interest {roi_px:?} leaves the {width} × {height} image"),
            ));
        }
        let half = subset_px / 2;
        let lo_x = x0.max(1) + half;
        let lo_y = y0.max(1) + half;
        let hi_x = x1.min(width - 2).saturating_sub(half);
        let hi_y = y1.min(height - 2).saturating_sub(half);
        if hi_x < lo_x || hi_y < lo_y {
            return Err(DicError::param(
                "subset_px",
                format!(
                    "a {subset_px} px subset does not fit in the region of interest {roi_px:?} \
                     ({} × {} px)",
                    x1 - x0 + 1,
                    y1 - y0 + 1
                ),
            ));
        }
        let nx = (hi_x - lo_x) / step_px + 1;
        let ny = (hi_y - lo_y) / step_px + 1;
        // Centre the grid in the room it has.
        let off_x = lo_x + (hi_x - lo_x - (nx - 1) * step_px) / 2;
        let off_y = lo_y + (hi_y - lo_y - (ny - 1) * step_px) / 2;
        let points = (0..ny)
            .flat_map(|iy| {
                (0..nx)
                    .map(move |ix| [(off_x + ix * step_px) as f64, (off_y + iy * step_px) as f64])
            })
            .collect();
        Ok(Self {
            nx,
            ny,
            step_px,
            points,
        })
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The 4-neighbours of POI `i`.
    pub fn neighbours(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        let (ix, iy) = (i % self.nx, i / self.nx);
        let left = (ix > 0).then(|| i - 1);
        let right = (ix + 1 < self.nx).then(|| i + 1);
        let up = (iy > 0).then(|| i - self.nx);
        let down = (iy + 1 < self.ny).then(|| i + self.nx);
        [left, right, up, down].into_iter().flatten()
    }

    /// The POI nearest the grid's centre.
    pub fn centre(&self) -> usize {
        (self.ny / 2) * self.nx + self.nx / 2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_fits_subsets_and_errors_name_the_parameter() {
        let g = PoiGrid::new([100, 50, 200, 120], "roi_px", 10, 31, 512, 512).unwrap();
        for p in &g.points {
            assert!(p[0] - 15.0 >= 100.0 && p[0] + 15.0 <= 200.0);
            assert!(p[1] - 15.0 >= 50.0 && p[1] + 15.0 <= 120.0);
        }
        assert_eq!((g.nx, g.ny), (8, 5));
        let e = PoiGrid::new([100, 50, 120, 120], "roi_px", 10, 31, 512, 512).unwrap_err();
        assert!(
            matches!(e, DicError::Param { ref param, .. } if param == "subset_px"),
            "{e}"
        );
        let e = PoiGrid::new([100, 50, 100, 120], "roi_px", 10, 31, 512, 512).unwrap_err();
        assert!(
            e.to_string().contains("roi_px") && e.to_string().contains("empty"),
            "{e}"
        );
    }
}
