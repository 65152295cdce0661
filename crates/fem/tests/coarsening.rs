//! Lateral coarsening with depth (issue #48): the patch test on a coarsened
//! mesh with hanging nodes (a homogeneous field is reproduced exactly, and
//! is in equilibrium at finite strain), the load–area response of a rough
//! patch within 1 % of the uniform mesh's at equal approach (small and
//! finite strain, and the paper's patch t3), the same bits on 1 and 2
//! threads, periodic faces, and the counts the option saves.

use hypercontact_fem::assembly::{self, Pattern};
use hypercontact_fem::dofs::Dofs;
use hypercontact_fem::hexahedron;
use hypercontact_fem::linear_solver::LinearSolver;
use hypercontact_fem::mesh::periodic_extension;
use hypercontact_fem::ordering::nested_dissection;
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    AreaSteps, ContactProblem, Curve, CurveOptions, HeightMap, Lateral, Law, Mesh, MeshOptions,
    NewtonOptions, bearing_approach_m, solve_area_steps, solve_curve,
};

const PIXEL_M: f64 = 20e-6;

/// A rough 17 × 15 block, 32 pixels deep in 4 layers of 8 pixels: element
/// sizes 8, 4, 2, 1 pixels from the base up, with shorter last elements in
/// y (14 is no multiple of 4 or 8).
fn patch_test_mesh() -> Mesh {
    let surface = SampleSurface {
        nx: 17,
        ny: 15,
        pixel_m: PIXEL_M,
        rms_m: 1.5 * PIXEL_M,
        hurst: 0.8,
        modes: 3,
        seed: 2,
    };
    let heights = surface.heights_m();
    let options = MeshOptions {
        depth_m: Some(32.0 * PIXEL_M),
        layers: 4,
        grading: 1.0,
        lateral_coarsening: true,
    };
    Mesh::new(&surface.on_grid(&heights), &options).unwrap()
}

/// u = A X, a small general strain (shear included).
const STRAIN: [[f64; 3]; 3] = [
    [1.0e-3, 0.4e-3, -0.2e-3],
    [-0.3e-3, -0.6e-3, 0.5e-3],
    [0.7e-3, 0.1e-3, 0.9e-3],
];

fn linear_field(x: [f64; 3], scale: f64) -> [f64; 3] {
    STRAIN.map(|row| scale * (row[0] * x[0] + row[1] * x[1] + row[2] * x[2]))
}

/// The unknowns of the field at their own (corner) nodes.
fn unknowns_of(mesh: &Mesh, dofs: &Dofs, field: impl Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
    let mut x = vec![f64::NAN; dofs.count];
    for node in (0..mesh.nodes_m.len()).filter(|n| mesh.used[*n] && !mesh.is_hanging(*n)) {
        let u = field(mesh.nodes_m[node]);
        for (c, value) in u.iter().enumerate() {
            if let Some(e) = dofs.equation(3 * node + c) {
                x[e] = *value;
            }
        }
    }
    assert!(x.iter().all(|v| v.is_finite()));
    x
}

/// The largest nodal force of any element at the unknowns `x`, N: the
/// size that the assembled residual's round-off is relative to.
fn element_force_scale(mesh: &Mesh, dofs: &Dofs, law: &Law, x: &[f64]) -> f64 {
    let u = dofs.expand(x);
    (mesh.elements.iter())
        .map(|e| {
            let out =
                hexahedron::evaluate(law, &e.map(|n| mesh.nodes_m[n]), &e.map(|n| u[n]), false)
                    .unwrap();
            out.force_n.iter().fold(0.0_f64, |m, f| m.max(f.abs()))
        })
        .fold(0.0, f64::max)
}

