//! The live status line: one line rewritten in place on a terminal, a line every few seconds
//! in a log.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Prints the status at a rate that suits where stderr goes.
#[derive(Debug)]
pub struct StatusLine {
    enabled: bool,
    terminal: bool,
    interval: Duration,
    last_print: Option<Instant>,
}

impl StatusLine {
    /// A status line on stderr (`enabled = false` silences it).
    pub fn new(enabled: bool) -> Self {
        let terminal = std::io::stderr().is_terminal();
        Self {
            enabled,
            terminal,
            interval: if terminal {
                Duration::from_millis(200)
            } else {
                Duration::from_secs(5)
            },
            last_print: None,
        }
    }

    /// Prints `text` if the interval passed (or `force`).
    pub fn update(&mut self, force: bool, text: impl FnOnce() -> String) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if !force
            && self
                .last_print
                .is_some_and(|last| now.duration_since(last) < self.interval)
        {
            return;
        }
        self.last_print = Some(now);
        let mut stderr = std::io::stderr().lock();
        if self.terminal {
            let _ = write!(stderr, "\r\x1b[2K{}", text());
        } else {
            let _ = writeln!(stderr, "{}", text());
        }
        let _ = stderr.flush();
    }

    /// Ends the line on a terminal so later output starts fresh.
    pub fn finish(&mut self) {
        if self.enabled && self.terminal && self.last_print.is_some() {
            eprintln!();
        }
    }
}
