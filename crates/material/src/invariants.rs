//! Stresses, slopes and the Drucker stiffness of strain energies written in
//! the invariants I1 = Σ λ_i², I2 = Σ λ_i⁻² of an incompressible solid
//! (neo-Hookean, Mooney–Rivlin, Yeoh, Arruda–Boyce).
//!
//! Along a test path λ ↦ (λ1, λ2, λ3) the nominal stress is
//! T = (W1 dI1/dλ + W2 dI2/dλ) / k (k loaded directions), and its slope adds
//! the second derivatives of W. The Drucker stiffness is the Hessian of
//! Ŵ(ε1, ε2) = W at log strains (ε1, ε2, −ε1 − ε2), as in [`crate::stability`];
//! its determinant is also given expanded ([`drucker_stiffness`]) so that it
//! does not cancel.

use std::fmt;

use crate::compensated_sum::CompensatedSum;
use crate::model::DruckerStiffness;
use crate::{Hyperelastic, Mode, Parameter};

/// W's partial derivatives with respect to I1 and I2 at one state, Pa.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InvariantSlopes {
    pub w1: f64,
    pub w2: f64,
    pub w11: f64,
    pub w12: f64,
    pub w22: f64,
}

/// A strain energy W(I1, I2): a family implements this and is a
/// [`Hyperelastic`] material through the blanket impl below, with stresses
/// and Drucker stiffness in closed form from the invariant derivatives.
pub trait InvariantEnergy: fmt::Debug + Send + Sync {
    /// W(I1, I2), Pa.
    fn energy_at(&self, i1: f64, i2: f64) -> f64;
    /// First and second partial derivatives of W, Pa.
    fn slopes_at(&self, i1: f64, i2: f64) -> InvariantSlopes;
    /// The family's name in the `material` table.
    fn family_name(&self) -> &'static str;
    /// Initial shear modulus μ0, Pa.
    fn initial_shear_modulus_pa(&self) -> f64;
    /// The parameters in SI units, in the order of the `material` table.
    fn named_parameters(&self) -> Vec<Parameter>;
}

impl<T: InvariantEnergy> Hyperelastic for T {
    fn family(&self) -> &'static str {
        self.family_name()
    }

    fn shear_modulus_pa(&self) -> f64 {
        self.initial_shear_modulus_pa()
    }

    fn energy_pa(&self, stretches: [f64; 3]) -> f64 {
        let (i1, i2) = invariants(stretches);
        self.energy_at(i1, i2)
    }

    fn nominal_stress_pa(&self, mode: Mode, stretch: f64) -> f64 {
        nominal_stress(self, mode, stretch)
    }

    fn nominal_stress_slope_pa(&self, mode: Mode, stretch: f64) -> f64 {
        nominal_stress_slope(self, mode, stretch)
    }

    fn parameters(&self) -> Vec<Parameter> {
        self.named_parameters()
    }

    fn log_strain_hessian_pa(&self, stretches: [f64; 3]) -> [[f64; 2]; 2] {
        log_strain_hessian(self, stretches)
    }

    fn drucker_stiffness(&self, stretches: [f64; 3]) -> DruckerStiffness {
        drucker_stiffness(self, stretches)
    }
}

/// I1 = Σ λ², I2 = Σ λ⁻².
pub fn invariants([l1, l2, l3]: [f64; 3]) -> (f64, f64) {
    (
        l1 * l1 + l2 * l2 + l3 * l3,
        1.0 / (l1 * l1) + 1.0 / (l2 * l2) + 1.0 / (l3 * l3),
    )
}

