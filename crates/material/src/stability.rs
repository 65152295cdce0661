//! Drucker stability of an incompressible hyperelastic model along the
//! three test paths, as Abaqus checks a fitted material (Abaqus Analysis
//! Guide, "Hyperelastic behavior of rubberlike materials", stability
//! checks: uniaxial, equibiaxial and planar, tension and compression,
//! 0.1 ≤ λ ≤ 10).
//!
//! What is checked: Drucker's condition dσ : dε > 0 for every increment of
//! logarithmic strain that keeps the volume (dε1 + dε2 + dε3 = 0). With
//! Ŵ(ε1, ε2) = W(e^ε1, e^ε2, e^(−ε1−ε2)) one has σ1 − σ3 = ∂Ŵ/∂ε1 and
//! σ2 − σ3 = ∂Ŵ/∂ε2, so dσ : dε = dεᵀ H dε with H the Hessian of Ŵ
//! ([`Hyperelastic::log_strain_hessian_pa`]): the condition is that H is
//! positive definite, trace H > 0 and det H > 0 (Abaqus' D11 + D22 > 0 and
//! det D > 0 for the same 2 × 2 matrix). This covers every volume-keeping
//! perturbation, not only the one along the test path: in BT it fails where
//! the true stress λT stops rising, a little after the nominal stress T
//! peaks.
//!
//! The determinant is not formed as H11 H22 − H12²: at large stretch powers
//! the three entries share one huge term (for Ogden 2 Σ μ_i λ3^α_i, 10²⁹
//! times the rest in equibiaxial compression at λ = 0.125 with α = 16) that
//! cancels in the difference and leaves 0 or noise, so fits that are stable
//! (an Ogden model with every μ_i ≥ 0 is stable at every stretch) were
//! reported unstable. Each family gives the trace and determinant in an
//! expanded form whose terms do not cancel for a stable material
//! ([`Hyperelastic::drucker_stiffness`]), summed with compensation; how
//! accurate that is is said there.
//!
//! Beside it, the interval where the nominal stress rises (dT/dλ > 0) is
//! reported: a load-controlled test is unstable where T falls, and in BT it
//! bounds where the paper's φ is invertible. The two differ: for the paper's
//! Table 1 material T_BT peaks at λ ≈ 1.46 while the Drucker condition holds
//! in BT tension up to λ ≈ 4.4; in equibiaxial compression (uniaxial
//! tension at λ^-2) the Drucker condition fails below λ ≈ 0.56 through the
//! in-plane shear perturbation, although T still rises there.
//!
//! The range reported per mode is the interval of stretches around λ = 1
//! where a condition holds, searched on a geometric grid of
//! [`GRID_POINTS`] stretches each side (an unstable window narrower than one
//! grid step, 0.12 % in stretch, could be missed) and refined by bisection.

use crate::{Hyperelastic, Mode};

/// The stretch window of the check.
pub const LAMBDA_LOW: f64 = 0.1;
pub const LAMBDA_HIGH: f64 = 10.0;
pub const GRID_POINTS: usize = 2000;

/// Where a model is Drucker stable, and where its nominal stress rises, in
/// one test mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityRange {
    pub mode: Mode,
    /// Smallest stretch of the Drucker-stable interval containing λ = 1
    /// ([`LAMBDA_LOW`] if stable all the way).
    pub lambda_min: f64,
    /// Largest stretch of that interval ([`LAMBDA_HIGH`] if stable all the way).
    pub lambda_max: f64,
    /// The interval around λ = 1 where the nominal stress rises with
    /// stretch (dT/dλ > 0): a load-controlled test is stable there, and for
    /// BT it is where the paper's φ is invertible. It is narrower than the
    /// Drucker interval where T peaks while λT still rises.
    pub monotonic_min: f64,
    pub monotonic_max: f64,
    /// False if the model is not even stable at λ = 1 (μ0 ≤ 0); the ranges
    /// are then the single point λ = 1.
    pub stable_at_rest: bool,
}

