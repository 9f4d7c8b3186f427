//! Frame conventions of the jumper: body frame, camera mount and Euler angles.
//!
//! - World: z up (world crate). Body: x forward (launch heading), y left, z up at launch.
//! - The camera sits at the rear, looking along body −x, pitched down by `pitch_down_rad`.
//!   Camera frame is OpenCV's (x right, y down, z forward). Looking backwards, image right is
//!   body +y.
//! - Attitude angles: `world_from_body = Rz(yaw) · Ry(−pitch) · Rx(roll)`, so a positive
//!   `pitch` is nose-up (body x rotating towards world +z).
//!
//! ```
//! use hopnav_jumper_vo::frames::{body_from_camera, euler_from_rotation};
//! use nalgebra::Vector3;
//! let mount = body_from_camera(0.5236, &Vector3::new(-0.1, 0.0, 0.0));
//! // The optical axis points backwards and down.
//! let axis = mount.rotation * Vector3::z();
//! assert!(axis.x < -0.8 && axis.z < -0.4);
//! let (roll, pitch, yaw) = euler_from_rotation(&nalgebra::UnitQuaternion::identity());
//! assert_eq!((roll, pitch, yaw), (0.0, 0.0, 0.0));
//! ```

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// `body_from_camera` of the rear camera: looks along body −x, pitched down by
/// `pitch_down_rad`, its centre at `offset_body_m` (body frame).
pub fn body_from_camera(pitch_down_rad: f64, offset_body_m: &Vector3<f64>) -> Isometry3<f64> {
    let (s, c) = pitch_down_rad.sin_cos();
    let x = Vector3::new(0.0, 1.0, 0.0);
    let y = Vector3::new(s, 0.0, -c);
    let z = Vector3::new(-c, 0.0, -s);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    Isometry3::from_parts(
        Translation3::from(*offset_body_m),
        UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// `world_from_body` rotation from roll, pitch (nose-up positive) and yaw, radians.
pub fn rotation_from_euler(roll_rad: f64, pitch_rad: f64, yaw_rad: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_rad)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -pitch_rad)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), roll_rad)
}

/// Inverse of [`rotation_from_euler`]: `(roll, pitch, yaw)` in radians (pitch nose-up positive).
pub fn euler_from_rotation(world_from_body: &UnitQuaternion<f64>) -> (f64, f64, f64) {
    // nalgebra's euler_angles are (roll, pitch', yaw) of Rz·Ry(pitch')·Rx with pitch' = −pitch.
    let (roll, pitch_ry, yaw) = world_from_body.euler_angles();
    (roll, -pitch_ry, yaw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_axes_are_right_handed_and_backwards() {
        let m = body_from_camera(0.0, &Vector3::zeros());
        let r = m.rotation;
        assert!((r * Vector3::z() - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
        assert!((r * Vector3::y() - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        assert!((r * Vector3::x() - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn euler_round_trip() {
        let q = rotation_from_euler(0.1, 0.7, -0.4);
        let (r, p, y) = euler_from_rotation(&q);
        assert!((r - 0.1).abs() < 1e-12 && (p - 0.7).abs() < 1e-12 && (y + 0.4).abs() < 1e-12);
        // Nose-up pitch lifts the body x axis.
        assert!((rotation_from_euler(0.0, 0.3, 0.0) * Vector3::x()).z > 0.0);
    }
}
