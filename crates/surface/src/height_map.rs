//! Stage `height-map`: loads one height map from a `.npy` file.

use hypercontact_core::{
    Checked, Context, Field, InputPath, Inputs, OutputSpec, Outputs, Stage, StageError, StageInfo,
    params,
};

/// Parameters of `height-map`.
#[params]
pub struct HeightMapParams {
    /// the .npy file (2-D, float64 or float32; axis 0 = x; NaN = missing)
    pub path: InputPath,
    /// grid spacing along x
    #[param(unit = "m", positive)]
    pub pixel_m: f64,
    /// grid spacing along y (default: pixel_m)
    #[param(unit = "m", positive)]
    pub pixel_y_m: Option<f64>,
    /// factor from file units to metres (1e-6 for micrometres)
    #[param(default = 1.0, unit = "m/unit", positive)]
    pub scale_to_m: f64,
}

/// The `height-map` stage.
pub struct HeightMap;

static INFO: StageInfo = StageInfo {
    kind: "height-map",
    version: 1,
    summary: "Load a height map (.npy, metres) with its grid spacing",
    doc: "Reads a 2-D .npy array (float64 or float32) whose axis 0 is x, as the \
          SurfaceTopography package writes it. NaN marks missing points and is kept. \
          Values are multiplied by `scale_to_m`.",
    inputs: &[],
    outputs: &[OutputSpec::field(
        "height",
        "heights in metres, NaN where not measured",
    )],
};

impl Stage for HeightMap {
    type Params = HeightMapParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<HeightMapParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let dy_m = p.pixel_y_m.unwrap_or(p.pixel_m);
        let mut field: Field = ctx.read_field(&p.path, p.pixel_m, dy_m)?;
        if field.values.iter().all(|h| h.is_nan()) {
            return Err(StageError::file(&p.path, "every point is NaN"));
        }
        if let Some(bad) = field.values.iter().find(|h| h.is_infinite()) {
            return Err(StageError::file(
                &p.path,
                format!("holds an infinite height ({bad})"),
            ));
        }
        if p.scale_to_m != 1.0 {
            field.values.mapv_inplace(|h| h * p.scale_to_m);
        }
        Ok(Outputs::new().field("height", field))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params};
    use ndarray::array;
    use serde_json::json;

    #[test]
    fn loads_and_scales_a_map() {
        let dir = std::env::temp_dir().join(format!("hc-hm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.npy");
        let f = Field::new(array![[1.0, 2.0], [f64::NAN, 4.0]], 1.0, 1.0).unwrap();
        f.write_npy(std::fs::File::create(&path).unwrap()).unwrap();
        let params = HeightMapParams {
            path: path.clone().into(),
            pixel_m: 2e-5,
            pixel_y_m: None,
            scale_to_m: 1e-6,
        }
        .check()
        .unwrap();
        let out = HeightMap
            .run(&params, &Inputs::new(), &Context::new("t"))
            .unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        assert_eq!(h.values[[1, 1]], 4e-6);
        assert!(h.values[[1, 0]].is_nan());
        assert_eq!((h.dx_m, h.dy_m), (2e-5, 2e-5));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn missing_path_and_spacing_are_named() {
        let parse = |value| HeightMap.params_from_json(value, std::path::Path::new("."));
        let e = parse(json!({"pixel_m": 2e-5})).unwrap_err();
        assert!(e.message.contains("missing field `path`"), "{e}");
        let e = parse(json!({"path": "x.npy"})).unwrap_err();
        assert!(e.message.contains("missing field `pixel_m`"), "{e}");
        let e = parse(json!({"path": "x.npy", "pixel_m": 0.0})).unwrap_err();
        assert_eq!(e.param, "pixel_m");
    }
}
