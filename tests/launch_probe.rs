//! The supervisor runs the probe graph in lockstep and reports what it measured.

mod common;

use common::*;

#[test]
fn lockstep_probe_launch_completes_every_frame_and_reports() {
    let (out, run) = out_and_run("probe");
    let output = launch(
        &out,
        &run,
        &[&probe_config(), "--lockstep", "--frames", "60"],
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "stdout:\n{stdout}\nstderr:\n{stderr}"
    );
    assert!(stdout.contains("completed (lockstep mode)"), "{stdout}");
    assert!(
        stdout.contains("probe_sink") && stdout.contains("p99 ms"),
        "summary table: {stdout}"
    );

    let report = report(&out, &run);
    assert_eq!(report["outcome"], "completed");
    assert_eq!(report["mode"], "lockstep");
    assert_eq!(report["frames_requested"], 60);
    assert_eq!(report["frames_completed"], 60);
    assert_eq!(report["frames_degraded"], 0);
    assert_eq!(report["leftover_files"], 0);
    assert_eq!(report["end_to_end_latency"]["count"], 60);
    assert!(report["end_to_end_latency"]["p50_ms"].as_f64().unwrap() > 0.0);
    assert!(report["config"]["run"]["lockstep"].as_bool().unwrap());
    for name in ["probe_source", "probe_sink"] {
        let process = process(&report, name);
        assert_eq!(process["frames_completed"], 60, "{name}");
        assert_eq!(process["restarts"], 0, "{name}");
        assert_eq!(process["rejected_samples"], 0, "{name}");
        for key in ["p50_ms", "p99_ms", "max_ms"] {
            assert!(
                process["cycle_time"][key].as_f64().unwrap() > 0.0,
                "{name} {key}"
            );
        }
    }
    // The sink checked every byte of every frame's image and found them all.
    assert!(
        stderr.contains("verified 60 probe images, 0 corrupt, 0 missing"),
        "{stderr}"
    );
    assert_no_leftover_files(&run);
    assert!(out.join(&run).join("config.toml").exists());
}

#[test]
fn lockstep_runs_are_reproducible() {
    let out = out_dir("repro");
    let summaries: Vec<_> = ["repro-a", "repro-b"]
        .iter()
        .map(|name| {
            let run = run_id(name);
            let output = launch(
                &out,
                &run,
                &[&probe_config(), "--lockstep", "--frames", "30"],
            );
            assert!(output.status.success());
            let report = report(&out, &run);
            (
                report["frames_completed"].clone(),
                report["frames_degraded"].clone(),
                process(&report, "probe_sink")["frames_completed"].clone(),
                String::from_utf8_lossy(&output.stderr)
                    .lines()
                    .find(|line| line.contains("verified"))
                    .map(|line| line.split(", delivery").next().unwrap_or("").to_owned()),
            )
        })
        .collect();
    assert_eq!(summaries[0], summaries[1]);
}
