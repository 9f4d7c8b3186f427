use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::PathBuf;

use hopnav_ipc::messages::{ImageHeader, PixelFormat, PoseEstimate};
use hopnav_ipc::wire;

use super::*;
use crate::recording::{McapRecording, RecordingContent};

const FRAMES: u64 = 12;

fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hopnav-inspect-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// A recording as the recorder writes it: a pose and a (noisy, incompressible) image channel
/// with `FRAMES` messages each, the Foxglove channels, and hopnav's metadata.
fn recording_bytes() -> Vec<u8> {
    recording_of(FRAMES, 64, RecordingContent::EVERYTHING)
}

/// A recording of `frames` poses and `side_px`² images, with `content`'s Foxglove channels.
fn recording_of(frames: u64, side_px: u32, content: RecordingContent) -> Vec<u8> {
    let path = temp_path(&format!("valid-{:?}.mcap", std::thread::current().id()));
    let channels = crate::recording::test_channels::pose_and_image();
    let metadata = [(
        "hopnav.build",
        BTreeMap::from([("commit".to_owned(), "abc123".to_owned())]),
    )];
    let mut recording =
        McapRecording::create(&path, &channels, content, &metadata).expect("create");
    let mut noise = 0x2545_f491_u32;
    for frame in 0..frames {
        let mut pose = PoseEstimate::default();
        pose.stamp.frame_index = frame;
        pose.stamp.sequence = frame;
        pose.stamp.sim_time_ns = (frame + 1) * 100_000_000;
        recording.record_message(0, &pose);
        let header = ImageHeader {
            stamp: pose.stamp,
            width_px: side_px,
            height_px: side_px,
            stride_bytes: side_px,
            view_count: 1,
            format: PixelFormat::Mono8.code(),
            ..ImageHeader::default()
        };
        let pixels: Vec<u8> = (0..side_px * side_px)
            .map(|_| {
                noise ^= noise << 13;
                noise ^= noise >> 17;
                noise ^= noise << 5;
                noise as u8
            })
            .collect();
        recording.record_slice(1, &header, &pixels);
    }
    let summary = recording.finish(&[0, 0]);
    assert_eq!(summary.error, None);
    let bytes = std::fs::read(&path).expect("read back");
    let _ = std::fs::remove_file(&path);
    bytes
}

/// The fuzz target's seed (`fuzz/seeds/recording_inspect/`): a tiny recording.
const FUZZ_SEED: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../fuzz/seeds/recording_inspect/tiny.mcap"
);

fn tiny_recording() -> Vec<u8> {
    let content = RecordingContent {
        foxglove: false,
        images: true,
    };
    recording_of(3, 4, content)
}

#[test]
#[ignore = "writes the fuzz seed; run after a layout version changes"]
fn write_fuzz_seed() {
    std::fs::write(FUZZ_SEED, tiny_recording()).expect("write the fuzz seed");
}

#[test]
fn the_fuzz_seed_is_a_recording_this_build_reads() {
    let seed = std::fs::read(FUZZ_SEED).expect("the fuzz seed");
    let info = inspect(&seed, Depth::EveryMessage).expect(
        "a recording this build reads; after a layout change run \
         `cargo test -p hopnav-recorder -- --ignored write_fuzz_seed`",
    );
    assert_eq!(info.messages, 6);
}

/// An MCAP file with `profile` and one channel of `encoding` messages under `schema`.
fn other_mcap(profile: &str, schema: &str, encoding: &str) -> Vec<u8> {
    let mut bytes = Cursor::new(Vec::new());
    {
        let mut writer = mcap::WriteOptions::new()
            .profile(profile)
            .create(&mut bytes)
            .expect("writer");
        let schema_id = writer
            .add_schema(schema, "hopnav/layout", b"")
            .expect("schema");
        let channel = writer
            .add_channel(
                schema_id,
                "hopnav/rover_vo/pose",
                encoding,
                &BTreeMap::new(),
            )
            .expect("channel");
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: 0,
            log_time: 1,
            publish_time: 1,
        };
        writer
            .write_to_known_channel(&header, &[0; 8])
            .expect("message");
        writer.finish().expect("finish");
    }
    bytes.into_inner()
}