/// The patch test (Irons; Zienkiewicz & Taylor, The Finite Element Method,
/// vol. 1, ch. 9): boundary displacements from a uniform strain, the
/// interior solved, equals the linear field to round-off, hanging nodes
/// (on the boundary and inside) included; and the exact field leaves no
/// residual at the free unknowns.
#[test]
fn a_coarsened_mesh_passes_the_patch_test() {
    let mesh = patch_test_mesh();
    assert_eq!(mesh.layer_steps, [8, 4, 2, 1]);
    let (nx, ny, layers) = (mesh.nx, mesh.ny, mesh.layers);
    let interior_hanging = (mesh.hanging.iter())
        .filter(|h| {
            let (i, j, _) = mesh.grid_of(h.node);
            i > 0 && j > 0 && i < nx - 1 && j < ny - 1
        })
        .count();
    assert!(interior_hanging > 20, "{interior_hanging}");
    let dofs = Dofs::prescribed(&mesh, |i, j, k, c| {
        let boundary = i == 0 || j == 0 || i == nx - 1 || j == ny - 1 || k == 0 || k == layers;
        boundary.then(|| linear_field(mesh.nodes_m[mesh.node(i, j, k)], 1.0)[c])
    });
    let law = Law::linear_elastic(1.0e6, 50.0).unwrap();
    let pattern = Pattern::new(&mesh, &dofs);
    let order = nested_dissection(&mesh, &dofs);
    let mut solver = LinearSolver::new(&pattern, Some(&order)).unwrap();
    // Linear: one Newton step from zero is the solution.
    let zero = vec![0.0; dofs.count];
    let start = assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &zero).unwrap();
    solver.factor(start.tangent.as_ref().unwrap()).unwrap();
    let mut x: Vec<f64> = start.residual_n.iter().map(|r| -r).collect();
    solver.solve(&mut x);
    let u = dofs.expand(&x);
    let largest = (0..mesh.nodes_m.len())
        .map(|n| linear_field(mesh.nodes_m[n], 1.0).map(f64::abs))
        .fold(0.0_f64, |m, v| m.max(v[0]).max(v[1]).max(v[2]));
    let mut error = 0.0_f64;
    for node in (0..mesh.nodes_m.len()).filter(|n| mesh.used[*n]) {
        let want = linear_field(mesh.nodes_m[node], 1.0);
        for c in 0..3 {
            error = error.max((u[node][c] - want[c]).abs());
        }
    }
    assert!(
        error < 1e-10 * largest,
        "largest error {error:e} of {largest:e} m"
    );
    let exact = unknowns_of(&mesh, &dofs, |x| linear_field(x, 1.0));
    let residual = assembly::evaluate(&mesh, &dofs, &law, None, &exact).unwrap();
    let force_scale = element_force_scale(&mesh, &dofs, &law, &exact);
    let worst = residual
        .residual_n
        .iter()
        .fold(0.0_f64, |m, r| m.max(r.abs()));
    assert!(
        worst < 1e-12 * force_scale,
        "{worst:e} N of {force_scale:e} N"
    );
}

/// At finite strain a homogeneous deformation (stretches of tens of per
/// cent) is in equilibrium on the coarsened mesh too: no residual at the
/// free unknowns, for a neo-Hookean solid and the paper's Ogden EPDM.
#[test]
fn a_homogeneous_finite_deformation_is_in_equilibrium_on_a_coarsened_mesh() {
    let mesh = patch_test_mesh();
    let (nx, ny, layers) = (mesh.nx, mesh.ny, mesh.layers);
    let field = |x: [f64; 3]| linear_field(x, 150.0);
    let dofs = Dofs::prescribed(&mesh, |i, j, k, c| {
        let boundary = i == 0 || j == 0 || i == nx - 1 || j == ny - 1 || k == 0 || k == layers;
        boundary.then(|| field(mesh.nodes_m[mesh.node(i, j, k)])[c])
    });
    let exact = unknowns_of(&mesh, &dofs, field);
    for (model, tolerance) in [
        (
            Box::new(hypercontact_material::NeoHookean::new(0.5e6).unwrap())
                as Box<dyn hypercontact_material::Hyperelastic>,
            1e-12,
        ),
        // The paper's Ogden terms cancel from ±5e9 Pa to 2e6 Pa.
        (Box::new(hypercontact_material::presets::paper_epdm()), 1e-9),
    ] {
        let law = Law::hyperelastic(model.as_ref(), 5000.0).unwrap();
        let e = assembly::evaluate(&mesh, &dofs, &law, None, &exact).unwrap();
        let force_scale = element_force_scale(&mesh, &dofs, &law, &exact);
        let worst = e.residual_n.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
        assert!(
            worst < tolerance * force_scale,
            "{}: {worst:e} N against {force_scale:e} N",
            model.family()
        );
    }
}

fn rough(n: usize, seed: u64) -> Vec<f64> {
    SampleSurface {
        nx: n,
        ny: n,
        pixel_m: PIXEL_M,
        rms_m: 3e-6 * n as f64 / 32.0,
        hurst: 0.8,
        modes: 8,
        seed,
    }
    .heights_m()
}

