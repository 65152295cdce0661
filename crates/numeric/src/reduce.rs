//! Parallel reductions whose result does not depend on the thread count.
//!
//! Floating-point addition is not associative ((a + b) + c and a + (b + c)
//! may differ in the last bit), so a rayon `sum()` or `reduce`, whose split
//! points follow the number of threads and the work stealing, may give
//! different bits from run to run. Here the work is cut into blocks fixed
//! by the data alone, and [`tree_reduce`] merges the blocks' partial
//! results in a fixed binary tree over the block indices: the range
//! [first, end) splits at first + (end − first)/2, the halves run in
//! parallel, and the left operand of every merge holds the lower indices.
//! Which partials meet, and in which order, is the same on any number of
//! threads; for sums the tree is pairwise summation (Higham, "The accuracy
//! of floating point summation", SIAM J. Sci. Comput. 14, 1993, §3).
//!
//! [`sums`], [`fill_sums`] and [`sum`] are its use for sums over a map:
//! chunks of [`CHUNK`] points, each added left to right, the chunk sums
//! then added left to right (gathered in order by the tree), the order the
//! BEM solver's products have always had.

use std::sync::{Mutex, PoisonError};

/// Reduces `leaf(0, &mut blocks[0])`, …, `leaf(n − 1, &mut blocks[n − 1])`
/// with `merge` in the fixed tree of the module doc; `empty()` when there
/// are no blocks. A block may be anything a leaf needs mutably (a chunk of
/// an output to fill, or `()`, see [`reduce`]).
pub fn tree_reduce<T, A>(
    blocks: &mut [T],
    empty: impl FnOnce() -> A,
    leaf: impl Fn(usize, &mut T) -> A + Sync,
    merge: impl Fn(A, A) -> A + Sync,
) -> A
where
    T: Send,
    A: Send,
{
    if blocks.is_empty() {
        return empty();
    }
    reduce_range(0, blocks, &leaf, &merge)
}

fn reduce_range<T, A, Leaf, Merge>(first: usize, blocks: &mut [T], leaf: &Leaf, merge: &Merge) -> A
where
    T: Send,
    A: Send,
    Leaf: Fn(usize, &mut T) -> A + Sync,
    Merge: Fn(A, A) -> A + Sync,
{
    if let [block] = blocks {
        return leaf(first, block);
    }
    let middle = blocks.len() / 2;
    let (left, right) = blocks.split_at_mut(middle);
    let (left, right) = rayon::join(
        || reduce_range(first, left, leaf, merge),
        || reduce_range(first + middle, right, leaf, merge),
    );
    merge(left, right)
}

/// [`tree_reduce`] over the block indices 0..`n_blocks` alone.
pub fn reduce<A: Send>(
    n_blocks: usize,
    empty: impl FnOnce() -> A,
    leaf: impl Fn(usize) -> A + Sync,
    merge: impl Fn(A, A) -> A + Sync,
) -> A {
    // `()` takes no memory: the vector never allocates.
    tree_reduce(&mut vec![(); n_blocks], empty, |i, _| leaf(i), merge)
}

/// Working buffers lent to the leaves of a reduction: about as many are
/// made as threads run leaves at once, not one per block. A leaf must not
/// depend on what a buffer held before (which leaf had it is up to the
/// scheduler).
pub struct ScratchPool<S, F> {
    make: F,
    free: Mutex<Vec<S>>,
}

impl<S, F: Fn() -> S> ScratchPool<S, F> {
    pub fn new(make: F) -> Self {
        Self {
            make,
            free: Mutex::new(Vec::new()),
        }
    }

    /// Runs `f` with a buffer from the pool (a new one if none is free).
    pub fn with<R>(&self, f: impl FnOnce(&mut S) -> R) -> R {
        // A poisoned lock means a leaf panicked; the buffers are still
        // buffers.
        let taken = self
            .free
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop();
        let mut buffer = taken.unwrap_or_else(&self.make);
        let out = f(&mut buffer);
        self.free
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(buffer);
        out
    }
}