/// (I, dI/dλ, d²I/dλ²) for I1 and I2 along a test path.
fn path_invariants(mode: Mode, l: f64) -> ([f64; 3], [f64; 3]) {
    match mode {
        // (λ, λ^-½, λ^-½)
        Mode::Uniaxial => (
            [
                l * l + 2.0 / l,
                2.0 * l - 2.0 / (l * l),
                2.0 + 4.0 / l.powi(3),
            ],
            [
                2.0 * l + 1.0 / (l * l),
                2.0 - 2.0 / l.powi(3),
                6.0 / l.powi(4),
            ],
        ),
        // (λ, 1, 1/λ): I1 = I2
        Mode::Planar => {
            let i = [
                l * l + 1.0 + 1.0 / (l * l),
                2.0 * l - 2.0 / l.powi(3),
                2.0 + 6.0 / l.powi(4),
            ];
            (i, i)
        }
        // (λ, λ, λ^-2)
        Mode::Equibiaxial => (
            [
                2.0 * l * l + l.powi(-4),
                4.0 * l - 4.0 * l.powi(-5),
                4.0 + 20.0 * l.powi(-6),
            ],
            [
                2.0 / (l * l) + l.powi(4),
                -4.0 / l.powi(3) + 4.0 * l.powi(3),
                12.0 / l.powi(4) + 12.0 * l * l,
            ],
        ),
    }
}

/// Nominal stress T = dW/dλ / k along `mode`, Pa.
pub fn nominal_stress(energy: &dyn InvariantEnergy, mode: Mode, stretch: f64) -> f64 {
    let ([i1, d1, _], [i2, d2, _]) = path_invariants(mode, stretch);
    let s = energy.slopes_at(i1, i2);
    (s.w1 * d1 + s.w2 * d2) / mode.loaded_directions()
}

/// dT/dλ along `mode`, Pa.
pub fn nominal_stress_slope(energy: &dyn InvariantEnergy, mode: Mode, stretch: f64) -> f64 {
    let ([i1, d1, dd1], [i2, d2, dd2]) = path_invariants(mode, stretch);
    let s = energy.slopes_at(i1, i2);
    (s.w11 * d1 * d1 + 2.0 * s.w12 * d1 * d2 + s.w22 * d2 * d2 + s.w1 * dd1 + s.w2 * dd2)
        / mode.loaded_directions()
}

/// The Hessian of Ŵ(ε1, ε2) = W(e^ε1, e^ε2, e^(−ε1−ε2)), Pa.
pub fn log_strain_hessian(energy: &dyn InvariantEnergy, stretches: [f64; 3]) -> [[f64; 2]; 2] {
    let [l1, l2, l3] = stretches;
    let (i1, i2) = invariants(stretches);
    let s = energy.slopes_at(i1, i2);
    let (a1, a2, a3) = (l1 * l1, l2 * l2, l3 * l3);
    let (b1, b2, b3) = (1.0 / a1, 1.0 / a2, 1.0 / a3);
    // ∂I/∂ε_j and ∂²I/∂ε_j∂ε_k with ε3 = −ε1 − ε2.
    let g1 = [2.0 * (a1 - a3), 2.0 * (a2 - a3)];
    let g2 = [2.0 * (b3 - b1), 2.0 * (b3 - b2)];
    let h1 = [[4.0 * (a1 + a3), 4.0 * a3], [4.0 * a3, 4.0 * (a2 + a3)]];
    let h2 = [[4.0 * (b1 + b3), 4.0 * b3], [4.0 * b3, 4.0 * (b2 + b3)]];
    let mut h = [[0.0; 2]; 2];
    for j in 0..2 {
        for k in 0..2 {
            h[j][k] = s.w1 * h1[j][k]
                + s.w2 * h2[j][k]
                + s.w11 * g1[j] * g1[k]
                + s.w12 * (g1[j] * g2[k] + g2[j] * g1[k])
                + s.w22 * g2[j] * g2[k];
        }
    }
    h
}

