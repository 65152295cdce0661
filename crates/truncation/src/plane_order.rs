//! The order in which the descending planes touch the measured pixels,
//! grouped by plane.
//!
//! The profile reads A and N only at the planes, and both belong to the
//! touched SET (its size and its number of connected components), not to
//! the order in which its pixels were added; so are the patch sizes of a
//! snapshot. The pixels therefore need not be sorted by height: it is
//! enough to group them by the first plane that touches them, a counting
//! sort (Cormen, Leiserson, Rivest and Stein, *Introduction to Algorithms*,
//! §8.2: count, prefix-sum, scatter) in two linear passes instead of an
//! O(n log n) comparison sort of 4 M heights. Within a group the pixels
//! stay in raster order, so the union–find that follows reads memory near
//! the previous pixel's rather than scattered by height.
//!
//! With `levels: all` every distinct height is a plane, so the heights are
//! sorted, highest first, and every group holds one height's pixels.

use rayon::slice::ParallelSliceMut;

use crate::TruncationError;
use crate::levels::Levels;

/// The planes and the measured pixels grouped by the first plane at or
/// below their height.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneOrder {
    /// Plane heights above the lowest measured point, top down, m.
    pub planes_m: Vec<f64>,
    /// Framed-map indices of the measured pixels, grouped by plane, the
    /// groups top down.
    pub pixels: Vec<u32>,
    /// `pixels[ends[k − 1]..ends[k]]` (from 0 for k = 0) are the pixels that
    /// plane k touches and plane k − 1 does not.
    pub ends: Vec<u32>,
}

/// Groups the measured pixels of `flat` (row-major, `ny` per row; NaN = not
/// measured) by plane; a pixel (ix, iy) is `(ix + 1)·stride + iy + 1` in the
/// framed map. Errors: an infinite height, nothing measured, a flat map.
pub fn plane_order(
    flat: &[f64],
    ny: usize,
    stride: usize,
    levels: Levels,
) -> Result<PlaneOrder, TruncationError> {
    if let Some(i) = flat.iter().position(|h| h.is_infinite()) {
        return Err(TruncationError::NonFinite {
            ix: i / ny,
            iy: i % ny,
            value: flat[i],
        });
    }
    let (h_min, h_max) = flat
        .iter()
        .filter(|h| !h.is_nan())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    if h_min == f64::INFINITY {
        return Err(TruncationError::NothingMeasured);
    }
    // Subtracting h_min is monotone under rounding, so this is the largest
    // of the heights above the lowest point, to the bit.
    let z_max_m = h_max - h_min;
    if z_max_m <= 0.0 {
        return Err(TruncationError::Flat);
    }
    let framed = |i: usize| ((i / ny + 1) * stride + i % ny + 1) as u32;
    match levels {
        Levels::Count(_) => {
            let planes_m = levels.planes_m(std::iter::empty(), z_max_m);
            let (pixels, ends) = group_by_plane(flat, h_min, &planes_m, framed);
            Ok(PlaneOrder {
                planes_m,
                pixels,
                ends,
            })
        }
        Levels::All => Ok(sorted_by_height(flat, h_min, levels, z_max_m, framed)),
    }
}

/// The first plane k with `z_m ≥ planes_m[k]`, for the equal steps
/// z_k = z_max (n − k) / n of [`Levels::Count`] (`planes_m[n]` = 0 ≤ z_m);
/// `steps_per_m` = n / z_max. The arithmetic guess is right, or one short
/// after truncation, but for rounding; it is accepted only if the very
/// comparison the sweep makes agrees, and otherwise (e.g. heights so small
/// that n / z_max overflows) a binary search over the planes decides.
fn first_plane_at_or_below(z_m: f64, planes_m: &[f64], steps_per_m: f64) -> usize {
    let n = planes_m.len() - 1;
    // `as` truncates and saturates (NaN and negatives give 0).
    let guess = (((planes_m[0] - z_m) * steps_per_m) as usize).min(n);
    for k in [guess, guess + 1] {
        if k <= n && z_m >= planes_m[k] && (k == 0 || z_m < planes_m[k - 1]) {
            return k;
        }
    }
    planes_m.partition_point(|&plane_m| z_m < plane_m)
}

