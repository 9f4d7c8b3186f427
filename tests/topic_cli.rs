//! `hopnav topic list`, `hz`, `bw` and `hopnav top` against a running lockstep launch: the
//! camera and pose topics are listed with their types and processes, `hz` receives samples,
//! `bw` their sizes and `top` every process's heartbeats. What is checked is behaviour (names, types, samples > 0, sizes), never a
//! rate: the machine may be loaded.

mod common;

use std::process::{Child, Output, Stdio};
use std::time::Duration;

use common::*;

/// A launch that is stopped (SIGINT, then SIGKILL if it lingers) however the test ends.
struct RunningLaunch {
    child: Child,
    run_id: String,
}

impl Drop for RunningLaunch {
    fn drop(&mut self) {
        signal(self.child.id() as i32, libc::SIGINT);
        let _ = wait_with_limit(&mut self.child, Duration::from_secs(60));
    }
}

fn topic(args: &[&str]) -> Output {
    hopnav()
        .arg("topic")
        .args(args)
        .output()
        .expect("run hopnav topic")
}

fn text(output: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// The line of `topic` in a `topic list` output.
fn line_of<'a>(list: &'a str, topic: &str) -> Option<&'a str> {
    list.lines()
        .find(|line| line.split_whitespace().next() == Some(topic))
}

