//! Config files: defaults round-trip, unknown keys and out-of-range values are rejected with
//! the key named, and bad start poses are reported.

mod common;

use hopnav_physics::{PhysicsConfig, PhysicsError, PhysicsSim};

#[test]
fn defaults_round_trip_through_toml() {
    let cfg = PhysicsConfig::default();
    let text = toml::to_string(&cfg).unwrap();
    let back: PhysicsConfig = toml::from_str(&text).unwrap();
    assert_eq!(back, cfg);
    assert_eq!(back.validate(), Ok(()));
}

#[test]
fn partial_file_keeps_defaults() {
    let cfg: PhysicsConfig =
        toml::from_str("[jumper]\nlaunch_speed_mps = 8.0\n[rover]\nmax_climbable_height_m = 0.1\n")
            .unwrap();
    assert_eq!(cfg.jumper.launch_speed_mps, 8.0);
    assert_eq!(cfg.rover.max_climbable_height_m, 0.1);
    assert_eq!(cfg.gravity_mps2, 3.711);
    assert_eq!(cfg.validate(), Ok(()));
}

#[test]
fn unknown_key_is_rejected() {
    let err = toml::from_str::<PhysicsConfig>("[jumper]\nlaunch_sped_mps = 8.0\n").unwrap_err();
    assert!(err.to_string().contains("launch_sped_mps"), "{err}");
}

fn error_of(edit: impl FnOnce(&mut PhysicsConfig)) -> String {
    let mut cfg = PhysicsConfig::default();
    edit(&mut cfg);
    cfg.validate().unwrap_err().to_string()
}

#[test]
fn out_of_range_values_name_their_key() {
    let e = error_of(|c| c.jumper.launch_speed_mps = 14.0);
    assert_eq!(
        e,
        "physics.jumper.launch_speed_mps = 14 is out of range: allowed [0.5, 12] \
         (bounds: physics.jumper.min_launch_speed_mps, physics.jumper.max_launch_speed_mps)"
    );
    let e = error_of(|c| c.jumper.launch_angle_rad = 1.5);
    assert!(
        e.starts_with("physics.jumper.launch_angle_rad = 1.5 is out of range"),
        "{e}"
    );
    let e = error_of(|c| c.substeps = 0);
    assert_eq!(e, "physics.substeps = 0 is out of range: allowed [1, 1000]");
    let e = error_of(|c| c.altimeter.sigma_m = -1.0);
    assert!(e.starts_with("physics.altimeter.sigma_m = -1"), "{e}");
    let e = error_of(|c| c.rover.max_climbable_height_m = 0.5);
    assert!(
        e.contains("physics.rover.max_climbable_height_m")
            && e.contains("physics.rover.ground_clearance_m"),
        "{e}"
    );
    let e = error_of(|c| c.imu.gyro_noise_radps = f64::INFINITY);
    assert!(e.starts_with("physics.imu.gyro_noise_radps = inf"), "{e}");
    let e = error_of(|c| c.rover.chassis_half_extents_m[1] = 0.0);
    assert!(
        e.starts_with("physics.rover.chassis_half_extents_m[1] = 0"),
        "{e}"
    );
}

#[test]
fn bad_start_poses_are_reported() {
    let rock = hopnav_world::config::ExplicitRockConfig {
        center_m: [2.0, 0.0],
        diameter_m: 1.2,
        height_m: Some(0.6),
    };
    let world = common::flat_world(20.0, 10.0, &[rock]);
    let sim = |j: [f64; 2], r: [f64; 2]| PhysicsSim::new(&world, &common::physics(j, r), 1).err();
    assert!(sim([-5.0, 2.0], [-5.0, -2.0]).is_none());
    let e = sim([-5.0, 2.0], [2.0, 0.3]).unwrap();
    assert!(
        matches!(e, PhysicsError::StartInsideRock { rock_index: 0, .. }),
        "{e}"
    );
    assert!(e.to_string().starts_with("physics.rover.start_xy_m"));
    let e = sim([2.0, 0.0], [-5.0, -2.0]).unwrap();
    assert!(
        e.to_string().starts_with("physics.jumper.start_xy_m"),
        "{e}"
    );
    let e = sim([-5.0, 2.0], [11.0, 0.0]).unwrap();
    assert!(matches!(e, PhysicsError::StartOutsideTerrain { .. }), "{e}");
    let e = sim([-5.0, 0.0], [-5.0, 0.5]).unwrap();
    assert!(matches!(e, PhysicsError::StartsOverlap { .. }), "{e}");
    let mut bad = common::physics([-5.0, 2.0], [-5.0, -2.0]);
    bad.jumper.launch_speed_mps = 14.0;
    let e = PhysicsSim::new(&world, &bad, 1).err().unwrap();
    assert!(
        e.to_string()
            .contains("physics.jumper.launch_speed_mps = 14"),
        "{e}"
    );
}

#[test]
fn fixture_files() {
    let valid: PhysicsConfig = toml::from_str(include_str!("fixtures/physics_valid.toml")).unwrap();
    assert_eq!(valid, PhysicsConfig::default());
    let invalid: PhysicsConfig =
        toml::from_str(include_str!("fixtures/physics_invalid_launch.toml")).unwrap();
    let e = invalid.validate().unwrap_err().to_string();
    assert!(
        e.starts_with("physics.jumper.launch_speed_mps = 14 is out of range: allowed [0.5, 12]"),
        "{e}"
    );
}
