//! One linear solve for the `bem` stages of a thread that ask for the same
//! curve. The contact set, the unit-modulus load f(δ) and the maps of a
//! linear half-space do not depend on the modulus, so a `bem` with the
//! linear law and one with the hyperelastic law (or another tangent) of the
//! same map and solver settings solve exactly the same problem: the paper
//! pipeline runs both per sample. The last curve solved on this thread is
//! kept, with every step's pressure and gap, and a stage asking for the same
//! one (same heights to the bit, grid, spacing, boundary, steps, top area
//! fraction and solver options) replays it instead of solving again. The
//! solve is deterministic, so a replay gives the bits a new solve would.
//!
//! Kept per thread, so stages on other threads (tests, Python threads) never
//! see each other's entries, and only while it fits [`BUDGET_BYTES`]: a
//! large map's forty steps are not held in memory to save a second solve
//! that may never come.

use std::cell::RefCell;
use std::rc::Rc;

use crate::curve::{CurveError, CurveOptions, Step, solve_curve};
use crate::influence::Boundary;
use crate::polonsky_keer::{Problem, Solution};

/// The most memory a kept curve may take (pressure and gap of every step).
pub const BUDGET_BYTES: usize = 512 << 20;

/// What makes two curves the same: the map to the bit and the settings.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveKey {
    /// (nx, ny)
    pub dim: (usize, usize),
    /// (dx, dy) as bits
    pub spacing_bits: (u64, u64),
    pub boundary: Boundary,
    /// The heights as bits (NaN payloads included), row-major.
    pub height_bits: Vec<u64>,
    pub options: CurveOptions,
}

impl CurveKey {
    pub fn new(
        (nx, ny, dx_m, dy_m): (usize, usize, f64, f64),
        boundary: Boundary,
        heights_m: &[f64],
        options: CurveOptions,
    ) -> Self {
        Self {
            dim: (nx, ny),
            spacing_bits: (dx_m.to_bits(), dy_m.to_bits()),
            boundary,
            height_bits: heights_m.iter().map(|h| h.to_bits()).collect(),
            options,
        }
    }
}

/// A solved step's maps, for E* = 1.
struct StepMaps {
    pressure: Vec<f64>,
    gap_m: Vec<f64>,
}

/// A solved curve: its rows and, for k = 1..=steps, the maps of step k at
/// `maps[k - 1]`.
struct Solved {
    key: CurveKey,
    rows: Vec<Step>,
    maps: Vec<StepMaps>,
}

thread_local! {
    static LAST: RefCell<Option<Rc<Solved>>> = const { RefCell::new(None) };
}

/// What sees each solved step: (k, row, pressure / E*, gap in m).
pub type OnStep<'a> = dyn FnMut(usize, &Step, &[f64], &[f64]) + 'a;

/// Drops the curve this thread kept (the runner's [`Stage::let_go`] when
/// the stages after are of other kinds: a paper-scale map's curve is
/// ~130 MB held through a sample's scan otherwise).
///
/// [`Stage::let_go`]: hypercontact_core::Stage::let_go
pub fn forget() {
    LAST.with(|l| l.borrow_mut().take());
}

/// Whether a curve came from a new solve or from the thread's last one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    Solved,
    Reused,
}

/// [`solve_curve`] on `problem` (whose map and grid `key` describes), or
/// the replay of the same curve solved last on this thread.
/// `on_step(k, row, pressure, gap_m)` sees each step as `solve_curve`'s
/// callback does.
pub fn solve_curve_shared(
    key: CurveKey,
    problem: &Problem<'_>,
    on_step: &mut OnStep<'_>,
) -> Result<(Vec<Step>, Source), CurveError> {
    solve_within(key, problem, on_step, BUDGET_BYTES)
}

