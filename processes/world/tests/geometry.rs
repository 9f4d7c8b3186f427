//! Rendering is geometrically right: marks appear where the pinhole model puts them, and the
//! stereo disparity of a mark equals baseline · f / depth.

mod common;

use hopnav_world::World;
use hopnav_world::camera::{CameraConfig, PinholeCamera, look_at, stereo_right};
use hopnav_world::config::MarkerConfig;
use hopnav_world::raster::{RenderScene, Renderer};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};

/// A grid of small white squares slightly above the flat ground (offsets break symmetry).
fn marks_grid(xs: &[f64], ys: &[f64], half_size_m: f64) -> Vec<MarkerConfig> {
    let mut v = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        for (j, y) in ys.iter().enumerate() {
            v.push(MarkerConfig {
                center_m: [*x + 0.13 * j as f64, *y + 0.07 * i as f64, 0.01],
                half_size_m,
                value_dn: 255,
            });
        }
    }
    v
}

fn marks() -> Vec<MarkerConfig> {
    marks_grid(&[-2.0, -1.0, 0.0, 1.0, 2.0], &[-1.5, 0.0, 1.5, 3.0], 0.04)
}

fn check_marks(
    cam: &PinholeCamera,
    pose: &Isometry3<f64>,
    img: &[u8],
    marks: &[MarkerConfig],
) -> usize {
    let (w, h) = (cam.width_px as usize, cam.height_px as usize);
    let mut seen = 0;
    for m in marks {
        let p = Point3::from(m.center_m);
        let Some(px) = cam.project_world(pose, &p) else {
            continue;
        };
        if px[0] < 8.0 || px[1] < 8.0 || px[0] > w as f64 - 9.0 || px[1] > h as f64 - 9.0 {
            continue;
        }
        let c = common::centroid(img, w, h, 255, px, 12.0).expect("mark not rendered");
        let err = ((c[0] - px[0]).powi(2) + (c[1] - px[1]).powi(2)).sqrt();
        assert!(
            err < 1.0,
            "mark {:?}: rendered at {c:?}, predicted {px:?} ({err:.3} px)",
            m.center_m
        );
        seen += 1;
    }
    seen
}

#[test]
fn marks_appear_where_the_pinhole_model_predicts() {
    let marks = marks();
    let world = World::generate(&common::flat_world(marks.clone())).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    for (cam_cfg, eye, target, roll) in [
        (
            CameraConfig::default(),
            [0.0, -4.0, 3.0],
            [0.0, 0.5, 0.0],
            0.0,
        ),
        (
            CameraConfig::default(),
            [3.0, -3.0, 2.0],
            [0.0, 0.5, 0.0],
            0.3,
        ),
        (
            CameraConfig {
                width_px: 400,
                height_px: 300,
                hfov_rad: 1.0,
                vfov_rad: Some(0.8),
                near_m: 0.05,
            },
            [-2.5, -2.0, 4.0],
            [0.5, 1.0, 0.0],
            -0.2,
        ),
    ] {
        let cam = PinholeCamera::from_config(&cam_cfg, "camera").unwrap();
        let mut r = Renderer::new(&cam_cfg, &common::clean_render()).unwrap();
        let base = look_at(&Point3::from(eye), &Point3::from(target), &Vector3::z());
        let pose = base * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), roll);
        let (w, h) = (cam.width_px as usize, cam.height_px as usize);
        let stride = w + 7; // a padded stride must work too
        let mut img = vec![0u8; stride * h];
        r.render(&scene, &pose, 0, &mut img, stride).unwrap();
        let packed: Vec<u8> = img
            .chunks(stride)
            .flat_map(|row| row[..w].to_vec())
            .collect();
        let seen = check_marks(&cam, &pose, &packed, &marks);
        assert!(seen >= 8, "only {seen} marks in view");
        // Uniform ground renders at its albedo (no noise, flat shading normalised to 1).
        assert!(packed.iter().filter(|&&v| v == 100).count() > w * h / 3);
    }
}

