//! Box sums in O(1) each by a summed-area table (Crow, "Summed-area tables
//! for texture mapping", SIGGRAPH 1984): S(x, y) = Σ over [0, x) × [0, y),
//! and a box's sum is four corners of S.

/// The summed-area table of a row-major `width × height` array.
pub(crate) struct SummedArea {
    width: usize,
    /// (width + 1) × (height + 1); entry (x, y) sums [0, x) × [0, y)
    table: Vec<f64>,
}

impl SummedArea {
    pub(crate) fn new(values: &[f64], width: usize, height: usize) -> Self {
        let stride = width + 1;
        let mut table = vec![0.0; stride * (height + 1)];
        for y in 0..height {
            // Each row's running sum added to the table above it.
            let mut row = 0.0;
            for x in 0..width {
                row += values[y * width + x];
                table[(y + 1) * stride + x + 1] = table[y * stride + x + 1] + row;
            }
        }
        Self { width, table }
    }

    /// Σ over [x, x + w) × [y, y + h).
    pub(crate) fn window(&self, x: usize, y: usize, w: usize, h: usize) -> f64 {
        let s = self.width + 1;
        let t = &self.table;
        t[(y + h) * s + x + w] - t[y * s + x + w] - t[(y + h) * s + x] + t[y * s + x]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_sum_what_they_cover() {
        let (w, h) = (7, 5);
        // integers: every sum exact, whatever the order of additions
        let values: Vec<f64> = (0..w * h).map(|k| ((k * 13) % 11) as f64 - 5.0).collect();
        let table = SummedArea::new(&values, w, h);
        for (x, y, bw, bh) in [(0, 0, 7, 5), (2, 1, 3, 4), (6, 4, 1, 1), (3, 2, 0, 2)] {
            let mut direct = 0.0;
            for v in y..y + bh {
                for u in x..x + bw {
                    direct += values[v * w + u];
                }
            }
            assert_eq!(table.window(x, y, bw, bh), direct, "({x}, {y}) {bw}×{bh}");
        }
    }
}
