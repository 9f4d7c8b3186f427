//! TUM trajectory files (`t tx ty tz qx qy qz qw` per line, `#` comments), readable by `evo`.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use std::fmt::Write as _;
use std::path::Path;

/// Error reading or writing a TUM file.
#[derive(Debug, thiserror::Error)]
pub enum TumError {
    /// File system error.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// A line does not hold eight finite numbers.
    #[error("line {line}: expected `t tx ty tz qx qy qz qw`")]
    Parse {
        /// 1-based line number.
        line: usize,
    },
}

/// Formats stamped poses as TUM text.
pub fn to_tum_string(poses: &[(f64, Isometry3<f64>)]) -> String {
    let mut s = String::from("# t tx ty tz qx qy qz qw\n");
    for (t, p) in poses {
        let q = p.rotation.quaternion();
        let v = p.translation.vector;
        let _ = writeln!(
            s,
            "{t:.6} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9}",
            v.x, v.y, v.z, q.i, q.j, q.k, q.w
        );
    }
    s
}

/// Parses TUM text.
pub fn parse_tum(text: &str) -> Result<Vec<(f64, Isometry3<f64>)>, TumError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let v: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|_| TumError::Parse { line: i + 1 })?;
        if v.len() != 8 || !v.iter().all(|x| x.is_finite()) {
            return Err(TumError::Parse { line: i + 1 });
        }
        let q = Quaternion::new(v[7], v[4], v[5], v[6]);
        if q.norm() < 1e-9 {
            return Err(TumError::Parse { line: i + 1 });
        }
        out.push((
            v[0],
            Isometry3::from_parts(
                Translation3::new(v[1], v[2], v[3]),
                UnitQuaternion::from_quaternion(q),
            ),
        ));
    }
    Ok(out)
}

/// Writes a TUM file.
pub fn write_tum(path: &Path, poses: &[(f64, Isometry3<f64>)]) -> Result<(), TumError> {
    std::fs::write(path, to_tum_string(poses)).map_err(|source| TumError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Reads a TUM file.
pub fn read_tum(path: &Path) -> Result<Vec<(f64, Isometry3<f64>)>, TumError> {
    let text = std::fs::read_to_string(path).map_err(|source| TumError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_tum(&text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn round_trip() {
        let poses: Vec<(f64, Isometry3<f64>)> = (0..5)
            .map(|i| {
                (
                    i as f64 * 0.1,
                    Isometry3::new(
                        Vector3::new(i as f64, -2.0, 0.5 * i as f64),
                        Vector3::new(0.0, -0.1 * i as f64, 0.02),
                    ),
                )
            })
            .collect();
        let dir = std::env::temp_dir().join(format!("jvo-tum-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("est.tum");
        write_tum(&path, &poses).unwrap();
        let back = read_tum(&path).unwrap();
        assert_eq!(back.len(), poses.len());
        for ((ta, a), (tb, b)) in poses.iter().zip(&back) {
            assert!((ta - tb).abs() < 1e-9);
            assert!((a.translation.vector - b.translation.vector).norm() < 1e-8);
            assert!(a.rotation.angle_to(&b.rotation) < 1e-8);
        }
        assert!(matches!(
            parse_tum("0 1 2 3\n"),
            Err(TumError::Parse { line: 1 })
        ));
        let _ = std::fs::remove_dir_all(dir);
    }
}