#[test]
fn topic_list_and_hz_see_a_running_lockstep_launch() {
    let (out, run) = out_and_run("topic");
    let stderr_file = std::fs::File::create(out.join("launch.stderr")).expect("stderr file");
    // Without warm standbys: a lockstep launch starts its frames once they are prepared, and
    // at idle priority on a loaded machine that can take tens of seconds.
    let config = out.join("no_standby.toml");
    std::fs::write(&config, "[restart]\nwarm_standby = false\n").expect("config");
    let config = config.display().to_string();
    // Far more frames than the test needs: the launch is stopped when the test ends.
    let child = launch_command(&out, &run, &[&config, "--lockstep", "--frames", "100000"])
        .stdout(Stdio::null())
        .stderr(stderr_file)
        .spawn()
        .expect("spawn launch");
    let launch = RunningLaunch {
        child,
        run_id: run.clone(),
    };

    // The camera and VO topics with their types and processes. The graph takes seconds to
    // start on a loaded machine and its ports open one by one: wait until all are there.
    let expect = [
        (
            "hopnav/camera/jumper",
            "ImageHeader + [u8]",
            "camera",
            "jumper_vo",
        ),
        (
            "hopnav/camera/rover_stereo",
            "ImageHeader + [u8]",
            "camera",
            "rover_vo",
        ),
        (
            "hopnav/jumper_vo/pose",
            "PoseEstimate",
            "jumper_vo",
            "planner",
        ),
        (
            "hopnav/rover_vo/pose",
            "PoseEstimate",
            "rover_vo",
            "planner",
        ),
    ];
    let mut list = String::new();
    let listed = wait_until(Duration::from_secs(120), || {
        let output = topic(&["list", "--run", &launch.run_id]);
        list = String::from_utf8_lossy(&output.stdout).into_owned();
        output.status.success()
            && expect
                .iter()
                .all(|(name, message_type, publisher, subscriber)| {
                    line_of(&list, name).is_some_and(|line| {
                        let columns: Vec<&str> = line.split_whitespace().collect();
                        line.contains(message_type)
                            && columns.contains(publisher)
                            && columns
                                .iter()
                                .any(|column| column.split(',').any(|name| name == *subscriber))
                    })
                })
    });
    let launch_log = std::fs::read_to_string(out.join("launch.stderr")).unwrap_or_default();
    assert!(
        listed,
        "topics, types or processes missing:\n{list}\nlaunch:\n{launch_log}"
    );
    // A jumper image is its header plus 320 × 320 pixels.
    let jumper = line_of(&list, "hopnav/camera/jumper").unwrap_or_default();
    assert!(jumper.ends_with(" 102560"), "{jumper}");

    let hz = topic(&[
        "hz",
        "hopnav/camera/jumper",
        "--run",
        &launch.run_id,
        "--duration-s",
        "3",
    ]);
    let hz_text = text(&hz);
    assert!(hz.status.success(), "{hz_text}");
    let stdout = String::from_utf8_lossy(&hz.stdout);
    let summary = stdout.lines().last().unwrap_or_default();
    let samples: u64 = summary
        .split(": ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|count| count.parse().ok())
        .unwrap_or_else(|| panic!("no sample count in {summary:?}\n{hz_text}"));
    assert!(samples > 0, "{hz_text}");
    assert!(summary.contains("rejected 0"), "{hz_text}");

    // Every jumper image is 102 560 bytes (the list's figure), so `bw` sees exactly that.
    let bw = topic(&[
        "bw",
        "camera/jumper",
        "--run",
        &launch.run_id,
        "--duration-s",
        "3",
    ]);
    let bw_text = text(&bw);
    assert!(bw.status.success(), "{bw_text}");
    let stdout = String::from_utf8_lossy(&bw.stdout);
    let summary = stdout.lines().last().unwrap_or_default();
    assert!(
        summary.contains("mean 100.16 KiB min 100.16 KiB max 100.16 KiB per sample"),
        "{bw_text}"
    );
    assert!(summary.contains("rejected 0"), "{bw_text}");

    // `top` names every process from its heartbeats and its budget from the launch's config.
    let top = hopnav()
        .args([
            "top",
            "--run",
            &launch.run_id,
            "--duration-s",
            "3",
            "--no-redraw",
        ])
        .output()
        .expect("run hopnav top");
    let top_text = text(&top);
    assert!(top.status.success(), "{top_text}");
    let stdout = String::from_utf8_lossy(&top.stdout);
    let mapper = stdout
        .lines()
        .rev()
        .find(|line| line.starts_with("mapper "))
        .unwrap_or_else(|| panic!("no mapper row\n{top_text}"));
    // The columns end BUDGET, OVER, RESTARTS.
    let columns: Vec<&str> = mapper.split_whitespace().collect();
    assert_eq!(
        columns[columns.len() - 3],
        "15.00",
        "the mapper's budget: {top_text}"
    );

    // A name the launch does not have is a usage error that lists the topics it has.
    let unknown = topic(&["hz", "hopnav/camera/nothing", "--run", &launch.run_id]);
    assert_eq!(unknown.status.code(), Some(2), "{}", text(&unknown));
    assert!(
        String::from_utf8_lossy(&unknown.stderr).contains("hopnav/camera/jumper"),
        "{}",
        text(&unknown)
    );

    // A tool still watching when the launch stops sees it end and leaves in time for the
    // launch to remove its whole namespace.
    let mut watching = hopnav()
        .args(["topic", "hz", "hopnav/rover_vo/pose", "--run", &run])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn hz");
    let mut watching_stderr = std::io::BufReader::new(watching.stderr.take().expect("stderr"));
    let mut first_line = String::new();
    std::io::BufRead::read_line(&mut watching_stderr, &mut first_line).expect("hz stderr");
    assert!(first_line.starts_with("subscribed to"), "{first_line}");
    drop(launch);
    let status = wait_with_limit(&mut watching, Duration::from_secs(30)).expect("hz ends");
    let mut rest = String::new();
    let _ = std::io::Read::read_to_string(&mut watching_stderr, &mut rest);
    assert!(status.success(), "{rest}");
    assert!(rest.contains(&format!("launch {run} ended")), "{rest}");
    assert_eq!(report(&out, &run)["leftover_files"], 0);
    assert_no_leftover_files(&run);
}

#[test]
fn a_run_that_is_not_running_is_named() {
    let list = topic(&["list", "--run", "no-such-run-4242"]);
    let top = hopnav()
        .args(["top", "--run", "no-such-run-4242"])
        .output()
        .expect("run hopnav top");
    for output in [list, top] {
        assert_eq!(output.status.code(), Some(2), "{}", text(&output));
        assert!(
            String::from_utf8_lossy(&output.stderr).contains("no-such-run-4242"),
            "{}",
            text(&output)
        );
    }
}
