//! Attitude of a torque-free flight: `R(τ) = exp(ω τ) · R_launch` with a constant world-frame
//! angular velocity `ω`, fitted by least squares to the vision rotations between keyframes and
//! a prior at the commanded launch spin.
//!
//! Chaining each keyframe's rotation onto the last lets the attitude drift as a random walk:
//! about 1° over a 4.7 s hop in missions, which tilts the VO's translation directions by as
//! much and turns into a 5–10 % error of the hop's horizontal length. Nothing acts on the body
//! in flight but gravity, so its angular velocity stays what the launch gave it (physics shows
//! it constant to the print precision until touchdown), and the launch mechanism commands it.
//! The launch attitude anchors the fit and the commanded spin bounds its rate: the attitude
//! error then grows with the prior's σ times the flight time, not as a random walk. (Without
//! the prior, independent keyframe rotations give back the chain exactly: `ω̂ τ` is their sum.)
//!
//! The commanded spin is a strong prior (σ 0.003 rad/s by default: as strong as some 30
//! keyframe rotations). A launch that a rock turned spins otherwise, often by 0.05–0.15 rad/s,
//! and holding the commanded rate then tilts the attitude by 15–40° over the flight (hops of
//! 20 m came out 6–7 m off in boulder-field missions). So the prior is doubted: once
//! [`MIN_ROWS_TO_DOUBT`] rotations are measured, if the component-wise median of their rates
//! lies more than [`PRIOR_DOUBT_RADPS`] from the command, the prior is dropped and the rate is
//! the least-squares fit of the rows near that median. The median, not the mean, decides, and
//! rows far from it are left out either way: a single wrong rotation (the impact) must neither
//! throw the prior away on a nominal hop nor tilt the fit.
//!
//! ```
//! use hopnav_jumper_vo::spin::SpinFit;
//! use nalgebra::{UnitQuaternion, Vector3};
//! let launch = UnitQuaternion::identity();
//! let omega = Vector3::new(0.0, 0.1, 0.0);
//! let mut fit = SpinFit::new(launch, Vector3::zeros(), 0.0);
//! fit.add_increment(0.5, &UnitQuaternion::from_scaled_axis(omega * 0.5), 0.005);
//! assert!((fit.rate_radps() - omega).norm() < 1e-12);
//! assert!(fit.attitude_at(2.0).angle_to(&UnitQuaternion::from_scaled_axis(omega * 2.0)) < 1e-12);
//! ```

use nalgebra::{UnitQuaternion, Vector3};

/// Rotations measured before the commanded spin can be doubted.
pub const MIN_ROWS_TO_DOUBT: usize = 4;

/// The measured rates' median must lie this far from the commanded spin to drop it, rad/s
/// (any axis). A nominal hop's keyframe rates scatter by about 0.017 rad/s each (0.005 rad
/// over 0.3 s), so their median over 4 or more stays well within this.
pub const PRIOR_DOUBT_RADPS: f64 = 0.03;

/// Rows kept per flight (a hop has about 20 keyframes); later rows are ignored.
const MAX_ROWS: usize = 64;

/// One measured keyframe interval.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RateRow {
    dtau_s: f64,
    rotation_rad: Vector3<f64>,
    weight: f64,
}

impl RateRow {
    fn rate_radps(&self) -> Vector3<f64> {
        self.rotation_rad / self.dtau_s
    }

    /// σ of this row's rate, rad/s.
    fn rate_sigma_radps(&self) -> f64 {
        1.0 / (self.weight.sqrt() * self.dtau_s)
    }
}

/// The constant-rate fit (isotropic weights: scalar normal equations) over the measured rows,
/// with the commanded spin as a prior while the rows' median agrees with it.
#[derive(Debug, Clone, PartialEq)]
pub struct SpinFit {
    launch_rotation: UnitQuaternion<f64>,
    prior_radps: Vector3<f64>,
    /// Weight of the prior (0: none).
    prior_weight: f64,
    rows: Vec<RateRow>,
    /// The fitted rate, recomputed when a row comes.
    rate_radps: Vector3<f64>,
    prior_doubted: bool,
    /// The bundle adjustment's rate and launch attitude, used once set.
    refined: Option<(Vector3<f64>, UnitQuaternion<f64>)>,
}

impl SpinFit {
    /// A fit for a flight launched with attitude `launch_rotation` (world from body) and
    /// commanded world-frame spin `prior_radps`, believed within `prior_sigma_radps` per axis
    /// (≤ 0 or not finite: no prior; the commanded spin is used until a rotation is measured).
    pub fn new(
        launch_rotation: UnitQuaternion<f64>,
        prior_radps: Vector3<f64>,
        prior_sigma_radps: f64,
    ) -> Self {
        let prior_radps = if prior_radps.iter().all(|v| v.is_finite()) {
            prior_radps
        } else {
            Vector3::zeros()
        };
        let prior_weight = if prior_sigma_radps.is_finite() && prior_sigma_radps > 0.0 {
            prior_sigma_radps.powi(-2)
        } else {
            0.0
        };
        Self {
            launch_rotation,
            prior_radps,
            prior_weight,
            rows: Vec::with_capacity(MAX_ROWS),
            rate_radps: prior_radps,
            prior_doubted: false,
            refined: None,
        }
    }