/// The counting sort of the module doc: how many measured pixels each
/// plane adds, then each plane's share of `pixels`, then the pixels in
/// raster order into their plane's share. The plane of a pixel is worked
/// out twice rather than stored: that is cheaper than writing and reading
/// back one more array as large as the map.
fn group_by_plane(
    flat: &[f64],
    h_min: f64,
    planes_m: &[f64],
    framed: impl Fn(usize) -> u32,
) -> (Vec<u32>, Vec<u32>) {
    let steps_per_m = (planes_m.len() - 1) as f64 / planes_m[0];
    let plane_of = |h: f64| first_plane_at_or_below(h - h_min, planes_m, steps_per_m);
    let mut ends = vec![0_u32; planes_m.len()];
    for &h in flat.iter().filter(|h| !h.is_nan()) {
        ends[plane_of(h)] += 1;
    }
    // Exclusive prefix sums: where each plane's share starts.
    let mut start = 0;
    for count in &mut ends {
        let c = *count;
        *count = start;
        start += c;
    }
    let mut pixels = vec![0_u32; start as usize];
    for (i, &h) in flat.iter().enumerate() {
        if !h.is_nan() {
            let next = &mut ends[plane_of(h)];
            pixels[*next as usize] = framed(i);
            // After the scatter each start has moved on to its share's end.
            *next += 1;
        }
    }
    (pixels, ends)
}

/// `levels: all`: the measured pixels sorted by height, highest first, one
/// plane per distinct height.
fn sorted_by_height(
    flat: &[f64],
    h_min: f64,
    levels: Levels,
    z_max_m: f64,
    framed: impl Fn(usize) -> u32,
) -> PlaneOrder {
    let mut order: Vec<(f64, u32)> = flat
        .iter()
        .enumerate()
        .filter(|(_, h)| !h.is_nan())
        .map(|(i, &h)| (h - h_min, framed(i)))
        .collect();
    order.par_sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
    let planes_m = levels.planes_m(order.iter().map(|&(z, _)| z), z_max_m);
    let mut ends = Vec::with_capacity(planes_m.len());
    let mut end = 0;
    for &z_m in &planes_m {
        while end < order.len() && order[end].0 >= z_m {
            end += 1;
        }
        ends.push(end as u32);
    }
    PlaneOrder {
        planes_m,
        pixels: order.into_iter().map(|(_, pixel)| pixel).collect(),
        ends,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_plane_is_the_one_the_sweep_would_stop_at() {
        // Heights on, just above and just below every plane of a few counts.
        // 1e-310 is subnormal: n / z_max overflows and the guess is NaN.
        for (n, z_max_m) in [1_u32, 3, 7, 1000]
            .into_iter()
            .flat_map(|n| [3.7e-5, 1e-310, f64::MAX / 2.0].map(|z| (n, z)))
        {
            let planes = Levels::Count(n).planes_m(std::iter::empty(), z_max_m);
            let steps_per_m = f64::from(n) / z_max_m;
            for &z in &planes {
                for z_m in [z, z.next_up(), z.next_down().max(0.0)] {
                    let expected = planes.iter().position(|&p| z_m >= p).unwrap();
                    assert_eq!(
                        first_plane_at_or_below(z_m, &planes, steps_per_m),
                        expected,
                        "{z_m}"
                    );
                }
            }
        }
    }

    #[test]
    fn groups_hold_each_plane_s_new_pixels_in_raster_order() {
        // 2 × 3 map, ny = 3, stride 5; one NaN.
        let flat = [4.0, 1.0, f64::NAN, 3.0, 5.0, 1.0];
        let order = plane_order(&flat, 3, 5, Levels::Count(4)).unwrap();
        // Above the lowest (1): 3, 0, -, 2, 4, 0; planes 4, 3, 2, 1, 0.
        assert_eq!(order.planes_m, [4.0, 3.0, 2.0, 1.0, 0.0]);
        let framed = |ix: u32, iy: u32| (ix + 1) * 5 + iy + 1;
        let expected = [
            framed(1, 1),
            framed(0, 0),
            framed(1, 0),
            framed(0, 1),
            framed(1, 2),
        ];
        assert_eq!(order.pixels, expected);
        assert_eq!(order.ends, [1, 2, 3, 3, 5]);
        let all = plane_order(&flat, 3, 5, Levels::All).unwrap();
        assert_eq!(all.planes_m, [4.0, 3.0, 2.0, 0.0]);
        assert_eq!(all.ends, [1, 2, 3, 5]);
    }
}
