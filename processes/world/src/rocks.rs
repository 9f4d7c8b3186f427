//! Rocks: Golombek size-frequency sampling, clusters and explicit rocks.
//!
//! Golombek & Rapp (1997): the cumulative fractional area covered by rocks of diameter ≥ D is
//! `F(D) = k·exp(−q·D)` with `q = 1.79 + 0.152/k`. The number density per unit diameter follows
//! as `n(D) = −F′(D) / (π D²/4)`; diameters are drawn from it by inverse transform (tabulated CDF)
//! until the covered area reaches `(F(D_min) − F(D_max)) × map area`.
//!
//! Each rock is a lumpy half-ellipsoid: horizontal semi-axes `a·b = (D/2)²` (so the footprint
//! area is `πD²/4`), vertical semi-axis = height ≈ D/2, resting on the lowest terrain point under
//! its footprint.
//!
//! ```
//! use hopnav_world::rocks::Golombek;
//! let g = Golombek::new(0.07);
//! assert!((g.q() - (1.79 + 0.152 / 0.07)).abs() < 1e-12);
//! assert!((g.cumulative_area_fraction(0.0) - 0.07).abs() < 1e-12);
//! ```

use crate::boulder_fields::{field_boulders, place_fields};
use crate::config::{RockClusterConfig, RockConfig, ScenarioConfig};
use crate::rng::{Rng, mix64};
use crate::terrain::Heightfield;

const GOLOMBEK_STREAM: u64 = 0x676f_6c6f_6d62; // "golomb"
const CLUSTER_STREAM: u64 = 0x636c_7573_7465; // "cluste"
const SHAPE_STREAM: u64 = 0x7368_6170_6573; // "shapes"
/// Resolution of the tabulated inverse CDF.
const CDF_SAMPLES: usize = 4096;
/// Placement attempts per rock before it is dropped.
const PLACE_ATTEMPTS: usize = 64;

/// Where a rock came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RockSource {
    /// Background population from the Golombek model.
    Golombek,
    /// Cluster with this index in `rocks.clusters`.
    Cluster(u32),
    /// Entry with this index in `rocks.explicit`.
    Explicit(u32),
    /// Boulder field with this index (see [`crate::boulder_fields`]).
    BoulderField(u32),
    /// Cul-de-sac with this index (see [`crate::landforms::cul_de_sac`]).
    CulDeSac(u32),
    /// The corridor field (see [`crate::landforms::corridor_field`]).
    CorridorField,
}

/// One rock resting on the terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rock {
    /// Centre of the base (x, y) and the ground height it rests on (z), metres.
    pub center_m: [f64; 3],
    /// Equivalent-area diameter D, metres (footprint area `πD²/4`).
    pub diameter_m: f64,
    /// Height of the top above `center_m[2]`, metres.
    pub height_m: f64,
    /// Ellipsoid semi-axes `[a, b, c]` along the rock's yawed x, y and world z, metres
    /// (`c == height_m`).
    pub half_extents_m: [f64; 3],
    /// Rotation of the footprint about world z, radians.
    pub yaw_rad: f64,
    /// Seed of the rock's lumpy shape (see [`rock_mesh`](crate::mesh::rock_mesh)).
    pub shape_seed: u64,
    /// Origin of the rock.
    pub source: RockSource,
}

impl Rock {
    /// Horizontal bounding radius, metres.
    pub fn bounding_radius_m(&self) -> f64 {
        self.half_extents_m[0].max(self.half_extents_m[1])
    }

    /// Footprint area, square metres.
    pub fn footprint_area_m2(&self) -> f64 {
        std::f64::consts::PI * self.half_extents_m[0] * self.half_extents_m[1]
    }

    /// World z of the top, metres.
    pub fn top_z_m(&self) -> f64 {
        self.center_m[2] + self.height_m
    }
}

/// The Golombek cumulative-area model for one abundance `k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Golombek {
    k: f64,
    q: f64,
}

impl Golombek {
    /// Model for total rock abundance `k` (> 0).
    pub fn new(k: f64) -> Self {
        let k = k.max(1e-9);
        Self {
            k,
            q: 1.79 + 0.152 / k,
        }
    }

    /// Abundance k.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// Decay constant q, 1/metres.
    pub fn q(&self) -> f64 {
        self.q
    }

    /// F(D): fraction of the area covered by rocks of diameter ≥ `d_m`.
    pub fn cumulative_area_fraction(&self, d_m: f64) -> f64 {
        self.k * (-self.q * d_m).exp()
    }

