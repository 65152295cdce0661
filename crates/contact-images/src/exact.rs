//! Exact comparison of ratios `d² / a` of integers, so that Otsu's
//! between-class variances (`D² / (n0 n1)` up to a common factor) are ordered
//! without rounding and ties are real ties.
//!
//! `d² · a'` against `d'² · a` needs up to 384 bits for `u128` operands; the
//! products are formed in six 64-bit limbs by schoolbook multiplication.

use std::cmp::Ordering;

/// Orders `d1² / a1` against `d2² / a2`; `a1` and `a2` must be positive.
pub(crate) fn cmp_square_ratio(d1: u128, a1: u128, d2: u128, a2: u128) -> Ordering {
    debug_assert!(a1 > 0 && a2 > 0);
    cmp_limbs(&square_times(d1, a2), &square_times(d2, a1))
}

/// `d² · a` in little-endian 64-bit limbs.
fn square_times(d: u128, a: u128) -> [u64; 6] {
    let mut square = [0_u64; 4];
    mul_into(&limbs(d), &limbs(d), &mut square);
    let mut product = [0_u64; 6];
    mul_into(&square, &limbs(a), &mut product);
    product
}

fn limbs(x: u128) -> [u64; 2] {
    [x as u64, (x >> 64) as u64]
}

/// `out = a · b`; `out` must have `a.len() + b.len()` limbs.
fn mul_into(a: &[u64], b: &[u64], out: &mut [u64]) {
    debug_assert_eq!(out.len(), a.len() + b.len());
    out.fill(0);
    for (i, &ai) in a.iter().enumerate() {
        let mut carry = 0_u128;
        for (j, &bj) in b.iter().enumerate() {
            let t = u128::from(out[i + j]) + u128::from(ai) * u128::from(bj) + carry;
            out[i + j] = t as u64;
            carry = t >> 64;
        }
        // Row i writes limbs i ..= i + b.len(); the top one was still zero.
        out[i + b.len()] = carry as u64;
    }
}

fn cmp_limbs(a: &[u64; 6], b: &[u64; 6]) -> Ordering {
    a.iter().rev().cmp(b.iter().rev())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `d² · a` for values small enough that `u128` holds it.
    fn small_product(d: u64, a: u64) -> u128 {
        u128::from(d) * u128::from(d) * u128::from(a)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

        /// Against plain `u128` arithmetic where it does not overflow.
        #[test]
        fn agrees_with_u128_on_small_values(
            d1 in 0_u64..(1 << 40), a1 in 1_u64..(1 << 40),
            d2 in 0_u64..(1 << 40), a2 in 1_u64..(1 << 40),
        ) {
            let expected = small_product(d1, a2).cmp(&small_product(d2, a1));
            prop_assert_eq!(
                cmp_square_ratio(d1.into(), a1.into(), d2.into(), a2.into()),
                expected
            );
        }

        /// Scaling both sides by the same power of two keeps the order, on
        /// operands far beyond `u128` products.
        #[test]
        fn big_operands_order_like_their_quotients(
            d in 1_u128..(1 << 100), a1 in 1_u128..(1 << 90), a2 in 1_u128..(1 << 90),
        ) {
            // d² / a1 against d² / a2 is a2 against a1.
            prop_assert_eq!(cmp_square_ratio(d, a1, d, a2), a2.cmp(&a1));
            // (2d)² / (4a) equals d² / a exactly.
            prop_assert_eq!(cmp_square_ratio(2 * d, 4 * a1, d, a1), Ordering::Equal);
        }
    }

    #[test]
    fn extremes_do_not_overflow() {
        let max = u128::MAX;
        assert_eq!(cmp_square_ratio(max, max, max, max), Ordering::Equal);
        assert_eq!(cmp_square_ratio(max, 1, max - 1, 1), Ordering::Greater);
        assert_eq!(cmp_square_ratio(max, max, max, max - 1), Ordering::Less);
        assert_eq!(cmp_square_ratio(0, 1, 1, max), Ordering::Less);
    }
}
