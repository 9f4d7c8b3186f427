//! Where the mapper's tall points and fitted rocks stand against the true rocks, over the
//! final maps of finished runs (a diagnostic for the traversability study; it reads each run
//! folder's `config.toml`, `mapper_snapshot.bin` and `rover_track.csv`).
//!
//! ```sh
//! cargo run --release -p hopnav-eval --example rock_points_vs_truth -- runs/eval-traversability/2026*/
//! ```
//!
//! Prints, for the points the mapper keeps as taller than 0.1 m, how many lie more than
//! 0.1 m outside every rock's footprint (bare ground read as a rock); and for the fitted rocks
//! on unclimbable rocks, the offset of their centre from the true one (along and across the
//! view from the nearest point of the track), their radius against the true one, and how far
//! the true footprint stands beyond them. Footprints are the rocks' half-extent ellipses.

use std::error::Error;
use std::path::Path;

use hopnav_eval::MissionTruth;
use hopnav_eval::traversability::RockEllipse;
use hopnav_mapper::{config::grid_geometry, map::FeatureMap, snapshot};

/// Per-run samples.
#[derive(Default)]
struct Samples {
    /// Tall points: gap to the nearest rock's footprint, metres.
    point_gaps_m: Vec<f64>,
    /// Fitted rocks on unclimbable rocks: [along the view, |across|, radius error, true
    /// footprint beyond the fitted base], metres.
    domes: Vec<[f64; 4]>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut samples = Samples::default();
    let runs: Vec<String> = std::env::args().skip(1).collect();
    if runs.is_empty() {
        return Err("usage: rock_points_vs_truth RUN_DIR...".into());
    }
    for run in &runs {
        read_run(Path::new(run), &mut samples).map_err(|error| format!("{run}: {error}"))?;
    }
    let gaps = &samples.point_gaps_m;
    let share = |limit_m: f64| {
        100.0 * gaps.iter().filter(|gap| **gap > limit_m).count() as f64 / gaps.len().max(1) as f64
    };
    println!("{} runs", runs.len());
    let between = |lo: f64, hi: f64| gaps.iter().filter(|gap| **gap > lo && **gap <= hi).count();
    let off = between(0.1, f64::INFINITY).max(1) as f64;
    println!(
        "points taller than 0.1 m: {}; beyond every rock by > 0.1 m: {:.1} %, > 0.2 m: {:.1} %",
        gaps.len(),
        share(0.1),
        share(0.2)
    );
    println!(
        "  of those beyond 0.1 m, gap 0.1-0.3 m: {:.0} %, 0.3-0.6 m: {:.0} %, farther: {:.0} %",
        100.0 * between(0.1, 0.3) as f64 / off,
        100.0 * between(0.3, 0.6) as f64 / off,
        100.0 * between(0.6, f64::INFINITY) as f64 / off
    );
    let column = |k: usize| spread(samples.domes.iter().map(|dome| dome[k]).collect());
    println!("fitted rocks on unclimbable rocks: {}", samples.domes.len());
    println!(
        "  centre offset along the view (+ beyond the rock), p10 / p50 / p90: {}",
        column(0)
    );
    println!(
        "  centre offset across the view, p10 / p50 / p90: {}",
        column(1)
    );
    println!(
        "  base radius minus the true one, p10 / p50 / p90: {}",
        column(2)
    );
    println!(
        "  true footprint beyond the fitted base, p10 / p50 / p90: {}",
        column(3)
    );
    Ok(())
}

