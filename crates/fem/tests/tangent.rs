//! The assembled consistent tangent equals central differences of the
//! assembled residual, for every material family, on a rough, graded mesh
//! at a finite, non-homogeneous deformation (mirror faces, clamped base).

use crate::common;

use hypercontact_fem::assembly::{self, Pattern};
use hypercontact_fem::dofs::Dofs;
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{Lateral, Law, Mesh, MeshOptions};

/// y = K v from the upper triangle.
fn multiply(pattern: &Pattern, values: &[f64], v: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; v.len()];
    for col in 0..pattern.size {
        let range = pattern.col_ptr[col]..pattern.col_ptr[col + 1];
        for (value, &row) in values[range.clone()].iter().zip(&pattern.row_idx[range]) {
            y[row] += value * v[col];
            if row != col {
                y[col] += value * v[row];
            }
        }
    }
    y
}

#[test]
fn assembled_tangent_equals_differences_of_the_residual() {
    let surface = SampleSurface {
        nx: 5,
        ny: 4,
        pixel_m: 1e-4,
        rms_m: 1e-5,
        hurst: 0.8,
        modes: 2,
        seed: 3,
    };
    let h = surface.heights_m();
    let map = surface.on_grid(&h);
    let options = MeshOptions {
        depth_m: None,
        layers: 3,
        grading: 3.0,
        lateral_coarsening: false,
    };
    tangent_equals_differences(&Mesh::new(&map, &options).unwrap());
}

/// The same on a laterally coarsened mesh (3 layers of 5.3 pixels: element
/// sizes 4, 2, 1 from the base up, shorter last elements in y): the hanging nodes' rows spread
/// over their masters (TᵀKT) are the derivative of the spread forces.
#[test]
fn assembled_tangent_equals_differences_of_the_residual_with_hanging_nodes() {
    let surface = SampleSurface {
        nx: 9,
        ny: 7,
        pixel_m: 1e-4,
        rms_m: 1e-5,
        hurst: 0.8,
        modes: 2,
        seed: 3,
    };
    let h = surface.heights_m();
    let options = MeshOptions {
        depth_m: Some(16.0 * 1e-4),
        layers: 3,
        grading: 1.0,
        lateral_coarsening: true,
    };
    let mesh = Mesh::new(&surface.on_grid(&h), &options).unwrap();
    assert_eq!(mesh.layer_steps, [4, 2, 1]);
    assert!(!mesh.hanging.is_empty());
    tangent_equals_differences(&mesh);
}

fn tangent_equals_differences(mesh: &Mesh) {
    let dofs = Dofs::new(mesh, Lateral::Mirror);
    let pattern = Pattern::new(mesh, &dofs);
    // A few percent of strain, varying from node to node.
    let x: Vec<f64> = (0..dofs.count)
        .map(|k| 3e-6 * (((k * 37) % 11) as f64 - 5.0) / 5.0)
        .collect();
    let v: Vec<f64> = (0..dofs.count)
        .map(|k| (((k * 13) % 7) as f64 - 3.0) / 3.0)
        .collect();
    for model in common::every_family() {
        // κ = 50 μ keeps the volumetric terms from hiding the isochoric ones.
        let law = Law::hyperelastic(model.as_ref(), 50.0).unwrap();
        let e = assembly::evaluate(mesh, &dofs, &law, Some(&pattern), &x).unwrap();
        let kv = multiply(&pattern, e.tangent.as_ref().unwrap(), &v);
        let h = 1e-10;
        let shifted = |s: f64| {
            let y: Vec<f64> = x.iter().zip(&v).map(|(a, b)| a + s * b).collect();
            assembly::evaluate(mesh, &dofs, &law, None, &y)
                .unwrap()
                .residual_n
        };
        let (plus, minus) = (shifted(h), shifted(-h));
        let largest = kv.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
        for (k, (p, m)) in plus.iter().zip(&minus).enumerate() {
            let fd = (p - m) / (2.0 * h);
            assert!(
                (fd - kv[k]).abs() < 1e-6 * largest,
                "{} row {k}: K v = {} vs differences {fd}",
                model.family(),
                kv[k]
            );
        }
    }
}

/// The small-strain law's assembled tangent is the same bits at any state
/// (what lets the contact problem assemble it once), and that of a
/// hyperelastic law is not (the check can fail).
#[test]
fn linear_tangent_is_the_same_bits_at_every_state() {
    let surface = SampleSurface {
        nx: 6,
        ny: 5,
        pixel_m: 1e-4,
        rms_m: 1e-5,
        hurst: 0.8,
        modes: 2,
        seed: 5,
    };
    let h = surface.heights_m();
    let mesh = Mesh::new(&surface.on_grid(&h), &MeshOptions::default()).unwrap();
    let dofs = Dofs::new(&mesh, Lateral::Mirror);
    let pattern = Pattern::new(&mesh, &dofs);
    let zero = vec![0.0; dofs.count];
    // Strains of about 0.1 % and 1 %.
    let states: Vec<Vec<f64>> = [1e-7, 1e-6]
        .iter()
        .map(|scale| {
            (0..dofs.count)
                .map(|k| scale * (((k * 37) % 11) as f64 - 5.0) / 5.0)
                .collect()
        })
        .collect();
    let bits = |law: &Law, x: &[f64]| -> Vec<u64> {
        let e = assembly::evaluate(&mesh, &dofs, law, Some(&pattern), x).unwrap();
        e.tangent.unwrap().iter().map(|v| v.to_bits()).collect()
    };
    let linear = Law::linear_elastic(2.0e6, 5000.0).unwrap();
    let hyperelastic =
        Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap();
    let (linear_at_rest, hyperelastic_at_rest) = (bits(&linear, &zero), bits(&hyperelastic, &zero));
    for x in &states {
        assert!(bits(&linear, x) == linear_at_rest);
        assert!(bits(&hyperelastic, x) != hyperelastic_at_rest);
    }
}
