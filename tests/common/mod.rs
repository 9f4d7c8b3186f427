//! Helpers for system tests that start the real `hopnav` binary.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The binary under test.
pub fn hopnav() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hopnav"))
}

/// The probe-graph config (no world): what runtime tests launch unless they bring their own.
pub fn probe_config() -> String {
    fixture_config("probe.toml")
}

/// A config file under tests/fixtures/config, e.g. `valid/strict_supervision.toml`.
pub fn fixture_config(relative: &str) -> String {
    format!(
        "{}/tests/fixtures/config/{relative}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// A run id unique to this test process and `test`.
pub fn run_id(test: &str) -> String {
    format!("t{}-{test}", std::process::id())
}

/// The fresh output folder and the run id of `test`.
pub fn out_and_run(test: &str) -> (PathBuf, String) {
    (out_dir(test), run_id(test))
}

/// A fresh output folder for `test`.
pub fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("hopnav-system-tests")
        .join(run_id(test));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create out dir");
    dir
}

/// `hopnav launch` with the given arguments, quiet, into `out`.
pub fn launch_command(out: &Path, run_id: &str, args: &[&str]) -> Command {
    let mut command = hopnav();
    command
        .arg("launch")
        .args(args)
        .arg("--quiet")
        .arg("--out")
        .arg(out)
        .arg("--run-id")
        .arg(run_id)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    command
}

/// `hopnav launch` with the given arguments, started in the background.
pub fn spawn_launch(out: &Path, run_id: &str, args: &[&str]) -> Child {
    launch_command(out, run_id, args)
        .spawn()
        .expect("spawn launch")
}

/// Runs a launch to completion.
pub fn launch(out: &Path, run_id: &str, args: &[&str]) -> Output {
    launch_command(out, run_id, args)
        .output()
        .expect("run hopnav launch")
}

/// The run left no shared-memory files and no process behind.
pub fn assert_nothing_left(report: &serde_json::Value, run_id: &str) {
    assert_eq!(report["leftover_files"], 0, "leftover files: {report:#}");
    let survivors = pids_with_args(&[run_id]);
    assert!(
        survivors.is_empty(),
        "no process of the run survives: {survivors:?}"
    );
}

/// Runs `command` to its end and returns its standard output; unless it succeeded, panics
/// naming `what` with both outputs.
pub fn stdout_of_success(command: &mut Command, what: &str) -> String {
    let output = command
        .output()
        .unwrap_or_else(|error| panic!("{what}: cannot run: {error}"));
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{what}: {stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// The run left no shared-memory files; panics listing them.
pub fn assert_no_leftover_files(run_id: &str) {
    let files = leftover_files(run_id);
    assert!(files.is_empty(), "{files:?}");
}

/// The parsed report of a run.
pub fn report(out: &Path, run_id: &str) -> serde_json::Value {
    let path = out.join(run_id).join("report.json");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|error| panic!("read {}: {error}", path.display()));
    serde_json::from_str(&text).expect("report is JSON")
}

/// The report entry of process `name`.
pub fn process<'a>(report: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    report["processes"]
        .as_array()
        .expect("processes array")
        .iter()
        .find(|process| process["name"] == name)
        .unwrap_or_else(|| panic!("no process {name} in report"))
}

/// Pids of live (non-zombie) processes whose command line contains every one of `needles`.
pub fn pids_with_args(needles: &[&str]) -> Vec<i32> {
    let mut pids = Vec::new();
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return pids;
    };
    for entry in entries.flatten() {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|s| s.parse::<i32>().ok())
        else {
            continue;
        };
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = cmdline
            .split(|byte| *byte == 0)
            .map(|arg| String::from_utf8_lossy(arg).into_owned())
            .collect();
        let zombie = std::fs::read_to_string(entry.path().join("stat"))
            .map(|stat| {
                stat.split(") ")
                    .nth(1)
                    .is_some_and(|rest| rest.starts_with('Z'))
            })
            .unwrap_or(false);
        if !zombie
            && needles
                .iter()
                .all(|needle| args.iter().any(|arg| arg == needle))
        {
            pids.push(pid);
        }
    }
    pids
}

/// Like [`pids_with_args`], but only processes in service: a warm standby waiting for its
/// promotion runs at SCHED_IDLE (a promoted one is back on the normal policy, though its
/// command line still says `--standby`).
pub fn serving_pids_with_args(needles: &[&str]) -> Vec<i32> {
    const SCHED_IDLE: u32 = 5;
    pids_with_args(needles)
        .into_iter()
        .filter(|pid| {
            let policy = std::fs::read_to_string(format!("/proc/{pid}/stat"))
                .ok()
                .and_then(|stat| {
                    let rest = stat.get(stat.rfind(')')? + 2..)?.to_owned();
                    // Field 41 of stat is the policy; `rest` starts at field 3.
                    rest.split(' ').nth(41 - 3)?.parse::<u32>().ok()
                });
            policy.is_some_and(|policy| policy != SCHED_IDLE)
        })
        .collect()
}

/// Waits until `condition` holds or `limit` passes; returns whether it held.
pub fn wait_until(limit: Duration, mut condition: impl FnMut() -> bool) -> bool {
    let deadline = Instant::now() + limit;
    while Instant::now() < deadline {
        if condition() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    condition()
}

/// Sends `signal` to `pid`.
pub fn signal(pid: i32, signal: i32) {
    // SAFETY: kill(2) with a pid we just read from /proc; at worst it fails with ESRCH.
    unsafe {
        libc::kill(pid, signal);
    }
}

/// Shared-memory and iceoryx2 files of run `run_id` still on disk.
pub fn leftover_files(run_id: &str) -> Vec<PathBuf> {
    let prefix = format!("hopnav_{run_id}_");
    let mut found = Vec::new();
    for dir in [
        "/dev/shm",
        hopnav_ipc::namespace::ROOT_PATH,
        "/dev/shm/hopnav-iceoryx2/nodes",
        "/dev/shm/hopnav-iceoryx2/services",
    ] {
        collect(Path::new(dir), &prefix, &mut found, 2);
    }
    found
}

fn collect(dir: &Path, prefix: &str, found: &mut Vec<PathBuf>, depth: u32) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with(prefix) {
            found.push(path);
        } else if depth > 0 && entry.file_type().map(|t| t.is_dir()).unwrap_or(false) {
            collect(&path, prefix, found, depth - 1);
        }
    }
}

/// Waits for `child` with a limit, killing it if it overruns.
pub fn wait_with_limit(child: &mut Child, limit: Duration) -> Option<std::process::ExitStatus> {
    let deadline = Instant::now() + limit;
    loop {
        if let Ok(Some(status)) = child.try_wait() {
            return Some(status);
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `(t, [x, y, z])` of each pose in a TUM trajectory file.
pub fn tum_positions(path: &std::path::Path) -> Vec<(f64, [f64; 3])> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|line| !line.starts_with('#'))
        .map(|line| {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            (v[0], [v[1], v[2], v[3]])
        })
        .collect()
}
