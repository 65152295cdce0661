// `Checked` cannot be built around unchecked values: only `Params::check`
// makes one.
use hypercontact_core::Checked;

#[hypercontact_core::params]
struct P {
    #[param(default = 0.5, range = 0.0..=0.5)]
    poisson: f64,
}

fn main() {
    let _ = Checked(P { poisson: 7.0 });
}
