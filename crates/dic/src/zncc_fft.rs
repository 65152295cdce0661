//! Integer-pixel initial guess by zero-normalised cross-correlation over a
//! search window: the subset's ZNCC at every integer shift at once, by the
//! workspace's FFT correlator (`hypercontact_numeric::zncc`: the numerator
//! Σ (T − T̄) S by FFT, the window means and norms under every shift from
//! summed-area tables, as in Lewis, "Fast normalized cross-correlation",
//! Vision Interface 1995).

use hypercontact_numeric::zncc::Correlator;

use crate::gray::GrayImage;

/// The best integer match of a template.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegerMatch {
    /// Displacement of the template centre, pixels.
    pub dx: i64,
    pub dy: i64,
    pub zncc: f64,
}

/// The pixels of `target` searched: [x0, x0 + width) × [y0, y0 + height).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SearchWindow {
    x0: usize,
    y0: usize,
    width: usize,
    height: usize,
}

impl SearchWindow {
    /// The pixels within `reach` of (cx, cy), clipped to the image; None
    /// when fewer than `side` remain either way.
    fn around(target: &GrayImage, cx: i64, cy: i64, reach: usize, side: usize) -> Option<Self> {
        let reach = reach as i64;
        if cx + reach < 0 || cy + reach < 0 {
            return None;
        }
        let x0 = (cx - reach).max(0) as usize;
        let y0 = (cy - reach).max(0) as usize;
        let x1 = ((cx + reach) as usize).min(target.width.saturating_sub(1));
        let y1 = ((cy + reach) as usize).min(target.height.saturating_sub(1));
        if x1 < x0 + side - 1 || y1 < y0 + side - 1 {
            return None;
        }
        Some(Self {
            x0,
            y0,
            width: x1 - x0 + 1,
            height: y1 - y0 + 1,
        })
    }

    /// The window's pixels of `image`, row-major.
    fn pixels(&self, image: &GrayImage) -> Vec<f64> {
        (self.y0..self.y0 + self.height)
            .flat_map(|y| (self.x0..self.x0 + self.width).map(move |x| image.get(x, y)))
            .collect()
    }
}

/// Finds the integer displacement of the `2 half + 1` square around
/// `(x0, y0)` in `reference` within ±`radius` pixels of `(cx, cy)` in
/// `target`; None if the template is flat or the window empty.
#[allow(clippy::too_many_arguments)]
pub fn integer_search(
    reference: &GrayImage,
    x0: usize,
    y0: usize,
    half: usize,
    target: &GrayImage,
    cx: i64,
    cy: i64,
    radius: usize,
) -> Option<IntegerMatch> {
    let side = 2 * half + 1;
    if x0 < half || y0 < half || x0 + half >= reference.width || y0 + half >= reference.height {
        return None;
    }
    let window = SearchWindow::around(target, cx, cy, radius + half, side)?;
    let subset = SearchWindow {
        x0: x0 - half,
        y0: y0 - half,
        width: side,
        height: side,
    };
    // The sizes agree by construction: a refusal would be a bug, and gives
    // no guess rather than a panic.
    let correlator = Correlator::new(
        &subset.pixels(reference),
        (side, side),
        (window.width, window.height),
        1.0,
    )
    .ok()??;
    let peak = correlator.best(&window.pixels(target)).ok()??;
    let (sx, sy) = peak.cell;
    Some(IntegerMatch {
        dx: (window.x0 + sx + half) as i64 - x0 as i64,
        dy: (window.y0 + sy + half) as i64 - y0 as i64,
        zncc: peak.zncc,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_an_integer_shift_and_matches_direct_zncc() {
        // A pseudo-random texture shifted by (7, -4) pixels.
        let (w, h) = (96, 80);
        let texture = |x: i64, y: i64| {
            let k = (x * 73_856_093) ^ (y * 19_349_663);
            ((k.wrapping_mul(2_654_435_761) >> 7) & 1023) as f64 / 1023.0
        };
        let mut a = Vec::new();
        let mut b = Vec::new();
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                a.push(texture(x, y));
                b.push(texture(x - 7, y + 4));
            }
        }
        let a = GrayImage::new(w, h, a).unwrap();
        let b = GrayImage::new(w, h, b).unwrap();
        let m = integer_search(&a, 40, 40, 7, &b, 40, 40, 12).unwrap();
        assert_eq!((m.dx, m.dy), (7, -4));
        assert!((m.zncc - 1.0).abs() < 1e-9, "{}", m.zncc);
    }

    #[test]
    fn a_window_is_clipped_to_the_image_and_refused_when_too_small() {
        let image = GrayImage::new(50, 40, vec![0.5; 2000]).unwrap();
        let inside = SearchWindow::around(&image, 25, 20, 10, 7).unwrap();
        assert_eq!(
            (inside.x0, inside.y0, inside.width, inside.height),
            (15, 10, 21, 21)
        );
        let corner = SearchWindow::around(&image, 2, 38, 10, 7).unwrap();
        assert_eq!(
            (corner.x0, corner.y0, corner.width, corner.height),
            (0, 28, 13, 12)
        );
        // beyond the image, or too few pixels left for the subset
        assert_eq!(SearchWindow::around(&image, -11, 20, 10, 7), None);
        assert_eq!(SearchWindow::around(&image, 60, 20, 10, 7), None);
        // rows 0..=6 above a centre at −4: just the 7 the subset needs
        assert_eq!(
            SearchWindow::around(&image, 25, -4, 10, 7).map(|w| w.height),
            Some(7)
        );
        assert_eq!(SearchWindow::around(&image, 25, -5, 10, 7), None);
        assert!(SearchWindow::around(&image, 25, -5, 10, 6).is_some());
        let pixels = corner.pixels(&image);
        assert_eq!(pixels.len(), 13 * 12);
    }

    #[test]
    fn a_subset_off_the_reference_or_a_flat_one_gives_no_guess() {
        let texture: Vec<f64> = (0..60 * 60)
            .map(|k| ((k * 7919) % 101) as f64 / 100.0)
            .collect();
        let image = GrayImage::new(60, 60, texture).unwrap();
        // the subset reaches past the reference's edge
        assert_eq!(integer_search(&image, 3, 30, 5, &image, 30, 30, 5), None);
        assert_eq!(integer_search(&image, 30, 55, 5, &image, 30, 30, 5), None);
        assert!(integer_search(&image, 30, 30, 5, &image, 30, 30, 5).is_some());
        let flat = GrayImage::new(60, 60, vec![0.25; 3600]).unwrap();
        assert_eq!(integer_search(&flat, 30, 30, 5, &image, 30, 30, 5), None);
        // a flat target has no window to match
        assert_eq!(integer_search(&image, 30, 30, 5, &flat, 30, 30, 5), None);
    }
}
