//! The declaration mechanism, end to end on small parameter structs.

use std::path::Path;

use serde_json::json;

use crate::param::{Choice, ParamRange, TypeDoc};
use crate::{Checked, InputPath, ParamError, ParamValue, Params};

/// How a contact law is chosen.
#[derive(Clone, Copy, Debug, PartialEq, crate::Choice)]
enum Law {
    /// The paper's tangent modulus.
    Hyperelastic,
    /// Wang's constant modulus.
    LinearElastic,
    /// A renamed variant.
    #[choice(name = "UT")]
    Uniaxial,
}

/// Weights per mode.
#[crate::params(check = weights_not_all_zero)]
struct Weights {
    /// Uniaxial weight.
    #[param(default = 1.0, range = 0.0.., rename = "UT")]
    ut: f64,
    /// Biaxial weight.
    #[param(default = 1.0, range = 0.0.., rename = "BT")]
    bt: f64,
}

fn weights_not_all_zero(w: &Weights) -> Result<(), ParamError> {
    if w.ut + w.bt > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new("", "at least one weight must be positive"))
    }
}

fn odd(n: &usize) -> Result<(), String> {
    if n % 2 == 1 {
        Ok(())
    } else {
        Err(format!("must be odd, got {n}"))
    }
}

/// A stage's parameters, exercising every kind of declaration.
#[crate::params]
struct Demo {
    /// Poisson's
    /// ratio.
    #[param(default = 0.5, range = 0.0..=0.5)]
    poisson: f64,
    /// Grid spacing.
    #[param(unit = "m", positive)]
    pixel_m: f64,
    /// The law.
    #[param(default = Law::Hyperelastic)]
    law: Law,
    /// Subset size.
    #[param(default = 31, range = 7..=501, check = odd)]
    subset_px: usize,
    /// An optional length.
    #[param(unit = "m", positive)]
    cutoff_m: Option<f64>,
    /// Fractions.
    #[param(default = vec![0.1, 0.5], range = 0.0..1.0)]
    fractions: Vec<f64>,
    /// A file to read.
    table: Option<InputPath>,
    /// More files.
    #[param(default = Vec::new())]
    tiles: Vec<InputPath>,
    /// Nested weights.
    #[param(default = Weights::default())]
    weights: Weights,
    /// A share in (0, 1].
    #[param(default = 0.5, positive, range = ..=1.0)]
    share: f64,
}

fn demo(value: serde_json::Value) -> Result<Demo, serde_json::Error> {
    serde_json::from_value(value)
}

#[test]
fn defaults_fill_in_and_unknown_or_missing_keys_are_errors() {
    let d = demo(json!({"pixel_m": 2e-5})).unwrap();
    assert_eq!(d.poisson, 0.5);
    assert_eq!(d.law, Law::Hyperelastic);
    assert_eq!(d.fractions, [0.1, 0.5]);
    assert_eq!(d.cutoff_m, None);
    assert_eq!(d.weights.ut, 1.0);
    let e = demo(json!({"pixel_m": 1.0, "poison": 0.3})).unwrap_err();
    assert!(e.to_string().contains("unknown field `poison`"), "{e}");
    let e = demo(json!({})).unwrap_err();
    assert!(e.to_string().contains("missing field `pixel_m`"), "{e}");
    let e = demo(json!({"pixel_m": 1.0, "law": "plastic"})).unwrap_err();
    assert!(
        e.to_string()
            .contains("unknown variant `plastic`, expected one of `hyperelastic`"),
        "{e}"
    );
    let e = demo(json!({"pixel_m": 1.0, "weights": {"PT": 1}})).unwrap_err();
    assert!(e.to_string().contains("unknown field `PT`"), "{e}");
}