#[test]
fn a_recording_reads_back_with_channels_counts_span_and_metadata() {
    let bytes = recording_bytes();
    for depth in [Depth::Summary, Depth::EveryMessage] {
        let info = inspect(&bytes, depth).expect("valid recording");
        assert_eq!(info.every_message_read, depth == Depth::EveryMessage);
        assert_eq!(info.size_bytes, bytes.len() as u64);
        assert_eq!(info.messages, 2 * FRAMES);
        assert_eq!(info.span_ns, Some((100_000_000, FRAMES * 100_000_000)));
        assert!((info.duration_s() - 1.1).abs() < 1e-9);
        assert_eq!(
            info.metadata_entry("hopnav.build", "commit"),
            Some("abc123")
        );
        let pose = info
            .channels
            .iter()
            .find(|channel| channel.topic == "hopnav/rover_vo/pose")
            .expect("pose channel");
        assert_eq!(pose.schema, "hopnav.PoseEstimate.v2");
        assert_eq!(pose.schema_encoding, wire::SCHEMA_ENCODING);
        assert_eq!(pose.message_encoding, wire::MESSAGE_ENCODING);
        assert_eq!(pose.messages, FRAMES);
        // The Foxglove channels are listed, empty, with their protobuf schemas.
        let map = info
            .channels
            .iter()
            .find(|channel| channel.topic == "/foxglove/map")
            .expect("map channel");
        assert_eq!((map.schema.as_str(), map.messages), ("foxglove.Grid", 0));
        assert_eq!(info.channels.len(), 2 + 8);
    }
}

#[test]
fn a_truncated_recording_is_named_truncated_at_any_length() {
    let bytes = recording_bytes();
    for length in [9, 100, bytes.len() / 2, bytes.len() - 1] {
        let error = inspect(&bytes[..length], Depth::EveryMessage).expect_err("truncated");
        assert!(
            matches!(error, InspectError::Truncated { size_bytes } if size_bytes == length as u64),
            "{length}: {error}"
        );
        assert!(error.to_string().contains("truncated"), "{error}");
    }
}

#[test]
fn corrupt_chunk_bytes_fail_the_full_read_as_corrupt() {
    let mut bytes = recording_bytes();
    // The middle of the file lies in the image chunks' compressed pixels.
    let middle = bytes.len() / 2;
    for byte in &mut bytes[middle..middle + 16] {
        *byte ^= 0xa5;
    }
    let error = inspect(&bytes, Depth::EveryMessage).expect_err("corrupt");
    assert!(matches!(error, InspectError::Corrupt { .. }), "{error}");
    assert!(error.to_string().starts_with("corrupt: "), "{error}");
}

#[test]
fn a_foreign_file_is_not_mcap() {
    for bytes in [&b""[..], b"P5\n64 64\n255\n", b"\x89PNG\r\n\x1a\n0000"] {
        let error = inspect(bytes, Depth::EveryMessage).expect_err("foreign");
        assert!(matches!(error, InspectError::NotMcap), "{error}");
        assert!(error.to_string().contains("not an MCAP file"), "{error}");
    }
}

#[test]
fn an_mcap_file_of_another_profile_is_not_a_hopnav_recording() {
    let bytes = other_mcap("ros2", "hopnav.PoseEstimate.v2", "cdr");
    let error = inspect(&bytes, Depth::EveryMessage).expect_err("foreign");
    assert!(
        matches!(&error, InspectError::NotHopnav { profile } if profile == "ros2"),
        "{error}"
    );
}

#[test]
fn a_recording_of_another_message_version_names_type_and_both_versions() {
    let bytes = other_mcap(PROFILE, "hopnav.PoseEstimate.v1", wire::MESSAGE_ENCODING);
    let error = inspect(&bytes, Depth::Summary).expect_err("old layout");
    let text = error.to_string();
    assert!(
        text.contains("hopnav/rover_vo/pose")
            && text.contains("PoseEstimate layout v1")
            && text.contains("reads v2"),
        "{text}"
    );
    let bytes = other_mcap(PROFILE, "hopnav.Teapot.v1", wire::MESSAGE_ENCODING);
    let error = inspect(&bytes, Depth::Summary).expect_err("unknown type");
    assert!(
        matches!(error, InspectError::UnknownSchema { .. }),
        "{error}"
    );
}

#[test]
fn a_missing_file_is_an_error_naming_it() {
    let path = temp_path("no-such.mcap");
    let error = inspect_file(&path, Depth::Summary).expect_err("missing");
    assert!(error.to_string().contains("no-such.mcap"), "{error}");
}

#[test]
fn inputs_the_fuzzer_found_give_an_answer_not_a_panic() {
    // A 4 GiB string in a header, a record overrunning its uncompressed chunk, and summary
    // counts whose sum overflows (fuzz/seeds/recording_inspect/found-*.mcap).
    let seeds = std::path::Path::new(FUZZ_SEED).with_file_name("");
    let mut found = 0;
    for entry in std::fs::read_dir(&seeds).expect("seed folder") {
        let path = entry.expect("entry").path();
        if !path.to_string_lossy().contains("found-") {
            continue;
        }
        let bytes = std::fs::read(&path).expect("seed");
        for depth in [Depth::Summary, Depth::EveryMessage] {
            if let Err(error) = inspect(&bytes, depth) {
                assert!(!error.to_string().is_empty(), "{}", path.display());
            }
        }
        found += 1;
    }
    assert_eq!(found, 3);
}
