//! The isochoric hyperelastic response in principal form: energy
//! W(F) = Ψ(m(C)), first Piola–Kirchhoff stress P = ∂W/∂F and the first
//! elasticity tensor A = ∂P/∂F, for Ψ of power traces
//! m_k = J^(−2p_k/3) Σ_a c_a^(p_k) ([`crate::energy`]), with c_a the
//! eigenvalues of C = FᵀF and N_a its eigenvectors.
//!
//! For an isotropic W(C) = w(c1, c2, c3) (Ogden 1984, Non-linear Elastic
//! Deformations, § 6.1; Simo & Taylor, CMAME 85, 1991):
//! S = 2 Σ_a w_a N_a⊗N_a and
//! ℂ = 4 [Σ_ab w_ab N_a⊗N_a⊗N_b⊗N_b + Σ_{a≠b} θ_ab N_a⊗N_b⊗(N_a⊗N_b)^sym]
//! with θ_ab = (w_a − w_b)/(c_a − c_b). That quotient is 0/0 where
//! stretches coincide (the undeformed state, equibiaxial states); here it
//! is never formed by subtraction: for a power trace it is, exactly,
//! p s [Δ_(p−1)(c_a, c_b) + t/(3 c_a c_b)] with the divided difference
//! Δ_q(x, y) = (x^q − y^q)/(x − y) evaluated as
//! y^(q−1) expm1(q ln(x/y)) / expm1(ln(x/y)), which is accurate for close
//! arguments and tends to q x^(q−1) at equal ones. So any orthonormal
//! eigenbasis from [`crate::tensor::symmetric_eigen`] serves, and no
//! perturbation of equal eigenvalues is needed.

use crate::energy::{IsochoricEnergy, MAX_TRACES};
use crate::tensor::{Mat3, apply, symmetric_eigen, transpose_times};

/// W, P and A = ∂P/∂F (A[3i + I][3j + J] = ∂P_iI/∂F_jJ) at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Response {
    pub energy_pa: f64,
    pub stress_pa: Mat3,
    pub tangent_pa: [[f64; 9]; 9],
}

/// Δ_q(x, y) = (x^q − y^q)/(x − y) for x, y > 0, without cancellation.
pub fn divided_difference(q: f64, x: f64, y: f64) -> f64 {
    divided_difference_at(q, y.powf(q - 1.0), (x / y).ln())
}

/// Δ_q(x, y) from y^(q−1) and L = ln(x/y): y^(q−1) expm1(qL)/expm1(L),
/// and q y^(q−1) at L = 0.
fn divided_difference_at(q: f64, y_power: f64, log: f64) -> f64 {
    if log == 0.0 {
        q * y_power
    } else {
        y_power * (q * log).exp_m1() / log.exp_m1()
    }
}

/// Per-trace quantities at one state: s = J^(−2p/3), t = Σ c_a^p,
/// c_a^(p−1), and q_a = c_a^(p−1) − t/(3 c_a), so that ∂m/∂c_a = p s q_a.
struct Trace {
    p: f64,
    s: f64,
    t: f64,
    power_less_one: [f64; 3],
    q: [f64; 3],
}

impl Trace {
    fn new(p: f64, ln_j: f64, c: &[f64; 3]) -> Self {
        let power = c.map(|ca| ca.powf(p));
        let t = power[0] + power[1] + power[2];
        let power_less_one = [0, 1, 2].map(|a| power[a] / c[a]);
        Self {
            p,
            s: (-2.0 * p / 3.0 * ln_j).exp(),
            t,
            power_less_one,
            q: [0, 1, 2].map(|a| power_less_one[a] - t / (3.0 * c[a])),
        }
    }
}

/// The isochoric response at deformation gradient `f` (A only
/// `with_tangent`, else zero); `None` where det F ≤ 0 (an inverted point,
/// which the solver backs away from).
pub fn response(energy: &IsochoricEnergy, f: &Mat3, with_tangent: bool) -> Option<Response> {
    let j = crate::tensor::det(f);
    let eigen = symmetric_eigen(&transpose_times(f, f));
    let c = eigen.values;
    if !(j > 0.0 && c.iter().all(|v| *v > 0.0) && j.is_finite()) {
        return None;
    }
    let (powers, count) = energy.powers();
    let ln_j = j.ln();
    let traces: [Trace; MAX_TRACES] =
        std::array::from_fn(|k| Trace::new(if k < count { powers[k] } else { 0.0 }, ln_j, &c));
    let traces = &traces[..count];
    let mut m = [0.0; MAX_TRACES];
    for (mk, tr) in m.iter_mut().zip(traces) {
        *mk = tr.s * tr.t;
    }
    let psi = energy.derivatives(&m[..count], with_tangent);
    let mut w1 = [0.0; 3];
    for (tr, g) in traces.iter().zip(&psi.gradient_pa) {
        for (w, q) in w1.iter_mut().zip(&tr.q) {
            *w += g * tr.p * tr.s * q;
        }
    }
    let (w2, theta) = if with_tangent {
        second_derivatives(traces, &psi, &c)
    } else {
        ([[0.0; 3]; 3], [[0.0; 3]; 3])
    };
    Some(assemble(
        f,
        &eigen,
        psi.energy_pa,
        &w1,
        &w2,
        &theta,
        with_tangent,
    ))
}

