//! Sums of f64 terms that keep their rounding errors, for the Drucker
//! determinant ([`crate::model::DruckerStiffness`]), whose terms can be
//! twenty orders of magnitude apart or cancel.
//!
//! Each addition is Knuth's error-free TwoSum (The Art of Computer
//! Programming vol. 2, 4.2.2) with the errors accumulated beside the sum, as
//! in Neumaier's compensated summation (ZAMM 54, 39, 1974) and Ogita, Rump &
//! Oishi's Sum2 (SIAM J. Sci. Comput. 26, 1955, 2005); each product a·b is
//! split exactly into its rounded value and its error with one fused
//! multiply–add (TwoProduct). The result is as accurate as if the sum had
//! been formed in twice the precision and rounded once: its error is about
//! u |Σ x| + n² u² Σ |x| (u = 2⁻⁵³, n terms), against n u Σ |x| for a
//! plain loop.

/// A running sum kept as the unevaluated pair `sum + error`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CompensatedSum {
    /// The rounded running sum.
    sum: f64,
    /// The accumulated rounding errors of every addition and product.
    error: f64,
}

impl CompensatedSum {
    /// Adds `x`, keeping the rounding error of the addition.
    pub fn add(&mut self, x: f64) {
        let total = self.sum + x;
        let x_part = total - self.sum;
        let lost = (self.sum - (total - x_part)) + (x - x_part);
        self.sum = total;
        self.error += lost;
    }

    /// Adds the exact product a·b.
    pub fn add_product(&mut self, a: f64, b: f64) {
        let product = a * b;
        self.add(product);
        if product.is_finite() {
            // Exact unless a·b underflows, where the loss is below 1e-300.
            self.error += a.mul_add(b, -product);
        }
    }

    /// Adds the product of two compensated sums, (s + e)(s' + e'), every
    /// partial product exactly.
    pub fn add_product_of(&mut self, a: &CompensatedSum, b: &CompensatedSum) {
        self.add_product(a.sum, b.sum);
        self.add_product(a.sum, b.error);
        self.add_product(a.error, b.sum);
        self.add_product(a.error, b.error);
    }

    /// Adds k times a compensated sum (k a small integer, so exactly).
    pub fn add_multiple_of(&mut self, k: f64, a: &CompensatedSum) {
        self.add_product(k, a.sum);
        self.add_product(k, a.error);
    }

    /// The sum, rounded once.
    pub fn value(&self) -> f64 {
        if self.sum.is_finite() {
            self.sum + self.error
        } else {
            // An overflow: the error term is meaningless (∞ − ∞).
            self.sum
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn recovers_what_a_plain_sum_loses() {
        // 1e16 + 1 − 1e16 is 0 in a plain loop (1 is below half an ulp of
        // 1e16) and 1 exactly here.
        let mut s = CompensatedSum::default();
        for x in [1e16, 1.0, -1e16] {
            s.add(x);
        }
        assert_eq!(s.value(), 1.0);
        assert_eq!(1e16 + 1.0 - 1e16, 0.0);
        // (1 + 2⁻³⁰)² − 1 − 2⁻²⁹: the square's 2⁻⁶⁰ is lost by a plain
        // product and kept by the fused multiply–add.
        let a = 1.0 + 2f64.powi(-30);
        let mut p = CompensatedSum::default();
        p.add_product(a, a);
        p.add(-1.0 - 2f64.powi(-29));
        assert_eq!(p.value(), 2f64.powi(-60));
        assert_eq!(a * a - 1.0 - 2f64.powi(-29), 0.0);
    }

    #[test]
    fn products_of_sums_are_exact_when_representable() {
        // (1 + 2⁻⁶⁰)(1 − 2⁻⁶⁰) − 1 = −2⁻¹²⁰ needs all four partial products.
        let mut a = CompensatedSum::default();
        a.add(1.0);
        a.add(2f64.powi(-60));
        let mut b = CompensatedSum::default();
        b.add(1.0);
        b.add(-(2f64.powi(-60)));
        let mut p = CompensatedSum::default();
        p.add_product_of(&a, &b);
        p.add(-1.0);
        assert_eq!(p.value(), -(2f64.powi(-120)));
        let mut twice = CompensatedSum::default();
        twice.add_multiple_of(2.0, &a);
        twice.add(-2.0);
        assert_eq!(twice.value(), 2f64.powi(-59));
    }

    #[test]
    fn overflow_stays_infinite() {
        let mut s = CompensatedSum::default();
        s.add_product(1e200, 1e200);
        s.add(1.0);
        assert_eq!(s.value(), f64::INFINITY);
    }

    proptest! {
        /// Integers times powers of two are exact in f64, so an exact
        /// reference exists: the compensated sum of terms k_i 2^(e_i) that
        /// cancel must equal the integer sum, which a plain loop misses.
        #[test]
        fn sums_of_scaled_integers_are_exact(
            terms in proptest::collection::vec((-1_000_000i64..1_000_000, -40i32..40), 1..30),
        ) {
            let mut s = CompensatedSum::default();
            let mut exact = 0i128;
            for &(k, e) in &terms {
                s.add(k as f64 * 2f64.powi(e));
                s.add(-(k as f64) * 2f64.powi(e));
                s.add(k as f64);
                exact += i128::from(k);
            }
            prop_assert_eq!(s.value(), exact as f64);
        }
    }
}
