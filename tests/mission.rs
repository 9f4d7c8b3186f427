//! The main job: the cooperative mission on the embedded default config runs A to B in
//! lockstep, with every process of the graph; the rover-only baseline runs without the jumper.

mod common;

use common::*;

fn mission(report: &serde_json::Value) -> &serde_json::Value {
    let mission = &report["mission"];
    assert!(mission.is_object(), "no mission section: {report:#}");
    mission
}

#[test]
fn the_default_cooperative_mission_reaches_the_goal() {
    let (out, run) = (out_dir("mission"), run_id("mission"));
    let output = launch(&out, &run, &["--lockstep"]);
    let report = report(&out, &run);
    assert!(output.status.success(), "{report:#}");
    assert!(
        report["outcome"]
            .as_str()
            .is_some_and(|outcome| outcome.contains("goal reached")),
        "{}",
        report["outcome"]
    );
    let mission = mission(&report);
    assert_eq!(mission["mode"], "cooperative");
    assert_eq!(mission["goal_reached"], true);
    assert!(mission["final_distance_to_goal_m"].as_f64().unwrap() < 1.0);
    // The jumper scouted: its launch at the start, and the rover's request(s).
    assert!(mission["jumper_hops"].as_u64().unwrap() >= 1, "{mission}");
    assert!(mission["node_expansions"].as_u64().unwrap() > 0);
    // Both robots mapped: the map holds cells seen by each.
    assert!(mission["mapped_cells"].as_u64().unwrap() > 100, "{mission}");
    // The full-knowledge path of the same world: no shorter than the straight A–B line.
    let best_m = mission["full_knowledge_path_m"]
        .as_f64()
        .expect("full-knowledge path");
    let straight_m = mission["straight_line_m"].as_f64().unwrap();
    assert!(
        best_m >= straight_m - 1e-6 && best_m < 1.5 * straight_m,
        "{mission}"
    );
    // The built map's path: planned on the final map, so the goal it reached is reachable.
    let built_m = mission["built_map_path_m"]
        .as_f64()
        .expect("built-map path");
    assert!(
        built_m >= straight_m - 1e-6 && built_m < 1.5 * straight_m,
        "{mission}"
    );
    // Every process of the graph ran every frame.
    for name in [
        "physics",
        "camera",
        "jumper_vo",
        "rover_vo",
        "mapper",
        "planner",
    ] {
        let process = process(&report, name);
        assert_eq!(process["restarts"], 0, "{name}");
        assert!(
            process["frames_completed"].as_u64().unwrap() > 100,
            "{name}"
        );
    }
    let figure = report["mission_figure"].as_str().expect("a map figure");
    assert!(std::path::Path::new(figure).exists());
    assert_eq!(report["leftover_files"], 0);
}

#[test]
fn the_rover_only_baseline_keeps_the_jumper_on_the_ground() {
    let (out, run) = (out_dir("mission-rover-only"), run_id("mission-ro"));
    let config = format!(
        "{}/tests/fixtures/config/missions/rover_only.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let output = launch(&out, &run, &[&config, "--lockstep", "--frames", "300"]);
    let report = report(&out, &run);
    assert!(output.status.success(), "{report:#}");
    let mission = mission(&report);
    assert_eq!(mission["mode"], "rover-only");
    assert_eq!(mission["jump_requests"], 0);
    assert_eq!(mission["jumper_hops"], 0);
    assert!(
        mission["executed_path_m"].as_f64().unwrap() > 5.0,
        "{mission}"
    );
}