impl StabilityRange {
    pub fn stable_everywhere(&self) -> bool {
        self.stable_at_rest && self.lambda_min <= LAMBDA_LOW && self.lambda_max >= LAMBDA_HIGH
    }

    /// `lambda_min` is the search range's edge (λ = 0.1), not a found
    /// instability.
    pub fn lambda_min_at_edge(&self) -> bool {
        self.stable_at_rest && self.lambda_min <= LAMBDA_LOW
    }

    /// `lambda_max` is the search range's edge (λ = 10).
    pub fn lambda_max_at_edge(&self) -> bool {
        self.stable_at_rest && self.lambda_max >= LAMBDA_HIGH
    }

    /// A sentence for the report: where the model becomes unstable.
    pub fn describe(&self) -> String {
        if !self.stable_at_rest {
            return "unstable at zero strain".into();
        }
        // A limit at the search range's edge is not a finding: say so.
        let mut parts = vec![
            if self.lambda_min_at_edge() {
                format!("Drucker-stable down to the edge of the search range (λ = {LAMBDA_LOW})")
            } else {
                format!("Drucker-unstable below λ = {:.4}", self.lambda_min)
            },
            if self.lambda_max_at_edge() {
                format!("stable up to the edge of the search range (λ = {LAMBDA_HIGH})")
            } else {
                format!("Drucker-unstable above λ = {:.4}", self.lambda_max)
            },
        ];
        if self.monotonic_min > LAMBDA_LOW {
            parts.push(format!(
                "nominal stress falls below λ = {:.4}",
                self.monotonic_min
            ));
        }
        if self.monotonic_max < LAMBDA_HIGH {
            parts.push(format!(
                "nominal stress peaks at λ = {:.4}",
                self.monotonic_max
            ));
        }
        parts.join("; ")
    }
}

/// Drucker's condition at loading stretch λ of `mode`: the log-strain
/// Hessian is positive definite (from its trace and determinant in the
/// family's expanded form, [`Hyperelastic::drucker_stiffness`]).
pub fn is_stable(model: &dyn Hyperelastic, mode: Mode, stretch: f64) -> bool {
    model
        .drucker_stiffness(mode.stretches(stretch))
        .is_positive_definite()
}

/// The stable interval around λ = 1 in `mode`, for Drucker's condition and
/// for a rising nominal stress.
pub fn stability_range(model: &dyn Hyperelastic, mode: Mode) -> StabilityRange {
    let drucker = |l: f64| is_stable(model, mode, l);
    let rising = |l: f64| model.nominal_stress_slope_pa(mode, l) > 0.0;
    if !drucker(1.0) {
        return StabilityRange {
            mode,
            lambda_min: 1.0,
            lambda_max: 1.0,
            monotonic_min: 1.0,
            monotonic_max: 1.0,
            stable_at_rest: false,
        };
    }
    StabilityRange {
        mode,
        lambda_min: edge(&drucker, LAMBDA_LOW),
        lambda_max: edge(&drucker, LAMBDA_HIGH),
        monotonic_min: edge(&rising, LAMBDA_LOW),
        monotonic_max: edge(&rising, LAMBDA_HIGH),
        stable_at_rest: true,
    }
}

