//! MovingAI benchmark formats: octile `.map` grids and version-1 `.scen` scenario lists.
//!
//! `.map`: a header `type octile`, `height H`, `width W`, `map`, then H rows of W
//! characters. `.`, `G` and `S` are passable; `@`, `O`, `T` and `W` are blocked (as used for
//! the octile, no-corner-cutting benchmark set). `x` is the column, `y` the row.
//!
//! `.scen`: a `version 1` line, then one scenario per line, tab separated:
//! `bucket map width height start_x start_y goal_x goal_y optimal_length`. Optimal lengths
//! use costs 1 and √2; compare with our 1000/1414 costs via [`cost_matches_optimal_length`].
//!
//! Parsers take bytes and never panic; every error names its 1-based line.
//!
//! # Example
//!
//! ```
//! use hopnav_planner::movingai::parse_map;
//! use hopnav_planner::{Cell, CellState};
//!
//! let grid = parse_map(b"type octile\nheight 2\nwidth 3\nmap\n..@\nT.G\n")?;
//! assert_eq!(grid.state(Cell::new(2, 0)), Some(CellState::Obstacle));
//! assert_eq!(grid.state(Cell::new(2, 1)), Some(CellState::Free));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::cost::{Cost, DIAGONAL_COST, STRAIGHT_COST};
use crate::grid::{Cell, CellState, Grid, GridError};

/// Why a `.map` file could not be parsed.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum MapParseError {
    /// A line is not valid UTF-8.
    #[error("line {line}: not valid UTF-8")]
    InvalidUtf8 {
        /// 1-based line number.
        line: usize,
    },
    /// The input ended before the header was complete.
    #[error("line {line}: header ended early, expected `{expected}`")]
    IncompleteHeader {
        /// 1-based line number where the header stopped.
        line: usize,
        /// The header item still missing.
        expected: &'static str,
    },
    /// A header line is not `type`, `height`, `width` or `map`, or has no value.
    #[error("line {line}: unexpected header line `{text}`")]
    BadHeaderLine {
        /// 1-based line number.
        line: usize,
        /// The offending line (truncated to 80 characters).
        text: String,
    },
    /// The map type is not `octile`.
    #[error("line {line}: map type `{found}` is not supported, expected `octile`")]
    UnsupportedType {
        /// 1-based line number.
        line: usize,
        /// The type found.
        found: String,
    },
    /// `height` or `width` is not a positive integer.
    #[error("line {line}: `{key}` must be a positive integer, found `{value}`")]
    BadDimension {
        /// 1-based line number.
        line: usize,
        /// `height` or `width`.
        key: &'static str,
        /// The value found.
        value: String,
    },
    /// A map row has the wrong number of characters.
    #[error("line {line}: map row has {found} characters, expected {expected}")]
    WrongRowLength {
        /// 1-based line number.
        line: usize,
        /// The header width.
        expected: usize,
        /// Characters found.
        found: usize,
    },
    /// A map row holds a character that is not a known terrain type.
    #[error("line {line}, column {column}: unknown terrain character {character:?}")]
    BadTerrain {
        /// 1-based line number.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The character (or replacement for a non-ASCII byte).
        character: char,
    },
    /// Fewer map rows than the header height.
    #[error("map has {found} rows, header says {expected}")]
    MissingRows {
        /// The header height.
        expected: usize,
        /// Rows found.
        found: usize,
    },
    /// Non-empty lines after the last map row.
    #[error("line {line}: unexpected content after the last map row")]
    TrailingContent {
        /// 1-based line number.
        line: usize,
    },
    /// The dimensions do not make a valid grid.
    #[error(transparent)]
    Grid(#[from] GridError),
}

/// Why a `.scen` file could not be parsed.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ScenParseError {
    /// A line is not valid UTF-8.
    #[error("line {line}: not valid UTF-8")]
    InvalidUtf8 {
        /// 1-based line number.
        line: usize,
    },
    /// The first line is not `version 1` (or `version 1.0`).
    #[error("line {line}: expected `version 1`, found `{found}`")]
    BadVersion {
        /// 1-based line number.
        line: usize,
        /// The line found (truncated to 80 characters).
        found: String,
    },
    /// A scenario line does not have 9 fields.
    #[error("line {line}: expected 9 fields, found {found}")]
    WrongFieldCount {
        /// 1-based line number.
        line: usize,
        /// Fields found.
        found: usize,
    },
    /// A numeric field does not parse or is out of range.
    #[error("line {line}: field `{field}` has invalid value `{value}`")]
    BadField {
        /// 1-based line number.
        line: usize,
        /// Field name.
        field: &'static str,
        /// The value found (truncated to 80 characters).
        value: String,
    },
    /// Start or goal lies outside the map size the line states.
    #[error("line {line}: {which} {cell} is outside the stated {width}x{height} map")]
    OutsideStatedMap {
        /// 1-based line number.
        line: usize,
        /// `start` or `goal`.
        which: &'static str,
        /// The cell.
        cell: Cell,
        /// Stated width.
        width: u32,
        /// Stated height.
        height: u32,
    },
}

