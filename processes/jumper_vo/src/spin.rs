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
//! keyframe rotations), so a launch that a rock set spinning otherwise keeps much of the
//! commanded rate; a weaker prior (`launch_angular_velocity_sigma_radps`) lets the
//! measurements decide sooner. Dropping the prior when the measurements disagree with it was
//! tried: single wrong keyframe rotations (the impact) then threw it away on nominal hops.
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

/// Normal equations of the constant-rate fit (isotropic weights: a scalar normal matrix), the
/// measurements' apart from the prior's.
#[derive(Debug, Clone, PartialEq)]
pub struct SpinFit {
    launch_rotation: UnitQuaternion<f64>,
    prior_radps: Vector3<f64>,
    /// Weight of the prior (0: none).
    prior_weight: f64,
    normal: f64,
    rhs: Vector3<f64>,
    increments: usize,
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
            normal: 0.0,
            rhs: Vector3::zeros(),
            increments: 0,
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
        let weight = sigma_rad.powi(-2);
        self.normal += weight * dtau_s * dtau_s;
        self.rhs += measured_rad * (weight * dtau_s);
        self.increments += 1;
    }

    /// Rotations measured so far.
    pub fn increments(&self) -> usize {
        self.increments
    }

    /// Fitted world-frame angular velocity, rad/s (the commanded one until anything is known).
    pub fn rate_radps(&self) -> Vector3<f64> {
        let normal = self.normal + self.prior_weight;
        if normal > 0.0 {
            (self.rhs + self.prior_radps * self.prior_weight) / normal
        } else {
            self.prior_radps
        }
    }

    /// Attitude (world from body) `tau_s` after the launch.
    pub fn attitude_at(&self, tau_s: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_scaled_axis(self.rate_radps() * tau_s) * self.launch_rotation
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::NoiseRng;

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
        assert!((fit.rate_radps() - commanded).norm() < 0.005);
        // A launch that a rock turned spins at 0.5 rad/s: with a weaker prior, ten keyframe
        // rotations take the rate most of the way.
        let mut fit = SpinFit::new(UnitQuaternion::identity(), commanded, 0.01);
        let actual = Vector3::new(0.3, 0.4, 0.0);
        for _ in 0..10 {
            fit.add_increment(0.3, &UnitQuaternion::from_scaled_axis(actual * 0.3), 0.005);
        }
        assert!(
            (fit.rate_radps() - actual).norm() < 0.1,
            "{:?}",
            fit.rate_radps()
        );
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