    /// Rocks per square metre per metre of diameter at `d_m`.
    pub fn number_density(&self, d_m: f64) -> f64 {
        let area = std::f64::consts::PI * d_m * d_m / 4.0;
        self.k * self.q * (-self.q * d_m).exp() / area
    }
}

/// Tabulated inverse CDF of the rock-number distribution on `[d_min, d_max]`.
struct DiameterSampler {
    d_m: Vec<f64>,
    cdf: Vec<f64>,
}

impl DiameterSampler {
    fn new(model: &Golombek, d_min_m: f64, d_max_m: f64) -> Self {
        let n = CDF_SAMPLES;
        let d_m: Vec<f64> = (0..n)
            .map(|i| d_min_m + (d_max_m - d_min_m) * i as f64 / (n - 1) as f64)
            .collect();
        let mut cdf = Vec::with_capacity(n);
        let mut acc = 0.0;
        cdf.push(0.0);
        for w in d_m.windows(2) {
            acc += 0.5 * (model.number_density(w[0]) + model.number_density(w[1])) * (w[1] - w[0]);
            cdf.push(acc);
        }
        Self { d_m, cdf }
    }

    fn sample(&self, u: f64) -> f64 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        if total <= 0.0 || self.d_m.len() < 2 {
            return self.d_m.first().copied().unwrap_or(0.0);
        }
        let target = u * total;
        let idx = self
            .cdf
            .partition_point(|&c| c <= target)
            .clamp(1, self.cdf.len() - 1);
        let (c0, c1) = (self.cdf[idx - 1], self.cdf[idx]);
        let t = if c1 > c0 {
            (target - c0) / (c1 - c0)
        } else {
            0.0
        };
        self.d_m[idx - 1] + t * (self.d_m[idx] - self.d_m[idx - 1])
    }
}

/// Builds one rock of diameter `d_m` at (x, y), resting on the terrain.
pub(crate) fn make_rock(
    hf: &Heightfield,
    rng: &mut Rng,
    xy: [f64; 2],
    d_m: f64,
    height_m: f64,
    shape_seed: u64,
    source: RockSource,
) -> Rock {
    let aspect = rng.uniform(0.65, 1.0);
    let r = d_m / 2.0;
    let a = r / aspect.sqrt();
    let b = r * aspect.sqrt();
    let yaw_rad = rng.uniform(0.0, std::f64::consts::PI);
    // Rest on the lowest ground under the footprint so no edge floats.
    let (s, c) = yaw_rad.sin_cos();
    let mut z = hf.height_at(xy[0], xy[1]);
    for k in 0..8 {
        let ang = k as f64 * std::f64::consts::FRAC_PI_4;
        let (lx, ly) = (a * ang.cos(), b * ang.sin());
        z = z.min(hf.height_at(xy[0] + c * lx - s * ly, xy[1] + s * lx + c * ly));
    }
    Rock {
        center_m: [xy[0], xy[1], z],
        diameter_m: d_m,
        height_m,
        half_extents_m: [a, b, height_m],
        yaw_rad,
        shape_seed,
        source,
    }
}

/// True when a disc of radius `rock_r` at `xy` stays more than `radius_m` from every point.
pub(crate) fn clear_of(points: &[[f64; 2]], radius_m: f64, xy: [f64; 2], rock_r: f64) -> bool {
    points.iter().all(|p| {
        let (dx, dy) = (p[0] - xy[0], p[1] - xy[1]);
        (dx * dx + dy * dy).sqrt() > radius_m + rock_r
    })
}

