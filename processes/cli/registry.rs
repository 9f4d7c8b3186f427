//! Which processes this binary can run, by name.

use hopnav_ipc::process_loop::{
    LoopError, LoopExit, ProcessIdentity, StartMode, run_process_with as run_process,
};

type Entry = fn(ProcessIdentity, StartMode) -> Result<LoopExit, LoopError>;

/// Every runnable process: name and entry point.
pub const PROCESSES: &[(&str, Entry)] = &[
    ("probe_source", run_process::<hopnav_probe::ProbeSource>),
    ("probe_sink", run_process::<hopnav_probe::ProbeSink>),
    ("recorder", run_process::<hopnav_recorder::Recorder>),
    ("camera", run_process::<hopnav_camera_node::CameraProcess>),
    (
        "physics",
        run_process::<hopnav_physics_node::PhysicsProcess>,
    ),
    (
        "jumper_vo",
        run_process::<hopnav_jumper_vo_node::JumperVoProcess>,
    ),
    (
        "planner",
        run_process::<hopnav_planner_node::PlannerProcess>,
    ),
    ("mapper", run_process::<hopnav_mapper_node::MapperProcess>),
    (
        "rover_vo",
        run_process::<hopnav_rover_vo_node::RoverVoProcess>,
    ),
];

/// A process library's config table and its validator.
type SectionCheck = fn(&hopnav_config::HopnavConfig) -> Result<(), hopnav_config::ConfigError>;

/// Every process-specific config table, with the check its library provides.
pub const SECTIONS: &[(&str, SectionCheck)] = &[
    ("world", |config| {
        hopnav_camera::check_world_section(config).map(|_| ())
    }),
    ("camera", |config| {
        hopnav_camera::CameraSection::from_config(config).map(|_| ())
    }),
    ("physics", |config| {
        hopnav_physics_node::physics_section(config).map(|_| ())
    }),
    ("jumper_vo", |config| {
        hopnav_jumper_vo_node::jumper_vo_section(config).map(|_| ())
    }),
    ("planner", |config| {
        hopnav_planner_node::planner_section(config).map(|_| ())
    }),
    ("mapper", |config| {
        hopnav_mapper::config::mapper_section(config).map(|_| ())
    }),
    ("rover_vo", |config| {
        hopnav_rover_vo_node::rover_vo_section(config).map(|_| ())
    }),
];

/// Validates every process-specific table; unknown tables are errors.
pub fn check_sections(
    config: &hopnav_config::HopnavConfig,
) -> Result<(), hopnav_config::ConfigError> {
    let known: Vec<&str> = SECTIONS.iter().map(|(name, _)| *name).collect();
    hopnav_config::check_section_names(config, &known)?;
    SECTIONS.iter().try_for_each(|(_, check)| check(config))
}

/// The entry point of `name`.
pub fn find(name: &str) -> Option<Entry> {
    PROCESSES
        .iter()
        .find(|(known, _)| *known == name)
        .map(|(_, entry)| *entry)
}

/// All names, for validation and help.
pub fn names() -> Vec<String> {
    PROCESSES
        .iter()
        .map(|(name, _)| (*name).to_owned())
        .collect()
}
