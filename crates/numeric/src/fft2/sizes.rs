//! Transform lengths of the form 2^a 3^b 5^c: rustfft's mixed-radix
//! butterflies handle them without Bluestein's or Rader's detour, so every
//! crate that pads a transform (the BEM's influence kernels, the synthetic
//! surfaces, the correlations) pads to one of these.

/// The smallest n ≥ `min` of the form 2^a 3^b 5^c (1 for `min` ≤ 1).
pub fn fast_size(min: usize) -> usize {
    let mut n = min.max(1);
    loop {
        let mut m = n;
        for p in [2, 3, 5] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        if m == 1 {
            return n;
        }
        n += 1;
    }
}

/// The smallest even [`fast_size`] ≥ `min`: a real transform's half
/// spectrum then ends on a real Nyquist term.
pub fn fast_even_size(min: usize) -> usize {
    let mut n = fast_size(min.max(2));
    while !n.is_multiple_of(2) {
        n = fast_size(n + 1);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether n has no prime factor above 5, by trial division.
    fn smooth(mut n: usize) -> bool {
        for p in [2, 3, 5] {
            while n.is_multiple_of(p) {
                n /= p;
            }
        }
        n == 1
    }

    #[test]
    fn fast_sizes_have_small_factors() {
        assert_eq!(fast_size(0), 1);
        assert_eq!(fast_size(1), 1);
        assert_eq!(fast_size(7), 8);
        assert_eq!(fast_size(1025), 1080);
        assert_eq!(fast_size(2049), 2160);
    }

    #[test]
    fn fast_even_sizes_are_even_and_smooth() {
        assert_eq!(fast_even_size(900), 900);
        assert_eq!(fast_even_size(242), 250);
        assert_eq!(fast_even_size(1), 2);
        assert_eq!(fast_even_size(4096), 4096);
        // 243 = 3^5 is fast but odd; 250 = 2 · 5^3 is the next even one.
        assert_eq!(fast_size(243), 243);
        assert_eq!(fast_even_size(243), 250);
    }

    #[test]
    fn no_smooth_size_is_skipped() {
        // Against a scan of every n: the answer is the first smooth n ≥ min.
        for min in 0..2000 {
            let first = (min.max(1)..).find(|&n| smooth(n)).unwrap();
            assert_eq!(fast_size(min), first, "{min}");
            let even = (min.max(2)..)
                .find(|&n| smooth(n) && n.is_multiple_of(2))
                .unwrap();
            assert_eq!(fast_even_size(min), even, "{min}");
        }
    }
}
