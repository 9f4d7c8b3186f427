//! Where the rover VO's tall cloud points come from: each keyframe's new points against the
//! renderer's depth at their pixel (a diagnostic for the traversability study).
//!
//! ```sh
//! cargo run --release -p hopnav-eval --example rover_cloud_vs_zbuffer -- [K] [SEED] [EDGE_PX]
//! ```
//!
//! Runs the rover VO over the rendered traverse of `hopnav eval rover-vo` (Golombek `K`,
//! default the world's; `EDGE_PX`: `rover_vo.stereo_max_half_disagreement_px`), re-renders the left view at each keyframe's true pose, and for every
//! point first published at that keyframe looks up the true depth at its pixel. A point the VO
//! calls tall (> 0.1 m above its local ground) whose pixel truly shows bare ground is "false
//! tall"; it prints how those split by depth error (foreground disparity taken at a silhouette,
//! background, or right depth and a wrong ground), and by how far the true depth jumps within
//! the stereo patch around the pixel (a silhouette).

use std::collections::HashSet;
use std::error::Error;

use hopnav_rover_vo::config::RoverVoConfig;
use hopnav_rover_vo::run::run_traverse;
use hopnav_rover_vo::simulate::{TraverseConfig, simulate_traverse};
use hopnav_world::raster::{RenderScene, Renderer};
use nalgebra::Point3;

/// A point is tall above its local ground from this height, metres (the mapper's rule).
const TALL_M: f64 = 0.1;
/// Truly on a rock when the surface at its pixel stands this high above the terrain, metres.
const ON_ROCK_M: f64 = 0.05;
/// Half the stereo patch, pixels.
const PATCH_RADIUS_PX: i64 = 3;

#[derive(Default)]
struct Counts {
    points: usize,
    tall: usize,
    tall_on_rock: usize,
    false_tall: usize,
    /// Of the false tall: estimated depth short of the truth by > 20 % (took a nearer surface).
    false_tall_short: usize,
    /// … beyond the truth by > 20 %.
    false_tall_long: usize,
    /// … depth right within 20 %.
    false_tall_depth_right: usize,
    /// … true depth jumps by > 20 % within the patch (a silhouette).
    false_tall_at_silhouette: usize,
    /// Of all points, those at a silhouette.
    at_silhouette: usize,
    /// Heights above the true ground of false tall points with the depth right, metres.
    depth_right_height_errors_m: Vec<f64>,
    /// Lateral offset of false-tall points from the true surface point at their pixel, m.
    false_tall_offsets_m: Vec<f64>,
    /// Signed depth error (estimate − truth) of false-tall points, in % of the true depth.
    false_tall_depth_errors_percent: Vec<f64>,
    /// … of the ground points the VO calls low, the same.
    ground_depth_errors_percent: Vec<f64>,
    /// Nearest minus farthest true depth within the patch, in % of the true depth: false tall.
    false_tall_patch_jump_percent: Vec<f64>,
    /// … ground points the VO calls low.
    ground_patch_jump_percent: Vec<f64>,
    /// Gap from the true surface point of false-tall points to the nearest rock's bounding
    /// circle, metres.
    false_tall_rock_gaps_m: Vec<f64>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut traverse = TraverseConfig::default();
    if let Some(k) = args.first() {
        traverse.world.rocks.golombek_k = k.parse()?;
    }
    if let Some(seed) = args.get(1) {
        traverse.world.seed = seed.parse()?;
        traverse.seed = traverse.world.seed;
    }
    let mut vo = RoverVoConfig::default();
    if let Some(edge_px) = args.get(2) {
        vo.stereo_max_half_disagreement_px = edge_px.parse()?;
    }
    eprintln!("rendering and tracking the traverse...");
    let sim = simulate_traverse(&traverse)?;
    let run = run_traverse(&sim, &vo)?;
    let scene = RenderScene::new(&sim.world)?;
    let mut renderer = Renderer::new(&traverse.camera, &traverse.render)?;
    let camera = *renderer.camera();
    let (width, height) = (camera.width_px as usize, camera.height_px as usize);
    let mut image = vec![0_u8; width * height];
    let mut seen_ids: HashSet<u32> = HashSet::new();
    let mut counts = Counts::default();
    let mut rendered_frame = None;
    for (frame, point) in &run.clouds {
        if !seen_ids.insert(point.track_id) || !point.height_above_ground_m.is_finite() {
            continue;
        }
        let (Some(output), Some(truth)) = (
            run.outputs.get(*frame),
            sim.truth_world_from_body.get(*frame),
        ) else {
            continue;
        };
        let true_world_from_camera = truth * sim.rig.body_from_camera;
        if rendered_frame != Some(*frame) {
            renderer.render(&scene, &true_world_from_camera, 0, &mut image, width)?;
            rendered_frame = Some(*frame);
        }
        let estimated_world_from_camera = output.world_from_body * sim.rig.body_from_camera;
        let in_camera = estimated_world_from_camera.inverse() * point.position_m;
        if in_camera.z <= 0.0 {
            continue;
        }
        let u = (camera.fx_px * in_camera.x / in_camera.z + camera.cx_px).round() as i64;
        let v = (camera.fy_px * in_camera.y / in_camera.z + camera.cy_px).round() as i64;
        let depth_at = |u: i64, v: i64| -> Option<f64> {
            if u < 0 || v < 0 || u >= width as i64 || v >= height as i64 {
                return None;
            }
            let inverse = renderer.inverse_depth()[v as usize * width + u as usize];
            (inverse > 0.0).then(|| 1.0 / f64::from(inverse))
        };
        let Some(true_depth_m) = depth_at(u, v) else {
            continue;
        };
        if true_depth_m > 10.0 {
            continue;
        }
        let mut nearest_m = true_depth_m;
        let mut farthest_m = true_depth_m;
        for dv in -PATCH_RADIUS_PX..=PATCH_RADIUS_PX {
            for du in -PATCH_RADIUS_PX..=PATCH_RADIUS_PX {
                let depth_m = depth_at(u + du, v + dv).unwrap_or(f64::INFINITY);
                nearest_m = nearest_m.min(depth_m);
                farthest_m = farthest_m.max(depth_m);
            }
        }
        let at_silhouette = farthest_m > 1.2 * nearest_m;
        let scale = true_depth_m / in_camera.z;
        let true_surface = true_world_from_camera
            * Point3::new(in_camera.x * scale, in_camera.y * scale, true_depth_m);
        let true_height_m =
            true_surface.z - sim.world.ground_height_at(true_surface.x, true_surface.y);
        counts.points += 1;
        counts.at_silhouette += usize::from(at_silhouette);
        let depth_error_percent = 100.0 * (in_camera.z / true_depth_m - 1.0);
        let patch_jump_percent = 100.0 * (farthest_m.min(1e3) - nearest_m) / true_depth_m;
        if point.height_above_ground_m <= TALL_M {
            if true_height_m <= ON_ROCK_M {
                counts.ground_depth_errors_percent.push(depth_error_percent);
                counts.ground_patch_jump_percent.push(patch_jump_percent);
            }
            continue;
        }
        counts.tall += 1;
        if true_height_m > ON_ROCK_M {
            counts.tall_on_rock += 1;
            continue;
        }
        counts.false_tall += 1;
        counts
            .false_tall_depth_errors_percent
            .push(depth_error_percent);
        counts
            .false_tall_patch_jump_percent
            .push(patch_jump_percent);
        counts.false_tall_rock_gaps_m.push(
            sim.world
                .rocks()
                .iter()
                .map(|rock| {
                    (true_surface.x - rock.center_m[0]).hypot(true_surface.y - rock.center_m[1])
                        - rock.bounding_radius_m()
                })
                .fold(f64::INFINITY, f64::min),
        );
        counts.false_tall_at_silhouette += usize::from(at_silhouette);
        let depth_ratio = in_camera.z / true_depth_m;
        if depth_ratio < 0.8 {
            counts.false_tall_short += 1;
        } else if depth_ratio > 1.2 {
            counts.false_tall_long += 1;
        } else {
            counts.false_tall_depth_right += 1;
            let estimated_true_frame = truth * output.world_from_body.inverse() * point.position_m;
            counts.depth_right_height_errors_m.push(
                estimated_true_frame.z
                    - sim
                        .world
                        .ground_height_at(estimated_true_frame.x, estimated_true_frame.y),
            );
        }
        let estimated_true_frame = truth * output.world_from_body.inverse() * point.position_m;
        counts.false_tall_offsets_m.push(
            (estimated_true_frame.x - true_surface.x)
                .hypot(estimated_true_frame.y - true_surface.y),
        );
    }
    print(&counts);
    Ok(())
}

