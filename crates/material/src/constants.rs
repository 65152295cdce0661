//! A material by its constants: a family and its parameters as the user
//! writes them (units in the names, moduli in Pa), checked per family, and
//! turned into the [`Material`] the `material` stage writes.
//!
//! The parameters follow Abaqus' conventions ("Hyperelastic behavior of
//! rubberlike materials"), as the families in this crate do: neo-Hookean
//! W = (μ/2)(I1 − 3), so `mu_pa` is the initial shear modulus μ0 and the
//! table's C10 = μ/2; Mooney–Rivlin C10, C01; Yeoh C10, C20, C30;
//! Arruda–Boyce μ and λm (μ0 = μ times its series factor); Ogden μ_i, α_i
//! with W = Σ 2μ_i/α_i² (…), μ0 = Σ μ_i. A linear solid is E and ν.

use hypercontact_core::param::{Choice, ParamRange, RangeCheck, TypeDoc};
use hypercontact_core::{InputPath, ParamError, ParamValue};

use crate::material::{LinearElastic, Material};
use crate::{ArrudaBoyce, Hyperelastic, MooneyRivlin, NeoHookean, Ogden, Yeoh};

/// The families a material can be given in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, hypercontact_core::Choice)]
pub enum Constants {
    /// linear elastic: `e_pa`, `poisson` (default 0.5)
    Linear,
    /// W = (μ/2)(I1 − 3): `mu_pa`
    NeoHookean,
    /// W = C10 (I1 − 3) + C01 (I2 − 3): `c10_pa`, `c01_pa`
    MooneyRivlin,
    /// W = C10 (I1 − 3) + C20 (I1 − 3)² + C30 (I1 − 3)³: `c10_pa`, `c20_pa`, `c30_pa`
    Yeoh,
    /// eight-chain, Abaqus' five-term series: `mu_pa`, `lambda_m`
    ArrudaBoyce,
    /// W = Σ 2μ_i/α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3): `mu_pa` and `alpha`, lists of one length
    Ogden,
}

impl Constants {
    /// The parameters the family takes, required ones first; `poisson` is
    /// optional for `linear` (½ when absent).
    pub fn parameters(self) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            Constants::Linear => (&["e_pa"], &["poisson"]),
            Constants::NeoHookean => (&["mu_pa"], &[]),
            Constants::MooneyRivlin => (&["c10_pa", "c01_pa"], &[]),
            Constants::Yeoh => (&["c10_pa", "c20_pa", "c30_pa"], &[]),
            Constants::ArrudaBoyce => (&["mu_pa", "lambda_m"], &[]),
            Constants::Ogden => (&["mu_pa", "alpha"], &[]),
        }
    }
}

/// One number or a list of them (`mu_pa: 6e5`, `mu_pa: [1.2e6, -2e5]`):
/// Ogden takes lists where the other families take one value.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Numbers {
    One(f64),
    List(Vec<f64>),
}

/// Read by hand rather than `#[serde(untagged)]`, whose error ("did not
/// match any variant") would not say what was expected or where.
impl<'de> serde::Deserialize<'de> for Numbers {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct NumbersVisitor;

        impl<'de> serde::de::Visitor<'de> for NumbersVisitor {
            type Value = Numbers;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or a list of numbers")
            }

            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Numbers, E> {
                Ok(Numbers::One(v))
            }

            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Numbers, E> {
                Ok(Numbers::One(v as f64))
            }

            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Numbers, E> {
                Ok(Numbers::One(v as f64))
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Numbers, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(Numbers::List(values))
            }
        }

        d.deserialize_any(NumbersVisitor)
    }
}

impl Numbers {
    pub fn values(&self) -> &[f64] {
        match self {
            Numbers::One(v) => std::slice::from_ref(v),
            Numbers::List(values) => values,
        }
    }
}

impl ParamValue for Numbers {
    fn type_doc() -> TypeDoc {
        TypeDoc::Custom("number or list of numbers".into())
    }

    fn validate_at(&self, _: &str) -> Result<(), ParamError> {
        Ok(())
    }

    fn visit_paths(&mut self, _: &str, _: &mut dyn FnMut(&str, &mut InputPath)) {}
}

impl RangeCheck for Numbers {
    fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError> {
        match self {
            Numbers::One(v) => v.check_in(path, range),
            Numbers::List(values) => values.check_in(path, range),
        }
    }
}

