//! Least-squares plane h ≈ a + b·i + c·j over the measured (non-NaN) points
//! of a map: the detrending applied before statistics and PSDs (the
//! SurfaceTopography `detrend("height")` model, made NaN-aware).

use nalgebra::{Matrix3, Vector3};
use ndarray::Array2;

/// Plane coefficients in pixel coordinates: h ≈ a + b·i + c·j.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl Plane {
    pub fn at(&self, i: f64, j: f64) -> f64 {
        self.a + self.b * i + self.c * j
    }
}

/// Solves the 3 × 3 normal equations m·x = r (row-major m) by LU with
/// partial pivoting; None if m is singular.
pub fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let x = Matrix3::from_fn(|i, j| m[i][j])
        .lu()
        .solve(&Vector3::from(r))?;
    x.iter().all(|v| v.is_finite()).then(|| x.into())
}

/// The least-squares plane through the non-NaN points; None if they are
/// fewer than three or collinear.
pub fn fit_plane(h: &Array2<f64>) -> Option<Plane> {
    let (nx, ny) = h.dim();
    let (ci, cj) = ((nx as f64 - 1.0) / 2.0, (ny as f64 - 1.0) / 2.0);
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for ((i, j), &v) in h.indexed_iter() {
        if v.is_nan() {
            continue;
        }
        let basis = [1.0, i as f64 - ci, j as f64 - cj];
        for p in 0..3 {
            r[p] += basis[p] * v;
            for q in 0..3 {
                m[p][q] += basis[p] * basis[q];
            }
        }
    }
    let [a, b, c] = solve3(m, r)?;
    Some(Plane {
        a: a - b * ci - c * cj,
        b,
        c,
    })
}

/// Subtracts the plane (NaN stays NaN).
pub fn subtract(h: &mut Array2<f64>, plane: &Plane) {
    for ((i, j), v) in h.indexed_iter_mut() {
        *v -= plane.at(i as f64, j as f64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_plane_through_gaps() {
        let mut h =
            Array2::from_shape_fn((20, 30), |(i, j)| 2.0 - 0.5 * i as f64 + 0.25 * j as f64);
        h[[3, 4]] = f64::NAN;
        h[[10, 10]] = f64::NAN;
        let p = fit_plane(&h).unwrap();
        assert!(
            (p.a - 2.0).abs() < 1e-12 && (p.b + 0.5).abs() < 1e-12 && (p.c - 0.25).abs() < 1e-12
        );
        subtract(&mut h, &p);
        assert!(h.iter().filter(|v| !v.is_nan()).all(|v| v.abs() < 1e-12));
        assert!(h[[3, 4]].is_nan());
    }

    #[test]
    fn a_line_of_points_has_no_plane() {
        let mut h = Array2::from_elem((5, 5), f64::NAN);
        for i in 0..5 {
            h[[i, 2]] = i as f64;
        }
        assert!(fit_plane(&h).is_none());
    }
}
