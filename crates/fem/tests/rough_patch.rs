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
