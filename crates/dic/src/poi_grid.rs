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
    /// Whether each POI is analysed (its subset inside the region; all,
    /// until [`PoiGrid::restrict`]).
    pub active: Vec<bool>,
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
        let points: Vec<[f64; 2]> = (0..ny)
            .flat_map(|iy| {
                (0..nx)
                    .map(move |ix| [(off_x + ix * step_px) as f64, (off_y + iy * step_px) as f64])
            })
            .collect();
        let active = vec![true; points.len()];
        Ok(Self {
            nx,
            ny,
            step_px,
            points,
            active,
        })
    }

    /// Keeps active only the POIs for which `keep` (of the frame-0 pixel
    /// position) holds; returns how many are left.
    pub fn restrict(&mut self, keep: impl Fn(usize, usize) -> bool) -> usize {
        for (p, active) in self.points.iter().zip(&mut self.active) {
            *active &= keep(p[0] as usize, p[1] as usize);
        }
        self.active_count()
    }

    /// How many POIs are analysed.
    pub fn active_count(&self) -> usize {
        self.active.iter().filter(|a| **a).count()
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

    /// Up to `blocks × blocks` of the POIs for which `eligible` holds,
    /// spread over the grid: the grid is cut into `blocks` bands each way
    /// and each block gives its eligible POI nearest the block's middle.
    pub fn spread(&self, blocks: usize, eligible: impl Fn(usize) -> bool) -> Vec<usize> {
        let blocks = blocks.max(1);
        let band = |n: usize| n.div_ceil(blocks).max(1);
        let (bx, by) = (band(self.nx), band(self.ny));
        let mut best: std::collections::BTreeMap<(usize, usize), (usize, usize)> =
            std::collections::BTreeMap::new();
        for i in (0..self.len()).filter(|&i| eligible(i)) {
            let (ix, iy) = (i % self.nx, i / self.nx);
            let key = (iy / by, ix / bx);
            let (mx, my) = (key.1 * bx + bx / 2, key.0 * by + by / 2);
            let d = ix.abs_diff(mx).pow(2) + iy.abs_diff(my).pow(2);
            let entry = best.entry(key).or_insert((d, i));
            if d < entry.0 {
                *entry = (d, i);
            }
        }
        best.into_values().map(|(_, i)| i).collect()
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
        assert_eq!(g.active_count(), 40);
        // Two blocks each way (columns 0–3, 4–7; rows 0–2, 3–4): one POI
        // per block, nearest its middle (column 2 or 6, row 1 or 4).
        assert_eq!(g.spread(2, |_| true), [8 + 2, 8 + 6, 4 * 8 + 2, 4 * 8 + 6]);
        // Blocks with nothing eligible give nothing; the others their best.
        assert_eq!(g.spread(2, |i| i % 8 >= 4), [8 + 6, 4 * 8 + 6]);
        assert_eq!(g.spread(2, |i| i % 8 >= 5 && i / 8 == 0), [6]);
        let mut g = g;
        assert_eq!(g.restrict(|x, _| x > 150), 40 - 5 * 4);
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
