//! The loading rig of the contact experiment (the paper's Section 3): a
//! servo ramp at constant speed, a camera exposing at a fixed frame rate and
//! a force sensor on its own clock. All times here are camera times unless
//! a name says otherwise.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// When the camera exposes and where the sample is then.
///
/// Frame k is exposed over [k Δt, k Δt + exposure]; at its mid-exposure the
/// penetration is (k − m + φ) Δδ with m the frames before contact and φ the
/// phase of first contact (0 < φ ≤ 1: how far into the interval before
/// frame m the touch falls, from its end), so frames 0 … m − 1 see an open
/// gap, frame m the first touch and the last frame the penetration asked
/// for. The ramp runs at `speed` throughout,
/// so Δt = Δδ / speed; the servo stops at the last frame's mid-exposure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ramp {
    pub frames: usize,
    pub before_contact: usize,
    pub phase: f64,
    pub speed_m_per_s: f64,
    pub exposure_s: f64,
    /// Δt between exposure starts.
    pub frame_interval_s: f64,
    /// Camera time at which the plane first touches (penetration 0).
    pub contact_time_s: f64,
    /// Penetration at the last frame's mid-exposure.
    pub max_penetration_m: f64,
}

impl Ramp {
    /// The ramp reaching `max_penetration_m` at the last of `frames`; an
    /// error if the frames would come faster than the exposure allows.
    pub fn new(
        frames: usize,
        before_contact: usize,
        phase: f64,
        max_penetration_m: f64,
        speed_m_per_s: f64,
        exposure_s: f64,
    ) -> Result<Self, String> {
        if !(phase > 0.0 && phase <= 1.0) {
            return Err(format!("the contact phase {phase} lies outside (0, 1]"));
        }
        if before_contact + 1 >= frames {
            return Err(format!(
                "{frames} frames leave none in contact after {before_contact} before contact"
            ));
        }
        if !(max_penetration_m > 0.0 && max_penetration_m.is_finite()) {
            return Err(format!(
                "the final penetration {max_penetration_m:e} m is not positive"
            ));
        }
        let in_contact = (frames - before_contact - 1) as f64 + phase;
        let step_m = max_penetration_m / in_contact;
        let frame_interval_s = step_m / speed_m_per_s;
        if frame_interval_s < exposure_s {
            return Err(format!(
                "at {speed_m_per_s:e} m/s the {frames} frames to {max_penetration_m:.3e} m come \
                 every {frame_interval_s:.4} s, shorter than the {exposure_s} s exposure: use \
                 fewer frames or a slower ramp"
            ));
        }
        Ok(Self {
            frames,
            before_contact,
            phase,
            speed_m_per_s,
            exposure_s,
            frame_interval_s,
            contact_time_s: (before_contact as f64 - phase) * frame_interval_s + 0.5 * exposure_s,
            max_penetration_m,
        })
    }

    /// Frame k's exposure start.
    pub fn start_s(&self, k: usize) -> f64 {
        k as f64 * self.frame_interval_s
    }

    /// Frame k's mid-exposure.
    pub fn mid_s(&self, k: usize) -> f64 {
        self.start_s(k) + 0.5 * self.exposure_s
    }

    /// The penetration at camera time t (negative before contact, held
    /// after the last frame's mid-exposure).
    pub fn penetration_m(&self, t_s: f64) -> f64 {
        (self.speed_m_per_s * (t_s - self.contact_time_s)).min(self.max_penetration_m)
    }

    /// The penetration of every frame at mid-exposure, increasing; the
    /// in-contact ones are exact multiples of the step (no rounding drift).
    pub fn penetrations_m(&self) -> Vec<f64> {
        let step_m = self.frame_interval_s * self.speed_m_per_s;
        (0..self.frames)
            .map(|k| {
                if k + 1 == self.frames {
                    self.max_penetration_m
                } else {
                    (k as f64 - self.before_contact as f64 + self.phase) * step_m
                }
            })
            .collect()
    }

    /// End of the last exposure.
    pub fn end_s(&self) -> f64 {
        self.start_s(self.frames - 1) + self.exposure_s
    }

    /// Whether the shutter is open at camera time t (the camera's trigger
    /// output: high from an exposure's start to its end).
    pub fn exposing(&self, t_s: f64) -> bool {
        let k = (t_s / self.frame_interval_s).floor();
        (0.0..self.frames as f64).contains(&k) && t_s - self.start_s(k as usize) < self.exposure_s
    }
}

/// The force sensor: sampling rate, resolution (the logged value is a
/// multiple of it), Gaussian noise before quantisation, and its clock's
/// offset (sensor time − camera time).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceSensor {
    pub rate_hz: f64,
    pub resolution_n: f64,
    pub noise_n: f64,
    pub clock_offset_s: f64,
}

/// Seconds of log at least before the first frame and after the last (and
/// at least two frame intervals, so a clock offset estimated within one
/// interval still finds every frame in the log).
const LOG_MARGIN_S: f64 = 1.0;

