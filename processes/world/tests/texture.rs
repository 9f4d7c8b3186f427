//! The surface texture has trackable corners from 0.5 m to 15 m, and the Fig. 6 rock wall
//! hides the goal from the rover's start.

mod common;

use hopnav_world::camera::{CameraConfig, PinholeCamera, look_at};
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{World, WorldConfig};
use nalgebra::{Point3, Vector3};

/// Fraction of 9×9 windows on a 10-px grid whose Shi–Tomasi score (smaller eigenvalue of the
/// mean structure tensor, DN²/px²) exceeds `threshold`.
fn corner_fraction(img: &[u8], w: usize, h: usize, threshold: f64) -> f64 {
    let at = |x: usize, y: usize| f64::from(img[y * w + x]);
    let (mut good, mut total) = (0, 0);
    for cy in (10..h - 10).step_by(10) {
        for cx in (10..w - 10).step_by(10) {
            let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
            for y in cy - 4..=cy + 4 {
                for x in cx - 4..=cx + 4 {
                    let gx = (at(x + 1, y) - at(x - 1, y)) / 2.0;
                    let gy = (at(x, y + 1) - at(x, y - 1)) / 2.0;
                    xx += gx * gx;
                    yy += gy * gy;
                    xy += gx * gy;
                }
            }
            let (a, b, c) = (xx / 81.0, yy / 81.0, xy / 81.0);
            let lmin = (a + b) / 2.0 - (((a - b) / 2.0).powi(2) + c * c).sqrt();
            total += 1;
            if lmin > threshold {
                good += 1;
            }
        }
    }
    good as f64 / total as f64
}

#[test]
fn ground_texture_has_corners_near_and_far() {
    let mut cfg = WorldConfig::default();
    cfg.terrain.size_x_m = 40.0;
    cfg.terrain.size_y_m = 40.0;
    cfg.rocks.golombek_k = 0.0; // the ground texture alone must carry the features
    cfg.craters.count = 0;
    let world = World::generate(&cfg).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let render = RenderConfig {
        noise_sigma_dn: 0.0,
        ..RenderConfig::default()
    };
    let mut r = Renderer::new(&CameraConfig::default(), &render).unwrap();
    let mut img = vec![0u8; 320 * 320];
    // Range along the optical axis: 0.5 m (close look-down) and 15 m (high, oblique).
    for (range_m, pitch) in [(0.5f64, 1.2f64), (15.0, 0.9)] {
        let target = Point3::new(2.0, 1.0, world.ground_height_at(2.0, 1.0));
        let dir = Vector3::new(pitch.cos(), 0.0, -f64::sin(pitch));
        let eye = target - dir * range_m;
        r.render(
            &scene,
            &look_at(&eye, &target, &Vector3::z()),
            0,
            &mut img,
            320,
        )
        .unwrap();
        let frac = corner_fraction(&img, 320, 320, 4.0);
        eprintln!("corner windows at {range_m} m: {:.0} %", frac * 100.0);
        assert!(
            frac > 0.6,
            "only {:.0} % of windows have corners at {range_m} m",
            frac * 100.0
        );
    }
}

#[test]
fn fig6_rock_wall_hides_the_goal_from_the_start() {
    let mut cfg = common::scenario_world("fig6");
    cfg.texture.texel_m = 0.1; // geometry matters here, not texture detail
    cfg.texture.pebble_density_per_m2 = 0.0;
    let world = World::generate(&cfg).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let cam_cfg = CameraConfig {
        width_px: 256,
        height_px: 192,
        hfov_rad: 1.2,
        ..CameraConfig::default()
    };
    let cam = PinholeCamera::from_config(&cam_cfg, "camera").unwrap();
    let mut r = Renderer::new(&cam_cfg, &common::clean_render()).unwrap();
    let [ax, ay] = cfg.scenario.start_m.unwrap();
    let [bx, by] = cfg.scenario.goal_m.unwrap();
    let eye = Point3::new(ax, ay, world.ground_height_at(ax, ay) + 0.6); // rover mast height
    let goal = Point3::new(bx, by, world.ground_height_at(bx, by) + 0.2);
    let pose = look_at(&eye, &goal, &Vector3::z());
    let mut img = vec![0u8; 256 * 192];
    r.render(&scene, &pose, 0, &mut img, 256).unwrap();
    let px = cam.project_world(&pose, &goal).unwrap();
    let iz = r.inverse_depth()[px[1].round() as usize * 256 + px[0].round() as usize];
    let dist = (goal - eye).norm();
    let hit = f64::from(1.0 / iz);
    assert!(
        iz > 0.0 && hit < dist * 0.75,
        "the goal must be hidden: hit at {hit} m, goal {dist} m"
    );
}