/// The trace and determinant of [`log_strain_hessian`] in a form without
/// cancellation for a stable material.
///
/// Derivation. Write a_j = λ_j², b_j = λ_j⁻². The Hessian is H = M + G with
/// M = W1 ∂²I1 + W2 ∂²I2 = 2 [[s1 + s3, s3], [s3, s2 + s3]],
/// s_j = 2 (W1 a_j + W2 b_j) (the Ogden form of [`crate::Ogden`] with
/// α = ±2), and G = P W'' Pᵀ, where P = [∇I1 ∇I2] has the columns
/// ∇I1 = 2 (a1 − a3, a2 − a3), ∇I2 = 2 (b3 − b1, b3 − b2) and
/// W'' = [[W11, W12], [W12, W22]]. For 2 × 2 matrices
/// det (M + G) = det M + tr (adj M · G) + det G, and
///
/// - det M = 4 (s1 s2 + s1 s3 + s2 s3);
/// - xᵀ adj M y = 2 [s3 (x1 − x2)(y1 − y2) + s2 x1 y1 + s1 x2 y2], so
///   tr (adj M · G) = Σ_kl W''_kl ∇I_kᵀ adj M ∇I_l = 8 Σ_k s_k q_k with
///   q_k = W11 d_k² + 2 W12 d_k e_k + W22 e_k², where for k = 1, 2, 3 the
///   pair (i, j) = (2, 3), (1, 3), (1, 2) and d_k = a_i − a_j,
///   e_k = b_j − b_i = d_k b_i b_j;
/// - det P = 4 d1 d2 d3 b1 b2 b3 (up to sign), so
///   det G = 16 (d1 d2 d3 b1 b2 b3)² (W11 W22 − W12²);
/// - trace H = 2 (s1 + s2 + 2 s3) + 4 (q1 + q2).
///
/// If W1, W2 ≥ 0 and W'' is positive semi-definite every term is ≥ 0, so
/// nothing cancels. H11 H22 − H12² instead cancels the part that all
/// three entries share (4 W1 λ3² + W11 |∇I1|² ... in equibiaxial
/// compression, where ∇I1 ≈ −2 λ3² (1, 1)) and keeps only ~ s1 s3, losing
/// about log10 (λ3/λ1)² digits: 6 at λ = 0.1 (measured for Yeoh and
/// Arruda–Boyce: 4e-10 relative, against 1e-16 expanded). The d_k are
/// formed as (λ_i − λ_j)(λ_i + λ_j), accurate to a few ulps even for close
/// stretches.
/// What remains is the rounding of W's derivatives by the family (a few u
/// relative for positive coefficients) and, for a material with W1 < 0 or
/// an indefinite W'', the cancellation between genuinely opposite terms.
pub fn drucker_stiffness(energy: &dyn InvariantEnergy, stretches: [f64; 3]) -> DruckerStiffness {
    let (i1, i2) = invariants(stretches);
    let w = energy.slopes_at(i1, i2);
    let a = stretches.map(|l| l * l);
    let b = a.map(|a| 1.0 / a);
    let s = [0, 1, 2].map(|j| {
        let mut s = CompensatedSum::default();
        s.add_product(2.0 * w.w1, a[j]);
        s.add_product(2.0 * w.w2, b[j]);
        s.value()
    });
    let q = [[1, 2], [0, 2], [0, 1]].map(|[i, j]| {
        let d = (stretches[i] - stretches[j]) * (stretches[i] + stretches[j]);
        let e = d * b[i] * b[j];
        (d, w.w11 * d * d + 2.0 * w.w12 * d * e + w.w22 * e * e)
    });
    let mut determinant = CompensatedSum::default();
    determinant.add_product(4.0 * s[0], s[1]);
    determinant.add_product(4.0 * s[0], s[2]);
    determinant.add_product(4.0 * s[1], s[2]);
    for k in 0..3 {
        determinant.add_product(8.0 * s[k], q[k].1);
    }
    let p = q[0].0 * q[1].0 * q[2].0 * b[0] * b[1] * b[2];
    let mut w_det = CompensatedSum::default();
    w_det.add_product(w.w11, w.w22);
    w_det.add_product(-w.w12, w.w12);
    determinant.add_product(16.0 * p * p, w_det.value());
    let mut trace = CompensatedSum::default();
    for x in [
        2.0 * s[0],
        2.0 * s[1],
        4.0 * s[2],
        4.0 * q[0].1,
        4.0 * q[1].1,
    ] {
        trace.add(x);
    }
    DruckerStiffness {
        trace_pa: trace.value(),
        determinant_pa2: determinant.value(),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::model::DruckerStiffness;
    use crate::{ArrudaBoyce, MooneyRivlin, Yeoh};

    /// A test energy with every first and second derivative non-zero
    /// (W = c1 x + c2 y + c11 x² + c12 x y + c22 y², x = I1 − 3,
    /// y = I2 − 3), which no shipped family has.
    #[derive(Debug)]
    struct Quadratic([f64; 5]);

    impl InvariantEnergy for Quadratic {
        fn energy_at(&self, i1: f64, i2: f64) -> f64 {
            let [c1, c2, c11, c12, c22] = self.0;
            let (x, y) = (i1 - 3.0, i2 - 3.0);
            c1 * x + c2 * y + c11 * x * x + c12 * x * y + c22 * y * y
        }
        fn slopes_at(&self, i1: f64, i2: f64) -> InvariantSlopes {
            let [c1, c2, c11, c12, c22] = self.0;
            let (x, y) = (i1 - 3.0, i2 - 3.0);
            InvariantSlopes {
                w1: c1 + 2.0 * c11 * x + c12 * y,
                w2: c2 + c12 * x + 2.0 * c22 * y,
                w11: 2.0 * c11,
                w12: c12,
                w22: 2.0 * c22,
            }
        }
        fn family_name(&self) -> &'static str {
            "quadratic"
        }
        fn initial_shear_modulus_pa(&self) -> f64 {
            2.0 * (self.0[0] + self.0[1])
        }
        fn named_parameters(&self) -> Vec<Parameter> {
            Vec::new()
        }
    }

    #[test]
    fn expanded_determinant_is_the_hessians() {
        // At moderate stretches H11 H22 − H12² is accurate, so the
        // expansion must agree with it: every W derivative non-zero, of
        // either sign (indefinite W'' and negative W2 included), on the
        // test paths and off them.
        let energies = [
            Quadratic([1e5, 2e4, 3e3, 1e3, 5e2]),
            Quadratic([1e5, -2e4, -3e3, 4e3, 5e2]),
            Quadratic([-1e4, 3e4, 2e3, -5e3, -1e3]),
        ];
        let mut states: Vec<[f64; 3]> = Mode::ALL
            .iter()
            .flat_map(|&mode| [0.5, 0.8, 1.0, 1.3, 2.0].map(|l| mode.stretches(l)))
            .collect();
        states.push([1.3, 0.8, 1.0 / 1.04]);
        states.push([0.7, 1.6, 1.0 / 1.12]);
        for energy in &energies {
            for &stretches in &states {
                let h = log_strain_hessian(energy, stretches);
                let naive = DruckerStiffness::from_hessian(h);
                let expanded = drucker_stiffness(energy, stretches);
                let scale = h[0][0].abs().max(h[1][1].abs()).max(h[0][1].abs());
                assert!(
                    (expanded.determinant_pa2 - naive.determinant_pa2).abs()
                        <= 1e-12 * scale * scale,
                    "{energy:?} {stretches:?}: {expanded:?} vs {naive:?}"
                );
                assert!(
                    (expanded.trace_pa - naive.trace_pa).abs() <= 1e-12 * scale,
                    "{energy:?} {stretches:?}: {expanded:?} vs {naive:?}"
                );
            }
        }
    }

    /// Drucker determinants and traces at 50 significant digits: mpmath
    /// 1.4.1 (`mp.dps = 50`), the stretches as `Mode::stretches` rounds
    /// them and the coefficients as the families round them (Arruda–Boyce's
    /// μ C_i / λm^(2i−2) formed in f64 as in `coefficients`), taken exactly;
    /// W1, W2, W11 from the closed forms, H from ∇I and ∂²I as in
    /// [`log_strain_hessian`], det = H11 H22 − H12² and trace = H11 + H22 in
    /// that precision (not the expanded form under test). Columns: mode,
    /// λ, det H (Pa²), trace H (Pa).
    type Reference = [(Mode, f64, f64, f64)];

    /// Yeoh C10 = 1.9e5, C20 = 4e3, C30 = 50 Pa.
    #[rustfmt::skip]
    const YEOH_REFERENCE: [(Mode, f64, f64, f64); 8] = [
        (Mode::Uniaxial, 0.1, 373475027382134.3, 49583223.88179999),
        (Mode::Uniaxial, 10.0, 4650916150738146.0, 2440200817.6),
        (Mode::Planar, 0.1, 2.4158374514997252e16, 4903903709.9818),
        (Mode::Planar, 10.0, 2.4158374514997252e16, 2471810125.6636),
        (Mode::Equibiaxial, 0.1, 2.1771164526740478e24, 3611379393695802.0),
        (Mode::Equibiaxial, 0.2, 9.347637067629552e18, 924213226225.2537),
        (Mode::Equibiaxial, 1.5, 4489796728398.493, 4281385.755897644),
        (Mode::Equibiaxial, 10.0, 2.550244254535769e19, 11437883101.887136),
    ];

    /// Arruda–Boyce μ = 2.7e5 Pa, λm = 2.8.
    #[rustfmt::skip]
    const ARRUDA_BOYCE_REFERENCE: [(Mode, f64, f64, f64); 8] = [
        (Mode::Uniaxial, 0.1, 480886529707079.8, 52279898.31541007),
        (Mode::Uniaxial, 10.0, 1.9173693458808735e18, 67109497734.7953),
        (Mode::Planar, 0.1, 1.0310530562415804e19, 136694819967.51442),
        (Mode::Planar, 10.0, 1.0310530562415804e19, 68961342509.1113),
        (Mode::Equibiaxial, 0.1, 1.2171137022154197e35, 1.102982753288164e21),
        (Mode::Equibiaxial, 0.2, 7.53412486817411e24, 1080897945993452.2),
        (Mode::Equibiaxial, 1.5, 2534548388787.1904, 3211911.070097523),
        (Mode::Equibiaxial, 10.0, 1.9141549390364916e23, 1164088075473.6465),
    ];

    /// Mooney–Rivlin C10 = 1.8e5, C01 = 2e4 Pa.
    #[rustfmt::skip]
    const MOONEY_RIVLIN_REFERENCE: [(Mode, f64, f64, f64); 8] = [
        (Mode::Uniaxial, 0.1, 167387059199999.94, 29631199.999999996),
        (Mode::Uniaxial, 10.0, 126329779199999.98, 74616800.0),
        (Mode::Planar, 0.1, 640531205760000.0, 152808800.0),
        (Mode::Planar, 10.0, 640531205760000.0, 88815200.0),
        (Mode::Equibiaxial, 0.1, 1.1536779537995515e17, 14416014415.999996),
        (Mode::Equibiaxial, 0.2, 1830036548812799.2, 904057855.9999998),
        (Mode::Equibiaxial, 1.5, 4552777777777.778, 4405555.555555556),
        (Mode::Equibiaxial, 10.0, 1.203854055687552e17, 1744001744.0),
    ];

    #[test]
    fn expanded_determinant_matches_high_precision() {
        // Positive coefficients: every term of the expansion is positive,
        // so only the roundings of W's derivatives and of the stretches'
        // squares remain, a few u; 1e-14 allows for them.
        let cases: [(&dyn InvariantEnergy, &Reference); 3] = [
            (&Yeoh::new(1.9e5, 4.0e3, 50.0).unwrap(), &YEOH_REFERENCE),
            (
                &ArrudaBoyce::new(2.7e5, 2.8).unwrap(),
                &ARRUDA_BOYCE_REFERENCE,
            ),
            (
                &MooneyRivlin::new(1.8e5, 2.0e4).unwrap(),
                &MOONEY_RIVLIN_REFERENCE,
            ),
        ];
        for (energy, reference) in cases {
            for &(mode, stretch, det, trace) in reference {
                let stretches = mode.stretches(stretch);
                let d = drucker_stiffness(energy, stretches);
                let naive = DruckerStiffness::from_hessian(log_strain_hessian(energy, stretches));
                let error = (d.determinant_pa2 / det - 1.0).abs();
                println!(
                    "{} {mode} λ={stretch}: det rel. error {error:.1e} (from the Hessian {:.1e})",
                    energy.family_name(),
                    (naive.determinant_pa2 / det - 1.0).abs()
                );
                assert!(
                    error < 1e-14,
                    "{} {mode} λ={stretch}: {d:?} vs {det}",
                    energy.family_name()
                );
                assert!(
                    (d.trace_pa / trace - 1.0).abs() < 1e-14,
                    "{} {mode} λ={stretch}: {d:?} vs {trace}",
                    energy.family_name()
                );
            }
        }
    }

    /// Checks a model's path stresses and slopes against central
    /// differences of its energy, and its Drucker Hessian against second
    /// differences of the energy in log strains.
    pub(crate) fn check_against_energy(m: &dyn crate::Hyperelastic) {
        for mode in Mode::ALL {
            for stretch in [0.4, 0.8, 1.0, 1.3, 2.0, 3.0] {
                let h = 1e-6 * stretch;
                let w = |l: f64| m.energy_pa(mode.stretches(l));
                let fd = (w(stretch + h) - w(stretch - h)) / (2.0 * h) / mode.loaded_directions();
                let exact = m.nominal_stress_pa(mode, stretch);
                let scale = m.shear_modulus_pa() + exact.abs();
                assert!(
                    (exact - fd).abs() <= 1e-7 * scale,
                    "{} {mode} λ={stretch}: {exact} vs {fd}",
                    m.family()
                );
                let slope_fd = (m.nominal_stress_pa(mode, stretch + h)
                    - m.nominal_stress_pa(mode, stretch - h))
                    / (2.0 * h);
                let slope = m.nominal_stress_slope_pa(mode, stretch);
                assert!(
                    (slope - slope_fd).abs() <= 1e-6 * (slope.abs() + m.shear_modulus_pa()),
                    "{} {mode} λ={stretch}: slope {slope} vs {slope_fd}",
                    m.family()
                );
                let hess = m.log_strain_hessian_pa(mode.stretches(stretch));
                let fd_hess =
                    crate::model::log_strain_hessian_by_differences(m, mode.stretches(stretch));
                for j in 0..2 {
                    for k in 0..2 {
                        assert!(
                            (hess[j][k] - fd_hess[j][k]).abs()
                                <= 1e-5 * (hess[j][k].abs() + m.shear_modulus_pa()),
                            "{} {mode} λ={stretch}: H[{j}][{k}] {} vs {}",
                            m.family(),
                            hess[j][k],
                            fd_hess[j][k]
                        );
                    }
                }
            }
        }
    }

    /// Small-strain limit shared by every family: UT slope 3 μ0, PT 4 μ0,
    /// BT 6 μ0 at λ = 1, and zero stress there.
    pub(crate) fn check_small_strain(m: &dyn crate::Hyperelastic) {
        let mu0 = m.shear_modulus_pa();
        for (mode, factor) in [
            (Mode::Uniaxial, 3.0),
            (Mode::Planar, 4.0),
            (Mode::Equibiaxial, 6.0),
        ] {
            let slope = m.nominal_stress_slope_pa(mode, 1.0);
            assert!(
                (slope / mu0 - factor).abs() < 1e-9,
                "{} {mode}: slope/μ0 = {}",
                m.family(),
                slope / mu0
            );
            assert!(m.nominal_stress_pa(mode, 1.0).abs() < 1e-9 * mu0);
        }
    }
}
