//! The robots' bodies, defined once: the rover's climb limit and footprint that physics'
//! collision rule, the mapper, the planner and the evaluation all read, and where both robots'
//! cameras sit ([`camera`]) for the camera process, the offline VO traverse and the evaluation.
//!
//! Its keys live in `[physics.rover]` (physics simulates the body); [`RoverBody::from_config`]
//! reads them there for any other crate, with the defaults of [`RoverBody::default`], the
//! only place they are written.
//!
//! ```
//! use hopnav_robot::RoverBody;
//! let body = RoverBody::default();
//! assert_eq!(body.max_climbable_height_m, 0.2);
//! assert!(body.inscribed_radius_m() < body.circumscribed_radius_m());
//! ```
#![warn(missing_docs)]

pub mod camera;

use hopnav_config::{ConfigError, HopnavConfig};
use serde::{Deserialize, Serialize};

/// The rover's rigid body: chassis on four wheels at `(±wheelbase/2, ±track/2)` in the body
/// frame (x forward, y left, z up).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RoverBody {
    /// Distance between front and rear axles, metres.
    pub wheelbase_m: f64,
    /// Distance between left and right wheel centres, metres.
    pub track_m: f64,
    /// Wheel radius, metres.
    pub wheel_radius_m: f64,
    /// Wheel width, metres.
    pub wheel_width_m: f64,
    /// Chassis box half extents (x, y, z), metres.
    pub chassis_half_extents_m: [f64; 3],
    /// Height of the chassis belly above the wheel contact plane, metres.
    pub ground_clearance_m: f64,
    /// Rocks taller than this block the rover; smaller ones are driven over, metres.
    pub max_climbable_height_m: f64,
    /// Largest pitch or roll the rover accepts before it refuses to move on, radians.
    pub max_tilt_rad: f64,
}

impl Default for RoverBody {
    fn default() -> Self {
        Self {
            wheelbase_m: 0.8,
            track_m: 0.7,
            wheel_radius_m: 0.15,
            wheel_width_m: 0.1,
            chassis_half_extents_m: [0.5, 0.35, 0.12],
            ground_clearance_m: 0.3,
            max_climbable_height_m: 0.2,
            max_tilt_rad: 30f64.to_radians(),
        }
    }
}

impl RoverBody {
    /// Reads the body's keys of `[physics.rover]` (absent keys take the defaults; the keys
    /// that are not the body's are physics' business). Physics validates the ranges; this
    /// refuses only what would make a footprint meaningless.
    pub fn from_config(config: &HopnavConfig) -> Result<Self, ConfigError> {
        let table = config
            .sections
            .get("physics")
            .and_then(|physics| physics.get("rover"))
            .cloned()
            .unwrap_or_else(|| toml::Value::Table(toml::Table::new()));
        let body: Self =
            table
                .try_into()
                .map_err(|error: toml::de::Error| ConfigError::Schema {
                    key: "physics.rover".to_owned(),
                    message: error.message().to_owned(),
                })?;
        body.check()?;
        Ok(body)
    }

    fn check(&self) -> Result<(), ConfigError> {
        let lengths = [
            ("wheelbase_m", self.wheelbase_m),
            ("track_m", self.track_m),
            ("wheel_radius_m", self.wheel_radius_m),
            ("wheel_width_m", self.wheel_width_m),
            ("chassis_half_extents_m[0]", self.chassis_half_extents_m[0]),
            ("chassis_half_extents_m[1]", self.chassis_half_extents_m[1]),
            ("chassis_half_extents_m[2]", self.chassis_half_extents_m[2]),
            ("ground_clearance_m", self.ground_clearance_m),
            ("max_climbable_height_m", self.max_climbable_height_m),
        ];
        for (key, value) in lengths {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ConfigError::Schema {
                    key: format!("physics.rover.{key}"),
                    message: format!("{value} is not a length: expected a finite value ≥ 0"),
                });
            }
        }
        if !(self.max_tilt_rad > 0.0 && self.max_tilt_rad < std::f64::consts::FRAC_PI_2) {
            return Err(ConfigError::Schema {
                key: "physics.rover.max_tilt_rad".to_owned(),
                message: format!(
                    "{} is not a tilt limit: expected an angle in (0, π/2) radians",
                    self.max_tilt_rad
                ),
            });
        }
        Ok(())
    }

    /// Length of the footprint along x (wheels or chassis, whichever reaches further), metres.
    pub fn footprint_length_m(&self) -> f64 {
        (self.wheelbase_m + 2.0 * self.wheel_radius_m).max(2.0 * self.chassis_half_extents_m[0])
    }

    /// Width of the footprint along y (wheels or chassis, whichever reaches further), metres.
    pub fn footprint_width_m(&self) -> f64 {
        (self.track_m + self.wheel_width_m).max(2.0 * self.chassis_half_extents_m[1])
    }

    /// Radius of the largest circle about the body centre inside the footprint, metres.
    pub fn inscribed_radius_m(&self) -> f64 {
        0.5 * self.footprint_length_m().min(self.footprint_width_m())
    }

    /// Radius of the smallest circle about the body centre holding the footprint, metres.
    pub fn circumscribed_radius_m(&self) -> f64 {
        0.5 * self.footprint_length_m().hypot(self.footprint_width_m())
    }
}

