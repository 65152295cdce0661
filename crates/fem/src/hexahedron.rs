//! The 8-node hexahedron with 2 × 2 × 2 Gauss points and a constant volume
//! ratio per element: the mixed u/p/J (Q1/P0) element of Simo, Taylor &
//! Pister (CMAME 51, 1985) after static condensation. With p and θ constant
//! per element, stationarity of ∫ [W(F) + U(θ) + p (J − θ)] dV in p and θ
//! gives θ = v/V (deformed over reference volume) and p = U′(θ), so the
//! condensed element is the energy functional
//!
//! Π_e(u) = Σ_g w_g W(F_g) + V U(v(u)/V),  v = Σ_g w_g J(F_g),
//!
//! whose gradient is the nodal force and whose Hessian the consistent
//! tangent (the volumetric part: U″/V ∂v⊗∂v + U′ ∂²v). The volume is
//! constrained once per element, not at every Gauss point, which is what
//! keeps the element free of locking as ν → ½.
//!
//! Node order is VTK's hexahedron: the bottom face (ζ = −1) counter-clockwise
//! from (−1, −1), then the top face.

use crate::law::Law;
use crate::tensor::Mat3;

/// The reference coordinates (ξ, η, ζ) of the nodes.
pub const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// 24 × 24 element stiffness, row/column 3a + i for node a, component i.
pub type Stiffness = [[f64; 24]; 24];

/// The condensed element's energy, nodal forces and tangent.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementOutput {
    /// Π_e, J.
    pub energy_j: f64,
    /// ∂Π_e/∂u, N (entry 3a + i).
    pub force_n: [f64; 24],
    /// ∂²Π_e/∂u∂u, N/m.
    pub stiffness: Option<Box<Stiffness>>,
    /// The element's volume ratio θ = v/V.
    pub volume_ratio: f64,
}

/// Why an element has no response.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ElementFailure {
    /// The reference element has a non-positive Jacobian at a Gauss point.
    BadReference,
    /// The deformed element is inverted at a Gauss point (det F ≤ 0).
    Inverted,
}

/// Derivatives of the shape functions N_a = ⅛ Π (1 + ξ_a ξ) in (ξ, η, ζ).
fn shape_derivatives(point: &[f64; 3]) -> [[f64; 3]; 8] {
    CORNERS.map(|c| {
        let f = [0, 1, 2].map(|k| 1.0 + c[k] * point[k]);
        [
            0.125 * c[0] * f[1] * f[2],
            0.125 * f[0] * c[1] * f[2],
            0.125 * f[0] * f[1] * c[2],
        ]
    })
}

/// The 2 × 2 × 2 Gauss points (weights 1).
fn gauss_points() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    CORNERS.map(|c| c.map(|s| s * g))
}

/// Reference gradients ∇_X N_a and the weight w = det(∂X/∂ξ) at a point.
fn reference_gradients(
    reference_m: &[[f64; 3]; 8],
    point: &[f64; 3],
) -> Result<([[f64; 3]; 8], f64), ElementFailure> {
    let dn = shape_derivatives(point);
    let mut jacobian = [[0.0; 3]; 3];
    for (x, d) in reference_m.iter().zip(&dn) {
        for i in 0..3 {
            for k in 0..3 {
                jacobian[i][k] += x[i] * d[k];
            }
        }
    }
    let det = crate::tensor::det(&jacobian);
    if det.is_nan() || det <= 0.0 {
        return Err(ElementFailure::BadReference);
    }
    // ∇_X N = J⁻ᵀ ∇_ξ N, with J⁻¹ = cof(J)ᵀ / det.
    let cof = crate::tensor::cofactor(&jacobian);
    let gradients =
        dn.map(|d| [0, 1, 2].map(|i| (0..3).map(|k| cof[i][k] * d[k]).sum::<f64>() / det));
    Ok((gradients, det))
}

/// One Gauss point's kinematic data kept for the volumetric tangent.
#[derive(Clone, Copy, Default)]
struct VolumePoint {
    weight: f64,
    volume_ratio: f64,
    /// h_a = ∂J/∂F · ∇_X N_a (= J ∇_x N_a at finite strain).
    h: [[f64; 3]; 8],
}

