//! Stereo disparities on a rendered pair against the renderer's depth buffer: unbiased and
//! sub-pixel.
use hopnav_rover_vo::simulate::TraverseConfig;
use hopnav_rover_vo::stereo::{StereoMatcher, StereoParams};
use hopnav_vision::image::ImageView;
use hopnav_world::World;
use hopnav_world::raster::{RenderScene, Renderer};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

#[test]
fn stereo_disparity_matches_the_zbuffer() {
    let cfg = TraverseConfig::default();
    let world = World::generate(&cfg.world).unwrap();
    let mut r = Renderer::new(&cfg.camera, &cfg.render).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    r.prepare(&scene);
    let c = *r.camera();
    let (w, h) = (c.width_px as usize, c.height_px as usize);
    let body = Isometry3::from_parts(
        Translation3::new(-10.0, -16.0, world.ground_height_at(-10.0, -16.0) + 0.42),
        UnitQuaternion::identity(),
    );
    let bfc = cfg.mount.body_from_left_camera(cfg.baseline_m);
    let mut left = vec![0u8; w * h];
    let mut right = vec![0u8; w * h];
    r.render(&scene, &(body * bfc), 1, &mut left, w).unwrap();
    let zbuf: Vec<f32> = r.inverse_depth().to_vec();
    r.render(
        &scene,
        &hopnav_world::camera::stereo_right(&(body * bfc), cfg.baseline_m),
        2,
        &mut right,
        w,
    )
    .unwrap();
    let p = StereoParams {
        fx_px: c.fx_px,
        fy_px: c.fy_px,
        cx_px: c.cx_px,
        cy_px: c.cy_px,
        ..StereoParams::default()
    };
    let mut m = StereoMatcher::new(c.width_px, c.height_px, p).unwrap();
    let l = ImageView::packed(&left, w, h).unwrap();
    let rr = ImageView::packed(&right, w, h).unwrap();
    let mut errs = Vec::new();
    for y in (20..220).step_by(10) {
        for x in (20..300).step_by(10) {
            if let Ok(sp) = m.match_point(&l, &rr, x as f32, y as f32) {
                let iz = zbuf[y * w + x];
                if iz > 0.0 {
                    let z = 1.0 / iz as f64;
                    let d_true = c.fx_px * 0.2 / z;
                    errs.push((sp.disparity_px - d_true, z));
                }
            }
        }
    }
    let mean = errs.iter().map(|e| e.0).sum::<f64>() / errs.len() as f64;
    let rms = (errs.iter().map(|e| e.0 * e.0).sum::<f64>() / errs.len() as f64).sqrt();
    let rel = errs
        .iter()
        .map(|e| e.0 / (c.fx_px * 0.2 / e.1))
        .sum::<f64>()
        / errs.len() as f64;
    println!(
        "n {} mean disparity err {mean:.3} px rms {rms:.3} px mean relative {rel:.4}",
        errs.len()
    );
    let mut s = errs.clone();
    s.sort_by(|a, b| a.0.total_cmp(&b.0));
    println!(
        "p10 {:.3} p50 {:.3} p90 {:.3}",
        s[s.len() / 10].0,
        s[s.len() / 2].0,
        s[s.len() * 9 / 10].0
    );
    assert!(errs.len() > 200, "matches {}", errs.len());
    assert!(mean.abs() < 0.1 && rms < 0.6, "mean {mean} rms {rms}");
}
