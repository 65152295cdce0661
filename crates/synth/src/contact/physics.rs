//! The experiment's physics in words: which solver, law, modulus and
//! boundary rendered the frames. Written into every row of the `truth`
//! table, so that a comparison (contact-compare's `truth`) and the report
//! can say which model shares it, and so agrees by construction.

use hypercontact_bem::Boundary;
use hypercontact_core::param::Choice;
use hypercontact_icm::{Model, Tangent};

/// The physics of a `synth-contact` run: the `bem` solver with `boundary`,
/// under `model` and `tangent`; a linear material is linear elastic
/// whatever the law says (its own constant E*).
pub fn label(model: Model, tangent: Tangent, boundary: Boundary, linear_material: bool) -> String {
    let law = if linear_material {
        "linear elastic, the material's own modulus".to_owned()
    } else {
        match model {
            Model::Linear => "linear elastic, small-strain modulus".to_owned(),
            Model::Hyperelastic => format!("hyperelastic, {} tangent", tangent.name()),
        }
    };
    format!("bem, {law}, {} boundary", boundary.name())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_law_tangent_and_boundary_are_named() {
        let free = Boundary::Free;
        assert_eq!(
            label(Model::Hyperelastic, Tangent::Equibiaxial, free, false),
            "bem, hyperelastic, equibiaxial tangent, free boundary"
        );
        assert_eq!(
            label(
                Model::Hyperelastic,
                Tangent::Uniaxial,
                Boundary::Periodic,
                false
            ),
            "bem, hyperelastic, uniaxial tangent, periodic boundary"
        );
        // A linear law has no tangent: the same physics whichever is set.
        for tangent in [Tangent::Equibiaxial, Tangent::Uniaxial] {
            assert_eq!(
                label(Model::Linear, tangent, free, false),
                "bem, linear elastic, small-strain modulus, free boundary"
            );
        }
        assert_eq!(
            label(Model::Hyperelastic, Tangent::Equibiaxial, free, true),
            "bem, linear elastic, the material's own modulus, free boundary"
        );
    }
}
