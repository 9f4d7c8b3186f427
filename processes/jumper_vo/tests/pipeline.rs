//! End-to-end tests on short rendered hops (small terrain so they stay fast in debug).

use hopnav_eval::jumper_vo::evaluate;
use hopnav_jumper_vo::config::{JumperVoConfig, ScaleMethod};
use hopnav_jumper_vo::output::{FrameInput, VoOutput, VoStatus};
use hopnav_jumper_vo::pipeline::JumperVo;
use hopnav_jumper_vo::run::run_hop;
use hopnav_jumper_vo::simulate::{SimConfig, SimulatedHop, simulate_hop};
use hopnav_vision::image::ImageView;
use nalgebra::Isometry3;

fn small_sim(frames: usize, blackout: Vec<usize>) -> SimulatedHop {
    let mut cfg = SimConfig::default();
    cfg.world.terrain.size_x_m = 64.0;
    cfg.world.terrain.size_y_m = 48.0;
    cfg.hop.launch_position_m.x = -4.0;
    cfg.num_frames = Some(frames);
    cfg.blackout_frames = blackout;
    simulate_hop(&cfg).unwrap()
}

/// A VO with the simulation's robot model, placed at the hop's first pose (returned too).
/// The index of the first output that says the jumper landed.
fn first_landed_at(outputs: &[VoOutput]) -> usize {
    outputs
        .iter()
        .position(|o| o.status == VoStatus::Landed)
        .expect("never landed")
}

fn vo_at_launch(sim: &SimulatedHop) -> (JumperVo, Isometry3<f64>) {
    let config = sim.robot_config(&JumperVoConfig::default());
    let launch = sim.truth_world_from_body[0];
    (JumperVo::new(config, sim.camera, launch).unwrap(), launch)
}

#[test]
fn rendered_hop_is_tracked_with_both_scale_methods() {
    let sim = small_sim(50, Vec::new());
    let default = run_hop(&sim, &JumperVoConfig::default()).unwrap();
    let report = evaluate(&default.outputs, &sim.truth_world_from_body).unwrap();
    println!("ballistic: {report}");
    assert!(report.ate_sim3_m < 0.5, "{report}");
    assert!(report.ate_se3_m < 0.6, "{report}");
    assert!(
        report.max_rotation_error_rad < 8f64.to_radians(),
        "{report}"
    );
    assert!(
        default
            .outputs
            .iter()
            .filter(|o| o.status == VoStatus::Tracking)
            .count()
            > 30
    );
    // Touchdown is detected and the pose is then held.
    assert!(default.outputs.iter().any(|o| o.status == VoStatus::Landed));
    // Keyframes publish a world-frame cloud near the ground.
    let cloud = default
        .outputs
        .iter()
        .filter_map(|o| o.cloud.as_ref())
        .find(|c| c.len() > 50)
        .expect("a keyframe cloud");
    assert!(cloud.iter().any(|p| p.height_above_ground_m.is_some()));

    let eq4 = JumperVoConfig {
        scale_method: ScaleMethod::PaperEq4,
        ..JumperVoConfig::default()
    };
    let baseline = run_hop(&sim, &eq4).unwrap();
    let report4 = evaluate(&baseline.outputs, &sim.truth_world_from_body).unwrap();
    println!("eq4: {report4}");
    assert!(report4.ate_sim3_m.is_finite() && report4.ate_sim3_m < 10.0);
    assert!(baseline.outputs.iter().all(|o| {
        o.world_from_body
            .translation
            .vector
            .iter()
            .all(|v| v.is_finite())
    }));
}

/// Nothing but gravity acts on the body in flight: one angular rate fitted to the keyframe
/// rotations, anchored at the launch attitude, keeps the attitude from drifting as the chained
/// keyframe rotations do (and with it the translation directions, and the hop's length).
#[test]
fn the_spin_fit_holds_the_attitude_closer_than_chained_keyframe_rotations() {
    let sim = small_sim(50, Vec::new());
    let report = |config: &JumperVoConfig| {
        let run = run_hop(&sim, config).unwrap();
        evaluate(&run.outputs, &sim.truth_world_from_body).unwrap()
    };
    let fitted = report(&JumperVoConfig {
        attitude_from_spin_fit: true,
        ..JumperVoConfig::default()
    });
    let chained = report(&JumperVoConfig {
        attitude_from_spin_fit: false,
        ..JumperVoConfig::default()
    });
    println!("spin fit: {fitted}\nchained: {chained}");
    assert!(
        fitted.max_rotation_error_rad < chained.max_rotation_error_rad,
        "spin fit {fitted} against chained {chained}"
    );
    assert!(fitted.ate_se3_m < 0.6, "{fitted}");
}