/// w_ab = ∂²w/∂c_a∂c_b and θ_ab = (w_a − w_b)/(c_a − c_b) (a ≠ b), the
/// latter through divided differences of c^(p−1) that share one
/// ln(c_a/c_b) per pair.
fn second_derivatives(
    traces: &[Trace],
    psi: &crate::energy::TraceDerivatives,
    c: &[f64; 3],
) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
    let mut w2 = [[0.0; 3]; 3];
    let mut theta = [[0.0; 3]; 3];
    let pairs = [(0, 1), (0, 2), (1, 2)];
    let logs = pairs.map(|(a, b)| (c[a] / c[b]).ln());
    for (k, tr) in traces.iter().enumerate() {
        let g = psi.gradient_pa[k];
        let (p, s, t) = (tr.p, tr.s, tr.t);
        for a in 0..3 {
            for b in 0..3 {
                let mut second = -(p / 3.0) * (tr.q[a] / c[b] + tr.power_less_one[b] / c[a]);
                if a == b {
                    second += (p - 1.0) * tr.power_less_one[a] / c[a] + t / (3.0 * c[a] * c[a]);
                }
                let mut hessian_part = 0.0;
                for (l, other) in traces.iter().enumerate() {
                    hessian_part += psi.hessian_pa[k][l] * other.p * other.s * other.q[b];
                }
                w2[a][b] += g * p * s * second + hessian_part * p * s * tr.q[a];
            }
        }
        for (&(a, b), &log) in pairs.iter().zip(&logs) {
            let divided = divided_difference_at(p - 1.0, tr.power_less_one[b] / c[b], log);
            let value = g * p * s * (divided + t / (3.0 * c[a] * c[b]));
            theta[a][b] += value;
            theta[b][a] += value;
        }
    }
    (w2, theta)
}

