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