/// [`solve_curve_shared`] keeping at most `budget_bytes`.
fn solve_within(
    key: CurveKey,
    problem: &Problem<'_>,
    on_step: &mut OnStep<'_>,
    budget_bytes: usize,
) -> Result<(Vec<Step>, Source), CurveError> {
    let last = LAST.with(|l| l.borrow().clone());
    if let Some(solved) = last.filter(|s| s.key == key) {
        for (k, (row, maps)) in solved.rows[1..].iter().zip(&solved.maps).enumerate() {
            on_step(k + 1, row, &maps.pressure, &maps.gap_m);
        }
        return Ok((solved.rows.clone(), Source::Reused));
    }
    let points = key.height_bits.len();
    let bytes = key.options.steps.max(1) * points * 2 * std::mem::size_of::<f64>();
    let keep = bytes <= budget_bytes;
    // The entry before is dropped first: two curves are never held at once.
    LAST.with(|l| l.borrow_mut().take());
    let mut maps = Vec::new();
    let mut each = |k: usize, row: &Step, s: &Solution| {
        on_step(k, row, &s.pressure, &s.gap_m);
        if keep {
            maps.push(StepMaps {
                pressure: s.pressure.clone(),
                gap_m: s.gap_m.clone(),
            });
        }
    };
    let rows = solve_curve(problem, key.options, &mut each)?;
    if keep {
        let solved = Solved {
            key,
            rows: rows.clone(),
            maps,
        };
        LAST.with(|l| *l.borrow_mut() = Some(Rc::new(solved)));
    }
    Ok((rows, Source::Solved))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::influence::Influence;
    use crate::polonsky_keer::SolverOptions;

    /// A small rough map: a sum of cosines, not periodic on the grid.
    fn heights(n: usize, shift: f64) -> Vec<f64> {
        (0..n * n)
            .map(|k| {
                let (i, j) = ((k / n) as f64, (k % n) as f64);
                1e-6 * ((0.7 * i).cos() + (0.45 * j + shift).sin() + 0.3 * (0.9 * (i + j)).cos())
            })
            .collect()
    }

    fn options(steps: usize) -> CurveOptions {
        CurveOptions {
            steps,
            max_area_fraction: 0.5,
            solver: SolverOptions::default(),
        }
    }

    type Seen = Vec<(usize, Step, Vec<f64>, Vec<f64>)>;

    fn solve(h: &[f64], n: usize, steps: usize) -> (Seen, Vec<Step>, Source) {
        solve_budget(h, n, steps, BUDGET_BYTES)
    }

    fn solve_budget(
        h: &[f64],
        n: usize,
        steps: usize,
        budget_bytes: usize,
    ) -> (Seen, Vec<Step>, Source) {
        let grid = (n, n, 1e-6, 1e-6);
        let influence = Influence::new(n, n, 1e-6, 1e-6, Boundary::Free);
        let problem = Problem::new(&influence, h).unwrap();
        let key = CurveKey::new(grid, Boundary::Free, h, options(steps));
        let mut seen = Vec::new();
        let mut push =
            |k, row: &Step, p: &[f64], g: &[f64]| seen.push((k, *row, p.to_vec(), g.to_vec()));
        let (rows, source) = solve_within(key, &problem, &mut push, budget_bytes).unwrap();
        (seen, rows, source)
    }

    #[test]
    fn the_same_curve_again_is_replayed_with_the_bits_of_a_new_solve() {
        let n = 24;
        let h = heights(n, 0.0);
        let (first, rows, source) = solve(&h, n, 4);
        assert_eq!(source, Source::Solved);
        assert_eq!(first.len(), 4);
        let (again, rows_again, source) = solve(&h, n, 4);
        assert_eq!(source, Source::Reused);
        assert_eq!(rows_again, rows);
        for (a, b) in first.iter().zip(&again) {
            assert_eq!(a.0, b.0);
            assert_eq!(a.1, b.1);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.2), bits(&b.2));
            assert_eq!(bits(&a.3), bits(&b.3));
        }
        // The same call on a solver with nothing kept gives the same bits.
        LAST.with(|l| l.borrow_mut().take());
        let (fresh, rows_fresh, source) = solve(&h, n, 4);
        assert_eq!(source, Source::Solved);
        assert_eq!(rows_fresh, rows);
        assert_eq!(
            fresh.iter().map(|s| s.2.clone()).collect::<Vec<_>>(),
            first.iter().map(|s| s.2.clone()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn another_map_or_setting_is_solved_again() {
        let n = 20;
        let h = heights(n, 0.0);
        assert_eq!(solve(&h, n, 3).2, Source::Solved);
        assert_eq!(solve(&h, n, 3).2, Source::Reused);
        // one height one bit away
        let mut nudged = h.clone();
        nudged[7] = f64::from_bits(nudged[7].to_bits() + 1);
        assert_eq!(solve(&nudged, n, 3).2, Source::Solved);
        // other steps
        assert_eq!(solve(&nudged, n, 4).2, Source::Solved);
        // the last one only is kept
        assert_eq!(solve(&h, n, 3).2, Source::Solved);
    }

    #[test]
    fn a_forgotten_curve_is_solved_again() {
        let h = heights(8, 0.0);
        assert_eq!(solve(&h, 8, 3).2, Source::Solved);
        assert_eq!(solve(&h, 8, 3).2, Source::Reused);
        forget();
        assert_eq!(solve(&h, 8, 3).2, Source::Solved);
    }

    #[test]
    fn a_curve_over_the_budget_is_not_kept() {
        let n = 16;
        let h = heights(n, 0.3);
        // 3 steps of 16² pressures and gaps: 12 288 bytes
        let budget = 3 * n * n * 16;
        assert_eq!(solve_budget(&h, n, 3, budget).2, Source::Solved);
        assert_eq!(solve_budget(&h, n, 3, budget).2, Source::Reused);
        LAST.with(|l| l.borrow_mut().take());
        assert_eq!(solve_budget(&h, n, 3, budget - 1).2, Source::Solved);
        assert_eq!(solve_budget(&h, n, 3, budget - 1).2, Source::Solved);
    }
}
