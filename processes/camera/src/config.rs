//! The `[camera]` table: both cameras' intrinsics, mounts and rendering options.

use hopnav_config::{ConfigError, HopnavConfig, in_section, parse_section};
use hopnav_world::camera::CameraConfig;
use hopnav_world::raster::RenderConfig;
use serde::{Deserialize, Serialize};

/// Where a camera sits on its robot (body frame: x forward, y left, z up).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MountConfig {
    /// Optical centre in the body frame, metres (for a stereo pair: midway between the two).
    pub position_m: [f64; 3],
    /// Viewing direction about body z: 0 = forward, π = backward, radians.
    pub yaw_rad: f64,
    /// Tilt below the body's x-y plane, radians.
    pub pitch_down_rad: f64,
}

/// `[camera]`: the jumper's rear mono camera and the rover's stereo pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSection {
    /// Jumper camera intrinsics (paper: 320×320, FOV 45° → f = 386.3 px, not the paper's
    /// 521.78 px, which does not match its own FOV).
    pub jumper: CameraConfig,
    /// Jumper camera mount: at the rear, facing backward (along body −x).
    pub jumper_mount: MountConfig,
    /// Rover stereo intrinsics (both views).
    pub rover: CameraConfig,
    /// Rover stereo mount (midpoint of the pair).
    pub rover_mount: MountConfig,
    /// Rover stereo baseline along the camera x axis, metres.
    pub rover_baseline_m: f64,
    /// Pixel noise, sky value, level of detail.
    pub render: RenderConfig,
}

impl Default for CameraSection {
    fn default() -> Self {
        Self {
            jumper: CameraConfig::default(),
            // Physics sets the jumper to its launch attitude (body x along the launch
            // direction, 60° up), so a camera along body −x looks 60° below the horizon,
            // backward, at launch and tilts up as the body pitches nose-down in flight.
            jumper_mount: MountConfig {
                position_m: [-0.12, 0.0, 0.0],
                yaw_rad: std::f64::consts::PI,
                pitch_down_rad: 0.0,
            },
            rover: CameraConfig {
                width_px: 320,
                height_px: 240,
                hfov_rad: 60_f64.to_radians(),
                vfov_rad: None,
                near_m: 0.05,
            },
            rover_mount: MountConfig {
                position_m: [0.3, 0.0, 1.0],
                yaw_rad: 0.0,
                pitch_down_rad: 15_f64.to_radians(),
            },
            rover_baseline_m: 0.2,
            render: RenderConfig::default(),
        }
    }
}

/// Maps a world-crate validation error to ours, with the key under `section` (the world crate
/// names keys relative to where it was asked to look).
pub fn from_world_error(error: hopnav_world::ConfigError, section: &str) -> ConfigError {
    let full_key = |key: String| {
        if key.starts_with(section) {
            key
        } else {
            format!("{section}.{key}")
        }
    };
    match error {
        hopnav_world::ConfigError::OutOfRange { key, range, value } => ConfigError::OutOfRange {
            key: full_key(key),
            value,
            allowed: range,
        },
        hopnav_world::ConfigError::Inconsistent { key, reason } => ConfigError::Schema {
            key: full_key(key),
            message: reason,
        },
    }
}

impl CameraSection {
    /// Parses and validates `[camera]`; errors name `camera.<key>`.
    pub fn from_config(config: &HopnavConfig) -> Result<Self, ConfigError> {
        let section: Self = parse_section(config, "camera")?;
        section.validate()?;
        Ok(section)
    }

    /// Checks every value.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.jumper
            .validate("camera.jumper")
            .map_err(|e| from_world_error(e, "camera"))?;
        self.rover
            .validate("camera.rover")
            .map_err(|e| from_world_error(e, "camera"))?;
        self.render
            .validate("camera.render")
            .map_err(|e| from_world_error(e, "camera"))?;
        for (name, mount) in [
            ("jumper_mount", &self.jumper_mount),
            ("rover_mount", &self.rover_mount),
        ] {
            if !mount
                .position_m
                .iter()
                .all(|v| v.is_finite() && v.abs() <= 10.0)
            {
                return Err(in_section(
                    "camera",
                    &format!("{name}.position_m"),
                    format!("{:?}", mount.position_m),
                    "finite, each |v| <= 10",
                ));
            }
            if !(mount.yaw_rad.is_finite() && mount.yaw_rad.abs() <= 2.0 * std::f64::consts::PI) {
                return Err(in_section(
                    "camera",
                    &format!("{name}.yaw_rad"),
                    mount.yaw_rad,
                    "[-2π, 2π]",
                ));
            }
            if !(mount.pitch_down_rad.is_finite()
                && mount.pitch_down_rad.abs() <= std::f64::consts::FRAC_PI_2)
            {
                return Err(in_section(
                    "camera",
                    &format!("{name}.pitch_down_rad"),
                    mount.pitch_down_rad,
                    "[-π/2, π/2]",
                ));
            }
        }
        if !(self.rover_baseline_m.is_finite()
            && self.rover_baseline_m > 0.0
            && self.rover_baseline_m <= 2.0)
        {
            return Err(in_section(
                "camera",
                "rover_baseline_m",
                self.rover_baseline_m,
                "(0, 2]",
            ));
        }
        Ok(())
    }
}

/// Validates `[world]` (used by the launcher at start; the world crate names `terrain.*` etc.).
pub fn check_world_section(
    config: &HopnavConfig,
) -> Result<hopnav_world::WorldConfig, ConfigError> {
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    world.validate().map_err(|e| from_world_error(e, "world"))?;
    Ok(world)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(text: &str) -> HopnavConfig {
        hopnav_config::load(Some(text)).expect("base config")
    }

    #[test]
    fn defaults_are_valid_and_match_the_paper() {
        let section = CameraSection::from_config(&config("")).expect("defaults");
        assert_eq!(
            (section.jumper.width_px, section.jumper.height_px),
            (320, 320)
        );
        assert!((section.jumper.hfov_rad - 45_f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn bad_values_name_their_key() {
        let cases = [
            ("[camera.jumper]\nhfov_rad = -0.5\n", "camera.jumper"),
            ("[camera.jumper]\nwidth_px = 0\n", "width_px"),
            (
                "[camera]\nrover_baseline_m = 0.0\n",
                "camera.rover_baseline_m",
            ),
            (
                "[camera.jumper_mount]\nposition_m = [0.0, 0.0, 0.0]\nyaw_rad = 0.0\npitch_down_rad = 9.0\n",
                "camera.jumper_mount.pitch_down_rad",
            ),
            ("[camera]\nlens = \"fisheye\"\n", "lens"),
        ];
        for (text, key) in cases {
            let error = CameraSection::from_config(&config(text)).expect_err(text);
            assert!(error.to_string().contains(key), "{text}: {error}");
        }
    }
}
