//! Edge cases: thin walls, start == goal, unreachable goals, walls that open again.

mod common;

use common::{assert_valid_path, grid_from_rows};
use hopnav_planner::cost::path_cost;
use hopnav_planner::{
    AStar, Cell, CellChange, CellState, DStarLite, Grid, GridError, PlanError, dijkstra_cost,
};

fn planner(rows: &[&str], start: Cell, goal: Cell) -> DStarLite {
    DStarLite::new(grid_from_rows(rows), start, goal).expect("planner")
}

#[test]
fn diagonal_wall_one_cell_thick_cannot_be_squeezed_through() {
    let rows = ["..#", ".#.", "#.."];
    let (start, goal) = (Cell::new(0, 0), Cell::new(2, 2));
    let mut planner = planner(&rows, start, goal);
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
    assert_eq!(planner.path(), None);
    assert_eq!(planner.next_step(), None);
    assert_eq!(dijkstra_cost(planner.grid(), start, goal), None);
    let mut astar = AStar::new(9);
    assert_eq!(
        astar
            .search(planner.grid(), start, goal)
            .map(|found| found.stats.cost),
        Err(PlanError::Unreachable)
    );
}

#[test]
fn single_obstacle_corner_blocks_the_diagonal_move() {
    // Going from (0,1) to (1,0) diagonally would cut the corner of the obstacle at (0,0).
    let rows = ["#.", ".."];
    let (start, goal) = (Cell::new(0, 1), Cell::new(1, 0));
    let mut planner = planner(&rows, start, goal);
    let stats = planner.compute_shortest_path().expect("reachable");
    assert_eq!(stats.cost, 2000);
    let path = planner.path().expect("path");
    assert_eq!(path, vec![start, Cell::new(1, 1), goal]);
}

#[test]
fn straight_wall_with_gap_is_passed_through_the_gap() {
    let rows = [
        ".....#.....",
        ".....#.....",
        ".....#.....",
        "...........",
        ".....#.....",
    ];
    let (start, goal) = (Cell::new(0, 0), Cell::new(10, 0));
    let mut planner = planner(&rows, start, goal);
    let stats = planner.compute_shortest_path().expect("reachable");
    let path = planner.path().expect("path");
    assert!(
        path.contains(&Cell::new(5, 3)),
        "must use the gap: {path:?}"
    );
    assert_eq!(
        assert_valid_path(planner.grid(), &path, start, goal),
        stats.cost
    );
    assert_eq!(Some(stats.cost), dijkstra_cost(planner.grid(), start, goal));
}

#[test]
fn start_equal_to_goal_costs_zero() {
    let rows = ["...", "...", "..."];
    let cell = Cell::new(1, 1);
    let mut planner = planner(&rows, cell, cell);
    let stats = planner.compute_shortest_path().expect("trivial");
    assert_eq!(stats.cost, 0);
    assert_eq!(planner.path(), Some(vec![cell]));
    assert_eq!(planner.next_step(), None);
    assert_eq!(dijkstra_cost(planner.grid(), cell, cell), Some(0));
    // Surrounding the cell with obstacles changes nothing.
    let walls: Vec<_> = (0..3)
        .flat_map(|y| (0..3).map(move |x| Cell::new(x, y)))
        .filter(|&c| c != cell)
        .map(|c| CellChange::new(c, CellState::Obstacle, 0))
        .collect();
    planner.update_cells(&walls).expect("in grid");
    assert_eq!(planner.compute_shortest_path().map(|s| s.cost), Ok(0));
}

#[test]
fn goal_on_obstacle_is_unreachable() {
    let rows = ["...", "..#"];
    let mut planner = planner(&rows, Cell::new(0, 0), Cell::new(2, 1));
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
}

#[test]
fn enclosed_goal_on_a_large_grid_is_unreachable_without_hanging() {
    let mut grid = Grid::new(257, 257, CellState::Unknown).expect("grid");
    let goal = Cell::new(200, 200);
    for y in 198..=202 {
        for x in 198..=202 {
            if x == 198 || x == 202 || y == 198 || y == 202 {
                grid.set(Cell::new(x, y), CellState::Obstacle, 0)
                    .expect("set");
            }
        }
    }
    let mut planner = DStarLite::new(grid, Cell::new(3, 3), goal).expect("planner");
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
    // The search exhausts the goal's pocket only (backwards search): a bounded amount of
    // work, asserted as expansions rather than time (timing lives in benchmarks).
    assert!(planner.counters().expansions < 100);
    // Repeating the call is stable.
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
}

