//! SIGINT and SIGTERM: iceoryx2's signal handler records them, and every WaitSet of the
//! supervisor and its children reports them as a termination request. Commands that run many
//! launches (`hopnav compare`, `hopnav chaos`) also ask between launches, so Ctrl-C stops the
//! whole command rather than only the launch it hit.

use iceoryx2_bb_posix::signal::SignalHandler;

/// True if SIGINT or SIGTERM arrived since the last ask (the request is consumed). The first
/// call installs iceoryx2's handler, after which these signals no longer kill the process.
pub fn termination_requested() -> bool {
    SignalHandler::termination_requested()
}

extern "C" fn on_child_exit(_signal: libc::c_int) {}

/// Installs a no-op SIGCHLD handler (once per process), so a child's death interrupts the
/// supervisor's wait at once instead of at its next housekeeping tick: a crash is noticed,
/// and the restart begins, within microseconds. SA_NOCLDSTOP: a stopped child is the
/// watchdog's business. SA_RESTART: other system calls carry on.
pub fn wake_on_child_exit() {
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    INSTALLED.call_once(|| {
        // SAFETY: sigaction with a zeroed, then filled, sigaction struct we own; the handler
        // does nothing, so it is async-signal-safe. The previous action (the default, which
        // ignores SIGCHLD) is not needed back.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_child_exit as extern "C" fn(libc::c_int) as usize;
            action.sa_flags = libc::SA_NOCLDSTOP | libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            if libc::sigaction(libc::SIGCHLD, &action, std::ptr::null_mut()) != 0 {
                eprintln!(
                    "warning: no SIGCHLD handler ({}); child exits are noticed by polling",
                    std::io::Error::last_os_error()
                );
            }
        }
    });
}
