//! The rover VO on short rendered traverses (known motion, textureless frames, a disagreeing
//! stereo pair, determinism), scored with the offline evaluation's metrics.

use hopnav_eval::rover_vo::evaluate;
use hopnav_rover_vo::config::RoverVoConfig;
use hopnav_rover_vo::pipeline::VoStatus;
use hopnav_rover_vo::run::run_traverse;
use hopnav_rover_vo::simulate::{TraverseConfig, simulate_traverse};

fn short_traverse(blackout: Vec<usize>) -> TraverseConfig {
    let mut cfg = TraverseConfig::default();
    cfg.world.terrain.size_x_m = 32.0;
    cfg.world.terrain.size_y_m = 32.0;
    cfg.waypoints_xy_m = vec![[-12.0, -4.0], [0.0, -4.0], [0.0, 6.0]];
    cfg.max_frames = Some(90);
    cfg.blackout_frames = blackout;
    cfg
}

#[test]
fn follows_a_rendered_traverse_with_known_motion() {
    let sim = simulate_traverse(&short_traverse(Vec::new())).unwrap();
    let run = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    let report = evaluate(&run, &sim.truth_world_from_body).unwrap();
    assert_eq!(report.propagated_frames, 0, "{report}");
    assert!(
        report.final_error_m < 0.05 + 0.02 * report.distance_m,
        "{report}"
    );
    assert!(run.cloud_points > 100);
}

#[test]
fn textureless_frames_propagate_with_low_confidence_and_recover() {
    let sim = simulate_traverse(&short_traverse((30..36).collect())).unwrap();
    let run = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    for k in 30..36 {
        let o = &run.outputs[k];
        assert!(
            o.confidence < 0.5 && o.status == VoStatus::Propagated,
            "frame {k}: {o:?}"
        );
        // Position held, attitude from the IMU.
        let err = o
            .world_from_body
            .rotation
            .angle_to(&sim.truth_world_from_body[k].rotation);
        assert!(err < 0.02, "frame {k}: rotation error {err}");
    }
    assert!(
        run.outputs[40..].iter().all(|o| o.confidence >= 0.5),
        "no recovery"
    );
    let last = run.outputs.len() - 1;
    let err = (run.outputs[last].world_from_body.translation.vector
        - sim.truth_world_from_body[last].translation.vector)
        .norm();
    // Six held frames lose at most their 0.3 m of motion.
    assert!(err < 0.45, "final error {err}");
}

#[test]
fn a_disagreeing_stereo_pair_does_not_diverge() {
    let mut sim = simulate_traverse(&short_traverse(Vec::new())).unwrap();
    // Frames 20..23: the right view shows something else (a much later left view).
    for k in 20..23 {
        sim.right[k] = sim.left[k + 60].clone();
    }
    let run = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    for k in 20..23 {
        let o = &run.outputs[k];
        let err = (o.world_from_body.translation.vector
            - sim.truth_world_from_body[k].translation.vector)
            .norm();
        assert!(err < 0.2, "frame {k}: error {err}, {o:?}");
    }
    let report = evaluate(&run, &sim.truth_world_from_body).unwrap();
    assert!(report.final_error_m < 0.3, "{report}");
}

#[test]
fn deterministic() {
    let sim = simulate_traverse(&TraverseConfig {
        max_frames: Some(30),
        ..short_traverse(Vec::new())
    })
    .unwrap();
    let a = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    let b = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    assert_eq!(a.outputs, b.outputs);
}
