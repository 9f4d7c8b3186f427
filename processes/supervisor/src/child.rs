//! Starting, signalling and reaping one child process.
//!
//! Children are the supervisor's own executable re-run as `hopnav run <name> …`. Each child
//! asks the kernel for SIGKILL when its parent dies (PR_SET_PDEATHSIG), so even a SIGKILL of
//! the supervisor leaves no orphan; std's `try_wait` reaps with waitpid, so no zombie lingers.

use std::io::Write as _;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Child, Command, Stdio};

use hopnav_ipc::process_loop::{PREPARED_FD, Promotion};

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
    /// Start a warm standby (`--standby`): it prepares, then waits for [`ChildProcess::promote`].
    pub standby: bool,
}

/// A running child.
#[derive(Debug)]
pub struct ChildProcess {
    child: Child,
    /// A standby's "prepared" pipe (read end, non-blocking) until it has said so.
    prepared_pipe: Option<std::fs::File>,
    /// A standby finished `prepare` (always true for other children).
    prepared: bool,
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
            .arg(spec.heartbeat_period_ms.to_string());
        if spec.standby {
            // The promotion arrives on stdin; its faults with it (the incarnation is unknown yet).
            command
                .arg("--standby")
                .stdin(Stdio::piped())
                .env_remove(hopnav_ipc::fault::FAULTS_ENV);
        } else {
            command.stdin(Stdio::null());
            match &spec.faults_env {
                Some(faults) => command.env(hopnav_ipc::fault::FAULTS_ENV, faults),
                None => command.env_remove(hopnav_ipc::fault::FAULTS_ENV),
            };
        }
        // Read before fork; the child compares it with getppid() after arming PDEATHSIG.
        let parent_pid = std::process::id() as libc::pid_t;
        let standby = spec.standby;
        // A standby says "prepared" on fd PREPARED_FD, the write end of this pipe.
        let pipe = if standby {
            Some(PreparedPipe::new()?)
        } else {
            None
        };
        let write_fd = pipe.as_ref().map_or(-1, |pipe| pipe.write_fd);
        // SAFETY: the closure runs in the forked child before exec and calls only
        // async-signal-safe functions (prctl, getppid, setsid, sched_setscheduler, fcntl, dup2,
        // _exit);
        // it touches no allocator or lock.
        unsafe {
            command.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // The parent may have died between fork and prctl: then nobody would kill us.
                if libc::getppid() != parent_pid {
                    libc::_exit(1);
                }
                // A session of its own: where the kernel groups CPU shares by session
                // (autogroup, the default on desktop kernels), each process of the graph then
                // weighs as much as the whole session that launched it, so a busy shell or
                // build beside the launch cannot crowd the frame out. It cannot fail in a
                // freshly forked child (not a group leader); if it did, the child would run
                // in the launcher's session as before. Ctrl-C reaches only the supervisor,
                // which stops the graph.
                libc::setsid();
                // A standby starts (exec, loading, preparing) at idle priority, so it never
                // takes CPU from the running graph; promotion restores the normal policy.
                if standby {
                    let param = libc::sched_param { sched_priority: 0 };
                    libc::sched_setscheduler(0, libc::SCHED_IDLE, &param);
                    // dup2 clears close-on-exec on the copy; if the pipe already is fd 3,
                    // clear it by hand.
                    let fd = PREPARED_FD;
                    let inherited = if write_fd == fd {
                        libc::fcntl(fd, libc::F_SETFD, 0)
                    } else {
                        libc::dup2(write_fd, fd)
                    };
                    if inherited < 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                }
                Ok(())
            });
        }
        let child = command.spawn()?;
        Ok(Self {
            child,
            prepared: pipe.is_none(),
            prepared_pipe: pipe.map(PreparedPipe::into_reader),
        })
    }

    /// True once a standby has finished `prepare` (always true for other children).
    pub fn is_prepared(&mut self) -> bool {
        if let Some(pipe) = self.prepared_pipe.as_mut() {
            let mut buffer = [0_u8; 16];
            match std::io::Read::read(pipe, &mut buffer) {
                Ok(read) if read > 0 => {
                    self.prepared = true;
                    self.prepared_pipe = None;
                }
                Ok(_) => self.prepared_pipe = None, // closed without a word: it died
                Err(_) => {}                        // nothing yet
            }
        }
        self.prepared
    }

    /// OS process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Promotes a standby: back to normal CPU priority (it prepared at SCHED_IDLE, and may
    /// not be done yet), then the promotion line on its stdin. Fails if it is not a standby
    /// or has died.
    pub fn promote(&mut self, promotion: &Promotion) -> std::io::Result<()> {
        restore_normal_priority(self.child.id());
        let Some(stdin) = self.child.stdin.as_mut() else {
            return Err(std::io::Error::other("not a standby"));
        };
        stdin.write_all(promotion.to_line().as_bytes())?;
        stdin.flush()?;
        // Close our end: the standby reads one line and never needs more.
        self.child.stdin = None;
        Ok(())
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

    /// Tells a standby it will not be needed: its stdin closes, and once prepared it ends
    /// cleanly (its node removed).
    pub fn retire(&mut self) {
        restore_normal_priority(self.child.id()); // so that it gets to the end soon
        self.child.stdin = None;
    }

    /// Kills and reaps a standby (the next clean-up removes its node).
    pub fn kill_and_reap(mut self) {
        restore_normal_priority(self.child.id()); // an idle-priority task may be slow to die
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The pipe a standby reports "prepared" on. Both ends are close-on-exec, so no other child
/// inherits them; the standby gets its own copy of the write end as fd [`PREPARED_FD`].
struct PreparedPipe {
    read_fd: libc::c_int,
    write_fd: libc::c_int,
}

impl PreparedPipe {
    fn new() -> std::io::Result<Self> {
        let mut fds = [-1; 2];
        // SAFETY: pipe2 writes two new descriptors into the two-element array we own.
        if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC | libc::O_NONBLOCK) } != 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(Self {
            read_fd: fds[0],
            write_fd: fds[1],
        })
    }

    /// Closes our write end (the standby has its copy) and keeps the read end.
    fn into_reader(self) -> std::fs::File {
        use std::os::fd::FromRawFd as _;
        let pipe = std::mem::ManuallyDrop::new(self);
        // SAFETY: both descriptors came from pipe2 and are owned by this value alone, which
        // is not dropped (ManuallyDrop), so each is closed or owned exactly once.
        unsafe {
            libc::close(pipe.write_fd);
            std::fs::File::from_raw_fd(pipe.read_fd)
        }
    }
}

