//! The model families a fit can choose from, and how each is parametrised
//! for least squares: a parameter vector x = (linear moduli…, nonlinear
//! shape parameters…). Every family's stress is linear in its moduli (μ_i,
//! C_ij, μ) for fixed shape parameters (α_i, λm), which the fit uses to
//! start from the best moduli for each trial shape (variable projection).

use nalgebra::DMatrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Uniform};

use crate::ogden::lateral_power;
use crate::{
    ArrudaBoyce, Hyperelastic, MaterialError, Mode, MooneyRivlin, NeoHookean, Ogden, Yeoh,
};

/// Largest Ogden order offered.
pub const MAX_OGDEN_TERMS: usize = 6;

/// A strain-energy family with its size, written by its name (`ogden-6`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Family {
    /// N-term Ogden, N = 1…6.
    Ogden(usize),
    NeoHookean,
    MooneyRivlin,
    /// Reduced polynomial N = 3.
    Yeoh,
    ArrudaBoyce,
}

impl TryFrom<String> for Family {
    type Error = MaterialError;

    fn try_from(name: String) -> Result<Self, MaterialError> {
        Family::parse(&name)
    }
}

impl From<Family> for String {
    fn from(family: Family) -> String {
        family.name()
    }
}

hypercontact_core::leaf_param_value!(Family, Family::names().replace(", ", " | "));

impl Family {
    /// Every family, in the order the comparison lists them before ranking.
    pub fn all() -> Vec<Family> {
        let mut all: Vec<Family> = (1..=MAX_OGDEN_TERMS).map(Family::Ogden).collect();
        all.extend([
            Family::NeoHookean,
            Family::MooneyRivlin,
            Family::Yeoh,
            Family::ArrudaBoyce,
        ]);
        all
    }

    /// The names accepted by [`Family::parse`].
    pub fn names() -> String {
        Family::all()
            .iter()
            .map(Family::name)
            .collect::<Vec<_>>()
            .join(", ")
    }

    pub fn parse(name: &str) -> Result<Family, MaterialError> {
        let family = match name.trim().to_ascii_lowercase().as_str() {
            "neo-hookean" => Some(Family::NeoHookean),
            "mooney-rivlin" => Some(Family::MooneyRivlin),
            "yeoh" => Some(Family::Yeoh),
            "arruda-boyce" => Some(Family::ArrudaBoyce),
            other => other
                .strip_prefix("ogden-")
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|n| (1..=MAX_OGDEN_TERMS).contains(n))
                .map(Family::Ogden),
        };
        family.ok_or_else(|| MaterialError::UnknownModel {
            name: name.to_owned(),
            known: Family::names(),
        })
    }

    /// `ogden-6`, `neo-hookean`, ...
    pub fn name(&self) -> String {
        match self {
            Family::Ogden(n) => format!("ogden-{n}"),
            Family::NeoHookean => "neo-hookean".into(),
            Family::MooneyRivlin => "mooney-rivlin".into(),
            Family::Yeoh => "yeoh".into(),
            Family::ArrudaBoyce => "arruda-boyce".into(),
        }
    }

    pub fn n_params(&self) -> usize {
        match self {
            Family::Ogden(n) => 2 * n,
            Family::NeoHookean => 1,
            Family::MooneyRivlin | Family::ArrudaBoyce => 2,
            Family::Yeoh => 3,
        }
    }

    /// How many leading entries of x are moduli (stress is linear in them).
    pub fn n_linear(&self) -> usize {
        match self {
            Family::Ogden(n) => *n,
            Family::ArrudaBoyce => 1,
            other => other.n_params(),
        }
    }

    /// The model at x, with moduli in x multiplied by `scale_pa`. For
    /// Arruda–Boyce the shape parameter is q = 1/λm.
    pub fn model(&self, x: &[f64], scale_pa: f64) -> Result<Box<dyn Hyperelastic>, MaterialError> {
        let k = self.n_linear();
        let moduli: Vec<f64> = x[..k].iter().map(|v| v * scale_pa).collect();
        Ok(match self {
            Family::Ogden(_) => Box::new(Ogden::new(moduli, x[k..].to_vec())?),
            Family::NeoHookean => Box::new(NeoHookean::new(moduli[0])?),
            Family::MooneyRivlin => Box::new(MooneyRivlin::new(moduli[0], moduli[1])?),
            Family::Yeoh => Box::new(Yeoh::new(moduli[0], moduli[1], moduli[2])?),
            Family::ArrudaBoyce => {
                Box::new(ArrudaBoyce::new(moduli[0], 1.0 / x[1].abs().max(1e-8))?)
            }
        })
    }

    /// x with Ogden's terms in ascending α (the energy is a sum over terms,
    /// so their order is arbitrary; one order makes fits comparable term
    /// by term, e.g. across bootstrap replicates). Other families as given.
    pub fn canonical_order(&self, x: Vec<f64>) -> Vec<f64> {
        let Family::Ogden(n) = *self else {
            return x;
        };
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| x[n + a].total_cmp(&x[n + b]));
        order
            .iter()
            .map(|&i| x[i])
            .chain(order.iter().map(|&i| x[n + i]))
            .collect()
    }

    /// Stresses (in units of the moduli in x) at the given points.
    pub fn stresses(&self, x: &[f64], points: &[(Mode, f64)]) -> Option<Vec<f64>> {
        let model = self.model(x, 1.0).ok()?;
        let t: Vec<f64> = points
            .iter()
            .map(|&(mode, l)| model.nominal_stress_pa(mode, l))
            .collect();
        t.iter().all(|v| v.is_finite()).then_some(t)
    }

    /// ∂T/∂x at the given points (rows = points). Moduli columns are exact
    /// (the stress is linear in them); Ogden's α columns are closed-form;
    /// the Arruda–Boyce shape column is a central difference.
    pub fn jacobian(&self, x: &[f64], points: &[(Mode, f64)]) -> Option<DMatrix<f64>> {
        let (m, n, k) = (points.len(), self.n_params(), self.n_linear());
        let mut jac = DMatrix::zeros(m, n);
        if let Family::Ogden(terms) = *self {
            for (row, &(mode, l)) in points.iter().enumerate() {
                let c = lateral_power(mode);
                let ln_l = l.ln();
                for i in 0..terms {
                    let (mu, a) = (x[i], x[terms + i]);
                    let p = l.powf(a - 1.0);
                    let q = l.powf(-c * a - 1.0);
                    jac[(row, i)] = 2.0 / a * (p - q);
                    jac[(row, terms + i)] =
                        2.0 * mu * (-(p - q) / (a * a) + (p * ln_l + c * q * ln_l) / a);
                }
            }
        } else {
            for j in 0..k {
                let mut unit = x.to_vec();
                unit[..k].iter_mut().for_each(|v| *v = 0.0);
                unit[j] = 1.0;
                let col = self.stresses(&unit, points)?;
                jac.set_column(j, &nalgebra::DVector::from_vec(col));
            }
            for j in k..n {
                let h = 1e-6 * x[j].abs().max(1e-3);
                let (mut plus, mut minus) = (x.to_vec(), x.to_vec());
                plus[j] += h;
                minus[j] -= h;
                let (tp, tm) = (
                    self.stresses(&plus, points)?,
                    self.stresses(&minus, points)?,
                );
                for row in 0..m {
                    jac[(row, j)] = (tp[row] - tm[row]) / (2.0 * h);
                }
            }
        }
        jac.iter().all(|v| v.is_finite()).then_some(jac)
    }

    /// Trial shape parameters (x[n_linear..]) for `count` starts, the same
    /// for the same `seed`. The first is a fixed, evenly spread guess.
    pub fn shape_starts(&self, count: usize, seed: u64) -> Vec<Vec<f64>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        match *self {
            Family::Ogden(n) => {
                // Ogden's classic fits mix α of both signs within |α| ≲ 8
                // (Ogden 1972: 1.3, 5.0, −2.0).
                let spread = Uniform::new(-6.0, 8.0).expect("valid range");
                (0..count.max(1))
                    .map(|s| {
                        (0..n)
                            .map(|i| {
                                let a = if s == 0 {
                                    first_guess_alpha(i)
                                } else {
                                    spread.sample(&mut rng)
                                };
                                // α = 0 is singular; keep the sign, move away.
                                if a.abs() < 0.3 { 0.3f64.copysign(a) } else { a }
                            })
                            .collect()
                    })
                    .collect()
            }
            Family::ArrudaBoyce => {
                let lock = Uniform::new(1.2, 12.0).expect("valid range");
                (0..count.max(1))
                    .map(|s| {
                        let lambda_m = if s == 0 { 3.0 } else { lock.sample(&mut rng) };
                        vec![1.0 / lambda_m]
                    })
                    .collect()
            }
            // Linear families: one start is the exact answer.
            _ => vec![Vec::new()],
        }
    }
}

