//! Exact percentiles of millions of `f32` values in two passes, for the
//! calibrated method's contact and background levels.
//!
//! Percentiles interpolate linearly between the order statistics around
//! position `p / 100 · (n − 1)` (NumPy's default, "linear"). Selection is a
//! one-level radix select: the first pass counts the values in 65536 buckets
//! of their top 16 order-preserving key bits, the cumulative counts name the
//! bucket and in-bucket rank of each wanted order statistic, and the second
//! pass gathers only those buckets' values for a final `select_nth` — exact,
//! without selecting on (or copying) the whole frame.

/// Bits of `x` as a `u32` ordered like `f32::total_cmp`.
fn key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

fn bucket(x: f32) -> usize {
    (key(x) >> 16) as usize
}

/// The `ps` percentiles (each in 0..=100) of the finite values of `values`
/// (non-finite ones are skipped); `None` when no value is finite.
pub(crate) fn percentiles(values: &[f32], ps: &[f64]) -> Option<Vec<f64>> {
    let mut counts = vec![0_u64; 1 << 16];
    let mut n = 0_u64;
    for &x in values.iter().filter(|x| x.is_finite()) {
        counts[bucket(x)] += 1;
        n += 1;
    }
    if n == 0 {
        return None;
    }

    // The order statistics wanted: rank → (bucket, rank within the bucket).
    let positions: Vec<(u64, f64)> = ps
        .iter()
        .map(|&p| {
            let position = p / 100.0 * (n - 1) as f64;
            let below = (position.floor() as u64).min(n - 1);
            (below, position - below as f64)
        })
        .collect();
    let mut ranks: Vec<u64> = positions
        .iter()
        .flat_map(|&(below, _)| [below, (below + 1).min(n - 1)])
        .collect();
    ranks.sort_unstable();
    ranks.dedup();
    let mut located = Vec::with_capacity(ranks.len());
    let mut before = 0_u64;
    let mut b = 0_usize;
    for &rank in &ranks {
        while before + counts[b] <= rank {
            before += counts[b];
            b += 1;
        }
        located.push((b, rank - before));
    }

    // Gather the wanted buckets' values.
    // At most 2 ranks per percentile; the callers ask for two percentiles.
    debug_assert!(located.len() < usize::from(u8::MAX));
    let mut slot_of = vec![u8::MAX; 1 << 16];
    let mut gathered: Vec<Vec<f32>> = Vec::new();
    for &(b, _) in &located {
        if slot_of[b] == u8::MAX {
            slot_of[b] = gathered.len() as u8;
            gathered.push(Vec::with_capacity(counts[b] as usize));
        }
    }
    for &x in values.iter().filter(|x| x.is_finite()) {
        let slot = slot_of[bucket(x)];
        if slot != u8::MAX {
            gathered[slot as usize].push(x);
        }
    }
    // Selecting reorders a bucket but keeps its values, so a second rank in
    // the same bucket selects correctly from the reordered one.
    let mut statistic = |rank: u64| {
        let i = ranks.binary_search(&rank).unwrap_or_else(|i| i);
        let (b, within) = located[i];
        let bucket_values = &mut gathered[slot_of[b] as usize];
        let (_, &mut x, _) = bucket_values.select_nth_unstable_by(within as usize, f32::total_cmp);
        f64::from(x)
    };
    Some(
        positions
            .iter()
            .map(|&(below, weight)| {
                let low = statistic(below);
                if weight > 0.0 && below + 1 < n {
                    low + weight * (statistic(below + 1) - low)
                } else {
                    low
                }
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Brute force: sort the finite values, interpolate at `p / 100 · (n − 1)`.
    fn sorted_percentile(values: &[f32], p: f64) -> f64 {
        let mut sorted: Vec<f32> = values.iter().copied().filter(|x| x.is_finite()).collect();
        sorted.sort_by(f32::total_cmp);
        let position = p / 100.0 * (sorted.len() - 1) as f64;
        let below = position.floor() as usize;
        let above = (below + 1).min(sorted.len() - 1);
        let weight = position - below as f64;
        f64::from(sorted[below]) + weight * (f64::from(sorted[above]) - f64::from(sorted[below]))
    }

    fn value() -> impl Strategy<Value = f32> {
        prop_oneof![
            4 => 0.0_f32..4.0,
            // Many equal values and values sharing a bucket.
            2 => prop_oneof![Just(0.0_f32), Just(1.0), Just(1.0001), Just(-0.0)],
            1 => Just(f32::INFINITY),
            1 => -1.0e3_f32..1.0e6,
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

        #[test]
        fn equal_sorting(
            values in prop::collection::vec(value(), 1..400),
            ps in prop::collection::vec(prop_oneof![Just(0.0), Just(50.0), Just(100.0), 0.0_f64..=100.0], 1..4),
        ) {
            let got = percentiles(&values, &ps);
            if values.iter().all(|x| !x.is_finite()) {
                prop_assert!(got.is_none());
                return Ok(());
            }
            let got = got.unwrap();
            for (&p, &g) in ps.iter().zip(&got) {
                let expected = sorted_percentile(&values, p);
                prop_assert!((g - expected).abs() <= 1e-9 * expected.abs().max(1.0),
                    "p = {p}: {g} against {expected}");
            }
        }
    }

    #[test]
    fn small_cases() {
        assert_eq!(percentiles(&[], &[50.0]), None);
        assert_eq!(percentiles(&[f32::NAN, f32::INFINITY], &[50.0]), None);
        assert_eq!(percentiles(&[3.0], &[0.0, 50.0, 100.0]), Some(vec![3.0; 3]));
        // Four values: the 50th percentile is half-way between the middle two.
        assert_eq!(
            percentiles(&[4.0, 1.0, 3.0, 2.0], &[0.0, 50.0, 100.0, 25.0]),
            Some(vec![1.0, 2.5, 4.0, 1.75])
        );
    }
}
