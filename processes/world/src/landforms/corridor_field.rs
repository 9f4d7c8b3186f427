//! A corridor field: a band across A–B, and across the whole terrain, packed with boulders
//! too close for the rover to pass between, crossed by a few clear corridors that bend once
//! and enter and leave well to the side of the A–B line. From the band's edge the rover sees
//! a wall of boulders; only a hop shows where the corridors run.
//!
//! ```
//! use hopnav_world::config::CorridorFieldConfig;
//! use hopnav_world::landforms::corridor_field::place_corridors;
//! let config = CorridorFieldConfig { depth_m: 20.0, ..CorridorFieldConfig::default() };
//! let corridors = place_corridors(3, &config);
//! assert_eq!(corridors.len(), 2);
//! // Every corridor keeps at least 6 m to the side of the A-B line.
//! assert!(corridors.iter().all(|c| c.sides_m.iter().all(|side| side.abs() >= 6.0)));
//! ```

use super::AbFrame;
use crate::boulder_fields::Boulder;
use crate::config::CorridorFieldConfig;
use crate::rng::Rng;

const CORRIDOR_STREAM: u64 = 0x636f_7272_6964; // "corrid"

/// At most this many boulders in a field (the config's check keeps well under it).
pub const MAX_FIELD_BOULDERS: usize = 200_000;

/// One clear corridor, in A–B coordinates: its centre line runs from the band's entry to its
/// middle to its exit at these sides of the A–B line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corridor {
    /// Side offsets at the entry, the bend and the exit, metres (left of A–B positive).
    pub sides_m: [f64; 3],
}

/// The band's extent along A–B, metres from A: `[start, end]`.
pub fn band_along_m(config: &CorridorFieldConfig, frame: &AbFrame) -> [f64; 2] {
    let start_m = config.start_fraction * frame.length_m;
    [start_m, start_m + config.depth_m]
}

/// The corridors of the field (none when its depth is 0), alternating sides of A–B.
pub fn place_corridors(seed: u64, config: &CorridorFieldConfig) -> Vec<Corridor> {
    if config.depth_m <= 0.0 {
        return Vec::new();
    }
    let mut rng = Rng::new(seed, CORRIDOR_STREAM);
    let first_side = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
    (0..config.corridors)
        .map(|index| {
            let side = if index % 2 == 0 {
                first_side
            } else {
                -first_side
            };
            let mut offset =
                || side * rng.uniform(config.corridor_offset_min_m, config.corridor_offset_max_m);
            Corridor {
                sides_m: [offset(), offset(), offset()],
            }
        })
        .collect()
}

impl Corridor {
    /// The centre line's corners as `(along, side)`, metres, over the band `[start, end]`
    /// (extended 2 m beyond each edge so no boulder closes its ends).
    pub fn corners(&self, band_m: [f64; 2]) -> [(f64, f64); 3] {
        [
            (band_m[0] - 2.0, self.sides_m[0]),
            (0.5 * (band_m[0] + band_m[1]), self.sides_m[1]),
            (band_m[1] + 2.0, self.sides_m[2]),
        ]
    }

    /// Distance from `(along, side)` to the centre line, metres.
    pub fn distance_m(&self, band_m: [f64; 2], along_m: f64, side_m: f64) -> f64 {
        let corners = self.corners(band_m);
        corners
            .windows(2)
            .map(|pair| segment_distance_m(pair[0], pair[1], (along_m, side_m)))
            .fold(f64::INFINITY, f64::min)
    }
}

