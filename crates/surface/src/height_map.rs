//! Stage `height-map`: loads one height map from a `.npy` file.

use std::path::PathBuf;

use hypercontact_core::params::positive;
use hypercontact_core::product::ProductKind;
use hypercontact_core::{
    Context, Field, Inputs, OutputSpec, Outputs, ParamDoc, ParamError, Params, Stage, StageError,
    StageInfo,
};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HeightMapParams {
    /// The `.npy` file (2-D, float64 or float32; axis 0 = x; NaN = missing).
    pub path: PathBuf,
    /// Grid spacing along x, metres.
    pub pixel_m: f64,
    /// Grid spacing along y, metres; the same as x when omitted.
    pub pixel_y_m: Option<f64>,
    /// Factor turning the file's values into metres (1e-6 for micrometres).
    pub scale_to_m: f64,
}

impl Default for HeightMapParams {
    fn default() -> Self {
        Self {
            path: PathBuf::new(),
            pixel_m: 0.0,
            pixel_y_m: None,
            scale_to_m: 1.0,
        }
    }
}

impl Params for HeightMapParams {
    fn check(&self) -> Result<(), ParamError> {
        if self.path.as_os_str().is_empty() {
            return Err(ParamError::new("path", "is required (a .npy height map)"));
        }
        positive("pixel_m", self.pixel_m)?;
        if let Some(dy) = self.pixel_y_m {
            positive("pixel_y_m", dy)?;
        }
        positive("scale_to_m", self.scale_to_m)
    }

    fn paths_mut(&mut self) -> Vec<&mut PathBuf> {
        vec![&mut self.path]
    }
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
    params: &[
        ParamDoc {
            name: "path",
            unit: "",
            doc: "the .npy file, relative to the pipeline file",
        },
        ParamDoc {
            name: "pixel_m",
            unit: "m",
            doc: "grid spacing along x",
        },
        ParamDoc {
            name: "pixel_y_m",
            unit: "m",
            doc: "grid spacing along y (default: pixel_m)",
        },
        ParamDoc {
            name: "scale_to_m",
            unit: "m/unit",
            doc: "factor from file units to metres",
        },
    ],
    inputs: &[],
    outputs: &[OutputSpec {
        name: "height",
        kind: ProductKind::Field,
        columns: &[],
        doc: "heights in metres, NaN where not measured",
    }],
};

impl Stage for HeightMap {
    type Params = HeightMapParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(&self, p: &HeightMapParams, _: &Inputs, ctx: &Context) -> Result<Outputs, StageError> {
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
    use ndarray::array;

    #[test]
    fn loads_and_scales_a_map() {
        let dir = std::env::temp_dir().join(format!("hc-hm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.npy");
        let f = Field::new(array![[1.0, 2.0], [f64::NAN, 4.0]], 1.0, 1.0).unwrap();
        f.write_npy(std::fs::File::create(&path).unwrap()).unwrap();
        let params = HeightMapParams {
            path: path.clone(),
            pixel_m: 2e-5,
            scale_to_m: 1e-6,
            ..Default::default()
        };
        params.check().unwrap();
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
        let e = HeightMapParams::default().check().unwrap_err();
        assert_eq!(e.param, "path");
        let e = HeightMapParams {
            path: "x.npy".into(),
            ..Default::default()
        }
        .check()
        .unwrap_err();
        assert_eq!(e.param, "pixel_m");
    }
}
