//! Terrain LOD leaves no cracks: looking down at rough terrain, every pixel is covered.

mod common;

use hopnav_world::World;
use hopnav_world::camera::{CameraConfig, look_at};
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use nalgebra::{Point3, Vector3};

#[test]
fn no_cracks_between_chunks_of_different_lod() {
    let mut cfg = common::small_world(11);
    cfg.terrain.size_x_m = 48.0;
    cfg.terrain.size_y_m = 48.0;
    cfg.terrain.relief_amplitude_m = 1.5; // rough: many LOD transitions
    cfg.texture.texel_m = 0.12;
    cfg.texture.pebble_density_per_m2 = 0.0;
    cfg.rocks.golombek_k = 0.0;
    let world = World::generate(&cfg).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    // A coarse error budget forces many chunks to coarse steps next to fine ones.
    let mut triangles = Vec::new();
    for lod_error_px in [0.0, 0.5, 4.0] {
        let render = RenderConfig {
            lod_error_px,
            ..RenderConfig::default()
        };
        let mut r = Renderer::new(&CameraConfig::default(), &render).unwrap();
        let mut img = vec![0u8; 320 * 320];
        for (alt, pitch, yaw) in [
            (3.0f64, 1.2f64, 0.3f64),
            (8.0, 1.0, 2.0),
            (15.0, 1.3, 4.0),
            (20.0, 1.35, 5.5),
        ] {
            let ground = world.ground_height_at(0.0, 0.0);
            let eye = Point3::new(0.0, 0.0, ground + alt);
            let dir = Vector3::new(
                pitch.cos() * yaw.cos(),
                pitch.cos() * yaw.sin(),
                -pitch.sin(),
            );
            let stats = r
                .render(
                    &scene,
                    &look_at(&eye, &(eye + dir), &Vector3::z()),
                    0,
                    &mut img,
                    320,
                )
                .unwrap();
            triangles.push(stats.triangles);
            let holes = r.inverse_depth().iter().filter(|&&z| z <= 0.0).count();
            assert_eq!(
                holes, 0,
                "{holes} uncovered pixels at {alt} m (lod_error_px {lod_error_px})"
            );
        }
    }
    // LOD really was at work: fewer triangles with a larger error budget, at every pose.
    let (full, fine, coarse) = (&triangles[0..4], &triangles[4..8], &triangles[8..12]);
    for k in 0..4 {
        assert!(coarse[k] < fine[k] && fine[k] <= full[k], "{triangles:?}");
    }
}
