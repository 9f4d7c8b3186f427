//! Shared helpers of the integration tests.
#![allow(dead_code)]

use hopnav_world::WorldConfig;
use hopnav_world::config::MarkerConfig;
use hopnav_world::raster::RenderConfig;

/// The default world on `size_x_m × size_y_m` of terrain with `golombek_k` of rock cover.
pub fn sized_world(size_x_m: f64, size_y_m: f64, golombek_k: f64) -> WorldConfig {
    let mut cfg = WorldConfig::default();
    cfg.terrain.size_x_m = size_x_m;
    cfg.terrain.size_y_m = size_y_m;
    cfg.rocks.golombek_k = golombek_k;
    cfg
}

/// A small textured world (16 m, coarse texture) that builds fast in debug builds.
pub fn small_world(seed: u64) -> WorldConfig {
    let mut cfg = WorldConfig {
        seed,
        ..WorldConfig::default()
    };
    cfg.terrain.size_x_m = 16.0;
    cfg.terrain.size_y_m = 16.0;
    cfg.craters.count = 2;
    cfg.craters.diameter_max_m = 4.0;
    cfg.texture.texel_m = 0.04;
    cfg
}

/// A flat, uniform (albedo 100 DN), rock-free world with the given markers.
pub fn flat_world(markers: Vec<MarkerConfig>) -> WorldConfig {
    let mut cfg = small_world(1);
    cfg.terrain.relief_amplitude_m = 0.0;
    cfg.craters.count = 0;
    cfg.rocks.golombek_k = 0.0;
    cfg.texture.albedo_dn = 100.0;
    cfg.texture.macro_contrast = 0.0;
    cfg.texture.detail_contrast = 0.0;
    cfg.texture.pebble_density_per_m2 = 0.0;
    cfg.texture.bump_amplitude_m = 0.0;
    cfg.markers = markers;
    cfg
}

/// Noise-free rendering with a dark sky.
pub fn clean_render() -> RenderConfig {
    RenderConfig {
        noise_sigma_dn: 0.0,
        sky_dn: 20,
        ..RenderConfig::default()
    }
}

/// Centroid of the pixels equal to `value` within `radius` px of `near`.
pub fn centroid(
    img: &[u8],
    w: usize,
    h: usize,
    value: u8,
    near: [f64; 2],
    radius: f64,
) -> Option<[f64; 2]> {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0usize);
    for y in 0..h {
        for x in 0..w {
            let (dx, dy) = (x as f64 - near[0], y as f64 - near[1]);
            if img[y * w + x] == value && dx * dx + dy * dy <= radius * radius {
                sx += x as f64;
                sy += y as f64;
                n += 1;
            }
        }
    }
    (n > 0).then(|| [sx / n as f64, sy / n as f64])
}

/// The `[world]` table of the shipped scenario `config/scenarios/NAME.toml` (not validated).
pub fn scenario_world(name: &str) -> WorldConfig {
    let path = format!(
        "{}/../../config/scenarios/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("scenario file");
    let mut table: toml::Table = toml::from_str(&text).expect("scenario is TOML");
    let world = table.remove("world").expect("scenario has a [world] table");
    world.try_into().expect("valid world table")
}
