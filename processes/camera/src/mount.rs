//! Where a camera sits on its robot: `body_from_camera` from a position, a yaw and a downward
//! pitch in the body frame (x forward, y left, z up).

use nalgebra::{Isometry3, Point3, Vector3};

use crate::MountConfig;

/// `body_from_camera` of a camera at `mount.position_m` looking along the body heading
/// `yaw_rad` (0 = forward, π = backward) tilted `pitch_down_rad` below the body's x-y plane.
/// Camera frame: OpenCV (x right, y down, z forward).
pub fn body_from_camera(mount: &MountConfig) -> Isometry3<f64> {
    let eye = Point3::from(Vector3::from(mount.position_m));
    let (sin_pitch, cos_pitch) = mount.pitch_down_rad.sin_cos();
    let (sin_yaw, cos_yaw) = mount.yaw_rad.sin_cos();
    let view = Vector3::new(cos_pitch * cos_yaw, cos_pitch * sin_yaw, -sin_pitch);
    hopnav_world::camera::look_at(&eye, &(eye + view), &Vector3::z())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mount(yaw_rad: f64, pitch_down_rad: f64) -> MountConfig {
        MountConfig {
            position_m: [-0.1, 0.0, 0.05],
            yaw_rad,
            pitch_down_rad,
        }
    }

    #[test]
    fn rear_camera_looks_backward_and_down_with_right_to_body_left() {
        let pose = body_from_camera(&mount(std::f64::consts::PI, 30_f64.to_radians()));
        let optical_axis = pose.rotation * Vector3::z();
        assert!((optical_axis - Vector3::new(-30_f64.to_radians().cos(), 0.0, -0.5)).norm() < 1e-9);
        let image_right = pose.rotation * Vector3::x();
        assert!((image_right - Vector3::y()).norm() < 1e-9, "{image_right}");
        assert!((pose.translation.vector - Vector3::new(-0.1, 0.0, 0.05)).norm() < 1e-12);
    }

    #[test]
    fn forward_camera_image_down_points_down() {
        let pose = body_from_camera(&mount(0.0, 0.0));
        assert!((pose.rotation * Vector3::z() - Vector3::x()).norm() < 1e-9);
        assert!((pose.rotation * Vector3::y() + Vector3::z()).norm() < 1e-9);
    }
}
