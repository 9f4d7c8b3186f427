//! How the surface looks: texture and lighting.

use serde::{Deserialize, Serialize};

use super::{Interval, MAX_TEXTURE_TEXELS, TerrainConfig, inconsistent};
use crate::error::ConfigError;

/// Procedural surface texture parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TextureConfig {
    /// Texel size of the baked terrain texture, metres.
    pub texel_m: f64,
    /// Texel size of the tiled fine-detail texture (sand, grit), metres.
    pub detail_texel_m: f64,
    /// Mean ground albedo in digital numbers (before shading).
    pub albedo_dn: f64,
    /// Relative albedo variation of the multi-scale noise (0 = uniform ground).
    pub macro_contrast: f64,
    /// Relative contrast of the fine-detail texture (0 = none).
    pub detail_contrast: f64,
    /// Pebbles (1–8 cm) per square metre baked into the terrain texture.
    pub pebble_density_per_m2: f64,
    /// Amplitude of the centimetre-scale bumps used for shading, metres.
    pub bump_amplitude_m: f64,
    /// Mean rock albedo in digital numbers.
    pub rock_albedo_dn: f64,
}

impl Default for TextureConfig {
    fn default() -> Self {
        Self {
            texel_m: 0.02,
            detail_texel_m: 0.004,
            albedo_dn: 150.0,
            macro_contrast: 0.35,
            detail_contrast: 0.4,
            pebble_density_per_m2: 60.0,
            bump_amplitude_m: 0.01,
            rock_albedo_dn: 140.0,
        }
    }
}

impl TextureConfig {
    /// Checks the values under `prefix`; the texture may not exceed
    /// [`MAX_TEXTURE_TEXELS`] per side over the terrain.
    pub fn validate(&self, prefix: &str, terrain: &TerrainConfig) -> Result<(), ConfigError> {
        Interval::closed(0.002, 0.5).check(prefix, "texel_m", self.texel_m)?;
        Interval::closed(0.0005, 0.05).check(prefix, "detail_texel_m", self.detail_texel_m)?;
        Interval::closed(1.0, 255.0).check(prefix, "albedo_dn", self.albedo_dn)?;
        Interval::closed(0.0, 1.0).check(prefix, "macro_contrast", self.macro_contrast)?;
        Interval::closed(0.0, 1.0).check(prefix, "detail_contrast", self.detail_contrast)?;
        Interval::closed(0.0, 5000.0).check(
            prefix,
            "pebble_density_per_m2",
            self.pebble_density_per_m2,
        )?;
        Interval::closed(0.0, 0.2).check(prefix, "bump_amplitude_m", self.bump_amplitude_m)?;
        Interval::closed(1.0, 255.0).check(prefix, "rock_albedo_dn", self.rock_albedo_dn)?;
        let side_m = terrain.size_x_m.max(terrain.size_y_m);
        let min_texel = side_m / MAX_TEXTURE_TEXELS as f64;
        if self.texel_m < min_texel {
            return Err(inconsistent(
                prefix,
                "texel_m",
                format!(
                    "must be >= {min_texel} for a {side_m} m terrain \
                     (at most {MAX_TEXTURE_TEXELS} texels per side), got {}",
                    self.texel_m
                ),
            ));
        }
        Ok(())
    }
}

/// Sun and ambient light, baked into the terrain texture and rock vertices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LightingConfig {
    /// Sun azimuth, radians, counter-clockwise from world +x.
    pub sun_azimuth_rad: f64,
    /// Sun elevation above the horizon, radians.
    pub sun_elevation_rad: f64,
    /// Ambient fraction of the light in `[0, 1]`.
    pub ambient: f64,
}

impl Default for LightingConfig {
    fn default() -> Self {
        Self {
            sun_azimuth_rad: 2.3,
            sun_elevation_rad: 0.6,
            ambient: 0.3,
        }
    }
}

impl LightingConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        let tau = std::f64::consts::TAU;
        Interval::closed(-tau, tau).check(prefix, "sun_azimuth_rad", self.sun_azimuth_rad)?;
        Interval::left_open(0.0, std::f64::consts::FRAC_PI_2).check(
            prefix,
            "sun_elevation_rad",
            self.sun_elevation_rad,
        )?;
        Interval::closed(0.0, 1.0).check(prefix, "ambient", self.ambient)?;
        Ok(())
    }

    /// Unit vector towards the sun in world coordinates (z up).
    pub fn sun_direction(&self) -> [f64; 3] {
        let (se, ce) = self.sun_elevation_rad.sin_cos();
        let (sa, ca) = self.sun_azimuth_rad.sin_cos();
        [ce * ca, ce * sa, se]
    }
}
