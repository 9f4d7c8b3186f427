//! The recorder's lifecycle: open its outputs (dataset, recording, viewer) in `new`, append
//! each frame in `step`, finish them in `stop`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use hopnav_ipc::messages::FrameTick;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::transport::ZeroCopySend;
use hopnav_ipc::validate::{Message, SliceHeader};
use hopnav_ipc::wire::WireBytes;

use crate::dataset::Dataset;
use crate::foxglove_out::Outputs;
use crate::recording::{BUILD_COMMIT, McapRecording, RecordingContent};
use crate::taps::{MessageTap, SliceTap, Taps};
use crate::viewer::Viewer;
use crate::writers::io_error;
use crate::{RecorderError, RecordingError};

/// Reads every tapped topic each frame and writes it to a dataset folder, an MCAP recording
/// and/or the live viewer.
pub struct Recorder {
    taps: Taps,
    dataset: Option<Dataset>,
    outputs: Outputs,
    run_dir: PathBuf,
}

/// Runs `write` on the dataset, if there is one.
fn into_dataset(
    dataset: &mut Option<Dataset>,
    write: impl FnOnce(&mut Dataset) -> Result<(), RecorderError>,
) -> Result<(), RecorderError> {
    dataset.as_mut().map_or(Ok(()), write)
}

/// Records every pending message of `tap` and writes each into the dataset, if there is one.
fn into_dataset_per_message<M: Message + ZeroCopySend + WireBytes>(
    tap: &MessageTap<M>,
    outputs: &mut Outputs,
    dataset: &mut Option<Dataset>,
    write: fn(&mut Dataset, &M) -> Result<(), RecorderError>,
) -> Result<(), RecorderError> {
    tap.drain(outputs, |message| {
        into_dataset(dataset, |d| write(d, message))
    })
}

/// Writes one slice (header and elements) into the dataset.
type WriteSlice<H> =
    fn(&mut Dataset, &H, &[<H as SliceHeader>::Element]) -> Result<(), RecorderError>;

/// Records every pending slice of `tap` and writes each into the dataset, if there is one.
fn into_dataset_per_slice<H: SliceHeader + ZeroCopySend + WireBytes>(
    tap: &SliceTap<H>,
    outputs: &mut Outputs,
    dataset: &mut Option<Dataset>,
    write: WriteSlice<H>,
) -> Result<(), RecorderError>
where
    H::Element: ZeroCopySend + WireBytes,
{
    tap.drain(outputs, |slice| {
        into_dataset(dataset, |d| write(d, slice.header(), slice.elements()))
    })
}

/// The file a start of the recorder writes: a restarted recorder must not overwrite what its
/// predecessor recorded, so it writes `NAME.restartN.mcap` beside it.
fn recording_path(configured: &Path, incarnation: u32) -> PathBuf {
    if incarnation == 0 {
        return configured.to_owned();
    }
    let stem = configured
        .file_stem()
        .map_or_else(|| "recording".into(), |stem| stem.to_string_lossy());
    configured.with_file_name(format!("{stem}.restart{incarnation}.mcap"))
}

impl Recorder {
    /// A recorder writing a dataset into `dataset_dir`, an MCAP file to `mcap_path` and/or
    /// serving the live view on `viewer_address`.
    pub fn open(
        context: &ProcessContext,
        dataset_dir: Option<PathBuf>,
        mcap_path: Option<PathBuf>,
        content: RecordingContent,
        viewer_address: Option<&str>,
    ) -> Result<Self, RecorderError> {
        let identity = &context.identity;
        let (taps, channels) = Taps::open(context, content.images)?;
        let dataset = dataset_dir.map(Dataset::create).transpose()?;
        let recording = match mcap_path {
            Some(path) => {
                let config_toml = std::fs::read_to_string(&identity.config_path)
                    .map_err(io_error(&identity.config_path))?;
                let metadata = [
                    (
                        "hopnav.launch",
                        BTreeMap::from([
                            ("run_id".to_owned(), identity.run_id.clone()),
                            ("config_toml".to_owned(), config_toml),
                        ]),
                    ),
                    (
                        "hopnav.build",
                        BTreeMap::from([
                            ("commit".to_owned(), BUILD_COMMIT.to_owned()),
                            ("version".to_owned(), env!("CARGO_PKG_VERSION").to_owned()),
                        ]),
                    ),
                ];
                let path = recording_path(&path, identity.incarnation);
                Some(McapRecording::create(&path, &channels, content, &metadata)?)
            }
            None => None,
        };
        let viewer = viewer_address
            .map(Viewer::start)
            .transpose()
            .map_err(|error| RecorderError::Own(error.into()))?;
        if let Some(viewer) = &viewer {
            // The one line a user (or a test on port 0) needs to connect.
            eprintln!(
                "[{}] viewer: ws://{} (Foxglove: Open connection, Foxglove WebSocket)",
                identity.name,
                viewer.address()
            );
        }
        let run_dir = identity
            .config_path
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_owned);
        Ok(Self {
            taps,
            dataset,
            outputs: Outputs::new(recording, viewer),
            run_dir,
        })
    }
}

