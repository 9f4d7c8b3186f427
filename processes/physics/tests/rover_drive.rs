//! Rover: waypoint following, turning on the spot, blocking rocks and climbable rocks.

mod common;

use common::{drive, flat_world, max_over, physics, run, yaw_of};
use hopnav_physics::{BlockReason, PhysicsConfig, PhysicsSim, RoverMode};
use hopnav_world::World;
use hopnav_world::config::ExplicitRockConfig;

fn rover_cfg(rover_xy: [f64; 2]) -> PhysicsConfig {
    let mut cfg = physics([-10.0, 6.0], rover_xy);
    cfg.jumper.initial_hop = false;
    cfg
}

fn rock(x: f64, y: f64, diameter_m: f64, height_m: f64) -> ExplicitRockConfig {
    ExplicitRockConfig {
        center_m: [x, y],
        diameter_m,
        height_m: Some(height_m),
    }
}

/// The rover at (−5, −3), 4.5 m short of a 0.5 m tall boulder on its way east.
fn rover_before_a_tall_rock() -> (World, PhysicsSim) {
    let world = flat_world(32.0, 16.0, &[rock(0.0, -3.0, 1.0, 0.5)]);
    let sim = PhysicsSim::new(&world, &rover_cfg([-5.0, -3.0]), 3).unwrap();
    (world, sim)
}

#[test]
fn drives_to_waypoint_ten_metres_away() {
    let world = flat_world(32.0, 16.0, &[]);
    let cfg = rover_cfg([-5.0, -3.0]);
    let tol = cfg.rover.arrive_tolerance_m;
    for goal in [[5.0, -3.0], [1.0, 5.0]] {
        let mut sim = PhysicsSim::new(&world, &cfg, 3).unwrap();
        let outs = run(&mut sim, 400, drive(goal, 0.5));
        let last = outs.last().unwrap();
        let p = last.rover.position_m;
        let miss = (p[0] - goal[0]).hypot(p[1] - goal[1]);
        let arrived_at = outs
            .iter()
            .position(|o| o.rover_status.mode == RoverMode::Arrived);
        eprintln!("goal {goal:?}: miss {miss:.3} m, arrived at frame {arrived_at:?}");
        assert_eq!(last.rover_status.mode, RoverMode::Arrived);
        assert!(miss <= tol + 0.02, "missed by {miss}");
        assert_eq!(last.rover_status.collision_count, 0);
        assert!(
            last.rover
                .linear_velocity_mps
                .iter()
                .all(|v| v.abs() < 1e-9)
        );
    }
}

#[test]
fn turns_on_the_spot() {
    let world = flat_world(32.0, 16.0, &[]);
    let cfg = rover_cfg([-5.0, -3.0]);
    let mut sim = PhysicsSim::new(&world, &cfg, 3).unwrap();
    let start = sim.rover_state().position_m;
    // Waypoint straight to the left: heading error 90°.
    let inputs = drive([-5.0, 5.0], 0.5);
    let mut turned = None;
    for _ in 0..200 {
        let out = sim.step_frame(&inputs);
        if out.rover_status.mode == RoverMode::Driving {
            break;
        }
        turned = Some(out);
    }
    let out = turned.expect("turned first");
    assert_eq!(out.rover_status.mode, RoverMode::Turning);
    let yaw = yaw_of(out.rover.orientation_xyzw);
    let p = out.rover.position_m;
    let moved = (p[0] - start[0]).hypot(p[1] - start[1]);
    eprintln!("yaw {:.2}°, translation {moved:.4} m", yaw.to_degrees());
    assert!(
        (yaw.to_degrees() - 90.0).abs() < 3.0,
        "yaw {}",
        yaw.to_degrees()
    );
    assert!(moved < 0.2, "moved {moved}");
    // Spinning wheels are steered tangentially (±atan(wheelbase/track)).
    let expect = (0.4f64).atan2(0.35);
    for a in out.rover_status.steer_angles_rad {
        assert!((a.abs() - expect).abs() < 0.06, "steer {a}");
    }
}

