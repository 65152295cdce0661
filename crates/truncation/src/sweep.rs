//! The plane's descent through the map: each newly touched pixel becomes a
//! patch of its own and is joined to the patches of its touched neighbours,
//! so N changes by +1 per added pixel and −1 per successful union.
//!
//! Fewer look-ups with 8-connectivity: two of a pixel's neighbours that
//! are 8-neighbours of each other, if both touched, were joined when the
//! later of them was added, so they are one patch already. Going round the
//! ring of neighbours, a touched neighbour next to an already visited
//! touched one needs no `find`. This is the neighbourhood reasoning of the
//! decision-tree labelling of Wu, Otoo and Suzuki (Pattern Anal. Appl. 12,
//! 2009, "Optimizing two-pass connected-component labeling algorithms"),
//! here in its simplest form; on a smooth height map most pixels then do
//! one `find` instead of several. 4-neighbours are never 4-neighbours of
//! each other, so 4-connectivity looks every touched one up.

use crate::levels::Connectivity;
use crate::union_find::PixelSets;

/// The neighbours of a pixel, going round it: (dx, dy) and, for each, the
/// bit mask of the EARLIER ones in this list that touch it under the
/// connectivity.
fn ring(connectivity: Connectivity) -> &'static [((isize, isize), u8)] {
    // N, NE, E, SE, S, SW, W, NW (N = −x). Each touches its ring
    // neighbours; the edge ones also touch the edge ones two steps round
    // (N–E, E–S, S–W, W–N). Bit i stands for entry i.
    const EIGHT: [((isize, isize), u8); 8] = [
        ((-1, 0), 0),
        ((-1, 1), 0b0000_0001),
        ((0, 1), 0b0000_0011),
        ((1, 1), 0b0000_0100),
        ((1, 0), 0b0000_1100),
        ((1, -1), 0b0001_0000),
        ((0, -1), 0b0011_0001),
        ((-1, -1), 0b0100_0001),
    ];
    const FOUR: [((isize, isize), u8); 4] = [((-1, 0), 0), ((0, 1), 0), ((1, 0), 0), ((0, -1), 0)];
    match connectivity {
        Connectivity::Eight => &EIGHT,
        Connectivity::Four => &FOUR,
    }
}

/// The touched pixels joined into patches, and how many of each so far.
pub struct Sweep {
    sets: PixelSets,
    /// Index steps to the neighbours in the framed map, in [`ring`] order.
    offsets: Vec<i32>,
    /// For each neighbour, the earlier neighbours already in its patch.
    joined_before: Vec<u8>,
    /// Pixels touched so far.
    pub added: usize,
    /// Connected touched patches N.
    pub patches: u64,
}

impl Sweep {
    /// An untouched framed map of `pixels` pixels, `stride` per row.
    pub fn new(connectivity: Connectivity, pixels: usize, stride: usize) -> Self {
        let ring = ring(connectivity);
        Self {
            sets: PixelSets::new(pixels),
            offsets: ring
                .iter()
                .map(|&((ox, oy), _)| (ox * stride as isize + oy) as i32)
                .collect(),
            joined_before: ring.iter().map(|&(_, mask)| mask).collect(),
            added: 0,
            patches: 0,
        }
    }

    /// Touches `pixels` (framed indices, never on the frame), one by one.
    pub fn add(&mut self, pixels: &[u32]) {
        for &pixel in pixels {
            self.sets.touch(pixel);
            self.patches += 1;
            let mut touched = 0_u8;
            for (i, &offset) in self.offsets.iter().enumerate() {
                let neighbour = pixel.wrapping_add_signed(offset);
                touched |= u8::from(self.sets.is_touched(neighbour)) << i;
            }
            // The new pixel's root, kept current so it is found only once.
            let mut root = pixel;
            let mut left = touched;
            while left != 0 {
                let i = left.trailing_zeros() as usize;
                left &= left - 1;
                if touched & self.joined_before[i] != 0 {
                    continue;
                }
                let other = self.sets.find(pixel.wrapping_add_signed(self.offsets[i]));
                if root == pixel {
                    // Still a singleton: it joins `other` (never apart).
                    self.sets.attach(pixel, other);
                    root = other;
                    self.patches -= 1;
                } else if other != root {
                    root = self.sets.link(root, other);
                    self.patches -= 1;
                }
            }
        }
        self.added += pixels.len();
    }

    /// Every patch's area, largest first.
    pub fn patch_areas_m2(&self, pixel_area_m2: f64) -> Vec<f64> {
        let mut sizes = self.sets.set_sizes();
        sizes.sort_unstable_by(|a, b| b.cmp(a));
        sizes
            .into_iter()
            .map(|s| f64::from(s) * pixel_area_m2)
            .collect()
    }
}
