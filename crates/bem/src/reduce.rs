//! Sums over a map that give the same bits on any number of threads.
//!
//! Floating-point addition is not associative, so a rayon `sum()` (whose
//! split points follow the work stealing) may differ in the last bits from
//! run to run and between thread counts (issue #12). Here the map is cut
//! into chunks of a fixed length, each chunk is summed left to right by one
//! thread, and the chunk sums are added left to right: the order of every
//! addition depends on the map's size only.

use rayon::prelude::*;

/// Points per chunk: large enough that the per-chunk overhead vanishes,
/// small enough that 2 threads share a 256² map evenly.
pub(crate) const CHUNK: usize = 4096;

/// `N` sums Σᵢ f(i)[k] over i in 0..len, in a fixed order.
pub fn sums<const N: usize, F>(len: usize, f: F) -> [f64; N]
where
    F: Fn(usize) -> [f64; N] + Sync,
{
    let chunks: Vec<[f64; N]> = (0..len.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut acc = [0.0; N];
            for i in c * CHUNK..((c + 1) * CHUNK).min(len) {
                let terms = f(i);
                for (a, t) in acc.iter_mut().zip(terms) {
                    *a += t;
                }
            }
            acc
        })
        .collect();
    let mut total = [0.0; N];
    for chunk in chunks {
        for (a, t) in total.iter_mut().zip(chunk) {
            *a += t;
        }
    }
    total
}

/// Writes `out[i] = f(i).0` and returns the `N` sums Σᵢ f(i).1[k], in the
/// same fixed order as [`sums`]: one pass where a map and its sums are
/// both needed.
pub fn fill_sums<const N: usize, F>(out: &mut [f64], f: F) -> [f64; N]
where
    F: Fn(usize) -> (f64, [f64; N]) + Sync,
{
    let chunks: Vec<[f64; N]> = out
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(c, values)| {
            let mut acc = [0.0; N];
            for (offset, value) in values.iter_mut().enumerate() {
                let (v, terms) = f(c * CHUNK + offset);
                *value = v;
                for (a, t) in acc.iter_mut().zip(terms) {
                    *a += t;
                }
            }
            acc
        })
        .collect();
    let mut total = [0.0; N];
    for chunk in chunks {
        for (a, t) in total.iter_mut().zip(chunk) {
            *a += t;
        }
    }
    total
}

/// Σᵢ f(i) over i in 0..len, in a fixed order.
pub fn sum<F>(len: usize, f: F) -> f64
where
    F: Fn(usize) -> f64 + Sync,
{
    sums(len, |i| [f(i)])[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_are_identical_on_one_and_on_three_threads() {
        // Terms of wildly different size, where the order of addition shows.
        let term = |i: usize| ((i as f64) * 0.7371).sin() * 10f64.powi((i % 17) as i32 - 8);
        let len = 100_003;
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| sums(len, |i| [term(i), term(i) * term(i)]))
        };
        let one = on(1);
        let three = on(3);
        assert_eq!(one.map(f64::to_bits), three.map(f64::to_bits));
        let mut filled = vec![0.0; len];
        let both = fill_sums(&mut filled, |i| {
            (2.0 * term(i), [term(i), term(i) * term(i)])
        });
        assert_eq!(both.map(f64::to_bits), one.map(f64::to_bits));
        assert_eq!(filled[7], 2.0 * term(7));
        let plain: f64 = (0..len).map(term).sum();
        assert!((one[0] - plain).abs() <= 1e-9 * plain.abs().max(1.0));
        assert_eq!(sum(0, term), 0.0);
    }
}
