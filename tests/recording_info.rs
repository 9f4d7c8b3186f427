//! `hopnav recording info FILE.mcap`: a recording of a short lockstep launch is summarised;
//! a damaged or foreign file is refused with exit code 1 and a message naming the problem.

mod common;

use std::path::Path;
use std::process::Output;

use common::*;

fn recording_info(file: &Path, options: &[&str]) -> Output {
    hopnav()
        .args(["recording", "info"])
        .arg(file)
        .args(options)
        .output()
        .expect("run hopnav recording info")
}

#[test]
fn a_recording_is_summarised_and_a_damaged_copy_is_refused() {
    let out = out_dir("recording-info");
    let run = run_id("recording-info");
    let file = out.join("mission.mcap");
    let mut command = launch_command(&out, &run, &["--lockstep", "--frames", "5"]);
    stdout_of_success(command.arg("--record").arg(&file), "hopnav launch");

    let output = recording_info(&file, &["--json"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    let info: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(info["every_message_read"], true);
    assert_eq!(info["metadata"]["hopnav.launch"]["run_id"], run.as_str());
    let channels = info["channels"].as_array().expect("channels");
    let pose = channels
        .iter()
        .find(|channel| channel["topic"] == "hopnav/rover_vo/pose")
        .expect("pose channel");
    assert_eq!(pose["schema"], "hopnav.PoseEstimate.v2");
    assert_eq!(pose["messages"], 5);

    let output = recording_info(&file, &["--summary-only"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    assert!(stdout.contains("hopnav/camera/jumper"), "{stdout}");
    assert!(stdout.contains("from the summary section"), "{stdout}");

    let bytes = std::fs::read(&file).expect("recording");
    let truncated = out.join("truncated.mcap");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).expect("truncated copy");
    let output = recording_info(&truncated, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("truncated.mcap") && stderr.contains("truncated: the file ends"),
        "{stderr}"
    );

    let foreign = out.join("config.toml");
    std::fs::write(&foreign, "[run]\n").expect("foreign file");
    let output = recording_info(&foreign, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("not an MCAP file"), "{stderr}");
}

#[test]
fn help_explains_every_option() {
    let output = hopnav()
        .args(["recording", "info", "--help"])
        .output()
        .expect("run hopnav");
    let help = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{help}");
    for option in ["--summary-only", "--json", "--config", "FILE.mcap"] {
        assert!(help.contains(option), "{option}: {help}");
    }
}
