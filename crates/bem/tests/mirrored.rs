//! A periodic map made by mirroring a patch (h[2(n−1) − i] = h[i] along x
//! and y, `crop`'s mirror-image tiling): its curve solves to the top with
//! the default parameters, its pressure is mirror-symmetric, and it agrees
//! with the same map tiled twice and with PK as published. The patch is the
//! 32 × 32 window x 53..85, y 53..85 of a measured 20 µm map, on which the
//! stage failed at step 20 of 40: two solves found the same contact area
//! (mirrored contacts come in pairs), the curve doubled the approach past
//! full contact (max h − mean h), where a periodic contact has no solution.

use hypercontact_bem::stage::{Bem, BemParams, BemResponseTable};
use hypercontact_bem::{
    Boundary, Control, CurveOptions, Influence, Problem, SolveError, SolverOptions, solve_curve,
};
use hypercontact_core::{Context, Field, Inputs, Params, Product, Schema, Stage};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_surface::crop::mirror_extension;

const PIXEL_M: f64 = 2e-5;

fn patch() -> Field {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/t1-window-x53-y53-32.npy"
    );
    Field::read_npy(std::fs::File::open(path).unwrap(), PIXEL_M, PIXEL_M).unwrap()
}

fn mirrored() -> Field {
    mirror_extension(&patch()).unwrap()
}

/// The largest |a(i, j) − a(mirrored i or j)| on an nx × ny map (axis 0
/// first), and the pixels whose contact (a > 0) differs from a mirror's.
fn asymmetry(a: &[f64], nx: usize, ny: usize) -> (f64, usize) {
    let (mut worst, mut contact_differs) = (0.0f64, 0);
    for i in 0..nx {
        for j in 0..ny {
            let v = a[i * ny + j];
            for w in [a[((nx - i) % nx) * ny + j], a[i * ny + (ny - j) % ny]] {
                worst = worst.max((v - w).abs());
                contact_differs += usize::from((v > 0.0) != (w > 0.0));
            }
        }
    }
    (worst, contact_differs)
}

#[test]
fn mirrored_patch_solves_to_the_top_with_the_default_parameters() {
    let surface = mirrored();
    assert_eq!(surface.values.dim(), (62, 62));
    let p = serde_json::from_str::<BemParams>(
        r#"{"boundary": "periodic", "max_area_fraction": 0.4, "map_fractions": [0.1, 0.3],
            "model": "linear"}"#,
    )
    .unwrap()
    .check()
    .unwrap();
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface))
        .with("material", Product::Table(to_table(&paper_epdm())));
    let out = Bem.run(&p, &inputs, &Context::new("bem")).unwrap();
    let r = match out.get("response") {
        Some(Product::Table(t)) => BemResponseTable::from_table(t).unwrap(),
        _ => panic!("no response table"),
    };
    let fractions = &r.response.area_fraction;
    assert_eq!(fractions.len(), 41);
    assert!(fractions[40] >= 0.4, "{}", fractions[40]);
    for k in 1..=40 {
        assert!(r.residual[k] <= 1e-8, "step {k}: {}", r.residual[k]);
        assert!(r.response.load_n[k] > r.response.load_n[k - 1], "step {k}");
    }
    let files = match out.get("contact_maps") {
        Some(Product::Files(f)) => &f.files,
        _ => panic!("no contact maps"),
    };
    for name in ["pressure_a0.100.npy", "pressure_a0.300.npy"] {
        let map = Field::read_npy(files[name].as_slice(), PIXEL_M, PIXEL_M).unwrap();
        let values: Vec<f64> = map.values.iter().copied().collect();
        let peak = values.iter().copied().fold(0.0, f64::max);
        let (worst, contact_differs) = asymmetry(&values, 62, 62);
        assert!(worst <= 1e-12 * peak, "{name}: {worst:e} of {peak:e}");
        assert_eq!(contact_differs, 0, "{name}");
    }
}

