//! Contact pixel counts of a `.npy` map under given mean pressures
//! (in units of E*), for side-by-side runs with other BEM codes (tamaas,
//! ContactMechanics) on the same map.
//!
//! Run: `cargo run -p hypercontact-bem --release --example contact_counts --
//! MAP.npy PIXEL_M TOLERANCE P1 P2 ... [--save DIR] [--free]` (`--save`
//! writes each pressure map as DIR/bem_p_<P>.npy; `--free` solves the map as
//! a finite sample instead of a periodic one), or with `write MAP.npy N SEED` to write
//! a periodic self-affine N × N map (H = 0.8, rms 1, pixel 1/N) first.

use std::time::Instant;

use hypercontact_bem::{Boundary, Control, Influence, Problem, SolverOptions};
use hypercontact_core::Field;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let boundary = match args.iter().position(|a| a == "--free") {
        Some(k) => {
            args.remove(k);
            Boundary::Free
        }
        None => Boundary::Periodic,
    };
    let save = match args.iter().position(|a| a == "--save") {
        Some(k) => {
            let dir = args.get(k + 1).cloned().expect("--save DIR");
            args.drain(k..k + 2);
            Some(dir)
        }
        None => None,
    };
    if args.first().map(String::as_str) == Some("write") {
        let n: usize = args[2].parse().expect("N");
        let seed: u64 = args[3].parse().expect("SEED");
        let pixel = 1.0 / n as f64;
        let surface = hypercontact_synth::surface::SelfAffine {
            hurst: 0.8,
            rms_m: 1.0,
            lambda_min_m: 2.0 * pixel,
            lambda_max_m: 1.0,
        }
        .periodic(n, n, pixel, seed);
        let file = std::fs::File::create(&args[1]).expect("create the map");
        Field::new(surface, pixel, pixel)
            .and_then(|f| f.write_npy(file))
            .expect("write the map");
        return;
    }
    let [path, pixel, tolerance, loads @ ..] = args.as_slice() else {
        panic!("usage: MAP.npy PIXEL_M TOLERANCE P1 P2 ...");
    };
    let pixel: f64 = pixel.parse().expect("PIXEL_M");
    let tolerance: f64 = tolerance.parse().expect("TOLERANCE");
    let field = Field::read_npy(
        std::fs::File::open(path).expect("open the map"),
        pixel,
        pixel,
    )
    .expect("read the map");
    let (nx, ny) = (field.nx(), field.ny());
    let heights: Vec<f64> = field.values.iter().copied().collect();
    let influence = Influence::new(nx, ny, pixel, pixel, boundary);
    let problem = Problem::new(&influence, &heights).expect("a contact problem");
    let options = SolverOptions {
        tolerance,
        max_iterations: 100_000,
        ..SolverOptions::default()
    };
    for load in loads {
        let mean: f64 = load.parse().expect("a mean pressure");
        let started = Instant::now();
        let s = problem
            .solve(Control::MeanPressure(mean), options, None)
            .expect("a solution");
        println!(
            "p/E* {mean}: {} contact pixels, {} iterations, {:.2?}",
            s.contact_pixels,
            s.iterations,
            started.elapsed()
        );
        if let Some(dir) = &save {
            let map = ndarray::Array2::from_shape_vec((nx, ny), s.pressure).expect("the grid");
            let file = std::fs::File::create(format!("{dir}/bem_p_{load}.npy")).expect("create");
            Field::new(map, pixel, pixel)
                .and_then(|f| f.write_npy(file))
                .expect("write the pressure");
        }
    }
}
