//! The brute-force reference: label the touched pixels of ONE plane with a
//! plain flood fill. Relabelling at every plane costs O(levels · pixels);
//! the stage never does that. This exists as an independent check of the
//! union–find sweep in tests, and as the baseline of the benchmark.

use ndarray::ArrayView2;

use crate::levels::Connectivity;

/// Pixels with h ≥ `threshold_m` (NaN never) and their number of connected
/// patches: `(touched, patches)`.
pub fn label_at(
    heights: ArrayView2<f64>,
    threshold_m: f64,
    connectivity: Connectivity,
) -> (usize, usize) {
    let (nx, ny) = heights.dim();
    let touched = |ix: usize, iy: usize| heights[[ix, iy]] >= threshold_m;
    let mut seen = vec![false; nx * ny];
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let (mut count, mut patches) = (0, 0);
    for sx in 0..nx {
        for sy in 0..ny {
            if seen[sx * ny + sy] || !touched(sx, sy) {
                continue;
            }
            patches += 1;
            seen[sx * ny + sy] = true;
            stack.push((sx, sy));
            while let Some((ix, iy)) = stack.pop() {
                count += 1;
                for &(ox, oy) in connectivity.offsets() {
                    let (Some(jx), Some(jy)) =
                        (ix.checked_add_signed(ox), iy.checked_add_signed(oy))
                    else {
                        continue;
                    };
                    if jx < nx && jy < ny && !seen[jx * ny + jy] && touched(jx, jy) {
                        seen[jx * ny + jy] = true;
                        stack.push((jx, jy));
                    }
                }
            }
        }
    }
    (count, patches)
}
