//! The outputs of one set of `hopnav compare` runs: the row table on stdout, `compare.csv`
//! and `compare.json` (their columns and values are what scripts read: keep them).

use std::io::Write as _;
use std::path::Path;
use std::process::ExitCode;

use crate::compare_pair::{built_map_m, full_knowledge_m};
use crate::compare_rows::CompareRow;

/// Prints a row per mission.
pub fn print_table(rows: &[CompareRow]) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "\n{:>5} {:>6} {:<12} {:>8} {:>9} {:>9} {:>9} {:>8} {:>7} {:>11} {:>7} {:>6} {:>10}",
        "seed",
        "k",
        "mode",
        "reached",
        "path m",
        "best m",
        "built m",
        "replans",
        "routes",
        "expansions",
        "time s",
        "hops",
        "collisions"
    );
    for row in rows {
        match &row.mission {
            Some(mission) => {
                let _ = writeln!(
                    out,
                    "{:>5} {:>6.3} {:<12} {:>8} {:>9.1} {:>9} {:>9} {:>8} {:>7} {:>11} {:>7.1} {:>6} {:>10}",
                    row.seed,
                    row.golombek_k,
                    row.mode,
                    if mission.goal_reached { "yes" } else { "no" },
                    mission.executed_path_m,
                    fmt_opt(full_knowledge_m(mission)),
                    fmt_opt(built_map_m(mission)),
                    mission.replans,
                    mission.route_changes,
                    mission.node_expansions,
                    mission.mission_time_s,
                    mission.jumper_hops,
                    mission.collisions
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "{:>5} {:>6.3} {:<12} launch failed",
                    row.seed, row.golombek_k, row.mode
                );
            }
        }
    }
}
fn fmt_opt(value: Option<f64>) -> String {
    value.map_or("-".to_owned(), |value| format!("{value:.1}"))
}

/// Writes `out/compare.csv` and `out/compare.json`; failure when a file cannot be written or
/// a launch failed.
pub fn write_outputs(out: &Path, rows: &[CompareRow]) -> ExitCode {
    let mut csv = String::from(
        "seed,golombek_k,mode,runtime_ok,goal_reached,executed_path_m,full_knowledge_path_m,built_map_path_m,replans,route_changes,node_expansions,mission_time_s,jump_requests,jumper_hops,collisions,run_dir\n",
    );
    for row in rows {
        let mission = row.mission.as_ref();
        csv.push_str(&format!(
            "{},{:.4},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            row.seed,
            row.golombek_k,
            row.mode,
            row.runtime_ok,
            mission.is_some_and(|m| m.goal_reached),
            mission.map_or(String::new(), |m| format!("{:.3}", m.executed_path_m)),
            mission
                .and_then(full_knowledge_m)
                .map_or(String::new(), |m| format!("{m:.3}")),
            mission
                .and_then(built_map_m)
                .map_or(String::new(), |m| format!("{m:.3}")),
            mission.map_or(String::new(), |m| m.replans.to_string()),
            mission.map_or(String::new(), |m| m.route_changes.to_string()),
            mission.map_or(String::new(), |m| m.node_expansions.to_string()),
            mission.map_or(String::new(), |m| format!("{:.2}", m.mission_time_s)),
            mission.map_or(String::new(), |m| m.jump_requests.to_string()),
            mission.map_or(String::new(), |m| m.jumper_hops.to_string()),
            mission.map_or(String::new(), |m| m.collisions.to_string()),
            row.run_dir
        ));
    }
    let csv_path = out.join("compare.csv");
    let json_path = out.join("compare.json");
    let json = serde_json::to_string_pretty(rows).unwrap_or_default();
    for (path, text) in [(&csv_path, csv), (&json_path, json)] {
        if let Err(error) = std::fs::write(path, text) {
            eprintln!("error: cannot write {}: {error}", path.display());
            return ExitCode::FAILURE;
        }
    }
    println!(
        "results: {} and {}",
        csv_path.display(),
        json_path.display()
    );
    if rows.iter().all(|row| row.runtime_ok) {
        ExitCode::SUCCESS
    } else {
        eprintln!("some launches failed: see the run folders");
        ExitCode::FAILURE
    }
}
