//! From tracked points to deformation: least-squares affine fits of point
//! positions (the displacement gradient over a strain window, or over the
//! whole gauge section), principal stretches and Green–Lagrange strain.
//!
//! With X the undeformed and x the current position, a window's points are
//! fitted by x = a + F (X − X̄) in least squares, F = I + ∇u being the
//! deformation gradient; principal stretches are the square roots of the
//! eigenvalues of C = FᵀF and E = ½ (C − I) (e.g. Holzapfel, "Nonlinear
//! Solid Mechanics", 2000, §2.5).

/// A 2 × 2 matrix, `m[row][column]`.
pub type Mat2 = [[f64; 2]; 2];

pub const IDENTITY: Mat2 = [[1.0, 0.0], [0.0, 1.0]];

pub fn mat_mul(a: &Mat2, b: &Mat2) -> Mat2 {
    [
        [
            a[0][0] * b[0][0] + a[0][1] * b[1][0],
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
        ],
        [
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1],
        ],
    ]
}

pub fn mat_inv(a: &Mat2) -> Option<Mat2> {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if det.is_nan() || det.abs() <= 1e-12 {
        return None;
    }
    Some([
        [a[1][1] / det, -a[0][1] / det],
        [-a[1][0] / det, a[0][0] / det],
    ])
}

/// Least-squares x = a + F (X − X̄) over matched points; returns (X̄, a, F),
/// or None with fewer than three points or collinear ones.
pub fn affine_fit(from: &[[f64; 2]], to: &[[f64; 2]]) -> Option<([f64; 2], [f64; 2], Mat2)> {
    let n = from.len().min(to.len());
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let mut mean_from = [0.0; 2];
    let mut mean_to = [0.0; 2];
    for (p, q) in from.iter().zip(to) {
        for c in 0..2 {
            mean_from[c] += p[c] / nf;
            mean_to[c] += q[c] / nf;
        }
    }
    // Normal equations of the centred problem: S F^T = B.
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let mut b = [[0.0; 2]; 2]; // b[c][k] = Σ (X_k − X̄_k)(x_c − x̄_c)
    for (p, q) in from.iter().zip(to) {
        let (dx, dy) = (p[0] - mean_from[0], p[1] - mean_from[1]);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
        for c in 0..2 {
            let d = q[c] - mean_to[c];
            b[c][0] += dx * d;
            b[c][1] += dy * d;
        }
    }
    let det = sxx * syy - sxy * sxy;
    if det.is_nan() || det <= 1e-12 * (sxx * syy).max(1e-300) {
        return None;
    }
    let mut f = [[0.0; 2]; 2];
    for c in 0..2 {
        f[c][0] = (syy * b[c][0] - sxy * b[c][1]) / det;
        f[c][1] = (sxx * b[c][1] - sxy * b[c][0]) / det;
    }
    Some((mean_from, mean_to, f))
}

/// Principal stretches (λ along the loading axis x, λ₂ across it): the
/// principal direction nearer to x takes the first.
pub fn principal_stretches(f: &Mat2) -> (f64, f64) {
    stretches_along(f, 0.0)
}

/// The larger principal stretch, the smaller, and the angle θ (radians,
/// from x, in the frame-0 configuration) of the larger one's direction:
/// the eigen-decomposition of C = FᵀF, tan 2θ = 2 C_xy / (C_xx − C_yy).
pub fn principal(f: &Mat2) -> (f64, f64, f64) {
    let c = right_cauchy_green(f);
    let mean = 0.5 * (c[0][0] + c[1][1]);
    let radius = (0.25 * (c[0][0] - c[1][1]).powi(2) + c[0][1] * c[0][1]).sqrt();
    let theta = 0.5 * (2.0 * c[0][1]).atan2(c[0][0] - c[1][1]);
    (
        (mean + radius).sqrt(),
        (mean - radius).max(0.0).sqrt(),
        theta,
    )
}

/// Principal stretches ordered by a loading axis at angle `axis_rad` from
/// x: the one whose principal direction is nearer the axis first.
pub fn stretches_along(f: &Mat2, axis_rad: f64) -> (f64, f64) {
    let (big, small, theta) = principal(f);
    let off = theta - axis_rad;
    if off.cos().abs() >= off.sin().abs() {
        (big, small)
    } else {
        (small, big)
    }
}

/// C = FᵀF.
pub fn right_cauchy_green(f: &Mat2) -> Mat2 {
    let mut c = [[0.0; 2]; 2];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = f[0][i] * f[0][j] + f[1][i] * f[1][j];
        }
    }
    c
}