#[test]
fn black_frames_mid_flight_do_not_diverge() {
    let sim = small_sim(30, (12..16).collect());
    let run = run_hop(&sim, &JumperVoConfig::default()).unwrap();
    for k in 12..16 {
        let o = &run.outputs[k];
        assert_eq!(o.status, VoStatus::Propagating, "frame {k}");
        assert!(o.confidence <= 0.1);
    }
    // Tracking resumes after the blackout.
    assert!(
        run.outputs[18..]
            .iter()
            .any(|o| o.status == VoStatus::Tracking)
    );
    for (o, g) in run.outputs.iter().zip(&sim.truth_world_from_body) {
        let err = (o.world_from_body.translation.vector - g.translation.vector).norm();
        assert!(err < 2.0, "frame {} error {err}", o.frame_index);
    }
}

/// A vision breakdown at the impact (black frames from just before touchdown)
/// must land the jumper near the touchdown point and hold it there, not keep propagating the
/// ballistic arc under the ground.
#[test]
fn breakdown_at_touchdown_lands_and_holds() {
    let sim = small_sim(52, (45..52).collect());
    let run = run_hop(&sim, &JumperVoConfig::default()).unwrap();
    let first_landed = first_landed_at(&run.outputs);
    assert!(
        (46..=48).contains(&first_landed),
        "landed at {first_landed}"
    );
    let launch_z = sim.truth_world_from_body[0].translation.z;
    for (o, g) in run.outputs[first_landed..]
        .iter()
        .zip(&sim.truth_world_from_body[first_landed..])
    {
        let err = (o.world_from_body.translation.vector - g.translation.vector).norm();
        assert!(err < 1.5, "frame {} error {err}", o.frame_index);
        assert!(o.world_from_body.translation.z > launch_z - 1.0);
        assert!(o.confidence <= 0.5);
    }
}

#[test]
fn hostile_input_never_panics() {
    let sim = small_sim(3, Vec::new());
    let mut vo = JumperVo::new(
        JumperVoConfig::default(),
        sim.camera,
        sim.truth_world_from_body[0],
    )
    .unwrap();
    let black = vec![0u8; sim.width_px * sim.height_px];
    let tiny = vec![7u8; 16];
    let frames: Vec<(f64, ImageView<'_>, Option<f64>)> = vec![
        (
            0.0,
            ImageView::packed(&black, sim.width_px, sim.height_px).unwrap(),
            Some(f64::NAN),
        ),
        (0.1, ImageView::packed(&tiny, 4, 4).unwrap(), None),
        (
            f64::NAN,
            ImageView::packed(&sim.images[1], sim.width_px, sim.height_px).unwrap(),
            Some(1.0),
        ),
        (
            0.05,
            ImageView::packed(&sim.images[1], sim.width_px, sim.height_px).unwrap(),
            Some(f64::INFINITY),
        ),
        (
            0.2,
            ImageView::packed(&sim.images[2], sim.width_px, sim.height_px).unwrap(),
            Some(1e300),
        ),
        (
            0.3,
            ImageView::packed(&black, sim.width_px, sim.height_px).unwrap(),
            None,
        ),
    ];
    for (k, (t, image, alt)) in frames.into_iter().enumerate() {
        let out = vo.process_frame(FrameInput {
            frame_index: k as u64,
            t_s: t,
            image,
            altimeter_m: alt,
        });
        assert!(
            out.world_from_body
                .translation
                .vector
                .iter()
                .all(|v| v.is_finite())
        );
        assert!((0.0..=1.0).contains(&out.confidence));
    }
}

