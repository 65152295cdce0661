use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{HeightMap, Lateral, Law, Mesh, MeshOptions};
use hypercontact_fem::{assembly, dofs::Dofs, linear_solver::LinearSolver};
use std::time::Instant;

fn main() {
    let n = 32;
    let s = SampleSurface {
        nx: n,
        ny: n,
        pixel_m: 20e-6,
        rms_m: 3e-6,
        hurst: 0.8,
        modes: 8,
        seed: 1,
    };
    let h = s.heights_m();
    let map = HeightMap {
        heights_m: &h,
        nx: n,
        ny: n,
        dx_m: 20e-6,
        dy_m: 20e-6,
    };
    let mesh = Mesh::new(&map, &MeshOptions::default()).unwrap();
    for law in [
        Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap(),
        Law::hyperelastic(
            &hypercontact_material::NeoHookean::new(0.9e6).unwrap(),
            5000.0,
        )
        .unwrap(),
    ] {
        let dofs = Dofs::new(&mesh, Lateral::Mirror);
        let t = Instant::now();
        let pattern = assembly::Pattern::new(&mesh, &dofs);
        println!("pattern {:?} nnz {}", t.elapsed(), pattern.row_idx.len());
        let t = Instant::now();
        let order = hypercontact_fem::ordering::nested_dissection(&mesh, &dofs);
        let mut solver = LinearSolver::new(
            &pattern,
            if std::env::var("AMD").is_ok() {
                None
            } else {
                Some(&order)
            },
        )
        .unwrap();
        println!(
            "symbolic {:?} L values {}",
            t.elapsed(),
            solver.factor_len()
        );
        let x: Vec<f64> = (0..dofs.count)
            .map(|k| 1e-7 * ((k % 7) as f64 - 3.0))
            .collect();
        let phase = std::env::var("PHASE").unwrap_or_default();
        let reps = 5;
        if phase == "tangent" {
            for _ in 0..reps {
                assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &x).unwrap();
            }
            return;
        }
        if phase == "residual" {
            for _ in 0..reps {
                assembly::evaluate(&mesh, &dofs, &law, None, &x).unwrap();
            }
            return;
        }
        if phase == "factor" {
            let e = assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &x).unwrap();
            for _ in 0..reps {
                solver.factor(e.tangent.as_ref().unwrap()).unwrap();
            }
            return;
        }
        if phase == "none" {
            let _e = assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &x).unwrap();
            return;
        }
        let t = Instant::now();
        let e = assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &x).unwrap();
        println!("tangent assembly {:?}", t.elapsed());
        let t = Instant::now();
        let _ = assembly::evaluate(&mesh, &dofs, &law, None, &x).unwrap();
        println!("residual assembly {:?}", t.elapsed());
        let t = Instant::now();
        let kind = solver.factor(e.tangent.as_ref().unwrap()).unwrap();
        println!("factor {:?} {kind:?}", t.elapsed());
        let mut r = e.residual_n.clone();
        let t = Instant::now();
        solver.solve(&mut r);
        println!("solve {:?}", t.elapsed());
    }
}