fn read_run(dir: &Path, samples: &mut Samples) -> Result<(), Box<dyn Error>> {
    let config = hopnav_config::load_file(&dir.join("config.toml"))?;
    let truth = MissionTruth::from_config(&config).ok_or("invalid world")?;
    let mapper = truth.mapper.clone().ok_or("invalid [mapper]")?;
    let mut map = FeatureMap::new(&mapper, grid_geometry(&mapper)?);
    snapshot::restore_file(&mut map, &dir.join("mapper_snapshot.bin"))?;
    map.update();
    let world_config: hopnav_world::WorldConfig = hopnav_config::parse_section(&config, "world")?;
    let world = hopnav_world::World::generate(&world_config)?;
    let rocks: Vec<RockEllipse> = world
        .rocks()
        .iter()
        .map(|rock| RockEllipse {
            center_m: [rock.center_m[0], rock.center_m[1]],
            semi_axes_m: [rock.half_extents_m[0], rock.half_extents_m[1]],
            yaw_rad: rock.yaw_rad,
            height_m: rock.height_m,
        })
        .collect();
    let track = read_track(&dir.join("rover_track.csv"))?;
    let domes = map
        .domes()
        .ok_or("the map fits no rocks (obstacle model)")?;
    let mut stored = Vec::new();
    domes.stored_points_into(&mut stored);
    for (_, cell) in &stored {
        for point in cell.as_slice().iter().filter(|point| point.height_m > 0.1) {
            let xy = [f64::from(point.xy_m[0]), f64::from(point.xy_m[1])];
            let gap_m = rocks
                .iter()
                .map(|rock| rock.gap_m(xy))
                .fold(f64::MAX, f64::min);
            samples.point_gaps_m.push(gap_m);
        }
    }
    for dome in domes.rocks() {
        let centre = [f64::from(dome.centre_m[0]), f64::from(dome.centre_m[1])];
        let Some(rock) = rocks
            .iter()
            .filter(|rock| rock.height_m > truth.climbable_height_m && rock.gap_m(centre) < 0.2)
            .min_by(|a, b| a.gap_m(centre).total_cmp(&b.gap_m(centre)))
        else {
            continue;
        };
        let base_m = f64::from(dome.base_radius_m);
        let Some(view) = nearest(&track, rock.center_m) else {
            continue;
        };
        let (ux, uy) = (rock.center_m[0] - view[0], rock.center_m[1] - view[1]);
        let length = ux.hypot(uy).max(1e-9);
        let (dx, dy) = (centre[0] - rock.center_m[0], centre[1] - rock.center_m[1]);
        let (sin, cos) = rock.yaw_rad.sin_cos();
        let beyond_m = (0..64)
            .map(|k| {
                let t = f64::from(k) * std::f64::consts::TAU / 64.0;
                let (u, v) = (rock.semi_axes_m[0] * t.cos(), rock.semi_axes_m[1] * t.sin());
                let p = [
                    rock.center_m[0] + u * cos - v * sin,
                    rock.center_m[1] + u * sin + v * cos,
                ];
                (p[0] - centre[0]).hypot(p[1] - centre[1]) - base_m
            })
            .fold(0.0, f64::max);
        samples.domes.push([
            (dx * ux + dy * uy) / length,
            (dy * ux - dx * uy).abs() / length,
            base_m - (rock.semi_axes_m[0] * rock.semi_axes_m[1]).sqrt(),
            beyond_m,
        ]);
    }
    Ok(())
}

fn read_track(path: &Path) -> Result<Vec<[f64; 2]>, Box<dyn Error>> {
    let text = std::fs::read_to_string(path)?;
    let mut track = Vec::new();
    for line in text.lines().skip(1) {
        let mut values = line.split(',').map(str::parse::<f64>);
        match (values.next(), values.next()) {
            (Some(Ok(x)), Some(Ok(y))) => track.push([x, y]),
            _ => return Err(format!("{}: bad line {line:?}", path.display()).into()),
        }
    }
    Ok(track)
}

fn nearest(track: &[[f64; 2]], point: [f64; 2]) -> Option<[f64; 2]> {
    let distance = |p: &[f64; 2]| (p[0] - point[0]).hypot(p[1] - point[1]);
    track
        .iter()
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .copied()
}

fn spread(mut values: Vec<f64>) -> String {
    values.sort_by(f64::total_cmp);
    if values.is_empty() {
        return "-".to_owned();
    }
    let at = |q: usize| values[(values.len() - 1) * q / 10];
    format!("{:.3} / {:.3} / {:.3} m", at(1), at(5), at(9))
}