#[test]
fn tall_rock_blocks_and_counts_a_collision() {
    // 0.5 m tall boulder on the path (max climbable 0.2 m).
    let (world, mut sim) = rover_before_a_tall_rock();
    let outs = run(&mut sim, 300, drive([5.0, -3.0], 0.5));
    let last = outs.last().unwrap();
    eprintln!(
        "stopped at x = {:.3}, status {:?}",
        last.rover.position_m[0], last.rover_status
    );
    assert_eq!(last.rover_status.blocked, Some(BlockReason::Rock));
    assert_eq!(last.rover_status.collision_count, 1, "one contact episode");
    // Front of the footprint (wheelbase/2 + wheel radius = 0.55 m) stops at the rock's edge.
    let front = last.rover.position_m[0] + 0.55;
    let rock_edge = -world.rocks()[0].bounding_radius_m();
    assert!(
        front < rock_edge + 0.1 && front > rock_edge - 0.3,
        "front {front} edge {rock_edge}"
    );
    assert!(outs.iter().all(|o| o.rover.position_m[0] < -0.5));
}

#[test]
fn a_blocked_rover_backs_away_rear_first_and_can_then_turn() {
    let (_, mut sim) = rover_before_a_tall_rock();
    let blocked = run(&mut sim, 300, drive([5.0, -3.0], 0.5));
    let against_x_m = blocked.last().unwrap().rover.position_m[0];
    let yaw_rad = yaw_of(blocked.last().unwrap().rover.orientation_xyzw);
    // Back up 0.6 m toward a point straight behind.
    let mut back = drive([against_x_m - 0.6, -3.0], 0.3);
    if let Some(command) = back.drive.as_mut() {
        command.reverse = true;
    }
    let outs = run(&mut sim, 60, back);
    let last = outs.last().unwrap();
    assert!(
        outs.iter()
            .any(|o| o.rover_status.mode == RoverMode::Reversing),
        "{:?}",
        last.rover_status
    );
    assert!(
        last.rover.position_m[0] < against_x_m - 0.45,
        "backed up from {against_x_m} to {}",
        last.rover.position_m[0]
    );
    // Rear first: the heading did not flip.
    assert!((yaw_of(last.rover.orientation_xyzw) - yaw_rad).abs() < 0.1);
    assert_eq!(last.rover_status.collision_count, 1, "no new contact");
    assert_eq!(last.rover_status.blocked, None);
    // Clear of the rock, it can turn on the spot toward a waypoint to the side.
    let outs = run(&mut sim, 100, drive([against_x_m - 0.5, 2.0], 0.5));
    let last = outs.last().unwrap();
    assert!(
        yaw_of(last.rover.orientation_xyzw) > 1.2,
        "{:?}",
        last.rover_status
    );
    assert_eq!(last.rover_status.collision_count, 1);
}

/// A turn on the spot that swings a rear corner into a tall rock is refused. Told next to
/// drive to a point almost straight ahead, where driving carries that corner away from the
/// rock, the rover must drive: insisting on finishing the refused turn first froze it against
/// the rock for the rest of a mission (compare seed 20, rover-only, 80 s).
#[test]
fn a_rover_whose_turn_a_rock_refuses_still_drives_ahead() {
    // The rear-right corner of the footprint is at (-0.55, -0.4); the rock's edge 7 cm below.
    let world = flat_world(32.0, 16.0, &[rock(-0.55, -0.82, 0.7, 0.33)]);
    let mut sim = PhysicsSim::new(&world, &rover_cfg([0.0, 0.0]), 3).unwrap();
    // Behind and to the left: a turn on the spot, counter-clockwise, into the rock.
    let turned = run(&mut sim, 40, drive([-3.0, 1.0], 0.5)).pop().unwrap();
    assert_eq!(turned.rover_status.blocked, Some(BlockReason::Rock));
    let from = turned.rover.position_m;
    // Almost straight ahead: 5° further counter-clockwise, below the error that starts a
    // turn on the spot, above the one that ends it.
    let heading_rad = yaw_of(turned.rover.orientation_xyzw) + 5f64.to_radians();
    let ahead = [
        from[0] + 3.0 * heading_rad.cos(),
        from[1] + 3.0 * heading_rad.sin(),
    ];
    let last = run(&mut sim, 60, drive(ahead, 0.5)).pop().unwrap();
    let moved_m = (last.rover.position_m[0] - from[0]).hypot(last.rover.position_m[1] - from[1]);
    assert!(
        moved_m > 1.0,
        "moved {moved_m:.3} m ({:?})",
        last.rover_status
    );
    assert_eq!(last.rover_status.collision_count, 1, "no new contact");
}

