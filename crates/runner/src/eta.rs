//! How long a stage, and the rest of a run, will take: the arithmetic
//! behind the `ETA` on the progress bars, as pure functions of what the
//! bars know (elapsed time, steps done, steps in all, the pace of the
//! latest steps) and of what earlier runs recorded.
//!
//! The rule. A stage with a recorded time T of the same computation (the
//! same kind and cache key, else the same kind and parameters: see
//! [`crate::timings::History`]) shows `ETA` T − elapsed; if its own
//! progress promises longer (this run is slower than that one), the
//! progress estimate instead. Without a record, the progress estimate:
//! the steps left × the mean time per step so far, or, when the latest
//! steps are slower than that mean by more than a quarter (uneven steps:
//! the BEM's load steps grow as contact spreads, so at 17/40 steps the
//! mean pace promised 81 s for minutes of work), the steps left × the
//! latest pace, shown as a lower bound `ETA ≥`. The run's ETA adds the
//! recorded times of the stages still to compute to what is left of the
//! current one; where a stage to compute has no record it is `ETA ≥`
//! (those stages count as nothing), and with no record at all there is
//! no run ETA.

/// The latest steps are "slower" when their pace exceeds the mean pace by
/// this factor.
pub const UNEVEN: f64 = 1.25;

/// What a stage's bar knows of its own progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pace {
    /// Seconds since the bar started.
    pub elapsed_s: f64,
    pub done: u64,
    pub total: u64,
    /// Seconds per step of the latest steps (see [`latest_s_per_step`]).
    pub latest_s_per_step: Option<f64>,
}

/// The labelled ETA of a stage: `ETA 1m20s`, `ETA ≥ 5m56s` (a lower
/// bound: uneven steps), `ETA ?` (nothing to go on). `recorded_left_s` is
/// an earlier run's time of the same computation less the time this stage
/// has run.
pub fn stage_eta(pace: &Pace, recorded_left_s: Option<f64>) -> String {
    if pace.total > 0 && pace.done >= pace.total {
        return "ETA 0s".to_owned();
    }
    let left = pace.total.saturating_sub(pace.done) as f64;
    let progress = (pace.done > 0 && pace.elapsed_s.is_finite()).then(|| {
        let mean = pace.elapsed_s / pace.done as f64;
        match pace.latest_s_per_step {
            Some(latest) if latest > UNEVEN * mean => (latest * left, true),
            _ => (mean * left, false),
        }
    });
    let recorded = recorded_left_s.filter(|r| r.is_finite() && *r > 0.0);
    match (recorded, progress) {
        (Some(r), Some((p, lower))) if p > r => labelled(p, lower),
        (Some(r), _) => labelled(r, false),
        (None, Some((p, lower))) => labelled(p, lower),
        (None, None) => "ETA ?".to_owned(),
    }
}

/// The ETA of the rest of a run: what is left of the current stage
/// (`current_left_s`, None when unknown) and the expected time of every
/// later stage (None: it computes and has no record; cached stages 0).
/// Empty when nothing left that computes has a record.
pub fn run_eta(current_left_s: Option<f64>, later_s: &[Option<f64>]) -> String {
    let all = std::iter::once(current_left_s).chain(later_s.iter().copied());
    let (mut known_s, mut unknown, mut any) = (0.0, 0, false);
    for expected in all {
        match expected {
            Some(s) if s.is_finite() => {
                known_s += s.max(0.0);
                // Stages that compute nothing (cached, done) tell nothing.
                any |= s > 0.0;
            }
            _ => unknown += 1,
        }
    }
    match (any, unknown) {
        (false, _) => String::new(),
        (true, 0) => labelled(known_s, false),
        (true, _) => labelled(known_s, true),
    }
}

/// `ETA 1m20s`, or `ETA ≥ 1m20s` for a lower bound.
fn labelled(seconds: f64, lower_bound: bool) -> String {
    let bound = if lower_bound { "≥ " } else { "" };
    format!("ETA {bound}{}", duration_text(seconds))
}

/// A duration as a person reads it on a bar: `45s`, `1m20s`, `2h05m`
/// (rounded up to the unit shown, so a few seconds left is never `0s`).
pub fn duration_text(seconds: f64) -> String {
    if !seconds.is_finite() || seconds <= 0.0 {
        return "0s".to_owned();
    }
    let s = seconds.ceil() as u64;
    if s < 60 {
        format!("{s}s")
    } else if s < 3600 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        let m = s.div_ceil(60);
        format!("{}h{:02}m", m / 60, m % 60)
    }
}

