//! The least-squares polynomial of total degree d (0..=6) through the
//! measured points of a map.
//!
//! Basis: P_a(u)·P_b(v) with a + b ≤ d, P_n the Legendre polynomials and
//! u = (x − x_c)/h_x, v = (y − y_c)/h_y the coordinates centred on the map
//! and scaled to [−1, 1] (x_c = (nx − 1)dx/2, h_x = x_c, likewise in y).
//! On a full grid these are nearly orthogonal, so the normal equations are
//! well conditioned: for d = 6 on 64² points their condition number lies
//! between 10 and 10² (the continuous limit is 7² = 49, the ratio of the
//! norms of P_0·P_0 and P_3·P_3), where monomials in pixel units would mix
//! entries from 1 to 63¹². The normal matrix is
//! solved by nalgebra's SVD (a rank below the number of terms, e.g. points
//! on one line, is refused), and one step of iterative refinement (the
//! normal equations of the residual, solved again) brings the coefficients
//! to what a QR of the full design matrix gives, without storing that
//! matrix (28 × 4 M values for d = 6 on 2048²).
//!
//! Separability makes the sums cheap: per row i, the sums over j of
//! P_b(v_j)·P_b'(v_j) and z·P_b(v_j) are formed once and multiplied by
//! P_a(u_i)·P_a'(u_i), so a point costs O(d²) operations, not O(d⁴).

use hypercontact_numeric::reduce;
use nalgebra::{DMatrix, DVector};
use ndarray::{Array2, ArrayView1};

use super::{Form, FormError, FormRemoval, check_map, subtract};

/// Highest total degree accepted.
pub const MAX_DEGREE: usize = 6;

/// A fitted polynomial: Σ_k c_k P_{a_k}(u) P_{b_k}(v) in the scaled
/// coordinates of the module doc.
#[derive(Clone, Debug, PartialEq)]
pub struct Polynomial {
    pub degree: usize,
    /// (a, b, coefficient in metres) per term, ordered by total degree a + b,
    /// then by a descending: (0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2), …
    pub terms: Vec<(usize, usize, f64)>,
    /// x_c and h_x of the scaling u = (x − x_c)/h_x, metres from the first point.
    pub x_centre_m: f64,
    pub x_half_m: f64,
    /// y_c and h_y.
    pub y_centre_m: f64,
    pub y_half_m: f64,
}

impl Polynomial {
    /// The polynomial's height at (x_m, y_m), metres from the map's first point.
    pub fn at(&self, x_m: f64, y_m: f64) -> f64 {
        let mut pu = [0.0; MAX_DEGREE + 1];
        let mut pv = [0.0; MAX_DEGREE + 1];
        legendre((x_m - self.x_centre_m) / self.x_half_m, &mut pu);
        legendre((y_m - self.y_centre_m) / self.y_half_m, &mut pv);
        self.terms.iter().map(|&(a, b, c)| c * pu[a] * pv[b]).sum()
    }
}

impl Form for Polynomial {
    fn name(&self) -> String {
        format!("polynomial of degree {}", self.degree)
    }
}

/// P_0(u), …, P_{n−1}(u) into `out` (n = out.len()), by Bonnet's recurrence
/// (n + 1) P_{n+1} = (2n + 1) u P_n − n P_{n−1}.
pub fn legendre(u: f64, out: &mut [f64]) {
    for n in 0..out.len() {
        out[n] = match n {
            0 => 1.0,
            1 => u,
            _ => {
                let k = (n - 1) as f64;
                ((2.0 * k + 1.0) * u * out[n - 1] - k * out[n - 2]) / (k + 1.0)
            }
        };
    }
}

/// The (a, b) of the terms of total degree ≤ `degree`, in [`Polynomial`]'s order.
pub fn exponents(degree: usize) -> Vec<(usize, usize)> {
    (0..=degree)
        .flat_map(|total| (0..=total).rev().map(move |a| (a, total - a)))
        .collect()
}

