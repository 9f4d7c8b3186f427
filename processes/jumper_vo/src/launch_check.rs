//! Did a commanded hop leave the ground? An altimeter test of three hypotheses.
//!
//! A hop can fail (the jumper wedged against a rock, or on its side: the body stays at its
//! launch altitude) or be deflected (a rock in the way of the launch: a lower, slower arc than
//! commanded). A deflected arc that climbs less than half the commanded height is nearer to
//! "stayed" than to "the commanded arc", so testing those two alone lands real flights back at
//! their launch (metres of error, seen in missions). The check
//! therefore also weighs the best-fitting *low* arc, vertical launch speed in
//! [[`MIN_CLIMB_FRACTION`] · commanded, commanded], which rests at the launch altitude after
//! its touchdown.
//!
//! ```
//! use hopnav_jumper_vo::launch_check::LaunchCheck;
//! let g = 3.711;
//! let mut stayed = LaunchCheck::new(8.66, g, 1.0);
//! let mut deflected = LaunchCheck::new(8.66, g, 1.0);
//! for k in 1..=12 {
//!     let t = 0.1 * k as f64;
//!     stayed.add(t, 0.0);
//!     deflected.add(t, 4.2 * t - 0.5 * g * t * t);
//! }
//! assert!(stayed.failed());
//! assert!(!deflected.failed());
//! ```

/// Log-odds of "stayed" against the commanded arc beyond which the commanded arc is ruled out
/// (e^12: a real climb of a few metres reaches the opposite sign within a second).
pub const COMMANDED_ARC_LLR: f64 = 12.0;

/// Log-odds of "stayed" against the best low arc beyond which the hop counts as failed. Low:
/// the commanded arc is already ruled out, and a low arc's evidence ends with its flight.
pub const LOW_ARC_LLR: f64 = 2.0;

/// Slowest deflected launch considered a flight, as a fraction of the commanded vertical
/// speed: at 10 m/s and 60° commanded, 2.6 m/s up (a 0.9 m apex); slower hops land within a
/// few metres of their launch, which a failed launch's estimate is no worse than.
pub const MIN_CLIMB_FRACTION: f64 = 0.3;

/// Samples weighed per hop (the commanded climb lasts ~2.3 s at 10 fps): bounds memory.
const MAX_SAMPLES: usize = 128;

/// Vertical launch speeds tried for the low arc.
const LOW_ARC_STEPS: usize = 24;

/// Altimeter evidence, since one launch, on whether it left the ground.
#[derive(Debug, Clone, PartialEq)]
pub struct LaunchCheck {
    commanded_vz_mps: f64,
    gravity_mps2: f64,
    sigma_m: f64,
    /// (τ since launch s, altitude above the launch altitude m), while the commanded arc climbs.
    samples: Vec<(f64, f64)>,
    /// Log-likelihood ratio of the commanded arc against "stayed" (negative: stayed).
    commanded_llr: f64,
}

impl LaunchCheck {
    /// A check for a launch commanded at `commanded_vz_mps` upward, with an altimeter of σ
    /// `sigma_m` (floored at 1 mm). Without an upward command there is nothing to check.
    pub fn new(commanded_vz_mps: f64, gravity_mps2: f64, sigma_m: f64) -> Self {
        Self {
            commanded_vz_mps,
            gravity_mps2,
            sigma_m: if sigma_m.is_finite() {
                sigma_m.max(1e-3)
            } else {
                1.0
            },
            samples: Vec::new(),
            commanded_llr: 0.0,
        }
    }

    /// Height of an arc launched at `vz_mps` above its launch altitude at `tau_s`, resting
    /// at the launch altitude once it is back down.
    fn arc_height_m(&self, vz_mps: f64, tau_s: f64) -> f64 {
        (vz_mps * tau_s - 0.5 * self.gravity_mps2 * tau_s * tau_s).max(0.0)
    }

    /// Weighs an altimeter sample `climbed_m` above the launch altitude at `tau_s` after the
    /// launch. Samples after the commanded apex are ignored (the arc flown may have landed on
    /// higher or lower ground by then); so are non-finite ones.
    pub fn add(&mut self, tau_s: f64, climbed_m: f64) {
        let v = self.commanded_vz_mps;
        if !(tau_s.is_finite() && climbed_m.is_finite())
            || v <= 0.0
            || tau_s <= 0.0
            || tau_s * self.gravity_mps2 > v
            || self.samples.len() >= MAX_SAMPLES
        {
            return;
        }
        let flew = climbed_m - self.arc_height_m(v, tau_s);
        self.commanded_llr +=
            (climbed_m * climbed_m - flew * flew) / (2.0 * self.sigma_m * self.sigma_m);
        self.samples.push((tau_s, climbed_m));
    }

    /// Log-likelihood ratio of the best low arc against "stayed" (negative: stayed).
    pub fn low_arc_llr(&self) -> f64 {
        let v_max = self.commanded_vz_mps;
        let v_min = MIN_CLIMB_FRACTION * v_max;
        let two_var = 2.0 * self.sigma_m * self.sigma_m;
        (0..=LOW_ARC_STEPS)
            .map(|i| v_min + (v_max - v_min) * i as f64 / LOW_ARC_STEPS as f64)
            .map(|vz| {
                self.samples
                    .iter()
                    .map(|&(tau, climbed)| {
                        let flew = climbed - self.arc_height_m(vz, tau);
                        (climbed * climbed - flew * flew) / two_var
                    })
                    .sum::<f64>()
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// True once the altimeter has ruled out the commanded arc (odds e^[`COMMANDED_ARC_LLR`])
    /// and favours "stayed" over every low arc (odds e^[`LOW_ARC_LLR`]).
    pub fn failed(&self) -> bool {
        self.commanded_llr < -COMMANDED_ARC_LLR && self.low_arc_llr() < -LOW_ARC_LLR
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 3.711;

    fn check_of(climb: impl Fn(f64) -> f64, frames: usize) -> LaunchCheck {
        let mut check = LaunchCheck::new(8.66, G, 1.0);
        for k in 1..=frames {
            let t = 0.1 * k as f64;
            check.add(t, climb(t));
        }
        check
    }

    #[test]
    fn the_commanded_arc_is_a_flight() {
        let check = check_of(|t| 8.66 * t - 0.5 * G * t * t, 20);
        assert!(!check.failed());
        assert!(check.low_arc_llr() > 0.0);
    }

    #[test]
    fn a_body_at_rest_fails_within_a_second() {
        assert!(check_of(|_| 0.0, 10).failed());
    }

    #[test]
    fn a_low_deflected_arc_is_a_flight_though_the_commanded_one_is_ruled_out() {
        let check = check_of(|t| (3.5 * t - 0.5 * G * t * t).max(0.0), 20);
        assert!(check.commanded_llr < -COMMANDED_ARC_LLR);
        assert!(!check.failed());
    }

    #[test]
    fn without_an_upward_command_or_with_bad_samples_nothing_is_weighed() {
        let mut check = LaunchCheck::new(0.0, G, 1.0);
        check.add(0.5, 0.0);
        assert!(check.samples.is_empty() && !check.failed());
        let mut check = LaunchCheck::new(8.66, G, f64::NAN);
        check.add(f64::NAN, 0.0);
        check.add(0.5, f64::INFINITY);
        check.add(-0.5, 0.0);
        assert!(check.samples.is_empty() && !check.failed());
    }
}
