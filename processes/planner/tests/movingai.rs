//! MovingAI `.map` / `.scen` parsing, scenario solving, and malformed input handling.

use std::path::Path;

use hopnav_planner::movingai::{
    MapParseError, ScenParseError, cost_matches_optimal_length, load_map, load_scen, parse_map,
    parse_scen,
};
use hopnav_planner::rng::SplitMix64;
use hopnav_planner::scenario::solve_scenario;
use hopnav_planner::{AStar, Cell, CellState};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

#[test]
fn parses_the_fixture_map() {
    let grid = load_map(&fixture("tiny.map")).expect("fixture map");
    assert_eq!((grid.width(), grid.height()), (8, 6));
    assert_eq!(grid.state(Cell::new(0, 0)), Some(CellState::Free));
    assert_eq!(grid.state(Cell::new(1, 1)), Some(CellState::Obstacle)); // '@'
    assert_eq!(grid.state(Cell::new(1, 3)), Some(CellState::Obstacle)); // 'T'
    assert_eq!(grid.state(Cell::new(5, 4)), Some(CellState::Obstacle)); // 'W'
    assert_eq!(grid.state(Cell::new(0, 5)), Some(CellState::Free)); // 'G'
    assert_eq!(grid.state(Cell::new(2, 5)), Some(CellState::Free)); // 'S'
}

#[test]
fn fixture_scenarios_match_their_optimal_lengths() {
    let grid = load_map(&fixture("tiny.map")).expect("fixture map");
    let scenarios = load_scen(&fixture("tiny.map.scen")).expect("fixture scen");
    assert_eq!(scenarios.len(), 6);
    assert_eq!(scenarios[0].map_name, "tiny.map");
    assert_eq!(scenarios[0].start, Cell::new(0, 0));
    assert_eq!(scenarios[0].goal, Cell::new(7, 5));
    let mut astar = AStar::new(grid.cell_count());
    for scenario in &scenarios {
        let outcome = solve_scenario(&grid, scenario, &mut astar).expect("solvable");
        assert!(
            outcome.matches_optimal,
            "{:?} -> {:?}: cost {:?} vs optimal {}",
            scenario.start, scenario.goal, outcome.cost, scenario.optimal_length
        );
        assert!(outcome.planners_agree);
    }
}

#[test]
fn cost_tolerance_accepts_rounding_and_rejects_real_differences() {
    assert!(cost_matches_optimal_length(1414, std::f64::consts::SQRT_2));
    assert!(cost_matches_optimal_length(
        100 * 1414,
        100.0 * std::f64::consts::SQRT_2
    ));
    assert!(cost_matches_optimal_length(3000, 3.0));
    assert!(!cost_matches_optimal_length(4000, 3.0));
    assert!(!cost_matches_optimal_length(2414, 3.0));
    assert!(!cost_matches_optimal_length(0, f64::NAN));
}

/// Each input fails to parse with its error, which has a message.
fn assert_map_errors(cases: &[(&[u8], MapParseError)]) {
    for (input, expected) in cases {
        assert_eq!(parse_map(input), Err(expected.clone()));
        assert!(!expected.to_string().is_empty());
    }
}

#[test]
fn header_errors_name_the_line_and_problem() {
    assert_map_errors(&[
        (
            b"type hex\nheight 1\nwidth 1\nmap\n.\n",
            MapParseError::UnsupportedType {
                line: 1,
                found: "hex".into(),
            },
        ),
        (
            b"type octile\nheight -3\nwidth 1\nmap\n.\n",
            MapParseError::BadDimension {
                line: 2,
                key: "height",
                value: "-3".into(),
            },
        ),
        (
            b"type octile\nwidth 1\nmap\n.\n",
            MapParseError::IncompleteHeader {
                line: 3,
                expected: "height",
            },
        ),
        (
            b"type octile\nheight 1\n",
            MapParseError::IncompleteHeader {
                line: 3,
                expected: "width",
            },
        ),
        (
            b"type octile\nheight 1\nwidth 1\nbanana split\n.\n",
            MapParseError::BadHeaderLine {
                line: 4,
                text: "banana split".into(),
            },
        ),
    ]);
    assert_eq!(
        parse_map(b"type \xc3\x28 octile\n"),
        Err(MapParseError::InvalidUtf8 { line: 1 })
    );
}