/// Feeds `sim`'s frames from `first` on (images, times, altimeter) into `vo`.
fn feed(
    vo: &mut JumperVo,
    sim: &SimulatedHop,
    first: usize,
) -> Vec<hopnav_jumper_vo::output::VoOutput> {
    (first..sim.images.len())
        .map(|k| {
            vo.process_frame(FrameInput {
                frame_index: k as u64,
                t_s: sim.t_s[k],
                image: ImageView::packed(&sim.images[k], sim.width_px, sim.height_px).unwrap(),
                altimeter_m: Some(sim.altimeter_m[k]),
            })
        })
        .collect()
}

/// A launch announced before its first image (the live process: the camera's first frame comes
/// a frame after the launch) is carried to that image with the commanded velocity and spin.
#[test]
fn launch_before_the_first_image_is_propagated_to_it() {
    let sim = small_sim(8, Vec::new());
    let (mut vo, launch) = vo_at_launch(&sim);
    vo.start_hop_at(launch, sim.t_s[0]);
    let outputs = feed(&mut vo, &sim, 2);
    assert_eq!(outputs[0].status, VoStatus::Initializing);
    let first = outputs[0].world_from_body;
    let truth = sim.truth_world_from_body[2];
    let position_error = (first.translation.vector - truth.translation.vector).norm();
    assert!(position_error < 1e-6, "position off by {position_error} m");
    let rotation_error = first.rotation.angle_to(&truth.rotation);
    assert!(
        rotation_error < 1e-6,
        "attitude off by {rotation_error} rad"
    );
    for o in &outputs {
        let err = (o.world_from_body.translation.vector
            - sim.truth_world_from_body[o.frame_index as usize]
                .translation
                .vector)
            .norm();
        assert!(err < 0.5, "frame {} off by {err} m", o.frame_index);
    }
}

/// After touchdown the landing cage's damping slides the body along its touchdown velocity:
/// `v_h / k` in all, then it rests.
#[test]
fn landed_body_slides_along_the_touchdown_velocity_then_rests() {
    let sim = small_sim(60, (45..60).collect());
    let config = JumperVoConfig {
        landing_slide_decay_per_s: 8.0,
        ..sim.robot_config(&JumperVoConfig::default())
    };
    let mut vo = JumperVo::new(config, sim.camera, sim.truth_world_from_body[0]).unwrap();
    let outputs = feed(&mut vo, &sim, 0);
    let landed: Vec<_> = outputs
        .iter()
        .filter(|o| o.status == VoStatus::Landed)
        .map(|o| o.world_from_body.translation.vector)
        .collect();
    assert!(landed.len() >= 10, "{} landed frames", landed.len());
    let heading = sim.hop.launch_velocity_mps().xy().normalize();
    let along: Vec<f64> = landed.iter().map(|p| p.xy().dot(&heading)).collect();
    assert!(along.windows(2).all(|w| w[1] >= w[0] - 1e-9), "{along:?}");
    let slide = along[along.len() - 1] - along[0];
    let expected = sim.hop.launch_velocity_mps().xy().norm() / 8.0;
    assert!(slide > 0.3 * expected && slide < expected, "slid {slide} m");
    // At rest: the last frames hold the position.
    assert!((along[along.len() - 1] - along[along.len() - 3]).abs() < 1e-3);
    let zero = JumperVoConfig {
        landing_slide_decay_per_s: 0.0,
        ..sim.robot_config(&JumperVoConfig::default())
    };
    let mut vo = JumperVo::new(zero, sim.camera, sim.truth_world_from_body[0]).unwrap();
    let held: Vec<_> = feed(&mut vo, &sim, 0)
        .into_iter()
        .filter(|o| o.status == VoStatus::Landed)
        .map(|o| o.world_from_body.translation.vector.xy())
        .collect();
    assert!(held.iter().all(|p| (p - held[0]).norm() < 1e-9));
}