fn segment_distance_m(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let length2 = dx * dx + dy * dy;
    let t = if length2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// The field's boulders: a jittered lattice over the band, out to `half_span_m` to either side
/// of A–B, without those that would reach into a corridor; at most [`MAX_FIELD_BOULDERS`].
pub fn field_boulders(
    seed: u64,
    config: &CorridorFieldConfig,
    frame: &AbFrame,
    half_span_m: f64,
    corridors: &[Corridor],
) -> Vec<Boulder> {
    if config.depth_m <= 0.0 {
        return Vec::new();
    }
    let mut rng = Rng::new(seed, CORRIDOR_STREAM ^ 0xF1E1D);
    let band_m = band_along_m(config, frame);
    let spacing_m = config.spacing_m;
    let jitter_m = 0.15 * spacing_m;
    let rows = (config.depth_m / spacing_m).floor() as usize + 1;
    let columns = (2.0 * half_span_m.max(0.0) / spacing_m).floor() as usize + 1;
    let mut boulders = Vec::new();
    for row in 0..rows {
        for column in 0..columns {
            if boulders.len() >= MAX_FIELD_BOULDERS {
                return boulders;
            }
            let along_m = band_m[0] + row as f64 * spacing_m + rng.uniform(-jitter_m, jitter_m);
            let side_m =
                -half_span_m + column as f64 * spacing_m + rng.uniform(-jitter_m, jitter_m);
            let diameter_m = rng.uniform(
                config.boulders.diameter_min_m,
                config.boulders.diameter_max_m,
            );
            let height_m = config.boulders.height_ratio * diameter_m * rng.uniform(0.9, 1.1);
            let clear_m = 0.5 * (config.corridor_width_m + diameter_m);
            if corridors
                .iter()
                .any(|corridor| corridor.distance_m(band_m, along_m, side_m) < clear_m)
            {
                continue;
            }
            boulders.push(Boulder {
                center_m: frame.world_m(along_m, side_m),
                diameter_m,
                height_m,
            });
        }
    }
    boulders
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> CorridorFieldConfig {
        CorridorFieldConfig {
            depth_m: 16.0,
            ..CorridorFieldConfig::default()
        }
    }

    fn frame() -> AbFrame {
        AbFrame::new([-50.0, 0.0], [50.0, 0.0]).expect("frame")
    }

    #[test]
    fn corridors_are_clear_and_the_rest_of_the_band_is_shut() {
        let (config, frame) = (config(), frame());
        for seed in 1..=5 {
            let corridors = place_corridors(seed, &config);
            let boulders = field_boulders(seed, &config, &frame, 32.0, &corridors);
            let band_m = band_along_m(&config, &frame);
            let local: Vec<(f64, f64, f64)> = boulders
                .iter()
                .map(|b| {
                    let (along, side) = frame.local_m(b.center_m);
                    (along, side, 0.5 * b.diameter_m)
                })
                .collect();
            // Along each corridor's centre line no boulder comes within half its width.
            for corridor in &corridors {
                for step in 0..=100 {
                    let along_m = band_m[0] + (band_m[1] - band_m[0]) * f64::from(step) / 100.0;
                    let side_m = (0..=400)
                        .map(|k| -32.0 + 0.16 * f64::from(k))
                        .min_by(|a, b| {
                            corridor
                                .distance_m(band_m, along_m, *a)
                                .total_cmp(&corridor.distance_m(band_m, along_m, *b))
                        })
                        .expect("sides");
                    let nearest_m = local
                        .iter()
                        .map(|&(a, s, r)| (a - along_m).hypot(s - side_m) - r)
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        nearest_m >= 0.5 * config.corridor_width_m - 0.2,
                        "seed {seed}: a boulder {nearest_m} m from a corridor's centre line"
                    );
                }
            }
            // Within 1.5 m of the A–B line the band is shut: a rover 0.8 m wide finds no way
            // across it there (a flood fill over 5 cm cells, each free when the rover's
            // centre there keeps half its width from every boulder).
            assert!(
                !crosses_near_the_line(&local, band_m, 0.4),
                "seed {seed}: a passage"
            );
        }
    }

    /// Whether a disc of `half_width_m` can cross the band `band_m` within 1.5 m of A–B.
    fn crosses_near_the_line(
        boulders: &[(f64, f64, f64)],
        band_m: [f64; 2],
        half_width_m: f64,
    ) -> bool {
        let cell_m = 0.05;
        let (along0_m, side0_m) = (band_m[0] - 1.0, -1.5);
        let rows = ((band_m[1] - band_m[0] + 2.0) / cell_m) as usize;
        let columns = (3.0 / cell_m) as usize;
        let near: Vec<&(f64, f64, f64)> = boulders.iter().filter(|b| b.1.abs() < 5.0).collect();
        let free = |row: usize, column: usize| {
            let (along_m, side_m) = (
                along0_m + (row as f64 + 0.5) * cell_m,
                side0_m + (column as f64 + 0.5) * cell_m,
            );
            near.iter()
                .all(|&&(a, s, r)| (a - along_m).hypot(s - side_m) >= r + half_width_m)
        };
        let mut seen = vec![false; rows * columns];
        let mut queue: Vec<(usize, usize)> = (0..columns)
            .filter(|&c| free(0, c))
            .map(|c| (0, c))
            .collect();
        for &(row, column) in &queue {
            seen[row * columns + column] = true;
        }
        while let Some((row, column)) = queue.pop() {
            if row + 1 == rows {
                return true;
            }
            let neighbours = [
                (row + 1, column),
                (row.wrapping_sub(1), column),
                (row, column + 1),
                (row, column.wrapping_sub(1)),
            ];
            for (r, c) in neighbours {
                if r < rows && c < columns && !seen[r * columns + c] && free(r, c) {
                    seen[r * columns + c] = true;
                    queue.push((r, c));
                }
            }
        }
        false
    }

    #[test]
    fn no_depth_no_field() {
        let config = CorridorFieldConfig::default();
        assert!(place_corridors(1, &config).is_empty());
        assert!(field_boulders(1, &config, &frame(), 30.0, &[]).is_empty());
    }
}
