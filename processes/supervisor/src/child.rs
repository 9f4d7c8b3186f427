//! Starting, signalling and reaping one child process.
//!
//! Children are the supervisor's own executable re-run as `hopnav run <name> …`. Each child
//! asks the kernel for SIGKILL when its parent dies (PR_SET_PDEATHSIG), so even a SIGKILL of
//! the supervisor leaves no orphan; std's `try_wait` reaps with waitpid, so no zombie lingers.

use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Child, Command, Stdio};

use crate::restart::ExitKind;

/// Everything a child needs on its command line.
#[derive(Debug, Clone)]
pub struct ChildSpec<'a> {
    /// The hopnav executable.
    pub executable: &'a Path,
    /// Process name (`hopnav run <name>`).
    pub name: &'a str,
    /// Launch run id.
    pub run_id: &'a str,
    /// Slot in the process table.
    pub slot: usize,
    /// Starts of this slot before this one.
    pub incarnation: u32,
    /// Resolved configuration file.
    pub config_path: &'a Path,
    /// Idle heartbeat period.
    pub heartbeat_period_ms: u64,
    /// In-process faults for this child (`HOPNAV_FAULTS`), if any.
    pub faults_env: Option<String>,
}

/// A running child.
#[derive(Debug)]
pub struct ChildProcess {
    child: Child,
}

impl ChildProcess {
    /// Starts the child.
    pub fn spawn(spec: &ChildSpec<'_>) -> std::io::Result<Self> {
        let mut command = Command::new(spec.executable);
        command
            .arg("run")
            .arg(spec.name)
            .arg("--run-id")
            .arg(spec.run_id)
            .arg("--slot")
            .arg(spec.slot.to_string())
            .arg("--incarnation")
            .arg(spec.incarnation.to_string())
            .arg("--config")
            .arg(spec.config_path)
            .arg("--heartbeat-ms")
            .arg(spec.heartbeat_period_ms.to_string())
            .stdin(Stdio::null());
        match &spec.faults_env {
            Some(faults) => command.env(hopnav_ipc::fault::FAULTS_ENV, faults),
            None => command.env_remove(hopnav_ipc::fault::FAULTS_ENV),
        };
        // Read before fork; the child compares it with getppid() after arming PDEATHSIG.
        let parent_pid = std::process::id() as libc::pid_t;
        // SAFETY: the closure runs in the forked child before exec and calls only
        // async-signal-safe functions (prctl, getppid, _exit); it touches no allocator or lock.
        unsafe {
            command.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // The parent may have died between fork and prctl: then nobody would kill us.
                if libc::getppid() != parent_pid {
                    libc::_exit(1);
                }
                Ok(())
            });
        }
        Ok(Self {
            child: command.spawn()?,
        })
    }

    /// OS process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// How the child ended, if it has (reaps it); `None` while it runs.
    pub fn try_reap(&mut self) -> Option<ExitKind> {
        match self.child.try_wait() {
            Ok(Some(status)) => Some(match (status.code(), status.signal()) {
                (Some(0), _) => ExitKind::Clean,
                (Some(code), _) => ExitKind::Failed(code),
                (None, Some(signal)) => ExitKind::Signaled(signal),
                (None, None) => ExitKind::Failed(-1),
            }),
            Ok(None) => None,
            // ECHILD: already reaped elsewhere; treat as gone.
            Err(_) => Some(ExitKind::Failed(-1)),
        }
    }

    /// Asks the child to stop (SIGTERM).
    pub fn terminate(&self) {
        // SAFETY: kill with a pid we spawned and have not reaped, so it cannot name another
        // process; a failure only means it is already gone.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
    }

    /// Kills the child (SIGKILL); it still has to be reaped.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
    }
}
