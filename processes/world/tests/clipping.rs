//! Near-plane clipping and robustness: cameras at, in or under the ground render without panics
//! or holes; bad buffers and poses are rejected with errors.

mod common;

use hopnav_world::camera::{CameraConfig, look_at};
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{RenderError, World};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

#[test]
fn ground_under_a_low_camera_is_clipped_not_dropped() {
    let world = World::generate(&common::flat_world(vec![])).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let mut r = Renderer::new(&CameraConfig::default(), &common::clean_render()).unwrap();
    // 8 cm above flat ground looking horizontally: the cells under the camera cross the near
    // plane (5 cm); dropping them would leave sky-coloured holes at the bottom of the image.
    let eye = Point3::new(0.1, 0.1, 0.08);
    let pose = look_at(&eye, &(eye + Vector3::new(1.0, 0.2, 0.0)), &Vector3::z());
    let mut img = vec![0u8; 320 * 320];
    r.render(&scene, &pose, 0, &mut img, 320).unwrap();
    for y in 0..320 {
        let row = &img[y * 320..(y + 1) * 320];
        if y >= 172 {
            assert!(row.iter().all(|&v| v == 100), "row {y} has holes");
        }
        if y <= 155 {
            assert!(row.iter().all(|&v| v == 20), "row {y} should be sky");
        }
    }
}

#[test]
fn cameras_inside_or_under_the_terrain_do_not_panic() {
    let world = World::generate(&common::small_world(3)).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let mut r = Renderer::new(&CameraConfig::default(), &RenderConfig::default()).unwrap();
    let mut img = vec![0u8; 320 * 320];
    let rock = world
        .rocks()
        .iter()
        .max_by(|a, b| a.diameter_m.total_cmp(&b.diameter_m))
        .unwrap();
    let c = rock.center_m;
    let ground = world.ground_height_at(1.0, 1.0);
    let poses = [
        // Inside the biggest rock.
        look_at(
            &Point3::new(c[0], c[1], c[2] + 0.3 * rock.height_m),
            &Point3::new(c[0] + 1.0, c[1], c[2]),
            &Vector3::z(),
        ),
        // Just under the surface, looking up and sideways.
        look_at(
            &Point3::new(1.0, 1.0, ground - 0.02),
            &Point3::new(3.0, 1.0, ground + 1.0),
            &Vector3::z(),
        ),
        // Exactly on the surface, looking straight down (view parallel to "up").
        look_at(
            &Point3::new(1.0, 1.0, ground),
            &Point3::new(1.0, 1.0, ground - 1.0),
            &Vector3::z(),
        ),
        // Far outside the map, looking at it.
        look_at(
            &Point3::new(200.0, 0.0, 5.0),
            &Point3::new(0.0, 0.0, 0.0),
            &Vector3::z(),
        ),
    ];
    for pose in poses {
        r.render(&scene, &pose, 1, &mut img, 320).unwrap();
    }
    // Grazing at 1 cm with a rock right in front.
    let eye = Point3::new(
        c[0] - rock.diameter_m,
        c[1],
        world.ground_height_at(c[0] - rock.diameter_m, c[1]) + 0.01,
    );
    r.render(
        &scene,
        &look_at(&eye, &Point3::new(c[0], c[1], eye.z), &Vector3::z()),
        2,
        &mut img,
        320,
    )
    .unwrap();
    let covered = r.inverse_depth().iter().filter(|&&z| z > 0.0).count();
    assert!(
        covered > 320 * 100,
        "the rock and ground should fill much of the view: {covered}"
    );
}

#[test]
fn bad_buffers_and_poses_are_errors() {
    let world = World::generate(&common::flat_world(vec![])).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let mut r = Renderer::new(&CameraConfig::default(), &RenderConfig::default()).unwrap();
    let pose = look_at(
        &Point3::new(0.0, 0.0, 2.0),
        &Point3::new(1.0, 0.0, 0.0),
        &Vector3::z(),
    );
    let mut small = vec![0u8; 320 * 319];
    assert_eq!(
        r.render(&scene, &pose, 0, &mut small, 320),
        Err(RenderError::BufferTooSmall {
            needed_bytes: 320 * 320,
            got_bytes: 320 * 319
        })
    );
    let mut img = vec![0u8; 320 * 320];
    assert!(matches!(
        r.render(&scene, &pose, 0, &mut img, 100),
        Err(RenderError::StrideTooSmall { .. })
    ));
    let nan = Isometry3::from_parts(
        Translation3::new(f64::NAN, 0.0, 1.0),
        UnitQuaternion::new_unchecked(Quaternion::identity()),
    );
    assert_eq!(
        r.render(&scene, &nan, 0, &mut img, 320),
        Err(RenderError::NonFinitePose)
    );
}

#[test]
fn stacked_stereo_matches_separate_views() {
    let world = World::generate(&common::small_world(5)).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let cam = CameraConfig {
        width_px: 64,
        height_px: 48,
        ..CameraConfig::default()
    };
    let mut r = Renderer::new(&cam, &RenderConfig::default()).unwrap();
    let pose = look_at(
        &Point3::new(0.0, -3.0, 1.5),
        &Point3::new(0.0, 1.0, 0.0),
        &Vector3::z(),
    );
    let stride = 70;
    let mut stacked = vec![0u8; 2 * stride * 48];
    r.render_stereo_stacked(&scene, &pose, 0.2, 9, &mut stacked, stride)
        .unwrap();
    let mut left = vec![0u8; stride * 48];
    let mut right = vec![0u8; stride * 48];
    r.render_stereo(&scene, &pose, 0.2, 9, &mut left, &mut right, stride)
        .unwrap();
    for y in 0..48 {
        assert_eq!(
            stacked[y * stride..y * stride + 64],
            left[y * stride..y * stride + 64]
        );
        let o = stride * 48;
        assert_eq!(
            stacked[o + y * stride..o + y * stride + 64],
            right[y * stride..y * stride + 64]
        );
    }
    assert_ne!(left, right);
    let mut short = vec![0u8; 2 * stride * 48 - 7];
    assert!(matches!(
        r.render_stereo_stacked(&scene, &pose, 0.2, 9, &mut short, stride),
        Err(RenderError::BufferTooSmall { .. })
    ));
}
