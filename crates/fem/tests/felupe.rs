//! Side by side with felupe (PyPI `felupe` 11.3.0, Python 3.11, run on
//! this project's 2-core machine on 2026-11-26 by a throwaway script, not
//! kept): the same 10 × 10 sample surface ([`SampleSurface`], 20 µm
//! pixels, rms 2 µm, H = 0.8, 3 modes, seed 5; rms slope ≈ 0.2), the
//! same mesh (issue #33 conventions, depth 9 pixels, 4 layers graded 4 : 1),
//! base clamped, mirror faces, an isochoric neo-Hookean solid μ = 1 MPa in
//! `SolidBodyNearlyIncompressible` with bulk modulus 5000 μ (felupe's
//! U(J̄) = K(J̄ − 1)²/2 on a constant J̄ per cell: the same Q1/P0 element), and
//! a frictionless `ContactRigidPlane` (penalty, multiplier 1000 × the mean
//! stiffness; largest penetration 8e-12 m) moving down in 5 equal steps to
//! 0.9 of the highest point's height above the mean. felupe's numbers:
//! its load on the plane and the fraction of top nodes in contact.

use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    ContactProblem, CurveOptions, Lateral, Law, Mesh, MeshOptions, NewtonOptions, solve_curve,
};
use hypercontact_material::NeoHookean;

/// (approach, m; load, N; area fraction) from felupe 11.3.0.
const FELUPE: [(f64, f64, f64); 5] = [
    (5.6587290584476e-07, 5.036634193392504e-05, 0.07),
    (1.13174581168952e-06, 0.00027981925994472915, 0.17),
    (1.6976187175342799e-06, 0.0007473306539325907, 0.28),
    (2.26349162337904e-06, 0.0018898743984020684, 0.52),
    (2.8293645292238e-06, 0.004791198788085806, 0.78),
];

#[test]
fn rough_patch_matches_felupe() {
    let n = 10;
    let surface = SampleSurface {
        nx: n,
        ny: n,
        pixel_m: 20e-6,
        rms_m: 2e-6,
        hurst: 0.8,
        modes: 3,
        seed: 5,
    };
    let heights = surface.heights_m();
    let map = surface.on_grid(&heights);
    let options = MeshOptions {
        depth_m: None,
        layers: 4,
        grading: 4.0,
        lateral_coarsening: false,
    };
    let mesh = Mesh::new(&map, &options).unwrap();
    let law = Law::hyperelastic(&NeoHookean::new(0.5e6).unwrap(), 5000.0).unwrap();
    let mut problem =
        ContactProblem::new(mesh, law, Lateral::Mirror, NewtonOptions::default()).unwrap();
    let curve = solve_curve(
        &mut problem,
        &CurveOptions {
            approaches_m: FELUPE.iter().map(|r| r.0).collect(),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(curve.steps.len(), FELUPE.len());
    for (step, (approach, load, fraction)) in curve.steps.iter().zip(FELUPE) {
        // Measured: 2e-6 to 7e-6 apart, felupe's penalty penetration
        // (~1e-12 m of ~1e-6 m) and its Newton tolerance; the same nodes in
        // contact.
        assert!(
            (step.load_n / load - 1.0).abs() < 5e-5
                && (step.area_fraction - fraction).abs() < 1e-12,
            "approach {approach:e} m: load {} N vs felupe {load} N, area fraction {} vs {fraction}",
            step.load_n,
            step.area_fraction
        );
    }
}