/// P_0..P_d at the n scaled coordinates −1 … 1 of one axis, row by row:
/// P_b(u_i) at i·(d + 1) + b.
fn legendre_table(n: usize, degree: usize) -> Vec<f64> {
    let half = (n as f64 - 1.0) / 2.0;
    let mut table = vec![0.0; n * (degree + 1)];
    for (i, row) in table.chunks_exact_mut(degree + 1).enumerate() {
        legendre((i as f64 - half) / half, row);
    }
    table
}

/// The tables and term list a fit works with.
struct Basis {
    /// [`legendre_table`] along x and along y.
    pu: Vec<f64>,
    pv: Vec<f64>,
    exponents: Vec<(usize, usize)>,
    degree: usize,
}

impl Basis {
    /// Σ_b q_b P_b(v_j) with q_b = Σ_{k: b_k = b} c_k P_{a_k}(u_i), per row i:
    /// the polynomial's values in O(d) per point.
    fn row_factors(&self, coefficients: &DVector<f64>) -> Vec<f64> {
        let n = self.degree + 1;
        let mut q = vec![0.0; self.pu.len()];
        for (row, pu) in q.chunks_exact_mut(n).zip(self.pu.chunks_exact(n)) {
            for (k, &(a, b)) in self.exponents.iter().enumerate() {
                row[b] += coefficients[k] * pu[a];
            }
        }
        q
    }

    /// The polynomial at (i, j) from [`Self::row_factors`] `q`.
    fn value(&self, q: &[f64], i: usize, j: usize) -> f64 {
        let n = self.degree + 1;
        let (q, p) = (&q[i * n..(i + 1) * n], &self.pv[j * n..(j + 1) * n]);
        q.iter().zip(p).map(|(a, b)| a * b).sum()
    }

    /// Per row i, the sums over its measured points j of P_b·P_b' (b ≤ b')
    /// and of value(j)·P_b, then their products with P_a(u_i)·P_a'(u_i) added
    /// into the normal matrix (upper triangle) and right-hand side.
    fn add_row(
        &self,
        i: usize,
        row: ArrayView1<f64>,
        value: impl Fn(usize, f64) -> f64,
        out: &mut [f64],
    ) {
        let n = self.degree + 1;
        let m = self.exponents.len();
        let mut vv = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        let mut zv = [0.0; MAX_DEGREE + 1];
        for (j, &z) in row.iter().enumerate() {
            if z.is_nan() {
                continue;
            }
            let p = &self.pv[j * n..(j + 1) * n];
            let target = value(j, z);
            for b in 0..n {
                zv[b] += target * p[b];
                for b2 in b..n {
                    vv[b][b2] += p[b] * p[b2];
                }
            }
        }
        let pu = &self.pu[i * n..(i + 1) * n];
        for (k, &(a, b)) in self.exponents.iter().enumerate() {
            out[m * m + k] += pu[a] * zv[b];
            for (l, &(a2, b2)) in self.exponents.iter().enumerate().skip(k) {
                out[k * m + l] += pu[a] * pu[a2] * vv[b.min(b2)][b.max(b2)];
            }
        }
    }

    /// The normal matrix and right-hand side of the fit to value(i, j, z)
    /// over the measured points, summed row by row in a fixed order.
    fn normal_equations(
        &self,
        h: &Array2<f64>,
        value: impl Fn(usize, usize, f64) -> f64 + Sync,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let m = self.exponents.len();
        let sums = reduce::reduce(
            h.nrows(),
            || vec![0.0; m * m + m],
            |i| {
                let mut out = vec![0.0; m * m + m];
                self.add_row(i, h.row(i), |j, z| value(i, j, z), &mut out);
                out
            },
            reduce::add_into,
        );
        let gram = DMatrix::from_fn(m, m, |k, l| sums[k.min(l) * m + k.max(l)]);
        (gram, DVector::from_column_slice(&sums[m * m..]))
    }
}

