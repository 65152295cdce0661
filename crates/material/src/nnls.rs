//! Linear least squares for the fit's moduli: [`least_squares`] by SVD
//! (the unconstrained fit) and, on top of it, non-negative least squares,
//! min |A x − b| subject to x ≥ 0, by the active-set method of Lawson &
//! Hanson (1974, "Solving Least Squares Problems", ch. 23; the constrained
//! fit). A handful of columns (one per Ogden term), some hundred rows. Both
//! give, beside the solution, an orthonormal basis of the range of the
//! columns they used, which the variable projection's Jacobian needs.
//!
//! Written here rather than taken from a crate: the one Rust NNLS crate
//! (`nnls` 0.3) is built on ndarray 0.15 and ndarray-stats, a second
//! ndarray beside the workspace's; this solver is on the nalgebra matrices
//! the fit already holds.

use nalgebra::{DMatrix, DVector, SVD};

/// The solution, which columns are free (x_j > 0) at it, and an
/// orthonormal basis of the free columns' numerical range.
#[derive(Clone, Debug)]
pub struct Nnls {
    pub x: DVector<f64>,
    /// Column indices with x_j > 0, ascending.
    pub free: Vec<usize>,
    /// Orthonormal basis of the range of A's free columns (no columns
    /// when none is free).
    pub range: DMatrix<f64>,
}

/// min |A x − b| by SVD, and an orthonormal basis of A's numerical range.
/// Columns closer to collinear than 1e-13 of the largest singular value
/// count as one, so the solve stays finite when two α_i meet. None where
/// the SVD breaks down (non-finite singular values).
pub fn least_squares(a: DMatrix<f64>, b: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)> {
    // Unordered first: nalgebra's sort panics on a NaN singular value.
    let mut svd = SVD::try_new_unordered(a, true, true, 5.0 * f64::EPSILON, 0)?;
    if svd.singular_values.iter().any(|s| !s.is_finite()) {
        return None;
    }
    svd.sort_by_singular_values();
    let cutoff = 1e-13 * svd.singular_values.max();
    let x = svd.solve(b, cutoff).ok()?;
    let kept: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&j| svd.singular_values[j] > cutoff)
        .collect();
    Some((x, svd.u.as_ref()?.select_columns(&kept)))
}

/// [`least_squares`] on the columns `cols` of `a`.
fn subset_solve(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    cols: &[usize],
) -> Option<(DVector<f64>, DMatrix<f64>)> {
    least_squares(a.select_columns(cols), b)
}

/// min |A x − b| with x ≥ 0. None if a subproblem's SVD breaks down
/// (non-finite entries).
pub fn nnls(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<Nnls> {
    let n = a.ncols();
    let mut x = DVector::zeros(n);
    let mut free = vec![false; n];
    let no_range = || DMatrix::zeros(a.nrows(), 0);
    let mut range = no_range();
    // The dual (gradient of −½|Ax − b|²) below this counts as zero: the
    // scale of Aᵀb times a few thousand roundings.
    let scale = (a.transpose() * b).amax().max(f64::MIN_POSITIVE);
    let tolerance = 1e3 * f64::EPSILON * scale * (a.nrows().max(n) as f64);
    // Each outer step frees one column; the inner loop only ever fixes
    // columns again. 3n outer steps is Lawson & Hanson's usual budget.
    for _ in 0..3 * n.max(1) {
        let w = a.transpose() * (b - a * &x);
        let Some(t) = (0..n)
            .filter(|&j| !free[j] && w[j] > tolerance)
            .max_by(|&i, &j| w[i].total_cmp(&w[j]))
        else {
            break;
        };
        free[t] = true;
        loop {
            let cols: Vec<usize> = (0..n).filter(|&j| free[j]).collect();
            let (s_free, s_range) = subset_solve(a, b, &cols)?;
            let mut s = DVector::zeros(n);
            for (k, &j) in cols.iter().enumerate() {
                s[j] = s_free[k];
            }
            if cols.iter().all(|&j| s[j] > 0.0) {
                x = s;
                range = s_range;
                break;
            }
            // Step from x towards s as far as x stays feasible, then fix
            // the columns that reached zero.
            let step = cols
                .iter()
                .filter(|&&j| s[j] <= 0.0)
                .map(|&j| x[j] / (x[j] - s[j]))
                .fold(f64::INFINITY, f64::min);
            x += (&s - &x) * step;
            for &j in &cols {
                if x[j] <= 0.0 || (s[j] <= 0.0 && x[j] <= f64::EPSILON * x.amax()) {
                    x[j] = 0.0;
                    free[j] = false;
                }
            }
            if free.iter().all(|f| !f) {
                range = no_range();
                break;
            }
        }
    }
    x.iter().all(|v| v.is_finite()).then(|| Nnls {
        free: (0..n).filter(|&j| x[j] > 0.0).collect(),
        x,
        range,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The NNLS optimum by brute force: the best non-negative solution of
    /// every column subset (the optimum is the unconstrained solution on
    /// its free columns, so one subset holds it).
    fn brute_force(a: &DMatrix<f64>, b: &DVector<f64>) -> f64 {
        let n = a.ncols();
        let mut best = b.norm_squared();
        for mask in 1..(1usize << n) {
            let cols: Vec<usize> = (0..n).filter(|j| mask >> j & 1 == 1).collect();
            let (s, _) = subset_solve(a, b, &cols).unwrap();
            if s.iter().all(|v| *v >= 0.0) {
                best = best.min((a.select_columns(&cols) * s - b).norm_squared());
            }
        }
        best
    }

    #[test]
    fn an_unconstrained_optimum_inside_the_orthant_is_found_exactly() {
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, -1.0]);
        let truth = DVector::from_vec(vec![0.7, 1.9]);
        let b = &a * &truth;
        let r = nnls(&a, &b).unwrap();
        assert!((r.x - truth).amax() < 1e-14);
        assert_eq!(r.free, [0, 1]);
    }

    #[test]
    fn a_negative_optimum_is_clamped_with_the_rest_refitted() {
        // b = e1 − e2 on columns e1, e2: the unconstrained answer (1, −1);
        // the constrained one (1, 0).
        let a = DMatrix::<f64>::identity(3, 2);
        let b = DVector::from_vec(vec![1.0, -1.0, 0.5]);
        let r = nnls(&a, &b).unwrap();
        assert_eq!(r.x.as_slice(), [1.0, 0.0]);
        assert_eq!(r.free, [0]);
    }

    proptest! {
        #[test]
        fn equals_brute_force_on_random_problems(
            entries in proptest::collection::vec(-1.0f64..1.0, 40),
            rhs in proptest::collection::vec(-1.0f64..1.0, 10),
            n in 1usize..=4,
        ) {
            let a = DMatrix::from_fn(10, n, |i, j| entries[i * 4 + j]);
            let b = DVector::from_vec(rhs);
            let r = nnls(&a, &b).unwrap();
            prop_assert!(r.x.iter().all(|v| *v >= 0.0));
            let ours = (&a * &r.x - &b).norm_squared();
            let best = brute_force(&a, &b);
            prop_assert!(ours <= best * (1.0 + 1e-10) + 1e-14, "{} vs {}", ours, best);
        }
    }
}
