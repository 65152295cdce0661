//! Parallel reductions whose result does not depend on the thread count.
//!
//! Floating-point addition is not associative, so a rayon `fold`/`reduce`
//! or `sum`, whose split points follow the number of threads and work
//! stealing, gives results that differ in the last bits from run to run.
//! Here the work is cut into blocks fixed by the data alone and the
//! partial results are merged in a fixed binary tree over the block
//! indices: the halves run in parallel, but which partials meet, and in
//! which order, is the same on any number of threads.

use std::sync::{Mutex, PoisonError};

/// Reduces `leaf(scratch, 0)`, …, `leaf(scratch, n_blocks − 1)` with
/// `merge`, the left operand always holding the lower block indices;
/// `empty()` when there are no blocks. Leaves borrow working buffers made
/// by `scratch()` from a pool, so there are about as many as threads, not
/// one per block; a leaf must not depend on what a buffer held before.
pub(crate) fn tree_reduce<S, A>(
    n_blocks: usize,
    empty: impl FnOnce() -> A,
    scratch: impl Fn() -> S + Sync,
    leaf: impl Fn(&mut S, usize) -> A + Sync,
    merge: impl Fn(A, A) -> A + Sync,
) -> A
where
    S: Send,
    A: Send,
{
    if n_blocks == 0 {
        return empty();
    }
    let pool = Mutex::new(Vec::new());
    let pooled_leaf = |block: usize| {
        let taken = pool.lock().unwrap_or_else(PoisonError::into_inner).pop();
        let mut buffers = taken.unwrap_or_else(&scratch);
        let partial = leaf(&mut buffers, block);
        pool.lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(buffers);
        partial
    };
    reduce_range(0, n_blocks, &pooled_leaf, &merge)
}

fn reduce_range<A, Leaf, Merge>(first: usize, end: usize, leaf: &Leaf, merge: &Merge) -> A
where
    A: Send,
    Leaf: Fn(usize) -> A + Sync,
    Merge: Fn(A, A) -> A + Sync,
{
    if end - first == 1 {
        return leaf(first);
    }
    let middle = first + (end - first) / 2;
    let (left, right) = rayon::join(
        || reduce_range(first, middle, leaf, merge),
        || reduce_range(middle, end, leaf, merge),
    );
    merge(left, right)
}

/// Adds `b` into `a` element by element.
pub(crate) fn add_into(mut a: Vec<f64>, b: Vec<f64>) -> Vec<f64> {
    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    #[test]
    fn the_same_bits_on_any_number_of_threads() {
        // Terms of very different magnitude, so that any change in the
        // order of additions shows in the last bits.
        let term = |i: usize| (i as f64 * 0.731).sin() * 10f64.powi((i % 17) as i32 - 8);
        let sum = || tree_reduce(1000, || 0.0, || (), |_, i| term(i), |a, b| a + b);
        let one = in_pool(1, sum);
        for threads in [2, 3, 4, 7] {
            assert_eq!(in_pool(threads, sum).to_bits(), one.to_bits(), "{threads}");
        }
        let add = |a: f64, b: f64| a + b;
        assert_eq!(tree_reduce(0, || -1.0, || (), |_, i| term(i), add), -1.0);
        assert_eq!(tree_reduce(1, || -1.0, || (), |_, i| term(i), add), term(0));
    }

    #[test]
    fn merges_keep_the_block_order() {
        let blocks = tree_reduce(
            9,
            Vec::new,
            || (),
            |_, i| vec![i],
            |mut a, b| {
                a.extend(b);
                a
            },
        );
        assert_eq!(blocks, (0..9).collect::<Vec<_>>());
    }
}