/// Background rocks by the Golombek model over the whole heightfield.
///
/// Rocks keep `scenario.clear_radius_m` away from the scenario points; the target area is
/// computed over the map minus those discs.
pub fn sample_golombek_rocks(
    seed: u64,
    cfg: &RockConfig,
    scenario: &ScenarioConfig,
    hf: &Heightfield,
) -> Vec<Rock> {
    if cfg.golombek_k <= 0.0 {
        return Vec::new();
    }
    let model = Golombek::new(cfg.golombek_k);
    let sampler = DiameterSampler::new(&model, cfg.diameter_min_m, cfg.diameter_max_m);
    let mut rng = Rng::new(seed, GOLOMBEK_STREAM);
    let [ox, oy] = hf.origin_m();
    let [ex, ey] = hf.extent_m();
    let clear: Vec<[f64; 2]> = scenario.clear_points().collect();
    let clear_area: f64 = clear.len() as f64
        * std::f64::consts::PI
        * scenario.clear_radius_m
        * scenario.clear_radius_m;
    let usable_m2 = (ex * ey - clear_area).max(0.0);
    let fraction = model.cumulative_area_fraction(cfg.diameter_min_m)
        - model.cumulative_area_fraction(cfg.diameter_max_m);
    let target_m2 = fraction * usable_m2;
    let mut rocks = Vec::new();
    let mut covered_m2 = 0.0;
    let mut failures = 0usize;
    while covered_m2 < target_m2 && failures < 1000 {
        let d = sampler.sample(rng.next_f64());
        let h = cfg.height_ratio * d * rng.uniform(0.85, 1.15);
        let r = d / 2.0;
        let mut placed = None;
        for _ in 0..PLACE_ATTEMPTS {
            let xy = [ox + rng.uniform(r, ex - r), oy + rng.uniform(r, ey - r)];
            if clear_of(&clear, scenario.clear_radius_m, xy, r) {
                placed = Some(xy);
                break;
            }
        }
        let Some(xy) = placed else {
            failures += 1;
            continue;
        };
        let shape_seed = mix64(seed ^ SHAPE_STREAM ^ (rocks.len() as u64).wrapping_mul(0x9E37));
        let rock = make_rock(hf, &mut rng, xy, d, h, shape_seed, RockSource::Golombek);
        covered_m2 += rock.footprint_area_m2();
        rocks.push(rock);
    }
    rocks
}

/// Rocks of one cluster: uniform in the ellipse, diameters uniform in the range.
pub fn sample_cluster(
    seed: u64,
    index: u32,
    cfg: &RockClusterConfig,
    hf: &Heightfield,
) -> Vec<Rock> {
    let mut rng = Rng::new(seed, CLUSTER_STREAM ^ (u64::from(index) << 48));
    (0..cfg.count)
        .map(|n| {
            // Uniform point in the unit disc, stretched to the ellipse.
            let rad = rng.next_f64().sqrt();
            let ang = rng.uniform(0.0, std::f64::consts::TAU);
            let xy = [
                cfg.center_m[0] + cfg.half_extents_m[0] * rad * ang.cos(),
                cfg.center_m[1] + cfg.half_extents_m[1] * rad * ang.sin(),
            ];
            let d = rng.uniform(cfg.diameter_min_m, cfg.diameter_max_m);
            let h = cfg.height_ratio * d * rng.uniform(0.9, 1.1);
            let shape_seed = mix64(seed ^ CLUSTER_STREAM ^ (u64::from(index) << 32) ^ u64::from(n));
            make_rock(
                hf,
                &mut rng,
                xy,
                d,
                h,
                shape_seed,
                RockSource::Cluster(index),
            )
        })
        .collect()
}

/// All rocks of the configuration: background, clusters, then explicit rocks.
pub fn generate_rocks(
    seed: u64,
    cfg: &RockConfig,
    scenario: &ScenarioConfig,
    hf: &Heightfield,
) -> Vec<Rock> {
    let mut rocks = sample_golombek_rocks(seed, cfg, scenario, hf);
    for (i, c) in cfg.clusters.iter().enumerate() {
        rocks.extend(sample_cluster(seed, i as u32, c, hf));
    }
    if let (Some(start_m), Some(goal_m)) = (scenario.start_m, scenario.goal_m) {
        let fields = place_fields(seed, &cfg.boulder_fields, start_m, goal_m);
        let mut rng = Rng::new(seed, SHAPE_STREAM ^ 0xB0);
        for (index, field) in (0u32..).zip(&fields) {
            for (n, boulder) in
                (0u64..).zip(field_boulders(seed, index, &cfg.boulder_fields, field))
            {
                let shape_seed = mix64(seed ^ SHAPE_STREAM ^ (u64::from(index) << 32) ^ n ^ 0xB0);
                rocks.push(make_rock(
                    hf,
                    &mut rng,
                    boulder.center_m,
                    boulder.diameter_m,
                    boulder.height_m,
                    shape_seed,
                    RockSource::BoulderField(index),
                ));
            }
        }
    }
    let mut rng = Rng::new(seed, SHAPE_STREAM);
    for (i, e) in cfg.explicit.iter().enumerate() {
        let h = e.height_m.unwrap_or(cfg.height_ratio * e.diameter_m);
        let shape_seed = mix64(seed ^ SHAPE_STREAM ^ (i as u64).wrapping_add(0xE1));
        rocks.push(make_rock(
            hf,
            &mut rng,
            e.center_m,
            e.diameter_m,
            h,
            shape_seed,
            RockSource::Explicit(i as u32),
        ));
    }
    rocks
}
