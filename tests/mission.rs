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
    let (out, run) = out_and_run("mission");
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
    let config = fixture_config("missions/rover_only.toml");
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

/// The jumper VO's position error at the first pose of every hop launched from rest (the
/// hops after the first), in launch order.
fn jumper_error_after_each_launch_m(run_dir: &std::path::Path) -> Vec<f64> {
    let truth = tum_positions(&run_dir.join("vo_jumper_truth.tum"));
    let estimate = tum_positions(&run_dir.join("vo_jumper_estimate.tum"));
    assert_eq!(truth.len(), estimate.len());
    let speed = |a: &(f64, [f64; 3]), b: &(f64, [f64; 3])| {
        (0..3)
            .map(|i| (b.1[i] - a.1[i]).powi(2))
            .sum::<f64>()
            .sqrt()
            / (b.0 - a.0)
    };
    (2..truth.len())
        .filter(|&i| {
            speed(&truth[i - 2], &truth[i - 1]) < 0.1 && speed(&truth[i - 1], &truth[i]) > 2.0
        })
        .map(|i| {
            assert_eq!(truth[i].0, estimate[i].0);
            (0..3)
                .map(|k| (estimate[i].1[k] - truth[i].1[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect()
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

#[test]
fn the_relocalization_oracle_starts_every_hop_at_the_true_launch_point() {
    let oracle_config = fixture_config("missions/oracle_relocalization.toml");
    let mut median_error_m = Vec::new();
    for (name, config) in [("vo", None), ("oracle", Some(oracle_config.as_str()))] {
        let (out, run) = (
            out_dir(&format!("mission-{name}")),
            run_id(&format!("mission-{name}")),
        );
        let mut args = vec!["--lockstep", "--frames", "400"];
        args.extend(config);
        let output = launch(&out, &run, &args);
        assert!(output.status.success(), "{:#}", report(&out, &run));
        let errors_m = jumper_error_after_each_launch_m(&out.join(&run));
        assert!(
            errors_m.len() >= 2,
            "{name}: hops launched from rest: {errors_m:?}"
        );
        median_error_m.push(median(errors_m));
    }
    // The VO carries its landing error into the next hop; the oracle starts it at the truth
    // (a hop a rock deflects at launch may still err, hence the median).
    assert!(median_error_m[0] > 0.2, "VO: {median_error_m:?}");
    assert!(median_error_m[1] < 0.05, "oracle: {median_error_m:?}");
}
