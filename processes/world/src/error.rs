//! Error types: one small enum per fallible operation, every variant documented.

use thiserror::Error;

/// A configuration value was rejected by `validate()`.
///
/// The message always names the full key, e.g.
/// `terrain.spacing_m must be in (0, 1], got 2`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// A value lies outside its allowed range.
    #[error("{key} must be in {range}, got {value}")]
    OutOfRange {
        /// Full dotted key, e.g. `rocks.golombek_k`.
        key: String,
        /// Allowed range in interval notation, e.g. `(0, 1]`.
        range: String,
        /// The rejected value as written.
        value: String,
    },
    /// A value contradicts another value (e.g. a minimum above its maximum).
    #[error("{key} {reason}")]
    Inconsistent {
        /// Full dotted key of the offending value.
        key: String,
        /// What is wrong, phrased to follow the key.
        reason: String,
    },
}

impl From<hopnav_config::range::OutOfRange> for ConfigError {
    fn from(rejected: hopnav_config::range::OutOfRange) -> Self {
        Self::OutOfRange {
            key: rejected.key,
            range: rejected.range,
            value: rejected.value,
        }
    }
}

/// Building a [`World`](crate::World) or a [`RenderScene`](crate::raster::RenderScene) failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WorldError {
    /// The configuration did not validate.
    #[error("invalid world config: {0}")]
    InvalidConfig(#[from] ConfigError),
}

/// Rendering one image failed; the output buffer is left in an unspecified but valid state.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RenderError {
    /// The row stride is smaller than the image width.
    #[error("stride {stride_bytes} bytes is smaller than the image width {width_px} px")]
    StrideTooSmall {
        /// Stride passed by the caller.
        stride_bytes: usize,
        /// Image width of the renderer.
        width_px: usize,
    },
    /// The output slice cannot hold the image at the given stride.
    #[error("output buffer holds {got_bytes} bytes, the image needs {needed_bytes}")]
    BufferTooSmall {
        /// Bytes needed: `stride · (height − 1) + width`.
        needed_bytes: usize,
        /// Bytes passed.
        got_bytes: usize,
    },
    /// The camera pose contains NaN or infinite numbers.
    #[error("camera pose is not finite")]
    NonFinitePose,
    /// The camera configuration did not validate.
    #[error("invalid camera config: {0}")]
    InvalidCamera(#[from] ConfigError),
}

/// An offline simulation that renders a generated world (the VO crates' scripted hop and
/// traverse) failed: the world, the renderer, or one of the simulation's own parameters.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The world config is invalid or the world could not be generated.
    #[error("world: {0}")]
    World(#[from] WorldError),
    /// The camera or render config is invalid.
    #[error("render config: {0}")]
    Config(#[from] ConfigError),
    /// A frame could not be rendered.
    #[error("render: {0}")]
    Render(#[from] RenderError),
    /// A simulation parameter is out of range.
    #[error("simulation parameter {key}: {message}")]
    BadParameter {
        /// Offending key.
        key: &'static str,
        /// Why.
        message: String,
    },
}