/// What the ground's slope under the rover's centre does to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlopeClass {
    /// The body tilts less than three quarters of its limit.
    Level,
    /// Within a quarter of the limit: the bumps that the slope averaged over the wheelbase
    /// hides may tip it over; drivable at a cost.
    Steep,
    /// Driven up or down it, the body tilts beyond what it accepts: it cannot go there.
    TooSteep,
}

impl RoverBody {
    /// Half the span over which the ground's slope tilts the body (its wheels stand half the
    /// wheelbase ahead of and behind its centre), metres.
    pub fn slope_half_span_m(&self) -> f64 {
        0.5 * self.wheelbase_m
    }

    /// What a ground rising `rise_per_run` (the gradient's magnitude, averaged over
    /// [`Self::slope_half_span_m`] either side of the centre) does to the body: a rover
    /// driven straight up or down it pitches by its full angle, so that angle is judged
    /// against [`Self::max_tilt_rad`]. A non-finite slope says nothing: `Level`.
    pub fn slope_class(&self, rise_per_run: f64) -> SlopeClass {
        let angle_rad = rise_per_run.abs().atan();
        if !angle_rad.is_finite() || angle_rad <= 0.75 * self.max_tilt_rad {
            SlopeClass::Level
        } else if angle_rad <= self.max_tilt_rad {
            SlopeClass::Steep
        } else {
            SlopeClass::TooSteep
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(toml_text: &str) -> HopnavConfig {
        hopnav_config::load(Some(toml_text)).expect("valid config")
    }

    #[test]
    fn the_default_footprint_is_the_wheels_and_chassis_extent() {
        let body = RoverBody::default();
        assert!((body.footprint_length_m() - 1.1).abs() < 1e-12);
        assert!((body.footprint_width_m() - 0.8).abs() < 1e-12);
        assert!((body.inscribed_radius_m() - 0.4).abs() < 1e-12);
        assert!((body.circumscribed_radius_m() - 0.5 * 1.1f64.hypot(0.8)).abs() < 1e-12);
    }

    #[test]
    fn a_slope_is_judged_by_the_pitch_it_gives_against_the_tilt_limit() {
        let body = RoverBody::default();
        let rise = |degrees: f64| degrees.to_radians().tan();
        assert_eq!(body.slope_class(rise(10.0)), SlopeClass::Level);
        assert_eq!(body.slope_class(-rise(26.0)), SlopeClass::Steep);
        // A fresh crater's wall (0.8 rise per run at its rim, 39°).
        assert_eq!(body.slope_class(0.8), SlopeClass::TooSteep);
        assert_eq!(body.slope_class(f64::NAN), SlopeClass::Level);
        assert!((body.slope_half_span_m() - 0.4).abs() < 1e-12);
    }

    #[test]
    fn the_body_is_read_from_physics_rover_and_other_keys_are_left_to_physics() {
        let body = RoverBody::from_config(&config(
            "[physics.rover]\nmax_climbable_height_m = 0.25\nmax_speed_mps = 0.3\n",
        ))
        .expect("body");
        assert_eq!(body.max_climbable_height_m, 0.25);
        assert_eq!(body.track_m, RoverBody::default().track_m);
        let absent = RoverBody::from_config(&config("")).expect("defaults");
        assert_eq!(absent, RoverBody::default());
    }

    #[test]
    fn a_bad_body_key_is_named() {
        let error = RoverBody::from_config(&config("[physics.rover]\ntrack_m = \"wide\"\n"))
            .expect_err("a string is no length")
            .to_string();
        assert!(error.contains("physics.rover"), "{error}");
        let error = RoverBody::from_config(&config("[physics.rover]\nmax_tilt_rad = 2.0\n"))
            .expect_err("beyond a right angle")
            .to_string();
        assert!(error.contains("max_tilt_rad"), "{error}");
        let error = RoverBody::from_config(&config("[physics.rover]\nwheelbase_m = -1.0\n"))
            .expect_err("negative")
            .to_string();
        assert!(error.contains("physics.rover.wheelbase_m"), "{error}");
    }
}