/// A family's parameter values by name, as given (YAML or a parameter
/// file): what [`material`] checks and builds from.
pub trait Given {
    /// The values of parameter `name`, None when it was not given.
    fn get(&self, name: &str) -> Option<&[f64]>;
}

/// Every parameter name any family takes, in the stage's order.
pub const NAMES: [&str; 9] = [
    "e_pa", "poisson", "mu_pa", "alpha", "c10_pa", "c01_pa", "c20_pa", "c30_pa", "lambda_m",
];

/// The material of `family` from the given parameters: unknown or
/// irrelevant ones refused, missing ones named, values checked, each error
/// naming its parameter.
pub fn material(family: Constants, given: &dyn Given) -> Result<Material, ParamError> {
    let (required, optional) = family.parameters();
    let takes = || -> String {
        let all: Vec<String> = required
            .iter()
            .chain(optional)
            .map(|n| format!("`{n}`"))
            .collect();
        all.join(", ")
    };
    for name in NAMES {
        if given.get(name).is_some() && !required.contains(&name) && !optional.contains(&name) {
            return Err(ParamError::new(
                name,
                format!(
                    "family `{}` does not take it (it takes {})",
                    family.name(),
                    takes()
                ),
            ));
        }
    }
    for name in required {
        if given.get(name).is_none() {
            return Err(ParamError::new(
                name,
                format!("family `{}` needs it (it takes {})", family.name(), takes()),
            ));
        }
    }
    let material = build(family, given)?;
    check_magnitudes(given)?;
    if let Material::Hyperelastic(model) = &material {
        check_stable(model.as_ref(), family)?;
    }
    Ok(material)
}

/// The values of parameter `name`, none if it was not given.
fn values_of<'a>(given: &'a dyn Given, name: &str) -> &'a [f64] {
    given.get(name).unwrap_or(&[])
}

/// The material from the values of a family's parameters, all present.
fn build(family: Constants, given: &dyn Given) -> Result<Material, ParamError> {
    let values = |name: &str| values_of(given, name);
    let one = |name: &str| -> Result<f64, ParamError> {
        match values(name) {
            [v] if v.is_finite() => Ok(*v),
            [v] => Err(ParamError::new(name, format!("must be finite, got {v}"))),
            list => Err(ParamError::new(
                name,
                format!(
                    "family `{}` takes one value, got {}",
                    family.name(),
                    list.len()
                ),
            )),
        }
    };
    let positive = |name: &str, what: &str| -> Result<f64, ParamError> {
        let v = one(name)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(ParamError::new(
                name,
                format!("{what} must be > 0, got {v}"),
            ))
        }
    };
    let model: Box<dyn Hyperelastic> = match family {
        Constants::Linear => {
            let e_pa = positive("e_pa", "Young's modulus")?;
            let poisson = match values("poisson") {
                [] => 0.5,
                _ => one("poisson")?,
            };
            return LinearElastic::new(e_pa, poisson)
                .map(Material::Linear)
                .map_err(|e| ParamError::new("poisson", e.to_string()));
        }
        Constants::NeoHookean => Box::new(invalid(
            "mu_pa",
            NeoHookean::new(positive("mu_pa", "the shear modulus")? / 2.0),
        )?),
        Constants::MooneyRivlin => {
            let (c10, c01) = (one("c10_pa")?, one("c01_pa")?);
            if c10 + c01 <= 0.0 {
                return Err(ParamError::new(
                    "c01_pa",
                    format!("μ0 = 2 (C10 + C01) must be > 0, got C10 = {c10}, C01 = {c01}"),
                ));
            }
            Box::new(invalid("c10_pa", MooneyRivlin::new(c10, c01))?)
        }
        Constants::Yeoh => {
            let c10 = positive("c10_pa", "C10 (μ0/2)")?;
            Box::new(invalid(
                "c10_pa",
                Yeoh::new(c10, one("c20_pa")?, one("c30_pa")?),
            )?)
        }
        Constants::ArrudaBoyce => {
            let mu = positive("mu_pa", "μ")?;
            let lambda_m = one("lambda_m")?;
            if lambda_m <= 1.0 {
                return Err(ParamError::new(
                    "lambda_m",
                    format!("the locking stretch must be > 1, got {lambda_m}"),
                ));
            }
            Box::new(invalid("lambda_m", ArrudaBoyce::new(mu, lambda_m))?)
        }
        Constants::Ogden => Box::new(ogden(values("mu_pa"), values("alpha"))?),
    };
    Ok(Material::from(model))
}