/// Backing away from a tall rock with a rear wheel rolling onto a small rock: the body pitches,
/// and the footprint's lower front corner swings a little into the tall rock it touches.
/// That must not wedge the rover.
#[test]
fn a_rover_backing_away_over_a_small_rock_is_not_wedged_by_the_rock_it_touched() {
    let tall = rock(0.0, -3.0, 1.0, 0.5);
    let probe = flat_world(32.0, 16.0, std::slice::from_ref(&tall));
    let mut sim = PhysicsSim::new(&probe, &rover_cfg([-5.0, -3.0]), 3).unwrap();
    let against_x_m = run(&mut sim, 300, drive([5.0, -3.0], 0.5))
        .last()
        .unwrap()
        .rover
        .position_m[0];
    // The same world with a small rock under the left rear wheel's way back (a spot found by
    // a scan of positions and heights: without the rule it wedged the rover for good).
    let small = rock(against_x_m - 0.45, -3.0 + 0.35, 0.3, 0.15);
    let world = flat_world(32.0, 16.0, &[tall, small]);
    let mut sim = PhysicsSim::new(&world, &rover_cfg([-5.0, -3.0]), 3).unwrap();
    let blocked = run(&mut sim, 300, drive([5.0, -3.0], 0.5)).pop().unwrap();
    assert_eq!(blocked.rover_status.blocked, Some(BlockReason::Rock));
    let against_x_m = blocked.rover.position_m[0];
    let mut back = drive([against_x_m - 1.5, -3.0], 0.3);
    if let Some(command) = back.drive.as_mut() {
        command.reverse = true;
    }
    let last = run(&mut sim, 80, back).pop().unwrap();
    assert!(
        last.rover.position_m[0] < against_x_m - 0.45,
        "backed up from {against_x_m} to {} ({:?})",
        last.rover.position_m[0],
        last.rover_status
    );
}

#[test]
fn small_rock_is_climbed() {
    // 0.12 m pebble under the left wheels' path.
    let world = flat_world(32.0, 16.0, &[rock(0.0, -3.0 + 0.35, 0.3, 0.12)]);
    let cfg = rover_cfg([-5.0, -3.0]);
    let mut sim = PhysicsSim::new(&world, &cfg, 3).unwrap();
    let outs = run(&mut sim, 400, drive([5.0, -3.0], 0.5));
    let last = outs.last().unwrap();
    let base_z = outs[0].rover.position_m[2];
    let max_z = max_over(&outs, |o| o.rover.position_m[2]);
    let max_roll = outs
        .iter()
        .map(|o| {
            let [x, y, z, w] = o.rover.orientation_xyzw;
            (2.0 * (w * x + y * z))
                .atan2(1.0 - 2.0 * (x * x + y * y))
                .abs()
        })
        .fold(0.0, f64::max);
    eprintln!(
        "rose {:.3} m, max roll {:.2}°",
        max_z - base_z,
        max_roll.to_degrees()
    );
    assert_eq!(last.rover_status.mode, RoverMode::Arrived);
    assert_eq!(last.rover_status.collision_count, 0);
    assert!(
        max_z - base_z > 0.02 && max_roll > 0.05,
        "the rover rode over the rock"
    );
}

#[test]
fn hold_stops_the_rover() {
    let world = flat_world(32.0, 16.0, &[]);
    let cfg = rover_cfg([-5.0, -3.0]);
    let mut sim = PhysicsSim::new(&world, &cfg, 3).unwrap();
    let _ = run(&mut sim, 40, drive([5.0, -3.0], 0.5));
    let mut hold = drive([5.0, -3.0], 0.5);
    if let Some(d) = hold.drive.as_mut() {
        d.hold = true;
    }
    let outs = run(&mut sim, 30, hold);
    let last = outs.last().unwrap();
    assert_eq!(last.rover_status.mode, RoverMode::Holding);
    assert_eq!(last.rover.linear_velocity_mps, [0.0; 3]);
    // Decelerating from 0.5 m/s at 0.5 m/s² takes 1 s: it then stays put.
    assert_eq!(outs[20].rover.position_m, last.rover.position_m);
}

#[test]
fn non_finite_commands_are_rejected() {
    let world = flat_world(32.0, 16.0, &[]);
    let cfg = rover_cfg([-5.0, -3.0]);
    let mut sim = PhysicsSim::new(&world, &cfg, 3).unwrap();
    let out = sim.step_frame(&drive([f64::NAN, 0.0], 0.5));
    assert_eq!(out.rejected_inputs, 1);
    assert_eq!(out.rover_status.mode, RoverMode::Idle);
}
