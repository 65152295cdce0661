//! Least squares with linear inequality constraints, min |A x − b| subject
//! to G x ≥ h (problem LSI of Lawson & Hanson 1974, "Solving Least Squares
//! Problems", ch. 23): the `in-range` fit's moduli for one set of shape
//! parameters, G holding Drucker's condition at chosen stretches and
//! directions ([`crate::drucker_windows`]).
//!
//! The reduction is Lawson & Hanson's: with A = U S Vᵀ (thin SVD) and
//! z = S Vᵀ x − Uᵀ b, |A x − b|² = |z|² + const, so LSI becomes the least
//! distance problem (LDP) min |z| subject to E z ≥ f with E = G V S⁻¹ and
//! f = h − E Uᵀ b; the LDP is solved through non-negative least squares
//! ([`crate::nnls::nnls`]) on the (n + 1) × p system [Eᵀ; fᵀ] u ≈ e_(n+1):
//! with r its residual, z = −r_(1..n) / r_(n+1), and r = 0 means the
//! constraints are inconsistent (their theorem 23.4).
//!
//! Directions of A's numerical null space (singular values below 1e-13 of
//! the largest, where Ogden's α_i meet) do not move the objective; there
//! the solve prefers x's component 0 with the weight of that cut-off, so
//! without active constraints it returns [`crate::nnls::least_squares`]'s
//! minimum-norm answer, and with them the least such component that the
//! constraints allow.

use nalgebra::{DMatrix, DVector, SVD};

use crate::nnls::nnls;

