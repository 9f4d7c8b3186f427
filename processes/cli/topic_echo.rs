//! `hopnav topic echo TOPIC`: the samples of one topic of a running launch, readable.

use std::ops::ControlFlow;
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use hopnav_ipc::live::{self, TapSample, WatchEnd, Watcher};

use crate::topic_cmd::{RunChoice, watch_failed};

#[derive(Debug, Args)]
pub struct EchoArgs {
    /// Topic name, e.g. hopnav/rover_vo/pose (the hopnav/ prefix may be left out).
    topic: String,
    /// Stop after this many samples.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..))]
    count: u64,
    #[command(flatten)]
    run: RunChoice,
}

pub fn run(args: &EchoArgs) -> ExitCode {
    let (namespace, topic) = match args.run.topic(&args.topic) {
        Ok(found) => found,
        Err(code) => return code,
    };
    let mut printer = Printer {
        topic: topic.spec.name.to_string(),
        printed: 0,
        count: args.count,
    };
    // Ticks check the count (and that the launch still runs) a few times a second.
    let watched = live::watch(&namespace, &topic, Duration::from_millis(200), &mut printer);
    match watched {
        Ok((WatchEnd::Stopped | WatchEnd::LaunchEnded, _)) => ExitCode::SUCCESS,
        Ok((WatchEnd::Interrupted, _)) => ExitCode::from(crate::EXIT_INTERRUPTED),
        Err(error) => watch_failed(&namespace, &args.topic, error),
    }
}

/// Prints the first `count` samples.
struct Printer {
    topic: String,
    printed: u64,
    count: u64,
}

impl Watcher for Printer {
    fn on_sample(&mut self, sample: &dyn TapSample, _arrival_ns: u64) {
        if self.printed < self.count {
            self.printed += 1;
            println!("--- {} sample {}", self.topic, self.printed);
            println!("{}", sample.describe());
        }
    }

    fn on_tick(&mut self, _now_ns: u64) -> ControlFlow<()> {
        if self.printed >= self.count {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}
