//! A child hit by kill -9 is restarted and the launch still completes.

mod common;

use std::time::Duration;

use common::*;

#[test]
fn killed_child_is_restarted_and_the_launch_completes() {
    let (out, run) = (out_dir("restart"), run_id("restart"));
    // Lockstep, long enough that the kill lands mid-run even on a fast machine.
    let mut child = launch_command(&out, &run, &["--lockstep", "--frames", "3000"])
        .spawn()
        .expect("spawn launch");
    let sink = || pids_with_args(&["run", "probe_sink", &run]);
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
    assert_eq!(report["leftover_files"], 0);
    assert!(
        pids_with_args(&[&run]).is_empty(),
        "no process of the run survives"
    );
}