/// The last stretch from λ = 1 towards `limit` where `holds` is still
/// true: a geometric scan, then bisection of the first failure.
fn edge(holds: &dyn Fn(f64) -> bool, limit: f64) -> f64 {
    let log_limit = limit.ln();
    let mut previous = 1.0;
    for k in 1..=GRID_POINTS {
        let stretch = (log_limit * k as f64 / GRID_POINTS as f64).exp();
        if !holds(stretch) {
            let (mut good, mut bad) = (previous, stretch);
            for _ in 0..60 {
                let mid = (good * bad).sqrt();
                if holds(mid) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            return good;
        }
        previous = stretch;
    }
    limit
}

/// [`stability_range`] for UT, PT and BT.
pub fn stability_ranges(model: &dyn Hyperelastic) -> Vec<StabilityRange> {
    Mode::ALL
        .iter()
        .map(|&mode| stability_range(model, mode))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::DruckerStiffness;
    use crate::presets::paper_epdm;
    use crate::{MooneyRivlin, NeoHookean, Ogden};
    use proptest::prelude::*;

    #[test]
    fn paper_epdm_nominal_stress_peaks_in_biaxial_tension_and_rises_in_compression() {
        let m = paper_epdm();
        let bt = stability_range(&m, Mode::Equibiaxial);
        assert!(bt.stable_at_rest);
        // φ = T_BT peaks near λ ≈ 1.45 (the paper's ε ≈ 0.5) ...
        assert!((1.4..1.5).contains(&bt.monotonic_max), "{bt:?}");
        let peak = crate::ContactLaw::new(std::sync::Arc::new(m.clone()))
            .unwrap()
            .range()
            .eps_max
            + 1.0;
        assert!(
            (bt.monotonic_max - peak).abs() < 1e-3,
            "{} vs {peak}",
            bt.monotonic_max
        );
        // ... and rises all the way down to λ = 0.1 in compression.
        assert_eq!(bt.monotonic_min, LAMBDA_LOW, "{bt:?}");
        assert!(
            bt.describe().contains("nominal stress peaks at λ = 1.4"),
            "{}",
            bt.describe()
        );
        // φ falls until λ ≈ 2, then rises again.
        assert!(m.nominal_stress_slope_pa(Mode::Equibiaxial, 1.9) < 0.0);
        assert!(m.nominal_stress_slope_pa(Mode::Equibiaxial, 2.05) > 0.0);
    }

    #[test]
    fn paper_epdm_drucker_limits_agree_across_modes() {
        let m = paper_epdm();
        let [ut, _, bt] =
            [Mode::Uniaxial, Mode::Planar, Mode::Equibiaxial].map(|mode| stability_range(&m, mode));
        // Abaqus' check (true stress against log strain) holds past the
        // nominal-stress peak: λT keeps rising after T peaks.
        assert!(bt.lambda_max > bt.monotonic_max + 1.0, "{bt:?}");
        // In equibiaxial compression the in-plane shear perturbation fails
        // first; that state is uniaxial tension at λ^-2, so the UT limit in
        // tension must be the BT limit in compression to the power −2.
        assert!((4.3..4.5).contains(&bt.lambda_max), "{bt:?}");
        assert!((0.55..0.57).contains(&bt.lambda_min), "{bt:?}");
        // Stress there: about −15 MPa, far beyond contact stresses.
        let s = m.nominal_stress_pa(Mode::Equibiaxial, bt.lambda_min);
        assert!((-16e6..-14e6).contains(&s), "{s}");
        let expected = bt.lambda_min.powi(-2);
        assert!(
            (ut.lambda_max / expected - 1.0).abs() < 1e-6,
            "{ut:?} vs {expected}"
        );
        // And BT tension at λ is UT compression at λ^-2 (below 0.1 here).
        assert!(bt.lambda_max.powi(-2) < LAMBDA_LOW && ut.lambda_min == LAMBDA_LOW);
        // Just inside and outside each edge.
        for edge in [bt.lambda_min, bt.lambda_max] {
            let inside = if edge < 1.0 {
                edge * 1.001
            } else {
                edge * 0.999
            };
            let outside = if edge < 1.0 {
                edge * 0.999
            } else {
                edge * 1.001
            };
            assert!(is_stable(&m, Mode::Equibiaxial, inside));
            assert!(!is_stable(&m, Mode::Equibiaxial, outside));
        }
    }

    #[test]
    fn neo_hookean_and_positive_mooney_rivlin_are_stable_everywhere() {
        for m in [
            Box::new(NeoHookean::new(0.2e6).unwrap()) as Box<dyn Hyperelastic>,
            Box::new(MooneyRivlin::new(0.2e6, 0.05e6).unwrap()),
        ] {
            for r in stability_ranges(m.as_ref()) {
                assert!(r.stable_everywhere(), "{} {r:?}", m.family());
            }
        }
    }

    #[test]
    fn negative_c01_destabilises_mooney_rivlin_in_biaxial_tension() {
        // Mooney–Rivlin with C01 < 0: in BT along the path λT ∝
        // (λ² − λ^-4)(C10 + λ² C01) must stop rising once λ² |C01| ~ C10.
        let m = MooneyRivlin::new(0.2e6, -0.02e6).unwrap();
        let bt = stability_range(&m, Mode::Equibiaxial);
        assert!(bt.lambda_max < 3.0, "{bt:?}");
        let just_past = bt.lambda_max * 1.01;
        let [[h11, h12], [_, h22]] =
            m.log_strain_hessian_pa(Mode::Equibiaxial.stretches(just_past));
        assert!(h11 <= 0.0 || h11 * h22 - h12 * h12 <= 0.0);
        assert!(bt.describe().contains("Drucker-unstable above"));
    }

    /// Reference determinants and traces of the Drucker stiffness, computed
    /// at 50 significant digits with mpmath 1.4.1 (`mp.dps = 50`, Python
    /// 3): every μ_i, α_i and stretch taken as the exact binary value of
    /// the f64 used here (the stretches as `Mode::stretches` rounds them),
    /// s_j = fsum(μ_i · power(λ_j, α_i)), H = 2 [[s1 + s3, s3], [s3, s2 +
    /// s3]], det = H11 H22 − H12² and trace = H11 + H22 formed in that
    /// precision from the entries (not from the expanded form under test).
    /// Columns: mode, λ, det H (Pa²), trace H (Pa).
    type Reference = [(Mode, f64, f64, f64)];

    /// The paper's Table 1 (`paper_epdm`), μ_i of ±5·10⁹ Pa.
    #[rustfmt::skip]
    const EPDM_REFERENCE: [(Mode, f64, f64, f64); 15] = [
        (Mode::Uniaxial, 0.1, 204413119624587.28, 56713228.659694314),
        (Mode::Uniaxial, 0.5, 12755404358767.582, 11900789.200610612),
        (Mode::Uniaxial, 2.0, 14269792849140.156, 8510740.06215048),
        (Mode::Uniaxial, 10.0, -2446465643896922.0, 1147638849.5298655),
        (Mode::Planar, 0.1, -2137945376032757.2, 2299817253.1547465),
        (Mode::Planar, 0.5, 10362601713894.074, 11104118.492603354),
        (Mode::Planar, 4.0, 181131427048658.34, 60766477.21633649),
        (Mode::Planar, 10.0, -2137945376032757.2, 1143567306.040446),
        (Mode::Equibiaxial, 0.1, -1.3432116554562263e18, 247779360697.78424),
        (Mode::Equibiaxial, 0.125, -1.5796049384845907e17, 115149294970.72437),
        (Mode::Equibiaxial, 0.2, 4189062230743487.5, 19276255519.908684),
        (Mode::Equibiaxial, 0.5, -61681098148921.055, 115038240.71645747),
        (Mode::Equibiaxial, 1.5, 8892460076439.719, 6255414.79086916),
        (Mode::Equibiaxial, 4.0, 253876281564170.22, 62426017.790863805),
        (Mode::Equibiaxial, 10.0, 2.6531910679235226e17, 1381375126.511481),
    ];

    /// An unconstrained 6-term Ogden fit to Treloar's (1944) data whose μ_i
    /// of ±10¹⁶ Pa cancel to μ0 ≈ 4.2·10⁵ Pa.
    fn treloar_ogden6() -> Ogden {
        Ogden::new(
            vec![
                11644.642748244894,
                932878840177834.9,
                -7379858483337793.0,
                19589279681462.47,
                -5464367512328935.0,
                1.1891757876216566e16,
            ],
            vec![
                -1.9553822299864672,
                3.6788927432418435,
                3.68273056333575,
                3.7037879229018342,
                3.6860731520018084,
                3.6845328918646447,
            ],
        )
        .unwrap()
    }

    #[rustfmt::skip]
    const TRELOAR_OGDEN6_REFERENCE: [(Mode, f64, f64, f64); 14] = [
        (Mode::Uniaxial, 0.1, 66363936892422.65, 21024550.65255272),
        (Mode::Uniaxial, 0.5, 2306156960325.5996, 3898197.919916594),
        (Mode::Uniaxial, 2.0, 2619607708686.0176, 3696135.700558903),
        (Mode::Uniaxial, 10.0, 1476364949788220.0, 2066884394.041599),
        (Mode::Planar, 0.1, 6101014977400503.0, 4134577441.665391),
        (Mode::Planar, 0.5, 2760725208998.743, 5109775.080916102),
        (Mode::Planar, 4.0, 15409762447532.924, 13509856.870237214),
        (Mode::Planar, 10.0, 6101014977400503.0, 2070875857.9644723),
        (Mode::Equibiaxial, 0.1, 3.9523578253507717e21, 1872352508797101.5),
        (Mode::Equibiaxial, 0.125, 2.821738618894011e20, 205237334179670.2),
        (Mode::Equibiaxial, 0.2, 8.118092402265642e17, 1370534915647.1072),
        (Mode::Equibiaxial, 0.5, 9860268109035.988, 24424755.642486572),
        (Mode::Equibiaxial, 2.0, 5391646095356.618, 4724134.183917052),
        (Mode::Equibiaxial, 10.0, 5.051085839882306e18, 4510896864.751119),
    ];

    /// An Ogden-4 with every μ_i ≥ 0 (so stable at every stretch) and an
    /// α = 16 term: in equibiaxial compression λ3^16 dwarfs everything else.
    fn positive_ogden4() -> Ogden {
        Ogden::new(vec![2.8e5, 3.0e4, 5.0, 1.0e3], vec![1.5, 5.0, 16.0, -3.0]).unwrap()
    }

    #[rustfmt::skip]
    const POSITIVE_OGDEN4_REFERENCE: [(Mode, f64, f64, f64); 10] = [
        (Mode::Uniaxial, 0.1, 1.0488597949674682e18, 3068386231.2377815),
        (Mode::Uniaxial, 10.0, 3.2603789327079018e22, 1.0000000601819781e17),
        (Mode::Planar, 0.1, 2.6397195137601157e23, 2.000000120380572e17),
        (Mode::Planar, 10.0, 2.6397195137601157e23, 1.0000000602236619e17),
        (Mode::Equibiaxial, 0.1, 4.035418709793876e39, 1.9999999999999956e33),
        (Mode::Equibiaxial, 0.125, 1.661811609396451e36, 1.584563250285287e30),
        (Mode::Equibiaxial, 0.15, 2.897878630074372e33, 4.635640045196963e27),
        (Mode::Equibiaxial, 0.2, 1.3974826908519025e29, 4.656612873089102e23),
        (Mode::Equibiaxial, 2.0, 18949344085290.31, 8715175.567215737),
        (Mode::Equibiaxial, 10.0, 1.0000001603541924e34, 2.0000001603541862e17),
    ];

    /// The determinant as this module formed it before: the Hessian's
    /// entries summed plainly, then H11 H22 − H12².
    fn naive_determinant(m: &Ogden, [l1, l2, l3]: [f64; 3]) -> f64 {
        let (mut h11, mut h22, mut h12) = (0.0, 0.0, 0.0);
        for (mu, a) in m.terms() {
            let p3 = l3.powf(a);
            h11 += 2.0 * mu * (l1.powf(a) + p3);
            h22 += 2.0 * mu * (l2.powf(a) + p3);
            h12 += 2.0 * mu * p3;
        }
        h11 * h22 - h12 * h12
    }

    /// The error the expanded form may keep (its doc in ogden.rs): each
    /// power rounded within an ulp, so |δs_j| ≤ 2u Σ_i |μ_i λ_j^α_i|,
    /// propagated to det = 4 (s1 s2 + s1 s3 + s2 s3) and
    /// trace = 2 (s1 + s2 + 2 s3), plus the final roundings. Returns
    /// (det bound, trace bound).
    fn error_bounds(m: &Ogden, stretches: [f64; 3]) -> (f64, f64) {
        let u = f64::EPSILON / 2.0;
        let s = stretches.map(|l| m.terms().map(|(mu, a)| mu * l.powf(a)).sum::<f64>());
        let ds = stretches
            .map(|l| 2.0 * u * m.terms().map(|(mu, a)| (mu * l.powf(a)).abs()).sum::<f64>());
        let det = 4.0 * (s[0] * s[1] + s[0] * s[2] + s[1] * s[2]);
        let det_bound = 4.0
            * ((s[1] + s[2]).abs() * ds[0]
                + (s[0] + s[2]).abs() * ds[1]
                + (s[0] + s[1]).abs() * ds[2])
            + 4.0 * u * det.abs();
        let trace = 2.0 * (s[0] + s[1] + 2.0 * s[2]);
        let trace_bound = 2.0 * (ds[0] + ds[1] + 2.0 * ds[2]) + 4.0 * u * trace.abs();
        (det_bound, trace_bound)
    }

    /// Checks the expanded form against the reference within the error
    /// bound and within `max_relative`; returns the worst relative errors of
    /// the expanded and of the naive determinant.
    fn check_against_reference(m: &Ogden, reference: &Reference, max_relative: f64) -> (f64, f64) {
        let (mut worst, mut worst_naive) = (0.0_f64, 0.0_f64);
        for &(mode, stretch, det, trace) in reference {
            let stretches = mode.stretches(stretch);
            let d = m.drucker_stiffness(stretches);
            let (det_bound, trace_bound) = error_bounds(m, stretches);
            let det_error = (d.determinant_pa2 - det).abs();
            let trace_error = (d.trace_pa - trace).abs();
            assert!(
                det_error <= det_bound && det_error <= max_relative * det.abs(),
                "{mode} λ={stretch}: det {} vs {det} (bound {det_bound:e})",
                d.determinant_pa2
            );
            assert!(
                trace_error <= trace_bound && trace_error <= max_relative * trace.abs(),
                "{mode} λ={stretch}: trace {} vs {trace} (bound {trace_bound:e})",
                d.trace_pa
            );
            assert_eq!(d.is_positive_definite(), det > 0.0 && trace > 0.0);
            worst = worst.max(det_error / det.abs());
            let naive = naive_determinant(m, stretches);
            worst_naive = worst_naive.max((naive - det).abs() / det.abs());
            println!(
                "{mode} λ={stretch}: det rel. error {:.1e} (naive {:.1e}), bound {:.1e}",
                det_error / det.abs(),
                (naive - det).abs() / det.abs(),
                det_bound / det.abs()
            );
        }
        (worst, worst_naive)
    }

    #[test]
    fn paper_epdm_determinant_matches_high_precision() {
        // Its μ_i cancel by a factor ~10⁴ (Σ|μ_i λ^α_i| / |s_j| ≤ 10⁵ at
        // these points): 1e-10 leaves room for that.
        let (worst, _) = check_against_reference(&paper_epdm(), &EPDM_REFERENCE, 1e-10);
        assert!(worst < 1e-10);
    }

    #[test]
    fn cancelling_treloar_fit_determinant_matches_high_precision() {
        // The s_j themselves cancel by up to 10¹² here (μ_i up to ±10¹⁶ Pa,
        // α_i equal to three digits): the rounding of each power λ^α_i,
        // amplified by that, is the error bound checked per point (2.7e-5
        // to 2e-4 relative at these points); the errors reached are up to
        // 1.1e-5, against 1e-16 with every μ_i ≥ 0 below.
        let m = treloar_ogden6();
        let (worst, worst_naive) = check_against_reference(&m, &TRELOAR_OGDEN6_REFERENCE, 1e-4);
        // The old form was off by a factor 60 in equibiaxial compression at
        // λ = 0.1, negative at 0.125 and 0 at 0.2, where the model is stable.
        assert!(worst_naive > 10.0, "{worst_naive}");
        for stretch in [0.125, 0.2] {
            let naive = naive_determinant(&m, Mode::Equibiaxial.stretches(stretch));
            assert!(naive <= 0.0, "λ={stretch}: {naive}");
            assert!(is_stable(&m, Mode::Equibiaxial, stretch));
        }
        assert!(worst < 1e-4, "{worst}");
        // A 50-digit scan (400 geometric steps each side of λ = 1, same
        // script) finds it stable over 0.1 ≤ λ ≤ 10 in every mode.
        for r in stability_ranges(&m) {
            assert!(r.stable_everywhere(), "{r:?}");
        }
    }

    #[test]
    fn positive_ogden_determinant_matches_high_precision_where_the_naive_one_is_zero() {
        let m = positive_ogden4();
        // Every term positive: a few u relative, whatever the magnitudes.
        let (worst, worst_naive) = check_against_reference(&m, &POSITIVE_OGDEN4_REFERENCE, 1e-14);
        assert!(worst < 1e-14, "{worst}");
        assert_eq!(worst_naive, 1.0);
        for stretch in [0.1, 0.125, 0.15, 0.2] {
            let stretches = Mode::Equibiaxial.stretches(stretch);
            assert_eq!(naive_determinant(&m, stretches), 0.0);
            // Accurate entries do not save H11 H22 − H12²: s1 is below
            // half an ulp of s1 + s3.
            let from_entries = DruckerStiffness::from_hessian(m.log_strain_hessian_pa(stretches));
            assert!(from_entries.determinant_pa2 <= 0.0, "{from_entries:?}");
        }
        for r in stability_ranges(&m) {
            assert!(r.stable_everywhere(), "{r:?}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// An Ogden model with every μ_i ≥ 0 is Drucker-stable at every
        /// stretch (each s_j > 0, so det = 4 (s1 s2 + s1 s3 + s2 s3) > 0):
        /// the check must say so over the whole window, in every mode.
        #[test]
        fn ogden_with_nonnegative_moduli_is_stable_everywhere(
            terms in proptest::collection::vec(
                (
                    prop_oneof![Just(0.0), 0.0..1e7_f64],
                    (-20.0..20.0_f64).prop_filter("α ≠ 0", |a| *a != 0.0),
                ),
                1..7,
            ),
            first_mu in 1.0..1e7_f64,
            stretch in 0.1..10.0_f64,
        ) {
            let (mut mu, alpha): (Vec<f64>, Vec<f64>) = terms.into_iter().unzip();
            mu[0] = first_mu;
            let m = Ogden::new(mu, alpha).unwrap();
            for mode in Mode::ALL {
                prop_assert!(is_stable(&m, mode, stretch), "{m:?} {mode} λ={stretch}");
                let r = stability_range(&m, mode);
                prop_assert!(r.stable_everywhere(), "{m:?} {r:?}");
            }
        }
    }

    #[test]
    fn negative_modulus_is_unstable_at_rest() {
        let m = Ogden::new(vec![-1e5], vec![2.0]).unwrap();
        let r = stability_range(&m, Mode::Uniaxial);
        assert!(!r.stable_at_rest && r.lambda_min == 1.0 && r.lambda_max == 1.0);
        assert!(!r.stable_everywhere());
        assert_eq!(r.describe(), "unstable at zero strain");
    }
}