/// The moduli a solid can have, Pa: a value outside is a typo or a unit
/// slip (rubbers are 1e5–1e7 Pa, steel 2e11 Pa).
pub const MODULUS_RANGE_PA: (f64, f64) = (1.0, 1e12);

/// The parameters that are moduli (Pa).
const MODULI: [&str; 6] = ["e_pa", "mu_pa", "c10_pa", "c01_pa", "c20_pa", "c30_pa"];

/// Refuses a modulus of absurd size, naming it: any term beyond
/// [`MODULUS_RANGE_PA`]'s upper end in size (a term may be negative or
/// zero), and a non-zero term below 1 Pa in size, which no solid has.
fn check_magnitudes(given: &dyn Given) -> Result<(), ParamError> {
    let (low, high) = MODULUS_RANGE_PA;
    for name in MODULI {
        let values = values_of(given, name);
        for (i, v) in values.iter().enumerate() {
            let size = v.abs();
            if size <= high && (size >= low || *v == 0.0) {
                continue;
            }
            let at = match values.len() {
                1 => name.to_owned(),
                _ => format!("{name}.{i}"),
            };
            return Err(ParamError::new(
                &at,
                format!(
                    "{v:e} Pa is no solid's modulus: a modulus term is 0 or {low} to \
                     {high:e} Pa in size (rubbers are 1e5 to 1e7 Pa); check the unit"
                ),
            ));
        }
    }
    Ok(())
}

/// The stretches over which `material` requires Drucker stability in
/// uniaxial, planar and equibiaxial loading: the contact models' range
/// (the paper's strains reach ε ≈ 0.5 in biaxial tension; compression to
/// 0.7 is equibiaxial thickening to 2.04).
pub const STABLE_STRETCHES: (f64, f64) = (0.7, 1.5);

