//! Disjoint sets over the pixels of a map, for labelling contact patches as
//! the truncating plane descends.
//!
//! The classic structure of Tarjan (1975), with union by size and path
//! compression, so a whole sweep over n pixels costs O(n α(n)). Pixels start
//! "untouched"; [`PixelSets::touch`] makes one a singleton set when the plane
//! reaches it. Indices are `u32` to halve the memory of 67 M-pixel maps.
//!
//! Which pixels are touched, and which are roots, are also kept as one bit
//! per pixel: the sweep asks the first of eight neighbours per added
//! pixel, and `find` the second at every step; the bits of a 2048² map
//! (512 KiB each) stay in cache where the 16 MiB of parents do not. A
//! root's parent slot, which would only point at itself, holds its set's
//! size instead, so the union after a `find` touches no other array.

/// The largest number of pixels a map may have (indices are `u32`).
pub const MAX_PIXELS: usize = u32::MAX as usize;

/// One bit per pixel, in 64-bit words.
#[derive(Clone, Debug)]
struct Bits(Vec<u64>);

impl Bits {
    fn new(n: usize) -> Self {
        Self(vec![0; n.div_ceil(64)])
    }

    fn get(&self, i: u32) -> bool {
        self.0[i as usize / 64] >> (i % 64) & 1 == 1
    }

    fn set(&mut self, i: u32) {
        self.0[i as usize / 64] |= 1 << (i % 64);
    }

    fn clear(&mut self, i: u32) {
        self.0[i as usize / 64] &= !(1 << (i % 64));
    }
}

/// Disjoint sets of touched pixels.
#[derive(Clone, Debug)]
pub struct PixelSets {
    /// Per touched pixel: its parent, or for a root its set's pixel count.
    slot: Vec<u32>,
    touched: Bits,
    root: Bits,
}

impl PixelSets {
    /// `n` untouched pixels; `n` must not exceed [`MAX_PIXELS`].
    pub fn new(n: usize) -> Self {
        assert!(n <= MAX_PIXELS, "{n} pixels exceed the index range");
        Self {
            slot: vec![0; n],
            touched: Bits::new(n),
            root: Bits::new(n),
        }
    }

    pub fn is_touched(&self, pixel: u32) -> bool {
        self.touched.get(pixel)
    }

    /// The parent of a touched pixel; a root is its own.
    pub fn parent(&self, pixel: u32) -> u32 {
        if self.root.get(pixel) {
            pixel
        } else {
            self.slot[pixel as usize]
        }
    }

    /// Makes `pixel` a new singleton set.
    pub fn touch(&mut self, pixel: u32) {
        self.slot[pixel as usize] = 1;
        self.touched.set(pixel);
        self.root.set(pixel);
    }

    /// Hangs the root `child` under the root `root`.
    fn hang(&mut self, child: u32, root: u32) {
        self.slot[root as usize] += self.slot[child as usize];
        self.slot[child as usize] = root;
        self.root.clear(child);
    }

    /// Joins the singleton set of `pixel`, just touched, to the set rooted
    /// at `root`: what [`PixelSets::link`] would do (a singleton is never
    /// larger), without reading the singleton's size.
    pub fn attach(&mut self, pixel: u32, root: u32) {
        self.slot[root as usize] += 1;
        self.slot[pixel as usize] = root;
        self.root.clear(pixel);
    }

    /// The root of `pixel`'s set, compressing the path to it.
    pub fn find(&mut self, pixel: u32) -> u32 {
        let mut root = pixel;
        while !self.root.get(root) {
            root = self.slot[root as usize];
        }
        // Second pass: point every pixel on the path straight at the root.
        let mut p = pixel;
        while p != root {
            let next = self.slot[p as usize];
            self.slot[p as usize] = root;
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
        let (big, small) = if self.slot[ra as usize] >= self.slot[rb as usize] {
            (ra, rb)
        } else {
            (rb, ra)
        };
        self.hang(small, big);
        big
    }

    /// The pixel count of every set, in pixel order of their roots.
    pub fn set_sizes(&self) -> Vec<u32> {
        (0..self.slot.len() as u32)
            .filter(|&i| self.root.get(i))
            .map(|i| self.slot[i as usize])
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
        assert!((0..n as u32).all(|p| s.parent(p) == root || s.find(p) == root));
        assert!((0..n as u32).all(|p| s.parent(p) == root));
        assert_eq!(s.set_sizes(), [n as u32]);
    }
}