fn print(counts: &Counts) {
    let share = |part: usize, whole: usize| 100.0 * part as f64 / whole.max(1) as f64;
    println!(
        "new cloud points within 10 m: {}; at a silhouette (true depth jumps > 20 % within the 7x7 patch): {:.1} %",
        counts.points,
        share(counts.at_silhouette, counts.points)
    );
    println!(
        "tall (> {TALL_M} m above the VO's local ground): {}; truly on a rock: {:.1} %; truly bare ground: {} ({:.1} %)",
        counts.tall,
        share(counts.tall_on_rock, counts.tall),
        counts.false_tall,
        share(counts.false_tall, counts.tall)
    );
    println!(
        "  of the bare-ground ones: depth short by > 20 % {:.1} %, long by > 20 % {:.1} %, right {:.1} %; at a silhouette {:.1} %",
        share(counts.false_tall_short, counts.false_tall),
        share(counts.false_tall_long, counts.false_tall),
        share(counts.false_tall_depth_right, counts.false_tall),
        share(counts.false_tall_at_silhouette, counts.false_tall)
    );
    println!(
        "  their offset from the surface their pixel shows, p10 / p50 / p90: {}",
        spread(counts.false_tall_offsets_m.clone())
    );
    println!(
        "  with the depth right, their height above the true ground, p10 / p50 / p90: {}",
        spread(counts.depth_right_height_errors_m.clone())
    );
    println!(
        "  depth error (estimate - truth), p10 / p50 / p90: false tall {}; ground called low {}",
        spread_percent(counts.false_tall_depth_errors_percent.clone()),
        spread_percent(counts.ground_depth_errors_percent.clone())
    );
    println!(
        "  true depth range within the patch, p10 / p50 / p90: false tall {}; ground called low {}",
        spread_percent(counts.false_tall_patch_jump_percent.clone()),
        spread_percent(counts.ground_patch_jump_percent.clone())
    );
    println!(
        "  gap from their true surface point to the nearest rock's bounding circle: {}",
        spread(counts.false_tall_rock_gaps_m.clone())
    );
}

fn spread(values: Vec<f64>) -> String {
    spread_in(values, "m")
}

fn spread_percent(values: Vec<f64>) -> String {
    spread_in(values, "%")
}

fn spread_in(mut values: Vec<f64>, unit: &str) -> String {
    if values.is_empty() {
        return "-".into();
    }
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((values.len() - 1) as f64 * q).round() as usize];
    format!("{:.3} / {:.3} / {:.3} {unit}", at(0.1), at(0.5), at(0.9))
}
