//! 3 × 3 matrices for the constitutive law and the element: products,
//! determinant, cofactor, and the eigen-decomposition of a symmetric matrix
//! by cyclic Jacobi rotations (Golub & Van Loan, Matrix Computations,
//! § 8.5), chosen because it returns an orthonormal basis to full accuracy
//! whatever the multiplicity of the eigenvalues: at the undeformed state and
//! at equibiaxial states two or three stretches coincide, and the spectral
//! formulas of [`crate::isochoric`] need only *some* orthonormal basis there.

/// A 3 × 3 matrix, row-major: `m[i][j]` is row i, column j.
pub type Mat3 = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

pub fn det(m: &Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The cofactor matrix, det(m) m⁻ᵀ: the derivative of det(m) with respect to
/// m, defined (and smooth) also where m is singular.
pub fn cofactor(m: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for (j, entry) in row.iter_mut().enumerate() {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            *entry = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
        }
    }
    c
}

/// aᵀ b.
pub fn transpose_times(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = (0..3).map(|k| a[k][i] * b[k][j]).sum();
        }
    }
    c
}

/// a b.
pub fn times(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// m v.
pub fn apply(m: &Mat3, v: &[f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// The eigenvalues and orthonormal eigenvectors of a symmetric matrix:
/// m = Σ_a values[a] vₐ vₐᵀ with vₐ = column a of `vectors`
/// (`vectors[i][a]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricEigen {
    pub values: [f64; 3],
    pub vectors: Mat3,
}

impl SymmetricEigen {
    /// Eigenvector a as an array.
    pub fn vector(&self, a: usize) -> [f64; 3] {
        [self.vectors[0][a], self.vectors[1][a], self.vectors[2][a]]
    }
}

/// Largest number of Jacobi sweeps; three to five reach round-off for any
/// 3 × 3 matrix (convergence is quadratic), so this bound is never the
/// reason a decomposition stops.
const MAX_SWEEPS: usize = 32;

/// The eigen-decomposition of the symmetric matrix `m` (only its upper
/// triangle is read). A diagonal matrix, e.g. the identity, is returned
/// as is with the unit vectors, without a rotation.
pub fn symmetric_eigen(m: &Mat3) -> SymmetricEigen {
    let mut a = [
        [m[0][0], m[0][1], m[0][2]],
        [m[0][1], m[1][1], m[1][2]],
        [m[0][2], m[1][2], m[2][2]],
    ];
    let mut v = IDENTITY;
    for _ in 0..MAX_SWEEPS {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diagonal = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        // Off-diagonal entries below 1e-18 of the diagonal's size no longer
        // move any eigenvalue in double precision.
        if off <= 1e-36 * diagonal || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            rotate(&mut a, &mut v, p, q);
        }
    }
    SymmetricEigen {
        values: [a[0][0], a[1][1], a[2][2]],
        vectors: v,
    }
}

/// One Jacobi rotation in the (p, q) plane that zeroes a[p][q]:
/// a ← Jᵀ a J, v ← v J.
fn rotate(a: &mut Mat3, v: &mut Mat3, p: usize, q: usize) {
    let apq = a[p][q];
    if apq == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
    // The smaller root of t² + 2θt − 1 = 0 (rotation angle ≤ π/4), written
    // so that it neither cancels nor overflows for large |θ|.
    let t = if theta.abs() > 1e150 {
        0.5 / theta
    } else {
        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
    };
    let t = if theta == 0.0 { 1.0 } else { t };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for row in a.iter_mut() {
        let (akp, akq) = (row[p], row[q]);
        row[p] = c * akp - s * akq;
        row[q] = s * akp + c * akq;
    }
    let (row_p, row_q) = (a[p], a[q]);
    for (k, (apk, aqk)) in row_p.iter().zip(&row_q).enumerate() {
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
    }
    // Exact zero, and exact symmetry for the next rotations.
    a[p][q] = 0.0;
    a[q][p] = 0.0;
    for row in v.iter_mut() {
        let (vp, vq) = (row[p], row[q]);
        row[p] = c * vp - s * vq;
        row[q] = s * vp + c * vq;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reconstruct(e: &SymmetricEigen) -> Mat3 {
        let mut m = [[0.0; 3]; 3];
        for a in 0..3 {
            let v = e.vector(a);
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] += e.values[a] * v[i] * v[j];
                }
            }
        }
        m
    }

    fn assert_decomposes(m: &Mat3) {
        let e = symmetric_eigen(m);
        let back = reconstruct(&e);
        let vtv = transpose_times(&e.vectors, &e.vectors);
        for i in 0..3 {
            for j in 0..3 {
                assert!((back[i][j] - m[i][j]).abs() < 1e-14, "{m:?}: {back:?}");
                let id = if i == j { 1.0 } else { 0.0 };
                assert!((vtv[i][j] - id).abs() < 1e-14, "not orthonormal: {vtv:?}");
            }
        }
    }

    #[test]
    fn decomposes_distinct_repeated_and_triple_eigenvalues() {
        assert_decomposes(&IDENTITY);
        assert_decomposes(&[[2.0, 0.3, -0.1], [0.3, 1.5, 0.2], [-0.1, 0.2, 0.7]]);
        // Equibiaxial: a double eigenvalue, rotated off the axes.
        let (c, s) = (0.6_f64, 0.8_f64);
        let q = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let d = [[1.44, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, 0.0, 1.44]];
        let m = times(
            &times(&q, &d),
            &[[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]],
        );
        assert_decomposes(&m);
        let mut values = symmetric_eigen(&m).values;
        values.sort_by(f64::total_cmp);
        assert!((values[0] - 0.2).abs() < 1e-15 && (values[2] - 1.44).abs() < 1e-15);
        // Nearly equal eigenvalues (1e-12 apart).
        assert_decomposes(&[
            [1.0, 1e-12, 0.0],
            [1e-12, 1.0, 0.0],
            [0.0, 0.0, 1.0 + 1e-12],
        ]);
    }

    #[test]
    fn cofactor_is_det_times_inverse_transpose() {
        let m = [[1.2, 0.1, -0.3], [0.05, 0.9, 0.2], [0.1, -0.2, 1.1]];
        let c = cofactor(&m);
        let product = transpose_times(&c, &m);
        for (i, row) in product.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                let expected = if i == j { det(&m) } else { 0.0 };
                assert!((value - expected).abs() < 1e-15);
            }
        }
    }
}
