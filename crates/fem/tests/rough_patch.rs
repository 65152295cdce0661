//! A rough patch of the paper's EPDM at finite strain: the same bits on 1
//! and 2 threads, periodic faces, and the load's convergence when the mesh
//! is refined in depth.

use hypercontact_fem::mesh::periodic_extension;
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    ContactProblem, Curve, CurveOptions, HeightMap, Lateral, Law, Mesh, MeshOptions, NewtonOptions,
    solve_curve,
};

fn surface(n: usize) -> Vec<f64> {
    SampleSurface {
        nx: n,
        ny: n,
        pixel_m: 20e-6,
        rms_m: 3e-6,
        hurst: 0.8,
        modes: 4,
        seed: 11,
    }
    .heights_m()
}

/// The paper's EPDM, nearly incompressible (κ = 5000 μ).
fn paper_epdm() -> Law {
    Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap()
}

fn curve(
    law: Law,
    heights: &[f64],
    n: usize,
    layers: usize,
    lateral: Lateral,
    approaches_m: Vec<f64>,
) -> Curve {
    let map = HeightMap {
        heights_m: heights,
        nx: n,
        ny: n,
        dx_m: 20e-6,
        dy_m: 20e-6,
    };
    let options = MeshOptions {
        layers,
        ..MeshOptions::default()
    };
    let mesh = Mesh::new(&map, &options).unwrap();
    let mut problem = ContactProblem::new(mesh, law, lateral, NewtonOptions::default()).unwrap();
    let options = CurveOptions {
        approaches_m,
        snapshot_area_fractions: vec![0.1],
        ..Default::default()
    };
    solve_curve(&mut problem, &options).unwrap()
}

fn approaches(heights: &[f64], fraction: f64, steps: usize) -> Vec<f64> {
    let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    CurveOptions::uniform(fraction * (top - mean), steps).approaches_m
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    let n = 12;
    let h = surface(n);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            curve(
                paper_epdm(),
                &h,
                n,
                4,
                Lateral::Mirror,
                approaches(&h, 0.8, 4),
            )
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.steps.last().unwrap().area_fraction > 0.1);
    let bits = |c: &Curve| -> Vec<u64> {
        c.steps
            .iter()
            .flat_map(|s| [s.load_n, s.area_fraction_current, s.mean_gap_m])
            .chain(
                c.snapshots
                    .iter()
                    .flat_map(|s| s.displacement_m.iter().flatten().copied()),
            )
            .chain(
                c.snapshots
                    .iter()
                    .flat_map(|s| s.pressure_pa.iter().copied()),
            )
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
}

/// A neo-Hookean solid (μ = 1 MPa): the paper's EPDM loses Drucker
/// stability in equibiaxial compression below λ ≈ 0.56, which the thin top
/// layers of the finer mesh reach under these asperities.
#[test]
fn load_converges_when_the_mesh_is_refined_in_depth() {
    let n = 12;
    let h = surface(n);
    let approach = approaches(&h, 0.3, 3);
    let law = || {
        Law::hyperelastic(
            &hypercontact_material::NeoHookean::new(0.5e6).unwrap(),
            5000.0,
        )
        .unwrap()
    };
    let default = curve(law(), &h, n, 8, Lateral::Mirror, approach.clone());
    let fine = curve(law(), &h, n, 16, Lateral::Mirror, approach);
    let (a, b) = (default.steps.last().unwrap(), fine.steps.last().unwrap());
    assert!(a.area_fraction > 0.1, "{}", a.area_fraction);
    let change = b.load_n / a.load_n - 1.0;
    eprintln!(
        "load at approach {:.3e} m: {:.6e} N (8 layers), {:.6e} N (16), change {change:+.3e}",
        a.approach_m, a.load_n, b.load_n
    );
    assert!(change.abs() < 0.02, "{change}");
}

#[test]
fn periodic_faces_tie_the_edges() {
    let n = 10;
    let h = periodic_extension(&surface(n), n, n);
    let c = curve(
        paper_epdm(),
        &h,
        n + 1,
        4,
        Lateral::Periodic,
        approaches(&h, 0.6, 3),
    );
    let last = c.steps.last().unwrap();
    assert!(last.load_n > 0.0 && last.area_fraction > 0.0);
    let snapshot = &c.snapshots[0];
    // The tied edge points share their contact state and pressure.
    for i in 0..=n {
        let (first, last) = (i * (n + 1), i * (n + 1) + n);
        assert_eq!(snapshot.contact[first], snapshot.contact[last]);
        assert_eq!(snapshot.pressure_pa[first], snapshot.pressure_pa[last]);
    }
}