#[test]
fn enclosed_start_is_unreachable_after_exhausting_the_map() {
    let mut grid = Grid::new(64, 64, CellState::Free).expect("grid");
    for (x, y) in [(1, 0), (1, 1), (0, 1)] {
        grid.set(Cell::new(x, y), CellState::Obstacle, 0)
            .expect("set");
    }
    let mut planner = DStarLite::new(grid, Cell::new(0, 0), Cell::new(63, 63)).expect("new");
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
    assert_eq!(planner.path(), None);
}

#[test]
fn goal_becomes_reachable_again_after_an_obstacle_is_removed() {
    let rows = ["..#..", "..#..", "..#..", "..#..", "..#.."];
    let (start, goal) = (Cell::new(0, 2), Cell::new(4, 2));
    let mut planner = planner(&rows, start, goal);
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));

    let opening = CellChange::new(Cell::new(2, 4), CellState::Free, 0);
    assert_eq!(planner.update_cells(&[opening]), Ok(1));
    let stats = planner.compute_shortest_path().expect("reachable again");
    assert_eq!(Some(stats.cost), dijkstra_cost(planner.grid(), start, goal));
    let path = planner.path().expect("path");
    assert_eq!(
        assert_valid_path(planner.grid(), &path, start, goal),
        stats.cost
    );

    let closing = CellChange::new(Cell::new(2, 4), CellState::Obstacle, 0);
    planner.update_cells(&[closing]).expect("in grid");
    assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
}

#[test]
fn following_next_step_without_changes_costs_the_initial_plan() {
    let rows = [
        "..........",
        ".####.....",
        "....#..#..",
        "..#.#..#..",
        "..#....#..",
    ];
    let (start, goal) = (Cell::new(0, 4), Cell::new(9, 0));
    let mut planner = planner(&rows, start, goal);
    let planned = planner.compute_shortest_path().expect("reachable").cost;
    let mut walked = vec![start];
    while let Some(next) = planner.next_step() {
        planner.move_start(next).expect("in grid");
        walked.push(next);
        assert!(walked.len() < 100, "walk does not terminate");
    }
    assert_eq!(planner.start(), goal);
    assert_eq!(path_cost(planner.grid(), &walked), Some(planned));
}

#[test]
fn extra_cost_steers_the_path_around_inflated_cells() {
    let rows = [".....", ".999.", "....."];
    let (start, goal) = (Cell::new(0, 1), Cell::new(4, 1));
    let mut planner = planner(&rows, start, goal);
    let stats = planner.compute_shortest_path().expect("reachable");
    assert_eq!(stats.cost, 2 * 1414 + 2 * 1000);
    let path = planner.path().expect("path");
    assert!(
        path.iter()
            .all(|cell| cell.y != 1 || cell.x == 0 || cell.x == 4)
    );
}

#[test]
fn out_of_bounds_inputs_are_errors_and_leave_the_planner_unchanged() {
    let rows = ["...", "..."];
    let bad = Cell::new(3, 0);
    assert!(matches!(
        DStarLite::new(grid_from_rows(&rows), bad, Cell::new(0, 0)),
        Err(PlanError::OutOfBounds(GridError::OutOfBounds { .. }))
    ));
    let mut planner = planner(&rows, Cell::new(0, 0), Cell::new(2, 1));
    let before = planner.compute_shortest_path().expect("reachable").cost;
    let changes = [
        CellChange::new(Cell::new(1, 0), CellState::Obstacle, 0),
        CellChange::new(bad, CellState::Obstacle, 0),
    ];
    assert!(planner.update_cells(&changes).is_err());
    assert_eq!(planner.grid().state(Cell::new(1, 0)), Some(CellState::Free));
    assert!(planner.move_start(bad).is_err());
    assert_eq!(planner.compute_shortest_path().map(|s| s.cost), Ok(before));
}

#[test]
fn unknown_cells_are_planned_through_as_free() {
    let rows = ["?????", "?###?", "?????"];
    let (start, goal) = (Cell::new(0, 1), Cell::new(4, 1));
    let mut planner = planner(&rows, start, goal);
    // Up, four across, down: the diagonals would cut the wall's corners.
    assert_eq!(planner.compute_shortest_path().map(|s| s.cost), Ok(6000));
    // Revealing unknown cells as free changes no cost and needs no replan work.
    let reveal = [CellChange::new(Cell::new(1, 0), CellState::Free, 0)];
    assert_eq!(planner.update_cells(&reveal), Ok(0));
}
