//! FFT lengths: every crate that pads a transform (the BEM's influence
//! kernels, the synthetic surfaces, the registration's correlations) pads
//! to the same kind of size.

/// The smallest n ≥ `min` of the form 2^a 3^b 5^c, a size FFTs handle fast.
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