/// P and A from the principal derivatives (module doc), with n_a = F N_a:
/// A_iIjJ = δ_ij S_IJ + 4 Σ_ab w_ab X_a,iI X_b,jJ
///        + 2 Σ_{a≠b} θ_ab Y_ab,iI (Y_ab,jJ + Y_ba,jJ),
/// X_a,iI = n_a,i N_a,I and Y_ab,iI = n_a,i N_b,I.
fn assemble(
    f: &Mat3,
    eigen: &crate::tensor::SymmetricEigen,
    energy_pa: f64,
    w1: &[f64; 3],
    w2: &[[f64; 3]; 3],
    theta: &[[f64; 3]; 3],
    with_tangent: bool,
) -> Response {
    let vectors = [0, 1, 2].map(|a| eigen.vector(a));
    let spatial = vectors.map(|v| apply(f, &v));
    let mut s = [[0.0; 3]; 3];
    for a in 0..3 {
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += 2.0 * w1[a] * vectors[a][i] * vectors[a][j];
            }
        }
    }
    let stress_pa = crate::tensor::times(f, &s);
    let mut tangent = [[0.0; 9]; 9];
    if !with_tangent {
        return Response {
            energy_pa,
            stress_pa,
            tangent_pa: tangent,
        };
    }
    let y = |a: usize, b: usize| -> [f64; 9] {
        std::array::from_fn(|iu| spatial[a][iu / 3] * vectors[b][iu % 3])
    };
    let x: [[f64; 9]; 3] = [y(0, 0), y(1, 1), y(2, 2)];
    for a in 0..3 {
        for b in 0..3 {
            let weight = 4.0 * w2[a][b];
            for (row, xa) in tangent.iter_mut().zip(x[a]) {
                for (entry, xb) in row.iter_mut().zip(x[b]) {
                    *entry += weight * xa * xb;
                }
            }
            if a != b {
                let (yab, yba) = (y(a, b), y(b, a));
                let weight = 2.0 * theta[a][b];
                for (row, ya) in tangent.iter_mut().zip(yab) {
                    for ((entry, u), v) in row.iter_mut().zip(yab).zip(yba) {
                        *entry += weight * ya * (u + v);
                    }
                }
            }
        }
    }
    for i in 0..3 {
        for big_i in 0..3 {
            for big_j in 0..3 {
                tangent[3 * i + big_i][3 * i + big_j] += s[big_i][big_j];
            }
        }
    }
    Response {
        energy_pa,
        stress_pa,
        tangent_pa: tangent,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::tests::every_family;

    #[test]
    fn divided_difference_is_accurate_near_and_at_equal_arguments() {
        for q in [-1.5, -0.52, 0.3, 2.0] {
            let x: f64 = 1.3;
            assert_eq!(divided_difference(q, x, x), q * x.powf(q - 1.0));
            // Far apart: the plain quotient is accurate.
            let plain = (x.powf(q) - 0.7f64.powf(q)) / (x - 0.7);
            assert!((divided_difference(q, x, 0.7) / plain - 1.0).abs() < 1e-14);
            // 1e-13 apart: the plain quotient has lost ~3 digits; the
            // series q x^(q−1) (1 + (q−1) δ/(2x)) has not.
            let delta = 1e-13;
            let series = q * x.powf(q - 1.0) * (1.0 + (q - 1.0) * delta / (2.0 * x));
            assert!((divided_difference(q, x + delta, x) / series - 1.0).abs() < 1e-15);
        }
    }

    fn sample_gradients() -> Vec<Mat3> {
        vec![
            crate::tensor::IDENTITY,
            [[1.2, 0.1, -0.05], [0.02, 0.85, 0.1], [0.07, -0.03, 1.1]],
            // equibiaxial compression with a rotation: a double eigenvalue
            [[0.0, -0.8, 0.0], [0.8, 0.0, 0.0], [0.0, 0.0, 1.5625]],
            [[0.8, 0.0, 0.0], [0.0, 0.8, 0.0], [0.0, 0.0, 1.5625]],
            // nearly equal stretches (1e-9 apart)
            [[1.1, 1e-9, 0.0], [0.0, 1.1, 0.0], [0.0, 0.0, 0.9]],
        ]
    }

    /// P against central differences of W, and A against central
    /// differences of P, for every family at equal and unequal stretches.
    #[test]
    fn stress_and_tangent_equal_differences_of_energy_and_stress() {
        for model in every_family() {
            let energy = IsochoricEnergy::from_model(model.as_ref()).unwrap();
            let mu = model.shear_modulus_pa();
            for f in sample_gradients() {
                let r = response(&energy, &f, true).unwrap();
                // The paper's Ogden terms (μ_i ~ 5e9 Pa, α_i ~ 0.05) cancel to
                // μ0 ~ 2e6 Pa: its energy carries ~1e-3 Pa of round-off and
                // its stress ~1e-5 Pa, which set the steps (1e-4 for the
                // energy's differences, 1e-5 for the stress's) and the 1e-5
                // tolerance of the stress; the tangent is held to 2e-6.
                let (h_energy, h) = (1e-4, 1e-5);
                for iu in 0..9 {
                    let shifted = |delta: f64| {
                        let mut g = f;
                        g[iu / 3][iu % 3] += delta;
                        response(&energy, &g, true).unwrap()
                    };
                    let stress_fd = (shifted(h_energy).energy_pa - shifted(-h_energy).energy_pa)
                        / (2.0 * h_energy);
                    let (plus, minus) = (shifted(h), shifted(-h));
                    let stress = r.stress_pa[iu / 3][iu % 3];
                    assert!(
                        (stress_fd - stress).abs() < 1e-5 * (mu + stress.abs()),
                        "{} F={f:?} P[{iu}]: {stress} vs {stress_fd}",
                        model.family()
                    );
                    for ju in 0..9 {
                        let fd = (plus.stress_pa[ju / 3][ju % 3] - minus.stress_pa[ju / 3][ju % 3])
                            / (2.0 * h);
                        let exact = r.tangent_pa[ju][iu];
                        assert!(
                            (fd - exact).abs() < 2e-6 * (mu + exact.abs()),
                            "{} F={f:?} A[{ju}][{iu}]: {exact} vs {fd}",
                            model.family()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn undeformed_state_is_stress_free_with_the_isotropic_shear_tangent() {
        for model in every_family() {
            let energy = IsochoricEnergy::from_model(model.as_ref()).unwrap();
            let mu = model.shear_modulus_pa();
            let r = response(&energy, &crate::tensor::IDENTITY, true).unwrap();
            assert!(r.stress_pa.iter().flatten().all(|s| s.abs() < 1e-9 * mu));
            // Linearised: A = μ (δ_ij δ_IJ + δ_iJ δ_jI) − (2μ/3) δ_iI δ_jJ.
            for iu in 0..9 {
                for ju in 0..9 {
                    let (i, ii, j, jj) = (iu / 3, iu % 3, ju / 3, ju % 3);
                    let d = |a: usize, b: usize| f64::from(u8::from(a == b));
                    let expected = mu * (d(i, j) * d(ii, jj) + d(i, jj) * d(j, ii))
                        - 2.0 * mu / 3.0 * d(i, ii) * d(j, jj);
                    assert!(
                        (r.tangent_pa[iu][ju] - expected).abs() < 1e-8 * mu,
                        "{} A[{iu}][{ju}] = {} vs {expected}",
                        model.family(),
                        r.tangent_pa[iu][ju]
                    );
                }
            }
        }
    }

    #[test]
    fn inverted_points_have_no_response() {
        let energy = IsochoricEnergy::NeoHookean { c10_pa: 1e5 };
        let f = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(response(&energy, &f, true).is_none());
    }
}