/// Why a MovingAI file could not be loaded.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The `.map` content is malformed.
    #[error("{path}: {source}")]
    Map {
        /// The file.
        path: PathBuf,
        /// The parse error.
        source: MapParseError,
    },
    /// The `.scen` content is malformed.
    #[error("{path}: {source}")]
    Scen {
        /// The file.
        path: PathBuf,
        /// The parse error.
        source: ScenParseError,
    },
}

/// One MovingAI scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Difficulty bucket.
    pub bucket: u32,
    /// Map file name as written in the scenario file.
    pub map_name: String,
    /// Map width the scenario was made for.
    pub map_width: u32,
    /// Map height the scenario was made for.
    pub map_height: u32,
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// Optimal path length with costs 1 and √2.
    pub optimal_length: f64,
}

/// Parses a `.map` file's bytes into a grid (passable cells become [`CellState::Free`]).
pub fn parse_map(bytes: &[u8]) -> Result<Grid, MapParseError> {
    let mut lines = numbered_lines(bytes);
    let (width, height) = parse_map_header(&mut lines)?;
    let rows = collect_map_rows(lines, width, height)?;
    let mut grid = Grid::new(width, height, CellState::Free)?;
    for (y, (line, raw)) in rows.into_iter().enumerate() {
        for (x, &byte) in raw.iter().enumerate() {
            let state = terrain_state(byte).ok_or(MapParseError::BadTerrain {
                line,
                column: x + 1,
                character: if byte.is_ascii() {
                    char::from(byte)
                } else {
                    char::REPLACEMENT_CHARACTER
                },
            })?;
            if state == CellState::Obstacle {
                grid.set(Cell::new(x as u32, y as u32), state, 0)?;
            }
        }
    }
    Ok(grid)
}

/// Reads the header up to and including its `map` line; returns `(width, height)`.
fn parse_map_header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
) -> Result<(u32, u32), MapParseError> {
    let mut height = None;
    let mut width = None;
    let mut last_line = 0;
    loop {
        let Some((line, raw)) = lines.next() else {
            return Err(MapParseError::IncompleteHeader {
                line: last_line + 1,
                expected: missing_header_item(height, width),
            });
        };
        last_line = line;
        let text = std::str::from_utf8(raw).map_err(|_| MapParseError::InvalidUtf8 { line })?;
        let mut words = text.split_whitespace();
        let (Some(key), value, None) = (words.next(), words.next(), words.next()) else {
            if text.trim().is_empty() {
                continue;
            }
            return Err(MapParseError::BadHeaderLine {
                line,
                text: truncate(text),
            });
        };
        match (key, value) {
            ("type", Some(kind)) => {
                if kind != "octile" {
                    return Err(MapParseError::UnsupportedType {
                        line,
                        found: truncate(kind),
                    });
                }
            }
            ("height", Some(value)) => height = Some(parse_dimension(line, "height", value)?),
            ("width", Some(value)) => width = Some(parse_dimension(line, "width", value)?),
            ("map", None) => break,
            _ => {
                return Err(MapParseError::BadHeaderLine {
                    line,
                    text: truncate(text),
                });
            }
        }
    }
    let (Some(height), Some(width)) = (height, width) else {
        return Err(MapParseError::IncompleteHeader {
            line: last_line,
            expected: missing_header_item(height, width),
        });
    };
    Ok((width, height))
}

/// The `height` rows of `width` bytes after the header, with their line numbers; only blank
/// lines may follow. Rows are collected before the grid is allocated, so a lying header
/// cannot force a huge allocation.
fn collect_map_rows<'a>(
    lines: impl Iterator<Item = (usize, &'a [u8])>,
    width: u32,
    height: u32,
) -> Result<Vec<(usize, &'a [u8])>, MapParseError> {
    let mut rows = Vec::new();
    for (line, raw) in lines {
        if rows.len() == height as usize {
            if !raw.iter().all(u8::is_ascii_whitespace) {
                return Err(MapParseError::TrailingContent { line });
            }
            continue;
        }
        if raw.len() != width as usize {
            let found = std::str::from_utf8(raw).map_or(raw.len(), |text| text.chars().count());
            return Err(MapParseError::WrongRowLength {
                line,
                expected: width as usize,
                found,
            });
        }
        rows.push((line, raw));
    }
    if rows.len() != height as usize {
        return Err(MapParseError::MissingRows {
            expected: height as usize,
            found: rows.len(),
        });
    }
    Ok(rows)
}

/// Parses a version-1 `.scen` file's bytes.
pub fn parse_scen(bytes: &[u8]) -> Result<Vec<Scenario>, ScenParseError> {
    let mut scenarios = Vec::new();
    let mut version_seen = false;
    for (line, raw) in numbered_lines(bytes) {
        let text = std::str::from_utf8(raw).map_err(|_| ScenParseError::InvalidUtf8 { line })?;
        if text.trim().is_empty() {
            continue;
        }
        if !version_seen {
            let mut words = text.split_whitespace();
            let ok = matches!(
                (words.next(), words.next(), words.next()),
                (Some("version"), Some("1" | "1.0"), None)
            );
            if !ok {
                return Err(ScenParseError::BadVersion {
                    line,
                    found: truncate(text),
                });
            }
            version_seen = true;
            continue;
        }
        scenarios.push(parse_scenario_line(line, text)?);
    }
    if !version_seen {
        return Err(ScenParseError::BadVersion {
            line: 1,
            found: String::new(),
        });
    }
    Ok(scenarios)
}

