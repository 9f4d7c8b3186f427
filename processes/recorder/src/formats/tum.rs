//! TUM trajectories: `t tx ty tz qx qy qz qw` per line, readable by `evo_ape`.

use std::io::{self, BufRead, Write};

/// One pose at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TumPose {
    /// Time, seconds.
    pub t_s: f64,
    /// Position, metres.
    pub position_m: [f64; 3],
    /// Orientation quaternion `[x, y, z, w]`.
    pub orientation_xyzw: [f64; 4],
}

/// Writes one TUM line.
pub fn write_tum_line(out: &mut impl Write, pose: &TumPose) -> io::Result<()> {
    let [x, y, z] = pose.position_m;
    let [qx, qy, qz, qw] = pose.orientation_xyzw;
    writeln!(
        out,
        "{:.6} {x:.6} {y:.6} {z:.6} {qx:.9} {qy:.9} {qz:.9} {qw:.9}",
        pose.t_s
    )
}

/// Why a TUM file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TumError {
    /// Reading failed.
    #[error("TUM read failed: {0}")]
    Io(#[from] io::Error),
    /// A line is not 8 finite numbers.
    #[error("TUM line {line}: {reason}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
}

/// Reads a TUM file; `#` comments and blank lines are skipped.
pub fn read_tum(input: impl BufRead) -> Result<Vec<TumPose>, TumError> {
    let mut poses = Vec::new();
    for (index, line) in input.lines().enumerate() {
        let line = line?;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let values: Vec<f64> = trimmed
            .split_whitespace()
            .map(str::parse::<f64>)
            .collect::<Result<_, _>>()
            .map_err(|error| TumError::Line {
                line: index + 1,
                reason: error.to_string(),
            })?;
        if values.len() != 8 || values.iter().any(|v| !v.is_finite()) {
            return Err(TumError::Line {
                line: index + 1,
                reason: format!("expected 8 finite numbers, got {}", values.len()),
            });
        }
        poses.push(TumPose {
            t_s: values[0],
            position_m: [values[1], values[2], values[3]],
            orientation_xyzw: [values[4], values[5], values[6], values[7]],
        });
    }
    Ok(poses)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let pose = TumPose {
            t_s: 1.5,
            position_m: [1.0, -2.0, 3.25],
            orientation_xyzw: [0.0, 0.0, 0.6, 0.8],
        };
        let mut bytes = b"# t tx ty tz qx qy qz qw\n".to_vec();
        write_tum_line(&mut bytes, &pose).expect("write");
        assert_eq!(read_tum(bytes.as_slice()).expect("read"), vec![pose]);
    }

    #[test]
    fn bad_lines_name_their_number() {
        let error = read_tum(&b"0 0 0 0 0 0 0 1\n1 2 3\n"[..]).expect_err("short line");
        assert!(error.to_string().contains("line 2"), "{error}");
        assert!(read_tum(&b"0 0 0 nan 0 0 0 1\n"[..]).is_err());
    }
}
