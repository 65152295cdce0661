//! One named parameter of a strain energy: its symbol, its Ogden term and
//! its unit travel with the value, so no consumer takes names apart.

/// A parameter's unit: a modulus or a pure number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamUnit {
    Pa,
    /// Dimensionless (α_i, λm).
    One,
}

impl ParamUnit {
    /// `Pa` or `1`, as tables write units.
    pub fn label(self) -> &'static str {
        match self {
            ParamUnit::Pa => "Pa",
            ParamUnit::One => "1",
        }
    }
}

/// A parameter value in SI units, with what it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameter {
    /// The symbol without a term index: `mu`, `alpha`, `c10`, `lambda_m`.
    pub symbol: &'static str,
    /// The Ogden term i (1…N); None for every other parameter.
    pub term: Option<usize>,
    pub unit: ParamUnit,
    pub value: f64,
}

impl Parameter {
    /// A modulus, Pa.
    pub fn modulus(symbol: &'static str, value_pa: f64) -> Self {
        Self {
            symbol,
            term: None,
            unit: ParamUnit::Pa,
            value: value_pa,
        }
    }

    /// A dimensionless parameter.
    pub fn number(symbol: &'static str, value: f64) -> Self {
        Self {
            symbol,
            term: None,
            unit: ParamUnit::One,
            value,
        }
    }

    /// The same parameter for Ogden term i (1-based).
    pub fn of_term(self, term: usize) -> Self {
        Self {
            term: Some(term),
            ..self
        }
    }

    /// The name in the `material` table: `mu_1`, `alpha_1`, `c10`, ...
    pub fn name(&self) -> String {
        match self.term {
            Some(i) => format!("{}_{i}", self.symbol),
            None => self.symbol.to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_carry_the_term_index() {
        let alpha = Parameter::number("alpha", 1.3).of_term(2);
        assert_eq!(alpha.name(), "alpha_2");
        assert_eq!(alpha.unit.label(), "1");
        let c10 = Parameter::modulus("c10", 2e5);
        assert_eq!((c10.name().as_str(), c10.term), ("c10", None));
        assert_eq!(c10.unit.label(), "Pa");
    }
}
