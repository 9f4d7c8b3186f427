//! A child hit by kill -9 is restarted and the launch still completes.

mod common;

use std::time::Duration;

use common::*;

#[test]
fn killed_child_is_restarted_and_the_launch_completes() {
    let (out, run) = (out_dir("restart"), run_id("restart"));
    // Lockstep, long enough that the kill lands mid-run even on a fast machine.
    let mut child = launch_command(
        &out,
        &run,
        &[&probe_config(), "--lockstep", "--frames", "3000"],
    )
    .spawn()
    .expect("spawn launch");
    let sink = || serving_pids_with_args(&["run", "probe_sink", &run]);
    assert!(
        wait_until(Duration::from_secs(20), || !sink().is_empty()),
        "sink never started"
    );
    std::thread::sleep(Duration::from_millis(300));
    let victims = sink();
    assert_eq!(victims.len(), 1);
    signal(victims[0], libc::SIGKILL);

    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "report: {report:#}");
    assert_eq!(report["outcome"], "completed");
    assert_eq!(
        report["frames_completed"], 3000,
        "lockstep waits for the restarted sink"
    );
    let sink_report = process(&report, "probe_sink");
    assert_eq!(sink_report["restarts"], 1);
    let exit = &sink_report["exits"][0];
    assert_eq!(exit["reason"], "killed by signal 9");
    assert!(exit["recovered_after_s"].as_f64().is_some(), "{exit}");
    // Lockstep starts once the standbys have prepared: the restart is a promotion.
    assert_eq!(exit["restart"], "standby", "{exit}");
    assert!(exit["startup_s"].as_f64().is_some(), "{exit}");
    assert_eq!(report["leftover_files"], 0);
    assert!(
        pids_with_args(&[&run]).is_empty(),
        "no process of the run survives"
    );
}

fn strict_config() -> String {
    format!(
        "{}/tests/fixtures/config/valid/strict_supervision.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn crash_loop_exceeding_restart_intensity_stops_the_launch_without_orphans() {
    let (out, run) = (out_dir("crash-loop"), run_id("crash-loop"));
    let config = strict_config();
    let mut child = launch_command(&out, &run, &[&config, "--lockstep", "--frames", "100000"])
        .spawn()
        .expect("spawn launch");
    let sink = || serving_pids_with_args(&["run", "probe_sink", &run]);
    for kill in 0..2 {
        assert!(
            wait_until(Duration::from_secs(20), || sink().len() == 1),
            "sink {kill} never started"
        );
        std::thread::sleep(Duration::from_millis(200));
        let victims = sink();
        assert_eq!(victims.len(), 1);
        signal(victims[0], libc::SIGKILL);
        assert!(wait_until(Duration::from_secs(10), || !sink().contains(&victims[0])));
    }
    let status = wait_with_limit(&mut child, Duration::from_secs(60)).expect("launch stopped");
    assert_eq!(status.code(), Some(1));
    let report = report(&out, &run);
    let outcome = report["outcome"].as_str().unwrap();
    assert!(
        outcome.starts_with("stopped: probe_sink killed by signal 9"),
        "{outcome}"
    );
    assert!(outcome.contains("restart.max_restarts = 1"), "{outcome}");
    assert!(
        pids_with_args(&[&run]).is_empty(),
        "orphans: {:?}",
        pids_with_args(&[&run])
    );
    assert_eq!(report["leftover_files"], 0);
}

#[test]
fn a_hung_child_is_detected_by_the_watchdog_killed_and_restarted() {
    let (out, run) = (out_dir("hang"), run_id("hang"));
    let config = strict_config();
    let mut child = launch_command(&out, &run, &[&config, "--lockstep", "--frames", "3000"])
        .spawn()
        .expect("spawn launch");
    let sink = || serving_pids_with_args(&["run", "probe_sink", &run]);
    assert!(wait_until(Duration::from_secs(20), || sink().len() == 1));
    std::thread::sleep(Duration::from_millis(200));
    let frozen = sink()[0];
    signal(frozen, libc::SIGSTOP); // alive but silent: a hang
    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "{report:#}");
    assert_eq!(report["frames_completed"], 3000);
    let sink_report = process(&report, "probe_sink");
    assert_eq!(sink_report["hangs_detected"], 1);
    assert_eq!(sink_report["restarts"], 1);
    let reason = sink_report["exits"][0]["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("hung (stopped, no heartbeat for"),
        "{reason}"
    );
    assert!(pids_with_args(&[&run]).is_empty());
}

#[test]
fn a_dead_standby_leaves_cold_restarts_and_the_launch_completes() {
    let (out, run) = (out_dir("dead-standby"), run_id("dead-standby"));
    let mut child = launch_command(
        &out,
        &run,
        &[&probe_config(), "--lockstep", "--frames", "3000"],
    )
    .spawn()
    .expect("spawn launch");
    let all_sinks = || pids_with_args(&["run", "probe_sink", &run]);
    let serving = || serving_pids_with_args(&["run", "probe_sink", &run]);
    assert!(
        wait_until(Duration::from_secs(20), || all_sinks().len() == 2),
        "sink and its standby never started"
    );
    let standby: Vec<i32> = all_sinks()
        .into_iter()
        .filter(|pid| !serving().contains(pid))
        .collect();
    assert_eq!(standby.len(), 1);
    signal(standby[0], libc::SIGKILL);
    assert!(wait_until(Duration::from_secs(10), || all_sinks().len() == 1));
    let victims = serving();
    assert_eq!(victims.len(), 1);
    signal(victims[0], libc::SIGKILL);

    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "report: {report:#}");
    assert_eq!(report["frames_completed"], 3000);
    let exit = &process(&report, "probe_sink")["exits"][0];
    assert_eq!(exit["restart"], "cold", "{exit}");
    assert_eq!(report["leftover_files"], 0);
    assert!(pids_with_args(&[&run]).is_empty());
}
