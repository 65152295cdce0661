//! The region a DIC analyses, in frame-0 pixels: the intersection of a
//! rectangle (`roi_px`), a polygon (`roi_polygon_px`) and a mask image
//! (non-zero = analyse), any of them optional. Holes, notches and grips are
//! cut out by the polygon or the mask; a POI is tracked only if its whole
//! subset lies inside ([`Region::holds_square`]).

use hypercontact_labfiles::sequence::{DecodedImage, Samples};

use crate::DicError;

/// Pixels to analyse, with a summed-area table for square queries.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    pub width: usize,
    pub height: usize,
    /// Row-major, `inside[y * width + x]`.
    pub inside: Vec<bool>,
    /// `sums[y * (width + 1) + x]`: inside pixels above and left of (x, y).
    sums: Vec<u32>,
}

/// Whether point (x, y) lies inside the polygon, by the even-odd
/// (crossing-number) rule, as W. R. Franklin's PNPOLY counts crossings.
pub fn in_polygon(polygon: &[[f64; 2]], x: f64, y: f64) -> bool {
    let mut inside = false;
    let mut j = polygon.len().wrapping_sub(1);
    for (i, a) in polygon.iter().enumerate() {
        let b = polygon[j];
        if (a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0] {
            inside = !inside;
        }
        j = i;
    }
    inside
}

impl Region {
    /// The pixels of a `width × height` frame inside every given limit:
    /// `rect` = [x0, y0, x1, y1] (inclusive, from `rect_name`), `polygon`
    /// (pixel centres, even-odd), `mask` (its file `mask_name`; non-zero
    /// pixels are inside).
    pub fn new(
        width: usize,
        height: usize,
        rect: Option<([usize; 4], &str)>,
        polygon: Option<&[[f64; 2]]>,
        mask: Option<(&DecodedImage, &str)>,
    ) -> Result<Self, DicError> {
        let mut inside = vec![true; width * height];
        if let Some(([x0, y0, x1, y1], name)) = rect {
            if x1 <= x0 || y1 <= y0 {
                return Err(DicError::param(
                    name,
                    format!(
                        "the region of interest {:?} is empty (need x0 < x1 and y0 < y1)",
                        [x0, y0, x1, y1]
                    ),
                ));
            }
            if x1 >= width || y1 >= height {
                return Err(DicError::param(
                    name,
                    format!(
                        "the region of interest {:?} leaves the {width} × {height} image",
                        [x0, y0, x1, y1]
                    ),
                ));
            }
            for (k, cell) in inside.iter_mut().enumerate() {
                let (x, y) = (k % width, k / width);
                *cell &= (x0..=x1).contains(&x) && (y0..=y1).contains(&y);
            }
        }
        if let Some(polygon) = polygon {
            if polygon.len() < 3 || polygon.iter().flatten().any(|v| !v.is_finite()) {
                return Err(DicError::param(
                    "roi_polygon_px",
                    format!(
                        "needs at least 3 finite [x, y] vertices in frame-0 pixels, e.g. \
                         [[10, 10], [200, 10], [200, 300]]; got {polygon:?}"
                    ),
                ));
            }
            for (k, cell) in inside.iter_mut().enumerate() {
                *cell &= in_polygon(polygon, (k % width) as f64, (k / width) as f64);
            }
        }
        if let Some((mask, name)) = mask {
            if (mask.width, mask.height) != (width, height) {
                return Err(DicError::file(
                    name,
                    format!(
                        "the mask is {} × {} pixels, the frames {width} × {height}",
                        mask.width, mask.height
                    ),
                ));
            }
            match &mask.samples {
                Samples::Counts { data, .. } => {
                    for (cell, &v) in inside.iter_mut().zip(data) {
                        *cell &= v != 0;
                    }
                }
                Samples::Float(data) => {
                    for (cell, &v) in inside.iter_mut().zip(data) {
                        *cell &= v != 0.0;
                    }
                }
            }
        }
        let mut sums = vec![0u32; (width + 1) * (height + 1)];
        for y in 0..height {
            let mut row = 0u32;
            for x in 0..width {
                row += u32::from(inside[y * width + x]);
                sums[(y + 1) * (width + 1) + x + 1] = sums[y * (width + 1) + x + 1] + row;
            }
        }
        Ok(Self {
            width,
            height,
            inside,
            sums,
        })
    }