/// Chord steps (the last factorisation kept once Newton converges) reach
/// the state that a factorisation at every iteration reaches: the same
/// contact set at every step and the load within Newton's tolerance, with
/// fewer factorisations.
#[test]
fn chord_steps_reach_the_newton_solution_with_fewer_factorisations() {
    let n = 12;
    let h = surface(n);
    let map = HeightMap {
        heights_m: &h,
        nx: n,
        ny: n,
        dx_m: 20e-6,
        dy_m: 20e-6,
    };
    let run = |chord_contraction: f64| {
        let options = MeshOptions {
            layers: 4,
            ..MeshOptions::default()
        };
        let mesh = Mesh::new(&map, &options).unwrap();
        let newton = NewtonOptions {
            chord_contraction,
            ..NewtonOptions::default()
        };
        let mut problem = ContactProblem::new(mesh, paper_epdm(), Lateral::Mirror, newton).unwrap();
        // Chord steps alone: conjugate gradients on the kept factorisation
        // would take the iterations they save.
        problem.set_krylov(false);
        let options = CurveOptions {
            // Steps small enough for Newton's convergence range (larger
            // ones are cut back, and chord steps then save nothing).
            approaches_m: approaches(&h, 0.4, 8),
            snapshot_area_fractions: vec![0.05, 0.1],
            ..Default::default()
        };
        let curve = solve_curve(&mut problem, &options).unwrap();
        (curve, problem.factorizations())
    };
    let ((newton, newton_factorizations), (chord, chord_factorizations)) = (run(0.0), run(0.25));
    assert!(newton.steps.last().unwrap().area_fraction > 0.1);
    eprintln!(
        "{newton_factorizations} factorisations without chord steps, {chord_factorizations} with"
    );
    for (a, b) in newton.steps.iter().zip(&chord.steps) {
        assert_eq!(a.area_fraction, b.area_fraction);
        assert!(
            (a.load_n / b.load_n - 1.0).abs() < 1e-6,
            "{} vs {} N",
            a.load_n,
            b.load_n
        );
    }
    for (a, b) in newton.snapshots.iter().zip(&chord.snapshots) {
        assert_eq!(a.contact, b.contact);
    }
    assert!(
        chord_factorizations < newton_factorizations,
        "{chord_factorizations} factorisations with chord steps, {newton_factorizations} without"
    );
}

/// At small strain (a constant tangent), Newton directions by conjugate
/// gradients on a kept factorisation, the default there, give the curve of
/// a fresh factorisation at every iteration (the same contact sets, loads
/// within Newton's tolerance) for fewer factorisations.
#[test]
fn conjugate_gradients_on_a_kept_factorisation_save_factorisations() {
    let n = 12;
    let h = surface(n);
    let shear_pa = paper_epdm().shear_modulus_pa();
    let run = |krylov: bool| {
        let map = HeightMap {
            heights_m: &h,
            nx: n,
            ny: n,
            dx_m: 20e-6,
            dy_m: 20e-6,
        };
        let options = MeshOptions {
            layers: 4,
            ..MeshOptions::default()
        };
        let mesh = Mesh::new(&map, &options).unwrap();
        let law = Law::linear_elastic(shear_pa, 5000.0).unwrap();
        let mut problem =
            ContactProblem::new(mesh, law, Lateral::Mirror, NewtonOptions::default()).unwrap();
        if !krylov {
            problem.set_krylov(false);
        }
        let options = CurveOptions {
            approaches_m: approaches(&h, 0.4, 8),
            snapshot_area_fractions: vec![0.05, 0.1],
            ..Default::default()
        };
        let curve = solve_curve(&mut problem, &options).unwrap();
        (curve, problem.factorizations(), problem.krylov_iterations())
    };
    let (direct, direct_factorizations, none) = run(false);
    let (krylov, krylov_factorizations, iterations) = run(true);
    eprintln!(
        "{direct_factorizations} factorisations without conjugate gradients; \
         {krylov_factorizations} and {iterations} CG iterations with"
    );
    assert_eq!(none, 0);
    assert!(direct.steps.last().unwrap().area_fraction > 0.1);
    for (a, b) in direct.steps.iter().zip(&krylov.steps) {
        assert_eq!(a.area_fraction, b.area_fraction);
        assert!(
            (a.load_n / b.load_n - 1.0).abs() < 1e-6,
            "{} vs {} N",
            a.load_n,
            b.load_n
        );
    }
    for (a, b) in direct.snapshots.iter().zip(&krylov.snapshots) {
        assert_eq!(a.contact, b.contact);
    }
    assert!(
        iterations > 0 && krylov_factorizations < direct_factorizations,
        "{krylov_factorizations} factorisations with conjugate gradients, \
         {direct_factorizations} without"
    );
}