/// The condensed Q1/P0 element ([module docs](self)) of `law` with nodes at
/// `reference_m` displaced by `displacement_m`.
pub fn evaluate(
    law: &Law,
    reference_m: &[[f64; 3]; 8],
    displacement_m: &[[f64; 3]; 8],
    with_tangent: bool,
) -> Result<ElementOutput, ElementFailure> {
    let mut out = ElementOutput {
        energy_j: 0.0,
        force_n: [0.0; 24],
        stiffness: with_tangent.then(|| Box::new([[0.0; 24]; 24])),
        volume_ratio: 0.0,
    };
    let mut points = [VolumePoint::default(); 8];
    let (mut volume, mut deformed_volume) = (0.0, 0.0);
    let mut dv = [0.0; 24];
    for (point, gauss) in points.iter_mut().zip(gauss_points()) {
        let (g, weight) = reference_gradients(reference_m, &gauss)?;
        let mut f: Mat3 = crate::tensor::IDENTITY;
        for (u, ga) in displacement_m.iter().zip(&g) {
            for i in 0..3 {
                for big_i in 0..3 {
                    f[i][big_i] += u[i] * ga[big_i];
                }
            }
        }
        let response = law
            .isochoric(&f, with_tangent)
            .ok_or(ElementFailure::Inverted)?;
        let ratio = law.volume_ratio(&f);
        if ratio.finite && (ratio.value.is_nan() || ratio.value <= 0.0) {
            return Err(ElementFailure::Inverted);
        }
        out.energy_j += weight * response.energy_pa;
        volume += weight;
        deformed_volume += weight * ratio.value;
        *point = VolumePoint {
            weight,
            volume_ratio: if ratio.finite { ratio.value } else { 0.0 },
            h: g.map(|ga| [0, 1, 2].map(|i| (0..3).map(|k| ratio.gradient[i][k] * ga[k]).sum())),
        };
        for (a, ga) in g.iter().enumerate() {
            for i in 0..3 {
                out.force_n[3 * a + i] += weight
                    * (0..3)
                        .map(|k| response.stress_pa[i][k] * ga[k])
                        .sum::<f64>();
                dv[3 * a + i] += weight * point.h[a][i];
            }
        }
        if let Some(k) = out.stiffness.as_deref_mut() {
            add_material_stiffness(k, &g, &response.tangent_pa, weight);
        }
    }
    let theta = deformed_volume / volume;
    let (u, pressure, stiffness) = law.volumetric(theta);
    out.energy_j += volume * u;
    out.volume_ratio = theta;
    for (force, d) in out.force_n.iter_mut().zip(&dv) {
        *force += pressure * d;
    }
    if let Some(k) = out.stiffness.as_deref_mut() {
        add_volumetric_stiffness(k, &dv, &points, stiffness / volume, pressure);
        mirror_lower_blocks(k);
    }
    Ok(out)
}

/// K_ab,ij += w Σ_IJ G_aI A_iI,jJ G_bJ for node blocks b ≥ a (A is a
/// Hessian, so K is symmetric: the blocks b < a are mirrored afterwards).
fn add_material_stiffness(
    k: &mut Stiffness,
    g: &[[f64; 3]; 8],
    tangent: &[[f64; 9]; 9],
    weight: f64,
) {
    for (a, ga) in g.iter().enumerate() {
        // t[i][jJ] = w Σ_I G_aI A[iI][jJ]
        let mut t = [[0.0; 9]; 3];
        for (i, ti) in t.iter_mut().enumerate() {
            for (big_i, gai) in ga.iter().enumerate() {
                let row = &tangent[3 * i + big_i];
                for (entry, value) in ti.iter_mut().zip(row) {
                    *entry += weight * gai * value;
                }
            }
        }
        for (b, gb) in g.iter().enumerate().skip(a) {
            for (i, ti) in t.iter().enumerate() {
                let row = &mut k[3 * a + i];
                for j in 0..3 {
                    row[3 * b + j] +=
                        ti[3 * j] * gb[0] + ti[3 * j + 1] * gb[1] + ti[3 * j + 2] * gb[2];
                }
            }
        }
    }
}

/// K += U″/V dv⊗dv + U′ Σ_g w_g ∂²J_g, with
/// ∂²J/∂u_ai∂u_bj = (h_ai h_bj − h_aj h_bi)/J at finite strain (0 for the
/// linear volume ratio).
fn add_volumetric_stiffness(
    k: &mut Stiffness,
    dv: &[f64; 24],
    points: &[VolumePoint; 8],
    stiffness_over_volume: f64,
    pressure: f64,
) {
    for (p, (row, dr)) in k.iter_mut().zip(dv).enumerate() {
        // Node blocks b ≥ a only (see `mirror_lower_blocks`).
        let first = 3 * (p / 3);
        for (entry, dc) in row[first..].iter_mut().zip(&dv[first..]) {
            *entry += stiffness_over_volume * dr * dc;
        }
    }
    for point in points.iter().filter(|p| p.volume_ratio > 0.0) {
        let scale = pressure * point.weight / point.volume_ratio;
        for a in 0..8 {
            for b in a..8 {
                let (ha, hb) = (&point.h[a], &point.h[b]);
                for i in 0..3 {
                    for j in 0..3 {
                        k[3 * a + i][3 * b + j] += scale * (ha[i] * hb[j] - ha[j] * hb[i]);
                    }
                }
            }
        }
    }
}

