//! Connected components (patches) of a contact mask, 8-connectivity.
//!
//! Two raster passes with an equivalence table (Rosenfeld & Pfaltz, 1966),
//! without recursion, so a 2048² all-contact mask labels in one go. The first
//! pass reads the already-labelled neighbours in the decision-tree order of
//! Wu, Otoo & Suzuki (2009): if the north pixel is contact, its label is taken
//! (west, north-west and north-east all touch north and were joined when they
//! were met); otherwise west or north-west, joined with north-east, or
//! north-east alone. Equivalences are a union–find whose root is always the
//! smallest provisional label, so a patch's root is the label created at its
//! first pixel in row-major order; the second pass numbers roots in order.
//!
//! **Order.** Patches are numbered 1, 2, … by their first pixel in row-major
//! order (top row first, left to right); 0 is background. Diagonal neighbours
//! touch (8-connectivity, as the `truncation` stage and MATLAB's `bwlabel`).

use crate::Mask;

/// The patches of a mask.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Labels {
    width: usize,
    height: usize,
    labels: Vec<u32>,
    sizes: Vec<u64>,
}

impl Labels {
    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Number of patches.
    pub fn count(&self) -> usize {
        self.sizes.len()
    }

    /// Pixel count of patch `k + 1` at index `k`.
    pub fn sizes(&self) -> &[u64] {
        &self.sizes
    }

    /// Patch number of every pixel, row-major: 0 for background, else 1..=count.
    pub fn labels(&self) -> &[u32] {
        &self.labels
    }

    /// Keeps the patches for which `keep(k)` holds (`k` from 0, patch `k + 1`),
    /// renumbered in the same order.
    pub(crate) fn retain(&mut self, keep: impl Fn(usize) -> bool) {
        let mut renumber = vec![0_u32; self.sizes.len() + 1];
        let mut sizes = Vec::new();
        for (k, &size) in self.sizes.iter().enumerate() {
            if keep(k) {
                sizes.push(size);
                renumber[k + 1] = sizes.len() as u32;
            }
        }
        for l in &mut self.labels {
            *l = renumber[*l as usize];
        }
        self.sizes = sizes;
    }

    /// The mask of every labelled pixel.
    pub fn mask(&self) -> Mask {
        Mask::from_checked(
            self.width,
            self.height,
            self.labels.iter().map(|&l| l != 0).collect(),
        )
    }
}

/// The root of provisional label `x`, halving the path on the way.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grandparent = parent[parent[x as usize] as usize];
        parent[x as usize] = grandparent;
        x = grandparent;
    }
    x
}

/// Joins the sets of `a` and `b` under the smaller root.
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra < rb {
        parent[rb as usize] = ra;
    } else if rb < ra {
        parent[ra as usize] = rb;
    }
}