/// Refuses a law that is Drucker-unstable somewhere in
/// [`STABLE_STRETCHES`] in any of the three tests, naming the test, where
/// it turns unstable and the parameters to look at (Abaqus' check, as the
/// fit reports it: [`crate::stability`]).
fn check_stable(model: &dyn Hyperelastic, family: Constants) -> Result<(), ParamError> {
    let (low, high) = STABLE_STRETCHES;
    for range in crate::stability::stability_ranges(model) {
        let unstable = if !range.stable_at_rest {
            Some("at rest (λ = 1)".to_owned())
        } else if range.lambda_min > low {
            Some(format!("below λ = {:.4}", range.lambda_min))
        } else if range.lambda_max < high {
            Some(format!("above λ = {:.4}", range.lambda_max))
        } else {
            None
        };
        let Some(unstable) = unstable else {
            continue;
        };
        let (required, _) = family.parameters();
        return Err(ParamError::new(
            required[0],
            format!(
                "the {} law with these constants is Drucker-unstable in {} {unstable}, inside \
                 the stretches it must hold over ({low} ≤ λ ≤ {high} in UT, PT and BT); check \
                 the signs and sizes of {}",
                family.name(),
                range.mode.label(),
                required
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    Ok(())
}

/// An Ogden model from its lists: one length, α_i finite and non-zero,
/// μ_i finite, μ0 = Σ μ_i > 0.
fn ogden(mu_pa: &[f64], alpha: &[f64]) -> Result<Ogden, ParamError> {
    if mu_pa.len() != alpha.len() {
        return Err(ParamError::new(
            "alpha",
            format!(
                "gives {} exponents for {} moduli in `mu_pa`: one α_i per μ_i",
                alpha.len(),
                mu_pa.len()
            ),
        ));
    }
    if mu_pa.is_empty() {
        return Err(ParamError::new("mu_pa", "needs at least one term"));
    }
    if let Some(i) = alpha.iter().position(|a| *a == 0.0 || !a.is_finite()) {
        let at = format!("alpha.{i}");
        return Err(ParamError::new(
            &at,
            format!("must be finite and non-zero, got {}", alpha[i]),
        ));
    }
    if let Some(i) = mu_pa.iter().position(|m| !m.is_finite()) {
        let at = format!("mu_pa.{i}");
        return Err(ParamError::new(
            &at,
            format!("must be finite, got {}", mu_pa[i]),
        ));
    }
    let mu0: f64 = mu_pa.iter().sum();
    if !(mu0 > 0.0 && mu0.is_finite()) {
        return Err(ParamError::new(
            "mu_pa",
            format!("μ0 = Σ μ_i must be > 0, got {mu0} Pa"),
        ));
    }
    invalid("mu_pa", Ogden::new(mu_pa.to_vec(), alpha.to_vec()))
}

/// A model constructor's own refusal, at parameter `name`.
fn invalid<M>(name: &str, built: Result<M, crate::MaterialError>) -> Result<M, ParamError> {
    built.map_err(|e| ParamError::new(name, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    impl Given for BTreeMap<&str, Vec<f64>> {
        fn get(&self, name: &str) -> Option<&[f64]> {
            BTreeMap::get(self, name).map(Vec::as_slice)
        }
    }

    /// A parameter's name and values.
    type Pair<'a> = (&'static str, &'a [f64]);

    fn given(pairs: &[Pair]) -> BTreeMap<&'static str, Vec<f64>> {
        pairs.iter().map(|(n, v)| (*n, v.to_vec())).collect()
    }

    #[test]
    fn each_family_builds_its_model_with_mu0_as_given() {
        let cases: [(Constants, &[Pair], f64); 5] = [
            (Constants::NeoHookean, &[("mu_pa", &[6e5])], 6e5),
            (
                Constants::MooneyRivlin,
                &[("c10_pa", &[2e5]), ("c01_pa", &[5e4])],
                5e5,
            ),
            (
                Constants::Yeoh,
                &[("c10_pa", &[2e5]), ("c20_pa", &[-1e4]), ("c30_pa", &[1e3])],
                4e5,
            ),
            (
                Constants::Ogden,
                &[("mu_pa", &[7e5, -1e5]), ("alpha", &[2.0, -2.0])],
                6e5,
            ),
            (
                Constants::ArrudaBoyce,
                &[("mu_pa", &[3e5]), ("lambda_m", &[1e9])],
                3e5,
            ),
        ];
        for (family, pairs, mu0) in cases {
            let Material::Hyperelastic(m) = material(family, &given(pairs)).unwrap() else {
                panic!("{family:?} is hyperelastic")
            };
            assert!(
                (m.shear_modulus_pa() / mu0 - 1.0).abs() < 1e-12,
                "{family:?}"
            );
        }
        let linear = material(Constants::Linear, &given(&[("e_pa", &[2e6])])).unwrap();
        let Material::Linear(solid) = linear else {
            panic!("linear")
        };
        assert_eq!((solid.e_pa, solid.poisson), (2e6, 0.5));
    }

    #[test]
    fn irrelevant_missing_and_bad_parameters_are_named() {
        let e = material(
            Constants::NeoHookean,
            &given(&[("mu_pa", &[6e5]), ("c01_pa", &[1e4])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "c01_pa");
        assert!(e.message.contains("`neo-hookean` does not take it"), "{e}");
        let e = material(Constants::MooneyRivlin, &given(&[("c10_pa", &[1e5])])).unwrap_err();
        assert_eq!(e.param, "c01_pa");
        assert!(e.message.contains("needs it"), "{e}");
        let e = material(
            Constants::Ogden,
            &given(&[("mu_pa", &[1e5, 2e5]), ("alpha", &[2.0])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "alpha");
        assert!(e.message.contains("1 exponents for 2 moduli"), "{e}");
        let e = material(
            Constants::Ogden,
            &given(&[("mu_pa", &[1e5, 2e5]), ("alpha", &[2.0, 0.0])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "alpha.1");
        let e = material(Constants::NeoHookean, &given(&[("mu_pa", &[-1.0])])).unwrap_err();
        assert_eq!(e.param, "mu_pa");
        assert!(e.message.contains("> 0"), "{e}");
        let e = material(Constants::NeoHookean, &given(&[("mu_pa", &[1.0, 2.0])])).unwrap_err();
        assert!(e.message.contains("takes one value, got 2"), "{e}");
        let e = material(
            Constants::ArrudaBoyce,
            &given(&[("mu_pa", &[1e5]), ("lambda_m", &[0.9])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "lambda_m");
        let e = material(
            Constants::Linear,
            &given(&[("e_pa", &[1e6]), ("poisson", &[0.7])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "poisson");
        let e = material(
            Constants::Linear,
            &given(&[("e_pa", &[1e6]), ("mu_pa", &[1e5])]),
        )
        .unwrap_err();
        assert_eq!(e.param, "mu_pa");
        assert!(e.message.contains("`e_pa`, `poisson`"), "{e}");
    }

    /// Issue #50, item 8: the unstable constants are refused,
    /// naming the test, where the law turns unstable and the range it must
    /// hold over; stable laws with negative terms (the version guard's
    /// Ogden, a softening Yeoh) still pass.
    #[test]
    fn unstable_constants_are_refused_naming_where() {
        let refused: [(Constants, &[Pair]); 2] = [
            (
                Constants::Ogden,
                &[("mu_pa", &[1.1e6, -1e6]), ("alpha", &[-2.0, 2.0])],
            ),
            (
                Constants::Yeoh,
                &[("c10_pa", &[5e5]), ("c20_pa", &[-1e7]), ("c30_pa", &[0.0])],
            ),
        ];
        for (family, pairs) in refused {
            let e = material(family, &given(pairs)).unwrap_err();
            assert!(
                e.message.contains("is Drucker-unstable in UT ")
                    && e.message.contains("(0.7 ≤ λ ≤ 1.5 in UT, PT and BT)"),
                "{e}"
            );
            assert_eq!(e.param, family.parameters().0[0], "{e}");
        }
        let e = material(
            Constants::Ogden,
            &given(&[("mu_pa", &[1.1e6, -1e6]), ("alpha", &[-2.0, 2.0])]),
        )
        .unwrap_err();
        assert!(
            e.message.starts_with("the ogden law with these constants"),
            "{e}"
        );
        let accepted: [(Constants, &[Pair]); 3] = [
            (
                Constants::Ogden,
                &[("mu_pa", &[7e5, -1e5]), ("alpha", &[1.3, -2.0])],
            ),
            (
                Constants::Ogden,
                &[("mu_pa", &[7e5, -1e5, 2e3]), ("alpha", &[1.3, -2.0, 5.0])],
            ),
            (
                Constants::Yeoh,
                &[("c10_pa", &[2e5]), ("c20_pa", &[-1e4]), ("c30_pa", &[1e3])],
            ),
        ];
        for (family, pairs) in accepted {
            material(family, &given(pairs)).unwrap();
        }
    }

    /// Moduli of absurd size are refused naming the parameter (and the
    /// term of a list); zero terms pass.
    #[test]
    fn absurd_moduli_are_refused_naming_the_parameter() {
        let cases: [(Constants, &[Pair], &str); 5] = [
            (Constants::NeoHookean, &[("mu_pa", &[1e300])], "mu_pa"),
            (Constants::Linear, &[("e_pa", &[3e12])], "e_pa"),
            (Constants::NeoHookean, &[("mu_pa", &[0.5])], "mu_pa"),
            (
                Constants::Ogden,
                &[("mu_pa", &[6e5, 1e13]), ("alpha", &[2.0, 4.0])],
                "mu_pa.1",
            ),
            (
                Constants::Yeoh,
                &[("c10_pa", &[2e5]), ("c20_pa", &[1e-3]), ("c30_pa", &[0.0])],
                "c20_pa",
            ),
        ];
        for (family, pairs, param) in cases {
            let e = material(family, &given(pairs)).unwrap_err();
            assert_eq!(e.param, param, "{e}");
            assert!(
                e.message.contains("is no solid's modulus")
                    && e.message.contains("is 0 or 1 to 1e12 Pa in size"),
                "{e}"
            );
        }
        let e = material(Constants::NeoHookean, &given(&[("mu_pa", &[1e300])])).unwrap_err();
        assert!(
            e.message.starts_with("1e300 Pa is no solid's modulus"),
            "{e}"
        );
        material(
            Constants::Yeoh,
            &given(&[("c10_pa", &[2e5]), ("c20_pa", &[0.0]), ("c30_pa", &[0.0])]),
        )
        .unwrap();
    }
}
