// A stage's `run` takes checked parameters only.
use hypercontact_core::{Checked, Context, Inputs, Outputs, Stage, StageError, StageInfo};

#[hypercontact_core::params]
struct P {
    #[param(default = 0.5, range = 0.0..=0.5)]
    poisson: f64,
}

struct S;

static INFO: StageInfo = StageInfo {
    kind: "s",
    version: 1,
    summary: "",
    doc: "",
    inputs: &[],
    outputs: &[],
};

impl Stage for S {
    type Params = P;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(&self, _: &Checked<P>, _: &Inputs, _: &Context) -> Result<Outputs, StageError> {
        Ok(Outputs::new())
    }
}

fn main() {
    let _ = S.run(&P { poisson: 7.0 }, &Inputs::new(), &Context::new("s"));
}