#[test]
fn checks_name_the_parameter_path() {
    let base = || demo(json!({"pixel_m": 1e-5})).unwrap();
    let err = |d: Demo| d.check().unwrap_err();
    assert!(base().check().is_ok());

    let e = err(Demo {
        poisson: 7.0,
        ..base()
    });
    assert_eq!(e.param, "poisson");
    assert_eq!(e.message, "must lie in [0, 0.5], got 7");
    let e = err(Demo {
        poisson: f64::NAN,
        ..base()
    });
    assert_eq!(e.message, "must lie in [0, 0.5], got NaN");
    let e = err(Demo {
        pixel_m: 0.0,
        ..base()
    });
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("pixel_m", "must be > 0, got 0")
    );
    let e = err(Demo {
        pixel_m: f64::INFINITY,
        ..base()
    });
    assert_eq!(e.message, "must be > 0, got inf");
    let e = err(Demo {
        subset_px: 30,
        ..base()
    });
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("subset_px", "must be odd, got 30")
    );
    let e = err(Demo {
        subset_px: 5,
        ..base()
    });
    assert_eq!(e.message, "must lie in [7, 501], got 5");
    let e = err(Demo {
        cutoff_m: Some(-1.0),
        ..base()
    });
    assert_eq!(e.param, "cutoff_m");
    let e = err(Demo {
        fractions: vec![0.2, 1.0],
        ..base()
    });
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("fractions.1", "must lie in [0, 1), got 1")
    );
    let e = err(Demo {
        weights: Weights { ut: -1.0, bt: 1.0 },
        ..base()
    });
    assert_eq!(e.param, "weights.UT");
    let e = err(Demo {
        weights: Weights { ut: 0.0, bt: 0.0 },
        ..base()
    });
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("weights", "at least one weight must be positive")
    );
    let e = err(Demo {
        share: 0.0,
        ..base()
    });
    assert_eq!(e.message, "must lie in (0, 1], got 0");
    assert!(
        Demo {
            share: 1.0,
            ..base()
        }
        .check()
        .is_ok()
    );
    let e = err(Demo {
        tiles: vec!["a.npy".into(), "".into()],
        ..base()
    });
    assert_eq!(e.param, "tiles.1");
}

#[test]
fn every_input_path_is_visited_wherever_it_is_declared() {
    let mut d = demo(json!({
        "pixel_m": 1.0, "table": "t.csv", "tiles": ["a.npy", "/abs/b.npy"]
    }))
    .unwrap();
    let mut seen = Vec::new();
    d.visit_paths("", &mut |param, path| {
        path.resolve_against(Path::new("/pipelines"));
        seen.push((param.to_owned(), path.path().display().to_string()));
    });
    assert_eq!(
        seen,
        [
            ("table".to_owned(), "/pipelines/t.csv".to_owned()),
            ("tiles.0".to_owned(), "/pipelines/a.npy".to_owned()),
            ("tiles.1".to_owned(), "/abs/b.npy".to_owned()),
        ]
    );
}

#[test]
fn the_spec_holds_each_declaration_once() {
    let spec = Demo::spec();
    let names: Vec<&str> = spec.iter().map(|p| p.name).collect();
    assert_eq!(
        names,
        [
            "poisson",
            "pixel_m",
            "law",
            "subset_px",
            "cutoff_m",
            "fractions",
            "table",
            "tiles",
            "weights",
            "share"
        ]
    );
    let p = &spec[0];
    assert_eq!((p.doc, p.unit), ("Poisson's ratio.", ""));
    assert_eq!(p.default, Some(json!(0.5)));
    assert_eq!(p.range.map(|r| r.to_string()).as_deref(), Some("[0, 0.5]"));
    assert!(!p.required);
    assert!(spec[1].required && spec[1].default.is_none());
    assert_eq!(spec[1].range, Some(ParamRange::POSITIVE));
    assert_eq!(spec[1].unit, "m");
    assert_eq!(spec[2].default, Some(json!("hyperelastic")));
    assert_eq!(spec[2].ty.to_string(), "hyperelastic | linear-elastic | UT");
    assert!(spec[3].custom_check);
    assert!(!spec[4].required && spec[4].default.is_none());
    assert_eq!(spec[4].ty.to_string(), "number (optional)");
    assert_eq!(spec[7].ty.to_string(), "list of path");
    let TypeDoc::Struct(inner) = &spec[8].ty else {
        panic!("weights is a struct")
    };
    assert_eq!(inner[0].name, "UT");
    assert_eq!(spec[8].default, Some(json!({"UT": 1.0, "BT": 1.0})));
}