impl ForceSensor {
    /// The log `(sensor time, force)` over the ramp, one sample every
    /// 1/rate of the sensor's clock from [`LOG_MARGIN_S`] (or two frame
    /// intervals) before the first frame to as long after the last.
    /// `force_at(penetration)` is the true force (0 before contact).
    pub fn log(&self, ramp: &Ramp, force_at: impl Fn(f64) -> f64, seed: u64) -> Vec<(f64, f64)> {
        let margin_s = LOG_MARGIN_S.max(2.0 * ramp.frame_interval_s);
        let first = ((-margin_s + self.clock_offset_s) * self.rate_hz).floor() as i64;
        let last = ((ramp.end_s() + margin_s + self.clock_offset_s) * self.rate_hz).ceil() as i64;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (first..=last)
            .map(|j| {
                let sensor_s = j as f64 / self.rate_hz;
                let camera_s = sensor_s - self.clock_offset_s;
                let true_n = force_at(ramp.penetration_m(camera_s));
                let z: f64 = StandardNormal.sample(&mut rng);
                let measured = true_n + self.noise_n * z;
                // + 0.0 turns a quantised −0 into 0 (no "-0.00" in the log)
                let logged = (measured / self.resolution_n).round() * self.resolution_n + 0.0;
                (sensor_s, logged)
            })
            .collect()
    }

    /// Decimals that show every multiple of the resolution exactly.
    pub fn decimals(&self) -> usize {
        (-self.resolution_n.log10()).ceil().clamp(0.0, 12.0) as usize
    }
}

/// The true force at `penetration_m` by linear interpolation of the solved
/// points (increasing penetrations, the first at first contact with F = 0);
/// 0 before contact, the last force beyond the last point.
pub fn interpolate_force(points: &[(f64, f64)], penetration_m: f64) -> f64 {
    if penetration_m <= 0.0 || points.is_empty() {
        return 0.0;
    }
    let i = points.partition_point(|(d, _)| *d < penetration_m);
    if i == 0 {
        return points[0].1;
    }
    if i >= points.len() {
        return points[points.len() - 1].1;
    }
    let (d0, f0) = points[i - 1];
    let (d1, f1) = points[i];
    f0 + (f1 - f0) * (penetration_m - d0) / (d1 - d0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shutter_is_open_from_each_start_for_one_exposure() {
        let ramp = Ramp::new(5, 1, 0.5, 1e-5, 1e-6, 0.05).unwrap();
        let dt = ramp.frame_interval_s;
        for k in 0..5 {
            let start = ramp.start_s(k);
            assert!(ramp.exposing(start) && ramp.exposing(start + 0.049));
            assert!(!ramp.exposing(start + 0.051) && !ramp.exposing(start - 0.001));
            assert!(!ramp.exposing(start + 0.5 * dt));
        }
        assert!(!ramp.exposing(-0.01) && !ramp.exposing(ramp.start_s(5) + 0.01));
    }

    #[test]
    fn frames_hit_the_schedule() {
        let ramp = Ramp::new(10, 3, 0.5, 20e-6, 3e-6, 0.05).unwrap();
        let d = ramp.penetrations_m();
        assert_eq!(d.len(), 10);
        assert!(d[..3].iter().all(|x| *x < 0.0) && d[3] > 0.0);
        assert_eq!(d[9], 20e-6);
        // Each frame's penetration is the ramp's at its mid-exposure.
        for (k, dk) in d.iter().enumerate() {
            assert!(
                (ramp.penetration_m(ramp.mid_s(k)) - dk).abs() < 1e-15,
                "{k}"
            );
        }
        // 6.5 steps of 20/6.5 µm at 3 µm/s
        assert!((ramp.frame_interval_s - 20.0 / 6.5 / 3.0).abs() < 1e-12);
        let e = Ramp::new(100, 3, 0.5, 1e-6, 3e-6, 0.05).unwrap_err();
        assert!(e.contains("shorter than the 0.05 s exposure"), "{e}");
        assert!(Ramp::new(4, 3, 0.5, 1e-6, 3e-6, 0.05).is_err());
        assert!(Ramp::new(10, 3, 0.0, 1e-6, 3e-6, 0.05).is_err());
        // phase 0.3: the touch falls 0.3 intervals before frame 3's mid-exposure
        let ramp = Ramp::new(10, 3, 0.3, 20e-6, 3e-6, 0.05).unwrap();
        let d = ramp.penetrations_m();
        assert!((d[3] - 0.3 * ramp.frame_interval_s * 3e-6).abs() < 1e-18);
        assert!((ramp.mid_s(3) - ramp.contact_time_s - 0.3 * ramp.frame_interval_s).abs() < 1e-12);
        assert_eq!(d[9], 20e-6);
    }

    #[test]
    fn force_log_is_on_the_sensor_clock_and_quantised() {
        let ramp = Ramp::new(10, 3, 0.5, 20e-6, 3e-6, 0.05).unwrap();
        let sensor = ForceSensor {
            rate_hz: 50.0,
            resolution_n: 0.01,
            noise_n: 0.0,
            clock_offset_s: 0.37,
        };
        // F = 1 N per µm of penetration
        let log = sensor.log(&ramp, |d| d.max(0.0) * 1e6, 5);
        assert!(
            log.windows(2)
                .all(|w| (w[1].0 - w[0].0 - 0.02).abs() < 1e-12)
        );
        let margin = 2.0 * ramp.frame_interval_s;
        assert!(log[0].0 <= 0.37 - margin && log.last().unwrap().0 >= ramp.end_s() + 0.37 + margin);
        for &(t, f) in &log {
            let truth = ramp.penetration_m(t - 0.37).max(0.0) * 1e6;
            assert!((f - truth).abs() <= 0.005 + 1e-12, "{t}: {f} vs {truth}");
            assert!((f / 0.01 - (f / 0.01).round()).abs() < 1e-9);
        }
        assert_eq!(sensor.decimals(), 2);
        let pts = [(0.0, 0.0), (1.0, 2.0), (3.0, 4.0)];
        assert_eq!(interpolate_force(&pts, -1.0), 0.0);
        assert_eq!(interpolate_force(&pts, 2.0), 3.0);
        assert_eq!(interpolate_force(&pts, 5.0), 4.0);
    }
}
