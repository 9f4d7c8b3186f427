//! Shared memory and iceoryx2 bookkeeping of a launch are readable by their owner only.

mod common;

use std::os::unix::fs::PermissionsExt;
use std::time::Duration;

use common::*;

#[test]
fn shared_memory_is_not_readable_by_other_users() {
    let (out, run) = out_and_run("shm-perms");
    // Real time, so the launch is still running while we look.
    let mut child = spawn_launch(&out, &run, &[&probe_config(), "--frames", "40"]);
    let files = || leftover_files(&run);
    // Look once the graph runs. (iceoryx2 makes its per-namespace management segment
    // world-accessible on purpose the moment the supervisor creates its first node; the
    // supervisor takes that back right after, before it starts any child. The segment holds
    // a node counter, no data.)
    assert!(
        wait_until(Duration::from_secs(20), || {
            serving_pids_with_args(&["run", &run]).len() == 2
                && files().iter().any(|path| path.starts_with("/dev/shm"))
        }),
        "no shared memory appeared"
    );
    let mut checked = 0;
    for path in files() {
        let Ok(metadata) = std::fs::metadata(&path) else {
            continue; // removed meanwhile
        };
        let mode = metadata.permissions().mode();
        assert_eq!(
            mode & 0o077,
            0,
            "{} is accessible to group or others (mode {mode:o})",
            path.display()
        );
        checked += 1;
    }
    assert!(checked > 0);
    let status = wait_with_limit(&mut child, Duration::from_secs(60)).expect("launch finished");
    assert!(status.success());
}