#[test]
fn mirrored_pressure_is_symmetric_and_that_of_a_larger_tiling_and_of_pk() {
    let surface = mirrored();
    let (nx, ny) = surface.values.dim();
    let heights: Vec<f64> = surface.values.iter().copied().collect();
    let influence = Influence::new(nx, ny, PIXEL_M, PIXEL_M, Boundary::Periodic);
    let problem = Problem::new(&influence, &heights).unwrap();
    let options = CurveOptions {
        steps: 40,
        max_area_fraction: 0.4,
        solver: SolverOptions {
            max_iterations: 2000,
            ..SolverOptions::default()
        },
    };
    // Every step's pressure mirror-symmetric; keep the one nearest 0.3.
    let mut kept = (f64::INFINITY, 0.0, Vec::new());
    let rows = solve_curve(&problem, options, &mut |k, row, solution| {
        let peak = solution.pressure.iter().copied().fold(0.0, f64::max);
        let (worst, contact_differs) = asymmetry(&solution.pressure, nx, ny);
        assert!(worst <= 1e-12 * peak, "step {k}: {worst:e} of {peak:e}");
        assert_eq!(contact_differs, 0, "step {k}");
        if (row.area_fraction - 0.3).abs() < kept.0 {
            kept = (
                (row.area_fraction - 0.3).abs(),
                row.approach_m,
                solution.pressure.clone(),
            );
        }
    })
    .unwrap();
    assert!(rows[40].area_fraction >= 0.4);
    let (_, approach_m, curve_pressure) = kept;
    let load = |p: &[f64]| p.iter().sum::<f64>() / p.len() as f64;
    // Solves to 1e-11 to compare methods beyond the curve's 1e-8; the
    // curve's load within its accuracy of the tight one.
    let tight = SolverOptions {
        tolerance: 1e-11,
        max_iterations: 20_000,
        preconditioned: true,
    };
    let pressure = problem
        .solve(Control::Approach(approach_m), tight, None)
        .unwrap()
        .pressure;
    let reference = load(&pressure);
    assert!((load(&curve_pressure) / reference - 1.0).abs() < 5e-8);

    // The map tiled 2 × 2 (period twice as long, every odd mode zero)
    // under the same approach: the same pressure in every tile.
    let (tx, ty) = (2 * nx, 2 * ny);
    let tiled: Vec<f64> = (0..tx * ty)
        .map(|k| heights[(k / ty % nx) * ny + k % ty % ny])
        .collect();
    let big = Influence::new(tx, ty, PIXEL_M, PIXEL_M, Boundary::Periodic);
    let big = Problem::new(&big, &tiled)
        .unwrap()
        .solve(Control::Approach(approach_m), tight, None)
        .unwrap();
    assert!((load(&big.pressure) / reference - 1.0).abs() < 1e-10);
    let peak = pressure.iter().copied().fold(0.0, f64::max);
    for (k, &p) in big.pressure.iter().enumerate() {
        let q = pressure[(k / ty % nx) * ny + k % ty % ny];
        assert!((p - q).abs() < 1e-10 * peak, "{k}: {p} vs {q}");
    }
    // PK as published: no preconditioner, restarts at every entry.
    let pk = problem
        .solve(
            Control::Approach(approach_m),
            SolverOptions {
                preconditioned: false,
                ..tight
            },
            None,
        )
        .unwrap();
    assert!((load(&pk.pressure) / reference - 1.0).abs() < 1e-10);
    for (a, b) in pk.pressure.iter().zip(&pressure) {
        assert_eq!(*a > 0.0, *b > 0.0);
        assert!((a - b).abs() < 1e-9 * peak);
    }
}

#[test]
fn approach_past_full_contact_of_a_periodic_map_is_refused() {
    let surface = mirrored();
    let (nx, ny) = surface.values.dim();
    let mut heights: Vec<f64> = surface.values.iter().copied().collect();
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let periodic = Influence::new(nx, ny, PIXEL_M, PIXEL_M, Boundary::Periodic);
    let problem = Problem::new(&periodic, &heights).unwrap();
    let limit_m = problem.full_contact_approach_m().unwrap();
    assert!((limit_m - (top - mean)).abs() < 1e-12 * limit_m);
    for approach_m in [limit_m, 1.4 * limit_m] {
        let refused = problem.solve(
            Control::Approach(approach_m),
            SolverOptions::default(),
            None,
        );
        assert_eq!(
            refused,
            Err(SolveError::BeyondFullContact {
                approach_m,
                limit_m
            })
        );
    }
    // Just short of it, nearly everything touches and the load is finite.
    let near = problem
        .solve(
            Control::Approach(0.997 * limit_m),
            SolverOptions::default(),
            None,
        )
        .unwrap();
    assert!(near.contact_pixels as f64 > 0.85 * (nx * ny) as f64);
    // A free map has no such limit, nor (its mean displacement not fixed)
    // a periodic one with an unmeasured point.
    let free = Influence::new(nx, ny, PIXEL_M, PIXEL_M, Boundary::Free);
    let free = Problem::new(&free, &heights).unwrap();
    assert_eq!(free.full_contact_approach_m(), None);
    free.solve(
        Control::Approach(1.4 * limit_m),
        SolverOptions::default(),
        None,
    )
    .unwrap();
    heights[5] = f64::NAN;
    let holed = Problem::new(&periodic, &heights).unwrap();
    assert_eq!(holed.full_contact_approach_m(), None);
}