#[test]
fn row_errors_name_the_line_and_problem() {
    assert_map_errors(&[
        (
            b"type octile\nheight 1\nwidth 2\nmap\n.x\n",
            MapParseError::BadTerrain {
                line: 5,
                column: 2,
                character: 'x',
            },
        ),
        (
            b"type octile\nheight 2\nwidth 3\nmap\n...\n..\n",
            MapParseError::WrongRowLength {
                line: 6,
                expected: 3,
                found: 2,
            },
        ),
        (
            b"type octile\nheight 3\nwidth 1\nmap\n.\n.\n",
            MapParseError::MissingRows {
                expected: 3,
                found: 2,
            },
        ),
        (
            b"type octile\nheight 1\nwidth 1\nmap\n.\n@\n",
            MapParseError::TrailingContent { line: 6 },
        ),
        (
            b"type octile\nheight 1\nwidth 1\nmap\n\xff\n",
            MapParseError::BadTerrain {
                line: 5,
                column: 1,
                character: char::REPLACEMENT_CHARACTER,
            },
        ),
    ]);
}

#[test]
fn crlf_maps_parse() {
    let grid = parse_map(b"type octile\r\nheight 1\r\nwidth 2\r\nmap\r\n.@\r\n").expect("crlf");
    assert_eq!(grid.state(Cell::new(1, 0)), Some(CellState::Obstacle));
}

#[test]
fn scen_errors_name_the_line_and_problem() {
    let cases: [(&[u8], ScenParseError); 5] = [
        (
            b"0\tm.map\t8\t6\t0\t0\t1\t1\t1.4\n",
            ScenParseError::BadVersion {
                line: 1,
                found: "0\tm.map\t8\t6\t0\t0\t1\t1\t1.4".into(),
            },
        ),
        (
            b"version 1\n0\tm.map\t8\t6\t0\t0\t1\n",
            ScenParseError::WrongFieldCount { line: 2, found: 7 },
        ),
        (
            b"version 1\n0\tm.map\t8\t6\t0\tzero\t1\t1\t1.4\n",
            ScenParseError::BadField {
                line: 2,
                field: "start_y",
                value: "zero".into(),
            },
        ),
        (
            b"version 1\n\n0\tm.map\t8\t6\t0\t0\t1\t1\tNaN\n",
            ScenParseError::BadField {
                line: 3,
                field: "optimal_length",
                value: "NaN".into(),
            },
        ),
        (
            b"version 1\n0\tm.map\t8\t6\t0\t0\t8\t1\t8.0\n",
            ScenParseError::OutsideStatedMap {
                line: 2,
                which: "goal",
                cell: Cell::new(8, 1),
                width: 8,
                height: 6,
            },
        ),
    ];
    for (input, expected) in cases {
        assert_eq!(parse_scen(input), Err(expected));
    }
    assert!(parse_scen(b"").is_err());
    assert_eq!(
        parse_scen(b"version 1.0\n3 my.map 4 4 0 0 3 3 4.24264069\n")
            .map(|scenarios| scenarios.len()),
        Ok(1)
    );
}

#[test]
fn arbitrary_bytes_never_panic() {
    let map = std::fs::read(fixture("tiny.map")).expect("fixture");
    let scen = std::fs::read(fixture("tiny.map.scen")).expect("fixture");
    let mut rng = SplitMix64::new(99);
    for round in 0..3000 {
        let mut bytes = if round % 2 == 0 {
            map.clone()
        } else {
            scen.clone()
        };
        if round % 5 == 0 {
            bytes = (0..rng.below(200)).map(|_| rng.below(256) as u8).collect();
        } else {
            for _ in 0..1 + rng.below(4) {
                let position = rng.below(bytes.len() as u64) as usize;
                match rng.below(3) {
                    0 => bytes[position] = rng.below(256) as u8,
                    1 => {
                        bytes.remove(position);
                    }
                    _ => bytes.insert(position, b"\n\t 9@.-"[rng.below(7) as usize]),
                }
            }
        }
        let _ = parse_map(&bytes);
        let _ = parse_scen(&bytes);
    }
    // A lying header cannot force a huge allocation: rows are counted first.
    assert!(matches!(
        parse_map(b"type octile\nheight 4000000000\nwidth 4000000000\nmap\n.\n"),
        Err(MapParseError::WrongRowLength { .. })
    ));
}
