//! What every object drawn in one frame shares: the camera and the scratch vertex buffers.

use super::tri::{ClipVertex, Projector, ScreenVertex};
use super::view::View;

/// The frame's camera and the scratch buffers an object's vertices pass through.
pub(crate) struct DrawPass<'a> {
    /// World → camera transform and frustum tests.
    pub view: &'a View,
    /// Camera → pixel projection and near plane.
    pub proj: &'a Projector,
    /// Scratch: the object's vertices in camera space.
    pub clip: &'a mut [ClipVertex],
    /// Scratch: their projections (valid where in front of the near plane).
    pub screen: &'a mut [ScreenVertex],
}
