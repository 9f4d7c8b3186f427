//! Removes the shared-memory resources of dead children off the supervisor's loop.
//!
//! A dead node's ports count against its topics' limits until removed, and removing them
//! opens every service the node used: tens of milliseconds on a loaded machine. Done inline,
//! that delayed every restart; on this thread it runs while the restarted process starts.
//! iceoryx2 lets any process (or thread) clean a dead node at any time.

use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use hopnav_ipc::namespace::Namespace;

/// The clean-up thread of one launch.
pub struct Janitor {
    requests: Option<Sender<()>>,
    thread: Option<JoinHandle<()>>,
    /// Cleans inline when no thread could be started.
    inline: Namespace,
}

impl Janitor {
    /// Starts the thread (without one, requests are served inline).
    pub fn start(namespace: Namespace) -> Self {
        let (requests, inbox) = channel::<()>();
        let worker = namespace.clone();
        let thread = std::thread::Builder::new()
            .name("janitor".into())
            .spawn(move || serve(&worker, &inbox))
            .map_err(|error| eprintln!("warning: no clean-up thread ({error}); cleaning inline"))
            .ok();
        Self {
            requests: thread.is_some().then_some(requests),
            thread,
            inline: namespace,
        }
    }

    /// Asks for the dead nodes to be removed (soon, not now).
    pub fn sweep(&self) {
        match &self.requests {
            Some(requests) => {
                let _ = requests.send(());
            }
            None => {
                self.inline.remove_dead_nodes();
            }
        }
    }
}

impl Drop for Janitor {
    fn drop(&mut self) {
        self.requests = None; // the thread finishes what is queued and ends
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn serve(namespace: &Namespace, inbox: &Receiver<()>) {
    while inbox.recv().is_ok() {
        while inbox.try_recv().is_ok() {} // one sweep covers every request queued so far
        namespace.remove_dead_nodes();
    }
}