/// Adds `b` into `a` element by element: the merge of vector-valued sums.
pub fn add_into(mut a: Vec<f64>, b: Vec<f64>) -> Vec<f64> {
    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
    a
}

/// Points per chunk of [`sums`]: large enough that the per-chunk overhead
/// vanishes, small enough that 2 threads share a 256² map evenly.
pub const CHUNK: usize = 4096;

/// `N` sums Σᵢ f(i)\[k\] over i in 0..len, in the fixed order of the module
/// doc.
pub fn sums<const N: usize, F>(len: usize, f: F) -> [f64; N]
where
    F: Fn(usize) -> [f64; N] + Sync,
{
    let chunks = reduce(
        len.div_ceil(CHUNK),
        Vec::new,
        |c| {
            let mut acc = [0.0; N];
            for i in c * CHUNK..((c + 1) * CHUNK).min(len) {
                add_terms(&mut acc, f(i));
            }
            vec![acc]
        },
        concatenate,
    );
    add_in_order(chunks)
}

/// Writes `out[i] = f(i).0` and returns the `N` sums Σᵢ f(i).1\[k\] in the
/// same order as [`sums`]: one pass where a map and its sums are both
/// needed.
pub fn fill_sums<const N: usize, F>(out: &mut [f64], f: F) -> [f64; N]
where
    F: Fn(usize) -> (f64, [f64; N]) + Sync,
{
    let mut blocks: Vec<&mut [f64]> = out.chunks_mut(CHUNK).collect();
    let chunks = tree_reduce(
        &mut blocks,
        Vec::new,
        |c, values| {
            let mut acc = [0.0; N];
            for (offset, value) in values.iter_mut().enumerate() {
                let (v, terms) = f(c * CHUNK + offset);
                *value = v;
                add_terms(&mut acc, terms);
            }
            vec![acc]
        },
        concatenate,
    );
    add_in_order(chunks)
}

/// Σᵢ f(i) over i in 0..len, in the order of [`sums`].
pub fn sum<F>(len: usize, f: F) -> f64
where
    F: Fn(usize) -> f64 + Sync,
{
    sums(len, |i| [f(i)])[0]
}

fn add_terms<const N: usize>(acc: &mut [f64; N], terms: [f64; N]) {
    for (a, t) in acc.iter_mut().zip(terms) {
        *a += t;
    }
}

fn concatenate<A>(mut left: Vec<A>, right: Vec<A>) -> Vec<A> {
    left.extend(right);
    left
}

fn add_in_order<const N: usize>(chunks: Vec<[f64; N]>) -> [f64; N] {
    let mut total = [0.0; N];
    for chunk in chunks {
        add_terms(&mut total, chunk);
    }
    total
}

#[cfg(test)]
mod tests {
    use hypercontact_fuzz::on_threads;
    use proptest::prelude::*;

    use super::*;

    /// Terms of very different magnitude, so that any change in the order
    /// of additions shows in the last bits.
    fn term(i: usize) -> f64 {
        (i as f64 * 0.731).sin() * 10f64.powi((i % 17) as i32 - 8)
    }

    /// The pairwise tree written out sequentially.
    fn pairwise(first: usize, end: usize) -> f64 {
        if end - first == 1 {
            return term(first);
        }
        let middle = first + (end - first) / 2;
        pairwise(first, middle) + pairwise(middle, end)
    }

    /// The order of [`sums`] written out sequentially.
    fn chunked(len: usize) -> f64 {
        let mut total = 0.0;
        for c in 0..len.div_ceil(CHUNK) {
            let mut chunk = 0.0;
            for i in c * CHUNK..((c + 1) * CHUNK).min(len) {
                chunk += term(i);
            }
            total += chunk;
        }
        total
    }

