//! The `[camera]` table: both cameras' intrinsics, mounts and rendering options.

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_robot::camera::{CameraMount, CameraRig};
use hopnav_world::camera::CameraConfig;
use hopnav_world::raster::RenderConfig;
use serde::{Deserialize, Serialize};

/// `[camera]`: the jumper's rear mono camera and the rover's stereo pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSection {
    /// Jumper camera intrinsics ([`CameraRig::jumper`]).
    pub jumper: CameraConfig,
    /// Jumper camera mount ([`CameraRig::jumper_mount`]).
    pub jumper_mount: CameraMount,
    /// Rover stereo intrinsics ([`CameraRig::rover`]).
    pub rover: CameraConfig,
    /// Rover stereo mount, the pair's midpoint ([`CameraRig::rover_mount`]).
    pub rover_mount: CameraMount,
    /// Rover stereo baseline, metres ([`CameraRig::rover_baseline_m`]).
    pub rover_baseline_m: f64,
    /// Pixel noise, sky value, level of detail.
    pub render: RenderConfig,
}

/// The cameras themselves are the robots' ([`CameraRig::default`], the one place their defaults
/// are written); the rendering options are this table's own.
impl Default for CameraSection {
    fn default() -> Self {
        let CameraRig {
            jumper,
            jumper_mount,
            rover,
            rover_mount,
            rover_baseline_m,
        } = CameraRig::default();
        Self {
            jumper,
            jumper_mount,
            rover,
            rover_mount,
            rover_baseline_m,
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

    /// The cameras without the rendering options.
    pub fn rig(&self) -> CameraRig {
        CameraRig {
            jumper: self.jumper.clone(),
            jumper_mount: self.jumper_mount,
            rover: self.rover.clone(),
            rover_mount: self.rover_mount,
            rover_baseline_m: self.rover_baseline_m,
        }
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
        self.rig().check()?;
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