/// A hop commanded but never flown (the jumper wedged against a rock): the camera sees the
/// same ground frame after frame. The VO must land where it launched, not fly the commanded
/// ballistic arc.
#[test]
fn a_launch_that_never_leaves_the_ground_lands_where_it_started() {
    let sim = small_sim(2, Vec::new());
    let (mut vo, launch) = vo_at_launch(&sim);
    let outputs: Vec<_> = (0..30)
        .map(|k| {
            vo.process_frame(FrameInput {
                frame_index: k,
                t_s: sim.t_s[0] + 0.1 * k as f64,
                image: ImageView::packed(&sim.images[0], sim.width_px, sim.height_px).unwrap(),
                altimeter_m: Some(sim.altimeter_m[0]),
            })
        })
        .collect();
    let first_landed = first_landed_at(&outputs);
    assert!(first_landed <= 6, "landed only at frame {first_landed}");
    // Until then the commanded arc is flown; from then on the body rests at the launch.
    for o in &outputs[first_landed..] {
        let err = (o.world_from_body.translation.vector - launch.translation.vector).xy();
        assert!(
            err.norm() < 0.1,
            "frame {} off by {} m",
            o.frame_index,
            err.norm()
        );
    }
}

/// The same, with a wedged body that rocks (the image jumps back and forth, never still):
/// the altimeter, which stays at the launch altitude within its noise, tells.
#[test]
fn a_rocking_launch_that_never_climbs_is_told_by_the_altimeter() {
    let sim = small_sim(2, Vec::new());
    let config = sim.robot_config(&JumperVoConfig::default());
    let launch = sim.truth_world_from_body[0];
    let mut vo = JumperVo::new(config.clone(), sim.camera, launch).unwrap();
    let noise_m = [0.8, -1.1, 0.3, -0.4, 1.2, -0.9, 0.1, 0.6, -1.3, 0.5];
    let outputs: Vec<_> = (0..30)
        .map(|k| {
            vo.process_frame(FrameInput {
                frame_index: k as u64,
                t_s: sim.t_s[0] + 0.1 * k as f64,
                image: ImageView::packed(&sim.images[k % 2], sim.width_px, sim.height_px).unwrap(),
                altimeter_m: Some(sim.altimeter_m[0] + config.altimeter_sigma_m * noise_m[k % 10]),
            })
        })
        .collect();
    let first_landed = first_landed_at(&outputs);
    assert!(first_landed <= 12, "landed only at frame {first_landed}");
    let last = outputs[outputs.len() - 1]
        .world_from_body
        .translation
        .vector;
    assert!((last - launch.translation.vector).xy().norm() < 0.1);
}

/// On bare ground every feature the cloud calls higher than the rover can climb is a phantom
/// rock. Counts the points the mapper would call high: above 0.15 m by more than two sigmas
/// of their height (depth sigma times the vertical part of the viewing ray), sigma ≤ 0.25 m.
fn phantom_rocks_on_bare_ground(seed: u64) -> (usize, usize) {
    let mut cfg = SimConfig::default();
    cfg.world.terrain.size_x_m = 64.0;
    cfg.world.terrain.size_y_m = 48.0;
    cfg.world.craters.count = 0;
    cfg.world.rocks.golombek_k = 0.0;
    cfg.world.seed = seed;
    cfg.seed = seed;
    cfg.hop.launch_position_m.x = -4.0;
    let sim = simulate_hop(&cfg).unwrap();
    let run = run_hop(&sim, &JumperVoConfig::default()).unwrap();
    let (mut points, mut phantoms) = (0, 0);
    for output in &run.outputs {
        let Some(cloud) = &output.cloud else {
            continue;
        };
        let camera_m = (output.world_from_body * sim.body_from_camera)
            .translation
            .vector;
        for point in cloud.iter().filter(|p| p.depth_sigma_m <= 0.25) {
            let Some(height_m) = point.height_above_ground_m else {
                continue;
            };
            let ray_m = point.position_m.coords - camera_m;
            let vertical_sigma_m = point.depth_sigma_m * ray_m.z.abs() / ray_m.norm();
            points += 1;
            if height_m > 0.15 + 2.0 * vertical_sigma_m {
                phantoms += 1;
            }
        }
    }
    (points, phantoms)
}

