//! `hopnav launch --record FILE.mcap`: a lockstep launch records every frame of every topic
//! (and, beside them, Foxglove's messages of the images and frames), readable by the `mcap`
//! crate; a path that cannot be written stops the launch before it starts.

mod common;

use std::collections::BTreeMap;

use common::*;
use hopnav_ipc::messages::{ImageHeader, PoseEstimate};
use hopnav_ipc::wire;

const FRAMES: u64 = 30;

#[test]
fn lockstep_launch_records_every_frame_of_every_topic() {
    let out = out_dir("record");
    let run = run_id("record");
    let file = out.join("mission.mcap");
    let mut command = launch_command(&out, &run, &["--lockstep", "--frames", &FRAMES.to_string()]);
    let stdout = stdout_of_success(command.arg("--record").arg(&file), "hopnav launch");
    assert!(
        stdout.contains("record: ") && stdout.contains("drops 0 "),
        "{stdout}"
    );
    let report = report(&out, &run);
    assert_eq!(report["outcome"], "completed");
    assert_eq!(process(&report, "recorder")["restarts"], 0);

    let bytes = std::fs::read(&file).expect("recording");
    let summary = mcap::Summary::read(&bytes)
        .expect("summary section")
        .expect("has a summary");
    let mut schemas = BTreeMap::new();
    for channel in summary.channels.values() {
        let schema = channel.schema.as_ref().expect("every channel has a schema");
        if channel.topic.starts_with("/foxglove/") {
            assert_eq!(channel.message_encoding, "protobuf");
            assert!(schema.name.starts_with("foxglove."), "{}", schema.name);
        } else {
            assert_eq!(channel.message_encoding, wire::MESSAGE_ENCODING);
            assert!(schema.name.starts_with("hopnav."), "{}", schema.name);
        }
        schemas.insert(channel.topic.clone(), schema.name.clone());
    }
    assert_eq!(schemas["hopnav/rover_vo/pose"], "hopnav.PoseEstimate.v2");
    assert_eq!(
        schemas["hopnav/camera/jumper"],
        "hopnav.ImageHeader.v1+u8[]"
    );
    assert!(schemas.contains_key("hopnav/mapper/cells"), "{schemas:?}");
    assert!(schemas.contains_key("hopnav/planner/path"), "{schemas:?}");

    // Every message reads back (chunk CRCs checked) and decodes as its schema says.
    let mut counts: BTreeMap<String, u64> = BTreeMap::new();
    for message in mcap::MessageStream::new(&bytes).expect("message stream") {
        let message = message.expect("valid message");
        let topic = message.channel.topic.clone();
        match topic.as_str() {
            "hopnav/camera/jumper" | "hopnav/camera/rover_stereo" => {
                let (header, pixels) =
                    wire::read_slice_sample::<ImageHeader, u8>(&message.data).expect("image");
                assert_eq!(pixels.len(), header.expected_len_bytes());
                assert_eq!(u64::from(message.sequence), header.stamp.frame_index);
                assert_eq!(message.log_time, header.stamp.sim_time_ns);
            }
            "hopnav/jumper_vo/pose" | "hopnav/rover_vo/pose" => {
                let pose = wire::read::<PoseEstimate>(&message.data).expect("pose");
                assert!(pose.world_from_body.is_valid());
            }
            _ => {}
        }
        *counts.entry(topic).or_default() += 1;
    }
    for topic in [
        "hopnav/physics/body_states",
        "hopnav/camera/jumper",
        "hopnav/camera/rover_stereo",
        "hopnav/jumper_vo/pose",
        "hopnav/rover_vo/pose",
        // Beside them, Foxglove's messages: the same images, one per view ...
        "/foxglove/jumper/image",
        "/foxglove/rover/left_image",
        "/foxglove/rover/right_image",
    ] {
        assert_eq!(counts.get(topic), Some(&FRAMES), "{topic}: {counts:?}");
    }
    // ... and the frames: the truth and both estimates, every frame.
    assert_eq!(
        counts.get("/foxglove/tf"),
        Some(&(3 * FRAMES)),
        "{counts:?}"
    );
    assert_eq!(schemas["/foxglove/map"], "foxglove.Grid");

    let metadata: BTreeMap<_, _> = summary
        .metadata_indexes
        .iter()
        .map(|index| {
            let record = mcap::read::metadata(&bytes, index).expect("metadata");
            (record.name, record.metadata)
        })
        .collect();
    assert!(metadata["hopnav.launch"]["config_toml"].contains("[recorder]"));
    assert!(!metadata["hopnav.build"]["commit"].is_empty());
}

/// Channel topics of an MCAP file and their message counts (0 for an empty channel).
fn messages_per_channel(bytes: &[u8]) -> BTreeMap<String, u64> {
    let summary = mcap::Summary::read(bytes)
        .expect("summary section")
        .expect("has a summary");
    let stats = summary.stats.as_ref().expect("statistics");
    summary
        .channels
        .values()
        .map(|channel| {
            let count = stats
                .channel_message_counts
                .get(&channel.id)
                .copied()
                .unwrap_or(0);
            (channel.topic.clone(), count)
        })
        .collect()
}

#[test]
fn images_false_leaves_every_camera_channel_out_and_keeps_the_rest() {
    let out = out_dir("record-no-images");
    let run = run_id("record-no-images");
    let file = out.join("mission.mcap");
    let config = out.join("no-images.toml");
    std::fs::write(&config, "[recorder]\nimages = false\n").expect("config");
    let frames = 10;
    let mut command = launch_command(&out, &run, &["--lockstep", "--frames", &frames.to_string()]);
    let stdout = stdout_of_success(
        command.arg(&config).arg("--record").arg(&file),
        "hopnav launch",
    );
    assert!(stdout.contains("drops 0 "), "{stdout}");

    let counts = messages_per_channel(&std::fs::read(&file).expect("recording"));
    for image_topic in [
        "hopnav/camera/jumper",
        "hopnav/camera/rover_stereo",
        "/foxglove/jumper/image",
        "/foxglove/rover/left_image",
        "/foxglove/rover/right_image",
    ] {
        assert!(
            !counts.contains_key(image_topic),
            "{image_topic}: {counts:?}"
        );
    }
    for topic in [
        "hopnav/physics/body_states",
        "hopnav/jumper_vo/pose",
        "hopnav/rover_vo/pose",
    ] {
        assert_eq!(counts.get(topic), Some(&frames), "{topic}: {counts:?}");
    }
    assert_eq!(
        counts.get("/foxglove/tf"),
        Some(&(3 * frames)),
        "{counts:?}"
    );
    assert!(counts.contains_key("/foxglove/map"), "{counts:?}");
    assert!(counts.contains_key("hopnav/mapper/cells"), "{counts:?}");
}

#[test]
fn an_unwritable_record_path_is_refused_before_the_launch() {
    let out = out_dir("record-bad-path");
    let run = run_id("record-bad-path");
    let file = out.join("no-such-folder").join("x.mcap");
    let output = launch_command(&out, &run, &["--lockstep", "--frames", "3"])
        .arg("--record")
        .arg(&file)
        .output()
        .expect("run hopnav");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(&file.display().to_string()), "{stderr}");
    assert!(!out.join(&run).exists(), "nothing was started");
}