fn solve(
    heights: &[f64],
    n: usize,
    options: MeshOptions,
    law: Law,
    lateral: Lateral,
    approaches_m: Vec<f64>,
) -> Curve {
    let map = HeightMap {
        heights_m: heights,
        nx: n,
        ny: n,
        dx_m: PIXEL_M,
        dy_m: PIXEL_M,
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

fn coarsened(layers: usize) -> MeshOptions {
    MeshOptions {
        layers,
        lateral_coarsening: true,
        ..MeshOptions::default()
    }
}

/// The acceptance figure: on a 32² rough patch (8 layers graded
/// 8 : 1, element sizes 8, 4, 4, 2, 2, 1, 1, 1 pixels from the base up),
/// the load at equal approach within 1 % of the uniform mesh's, at small
/// strain and at finite strain (the paper's EPDM), up to ~25 % contact.
#[test]
fn coarsened_load_is_within_one_percent_of_the_uniform_mesh() {
    let n = 32;
    let h = rough(n, 1);
    let steps = approaches(&h, 0.8, 4);
    let map = HeightMap {
        heights_m: &h,
        nx: n,
        ny: n,
        dx_m: PIXEL_M,
        dy_m: PIXEL_M,
    };
    let mesh = Mesh::new(&map, &coarsened(8)).unwrap();
    assert_eq!(mesh.layer_steps, [8, 4, 4, 2, 2, 1, 1, 1]);
    let epdm = Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap();
    let small = Law::linear_elastic(epdm.shear_modulus_pa(), 5000.0).unwrap();
    for (name, law) in [("small", small), ("finite", epdm)] {
        let uniform = solve(
            &h,
            n,
            MeshOptions::default(),
            law.clone(),
            Lateral::Mirror,
            steps.clone(),
        );
        let coarse = solve(&h, n, coarsened(8), law, Lateral::Mirror, steps.clone());
        assert!(uniform.steps.last().unwrap().area_fraction > 0.15);
        for (u, c) in uniform.steps.iter().zip(&coarse.steps) {
            let change = c.load_n / u.load_n - 1.0;
            eprintln!(
                "{name} strain, approach {:.3e} m: load {:.6e} N uniform, {:.6e} N coarsened \
                 ({change:+.3e}); A/A0 {:.4}, {:.4}",
                u.approach_m, u.load_n, c.load_n, u.area_fraction, c.area_fraction
            );
            assert!(change.abs() < 0.01, "{name}: {change}");
            assert!((c.area_fraction - u.area_fraction).abs() < 0.01);
        }
    }
}

#[test]
fn coarsened_mesh_gives_the_same_bits_on_one_and_two_threads() {
    let n = 16;
    let h = rough(n, 4);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let law = Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap();
        pool.install(|| {
            solve(
                &h,
                n,
                coarsened(6),
                law,
                Lateral::Mirror,
                approaches(&h, 0.8, 3),
            )
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.steps.last().unwrap().area_fraction > 0.1);
    let bits = |c: &Curve| -> Vec<u64> {
        (c.steps.iter())
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

/// Periodic faces on a coarsened mesh: the tied edge points share contact
/// and pressure, and the load is that of the uniform mesh within 1 %.
#[test]
fn periodic_faces_tie_the_edges_of_a_coarsened_mesh() {
    let n = 16;
    let h = periodic_extension(&rough(n, 6), n, n);
    let law = || Law::linear_elastic(1.0e6, 5000.0).unwrap();
    let steps = approaches(&h, 0.7, 3);
    let uniform = solve(
        &h,
        n + 1,
        MeshOptions::default(),
        law(),
        Lateral::Periodic,
        steps.clone(),
    );
    let coarse = solve(&h, n + 1, coarsened(8), law(), Lateral::Periodic, steps);
    let snapshot = &coarse.snapshots[0];
    for i in 0..=n {
        let (first, last) = (i * (n + 1), i * (n + 1) + n);
        assert_eq!(snapshot.contact[first], snapshot.contact[last]);
        assert_eq!(snapshot.pressure_pa[first], snapshot.pressure_pa[last]);
    }
    for (u, c) in uniform.steps.iter().zip(&coarse.steps) {
        assert!(
            (c.load_n / u.load_n - 1.0).abs() < 0.01,
            "{} vs {} N",
            c.load_n,
            u.load_n
        );
    }
}

/// Nodes, unknowns and the Cholesky factor with and without coarsening on
/// the paper's 48² patch size, 8 layers (printed; the example
/// `mesh_sizes` prints 96² too).
#[test]
fn coarsening_shrinks_the_unknowns_and_the_factor() {
    let n = 48;
    let h = rough(n, 1);
    let map = HeightMap {
        heights_m: &h,
        nx: n,
        ny: n,
        dx_m: PIXEL_M,
        dy_m: PIXEL_M,
    };
    let sizes = |options: MeshOptions| {
        let mesh = Mesh::new(&map, &options).unwrap();
        let dofs = Dofs::new(&mesh, Lateral::Mirror);
        let pattern = Pattern::new(&mesh, &dofs);
        let solver = LinearSolver::new(&pattern, Some(&nested_dissection(&mesh, &dofs))).unwrap();
        assert_eq!(Mesh::node_count_of(&map, &options), mesh.node_count());
        (mesh.node_count(), dofs.count, solver.factor_len())
    };
    let (uniform, coarse) = (sizes(MeshOptions::default()), sizes(coarsened(8)));
    eprintln!(
        "48² × 8 (nodes, unknowns, factor values): uniform {uniform:?}, coarsened {coarse:?}"
    );
    assert_eq!(uniform.0, 48 * 48 * 9);
    // Measured: 20 736 → 8 142 nodes, 53 760 → 16 818 unknowns, 32.5 M →
    // 4.9 M factor values.
    assert!(
        2 * coarse.0 < uniform.0 && 3 * coarse.1 < uniform.1,
        "{coarse:?}"
    );
    assert!(6 * coarse.2 < uniform.2, "{coarse:?}");
}

/// The paper's sample t3 as its pipeline crops it (48 × 48 points of
/// 20 µm, `tests/data/t3-patch-height.npy`, from pipelines/paper.yaml's
/// t3-patch), the paper patch whose load the coarsening moves most: at
/// small strain, on the uniform mesh's steps aimed at A/A0 up to 0.3, the
/// coarsened load within 1 % at every approach (measured: 0.90 % at the
/// first step, A/A0 = 0.022, 0.34 % at the last).
#[test]
fn coarsened_load_on_the_paper_patch_t3_is_within_one_percent() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/t3-patch-height.npy");
    let array: ndarray::Array2<f64> = ndarray_npy::read_npy(path).unwrap();
    let (n, heights) = (array.dim().0, array.iter().copied().collect::<Vec<f64>>());
    let map = HeightMap {
        heights_m: &heights,
        nx: n,
        ny: n,
        dx_m: PIXEL_M,
        dy_m: PIXEL_M,
    };
    let law = Law::linear_elastic(1.0e6, 5000.0).unwrap();
    let problem = |options: &MeshOptions| {
        let mesh = Mesh::new(&map, options).unwrap();
        ContactProblem::new(mesh, law.clone(), Lateral::Mirror, NewtonOptions::default()).unwrap()
    };
    let range_m = heights.iter().fold(f64::NEG_INFINITY, |m, h| m.max(*h))
        - heights.iter().fold(f64::INFINITY, |m, h| m.min(*h));
    let steps = AreaSteps {
        steps: 10,
        max_area_fraction: 0.3,
        first_approach_m: bearing_approach_m(&heights, 0.03).max(1e-3 * range_m),
        snapshot_area_fractions: Vec::new(),
        max_steps: 50,
    };
    let uniform =
        solve_area_steps(&mut problem(&MeshOptions::default()), &steps, &mut |_| {}).unwrap();
    let options = CurveOptions {
        approaches_m: uniform.steps.iter().map(|s| s.approach_m).collect(),
        ..Default::default()
    };
    let coarse = solve_curve(&mut problem(&coarsened(8)), &options).unwrap();
    for (u, c) in uniform.steps.iter().zip(&coarse.steps) {
        let change = c.load_n / u.load_n - 1.0;
        eprintln!(
            "t3, approach {:.4e} m: A/A0 {:.4} uniform, {:.4} coarsened; load change {change:+.3e}",
            u.approach_m, u.area_fraction, c.area_fraction
        );
        assert!(change.abs() < 0.01, "{change}");
    }
}
