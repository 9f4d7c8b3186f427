//! Injected faults, each kind once, on the probe graph in lockstep: the report records each
//! fault with its detection and recovery, the launch completes, and nothing leaks.

mod common;

use common::*;

fn fault<'a>(report: &'a serde_json::Value, spec: &str) -> &'a serde_json::Value {
    report["faults"]
        .as_array()
        .and_then(|faults| faults.iter().find(|fault| fault["fault"] == spec))
        .unwrap_or_else(|| panic!("no fault {spec} in {report:#}"))
}

/// A lockstep launch of the probe graph under tight supervision with one fault: the run id,
/// the output and the report.
fn launch_strict(
    name: &str,
    frames: &str,
    fault: &str,
) -> (String, std::process::Output, serde_json::Value) {
    let (out, run) = (out_dir(name), run_id(name));
    let config = fixture_config("valid/strict_supervision.toml");
    let output = launch(
        &out,
        &run,
        &[&config, "--lockstep", "--frames", frames, "--fault", fault],
    );
    let report = report(&out, &run);
    (run, output, report)
}

#[test]
fn every_fault_kind_is_executed_recorded_and_survived() {
    let (out, run) = out_and_run("faults");
    let output = launch(
        &out,
        &run,
        &[
            &probe_config(),
            "--lockstep",
            "--frames",
            "60",
            "--fault",
            "kill:probe_sink@f10",
            "--fault",
            "stall:probe_sink@f30+30ms",
            "--fault",
            "corrupt:probe_source/image@20%",
            "--fault",
            "drop:probe_source/image@10%",
            "--fault",
            "delay:probe_source@5ms",
        ],
    );
    let report = report(&out, &run);
    assert!(output.status.success(), "{report:#}");
    assert_eq!(report["frames_completed"], 60);

    let kill = fault(&report, "kill:probe_sink@f10");
    assert_eq!(kill["injected_frame"], 10);
    assert!(kill["detected_after_s"].as_f64().is_some(), "{kill}");
    assert!(kill["recovered_after_s"].as_f64().is_some(), "{kill}");
    assert_eq!(process(&report, "probe_sink")["restarts"], 1);
    assert_eq!(
        process(&report, "probe_sink")["exits"][0]["restart"],
        "standby"
    );

    // A freeze shorter than the watchdog's stall limit: the process resumes, no restart.
    let stall = fault(&report, "stall:probe_sink@f30+30ms");
    assert_eq!(stall["injected_frame"], 30);
    let resumed_after_s = stall["recovered_after_s"]
        .as_f64()
        .expect("stall recovered");
    assert!(resumed_after_s >= 0.03, "{stall}");
    assert!(stall["detected_after_s"].is_null(), "not a hang: {stall}");

    // Garbled headers are rejected and counted by the consumer.
    let rejected = process(&report, "probe_sink")["rejected_samples"]
        .as_u64()
        .unwrap();
    assert!(rejected > 0, "no corrupt sample was rejected: {report:#}");

    // The delay shows in the source's cycle times.
    let source_p50_ms = process(&report, "probe_source")["cycle_time"]["p50_ms"]
        .as_f64()
        .unwrap();
    assert!(source_p50_ms >= 5.0, "{source_p50_ms}");

    assert_nothing_left(&report, &run);
}