/// min |A x − b| subject to G x ≥ h. None where the constraints are
/// inconsistent or the SVD breaks down (non-finite entries).
pub fn lsi(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    g: &DMatrix<f64>,
    h: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = a.ncols();
    let svd = SVD::try_new_unordered(a.clone(), true, true, 5.0 * f64::EPSILON, 0)?;
    if svd.singular_values.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let (u, v_t) = (svd.u.as_ref()?, svd.v_t.as_ref()?);
    let cutoff = 1e-13 * svd.singular_values.max().max(f64::MIN_POSITIVE);
    let kept = |j: usize| svd.singular_values[j] > cutoff;
    let s: Vec<f64> = (0..n).map(|j| svd.singular_values[j].max(cutoff)).collect();
    let c = DVector::from_fn(n, |j, _| if kept(j) { u.column(j).dot(b) } else { 0.0 });
    // x = V S⁻¹ (z + c): the map from z to x.
    let to_x = DMatrix::from_fn(n, n, |i, j| v_t[(j, i)] / s[j]);
    let x_of = |z: &DVector<f64>| &to_x * (z + &c);
    if g.nrows() == 0 {
        return Some(x_of(&DVector::zeros(n)));
    }
    let e = g * &to_x;
    let f = h - &e * &c;
    let z = ldp(&e, &f)?;
    let x = x_of(&z);
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// min |z| subject to E z ≥ f, through NNLS; None if infeasible.
fn ldp(e: &DMatrix<f64>, f: &DVector<f64>) -> Option<DVector<f64>> {
    let (p, n) = (e.nrows(), e.ncols());
    // Each constraint row scaled to unit length: the same feasible set,
    // and NNLS's columns of one size.
    let norms: Vec<f64> = (0..p)
        .map(|i| {
            (e.row(i).norm_squared() + f[i] * f[i])
                .sqrt()
                .max(f64::MIN_POSITIVE)
        })
        .collect();
    let system = DMatrix::from_fn(n + 1, p, |r, i| {
        if r < n {
            e[(i, r)] / norms[i]
        } else {
            f[i] / norms[i]
        }
    });
    let mut target = DVector::zeros(n + 1);
    target[n] = 1.0;
    let u = nnls(&system, &target)?.x;
    let residual = &system * u - target;
    // |r| = 1 exactly when u = 0 (no constraint binds); r_(n+1) → 0 when
    // the constraints cannot all hold.
    if residual.norm() <= 1e-10 || -residual[n] <= 1e-12 {
        return None;
    }
    Some(DVector::from_fn(n, |r, _| -residual[r] / residual[n]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nnls::least_squares;
    use proptest::prelude::*;

    #[test]
    fn without_binding_constraints_it_is_least_squares() {
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, -1.0]);
        let b = DVector::from_vec(vec![0.3, 1.0, 1.2, -0.5]);
        let (plain, _) = least_squares(a.clone(), &b).unwrap();
        let g = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let x = lsi(&a, &b, &g, &DVector::from_vec(vec![-10.0])).unwrap();
        assert!((x - &plain).amax() < 1e-13, "{plain}");
        let none = lsi(&a, &b, &DMatrix::zeros(0, 2), &DVector::zeros(0)).unwrap();
        assert!((none - plain).amax() < 1e-13);
    }

    #[test]
    fn a_binding_constraint_is_met_with_equality_at_the_projection() {
        // min |x − (1, −1)| with x2 ≥ 0.5 on the identity: (1, 0.5).
        let a = DMatrix::<f64>::identity(2, 2);
        let b = DVector::from_vec(vec![1.0, -1.0]);
        let g = DMatrix::from_row_slice(1, 2, &[0.0, 1.0]);
        let x = lsi(&a, &b, &g, &DVector::from_vec(vec![0.5])).unwrap();
        assert!(
            (x[0] - 1.0).abs() < 1e-14 && (x[1] - 0.5).abs() < 1e-14,
            "{x}"
        );
    }

    #[test]
    fn collinear_columns_meet_the_constraint_at_the_least_squares_objective() {
        // Two equal columns (two Ogden α_i met): only x1 + x2 is pinned by
        // the data, 1 here; x1 − x2 ≥ 3 is met along the free direction,
        // at no cost, by the smallest such move: x = (2, −1).
        let a = DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 2.0, 2.0, -1.0, -1.0]);
        let b = &a * DVector::from_vec(vec![0.5, 0.5]);
        let g = DMatrix::from_row_slice(1, 2, &[1.0, -1.0]);
        let x = lsi(&a, &b, &g, &DVector::from_vec(vec![3.0])).unwrap();
        assert!((&a * &x - &b).norm() < 1e-12, "{x}");
        assert!(
            (x[0] - 2.0).abs() < 1e-12 && (x[1] + 1.0).abs() < 1e-12,
            "{x}"
        );
    }

    #[test]
    fn inconsistent_constraints_have_no_solution() {
        // x1 ≥ 1 and −x1 ≥ 0.
        let a = DMatrix::<f64>::identity(2, 2);
        let b = DVector::from_vec(vec![1.0, 1.0]);
        let g = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, -1.0, 0.0]);
        assert!(lsi(&a, &b, &g, &DVector::from_vec(vec![1.0, 0.0])).is_none());
    }

    proptest! {
        /// x ≥ 0 as G = I, h = 0 is NNLS: both reach the same objective.
        #[test]
        fn equals_nnls_with_identity_constraints(
            entries in proptest::collection::vec(-1.0f64..1.0, 40),
            rhs in proptest::collection::vec(-1.0f64..1.0, 10),
            n in 1usize..=4,
        ) {
            let a = DMatrix::from_fn(10, n, |i, j| entries[i * 4 + j]);
            let b = DVector::from_vec(rhs);
            let x = lsi(&a, &b, &DMatrix::identity(n, n), &DVector::zeros(n)).unwrap();
            // LDP meets its constraints to rounding of the problem's scale.
            prop_assert!(x.iter().all(|v| *v >= -1e-10 * (1.0 + x.amax())), "{}", x);
            let ours = (&a * &x - &b).norm_squared();
            let reference = (&a * nnls(&a, &b).unwrap().x - &b).norm_squared();
            prop_assert!((ours - reference).abs() <= 1e-9 * (1.0 + reference), "{} vs {}", ours, reference);
        }
    }
}