#[test]
fn clouds_after_takeoff_put_no_rock_on_bare_ground() {
    // The cloud of a keyframe pair must be triangulated over the baseline that was measured
    // (vision direction times scale from the re-anchored keyframe). Over the stored keyframe
    // pose instead, the ground behind the takeoff spot rose into 1-32 high points per hop on
    // 8 of 8 seeds (80 m × 64 m terrain), and on seed 3 here.
    for seed in [3, 7] {
        let (points, phantoms) = phantom_rocks_on_bare_ground(seed);
        println!("seed {seed}: {phantoms} of {points} points high");
        assert!(points > 1000, "seed {seed}: only {points} cloud points");
        assert_eq!(
            phantoms, 0,
            "seed {seed}: {phantoms} of {points} points high"
        );
    }
}

/// The local bundle adjustment refines the flight from every keyframe's sightings: on a
/// rendered hop it ends closer to the truth than the fits alone, and says it ran.
#[test]
fn the_bundle_adjustment_brings_the_hop_closer_than_the_fits_alone() {
    let sim = small_sim(50, Vec::new());
    let errors = |bundle_adjustment: bool| {
        let config = JumperVoConfig {
            bundle_adjustment,
            ..JumperVoConfig::default()
        };
        let run = run_hop(&sim, &config).unwrap();
        let report = evaluate(&run.outputs, &sim.truth_world_from_body).unwrap();
        println!("bundle adjustment {bundle_adjustment}: {report}");
        // The published σ is honest with the adjustment: the error stays within 2 σ on most
        // frames. (The fits alone treat correlated directions as independent and publish a σ
        // that is too small: 58 % here.)
        if bundle_adjustment {
            assert!(report.within_two_sigma_percent >= 80.0, "{report}");
        }
        (report.ate_sim3_m, report.rmse_unaligned_m)
    };
    let (ate_with, unaligned_with) = errors(true);
    let (ate_without, unaligned_without) = errors(false);
    assert!(ate_with < ate_without, "{ate_with} against {ate_without}");
    assert!(
        unaligned_with < unaligned_without,
        "{unaligned_with} against {unaligned_without}"
    );
    let (mut vo, _) = vo_at_launch(&sim);
    for (k, image) in sim.images.iter().enumerate() {
        vo.process_frame(FrameInput {
            frame_index: k as u64,
            t_s: sim.t_s[k],
            image: ImageView::packed(image, sim.width_px, sim.height_px).unwrap(),
            altimeter_m: sim.altimeter_m.get(k).copied(),
        });
    }
    let stats = vo.ba_stats();
    assert!(
        stats.accepted >= 5 && stats.accepted <= stats.tried,
        "{stats:?}"
    );
}

/// A second of sky (ten black frames, as when a tumbling launch points the camera up): the VO
/// says it coasts, coasts on the adjusted flight within decimetres, re-acquires the ground,
/// and does not jump when it does.
#[test]
fn a_second_without_ground_is_coasted_and_rejoined_without_a_jump() {
    let sim = small_sim(36, (12..22).collect());
    let run = run_hop(&sim, &JumperVoConfig::default()).unwrap();
    for k in 12..22 {
        assert_eq!(run.outputs[k].status, VoStatus::Propagating, "frame {k}");
    }
    // The published σ widens while the VO coasts.
    let sigma = |k: usize| run.outputs[k].position_sigma_m;
    assert!(
        sigma(11).is_finite() && sigma(21) > sigma(11),
        "{} then {}",
        sigma(11),
        sigma(21)
    );
    assert!(
        run.outputs[22..]
            .iter()
            .any(|o| o.status == VoStatus::Tracking)
    );
    let error = |k: usize| {
        (run.outputs[k].world_from_body.translation.vector
            - sim.truth_world_from_body[k].translation.vector)
            .norm()
    };
    let worst = (0..run.outputs.len()).map(error).fold(0.0, f64::max);
    println!("worst error {worst:.3} m");
    // Measured 0.13 m; before empty keyframes were kept out of the adjustment's window, the
    // blackout pushed every seeing keyframe out and the error jumped by 0.45 m.
    assert!(worst < 0.3, "worst error {worst} m");
    for k in 12..run.outputs.len() {
        let jump = (error(k) - error(k - 1)).abs();
        assert!(jump < 0.15, "frame {k}: error changed by {jump} m");
    }
}