#[test]
fn choices_read_and_write_their_names() {
    assert_eq!(Law::LinearElastic.to_string(), "linear-elastic");
    assert_eq!("UT".parse::<Law>().unwrap(), Law::Uniaxial);
    let e = "ut".parse::<Law>().unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown value `ut` (expected one of: hyperelastic, linear-elastic, UT)"
    );
    assert_eq!(Law::VARIANTS[0].doc, "The paper's tangent modulus.");
    assert_eq!(serde_json::to_value(Law::Uniaxial).unwrap(), json!("UT"));
    assert_eq!(Law::name(&Law::Hyperelastic), "hyperelastic");
}

#[test]
fn checked_parameters_come_only_from_check() {
    let d = demo(json!({"pixel_m": 1e-5})).unwrap();
    let checked: Checked<Demo> = d.clone().check().unwrap();
    assert_eq!(*checked, d);
    assert_eq!(checked.into_inner(), d);
}

/// A block of parameters several stages share, declared once.
#[crate::params]
struct Shared {
    /// The law.
    #[param(default = Law::Hyperelastic)]
    law: Law,
    /// Poisson's ratio.
    #[param(default = 0.5, range = 0.0..=0.5)]
    poisson: f64,
    /// A file the block reads.
    table: Option<InputPath>,
}

/// A second block, itself holding the first.
#[crate::params]
struct Outer {
    /// First of the outer block's own.
    #[param(default = 3, range = 1..=9)]
    steps: usize,
    #[param(flatten)]
    shared: Shared,
}

/// A stage's parameters with a flattened block between its own.
#[crate::params(check = ordered)]
struct WithBlock {
    /// Required.
    #[param(unit = "m", positive)]
    pixel_m: f64,
    #[param(flatten)]
    outer: Outer,
    /// Last.
    #[param(default = 0.9, positive, range = ..=1.0, rename = "max")]
    max_fraction: f64,
}

fn ordered(p: &WithBlock) -> Result<(), ParamError> {
    if p.outer.steps as f64 > p.max_fraction * 10.0 {
        Err(ParamError::new("steps", "too many for max"))
    } else {
        Ok(())
    }
}

/// The error a stage's parameters give, as the runner reports it: the
/// parameter path from serde_path_to_error and the message.
fn read_error<P: serde::de::DeserializeOwned>(value: serde_json::Value) -> (String, String) {
    let e = serde_path_to_error::deserialize::<_, P>(value)
        .map(|_| ())
        .unwrap_err();
    (e.path().to_string(), e.inner().to_string())
}

#[test]
fn a_flattened_block_reads_writes_checks_and_describes_its_keys_in_place() {
    let p: WithBlock = serde_json::from_value(json!({
        "pixel_m": 1e-5, "poisson": 0.3, "steps": 2, "max": 0.5, "table": "t.csv"
    }))
    .unwrap();
    assert_eq!((p.outer.steps, p.outer.shared.poisson), (2, 0.3));
    assert_eq!(p.outer.shared.law, Law::Hyperelastic);
    let names: Vec<&str> = WithBlock::spec().iter().map(|s| s.name).collect();
    assert_eq!(
        names,
        ["pixel_m", "steps", "law", "poisson", "table", "max"]
    );
    assert_eq!(
        serde_json::to_value(&p).unwrap(),
        json!({"pixel_m": 1e-5, "steps": 2, "law": "hyperelastic", "poisson": 0.3,
               "table": "t.csv", "max": 0.5})
    );
    // Defaults of the blocks fill in; required keys stay required.
    let d: WithBlock = serde_json::from_value(json!({"pixel_m": 1.0})).unwrap();
    assert_eq!(
        (d.outer.steps, d.outer.shared.poisson, d.max_fraction),
        (3, 0.5, 0.9)
    );
    assert!(d.outer.shared.table.is_none());
    let (_, e) = read_error::<WithBlock>(json!({"steps": 2}));
    assert_eq!(e, "missing field `pixel_m`");
    // Checks at the block's keys, at the stage's level.
    let e = WithBlock {
        outer: Outer {
            shared: Shared {
                poisson: 0.7,
                ..Shared::default()
            },
            ..Outer::default()
        },
        ..d.clone()
    }
    .check()
    .unwrap_err();
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("poisson", "must lie in [0, 0.5], got 0.7")
    );
    let e = WithBlock {
        outer: Outer {
            steps: 10,
            ..Outer::default()
        },
        ..d.clone()
    }
    .check()
    .unwrap_err();
    assert_eq!(e.param, "steps");
    let e = WithBlock {
        max_fraction: 0.1,
        ..d.clone()
    }
    .check()
    .unwrap_err();
    assert_eq!(
        (e.param.as_str(), e.message.as_str()),
        ("steps", "too many for max")
    );
    // Paths inside a block are visited at the stage's level.
    let mut p = p;
    let mut seen = Vec::new();
    p.visit_paths("", &mut |param, _| seen.push(param.to_owned()));
    assert_eq!(seen, ["table"]);
}