/// Fits the polynomial of total degree `degree` to the measured points of
/// `height_m` (axis 0 = x, spacings `dx_m`, `dy_m`) and subtracts it.
pub fn remove_polynomial(
    height_m: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    degree: usize,
) -> Result<FormRemoval<Polynomial>, FormError> {
    if degree > MAX_DEGREE {
        return Err(FormError::Degree { degree });
    }
    let measured = check_map(height_m, dx_m, dy_m)?;
    let (nx, ny) = height_m.dim();
    let basis = Basis {
        pu: legendre_table(nx, degree),
        pv: legendre_table(ny, degree),
        exponents: exponents(degree),
        degree,
    };
    let m = basis.exponents.len();
    let form = || format!("polynomial of degree {degree}");
    if measured < m {
        return Err(FormError::TooFewPoints {
            form: form(),
            needed: m,
            found: measured,
        });
    }
    let (gram, rhs) = basis.normal_equations(height_m, |_, _, z| z);
    let svd = gram.svd(true, true);
    let largest = svd.singular_values.max();
    let smallest = svd.singular_values.min();
    // The normal matrix's condition number is the square of the design
    // matrix's: 1e12 here is 1e6 there, far beyond any map whose measured
    // points span the plane, and well inside what the SVD resolves.
    if smallest.is_nan() || smallest <= 1e-12 * largest {
        return Err(FormError::Degenerate {
            form: form(),
            why: format!(
                "the measured points do not determine its {m} coefficients (condition number \
                 of the normal equations {:.1e}): are they all on a line?",
                largest / smallest
            ),
        });
    }
    let solve = |rhs: &DVector<f64>| {
        svd.solve(rhs, 0.0).map_err(|why| FormError::Degenerate {
            form: form(),
            why: why.to_string(),
        })
    };
    let mut coefficients = solve(&rhs)?;
    // One step of iterative refinement on the residual.
    let q = basis.row_factors(&coefficients);
    let (_, correction_rhs) = basis.normal_equations(height_m, |i, j, z| z - basis.value(&q, i, j));
    coefficients += solve(&correction_rhs)?;
    let q = basis.row_factors(&coefficients);
    let (residual_m, points, removed_rms_m, residual_rms_m) =
        subtract(height_m, coefficients[0], |i, j| basis.value(&q, i, j));
    let (x_half_m, y_half_m) = ((nx - 1) as f64 * dx_m / 2.0, (ny - 1) as f64 * dy_m / 2.0);
    let polynomial = Polynomial {
        degree,
        terms: basis
            .exponents
            .iter()
            .zip(coefficients.iter())
            .map(|(&(a, b), &c)| (a, b, c))
            .collect(),
        x_centre_m: x_half_m,
        x_half_m,
        y_centre_m: y_half_m,
        y_half_m,
    };
    Ok(FormRemoval {
        residual_m,
        form: polynomial,
        points,
        removed_rms_m,
        residual_rms_m,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legendre_polynomials_match_their_closed_forms() {
        let mut p = [0.0; 5];
        legendre(0.3, &mut p);
        let u: f64 = 0.3;
        let closed = [
            1.0,
            u,
            (3.0 * u * u - 1.0) / 2.0,
            (5.0 * u.powi(3) - 3.0 * u) / 2.0,
            (35.0 * u.powi(4) - 30.0 * u * u + 3.0) / 8.0,
        ];
        for (a, b) in p.iter().zip(closed) {
            assert!((a - b).abs() < 1e-15, "{a} vs {b}");
        }
        assert_eq!(
            exponents(2),
            [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
        );
        assert_eq!(exponents(6).len(), 28);
    }

    /// The module doc's claim on the conditioning.
    #[test]
    fn the_normal_equations_of_degree_6_are_well_conditioned() {
        let (n, degree) = (64, 6);
        let basis = Basis {
            pu: legendre_table(n, degree),
            pv: legendre_table(n, degree),
            exponents: exponents(degree),
            degree,
        };
        let (gram, _) = basis.normal_equations(&Array2::zeros((n, n)), |_, _, z| z);
        let s = gram.svd(false, false).singular_values;
        let condition = s.max() / s.min();
        assert!((10.0..100.0).contains(&condition), "{condition}");
    }
}