    /// Adds a measured world-frame rotation `increment` (`R(τb) · R(τa)⁻¹`) over `dtau_s` =
    /// `τb − τa`, with angular σ `sigma_rad`. Non-finite or non-positive inputs are ignored.
    pub fn add_increment(&mut self, dtau_s: f64, increment: &UnitQuaternion<f64>, sigma_rad: f64) {
        let measured_rad = increment.scaled_axis();
        if !(dtau_s > 0.0
            && dtau_s.is_finite()
            && sigma_rad > 0.0
            && sigma_rad.is_finite()
            && measured_rad.iter().all(|v| v.is_finite()))
        {
            return;
        }
        if self.rows.len() >= MAX_ROWS {
            return;
        }
        self.rows.push(RateRow {
            dtau_s,
            rotation_rad: measured_rad,
            weight: sigma_rad.powi(-2),
        });
        self.refit();
    }

    /// Rotations measured so far.
    pub fn increments(&self) -> usize {
        self.rows.len()
    }

    /// The commanded world-frame spin the fit started from (zero when it was not finite).
    pub fn prior_radps(&self) -> Vector3<f64> {
        self.prior_radps
    }

    /// The measured rates disagree with the commanded spin: it no longer counts.
    pub fn prior_doubted(&self) -> bool {
        self.prior_doubted
    }

    /// Fitted world-frame angular velocity, rad/s (the commanded one until anything is known).
    pub fn rate_radps(&self) -> Vector3<f64> {
        self.refined.map_or(self.rate_radps, |(rate, _)| rate)
    }

    /// Hands the rate and the launch attitude to a better estimate (the bundle adjustment,
    /// which reads the tracks the increments came from): [`Self::rate_radps`] and
    /// [`Self::attitude_at`] use them from now on. Non-finite input is ignored.
    pub fn set_refined(
        &mut self,
        rate_radps: &Vector3<f64>,
        launch_rotation: &UnitQuaternion<f64>,
    ) {
        let finite = rate_radps.iter().all(|v| v.is_finite())
            && launch_rotation.coords.iter().all(|v| v.is_finite());
        if finite {
            self.refined = Some((*rate_radps, *launch_rotation));
        }
    }

    fn refit(&mut self) {
        let median = self.median_rate_radps();
        self.prior_doubted = self.rows.len() >= MIN_ROWS_TO_DOUBT
            && (median - self.prior_radps).amax() > PRIOR_DOUBT_RADPS;
        let (mut normal, mut rhs) = if self.prior_doubted {
            (0.0, Vector3::zeros())
        } else {
            (self.prior_weight, self.prior_radps * self.prior_weight)
        };
        for row in &self.rows {
            // A row far from the others' median (the impact: a wrong rotation of a few tenths
            // of a radian) is left out; with the prior kept it would still tilt the fit.
            let near_median = (row.rate_radps() - median).amax()
                <= (3.0 * row.rate_sigma_radps()).max(PRIOR_DOUBT_RADPS);
            if !near_median {
                continue;
            }
            normal += row.weight * row.dtau_s * row.dtau_s;
            rhs += row.rotation_rad * (row.weight * row.dtau_s);
        }
        self.rate_radps = if normal > 0.0 {
            rhs / normal
        } else if self.prior_doubted {
            median
        } else {
            self.prior_radps
        };
    }

    /// Component-wise median of the rows' rates (the prior without rows).
    fn median_rate_radps(&self) -> Vector3<f64> {
        if self.rows.is_empty() {
            return self.prior_radps;
        }
        let mut values = Vec::with_capacity(self.rows.len());
        Vector3::from_fn(|axis, _| {
            values.clear();
            values.extend(self.rows.iter().map(|row| row.rate_radps()[axis]));
            values.sort_by(f64::total_cmp);
            let mid = values.len() / 2;
            if values.len() % 2 == 0 {
                0.5 * (values[mid - 1] + values[mid])
            } else {
                values[mid]
            }
        })
    }

