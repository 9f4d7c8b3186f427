//! Configuration: defaults and shipped scenarios validate; bad values name their key.

mod common;

use hopnav_world::camera::CameraConfig;
use hopnav_world::raster::{RenderConfig, Renderer};
use hopnav_world::{ConfigError, World, WorldConfig};

fn err(cfg: &WorldConfig) -> String {
    cfg.validate().unwrap_err().to_string()
}

#[test]
fn defaults_meet_the_issue() {
    let cfg = WorldConfig::default();
    cfg.validate().unwrap();
    assert!(cfg.terrain.size_x_m >= 64.0 && cfg.terrain.size_y_m >= 64.0);
    assert!(cfg.terrain.spacing_m <= 0.25);
    assert_eq!(cfg.rocks.golombek_k, 0.07);
    assert_eq!(cfg.craters.depth_ratio, 0.2);
}

#[test]
fn bad_values_name_the_key_and_range() {
    let mut c = WorldConfig::default();
    c.terrain.spacing_m = 2.0;
    assert_eq!(err(&c), "terrain.spacing_m must be in (0, 1], got 2");
    let mut c = WorldConfig::default();
    c.rocks.golombek_k = -0.1;
    assert_eq!(err(&c), "rocks.golombek_k must be in [0, 0.5], got -0.1");
    let mut c = WorldConfig::default();
    c.craters.diameter_max_m = 1.0;
    assert_eq!(
        err(&c),
        "craters.diameter_max_m must be >= 1.5 (diameter_min_m)"
    );
    let mut c = WorldConfig::default();
    c.terrain.relief_gain = f64::NAN;
    assert!(err(&c).starts_with("terrain.relief_gain must be in [0, 1]"));
    let mut c = WorldConfig::default();
    c.texture.texel_m = 0.005;
    assert!(
        err(&c).starts_with("texture.texel_m must be >= 0.015625"),
        "{}",
        err(&c)
    );
    let mut c = WorldConfig::default();
    c.scenario.goal_m = Some([40.0, 0.0]);
    assert_eq!(err(&c), "scenario.goal_m[0] must be in [-32, 32], got 40");
    let mut c = WorldConfig::default();
    c.rocks.clusters.push(Default::default());
    c.rocks.clusters.push(Default::default());
    c.rocks.clusters[1].diameter_min_m = 0.0;
    assert_eq!(
        err(&c),
        "rocks.clusters[1].diameter_min_m must be in [0.02, 10], got 0"
    );
    assert!(matches!(
        World::generate(&c),
        Err(hopnav_world::WorldError::InvalidConfig(
            ConfigError::OutOfRange { .. }
        ))
    ));
}

#[test]
fn camera_and_render_config_errors_name_the_key() {
    let r = RenderConfig::default();
    let e = Renderer::new(
        &CameraConfig {
            hfov_rad: -0.8,
            ..Default::default()
        },
        &r,
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "camera.hfov_rad must be in (0, 3], got -0.8");
    let e = Renderer::with_prefix(
        &CameraConfig {
            height_px: 0,
            ..Default::default()
        },
        &r,
        "camera.rover",
        "render",
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "camera.rover.height_px must be in [1, 8192], got 0"
    );
    let bad = RenderConfig {
        noise_sigma_dn: -1.0,
        ..Default::default()
    };
    let e = Renderer::new(&CameraConfig::default(), &bad).unwrap_err();
    assert_eq!(
        e.to_string(),
        "render.noise_sigma_dn must be in [0, 64], got -1"
    );
}

#[test]
fn toml_partial_files_and_typos() {
    let cfg: WorldConfig = toml::from_str("seed = 9\n[rocks]\ngolombek_k = 0.16\n").unwrap();
    assert_eq!(cfg.seed, 9);
    assert_eq!(cfg.rocks.golombek_k, 0.16);
    assert_eq!(cfg.terrain, WorldConfig::default().terrain);
    let typo = toml::from_str::<WorldConfig>("[terrain]\nspacing = 0.1\n").unwrap_err();
    assert!(typo.to_string().contains("spacing"), "{typo}");
}

#[test]
fn shipped_scenarios_validate() {
    for name in ["default", "rocky", "fig6"] {
        let cfg = common::scenario_world(name);
        cfg.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    let default = common::scenario_world("default");
    assert_eq!(
        default,
        WorldConfig::default(),
        "default.toml must equal the built-in defaults"
    );
    let fig6 = common::scenario_world("fig6");
    assert_eq!(fig6.scenario.start_m, Some([-12.0, 0.0]));
    assert_eq!(fig6.rocks.clusters.len(), 1);
}
