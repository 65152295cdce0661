//! Median wall time of the 1-D (x, y) and radial PSDs of an n × n synthetic
//! map, for a side-by-side with SurfaceTopography's timing script.
//!
//! Run: `cargo run -p hypercontact-surface --release --example psd_timing -- 4096 7`
//! (arguments: map size n, number of runs).

use std::time::Instant;

use hypercontact_surface::psd::{Window, psd_radial, psd_x, psd_y};
use hypercontact_synth::surface::SelfAffine;

fn median_s(runs: usize, mut f: impl FnMut()) -> f64 {
    f(); // warm-up
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[runs / 2]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .map_or(4096, |a| a.parse().expect("n: map size"));
    let runs: usize = args.next().map_or(7, |a| a.parse().expect("runs: count"));
    let pixel_m = 1e-6;
    let h = SelfAffine::MICRON.periodic(n, n, pixel_m, 4);
    println!(
        "n = {n}, runs = {runs}, threads = {}",
        rayon::current_num_threads()
    );
    for (name, window) in [("hann", Window::Hann), ("periodic", Window::None)] {
        let x = median_s(runs, || {
            std::hint::black_box(psd_x(&h, pixel_m, window, 10));
        });
        let y = median_s(runs, || {
            std::hint::black_box(psd_y(&h, pixel_m, window, 10));
        });
        let r = median_s(runs, || {
            std::hint::black_box(psd_radial(&h, pixel_m, pixel_m, window, 10));
        });
        println!("{name:9} x {x:.4} s   y {y:.4} s   radial {r:.4} s");
    }
}
