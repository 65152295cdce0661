//! Disjoint sets over the pixels of a map, for labelling contact patches as
//! the truncating plane descends.
//!
//! The classic structure of Tarjan (1975), with union by size and path
//! compression, so a whole sweep over n pixels costs O(n α(n)). Pixels start
//! "untouched"; [`PixelSets::touch`] makes one a singleton set when the plane
//! reaches it. Indices are `u32` to halve the memory of 67 M-pixel maps.
//!
//! Which pixels are touched is also kept as one bit per pixel: the sweep
//! asks it of eight neighbours per added pixel, and the bits of a 2048²
//! map (512 KiB) stay in cache where the 16 MiB of parents do not.

/// Marks a pixel the plane has not reached yet.
const UNTOUCHED: u32 = u32::MAX;

/// The largest number of pixels a map may have (one index is the sentinel).
pub const MAX_PIXELS: usize = UNTOUCHED as usize;

/// Disjoint sets of touched pixels.
#[derive(Clone, Debug)]
pub struct PixelSets {
    /// Parent of each pixel; a root is its own parent.
    parent: Vec<u32>,
    /// Pixel count of the set rooted here; meaningful for roots only.
    /// Starts at 1 everywhere, so touching a pixel need not write it.
    size: Vec<u32>,
    /// Bit `p % 64` of word `p / 64`: pixel p is touched.
    touched: Vec<u64>,
}

impl PixelSets {
    /// `n` untouched pixels; `n` must not exceed [`MAX_PIXELS`].
    pub fn new(n: usize) -> Self {
        assert!(n <= MAX_PIXELS, "{n} pixels exceed the index range");
        Self {
            parent: vec![UNTOUCHED; n],
            size: vec![1; n],
            touched: vec![0; n.div_ceil(64)],
        }
    }

    pub fn is_touched(&self, pixel: u32) -> bool {
        self.touched[pixel as usize / 64] >> (pixel % 64) & 1 == 1
    }

    /// Makes `pixel` a new singleton set.
    pub fn touch(&mut self, pixel: u32) {
        self.parent[pixel as usize] = pixel;
        self.touched[pixel as usize / 64] |= 1 << (pixel % 64);
    }

    /// Joins the singleton set of `pixel`, just touched, to the set rooted
    /// at `root`: what [`PixelSets::link`] would do (a singleton is never
    /// larger), without reading the singleton's size.
    pub fn attach(&mut self, pixel: u32, root: u32) {
        self.parent[pixel as usize] = root;
        self.size[root as usize] += 1;
    }

    /// The root of `pixel`'s set, compressing the path to it.
    pub fn find(&mut self, pixel: u32) -> u32 {
        let mut root = pixel;
        while self.parent[root as usize] != root {
            root = self.parent[root as usize];
        }
        // Second pass: point every pixel on the path straight at the root.
        let mut p = pixel;
        while p != root {
            let next = self.parent[p as usize];
            self.parent[p as usize] = root;
            p = next;
        }
        root
    }

    /// Joins the sets of two touched pixels; true if they were apart.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.link(ra, rb);
        true
    }

    /// Joins two distinct roots and returns the root of the joined set.
    pub fn link(&mut self, ra: u32, rb: u32) -> u32 {
        // Union by size: the smaller tree hangs under the larger one, so no
        // path grows longer than log2(n) even before compression.
        let (big, small) = if self.size[ra as usize] >= self.size[rb as usize] {
            (ra, rb)
        } else {
            (rb, ra)
        };
        self.parent[small as usize] = big;
        self.size[big as usize] += self.size[small as usize];
        big
    }

    /// The pixel count of every set, in pixel order of their roots.
    pub fn set_sizes(&self) -> Vec<u32> {
        self.parent
            .iter()
            .enumerate()
            .filter(|&(i, &p)| p as usize == i)
            .map(|(i, _)| self.size[i])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unions_track_sets_and_sizes() {
        let mut s = PixelSets::new(6);
        for p in [0, 1, 2, 4] {
            s.touch(p);
        }
        assert!(!s.is_touched(3));
        assert!(s.union(0, 1));
        assert!(s.union(2, 1));
        assert!(!s.union(0, 2), "already joined");
        assert_eq!(s.find(2), s.find(0));
        let mut sizes = s.set_sizes();
        sizes.sort_unstable();
        assert_eq!(sizes, [1, 3]);
    }

    #[test]
    fn a_long_chain_is_compressed() {
        let n = 1000;
        let mut s = PixelSets::new(n);
        for p in 0..n as u32 {
            s.touch(p);
        }
        for p in 1..n as u32 {
            s.union(p - 1, p);
        }
        let root = s.find(0);
        assert!((0..n as u32).all(|p| s.parent[p as usize] == root || s.find(p) == root));
        assert!((0..n as u32).all(|p| s.parent[p as usize] == root));
        assert_eq!(s.set_sizes(), [n as u32]);
    }
}
