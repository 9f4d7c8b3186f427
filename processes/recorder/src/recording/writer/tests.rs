use std::collections::BTreeMap;

use hopnav_ipc::messages::{ImageHeader, PoseEstimate};
use hopnav_ipc::wire;

use super::*;

const NO_FOXGLOVE: RecordingContent = RecordingContent {
    foxglove: false,
    images: true,
};

fn channels() -> Vec<ChannelSpec> {
    crate::recording::test_channels::pose_and_image()
}

fn pose(frame: u64, sequence: u64) -> PoseEstimate {
    let mut pose = PoseEstimate::default();
    pose.stamp.frame_index = frame;
    pose.stamp.sequence = sequence;
    pose.stamp.sim_time_ns = (frame + 1) * 100_000_000;
    pose.world_from_body.position_m = [frame as f64, 0.5, -1.0];
    pose
}

fn image(frame: u64, side_px: u32) -> (ImageHeader, Vec<u8>) {
    let mut header = ImageHeader::default();
    header.stamp.frame_index = frame;
    header.stamp.sequence = frame;
    header.stamp.sim_time_ns = (frame + 1) * 100_000_000;
    header.width_px = side_px;
    header.height_px = side_px;
    header.stride_bytes = side_px;
    header.view_count = 1;
    header.format = hopnav_ipc::messages::PixelFormat::Mono8.code();
    let pixels = (0..side_px * side_px).map(|i| (i % 251) as u8).collect();
    (header, pixels)
}

fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hopnav-recording-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn synthetic_messages_read_back_with_schemas_times_and_metadata() {
    let path = temp_path("synthetic.mcap");
    let metadata = [(
        "hopnav.build",
        BTreeMap::from([("commit".to_owned(), "abc123".to_owned())]),
    )];
    let mut recording =
        McapRecording::create(&path, &channels(), NO_FOXGLOVE, &metadata).expect("create");
    // Frames 0..5 of poses with frame 3 missing from the sequence; three images.
    for frame in [0, 1, 2, 4] {
        recording.record_message(0, &pose(frame, frame + 10));
    }
    for frame in 0..3 {
        let (header, pixels) = image(frame, 16);
        recording.record_slice(1, &header, &pixels);
    }
    let summary = recording.finish(&[0, 2]);
    assert_eq!(summary.error, None);
    assert_eq!(summary.channels[0].messages, 4);
    assert_eq!(summary.channels[0].missed, 1);
    assert_eq!(summary.channels[1].messages, 3);
    assert_eq!(summary.drops(), 3);
    let bytes = std::fs::read(&path).expect("read file");
    assert_eq!(summary.file_size_bytes, bytes.len() as u64);

    let mcap_summary = mcap::Summary::read(&bytes)
        .expect("summary")
        .expect("has a summary");
    let mut topics: Vec<_> = mcap_summary
        .channels
        .values()
        .map(|channel| {
            let schema = channel.schema.as_ref().expect("schema");
            (
                channel.topic.clone(),
                channel.message_encoding.clone(),
                schema.name.clone(),
            )
        })
        .collect();
    topics.sort();
    assert_eq!(
        topics,
        vec![
            (
                "hopnav/camera/jumper".to_owned(),
                "hopnav/repr-c".to_owned(),
                "hopnav.ImageHeader.v1+u8[]".to_owned()
            ),
            (
                "hopnav/rover_vo/pose".to_owned(),
                "hopnav/repr-c".to_owned(),
                "hopnav.PoseEstimate.v2".to_owned()
            ),
        ]
    );
    assert_eq!(mcap_summary.stats.expect("statistics").message_count, 7);
    assert_eq!(mcap_summary.metadata_indexes[0].name, "hopnav.build");

    let mut poses = Vec::new();
    let mut images = Vec::new();
    for message in mcap::MessageStream::new(&bytes).expect("stream") {
        let message = message.expect("valid message");
        assert_eq!(
            message.log_time,
            (u64::from(message.sequence) + 1) * 100_000_000
        );
        assert_eq!(message.publish_time, message.log_time);
        match message.channel.topic.as_str() {
            "hopnav/rover_vo/pose" => poses.push(wire::read::<PoseEstimate>(&message.data)),
            _ => images.push(wire::read_slice_sample::<ImageHeader, u8>(&message.data)),
        }
    }
    let expected: Vec<_> = [0, 1, 2, 4]
        .map(|frame| Some(pose(frame, frame + 10)))
        .into();
    assert_eq!(poses, expected);
    let (header, pixels) = image(2, 16);
    assert_eq!(images[2], Some((header, pixels)));
    let _ = std::fs::remove_file(&path);
}

