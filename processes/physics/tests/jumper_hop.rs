//! Jumper hops on flat ground: Table 1 range and apex, aimed hops, clamping, settling.

mod common;

use common::{flat_world, hop_scene, physics, run};
use hopnav_physics::{FrameInputs, HopRequest, HopState, PhysicsSim};

/// Analytic Table 1 hop: 10 m/s at 60° under 3.711 m/s².
const RANGE_M: f64 = 23.34;
const APEX_M: f64 = 10.10;

#[test]
fn table1_hop_matches_analytic_range_and_apex() {
    let (world, cfg) = hop_scene();
    let mut sim = PhysicsSim::new(&world, &cfg, 1).unwrap();
    let outs = run(&mut sim, 120, FrameInputs::default());
    let hop = outs.last().unwrap().jumper_status.current_hop.unwrap();
    let range = hop.range_m().expect("landed");
    eprintln!(
        "range {range:.4} m apex {:.4} m flight {:.3} s",
        hop.apex_height_m, hop.flight_time_s
    );
    assert!((range - RANGE_M).abs() / RANGE_M < 0.01, "range {range}");
    assert!(
        (hop.apex_height_m - APEX_M).abs() / APEX_M < 0.01,
        "apex {}",
        hop.apex_height_m
    );
    assert!(
        (hop.flight_time_s - 4.667).abs() < 0.1,
        "flight {}",
        hop.flight_time_s
    );
    let last = outs.last().unwrap();
    assert_eq!(last.jumper_status.state, HopState::Settled);
    assert_eq!(last.jumper_status.hop_count, 1);
}

/// Runs until the jumper has landed and settled after hop number `hop`.
fn run_until_settled(
    sim: &mut PhysicsSim,
    hop: u32,
    max_frames: usize,
) -> hopnav_physics::FrameOutputs {
    let mut last = *sim.last_outputs();
    for _ in 0..max_frames {
        last = sim.step_frame(&FrameInputs::default());
        if last.jumper_status.hop_count == hop && last.jumper_status.state == HopState::Settled {
            return last;
        }
    }
    panic!("hop {hop} did not settle: {:?}", last.jumper_status);
}

#[test]
fn requested_hop_lands_near_target_and_settles() {
    let world = flat_world(64.0, 16.0, &[]);
    let mut cfg = physics([-10.0, 2.0], [-10.0, -4.0]);
    cfg.jumper.initial_hop = false;
    let mut sim = PhysicsSim::new(&world, &cfg, 5).unwrap();
    for (n, target) in [[5.0, 5.0], [-12.0, 0.0], [-6.0, -2.0]]
        .into_iter()
        .enumerate()
    {
        let start = sim.jumper_state().position_m;
        let out = sim.step_frame(&FrameInputs {
            drive: None,
            hop_request: Some(HopRequest {
                target_xy_m: target,
            }),
        });
        assert_eq!(out.jumper_status.state, HopState::InFlight);
        let done = run_until_settled(&mut sim, n as u32 + 1, 400);
        let hop = done.jumper_status.current_hop.unwrap();
        assert!(!hop.clamped);
        let land = hop.landing_position_m.unwrap();
        let want = (target[0] - start[0]).hypot(target[1] - start[1]);
        let got = hop.range_m().unwrap();
        let miss = (land[0] - target[0]).hypot(land[1] - target[1]);
        eprintln!(
            "hop {}: wanted {want:.2} m, flew {got:.2} m, missed target by {miss:.3} m",
            n + 1
        );
        assert!((got - want).abs() / want < 0.03, "range {got} vs {want}");
        assert!(miss / want < 0.03, "missed by {miss}");
    }
}

#[test]
fn request_beyond_limits_is_clamped() {
    let world = flat_world(72.0, 12.0, &[]);
    let mut cfg = physics([-30.0, 2.0], [-30.0, -3.0]);
    cfg.jumper.initial_hop = false;
    let max_speed = cfg.jumper.max_launch_speed_mps;
    let mut sim = PhysicsSim::new(&world, &cfg, 5).unwrap();
    sim.request_hop([40.0, 2.0]);
    let done = run_until_settled(&mut sim, 1, 400);
    let hop = done.jumper_status.current_hop.unwrap();
    assert!(hop.clamped);
    assert_eq!(hop.launch_speed_mps, max_speed);
    let expected = max_speed * max_speed * (2.0 * hop.launch_angle_rad).sin() / 3.711;
    let got = hop.range_m().unwrap();
    assert!(
        (got - expected).abs() / expected < 0.01,
        "range {got} vs {expected}"
    );
}

#[test]
fn request_during_flight_waits_for_settle() {
    let (world, cfg) = hop_scene();
    let mut sim = PhysicsSim::new(&world, &cfg, 1).unwrap();
    let _ = sim.step_frame(&FrameInputs::default());
    let out = sim.step_frame(&FrameInputs {
        drive: None,
        hop_request: Some(HopRequest {
            target_xy_m: [0.0, 0.0],
        }),
    });
    assert_eq!(out.jumper_status.state, HopState::InFlight);
    assert_eq!(out.jumper_status.pending_target_xy_m, Some([0.0, 0.0]));
    let done = run_until_settled(&mut sim, 2, 600);
    assert_eq!(
        done.jumper_status.current_hop.unwrap().target_xy_m,
        Some([0.0, 0.0])
    );
}
