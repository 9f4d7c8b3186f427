//! The physics process over real iceoryx2 ports in an isolated namespace, with the test in the
//! supervisor's place (it relays the state topic to the resume topic): a restarted physics
//! continues the simulation from the last state the killed one published, and one handed a
//! corrupt or impossible state says so and starts over at t = 0 instead of failing.

use hopnav_config::parse_section;
use hopnav_ipc::messages::{BodyStates, PhysicsState};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, Subscriber};
use hopnav_physics::{FrameInputs, FrameOutputs, PhysicsSim};
use hopnav_physics_node::{PhysicsProcess, physics_section};
use hopnav_world::{World, WorldConfig};

#[path = "../../../../ipc/tests/support/node_harness.rs"]
mod node_harness;

use node_harness::{PERIOD_NS, run_dir_with_config, tick};

fn context(namespace: &Namespace, run_dir: &std::path::Path, incarnation: u32) -> ProcessContext {
    node_harness::context(namespace, run_dir, "physics", incarnation)
}

/// The supervisor's part: the newest state sample, republished on the resume topic.
struct Relay {
    from: Subscriber<PhysicsState>,
    to: Publisher<PhysicsState>,
    last: Option<PhysicsState>,
}

impl Relay {
    fn forward(&mut self) {
        if let Some(state) = self.from.receive_latest().expect("receive state") {
            self.to.send(state).expect("relay");
            self.last = Some(state);
        }
    }
}

/// A restarted physics (incarnation `incarnation`) handed the resume topic's history, after
/// its first frame `frame_index`: the body states it published.
fn restart_and_step(
    namespace: &Namespace,
    run_dir: &std::path::Path,
    relay: &Relay,
    body_states: &Subscriber<BodyStates>,
    incarnation: u32,
    frame_index: u64,
) -> (BodyStates, u64) {
    let context = context(namespace, run_dir, incarnation);
    let mut physics = PhysicsProcess::new(&context).expect("new");
    // As the supervisor does when the restarted process reports ready.
    relay.to.update_connections().expect("hand over");
    physics
        .step(&context, &tick(frame_index))
        .expect("a bad resume sample is no error");
    let states = body_states
        .receive_latest()
        .expect("receive")
        .expect("body states");
    (states, physics.rejected_samples())
}

/// The uninterrupted reference: the same world, configuration and seed, no inputs, for
/// `frames` frames.
fn uninterrupted_reference(
    config: &hopnav_config::HopnavConfig,
    frames: usize,
) -> Vec<FrameOutputs> {
    let world_config: WorldConfig = parse_section(config, "world").expect("world");
    let world = World::generate(&world_config).expect("world");
    let mut reference = PhysicsSim::new(
        &world,
        &physics_section(config).expect("physics"),
        world_config.seed,
    )
    .expect("sim");
    (0..frames)
        .map(|_| reference.step_frame(&FrameInputs::default()))
        .collect()
}

/// The first incarnation runs `frames` frames, its states relayed, and is killed: no stop,
/// nothing saved on the way out.
fn run_and_kill(namespace: &Namespace, run_dir: &std::path::Path, relay: &mut Relay, frames: u64) {
    let context = context(namespace, run_dir, 0);
    let mut physics = PhysicsProcess::new(&context).expect("new");
    for frame_index in 0..frames {
        physics.step(&context, &tick(frame_index)).expect("step");
        relay.forward();
    }
}

#[test]
fn a_restarted_physics_continues_from_the_last_state_and_refuses_a_bad_one() {
    let run_id = format!("physics-resume-test-{}", std::process::id());
    let namespace = Namespace::new(&run_id).expect("namespace");
    let run_dir = run_dir_with_config(&run_id, None);
    let config = hopnav_config::load(None).expect("defaults");

    let test_node = namespace.create_node("physics_test").expect("node");
    let body_states =
        Subscriber::<BodyStates>::open(&test_node, &topics::BODY_STATES).expect("sub");
    let mut relay = Relay {
        from: Subscriber::open(&test_node, &topics::PHYSICS_STATE).expect("sub"),
        to: Publisher::open(&test_node, &topics::RESUME_PHYSICS_STATE).expect("pub"),
        last: None,
    };

    let reference = uninterrupted_reference(&config, 31);

    // The first incarnation runs 30 frames (the jumper is in its initial hop) and is killed.
    const KILLED_AFTER: u64 = 30;
    run_and_kill(&namespace, &run_dir, &mut relay, KILLED_AFTER);
    let last = relay.last.expect("state published every frame");
    assert_eq!(last.frames_simulated, KILLED_AFTER);
    assert_eq!(last.stamp.sim_time_ns, KILLED_AFTER * PERIOD_NS);
    body_states.receive_latest().expect("drain");

    // The restarted one continues: frame 30 ends at t = 3.1 s, exactly where the
    // uninterrupted run is (the jumper is in flight: no contact state is lost).
    let (states, rejected) =
        restart_and_step(&namespace, &run_dir, &relay, &body_states, 1, KILLED_AFTER);
    assert_eq!(rejected, 0);
    assert_eq!(states.stamp.sim_time_ns, (KILLED_AFTER + 1) * PERIOD_NS);
    let expected = reference[KILLED_AFTER as usize];
    assert_eq!(
        states.jumper.world_from_body.position_m,
        expected.jumper.position_m
    );
    assert_eq!(
        states.rover.world_from_body.position_m,
        expected.rover.position_m
    );

    // A corrupt sample (NaN velocity) fails the message checks: counted, and a fresh start.
    let mut corrupt = last;
    corrupt.jumper_body.linear_velocity_mps[0] = f64::NAN;
    relay.to.send(corrupt).expect("send");
    let (states, rejected) =
        restart_and_step(&namespace, &run_dir, &relay, &body_states, 2, KILLED_AFTER);
    assert_eq!(rejected, 1);
    assert_eq!(states.stamp.sim_time_ns, PERIOD_NS, "starts over");
    assert_eq!(
        states.jumper.world_from_body.position_m,
        reference[0].jumper.position_m
    );

    // A well-formed sample with an impossible state (the jumper at 1 km/s): refused too.
    let mut impossible = last;
    impossible.jumper_body.linear_velocity_mps = [1_000.0, 0.0, 0.0];
    relay.to.send(impossible).expect("send");
    let (states, rejected) =
        restart_and_step(&namespace, &run_dir, &relay, &body_states, 3, KILLED_AFTER);
    assert_eq!(rejected, 1);
    assert_eq!(states.stamp.sim_time_ns, PERIOD_NS, "starts over");

    drop(relay);
    std::fs::remove_dir_all(&run_dir).expect("cleanup");
}