    /// Inside pixels.
    pub fn count(&self) -> usize {
        self.sums[self.sums.len() - 1] as usize
    }

    /// The bounding box [x0, y0, x1, y1] of the inside pixels, if any.
    pub fn bounds(&self) -> Option<[usize; 4]> {
        let mut b: Option<[usize; 4]> = None;
        for (k, _) in self.inside.iter().enumerate().filter(|(_, c)| **c) {
            let (x, y) = (k % self.width, k / self.width);
            b = Some(match b {
                None => [x, y, x, y],
                Some([x0, y0, x1, y1]) => [x0.min(x), y0.min(y), x1.max(x), y1.max(y)],
            });
        }
        b
    }

    /// Whether the square of half-side `half` around pixel (x, y) lies
    /// wholly inside.
    pub fn holds_square(&self, x: usize, y: usize, half: usize) -> bool {
        let (Some(x0), Some(y0)) = (x.checked_sub(half), y.checked_sub(half)) else {
            return false;
        };
        let (x1, y1) = (x + half + 1, y + half + 1);
        if x1 > self.width || y1 > self.height {
            return false;
        }
        let w = self.width + 1;
        let total = self.sums[y1 * w + x1] + self.sums[y0 * w + x0]
            - self.sums[y0 * w + x1]
            - self.sums[y1 * w + x0];
        total as usize == (2 * half + 1) * (2 * half + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygon_rectangle_and_mask_intersect() {
        // A triangle holding the pixel centres x + y ≤ 10 (x, y ≥ 0), its
        // edges between pixel centres; and a notched square (non-convex).
        let triangle = [[-0.5, -0.5], [10.7, -0.5], [-0.5, 10.7]];
        let r = Region::new(20, 20, None, Some(&triangle), None).unwrap();
        for y in 0..20 {
            for x in 0..20 {
                assert_eq!(r.inside[y * 20 + x], x + y <= 10, "({x}, {y})");
            }
        }
        assert_eq!(r.count(), 66);
        let notched = [
            [0.5, 0.5],
            [9.5, 0.5],
            [9.5, 9.5],
            [5.5, 9.5],
            [5.5, 4.5],
            [4.5, 4.5],
            [4.5, 9.5],
            [0.5, 9.5],
        ];
        let r = Region::new(12, 12, None, Some(&notched), None).unwrap();
        for y in 0..12 {
            for x in 0..12 {
                let square = (1..=9).contains(&x) && (1..=9).contains(&y);
                let notch = x == 5 && y >= 5;
                assert_eq!(r.inside[y * 12 + x], square && !notch, "({x}, {y})");
            }
        }
        // A square mask with a hole, and a rectangle cutting its right side.
        let mut data = vec![1u16; 400];
        for y in 8..12 {
            for x in 8..12 {
                data[y * 20 + x] = 0;
            }
        }
        let mask = DecodedImage {
            width: 20,
            height: 20,
            samples: Samples::Counts { bits: 8, data },
            kind: "mask".into(),
        };
        let r = Region::new(
            20,
            20,
            Some(([2, 0, 15, 19], "roi_px")),
            None,
            Some((&mask, "m.png")),
        )
        .unwrap();
        assert_eq!(r.count(), 14 * 20 - 16);
        assert_eq!(r.bounds(), Some([2, 0, 15, 19]));
        assert!(r.holds_square(5, 5, 2) && !r.holds_square(6, 6, 2) && r.holds_square(5, 5, 0));
        assert!(!r.holds_square(14, 5, 2) && !r.holds_square(1, 1, 3));
        // Brute force against the summed-area table.
        for y in 0..20 {
            for x in 0..20 {
                for half in 0..4 {
                    let brute = x >= half
                        && y >= half
                        && x + half < 20
                        && y + half < 20
                        && (y - half..=y + half)
                            .all(|j| (x - half..=x + half).all(|i| r.inside[j * 20 + i]));
                    assert_eq!(r.holds_square(x, y, half), brute, "({x}, {y}) ± {half}");
                }
            }
        }
        let e = Region::new(21, 20, None, None, Some((&mask, "m.png")))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("m.png: the mask is 20 × 20 pixels, the frames 21 × 20"),
            "{e}"
        );
        let e = Region::new(20, 20, None, Some(&[[0.0, 0.0], [1.0, 1.0]]), None)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("roi_polygon_px") && e.contains("at least 3"),
            "{e}"
        );
    }
}
