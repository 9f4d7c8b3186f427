//! How the event-driven subscriber halves sleep: a WaitSet on the data's listener, waited on
//! with the harness's timeout.

use std::time::Duration;

use hopnav_ipc::IpcService;
use iceoryx2::prelude::{CallbackProgression, WaitSet, WaitSetBuilder};

use crate::BenchError;

/// How long a subscriber sleeps for a wake-up before the run counts as stuck.
const WAKE_TIMEOUT: Duration = Duration::from_secs(10);

/// A WaitSet for the subscriber half to attach its listener to.
pub(crate) fn waitset() -> Result<WaitSet<IpcService>, BenchError> {
    WaitSetBuilder::new()
        .create::<IpcService>()
        .map_err(|e| BenchError::transport("waitset", e))
}

/// Sleeps until an attached listener fires (or the timeout passes).
pub(crate) fn wait_for_wakeup(waitset: &WaitSet<IpcService>) -> Result<(), BenchError> {
    waitset
        .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, WAKE_TIMEOUT)
        .map_err(|e| BenchError::transport("wait", e))?;
    Ok(())
}
