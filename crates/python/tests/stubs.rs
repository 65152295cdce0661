//! The committed type stub equals what the declarations give today, so an
//! editor never completes a parameter that is gone; and no stage declares a
//! name the generated functions keep for themselves.

use std::collections::BTreeSet;
use std::path::Path;

use _hypercontact::stubs::{RESERVED, attribute, stages_pyi};

const STUB: &str = "python/hypercontact/stages.pyi";

#[test]
fn committed_stub_is_generated_from_the_declarations() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(STUB);
    let generated = stages_pyi(&hypercontact::registry());
    if std::env::var_os("HYPERCONTACT_WRITE_STUBS").is_some() {
        std::fs::write(&path, &generated).expect("stub written");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{} is not what the stage declarations give; rewrite it with \
         HYPERCONTACT_WRITE_STUBS=1 cargo test --release -p hypercontact-python --test stubs",
        path.display()
    );
}

#[test]
fn stub_names_every_kind_with_its_parameters() {
    let registry = hypercontact::registry();
    let stub = stages_pyi(&registry);
    for stage in registry.iter() {
        let name = attribute(stage.info().kind);
        assert!(stub.contains(&format!("\ndef {name}(\n")), "{name}");
    }
    // One concrete declaration, as an editor would show it.
    assert!(stub.contains("    boundary: Literal[\"free\", \"periodic\"] = \"free\",\n"));
    assert!(stub.contains("    steps: int = 40,\n"));
    assert!(stub.contains("    surface: Field,\n"));
}

#[test]
fn no_stage_declares_a_reserved_or_clashing_name() {
    let registry = hypercontact::registry();
    let mut attributes = BTreeSet::new();
    for stage in registry.iter() {
        let info = stage.info();
        assert!(
            attributes.insert(attribute(info.kind)),
            "two kinds map to the Python name {}",
            attribute(info.kind)
        );
        let params: Vec<&str> = stage.params_spec().iter().map(|p| p.name).collect();
        for name in params
            .iter()
            .copied()
            .chain(info.inputs.iter().map(|i| i.name))
        {
            assert!(
                !RESERVED.contains(&name),
                "{}: `{name}` is reserved",
                info.kind
            );
        }
        for input in info.inputs {
            assert!(
                !params.contains(&input.name),
                "{}: `{}` is both an input and a parameter",
                info.kind,
                input.name
            );
        }
    }
}
