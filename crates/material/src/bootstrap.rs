//! Bootstrap replicates of a fit: how far the tensile data's scatter moves
//! the fitted material, so that contact models downstream can show how far
//! it moves their curves.
//!
//! Resampling: points within each mode, with replacement, as many as the
//! mode has (the case or "pairs" bootstrap; Efron & Tibshirani 1993,
//! ch. 9). Chosen over resampling residuals because it does not assume the
//! fitted family is the true law: where a family misfits a mode (a 1-term
//! Ogden in BT), a residual bootstrap would scatter systematic misfit over
//! the whole curve as if it were noise, while resampled points keep each
//! stretch's own error. Resampling within a mode keeps every mode's point
//! count, so the mode weights of the objective mean the same in every
//! replicate.
//!
//! Each replicate refits from the full-data optimum's shape parameters
//! (a warm start) plus a few seeded starts, with the same options
//! otherwise. Replicate r draws from its own ChaCha8 stream (seed, stream
//! r), so the replicates are the same on any number of threads.

use hypercontact_core::{Schema, Table};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::fit::{FitOptions, FitResult, fit};
use crate::table::{from_parts, parameter_rows};
use crate::tensile::{TensileCurve, TensileData};
use crate::{Hyperelastic, MaterialError};

/// The data set of one replicate: each mode's points drawn with
/// replacement, in increasing stretch (a point drawn twice appears twice).
pub fn resample(data: &TensileData, rng: &mut ChaCha8Rng) -> TensileData {
    let curves = data
        .curves
        .iter()
        .map(|c| {
            let mut picks: Vec<usize> =
                (0..c.len()).map(|_| rng.random_range(0..c.len())).collect();
            picks.sort_unstable();
            TensileCurve {
                mode: c.mode,
                stretch: picks.iter().map(|&i| c.stretch[i]).collect(),
                stress_pa: picks.iter().map(|&i| c.stress_pa[i]).collect(),
            }
        })
        .collect();
    TensileData { curves }
}

/// How many replicates, drawn how, refitted from how many starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bootstrap {
    pub count: usize,
    pub seed: u64,
    /// Seeded starts per refit, beside the full-data optimum's shape.
    pub starts: usize,
}

/// `count` refits of `best`'s family on resampled data. Entry r is
/// replicate r + 1's fitted model, or why it failed. `done` is called once
/// per finished refit (from any thread), e.g. to move a progress bar.
pub fn replicates(
    data: &TensileData,
    best: &FitResult,
    options: &FitOptions,
    Bootstrap {
        count,
        seed,
        starts,
    }: Bootstrap,
    done: &(dyn Fn() + Sync),
) -> Vec<Result<Box<dyn Hyperelastic>, MaterialError>> {
    (0..count)
        .into_par_iter()
        .map(|r| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(r as u64 + 1);
            let sample = resample(data, &mut rng);
            let refit = FitOptions {
                warm_starts: vec![best.shape.clone()],
                starts,
                seed: seed.wrapping_add(r as u64 + 1),
                ..options.clone()
            };
            let model = fit(&sample, best.family, &refit).map(|f| f.model);
            done();
            model
        })
        .collect()
}

/// The `replicates` table: the `material` table of every bootstrap
/// replicate, stacked.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ReplicatesTable {
    /// bootstrap replicate, 1…count (empty without a bootstrap)
    pub replicate: Vec<i64>,
    /// model family, as in the `material` table
    pub model: Vec<String>,
    /// parameter name (mu_1, alpha_1, c10, ...)
    pub param: Vec<String>,
    /// parameter value in SI units (moduli in Pa)
    #[column(unit = "Pa or 1")]
    pub value: Vec<f64>,
}

