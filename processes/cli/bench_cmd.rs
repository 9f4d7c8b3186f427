//! `hopnav bench …`: benchmarks with their own harness.

use std::process::ExitCode;

use clap::Subcommand;

#[derive(Debug, Subcommand)]
pub enum BenchCommand {}

pub fn run(command: BenchCommand) -> ExitCode {
    match command {}
}