    /// Attitude (world from body) `tau_s` after the launch.
    pub fn attitude_at(&self, tau_s: f64) -> UnitQuaternion<f64> {
        let launch = self
            .refined
            .map_or(self.launch_rotation, |(_, launch)| launch);
        UnitQuaternion::from_scaled_axis(self.rate_radps() * tau_s) * launch
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::NoiseRng;

    /// Asserts that the fitted rate lies within `tol_radps` of `expected_radps`.
    #[track_caller]
    fn assert_rate_near(fit: &SpinFit, expected_radps: Vector3<f64>, tol_radps: f64) {
        let rate_radps = fit.rate_radps();
        assert!(
            (rate_radps - expected_radps).norm() < tol_radps,
            "{rate_radps:?} against {expected_radps:?}"
        );
    }

    fn noisy_increment(
        omega: Vector3<f64>,
        dtau: f64,
        sigma: f64,
        rng: &mut NoiseRng,
    ) -> UnitQuaternion<f64> {
        let noise = Vector3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * sigma;
        UnitQuaternion::from_scaled_axis(omega * dtau + noise)
    }

    #[test]
    fn the_commanded_spin_holds_the_attitude_closer_than_the_chain() {
        let omega = Vector3::new(0.02, -0.098, 0.0);
        let launch = UnitQuaternion::from_euler_angles(0.1, -0.5, 2.0);
        let mut fit = SpinFit::new(launch, omega, 0.003);
        let mut rng = NoiseRng::new(7);
        let mut chained = launch;
        let dtau = 0.3;
        for _ in 0..15 {
            let increment = noisy_increment(omega, dtau, 0.005, &mut rng);
            chained = increment * chained;
            fit.add_increment(dtau, &increment, 0.005);
        }
        let tau = 15.0 * dtau;
        let truth = UnitQuaternion::from_scaled_axis(omega * tau) * launch;
        let fitted_error = fit.attitude_at(tau).angle_to(&truth);
        let chained_error = chained.angle_to(&truth);
        assert!(fitted_error < 0.02, "fitted {fitted_error} rad");
        assert!(
            fitted_error < 0.5 * chained_error,
            "{fitted_error} vs chain {chained_error}"
        );
    }

    #[test]
    fn the_commanded_spin_pulls_until_enough_rotations_outweigh_it() {
        let commanded = Vector3::new(0.0, 0.1, 0.0);
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, 0.003);
        assert_eq!(fit.rate_radps(), commanded);
        // Rotations within their noise of the command: the prior holds them near it.
        let mut rng = NoiseRng::new(3);
        for _ in 0..5 {
            fit.add_increment(
                0.3,
                &noisy_increment(commanded, 0.3, 0.005, &mut rng),
                0.005,
            );
        }
        assert_rate_near(&fit, commanded, 0.005);
        // A launch that a rock turned spins at 0.5 rad/s: with a weaker prior, ten keyframe
        // rotations take the rate most of the way.
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, 0.01);
        let actual = Vector3::new(0.3, 0.4, 0.0);
        for _ in 0..10 {
            fit.add_increment(0.3, &UnitQuaternion::from_scaled_axis(actual * 0.3), 0.005);
        }
        assert_rate_near(&fit, actual, 0.1);
    }

    #[test]
    fn a_launch_spinning_otherwise_drops_the_prior_after_a_few_rotations() {
        // A rock turned the launch: it spins 0.1 rad/s off the command, about one keyframe
        // rate sigma; the default prior would hold the command through a whole hop.
        let commanded = Vector3::new(0.0, 0.1, 0.0);
        let actual = Vector3::new(0.08, 0.02, -0.05);
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, 0.003);
        let mut rng = NoiseRng::new(11);
        for row in 0..15 {
            fit.add_increment(0.3, &noisy_increment(actual, 0.3, 0.005, &mut rng), 0.005);
            assert_eq!(
                fit.prior_doubted(),
                row + 1 >= MIN_ROWS_TO_DOUBT,
                "row {row}"
            );
        }
        assert_rate_near(&fit, actual, 0.01);
    }

    #[test]
    fn one_wrong_rotation_does_not_throw_the_prior_away() {
        let commanded = Vector3::new(0.0, 0.1, 0.0);
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, 0.003);
        let mut rng = NoiseRng::new(5);
        for row in 0..10 {
            let increment = if row == 6 {
                // The impact: half a radian in one interval.
                UnitQuaternion::from_scaled_axis(Vector3::new(0.5, 0.0, 0.2))
            } else {
                noisy_increment(commanded, 0.3, 0.005, &mut rng)
            };
            fit.add_increment(0.3, &increment, 0.005);
        }
        assert!(!fit.prior_doubted());
        // Nor does it pull the fit: 0.04 rad/s (11° over a hop) if it were kept.
        assert_rate_near(&fit, commanded, 0.01);
    }

    #[test]
    fn bad_rows_are_ignored() {
        let commanded = Vector3::new(0.0, 0.1, 0.0);
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, f64::NAN);
        fit.add_increment(0.0, &UnitQuaternion::identity(), 0.005);
        fit.add_increment(f64::NAN, &UnitQuaternion::identity(), 0.005);
        fit.add_increment(0.3, &UnitQuaternion::identity(), 0.0);
        assert_eq!(fit.increments(), 0);
        assert_eq!(fit.rate_radps(), commanded);
        let no_prior = SpinFit::new(
            UnitQuaternion::identity(),
            Vector3::new(f64::NAN, 0.0, 0.0),
            1.0,
        );
        assert_eq!(no_prior.rate_radps(), Vector3::zeros());
    }
}