/// The 8-connected patches of `mask`, numbered by first pixel in row-major order.
pub fn label(mask: &Mask) -> Labels {
    let (width, height) = (mask.width(), mask.height());
    let pixels = mask.pixels();
    let mut labels = vec![0_u32; pixels.len()];
    // parent[0] is the background; provisional labels start at 1.
    let mut parent: Vec<u32> = vec![0];

    for y in 0..height {
        let row = y * width;
        for x in 0..width {
            let i = row + x;
            if !pixels[i] {
                continue;
            }
            let north = if y > 0 { labels[i - width] } else { 0 };
            if north != 0 {
                labels[i] = north;
                continue;
            }
            let west = if x > 0 { labels[i - 1] } else { 0 };
            let north_west = if y > 0 && x > 0 {
                labels[i - width - 1]
            } else {
                0
            };
            let north_east = if y > 0 && x + 1 < width {
                labels[i - width + 1]
            } else {
                0
            };
            let joined = if west != 0 || north_west != 0 {
                let left = if west != 0 { west } else { north_west };
                if north_east != 0 {
                    union(&mut parent, left, north_east);
                }
                left
            } else if north_east != 0 {
                north_east
            } else {
                // The first pixel of a patch (or of a branch met later).
                let fresh = parent.len() as u32;
                parent.push(fresh);
                fresh
            };
            labels[i] = joined;
        }
    }

    // Roots are their own parent and smaller than every label of their set,
    // so one ascending sweep numbers roots in first-pixel order and resolves
    // every other label through an already-numbered parent.
    let mut number = vec![0_u32; parent.len()];
    let mut count = 0_u32;
    for l in 1..parent.len() {
        let p = parent[l] as usize;
        number[l] = if p == l {
            count += 1;
            count
        } else {
            number[p]
        };
    }
    let mut sizes = vec![0_u64; count as usize];
    for l in &mut labels {
        if *l != 0 {
            *l = number[*l as usize];
            sizes[*l as usize - 1] += 1;
        }
    }
    Labels {
        width,
        height,
        labels,
        sizes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};
    use std::collections::VecDeque;

    /// Brute force: breadth-first flood fill from each unlabelled contact
    /// pixel in row-major order, over the 8 neighbours.
    fn flood_fill(mask: &Mask) -> (Vec<u32>, Vec<u64>) {
        let (w, h) = (mask.width() as i64, mask.height() as i64);
        let pixels = mask.pixels();
        let mut labels = vec![0_u32; pixels.len()];
        let mut sizes = Vec::new();
        let mut queue = VecDeque::new();
        for start in 0..pixels.len() {
            if !pixels[start] || labels[start] != 0 {
                continue;
            }
            sizes.push(0_u64);
            let current = sizes.len() as u32;
            labels[start] = current;
            queue.push_back(start);
            while let Some(i) = queue.pop_front() {
                sizes[current as usize - 1] += 1;
                let (x, y) = (i as i64 % w, i as i64 / w);
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (nx, ny) = (x + dx, y + dy);
                        if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w || ny >= h {
                            continue;
                        }
                        let j = (ny * w + nx) as usize;
                        if pixels[j] && labels[j] == 0 {
                            labels[j] = current;
                            queue.push_back(j);
                        }
                    }
                }
            }
        }
        (labels, sizes)
    }

    fn mask_of(rows: &[&str]) -> Mask {
        let pixels = rows
            .iter()
            .flat_map(|r| r.chars().map(|c| c == '#'))
            .collect();
        Mask::new(rows[0].len(), rows.len(), pixels).unwrap()
    }

    fn random_mask() -> impl Strategy<Value = Mask> {
        (1_usize..=64, 1_usize..=64, 0.05_f64..0.95, any::<u64>()).prop_map(|(w, h, p, seed)| {
            use rand::{RngExt, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let pixels = (0..w * h).map(|_| rng.random_bool(p)).collect();
            Mask::new(w, h, pixels).unwrap()
        })
    }

    proptest! {
        #![proptest_config(Config { cases: 256, rng_seed: RngSeed::Fixed(14), ..Config::default() })]

        /// Same labels pixel for pixel (so the same count, sizes and order).
        #[test]
        fn equals_flood_fill_on_random_masks(mask in random_mask()) {
            let labels = label(&mask);
            let (expected_labels, expected_sizes) = flood_fill(&mask);
            prop_assert_eq!(labels.labels(), &expected_labels[..]);
            prop_assert_eq!(labels.sizes(), &expected_sizes[..]);
            prop_assert_eq!(labels.sizes().iter().sum::<u64>(), mask.count() as u64);
            prop_assert_eq!(labels.mask(), mask);
        }
    }

    #[test]
    fn edge_cases() {
        let empty = Mask::new(5, 3, vec![false; 15]).unwrap();
        assert_eq!(label(&empty).count(), 0);
        assert!(label(&empty).labels().iter().all(|&l| l == 0));

        let full = Mask::new(7, 4, vec![true; 28]).unwrap();
        assert_eq!(label(&full).sizes(), &[28]);

        let single = Mask::new(1, 1, vec![true]).unwrap();
        assert_eq!(label(&single).sizes(), &[1]);

        // A diagonal chain touches only at corners: one patch with 8-connectivity.
        let diagonal = mask_of(&["#....", ".#...", "..#..", "...#.", "....#"]);
        assert_eq!(label(&diagonal).sizes(), &[5]);
        let anti_diagonal = mask_of(&["....#", "...#.", "..#..", ".#...", "#...."]);
        assert_eq!(label(&anti_diagonal).sizes(), &[5]);

        // A checkerboard is one patch with 8-connectivity.
        let checker = Mask::new(6, 5, (0..30).map(|i| (i % 6 + i / 6) % 2 == 0).collect()).unwrap();
        assert_eq!(label(&checker).sizes(), &[15]);

        // A U whose arms meet only at the bottom: one patch, numbered from
        // the left arm's first pixel; a later patch second.
        let u = mask_of(&["#.#..#", "#.#...", "###...", "......"]);
        let labels = label(&u);
        assert_eq!(labels.sizes(), &[7, 1]);
        assert_eq!(labels.labels()[0], 1);
        assert_eq!(labels.labels()[5], 2);

        // First-pixel order: the patch starting higher comes first even
        // though another starts further left lower down.
        let order = mask_of(&["...#", "#...", "#..."]);
        let labels = label(&order);
        assert_eq!(labels.sizes(), &[1, 2]);
        assert_eq!(labels.labels()[3], 1);

        // Rows and columns of one pixel.
        let row = mask_of(&["##.#.##"]);
        assert_eq!(label(&row).sizes(), &[2, 1, 2]);
        let column = Mask::new(1, 5, vec![true, false, true, true, false]).unwrap();
        assert_eq!(label(&column).sizes(), &[1, 2]);
    }

    #[test]
    fn all_true_2048_squared_needs_no_recursion() {
        let n = 2048;
        let labels = label(&Mask::new(n, n, vec![true; n * n]).unwrap());
        assert_eq!(labels.sizes(), &[(n * n) as u64]);
        // A comb: 1024 vertical teeth joined by the bottom row; the
        // equivalence table merges 1024 provisional labels into one.
        let comb = Mask::new(
            n,
            n,
            (0..n * n).map(|i| i % 2 == 0 || i / n == n - 1).collect(),
        )
        .unwrap();
        assert_eq!(label(&comb).sizes(), &[(n * n / 2 + n / 2) as u64]);
    }

    #[test]
    fn retain_renumbers_in_order() {
        let mut labels = label(&mask_of(&["#.#.#", ".....", "##..#"]));
        assert_eq!(labels.sizes(), &[1, 1, 1, 2, 1]);
        labels.retain(|k| k % 2 == 1);
        assert_eq!(labels.sizes(), &[1, 2]);
        assert_eq!(
            labels.labels(),
            &[0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 2, 2, 0, 0, 0]
        );
    }
}
