//! Nelder–Mead simplex minimisation, with the coefficients of Lagarias,
//! Reeds, Wright & Wright (SIAM J. Optim. 9, 112, 1998): reflection 1,
//! expansion 2, contraction ½, shrink ½.
//!
//! The registration's refinement maximises a correlation of bilinearly
//! sampled maps: a function of four parameters whose gradient jumps at every
//! cell edge the sample points cross, so a derivative-free search suits it.

/// When to stop.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Options {
    /// evaluations of the function, at most (a step may overrun it by the
    /// simplex's size when it shrinks)
    pub max_evaluations: usize,
    /// every vertex within this of the best, in each coordinate
    pub x_tolerance: f64,
    /// and every value within this of the best
    pub f_tolerance: f64,
}

/// The best point found.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Minimum {
    pub x: Vec<f64>,
    pub value: f64,
    pub evaluations: usize,
}

/// Minimises `f` from a simplex spanned by `start` and `start + step[i] eᵢ`.
/// A NaN value counts as +∞; an error of `f` ends the search.
pub(crate) fn minimise<E>(
    mut f: impl FnMut(&[f64]) -> Result<f64, E>,
    start: &[f64],
    step: &[f64],
    options: &Options,
) -> Result<Minimum, E> {
    let n = start.len();
    let evaluations = std::cell::Cell::new(0usize);
    let mut eval = |x: &[f64]| -> Result<f64, E> {
        evaluations.set(evaluations.get() + 1);
        let v = f(x)?;
        Ok(if v.is_nan() { f64::INFINITY } else { v })
    };
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    simplex.push((start.to_vec(), eval(start)?));
    for i in 0..n {
        let mut x = start.to_vec();
        x[i] += step.get(i).copied().unwrap_or(0.0);
        let v = eval(&x)?;
        simplex.push((x, v));
    }
    // x_a + t (x_b − x_a)
    let along = |a: &[f64], b: &[f64], t: f64| -> Vec<f64> {
        a.iter().zip(b).map(|(a, b)| a + t * (b - a)).collect()
    };
    loop {
        // stable: among equal values the earlier vertex stays first
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (&simplex[0], &simplex[n]);
        let spread_x = simplex
            .iter()
            .flat_map(|(x, _)| x.iter().zip(&best.0).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        let converged =
            spread_x <= options.x_tolerance && (worst.1 - best.1).abs() <= options.f_tolerance;
        if converged || evaluations.get() >= options.max_evaluations || n == 0 {
            break;
        }
        let mut centroid = vec![0.0; n];
        for (x, _) in &simplex[..n] {
            for (c, xi) in centroid.iter_mut().zip(x) {
                *c += xi / n as f64;
            }
        }
        let worst_x = simplex[n].0.clone();
        let (f_best, f_second, f_worst) = (simplex[0].1, simplex[n - 1].1, simplex[n].1);
        let reflected = along(&centroid, &worst_x, -1.0);
        let f_reflected = eval(&reflected)?;
        if f_reflected < f_best {
            let expanded = along(&centroid, &worst_x, -2.0);
            let f_expanded = eval(&expanded)?;
            simplex[n] = if f_expanded < f_reflected {
                (expanded, f_expanded)
            } else {
                (reflected, f_reflected)
            };
            continue;
        }
        if f_reflected < f_second {
            simplex[n] = (reflected, f_reflected);
            continue;
        }
        let (contracted, accept) = if f_reflected < f_worst {
            let x = along(&centroid, &reflected, 0.5);
            let v = eval(&x)?;
            ((x, v), v <= f_reflected)
        } else {
            let x = along(&centroid, &worst_x, 0.5);
            let v = eval(&x)?;
            ((x, v), v < f_worst)
        };
        if accept {
            simplex[n] = contracted;
            continue;
        }
        let best_x = simplex[0].0.clone();
        for vertex in simplex.iter_mut().skip(1) {
            let x = along(&best_x, &vertex.0, 0.5);
            let v = eval(&x)?;
            *vertex = (x, v);
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (x, value) = simplex.swap_remove(0);
    Ok(Minimum {
        x,
        value,
        evaluations: evaluations.get(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::convert::Infallible;

    const TIGHT: Options = Options {
        max_evaluations: 5000,
        x_tolerance: 1e-9,
        f_tolerance: 1e-14,
    };

    #[test]
    fn finds_the_centre_of_a_tilted_quadratic_bowl() {
        let centre = [0.3, -1.7, 2.2, 0.05];
        let f = |x: &[f64]| -> Result<f64, Infallible> {
            let d: Vec<f64> = x.iter().zip(&centre).map(|(a, b)| a - b).collect();
            // positive definite, coupled
            Ok(d[0] * d[0]
                + 2.0 * d[1] * d[1]
                + 0.5 * d[2] * d[2]
                + 3.0 * d[3] * d[3]
                + 0.4 * d[0] * d[1]
                - 0.3 * d[2] * d[3]
                + 7.0)
        };
        let m = minimise(f, &[0.0; 4], &[0.5; 4], &TIGHT).unwrap();
        for (x, c) in m.x.iter().zip(&centre) {
            assert!((x - c).abs() < 1e-6, "{:?}", m.x);
        }
        assert!((m.value - 7.0).abs() < 1e-12);
        assert!(m.evaluations < TIGHT.max_evaluations);
    }

    #[test]
    fn follows_the_rosenbrock_valley_to_its_minimum() {
        let f = |x: &[f64]| -> Result<f64, Infallible> {
            Ok(100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2))
        };
        let m = minimise(f, &[-1.2, 1.0], &[0.1, 0.1], &TIGHT).unwrap();
        assert!(
            (m.x[0] - 1.0).abs() < 1e-5 && (m.x[1] - 1.0).abs() < 1e-5,
            "{:?}",
            m
        );
    }

    #[test]
    fn stops_at_the_evaluation_budget_and_passes_errors_on() {
        let options = Options {
            max_evaluations: 25,
            ..TIGHT
        };
        let mut calls = 0;
        let m = minimise(
            |x: &[f64]| -> Result<f64, Infallible> {
                calls += 1;
                Ok(x.iter().map(|v| v * v).sum())
            },
            &[3.0, -2.0, 1.0],
            &[0.01; 3],
            &options,
        )
        .unwrap();
        assert_eq!(m.evaluations, calls);
        // the last step may add up to n + 1 evaluations (a shrink)
        assert!((25..=25 + 4).contains(&calls), "{calls}");
        let failed = minimise(
            |x: &[f64]| if x[0] > 1.5 { Err("far") } else { Ok(-x[0]) },
            &[0.0],
            &[1.0],
            &TIGHT,
        );
        assert_eq!(failed, Err("far"));
    }

    #[test]
    fn nan_counts_as_worse_than_anything() {
        // NaN beyond x = 1: the minimum of (x − 2)² inside is at the edge
        let m = minimise(
            |x: &[f64]| -> Result<f64, Infallible> {
                Ok(if x[0] > 1.0 {
                    f64::NAN
                } else {
                    (x[0] - 2.0).powi(2)
                })
            },
            &[0.0],
            &[0.25],
            &TIGHT,
        )
        .unwrap();
        assert!(m.x[0] <= 1.0 && m.x[0] > 1.0 - 1e-6, "{m:?}");
    }
}
