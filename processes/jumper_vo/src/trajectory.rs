//! Analytic ballistic hop (Table 1 of the paper): the truth trajectory of the simulator.
//!
//! Position `p(t) = p0 + v0 t − ½ g t² ẑ` until touchdown (back at the launch altitude), then
//! at rest. Attitude: yaw = heading, pitch = `initial_pitch_rad + pitch_rate_radps · t`
//! (nose-up positive; the sign of the rate is a parameter), roll 0, frozen at touchdown.
//!
//! ```
//! use hopnav_jumper_vo::trajectory::HopTrajectory;
//! let hop = HopTrajectory::table1();
//! assert!((hop.flight_time_s() - 4.667).abs() < 1e-3);
//! assert!((hop.range_m() - 23.34).abs() < 1e-2);
//! assert!((hop.apex_height_m() - 10.10).abs() < 1e-2);
//! ```

use crate::frames::rotation_from_euler;
use nalgebra::{Isometry3, Point3, Translation3, Vector3};

/// Mars surface gravity, m/s².
pub const MARS_G_MPS2: f64 = 3.711;

/// Parameters of one analytic hop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HopTrajectory {
    /// Body origin at launch, world frame, metres.
    pub launch_position_m: Point3<f64>,
    /// Launch heading (yaw of body x), radians.
    pub heading_rad: f64,
    /// Launch speed, m/s.
    pub speed_mps: f64,
    /// Launch elevation angle of the velocity, radians.
    pub elevation_rad: f64,
    /// Gravity, m/s².
    pub gravity_mps2: f64,
    /// Body pitch at launch (nose-up positive), radians.
    pub initial_pitch_rad: f64,
    /// Body pitch rate (nose-up positive), rad/s.
    pub pitch_rate_radps: f64,
}

impl HopTrajectory {
    /// Table 1: 10 m/s at 60°, Mars gravity, 0.1 rad/s nose-up, level body at launch, from the
    /// origin along +x.
    pub fn table1() -> Self {
        Self {
            launch_position_m: Point3::origin(),
            heading_rad: 0.0,
            speed_mps: 10.0,
            elevation_rad: 60f64.to_radians(),
            gravity_mps2: MARS_G_MPS2,
            initial_pitch_rad: 0.0,
            pitch_rate_radps: 0.1,
        }
    }

    /// Launch velocity, world frame, m/s.
    pub fn launch_velocity_mps(&self) -> Vector3<f64> {
        let (se, ce) = self.elevation_rad.sin_cos();
        let (sh, ch) = self.heading_rad.sin_cos();
        self.speed_mps * Vector3::new(ce * ch, ce * sh, se)
    }

    /// Time from launch to touchdown at the launch altitude, seconds.
    pub fn flight_time_s(&self) -> f64 {
        if self.gravity_mps2 > 0.0 {
            (2.0 * self.launch_velocity_mps().z / self.gravity_mps2).max(0.0)
        } else {
            f64::INFINITY
        }
    }

    /// Horizontal distance of the hop, metres.
    pub fn range_m(&self) -> f64 {
        self.speed_mps * self.elevation_rad.cos() * self.flight_time_s()
    }

    /// Apex height above the launch point, metres.
    pub fn apex_height_m(&self) -> f64 {
        let vz = self.launch_velocity_mps().z;
        vz * vz / (2.0 * self.gravity_mps2)
    }

    /// Body origin at `t_s` seconds after launch (clamped to `[0, flight time]`).
    pub fn position_m(&self, t_s: f64) -> Point3<f64> {
        let t = t_s.clamp(0.0, self.flight_time_s());
        self.launch_position_m + self.launch_velocity_mps() * t
            - Vector3::z() * (0.5 * self.gravity_mps2 * t * t)
    }

    /// Body velocity at `t_s` (zero after touchdown).
    pub fn velocity_mps(&self, t_s: f64) -> Vector3<f64> {
        if !(0.0..=self.flight_time_s()).contains(&t_s) {
            return Vector3::zeros();
        }
        self.launch_velocity_mps() - Vector3::z() * (self.gravity_mps2 * t_s)
    }

    /// Body pitch at `t_s` (nose-up positive), radians.
    pub fn pitch_rad(&self, t_s: f64) -> f64 {
        self.initial_pitch_rad + self.pitch_rate_radps * t_s.clamp(0.0, self.flight_time_s())
    }

    /// `world_from_body` at `t_s`.
    pub fn world_from_body(&self, t_s: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.position_m(t_s).coords),
            rotation_from_euler(0.0, self.pitch_rad(t_s), self.heading_rad),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lands_at_launch_altitude_and_rests() {
        let hop = HopTrajectory::table1();
        let tf = hop.flight_time_s();
        assert!(hop.position_m(tf).z.abs() < 1e-9);
        assert_eq!(hop.position_m(tf + 1.0), hop.position_m(tf));
        assert_eq!(hop.velocity_mps(tf + 0.1), Vector3::zeros());
        assert!((hop.position_m(tf / 2.0).z - hop.apex_height_m()).abs() < 1e-9);
    }
}