/// Width and height of the box around a mark's projected corners, pixels.
fn projected_extent(cam: &PinholeCamera, pose: &Isometry3<f64>, m: &MarkerConfig) -> [f64; 2] {
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let c = m.center_m;
        let p = Point3::new(c[0] + sx * m.half_size_m, c[1] + sy * m.half_size_m, c[2]);
        if let Some(q) = cam.project_world(pose, &p) {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
    }
    [hi[0] - lo[0], hi[1] - lo[1]]
}

/// Renders a stereo pair with `scale`× the base resolution (same field of view) and checks the
/// disparity of every visible mark, in base-resolution pixels, against b·f/Z within `tol_px`.
fn check_disparity(scale: u32, tol_px: f64) {
    let marks = marks_grid(&[-2.4, -1.2, 0.0, 1.2, 2.4], &[-1.0, 1.0, 3.0], 0.1);
    let world = World::generate(&common::flat_world(marks.clone())).unwrap();
    let scene = RenderScene::new(&world).unwrap();
    let (w, h) = (256 * scale as usize, 192 * scale as usize);
    let cam_cfg = CameraConfig {
        width_px: w as u32,
        height_px: h as u32,
        hfov_rad: 1.2,
        vfov_rad: None,
        near_m: 0.05,
    };
    let cam = PinholeCamera::from_config(&cam_cfg, "camera").unwrap();
    let mut r = Renderer::new(&cam_cfg, &common::clean_render()).unwrap();
    let baseline_m = 0.3;
    let left = look_at(
        &Point3::new(-0.2, -3.5, 3.5),
        &Point3::new(0.0, 1.0, 0.0),
        &Vector3::z(),
    );
    let mut li = vec![0u8; w * h];
    let mut ri = vec![0u8; w * h];
    r.render_stereo(&scene, &left, baseline_m, 5, &mut li, &mut ri, w)
        .unwrap();
    let right = stereo_right(&left, baseline_m);
    let s = f64::from(scale);
    let mut checked = 0;
    for m in &marks {
        let p = Point3::from(m.center_m);
        let (Some(pl), Some(pr)) = (cam.project_world(&left, &p), cam.project_world(&right, &p))
        else {
            continue;
        };
        // Marks thinner than 2 native pixels may cover no pixel centre at all.
        let ext = projected_extent(&cam, &left, m);
        if ext[0].min(ext[1]) < 2.0 * s {
            continue;
        }
        let margin = 10.0 * s;
        if [pl, pr].iter().any(|q| {
            q[0] < margin || q[1] < margin || q[0] > w as f64 - margin || q[1] > h as f64 - margin
        }) {
            continue;
        }
        let cl = common::centroid(&li, w, h, 255, pl, 8.0 * s).expect("left mark");
        let cr = common::centroid(&ri, w, h, 255, pr, 8.0 * s).expect("right mark");
        let depth = left.inverse_transform_point(&p).z;
        let expected = baseline_m * cam.fx_px / depth / s;
        let disparity = (cl[0] - cr[0]) / s;
        assert!(
            (disparity - expected).abs() < tol_px,
            "{scale}x: disparity {disparity:.3} px vs b·f/Z = {expected:.3} px at depth {depth:.2} m"
        );
        assert!(
            (cl[1] - cr[1]).abs() / s < tol_px,
            "rectified pair: rows must match"
        );
        checked += 1;
    }
    assert!(checked >= 8, "only {checked} marks checked");
}

/// At native resolution the binary coverage of a mark quantises each centroid by up to half a
/// pixel, so the disparity is right to within 1 px.
#[test]
fn stereo_disparity_is_baseline_times_focal_over_depth() {
    check_disparity(1, 1.0);
}

/// Rendering the same pair at 4× resolution shrinks the quantisation: the disparity matches
/// b·f/Z to a quarter pixel (in native pixels), so the geometry itself is exact.
#[test]
fn stereo_disparity_is_exact_when_supersampled() {
    check_disparity(4, 0.25);
}
