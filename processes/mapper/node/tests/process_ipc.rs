//! The mapper process over real iceoryx2 ports in an isolated namespace: header on the first
//! frame, changed cells after clouds, nothing on quiet frames, rejected samples counted, and a
//! restart that restores the map from its snapshot.

use hopnav_ipc::messages::{CellClass, CellUpdate, CloudHeader, FeaturePoint, MapHeader, Robot};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SlicePublisher, SliceSubscriber};
use hopnav_mapper_node::{MapperProcess, SNAPSHOT_FILE};

#[path = "../../../../ipc/tests/support/node_harness.rs"]
mod node_harness;

use node_harness::{run_dir_with_config, tick};

fn context(namespace: &Namespace, run_dir: &std::path::Path) -> ProcessContext {
    context_of_incarnation(namespace, run_dir, 0)
}

fn context_of_incarnation(
    namespace: &Namespace,
    run_dir: &std::path::Path,
    incarnation: u32,
) -> ProcessContext {
    node_harness::context(namespace, run_dir, "mapper", incarnation)
}

/// Ground at z = 0 around (1, 1) and a 0.6 m rock in the cell at (1.2, 1.2).
fn rover_cloud() -> Vec<FeaturePoint> {
    let mut points = Vec::new();
    for i in 0..30 {
        for j in 0..30 {
            let (x, y) = (i as f32 * 0.1 - 0.5, j as f32 * 0.1 - 0.5);
            let rock = (1.0..1.5).contains(&x) && (1.0..1.5).contains(&y);
            let height = if rock { 0.6 } else { 0.0 };
            points.push(FeaturePoint {
                position_m: [x, y, height],
                height_above_ground_m: height,
                track_id: (i * 30 + j) as u32,
                depth_sigma_m: 0.05,
            });
        }
    }
    points
}

fn send(publisher: &mut SlicePublisher<CloudHeader>, robot: u32, points: &[FeaturePoint]) {
    publisher
        .send_from_fn(
            points.len(),
            |header| {
                header.point_count = points.len() as u32;
                header.robot = robot;
            },
            |index| points[index],
        )
        .expect("send");
}

/// All updates of the samples received now, and the last header.
fn receive_all(subscriber: &SliceSubscriber<MapHeader>) -> (Vec<CellUpdate>, Option<MapHeader>) {
    let mut updates = Vec::new();
    let mut header = None;
    while let Some(sample) = subscriber.receive().expect("receive") {
        updates.extend_from_slice(sample.elements());
        header = Some(*sample.header());
    }
    (updates, header)
}

#[test]
fn publishes_header_then_changed_cells_and_recovers_after_restart() {
    let run_id = format!("mapper-test-{}", std::process::id());
    let namespace = Namespace::new(&run_id).expect("namespace");
    let run_dir = run_dir_with_config(&run_id, Some("[mapper]\nsnapshot_every_frames = 1\n"));

    let test_node = namespace.create_node("mapper_test").expect("node");
    let updates =
        SliceSubscriber::<MapHeader>::open(&test_node, &topics::MAP_UPDATES).expect("sub");
    let mut rover =
        SlicePublisher::<CloudHeader>::open(&test_node, &topics::ROVER_CLOUD, 4096).expect("pub");

    let context = context(&namespace, &run_dir);
    let mut mapper = MapperProcess::new(&context).expect("new");

    // Frame 0, no clouds: the header alone announces the grid.
    mapper.step(&context, &tick(0)).expect("step");
    let (cells, header) = receive_all(&updates);
    let header = header.expect("a header on the first frame");
    assert!(cells.is_empty());
    assert_eq!((header.width_cells, header.height_cells), (256, 256));
    assert_eq!((header.origin_x_m, header.cell_size_m), (-32.0, 0.25));

    // Frame 1: two rover keyframes with a rock (one cloud alone makes no obstacle), plus a
    // cloud that claims the wrong robot.
    send(&mut rover, Robot::Rover.code(), &rover_cloud());
    send(&mut rover, Robot::Rover.code(), &rover_cloud());
    send(&mut rover, Robot::Jumper.code(), &rover_cloud());
    mapper.step(&context, &tick(1)).expect("step");
    let (cells, header) = receive_all(&updates);
    assert_eq!(header.expect("changes").stamp.frame_index, 1);
    let rock = cells
        .iter()
        .find(|c| (c.x, c.y) == (132, 132))
        .expect("rock cell published");
    assert_eq!(rock.class, CellClass::Obstacle.code());
    assert_eq!(rock.observed_by, 1 << Robot::Rover.code());
    assert!(cells.iter().any(|c| c.class == CellClass::Inflated.code()));
    assert_eq!(mapper.rejected_samples(), 1, "the wrong-robot cloud");

    // Frame 2, nothing new: nothing published.
    mapper.step(&context, &tick(2)).expect("step");
    assert!(receive_all(&updates).1.is_none());

    // A restarted mapper restores its map and republishes it on its first frame.
    mapper.stop(&context);
    drop(mapper);
    drop(context);
    assert!(run_dir.join(SNAPSHOT_FILE).exists());
    // A first start in the same folder (a reused run id) does not take the old map.
    let context = self::context(&namespace, &run_dir);
    let mut fresh = MapperProcess::new(&context).expect("new");
    fresh.step(&context, &tick(0)).expect("step");
    let (fresh_cells, _) = receive_all(&updates);
    assert!(fresh_cells.is_empty(), "{} cells", fresh_cells.len());
    drop(fresh);
    drop(context);
    let context = context_of_incarnation(&namespace, &run_dir, 1);
    let mut restarted = MapperProcess::new(&context).expect("new");
    restarted.step(&context, &tick(3)).expect("step");
    let (recovered, _) = receive_all(&updates);
    let mut before = cells;
    let mut after = recovered;
    before.sort_by_key(|c| (c.y, c.x));
    after.sort_by_key(|c| (c.y, c.x));
    assert_eq!(before, after);

    drop(restarted);
    std::fs::remove_dir_all(&run_dir).expect("cleanup");
}

#[test]
fn the_oracle_prior_map_starts_with_the_worlds_rocks() {
    let run_id = format!("mapper-oracle-test-{}", std::process::id());
    let namespace = Namespace::new(&run_id).expect("namespace");
    let text = "[mapper]\noracle_prior_map = true\nsnapshot_every_frames = 0\n\
                [[world.rocks.explicit]]\ncenter_m = [5.2, 5.2]\ndiameter_m = 1.5\nheight_m = 0.8\n";
    let run_dir = run_dir_with_config(&run_id, Some(text));
    let test_node = namespace.create_node("mapper_test").expect("node");
    let updates =
        SliceSubscriber::<MapHeader>::open(&test_node, &topics::MAP_UPDATES).expect("sub");
    let context = context(&namespace, &run_dir);
    let mut mapper = MapperProcess::new(&context).expect("new");

    // No cloud arrives: the rock is on the map from the first frames on, seen "by the rover".
    let mut cells = Vec::new();
    for frame in 0..5 {
        mapper.step(&context, &tick(frame)).expect("step");
        cells.extend(receive_all(&updates).0);
    }
    // (5.2, 5.2) lies in cell (148, 148) of the 0.25 m grid from (−32, −32).
    let rock = cells
        .iter()
        .rfind(|c| (c.x, c.y) == (148, 148))
        .expect("the rock's cell published");
    assert_eq!(rock.class, CellClass::Obstacle.code());
    assert_eq!(rock.observed_by, 1 << Robot::Rover.code());
    mapper.stop(&context);
    let _ = std::fs::remove_dir_all(&run_dir);
}