/// Green–Lagrange strain (E_xx, E_yy, E_xy).
pub fn green_lagrange(f: &Mat2) -> [f64; 3] {
    let c = right_cauchy_green(f);
    [0.5 * (c[0][0] - 1.0), 0.5 * (c[1][1] - 1.0), 0.5 * c[0][1]]
}

/// The deformation gradient at every point of an `nx × ny` grid (index
/// `iy * nx + ix`) from a least-squares fit over the `window × window`
/// points around it; None where fewer than half the window's points are
/// valid.
pub fn gradient_field(
    nx: usize,
    ny: usize,
    reference: &[[f64; 2]],
    current: &[Option<[f64; 2]>],
    window: usize,
) -> Vec<Option<Mat2>> {
    let half = window / 2;
    let mut out = Vec::with_capacity(nx * ny);
    let mut from = Vec::new();
    let mut to = Vec::new();
    for iy in 0..ny {
        for ix in 0..nx {
            from.clear();
            to.clear();
            if current[iy * nx + ix].is_none() {
                out.push(None);
                continue;
            }
            let mut total = 0;
            for jy in iy.saturating_sub(half)..(iy + half + 1).min(ny) {
                for jx in ix.saturating_sub(half)..(ix + half + 1).min(nx) {
                    total += 1;
                    if let Some(x) = current[jy * nx + jx] {
                        from.push(reference[jy * nx + jx]);
                        to.push(x);
                    }
                }
            }
            out.push(if 2 * from.len() >= total {
                affine_fit(&from, &to).map(|(_, _, f)| f)
            } else {
                None
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn affine_fit_recovers_an_exact_map() {
        let f_true = [[1.3, 0.05], [-0.02, 0.9]];
        let from: Vec<[f64; 2]> = (0..5)
            .flat_map(|i| (0..4).map(move |j| [10.0 * i as f64, 7.0 * j as f64]))
            .collect();
        let to: Vec<[f64; 2]> = from
            .iter()
            .map(|p| {
                [
                    3.0 + f_true[0][0] * p[0] + f_true[0][1] * p[1],
                    -2.0 + f_true[1][0] * p[0] + f_true[1][1] * p[1],
                ]
            })
            .collect();
        let (_, _, f) = affine_fit(&from, &to).unwrap();
        for i in 0..2 {
            for j in 0..2 {
                assert!((f[i][j] - f_true[i][j]).abs() < 1e-12);
            }
        }
        assert!(affine_fit(&from[..2], &to[..2]).is_none());
    }

    #[test]
    fn principal_stretches_survive_a_rotation_and_keep_the_loading_axis() {
        // F = R U with U = diag(2.5, 0.632) and a 10° rotation: the
        // stretches are U's, the loading one first.
        let (s, c) = 10f64.to_radians().sin_cos();
        let r = [[c, -s], [s, c]];
        let u = [[2.5, 0.0], [0.0, 2.5f64.powf(-0.5)]];
        let (l1, l2) = principal_stretches(&mat_mul(&r, &u));
        assert!((l1 - 2.5).abs() < 1e-12 && (l2 - 2.5f64.powf(-0.5)).abs() < 1e-12);
        // Compression along x: x's stretch is still first.
        let (l1, l2) = principal_stretches(&[[0.8, 0.0], [0.0, 1.2]]);
        assert!((l1 - 0.8).abs() < 1e-12 && (l2 - 1.2).abs() < 1e-12);
        // Along y, and along a principal direction at 30°: F = R(30°) U R(30°)ᵀ
        // stretches by 1.4 along 30° and 0.9 across.
        let (l1, l2) = stretches_along(&[[0.8, 0.0], [0.0, 1.2]], std::f64::consts::FRAC_PI_2);
        assert!((l1 - 1.2).abs() < 1e-12 && (l2 - 0.8).abs() < 1e-12);
        let (s, c) = 30f64.to_radians().sin_cos();
        let (a, b) = (1.4, 0.9);
        let f = [
            [a * c * c + b * s * s, (a - b) * s * c],
            [(a - b) * s * c, a * s * s + b * c * c],
        ];
        let (big, small, theta) = principal(&f);
        assert!((big - 1.4).abs() < 1e-12 && (small - 0.9).abs() < 1e-12);
        assert!((theta - 30f64.to_radians()).abs() < 1e-12);
        let across = stretches_along(&f, 120f64.to_radians());
        assert!((across.0 - 0.9).abs() < 1e-12 && (across.1 - 1.4).abs() < 1e-12);
        let e = green_lagrange(&[[2.0, 0.0], [0.0, 1.0]]);
        assert_eq!(e, [1.5, 0.0, 0.0]);
    }
}
