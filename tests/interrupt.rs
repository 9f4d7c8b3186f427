//! Ctrl-C (SIGINT) or SIGTERM stops a command that runs many launches — `hopnav chaos`,
//! `hopnav compare` — as a whole: the launch it hit shuts down, no later launch starts, what
//! finished is written, no child survives and the exit code is 130.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

/// Pids of live processes with an argument containing `needle` (children name their run
/// folder in `--config`).
fn pids_mentioning(needle: &str) -> Vec<i32> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter_map(|entry| {
            let pid = entry.file_name().to_str()?.parse::<i32>().ok()?;
            let cmdline = std::fs::read(entry.path().join("cmdline")).ok()?;
            let stat = std::fs::read_to_string(entry.path().join("stat")).ok()?;
            let zombie = stat.split(") ").nth(1).is_some_and(|s| s.starts_with('Z'));
            let mentions = cmdline
                .split(|byte| *byte == 0)
                .any(|arg| String::from_utf8_lossy(arg).contains(needle));
            (mentions && !zombie).then_some(pid)
        })
        .collect()
}

/// Run folders (one per launch started) under `out`.
fn run_dirs(out: &Path) -> Vec<String> {
    std::fs::read_dir(out)
        .map(|entries| {
            entries
                .flatten()
                .filter(|entry| entry.path().join("config.toml").exists())
                .filter_map(|entry| entry.file_name().to_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

/// Starts `command` with its output piped, waits for the first launch's children, interrupts
/// it, and checks the common part: exit code 130, no child left, no later launch started, no
/// shared memory left.
fn interrupt_during_first_launch(command: &mut Command, out: &Path) -> String {
    let mut command = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let out_text = out.display().to_string();
    assert!(
        // The command itself (its --out) and at least two children (their --config).
        wait_until(Duration::from_secs(60), || pids_mentioning(&out_text).len()
            >= 3),
        "the first launch never started its children"
    );
    std::thread::sleep(Duration::from_millis(500));
    signal(command.id() as i32, libc::SIGINT);
    let status = wait_with_limit(&mut command, Duration::from_secs(60)).expect("stopped");
    let stderr = command
        .stderr
        .take()
        .map(|mut pipe| {
            let mut text = String::new();
            let _ = std::io::Read::read_to_string(&mut pipe, &mut text);
            text
        })
        .unwrap_or_default();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(
        pids_mentioning(&out_text).is_empty(),
        "children survive: {:?}",
        pids_mentioning(&out_text)
    );
    let runs = run_dirs(out);
    assert_eq!(runs.len(), 1, "a later launch started: {runs:?}\n{stderr}");
    assert_no_leftover_files(&runs[0]);
    stderr
}

#[test]
fn sigint_stops_the_whole_chaos_run_and_keeps_what_finished() {
    let out = out_dir("chaos-sigint");
    let stderr = interrupt_during_first_launch(
        hopnav()
            .args([
                "chaos",
                &probe_config(),
                "--runs",
                "5",
                "--frames",
                "1000000",
            ])
            .args(["--kinds", "delay", "--faults-per-run", "1", "--out"])
            .arg(&out),
        &out,
    );
    assert!(
        stderr.contains("interrupted: stopped after 1 of 5 runs"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(out.join("chaos.json")).expect("chaos.json written");
    let runs: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let runs = runs.as_array().expect("array of runs");
    // The signal hit the first launch (in its frame loop, or still starting on a busy
    // machine): it is the only one recorded.
    assert_eq!(runs.len(), 1, "{text}");
    let outcome = runs[0]["outcome"].as_str().unwrap_or_default();
    assert!(outcome.starts_with("interrupted"), "{text}");
    assert_eq!(runs[0]["leftover_files"], 0);
}

#[test]
fn sigint_stops_the_whole_comparison_and_keeps_what_finished() {
    let out = out_dir("compare-sigint");
    let stderr = interrupt_during_first_launch(
        hopnav()
            .args(["compare", "--seeds", "3", "--frames", "1000000", "--out"])
            .arg(&out),
        &out,
    );
    // The mission graph may still be starting (then the launch has no row) or running.
    assert!(stderr.contains("interrupted: stopped after"), "{stderr}");
    assert!(stderr.contains("of 6 launches"), "{stderr}");
    let csv = std::fs::read_to_string(out.join("compare.csv")).expect("compare.csv written");
    assert!(
        csv.lines().count() <= 2,
        "header and at most the interrupted row: {csv}"
    );
}