    #[test]
    fn the_tree_is_pairwise_and_the_same_on_any_number_of_threads() {
        let tree = || reduce(1000, || 0.0, term, |a, b| a + b);
        let one = on_threads(1, tree);
        assert_eq!(one.to_bits(), pairwise(0, 1000).to_bits());
        for threads in [2, 3, 4, 7] {
            assert_eq!(
                on_threads(threads, tree).to_bits(),
                one.to_bits(),
                "{threads}"
            );
        }
        let add = |a: f64, b: f64| a + b;
        assert_eq!(reduce(0, || -1.0, term, add), -1.0);
        assert_eq!(reduce(1, || -1.0, term, add), term(0));
    }

    #[test]
    fn merges_keep_the_block_order() {
        let blocks = reduce(9, Vec::new, |i| vec![i], concatenate);
        assert_eq!(blocks, (0..9).collect::<Vec<_>>());
        // Leaves get their own block mutably.
        let mut cells = vec![0usize; 7];
        let total = tree_reduce(
            &mut cells,
            || 0,
            |i, c| {
                *c = 10 * i;
                i
            },
            |a, b| a + b,
        );
        assert_eq!(total, 21);
        assert_eq!(cells, [0, 10, 20, 30, 40, 50, 60]);
    }

    #[test]
    fn pooled_buffers_are_reused_not_made_per_block() {
        let made = std::sync::atomic::AtomicUsize::new(0);
        let pool = ScratchPool::new(|| {
            made.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            vec![0.0; 8]
        });
        let total = on_threads(2, || {
            reduce(
                500,
                || 0.0,
                |i| {
                    pool.with(|b| {
                        b.fill(term(i));
                        b.iter().sum::<f64>()
                    })
                },
                |a, b| a + b,
            )
        });
        let expected = reduce(500, || 0.0, |i| 8.0 * term(i), |a, b| a + b);
        assert!((total - expected).abs() < 1e-12);
        assert!(made.into_inner() <= 2, "one buffer per running leaf");
    }

    #[test]
    fn chunked_sums_are_identical_on_one_and_on_three_threads() {
        let len = 100_003;
        let run = || sums(len, |i| [term(i), term(i) * term(i)]);
        let one = on_threads(1, run);
        assert_eq!(one.map(f64::to_bits), on_threads(3, run).map(f64::to_bits));
        assert_eq!(one[0].to_bits(), chunked(len).to_bits());
        let mut filled = vec![0.0; len];
        let both = on_threads(2, || {
            fill_sums(&mut filled, |i| {
                (2.0 * term(i), [term(i), term(i) * term(i)])
            })
        });
        assert_eq!(both.map(f64::to_bits), one.map(f64::to_bits));
        assert!(filled.iter().enumerate().all(|(i, &v)| v == 2.0 * term(i)));
        let plain: f64 = (0..len).map(term).sum();
        assert!((one[0] - plain).abs() <= 1e-9 * plain.abs().max(1.0));
        assert_eq!(sum(0, term), 0.0);
        assert_eq!(fill_sums::<1, _>(&mut [], |_| (0.0, [1.0])), [0.0]);
    }

    proptest! {
        #![proptest_config(hypercontact_fuzz::config(32))]

        /// Any length, at and around the chunk boundaries and prime: the
        /// chunked order to the bit, and the tree's pairwise order.
        #[test]
        fn sums_follow_their_sequential_order(
            len in prop_oneof![0usize..20, (1usize..5).prop_map(|k| k * CHUNK), 1usize..3 * CHUNK + 7],
            threads in 1usize..4,
        ) {
            let chunk_order = on_threads(threads, || sum(len, term));
            prop_assert_eq!(chunk_order.to_bits(), chunked(len).to_bits());
            if len > 0 {
                let tree = on_threads(threads, || reduce(len, || 0.0, term, |a, b| a + b));
                prop_assert_eq!(tree.to_bits(), pairwise(0, len).to_bits());
            }
        }
    }
}