#[test]
fn a_stall_beyond_the_watchdog_is_a_hang_and_is_restarted() {
    let (run, output, report) = launch_strict("fault-hang", "40", "stall:probe_sink@f10+30s");
    assert!(output.status.success(), "{report:#}");
    let stall = fault(&report, "stall:probe_sink@f10+30s");
    assert!(
        stall["detected_after_s"].as_f64().is_some(),
        "hang detected: {stall}"
    );
    assert!(stall["recovered_after_s"].as_f64().is_some(), "{stall}");
    let sink = process(&report, "probe_sink");
    assert_eq!(sink["hangs_detected"], 1);
    // A stopped process makes no progress: the stall limit applies (watchdog.
    // stall_timeout_frames), not the longer limit for busy processes.
    let reason = sink["exits"][0]["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("hung (stopped, no heartbeat for"),
        "{reason}"
    );
    assert_nothing_left(&report, &run);
}

#[test]
fn a_step_asleep_beyond_the_watchdog_is_a_hang() {
    // Every step sleeps 400 ms: silent past the stall limit (1.5 periods) without running.
    // The first kill must name sleep, not the longer limit for busy processes; with one
    // restart allowed, the second kill stops the launch.
    let (run, output, report) = launch_strict("fault-asleep", "20", "delay:probe_sink@400ms");
    let sink = process(&report, "probe_sink");
    assert!(sink["hangs_detected"].as_u64() >= Some(1), "{report:#}");
    let reason = sink["exits"][0]["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("hung (asleep without using CPU, no heartbeat for"),
        "{reason}"
    );
    assert_ne!(output.status.code(), Some(2), "{report:#}");
    assert!(pids_with_args(&[&run]).is_empty(), "no process survives");
}

#[test]
fn a_fault_on_a_process_outside_the_graph_is_a_config_error() {
    let (out, run) = out_and_run("fault-bad");
    let with_fault = |fault: &str| {
        launch(
            &out,
            &run,
            &[&probe_config(), "--frames", "5", "--fault", fault],
        )
    };
    let output = with_fault("kill:mapper@1s");
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("not an enabled process"), "{stderr}");
    let output = with_fault("kill:probe_sink");
    assert_eq!(output.status.code(), Some(2));
}

/// The default cooperative mission in lockstep, with every process but physics killed once
/// (jumper_vo twice: in flight, then at rest): each restart is a promotion of a prepared
/// standby, the VO processes continue from their last pose (not from the start point), the
/// mapper from its snapshot, the planner replans, and the rover still reaches the goal as
/// closely as without faults. (physics is killed in its own test below.)
#[test]
fn the_mission_reaches_its_goal_through_restarts_of_its_processes() {
    let (out, run) = out_and_run("mission-faults");
    // Kills are the faults here: a loaded machine that delays a frame must not add a hang.
    let patient = fixture_config("valid/patient_watchdog.toml");
    let output = launch(
        &out,
        &run,
        &[
            &patient,
            "--lockstep",
            "--fault",
            "kill:jumper_vo@f25",
            "--fault",
            "kill:camera@f30",
            "--fault",
            "kill:rover_vo@f150",
            "--fault",
            "kill:mapper@f200",
            "--fault",
            "kill:planner@f250",
            "--fault",
            "kill:jumper_vo@f300",
        ],
    );
    let report = report(&out, &run);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{report:#}\n{stderr}");
    let mission = &report["mission"];
    assert_eq!(mission["goal_reached"], true, "{mission}");
    assert!(
        mission["final_distance_to_goal_m"].as_f64().unwrap() < 1.0,
        "{mission}"
    );
    for (name, kills) in [
        ("camera", 1),
        ("jumper_vo", 2),
        ("rover_vo", 1),
        ("mapper", 1),
        ("planner", 1),
    ] {
        let process = process(&report, name);
        assert_eq!(process["restarts"], kills, "{name}: {process}\n{stderr}");
        assert_eq!(process["hangs_detected"], 0, "{name}: {process}");
        for exit in process["exits"].as_array().unwrap() {
            assert_eq!(exit["reason"], "killed by signal 9", "{name}: {exit}");
            assert_eq!(exit["restart"], "standby", "{name}: {exit}");
            assert!(exit["recovered_after_s"].as_f64().is_some(), "{exit}");
        }
    }
    assert_eq!(process(&report, "physics")["restarts"], 0);
    // The restarted mapper took in the clouds its snapshot did not hold yet.
    assert!(
        stderr.contains("mapper: took in "),
        "no clouds replayed after the mapper's restart\n{stderr}"
    );
    assert_nothing_left(&report, &run);
}

/// The default mission in lockstep with rover_vo killed while the rover drives: the restarted
/// VO anchors on the stereo pair of the last pose its predecessor published (from the camera
/// topic's history) and measures the motion since then, so its position error does not jump
/// at the restart (losing one frame's motion would add about the rover's 0.04 m per frame).
#[test]
fn a_restarted_rover_vo_measures_the_motion_it_did_not_see() {
    const KILL_FRAME: u64 = 150;
    let (out, run) = out_and_run("rover-vo-kill");
    let kill = format!("kill:rover_vo@f{KILL_FRAME}");
    let output = launch(
        &out,
        &run,
        &["--lockstep", "--frames", "170", "--fault", &kill],
    );
    let report = report(&out, &run);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{report:#}\n{stderr}");
    assert_eq!(process(&report, "rover_vo")["restarts"], 1, "{stderr}");
    assert!(stderr.contains("rover_vo: resumed on frame"), "{stderr}");
    assert!(!stderr.contains("rover_vo: restarted without"), "{stderr}");
    let run_dir = out.join(&run);
    let truth = tum_positions(&run_dir.join("vo_rover_truth.tum"));
    let estimate = tum_positions(&run_dir.join("vo_rover_estimate.tum"));
    let error_at = |t_s: f64| {
        let (_, e) = estimate
            .iter()
            .find(|(t, _)| (t - t_s).abs() < 0.01)
            .unwrap_or_else(|| panic!("no estimate at {t_s} s"));
        let (_, g) = truth
            .iter()
            .find(|(t, _)| (t - t_s).abs() < 0.01)
            .unwrap_or_else(|| panic!("no truth at {t_s} s"));
        (e[0] - g[0]).hypot(e[1] - g[1])
    };
    let before_m = error_at((KILL_FRAME - 5) as f64 * 0.1);
    let after_m = error_at((KILL_FRAME + 10) as f64 * 0.1);
    assert!(
        (after_m - before_m).abs() < 0.02,
        "error {before_m:.3} m before the restart, {after_m:.3} m after"
    );
    assert!(pids_with_args(&[&run]).is_empty(), "no process survives");
}

/// The default mission in lockstep with physics killed during the jumper's first hop: the
/// restarted physics continues the simulation from the last state it published (relayed by
/// the supervisor) instead of starting over at t = 0, so after 120 frames the simulation is at
/// 12 s (a restart from scratch would end at 8 s, the 80 frames after the kill).
#[test]
fn a_killed_physics_resumes_its_simulation_instead_of_starting_over() {
    const FRAMES: u64 = 120;
    const KILL_FRAME: u64 = 40;
    let (out, run) = out_and_run("physics-kill");
    let kill = format!("kill:physics@f{KILL_FRAME}");
    let frames = FRAMES.to_string();
    let output = launch(
        &out,
        &run,
        &["--lockstep", "--frames", &frames, "--fault", &kill],
    );
    let report = report(&out, &run);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{report:#}\n{stderr}");
    let physics = process(&report, "physics");
    assert_eq!(physics["restarts"], 1, "{physics}\n{stderr}");
    for exit in physics["exits"].as_array().unwrap() {
        assert_eq!(exit["reason"], "killed by signal 9", "{exit}");
        assert!(exit["recovered_after_s"].as_f64().is_some(), "{exit}");
    }
    // The last body states' sim time: every frame simulated once, none lost, none repeated.
    let mission_time_s = report["mission"]["mission_time_s"].as_f64().unwrap();
    assert!(
        (mission_time_s - FRAMES as f64 * 0.1).abs() < 1e-6,
        "sim time at the end {mission_time_s} s\n{:#}",
        report["mission"]
    );
    assert!(
        stderr.contains(&format!("physics: resumed at frame {KILL_FRAME} ")),
        "{stderr}"
    );
    assert!(!stderr.contains("starts over"), "{stderr}");
    // Both robots go on from where they were: no jump in their true tracks at the restart
    // (a fresh world would put them back at their start points, metres away).
    let run_dir = out.join(&run);
    for robot in ["jumper", "rover"] {
        let track = tum_positions(&run_dir.join(format!("vo_{robot}_truth.tum")));
        let step_m = |i: usize| {
            let (a, b) = (track[i - 1].1, track[i].1);
            ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
        };
        let at_kill = track
            .iter()
            .position(|(t_s, _)| *t_s > KILL_FRAME as f64 * 0.1 - 1e-6)
            .unwrap_or_else(|| panic!("{robot}: no pose after the kill"));
        let before_m = (at_kill - 5..at_kill - 1).map(step_m).fold(0.0, f64::max);
        for (i, (t_s, _)) in track.iter().enumerate().take(at_kill + 3).skip(at_kill - 1) {
            assert!(
                step_m(i) <= 2.0 * before_m + 0.02,
                "{robot}: moved {:.3} m in the frame to t = {t_s:.1} s (at most {before_m:.3} m per frame before the kill)",
                step_m(i),
            );
        }
    }
    assert_nothing_left(&report, &run);
}
