//! `hopnav compare`'s launches: every mission of every run set, seed by seed, and each set's
//! map figure (its first seed with both modes).

use std::path::Path;

use hopnav_config::{HopnavConfig, MissionMode};
use hopnav_eval::figure::mission_figure;
use hopnav_eval::{MissionTruth, TruthEvaluator};
use hopnav_metrics::map_plot::{MapFigure, Track, write_map_png};
use hopnav_supervisor::{LaunchError, LaunchOptions, launch};

use crate::compare_rows::{CompareRow, RunSet};
use crate::compare_variant::{RunSetPlan, mission_config};
use crate::registry;

/// What the missions of one run set produced on one seed, for its map figure.
#[derive(Default)]
struct SeedFigure {
    /// The cooperative mission's figure (the world's rocks, the jumper's and rover's tracks).
    cooperative: Option<MapFigure>,
    /// The rover-only rover's track.
    rover_only_track: Option<Vec<(f64, f64)>>,
}

/// One finished launch.
struct Launched {
    row: CompareRow,
    /// Ctrl-C (or SIGTERM) stopped it.
    interrupted: bool,
    figure: SeedFigure,
}

/// Launches every mission, seed by seed (a seed's base runs, then its variant runs), and
/// writes each set's map figure: its first seed with both modes, the cooperative mission with
/// the world's rocks and the rover-only rover's track. Returns the sets and whether Ctrl-C
/// (or SIGTERM) stopped the comparison.
pub fn run_missions(
    seeds: &[(u64, f64)],
    frames: u64,
    plans: &[RunSetPlan],
    executable: &Path,
) -> (Vec<RunSet>, bool) {
    let total = plans.iter().map(|plan| plan.modes.len()).sum::<usize>() * seeds.len();
    let mut sets: Vec<RunSet> = plans
        .iter()
        .map(|plan| RunSet {
            label: plan.label.clone(),
            rows: Vec::new(),
        })
        .collect();
    let mut figure_written = vec![false; plans.len()];
    let mut launched = 0;
    for &(seed, k) in seeds {
        for (plan_index, plan) in plans.iter().enumerate() {
            let mut figure = SeedFigure::default();
            for &mode in &plan.modes {
                launched += 1;
                let set_name = if plan_index == 0 {
                    String::new()
                } else {
                    format!("{} ", plan.label)
                };
                eprintln!(
                    "[{launched}/{total}] {set_name}seed {seed}, k {k:.3}, {} ...",
                    mode.name()
                );
                let config = mission_config(plan, frames, seed, k, mode);
                let wants_figure = mode == MissionMode::Cooperative && !figure_written[plan_index];
                let Some(done) = launch_mission(config, executable, (seed, k), mode, wants_figure)
                else {
                    return (sets, true);
                };
                sets[plan_index].rows.push(done.row);
                figure.cooperative = figure.cooperative.or(done.figure.cooperative);
                figure.rover_only_track = figure.rover_only_track.or(done.figure.rover_only_track);
                if done.interrupted {
                    // Ctrl-C stops the whole comparison, not just this launch: the tables
                    // and files keep what finished.
                    return (sets, true);
                }
            }
            if !figure_written[plan_index]
                && let (Some(cooperative), Some(track)) =
                    (figure.cooperative, figure.rover_only_track)
            {
                let label = (plan_index > 0).then_some(plan.label.as_str());
                figure_written[plan_index] =
                    write_compare_figure(&plan.out, label, (seed, k), cooperative, track);
            }
        }
    }
    (sets, false)
}

/// Launches one mission on terrain `(seed, k)` and prints its report; `None` when Ctrl-C
/// stopped it before it ran. With `wants_figure`, a cooperative mission also draws its map
/// figure.
fn launch_mission(
    config: HopnavConfig,
    executable: &Path,
    (seed, k): (u64, f64),
    mode: MissionMode,
    wants_figure: bool,
) -> Option<Launched> {
    let figure_config = wants_figure.then(|| config.clone());
    let options = LaunchOptions {
        config,
        executable: executable.to_owned(),
        known_processes: registry::names(),
        run_id: None,
        show_status: false,
        evaluator: Some(std::sync::Arc::new(TruthEvaluator)),
    };
    let mut done = Launched {
        row: CompareRow {
            seed,
            golombek_k: k,
            mode: mode.name().to_owned(),
            run_dir: String::new(),
            runtime_ok: false,
            mission: None,
        },
        interrupted: false,
        figure: SeedFigure::default(),
    };
    let outcome = match launch(options) {
        Err(LaunchError::Interrupted) => return None,
        Err(error) => {
            eprintln!("  launch failed: {error}");
            return Some(done);
        }
        Ok(outcome) => outcome,
    };
    if let Some(mission) = &outcome.report.mission {
        let _ = mission.print(&mut std::io::stderr());
    }
    for line in &outcome.report.evaluation_summary {
        eprintln!("{line}");
    }
    let record = outcome.mission_record.as_ref();
    match mode {
        MissionMode::Cooperative => {
            let truth = figure_config.as_ref().and_then(MissionTruth::from_config);
            done.figure.cooperative = record
                .zip(truth.as_ref())
                .and_then(|(record, truth)| mission_figure("", truth, record));
        }
        MissionMode::RoverOnly => {
            done.figure.rover_only_track = record.map(|record| record.rover_track_m.clone());
        }
    }
    done.row.run_dir = outcome.run_dir.display().to_string();
    done.row.runtime_ok = outcome.success;
    done.row.mission = outcome.report.mission.clone();
    done.interrupted = outcome.interrupted;
    Some(done)
}

/// Writes a set's `compare_map.png`: the cooperative mission's figure with the rover-only
/// rover's track added. `variant` names a set other than the base in the title. Returns
/// whether the figure was written.
fn write_compare_figure(
    out: &Path,
    variant: Option<&str>,
    (seed, k): (u64, f64),
    mut figure: MapFigure,
    rover_only_track: Vec<(f64, f64)>,
) -> bool {
    figure.title = format!("cooperative vs rover-only, seed {seed}, k {k:.3}");
    if let Some(label) = variant {
        figure.title.push_str(&format!(" ({label})"));
    }
    figure.tracks.insert(
        1,
        Track {
            label: "rover (rover-only)".into(),
            points_m: rover_only_track,
            rgb: (120, 0, 160),
            markers_only: false,
        },
    );
    let path = out.join("compare_map.png");
    match write_map_png(&path, &figure) {
        Ok(()) => {
            eprintln!("map figure: {}", path.display());
            true
        }
        Err(error) => {
            eprintln!("warning: {error}");
            false
        }
    }
}