impl ReplicatesTable {
    /// The models in replicate order, numbered from 1.
    pub fn new<'a>(models: impl IntoIterator<Item = (i64, &'a dyn Hyperelastic)>) -> Self {
        let mut t = ReplicatesTable {
            replicate: Vec::new(),
            model: Vec::new(),
            param: Vec::new(),
            value: Vec::new(),
        };
        for (r, m) in models {
            let (model, param, value) = parameter_rows(m);
            t.replicate.extend(std::iter::repeat_n(r, model.len()));
            t.model.extend(model);
            t.param.extend(param);
            t.value.extend(value);
        }
        t
    }
}

/// A replicate's number and its material.
pub type Replicate = (i64, Box<dyn Hyperelastic>);

/// Reads every replicate's model from a `replicates` table, in the order
/// of first appearance, with its number.
pub fn from_replicates_table(table: &Table) -> Result<Vec<Replicate>, MaterialError> {
    let t = ReplicatesTable::from_table(table).map_err(|e| MaterialError::Table(e.to_string()))?;
    let mut order: Vec<i64> = Vec::new();
    for &r in &t.replicate {
        if !order.contains(&r) {
            order.push(r);
        }
    }
    order
        .into_iter()
        .map(|r| {
            let rows: Vec<usize> = (0..t.replicate.len())
                .filter(|&i| t.replicate[i] == r)
                .collect();
            let pick = |col: &[String]| rows.iter().map(|&i| col[i].clone()).collect::<Vec<_>>();
            let values: Vec<f64> = rows.iter().map(|&i| t.value[i]).collect();
            from_parts(&pick(&t.model), &pick(&t.param), &values)
                .map(|m| (r, m))
                .map_err(|e| MaterialError::Table(format!("replicate {r}: {e}")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::paper_sample;
    use crate::{Constraint, Family, Mode};

    #[test]
    fn resampling_keeps_each_modes_count_and_draws_only_its_points() {
        let data = paper_sample();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let r = resample(&data, &mut rng);
        for (a, b) in data.curves.iter().zip(&r.curves) {
            assert_eq!((a.mode, a.len()), (b.mode, b.len()));
            assert!(b.stretch.windows(2).all(|w| w[0] <= w[1]));
            for (l, t) in b.stretch.iter().zip(&b.stress_pa) {
                let i = a.stretch.iter().position(|x| x == l).unwrap();
                assert_eq!(a.stress_pa[i], *t);
            }
        }
        // Some point is drawn twice (P(no repeat in 50 draws) ~ 1e-21).
        assert!(r.curves[0].stretch.windows(2).any(|w| w[0] == w[1]));
    }

    #[test]
    fn replicates_are_the_same_on_any_thread_count_and_round_trip() {
        let data = paper_sample();
        let options = FitOptions {
            constraint: Constraint::Stable,
            ..FitOptions::default()
        };
        let best = fit(&data, Family::Ogden(3), &options).unwrap();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let plan = Bootstrap {
                        count: 6,
                        seed: 9,
                        starts: 2,
                    };
                    replicates(&data, &best, &options, plan, &|| ())
                })
        };
        let (one, two) = (run(1), run(2));
        let params = |v: &[Result<Box<dyn Hyperelastic>, MaterialError>]| -> Vec<Vec<f64>> {
            v.iter()
                .map(|m| {
                    m.as_ref()
                        .unwrap()
                        .parameters()
                        .iter()
                        .map(|p| p.value)
                        .collect()
                })
                .collect()
        };
        assert_eq!(params(&one), params(&two));
        // Replicates differ from each other and from the best fit.
        let p = params(&one);
        assert_ne!(p[0], p[1]);
        let models: Vec<&dyn Hyperelastic> =
            one.iter().map(|m| m.as_ref().unwrap().as_ref()).collect();
        let table = ReplicatesTable::new((1..).zip(models.iter().copied())).into_table();
        let back = from_replicates_table(&table).unwrap();
        assert_eq!(back.len(), 6);
        for ((r, m), orig) in back.iter().zip(&models) {
            assert!(*r >= 1);
            assert_eq!(
                m.nominal_stress_pa(Mode::Equibiaxial, 0.8),
                orig.nominal_stress_pa(Mode::Equibiaxial, 0.8)
            );
        }
    }
}
