//! Homogeneous deformations against the material crate's closed-form
//! nominal stresses of the incompressible solid, UT, PT and BT, for every
//! family.
//!
//! - One element deformed by exactly incompressible stretches
//!   (λ1 λ2 λ3 = 1, so θ = 1 and the volumetric pressure vanishes): the
//!   face forces give P11 and P33 of the isochoric response, and the
//!   incompressible nominal stress is T = (σ11 − σ33)/λ1 = P11 − P33 λ3/λ1,
//!   independent of the pressure the incompressible theory leaves
//!   undetermined. This is the exact incompressible limit: 1e-8 relative.
//! - A 2 × 2 × 2 block stretched by its faces with the transverse faces
//!   free, solved by Newton: its lateral contraction comes from the bulk
//!   modulus, so T approaches the incompressible value as O(μ/κ); shown by
//!   the error falling a hundredfold from κ = 1e4 μ to 1e6 μ.

use crate::common;

use hypercontact_fem::assembly::{self, Pattern};
use hypercontact_fem::dofs::Dofs;
use hypercontact_fem::hexahedron::{self, CORNERS};
use hypercontact_fem::linear_solver::LinearSolver;
use hypercontact_fem::{HeightMap, Law, Mesh, MeshOptions};
use hypercontact_material::{Hyperelastic, Mode};

const SIDE_M: f64 = 1e-3;

#[test]
fn one_element_at_incompressible_stretches_gives_the_analytic_nominal_stress() {
    let reference = CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0) * SIDE_M));
    let area = SIDE_M * SIDE_M;
    for model in common::every_family() {
        let law = Law::hyperelastic(model.as_ref(), 5000.0).unwrap();
        for mode in Mode::ALL {
            for stretch in [0.6, 0.8, 0.95, 1.05, 1.3, 1.8, 2.5] {
                let l = mode.stretches(stretch);
                let u = reference.map(|x| [0, 1, 2].map(|i| (l[i] - 1.0) * x[i]));
                let out = hexahedron::evaluate(&law, &reference, &u, false).unwrap();
                let face_force = |axis: usize| -> f64 {
                    (0..8)
                        .filter(|&a| reference[a][axis] == SIDE_M)
                        .map(|a| out.force_n[3 * a + axis])
                        .sum()
                };
                let (p11, p33) = (face_force(0) / area, face_force(2) / area);
                let nominal = p11 - p33 * l[2] / l[0];
                let expected = model.nominal_stress_pa(mode, stretch);
                assert!(
                    (nominal - expected).abs() <= 1e-8 * expected.abs(),
                    "{} {mode} λ = {stretch}: {nominal} vs {expected} ({:e})",
                    model.family(),
                    nominal / expected - 1.0
                );
            }
        }
    }
}

/// The stretched block's nominal stress P11 (reaction on x = L over the
/// reference area).
fn block_nominal_stress(
    model: &dyn Hyperelastic,
    mode: Mode,
    stretch: f64,
    bulk_ratio: f64,
) -> f64 {
    let h = [0.0; 9];
    let map = HeightMap {
        heights_m: &h,
        nx: 3,
        ny: 3,
        dx_m: 0.5 * SIDE_M,
        dy_m: 0.5 * SIDE_M,
    };
    let options = MeshOptions {
        depth_m: Some(SIDE_M),
        layers: 2,
        grading: 1.0,
        lateral_coarsening: false,
    };
    let mesh = Mesh::new(&map, &options).unwrap();
    let l = mode.stretches(stretch);
    // x stretched on x = L; y held on y = L in PT (λ2 = 1) and BT; the
    // z = L face (and y = L in UT) traction free; symmetry planes at 0.
    let dofs = Dofs::prescribed(&mesh, |i, j, k, c| match c {
        0 if i == 0 => Some(0.0),
        0 if i == 2 => Some((l[0] - 1.0) * SIDE_M),
        1 if j == 0 => Some(0.0),
        1 if j == 2 && mode != Mode::Uniaxial => Some((l[1] - 1.0) * SIDE_M),
        2 if k == 0 => Some(0.0),
        _ => None,
    });
    let law = Law::hyperelastic(model, bulk_ratio).unwrap();
    let pattern = Pattern::new(&mesh, &dofs);
    let mut solver = LinearSolver::new(&pattern, None).unwrap();
    // Start from the incompressible homogeneous field.
    let mut x = vec![0.0; dofs.count];
    for slot in 0..3 * mesh.nodes_m.len() {
        if let Some(e) = dofs.equation(slot) {
            x[e] = (l[slot % 3] - 1.0) * mesh.nodes_m[slot / 3][slot % 3];
        }
    }
    let force_scale = model.shear_modulus_pa() * SIDE_M * SIDE_M;
    for _ in 0..30 {
        let e = assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &x).unwrap();
        let norm = e.residual_n.iter().map(|r| r * r).sum::<f64>().sqrt();
        if norm < 1e-13 * force_scale {
            break;
        }
        solver.factor(e.tangent.as_ref().unwrap()).unwrap();
        let mut d: Vec<f64> = e.residual_n.iter().map(|r| -r).collect();
        solver.solve(&mut d);
        x.iter_mut().zip(&d).for_each(|(u, du)| *u += du);
    }
    let displacement = dofs.expand(&x);
    let mut reaction = 0.0;
    for element in &mesh.elements {
        let out = hexahedron::evaluate(
            &law,
            &element.map(|n| mesh.nodes_m[n]),
            &element.map(|n| displacement[n]),
            false,
        )
        .unwrap();
        for (a, node) in element.iter().enumerate() {
            if mesh.grid_of(*node).0 == 2 {
                reaction += out.force_n[3 * a];
            }
        }
    }
    reaction / (SIDE_M * SIDE_M)
}

#[test]
fn stretched_block_tends_to_the_incompressible_stress_as_the_bulk_modulus_grows() {
    for model in common::every_family() {
        for mode in Mode::ALL {
            for stretch in [0.8, 1.3] {
                let expected = model.nominal_stress_pa(mode, stretch);
                let error = |ratio: f64| {
                    (block_nominal_stress(model.as_ref(), mode, stretch, ratio) / expected - 1.0)
                        .abs()
                };
                let (soft, stiff) = (error(1e4), error(1e6));
                assert!(
                    stiff < 1e-5 && stiff < soft / 30.0,
                    "{} {mode} λ = {stretch}: error {soft:e} at κ = 1e4 μ, {stiff:e} at 1e6 μ",
                    model.family()
                );
            }
        }
    }
}