/// K_ba = K_abᵀ for b < a, from the blocks computed.
fn mirror_lower_blocks(k: &mut Stiffness) {
    for a in 0..8 {
        for b in 0..a {
            for i in 0..3 {
                for j in 0..3 {
                    k[3 * a + i][3 * b + j] = k[3 * b + j][3 * a + i];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::tests::every_family;

    fn unit_cube_distorted() -> [[f64; 3]; 8] {
        let mut x = CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0) * 1e-3));
        x[6][0] += 0.1e-3;
        x[7][2] -= 0.05e-3;
        x[1][1] += 0.03e-3;
        x
    }

    fn displacement(scale: f64) -> [[f64; 3]; 8] {
        std::array::from_fn(|a| {
            [0, 1, 2].map(|i| scale * 1e-3 * (((a * 7 + i * 3) % 5) as f64 - 2.0) * 0.04)
        })
    }

    /// The tangent equals central differences of the nodal forces, and the
    /// forces equal differences of the energy, for every family and the
    /// linear law.
    #[test]
    fn tangent_and_forces_equal_differences() {
        let x = unit_cube_distorted();
        let mut laws: Vec<Law> = every_family()
            .iter()
            .map(|m| Law::hyperelastic(m.as_ref(), 50.0).unwrap())
            .collect();
        laws.push(Law::linear_elastic(1.0e6, 50.0).unwrap());
        for law in laws {
            let u = displacement(1.0);
            let out = evaluate(&law, &x, &u, true).unwrap();
            let k = out.stiffness.as_deref().unwrap();
            // Steps: the paper's Ogden terms cancel (μ_i ~ 5e9 Pa summing to
            // 2e6 Pa), so its energy carries ~1e-3 Pa of round-off; 1e-6 m
            // (a strain of 1e-3) keeps that below the tolerance, and the
            // forces, accurate to ~1e-5 Pa, allow 1e-7 m.
            let (h_energy, h_force) = (1e-6, 1e-7);
            let stiffness_scale = law.shear_modulus_pa() * 1e-3;
            let force_scale = law.shear_modulus_pa() * 1e-6;
            for p in 0..24 {
                let shifted = |delta: f64| {
                    let mut v = u;
                    v[p / 3][p % 3] += delta;
                    evaluate(&law, &x, &v, false).unwrap()
                };
                let force =
                    (shifted(h_energy).energy_j - shifted(-h_energy).energy_j) / (2.0 * h_energy);
                assert!(
                    (force - out.force_n[p]).abs() < 1e-6 * force_scale,
                    "{law:?} f[{p}]: {} vs {force}",
                    out.force_n[p]
                );
                let (plus, minus) = (shifted(h_force), shifted(-h_force));
                for (q, (fp, fm)) in plus.force_n.iter().zip(&minus.force_n).enumerate() {
                    let fd = (fp - fm) / (2.0 * h_force);
                    assert!(
                        (fd - k[q][p]).abs() < 1e-6 * stiffness_scale,
                        "K[{q}][{p}]: {} vs {fd}",
                        k[q][p]
                    );
                    assert!((k[q][p] - k[p][q]).abs() < 1e-9 * stiffness_scale);
                }
            }
        }
    }

    #[test]
    fn rigid_translation_is_force_free_and_inversion_is_reported() {
        let x = unit_cube_distorted();
        let law = Law::hyperelastic(every_family()[2].as_ref(), 5000.0).unwrap();
        let shift = [[1e-4, -2e-4, 3e-4]; 8];
        let out = evaluate(&law, &x, &shift, false).unwrap();
        assert!(out.force_n.iter().all(|f| f.abs() < 1e-12));
        let mut flat = [[0.0; 3]; 8];
        for (u, xa) in flat.iter_mut().zip(&x) {
            u[2] = -2.0 * xa[2];
        }
        assert_eq!(
            evaluate(&law, &x, &flat, false),
            Err(ElementFailure::Inverted)
        );
        let bad = x.map(|p| [p[0], p[1], -p[2]]);
        assert_eq!(
            evaluate(&law, &bad, &shift, false),
            Err(ElementFailure::BadReference)
        );
    }
}