/// An evenly spread first guess: α from 2 upwards and −2 downwards,
/// alternating (n = 3 gives 2, −2, 5).
fn first_guess_alpha(i: usize) -> f64 {
    const GUESS: [f64; 6] = [2.0, -2.0, 5.0, 0.8, -4.0, 8.0];
    GUESS[i % GUESS.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_names_list_the_known_ones() {
        for f in Family::all() {
            assert_eq!(Family::parse(&f.name()).unwrap(), f);
        }
        let e = Family::parse("ogden-7").unwrap_err().to_string();
        assert!(e.contains("`ogden-7`") && e.contains("arruda-boyce"), "{e}");
        assert!(Family::parse("gent").is_err());
    }

    #[test]
    fn jacobians_match_central_differences() {
        let points: Vec<(Mode, f64)> = Mode::ALL
            .iter()
            .flat_map(|&m| [1.1, 1.7, 2.5].map(|l| (m, l)))
            .collect();
        let cases: Vec<(Family, Vec<f64>)> = vec![
            (Family::Ogden(3), vec![0.6, 0.01, -0.02, 1.3, 5.0, -2.0]),
            (Family::NeoHookean, vec![0.2]),
            (Family::MooneyRivlin, vec![0.2, 0.05]),
            (Family::Yeoh, vec![0.2, -0.01, 0.003]),
            (Family::ArrudaBoyce, vec![0.3, 0.35]),
        ];
        for (family, x) in cases {
            let jac = family.jacobian(&x, &points).unwrap();
            for j in 0..x.len() {
                let h = 1e-6;
                let (mut plus, mut minus) = (x.clone(), x.clone());
                plus[j] += h;
                minus[j] -= h;
                let tp = family.stresses(&plus, &points).unwrap();
                let tm = family.stresses(&minus, &points).unwrap();
                for row in 0..points.len() {
                    let fd = (tp[row] - tm[row]) / (2.0 * h);
                    assert!(
                        (jac[(row, j)] - fd).abs() <= 1e-5 * (fd.abs() + 1.0),
                        "{} d/dx{j} at {:?}: {} vs {fd}",
                        family.name(),
                        points[row],
                        jac[(row, j)]
                    );
                }
            }
        }
    }

    #[test]
    fn starts_are_deterministic_and_avoid_zero_alpha() {
        let f = Family::Ogden(6);
        let a = f.shape_starts(5, 7);
        assert_eq!(a, f.shape_starts(5, 7));
        assert_ne!(a, f.shape_starts(5, 8));
        assert!(a.iter().flatten().all(|x| x.abs() >= 0.3));
    }
}