fn configured(value: &str) -> Option<PathBuf> {
    let value = value.trim();
    (!value.is_empty()).then(|| PathBuf::from(value))
}

impl Process for Recorder {
    type Error = RecorderError;

    fn new(context: &ProcessContext) -> Result<Self, RecorderError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        let dataset_dir = configured(&config.recorder.dir);
        let mcap_path = configured(&config.recorder.mcap);
        let viewer_address = config.recorder.viewer.trim();
        let viewer_address = (!viewer_address.is_empty()).then_some(viewer_address);
        if dataset_dir.is_none() && mcap_path.is_none() && viewer_address.is_none() {
            return Err(RecorderError::Own(RecordingError::NoOutput));
        }
        let content = RecordingContent {
            foxglove: config.recorder.foxglove,
            images: config.recorder.images,
        };
        Self::open(context, dataset_dir, mcap_path, content, viewer_address)
    }

    fn step(&mut self, _context: &ProcessContext, _tick: &FrameTick) -> Result<(), RecorderError> {
        let Self {
            taps,
            dataset,
            outputs,
            ..
        } = self;
        into_dataset_per_message(&taps.body_states, outputs, dataset, Dataset::body_states)?;
        into_dataset_per_message(&taps.altimeter, outputs, dataset, Dataset::altimeter)?;
        into_dataset_per_message(&taps.imu, outputs, dataset, Dataset::imu)?;
        taps.physics_state.drain(outputs, |_| Ok(()))?;
        taps.hop_launches.drain(outputs, |_| Ok(()))?;
        into_dataset_per_slice(&taps.jumper_images, outputs, dataset, Dataset::jumper_image)?;
        into_dataset_per_slice(&taps.rover_stereo, outputs, dataset, Dataset::rover_pair)?;
        into_dataset_per_message(&taps.jumper_poses, outputs, dataset, Dataset::jumper_pose)?;
        into_dataset_per_message(&taps.rover_poses, outputs, dataset, Dataset::rover_pose)?;
        into_dataset_per_slice(&taps.jumper_clouds, outputs, dataset, Dataset::cloud)?;
        into_dataset_per_slice(&taps.rover_clouds, outputs, dataset, Dataset::cloud)?;
        taps.map_updates.drain(outputs, |_| Ok(()))?;
        taps.map_snapshots.drain(outputs, |_| Ok(()))?;
        taps.paths.drain(outputs, |_| Ok(()))?;
        taps.drive_commands.drain(outputs, |_| Ok(()))?;
        taps.jump_requests.drain(outputs, |_| Ok(()))?;
        taps.control.drain(outputs, |_| Ok(()))?;
        // Flush the dataset every frame: a killed recorder loses at most the frame in
        // progress. The recording writes whole chunks as they fill.
        into_dataset(dataset, Dataset::flush_all)
    }

    fn rejected_samples(&self) -> u64 {
        self.taps.rejected_total()
    }

    fn stop(&mut self, context: &ProcessContext) {
        let name = &context.identity.name;
        if let Some(dataset) = &mut self.dataset {
            if let Err(error) = dataset.finish() {
                eprintln!("[{name}] {error}");
            }
            eprintln!("[{name}] {}", dataset.describe());
        }
        if let Some(viewer) = &mut self.outputs.viewer {
            viewer.stop();
        }
        if let Some(recording) = &mut self.outputs.recording {
            let summary = recording.finish(&self.taps.rejected_per_channel());
            if let Err(error) = summary.write_into(&self.run_dir) {
                eprintln!(
                    "[{name}] recording summary in {}: {error}",
                    self.run_dir.display()
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_restarted_recorder_writes_beside_the_first_file() {
        let configured = Path::new("/tmp/run/mission.mcap");
        assert_eq!(recording_path(configured, 0), configured);
        assert_eq!(
            recording_path(configured, 2),
            Path::new("/tmp/run/mission.restart2.mcap")
        );
    }
}