#[test]
fn bad_paths_are_errors_that_name_the_path() {
    let missing = temp_path("no-such-folder").join("x.mcap");
    let error = check_writable(&missing).expect_err("missing folder");
    assert!(
        error.to_string().contains(&missing.display().to_string()),
        "{error}"
    );
    let error = McapRecording::create(&missing, &channels(), NO_FOXGLOVE, &[])
        .err()
        .expect("create fails");
    assert!(error.to_string().contains("no-such-folder"), "{error}");
    let folder = temp_path("");
    assert!(check_writable(&folder).is_err());
    // A writable path passes and is not left behind.
    let fresh = temp_path("fresh.mcap");
    let _ = std::fs::remove_file(&fresh);
    check_writable(&fresh).expect("writable");
    assert!(!fresh.exists());
}

/// A disk that fills up after `capacity_bytes`: later writes fail as on a full disk.
struct FillingDisk {
    bytes: std::io::Cursor<Vec<u8>>,
    capacity_bytes: u64,
}

impl std::io::Write for FillingDisk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.bytes.position() + buf.len() as u64 > self.capacity_bytes {
            return Err(std::io::ErrorKind::StorageFull.into());
        }
        self.bytes.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl std::io::Seek for FillingDisk {
    fn seek(&mut self, position: std::io::SeekFrom) -> std::io::Result<u64> {
        self.bytes.seek(position)
    }
}

#[test]
fn a_full_disk_stops_the_recording_with_an_error_not_a_panic() {
    let disk = FillingDisk {
        bytes: std::io::Cursor::new(Vec::new()),
        capacity_bytes: 2 << 20,
    };
    let path = Path::new("/full/disk.mcap");
    let mut recording =
        McapRecording::into_sink(path, disk, &channels(), NO_FOXGLOVE, &[]).expect("create");
    // 40 images of 100 kB do not fit in 2 MB, even compressed (the pixels are noise).
    let mut state = 0x2545_f491_u32;
    for frame in 0..40 {
        let (header, mut pixels) = image(frame, 320);
        for pixel in &mut pixels {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            *pixel = state as u8;
        }
        recording.record_slice(1, &header, &pixels);
    }
    assert!(!recording.is_writing());
    // Samples after the failure are not written, and nothing panics.
    recording.record_message(0, &pose(40, 1));
    let summary = recording.finish(&[0, 0]);
    let error = summary.error.expect("error");
    assert!(error.contains("/full/disk.mcap"), "{error}");
    assert!(error.contains("no storage space"), "{error}");
    assert!(summary.channels[1].messages < 40);
    assert_eq!(summary.channels[0].messages, 0);
}

#[test]
fn foxglove_messages_read_back_as_their_protobuf_types() {
    use foxglove::messages::{FrameTransforms, RawImage};
    use prost::Message as _;

    let path = temp_path("foxglove.mcap");
    let mut recording =
        McapRecording::create(&path, &channels(), RecordingContent::EVERYTHING, &[])
            .expect("create");
    assert!(recording.wants_foxglove(FoxgloveTopic::Transforms));
    let (header, pixels) = image(2, 8);
    for frame in 0..3 {
        let pose = pose(frame, frame);
        recording.record_message(0, &pose);
        let transforms = crate::recording::foxglove_view::estimate(&PoseEstimate {
            robot: hopnav_ipc::messages::Robot::Rover.code(),
            ..pose
        })
        .expect("a rover pose");
        recording.record_foxglove(FoxgloveTopic::Transforms, pose.stamp, &transforms);
    }
    let raw = crate::recording::foxglove_view::image(&header, &pixels, 0).expect("view");
    recording.record_foxglove(FoxgloveTopic::JumperImage, header.stamp, &raw);
    let summary = recording.finish(&[0, 0]);
    assert_eq!(summary.error, None);
    let count = |topic: &str| {
        summary
            .channels
            .iter()
            .find(|channel| channel.topic == topic)
            .map(|channel| (channel.schema.clone(), channel.messages))
    };
    assert_eq!(
        count("/foxglove/tf"),
        Some(("foxglove.FrameTransforms".into(), 3))
    );
    assert_eq!(count("/foxglove/map"), Some(("foxglove.Grid".into(), 0)));

    let bytes = std::fs::read(&path).expect("read file");
    let mut frames = Vec::new();
    for message in mcap::MessageStream::new(&bytes).expect("stream") {
        let message = message.expect("valid message");
        let schema = message.channel.schema.as_ref().expect("schema");
        match message.channel.topic.as_str() {
            "/foxglove/tf" => {
                assert_eq!(schema.encoding, "protobuf");
                let decoded = FrameTransforms::decode(&message.data[..]).expect("protobuf");
                let only = &decoded.transforms[0];
                assert_eq!(only.child_frame_id, "rover_vo");
                frames.push(only.translation.as_ref().map_or(-1.0, |t| t.x));
            }
            "/foxglove/jumper/image" => {
                let decoded = RawImage::decode(&message.data[..]).expect("protobuf");
                assert_eq!((decoded.width, decoded.encoding.as_str()), (8, "mono8"));
                assert_eq!(&decoded.data[..], &pixels[..]);
            }
            _ => {}
        }
    }
    assert_eq!(frames, [0.0, 1.0, 2.0]);
    std::fs::remove_file(&path).expect("cleanup");
}