/// Reads and parses a `.map` file.
pub fn load_map(path: &Path) -> Result<Grid, LoadError> {
    parse_map(&read(path)?).map_err(|source| LoadError::Map {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads and parses a `.scen` file.
pub fn load_scen(path: &Path) -> Result<Vec<Scenario>, LoadError> {
    parse_scen(&read(path)?).map_err(|source| LoadError::Scen {
        path: path.to_path_buf(),
        source,
    })
}

fn read(path: &Path) -> Result<Vec<u8>, LoadError> {
    std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Whether our integer cost (1000 / 1414 units) matches a MovingAI optimal length
/// (1 / √2 units) within rounding. Every path's cost `C` satisfies
/// `1000·L·(1414 / (1000·√2)) ≤ C ≤ 1000·L`, so the optimum does too; half a unit of slack
/// on each side covers the decimals printed in `.scen` files.
pub fn cost_matches_optimal_length(cost: Cost, optimal_length: f64) -> bool {
    if !optimal_length.is_finite() || optimal_length < 0.0 {
        return false;
    }
    let diagonal_ratio = DIAGONAL_COST as f64 / (STRAIGHT_COST as f64 * std::f64::consts::SQRT_2);
    let upper = optimal_length * STRAIGHT_COST as f64 + 0.5;
    let lower = optimal_length * STRAIGHT_COST as f64 * diagonal_ratio - 0.5;
    let cost = cost as f64;
    cost >= lower && cost <= upper
}

fn parse_scenario_line(line: usize, text: &str) -> Result<Scenario, ScenParseError> {
    let tab_fields: Vec<&str> = text.split('\t').map(str::trim).collect();
    let fields: Vec<&str> = if tab_fields.len() == 9 {
        tab_fields
    } else {
        text.split_whitespace().collect()
    };
    let [bucket, map_name, width, height, sx, sy, gx, gy, length] = fields.as_slice() else {
        return Err(ScenParseError::WrongFieldCount {
            line,
            found: fields.len(),
        });
    };
    let integer = |field: &'static str, value: &str| -> Result<u32, ScenParseError> {
        value.parse::<u32>().map_err(|_| ScenParseError::BadField {
            line,
            field,
            value: truncate(value),
        })
    };
    let map_width = integer("width", width)?;
    let map_height = integer("height", height)?;
    let start = Cell::new(integer("start_x", sx)?, integer("start_y", sy)?);
    let goal = Cell::new(integer("goal_x", gx)?, integer("goal_y", gy)?);
    let optimal_length = length
        .parse::<f64>()
        .ok()
        .filter(|value| value.is_finite() && *value >= 0.0)
        .ok_or_else(|| ScenParseError::BadField {
            line,
            field: "optimal_length",
            value: truncate(length),
        })?;
    for (which, cell) in [("start", start), ("goal", goal)] {
        if cell.x >= map_width || cell.y >= map_height {
            return Err(ScenParseError::OutsideStatedMap {
                line,
                which,
                cell,
                width: map_width,
                height: map_height,
            });
        }
    }
    Ok(Scenario {
        bucket: integer("bucket", bucket)?,
        map_name: (*map_name).to_string(),
        map_width,
        map_height,
        start,
        goal,
        optimal_length,
    })
}

fn terrain_state(byte: u8) -> Option<CellState> {
    match byte {
        b'.' | b'G' | b'S' => Some(CellState::Free),
        b'@' | b'O' | b'T' | b'W' => Some(CellState::Obstacle),
        _ => None,
    }
}

fn parse_dimension(line: usize, key: &'static str, value: &str) -> Result<u32, MapParseError> {
    value
        .parse::<u32>()
        .ok()
        .filter(|&value| value > 0)
        .ok_or_else(|| MapParseError::BadDimension {
            line,
            key,
            value: truncate(value),
        })
}

fn missing_header_item(height: Option<u32>, width: Option<u32>) -> &'static str {
    match (height, width) {
        (None, _) => "height",
        (_, None) => "width",
        _ => "map",
    }
}

/// Lines with 1-based numbers, split on `\n`, trailing `\r` removed. A final empty piece
/// after the last newline is dropped.
fn numbered_lines(bytes: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    let ends_with_newline = bytes.last() == Some(&b'\n');
    let pieces = bytes.split(|&byte| byte == b'\n').count();
    let keep = if ends_with_newline || bytes.is_empty() {
        pieces.saturating_sub(1)
    } else {
        pieces
    };
    bytes
        .split(|&byte| byte == b'\n')
        .take(keep)
        .enumerate()
        .map(|(index, raw)| (index + 1, raw.strip_suffix(b"\r").unwrap_or(raw)))
}

fn truncate(text: &str) -> String {
    text.chars().take(80).collect()
}