/// The pace of the latest steps, seconds per step: over the last quarter
/// of the steps done (at least one), from `samples` (seconds since the
/// bar started, steps done then; in order), or the time spent on the step
/// in progress if that is longer already. None before the first step.
pub fn latest_s_per_step(samples: &[(f64, u64)], elapsed_s: f64) -> Option<f64> {
    let &(t_last, done) = samples.last()?;
    if done == 0 {
        return None;
    }
    let from = done - (done / 4).max(1);
    let (t_from, pos_from) = samples
        .iter()
        .rev()
        .find(|(_, pos)| *pos <= from)
        .copied()
        .unwrap_or((0.0, 0));
    let window = (t_last - t_from) / (done - pos_from) as f64;
    Some(window.max(elapsed_s - t_last))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The BEM of issue #37: step k takes k seconds (40 steps, 820 s in
    /// all), so at 17 steps 153 s have passed and 667 s are left. The mean
    /// pace (9 s a step) promised 207 s; the latest quarter (steps 14–17,
    /// 15.5 s a step) gives a lower bound of 23 × 15.5 = 356.5 s, and a
    /// record of the same computation gives the truth.
    #[test]
    fn growing_steps_give_a_lower_bound_and_a_record_the_rest() {
        let mut samples = Vec::new();
        let mut t = 0.0;
        for k in 1..=17u64 {
            t += k as f64;
            samples.push((t, k));
        }
        assert_eq!(t, 153.0);
        let latest = latest_s_per_step(&samples, t).unwrap();
        assert_eq!(latest, 15.5);
        let pace = Pace {
            elapsed_s: t,
            done: 17,
            total: 40,
            latest_s_per_step: Some(latest),
        };
        assert_eq!(stage_eta(&pace, None), "ETA ≥ 5m57s");
        assert_eq!(stage_eta(&pace, Some(820.0 - t)), "ETA 11m07s");
        // A record this run has outlasted says nothing: the progress does.
        assert_eq!(stage_eta(&pace, Some(-3.0)), "ETA ≥ 5m57s");
        // A record shorter than the progress estimate: this run is slower.
        assert_eq!(stage_eta(&pace, Some(100.0)), "ETA ≥ 5m57s");
    }

    #[test]
    fn even_steps_extrapolate_the_mean() {
        // 2 s a step, 10 of 25 done: 30 s left.
        let samples: Vec<(f64, u64)> = (1..=10).map(|k| (2.0 * k as f64, k)).collect();
        let latest = latest_s_per_step(&samples, 20.5);
        assert_eq!(latest, Some(2.0));
        let pace = Pace {
            elapsed_s: 20.0,
            done: 10,
            total: 25,
            latest_s_per_step: latest,
        };
        assert_eq!(stage_eta(&pace, None), "ETA 30s");
        // The record is trusted when the pace promises less.
        assert_eq!(stage_eta(&pace, Some(80.0)), "ETA 1m20s");
        // Nothing done and nothing recorded; done; a record alone.
        let start = Pace {
            done: 0,
            latest_s_per_step: None,
            ..pace
        };
        assert_eq!(stage_eta(&start, None), "ETA ?");
        assert_eq!(stage_eta(&start, Some(75.2)), "ETA 1m16s");
        let finished = Pace { done: 25, ..pace };
        assert_eq!(stage_eta(&finished, None), "ETA 0s");
    }

    #[test]
    fn a_step_in_progress_longer_than_the_latest_pace_counts() {
        // 1 s a step for 8 steps, then the 9th has run 5 s already.
        let samples: Vec<(f64, u64)> = (1..=8).map(|k| (k as f64, k)).collect();
        assert_eq!(latest_s_per_step(&samples, 13.0), Some(5.0));
        assert_eq!(latest_s_per_step(&[], 13.0), None);
        assert_eq!(latest_s_per_step(&[(0.5, 0)], 13.0), None);
        // Samples thinned out: the window starts at the nearest earlier one.
        assert_eq!(latest_s_per_step(&[(1.0, 2), (9.0, 10)], 9.0), Some(1.0));
    }

    #[test]
    fn the_run_adds_records_and_says_when_some_are_missing() {
        assert_eq!(run_eta(Some(20.0), &[Some(40.0), Some(0.0)]), "ETA 1m00s");
        assert_eq!(run_eta(Some(20.0), &[None, Some(40.0)]), "ETA ≥ 1m00s");
        assert_eq!(run_eta(None, &[Some(3600.0), Some(1.0)]), "ETA ≥ 1h01m");
        // Negative: the current stage has outlasted its record.
        assert_eq!(run_eta(Some(-5.0), &[Some(10.0)]), "ETA 10s");
        assert_eq!(run_eta(None, &[None]), "");
        assert_eq!(run_eta(Some(0.0), &[None, Some(0.0)]), "");
        assert_eq!(run_eta(None, &[]), "");
    }

    #[test]
    fn durations_read_as_a_person_says_them() {
        let cases = [
            (0.0, "0s"),
            (0.2, "1s"),
            (59.0, "59s"),
            (59.5, "1m00s"),
            (80.0, "1m20s"),
            (3599.0, "59m59s"),
            (3600.0, "1h00m"),
            (7501.0, "2h06m"),
            (f64::NAN, "0s"),
            (-4.0, "0s"),
        ];
        for (s, text) in cases {
            assert_eq!(duration_text(s), text, "{s}");
        }
    }
}