#[test]
fn a_flattened_blocks_errors_read_as_a_plain_structs_do() {
    // The same parameters declared without blocks: every error must read
    // the same (the runner pins them in its snapshots).
    #[crate::params]
    struct Plain {
        #[param(unit = "m", positive)]
        pixel_m: f64,
        #[param(default = 3, range = 1..=9)]
        steps: usize,
        #[param(default = Law::Hyperelastic)]
        law: Law,
        #[param(default = 0.5, range = 0.0..=0.5)]
        poisson: f64,
        table: Option<InputPath>,
        #[param(default = 0.9, positive, range = ..=1.0, rename = "max")]
        max_fraction: f64,
    }
    let cases = [
        json!({"pixel_m": 1.0, "poison": 0.3}),
        json!({"pixel_m": 1.0, "law": "plastic"}),
        json!({"pixel_m": 1.0, "poisson": "half"}),
        json!({"pixel_m": 1.0, "steps": -2}),
        json!({"pixel_m": 1.0, "table": 3}),
        json!({"pixel_m": "one"}),
        json!({"steps": 1}),
        json!("text"),
    ];
    for case in cases {
        let flat = read_error::<WithBlock>(case.clone());
        let plain = read_error::<Plain>(case.clone());
        assert_eq!(
            flat.0, plain.0,
            "path for {case}: {flat:?} against {plain:?}"
        );
        let msg = |m: &str| m.replace("WithBlock", "Plain");
        assert_eq!(msg(&flat.1), plain.1, "message for {case}");
    }
    // A list is not read positionally (serde's derive would).
    let (_, e) = read_error::<WithBlock>(json!([1.0, 2]));
    assert_eq!(e, "invalid type: sequence, expected struct WithBlock");
}

#[test]
fn a_quoted_number_is_refused_with_how_to_write_it() {
    use crate::param::{explain_quoted_number, quoted_number_advice};
    // YAML types "10" as text: serde refuses it for a number, and the
    // message gains the advice (before #31 it ended at `expected usize`).
    let (path, e) = read_error::<Demo>(json!({ "pixel_m": 1e-5, "subset_px": "31" }));
    assert_eq!(path, "subset_px");
    assert_eq!(
        explain_quoted_number(&e),
        "invalid type: string \"31\", expected usize; a number is written without quotes: \
         write 31, not \"31\""
    );
    let (_, e) = read_error::<Demo>(json!({ "pixel_m": "1e-5" }));
    assert!(
        explain_quoted_number(&e).ends_with("write 1e-5, not \"1e-5\""),
        "{e}"
    );
    // Text that is no number, or a string where text is expected, keeps
    // serde's message.
    let (_, e) = read_error::<Demo>(json!({ "pixel_m": 1e-5, "subset_px": "many" }));
    assert_eq!(explain_quoted_number(&e), e);
    assert_eq!(
        explain_quoted_number("invalid type: string \"10\", expected a boolean"),
        "invalid type: string \"10\", expected a boolean"
    );
    assert_eq!(
        quoted_number_advice(" 10 ").as_deref(),
        Some("a number is written without quotes: write 10, not \" 10 \"")
    );
    assert_eq!(quoted_number_advice("ten"), None);
}