impl Drop for PreparedPipe {
    fn drop(&mut self) {
        // SAFETY: closes the two descriptors this value owns (spawn failed before handing
        // them on).
        unsafe {
            libc::close(self.read_fd);
            libc::close(self.write_fd);
        }
    }
}

/// Puts every thread of `pid` back on the normal scheduling policy (a standby's threads run
/// at SCHED_IDLE while they prepare; after promotion they must not starve).
fn restore_normal_priority(pid: u32) {
    let param = libc::sched_param { sched_priority: 0 };
    for (tid, _) in crate::progress::threads_of(pid) {
        // SAFETY: sched_setscheduler with a thread id of our own unreaped child and a valid
        // sched_param; it only changes that thread's scheduling, and fails harmlessly if the
        // thread has just exited.
        unsafe {
            libc::sched_setscheduler(tid, libc::SCHED_OTHER, &param);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn a_child_runs_in_a_session_of_its_own() {
        // A stand-in for the hopnav executable that ignores its arguments and waits.
        let dir = std::env::temp_dir().join(format!("hopnav-child-session-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let script = dir.join("fake-hopnav");
        std::fs::write(&script, "#!/bin/sh\nexec sleep 30\n").unwrap();
        std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
        let spec = ChildSpec {
            executable: &script,
            name: "mapper",
            run_id: "session-test",
            slot: 0,
            incarnation: 0,
            config_path: &dir,
            heartbeat_period_ms: 100,
            faults_env: None,
            standby: false,
        };
        let child = ChildProcess::spawn(&spec).unwrap();
        let pid = child.pid() as libc::pid_t;
        // SAFETY: getsid only reads the session id of a process.
        let (ours, its) = unsafe { (libc::getsid(0), libc::getsid(pid)) };
        child.kill_and_reap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(its, pid, "the child leads its own session");
        assert_ne!(its, ours);
    }
}
