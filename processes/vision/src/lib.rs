//! Hand-written feature tracking and two-view geometry for the hopnav visual-odometry processes.
//!
//! Shared by `jumper_vo` (monocular) and `rover_vo` (stereo). No CV crate: everything here is
//! written against `nalgebra` so that it can be audited, made deterministic and kept
//! allocation-free on the per-frame path.
//!
//! Per-frame pipeline of a monocular VO process:
//!
//! 1. [`pyramid::Pyramid::build`] the new frame (buffers allocated once in `new`);
//! 2. [`klt::KltTracker::track`] the previous features into it (pyramidal Lucas–Kanade with a
//!    forward–backward check);
//! 3. [`corners::CornerDetector::detect`] new Shi–Tomasi corners in empty grid cells;
//! 4. convert pixels to normalized coordinates with [`camera::PinholeCamera`];
//! 5. [`two_view::TwoViewEstimator::estimate`] the relative motion: 5-point (or 8-point) essential
//!    RANSAC and homography RANSAC, model selection, decomposition with the gravity normal and
//!    cheirality;
//! 6. [`triangulate`] the inliers.
//!
//! Conventions: image `x` right, `y` down, camera `z` forward. Transforms are named
//! `cam2_from_cam1`, so `p_cam2 = cam2_from_cam1 * p_cam1`. The essential matrix satisfies
//! `x2ᵀ E x1 = 0` with `E = [t]ₓ R`. Angles are radians.
//!
//! ```
//! use hopnav_vision::{camera::PinholeCamera, synthetic, two_view::{TwoViewConfig, TwoViewEstimator}};
//! use nalgebra::{Isometry3, Vector3};
//! let cam = PinholeCamera::from_fov(320, 320, 0.785, 0.785).unwrap();
//! let motion = Isometry3::new(Vector3::new(0.3, 0.0, 0.05), Vector3::new(0.0, 0.05, 0.0));
//! let points = synthetic::random_points_in_box(200, 4.0, 4.0, 12.0, 1);
//! let scene = synthetic::TwoViewScene::from_points(&cam, motion, &points, 0.3, 0.0, 2);
//! let mut est = TwoViewEstimator::new(TwoViewConfig::for_camera(&cam), 1000);
//! let result = est.estimate(&scene.x1_norm, &scene.x2_norm, None).unwrap();
//! assert!(result.rotation_error_rad(&motion) < 0.01);
//! ```

#![warn(missing_docs)]

pub mod bench;
pub mod camera;
pub mod corners;
pub mod essential;
pub mod homography;
pub mod image;
pub mod klt;
pub mod model_select;
pub mod pyramid;
pub mod ransac;
pub mod rng;
pub mod simd;
pub mod synthetic;
pub mod triangulate;
pub mod two_view;
