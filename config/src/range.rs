//! Range checks shared by the processes' own configuration types.
//!
//! Each process library keeps its own documented error type and key style; what they share is
//! the check itself and how a key and a range are written: an [`Interval`] says whether a value
//! is allowed (finite and inside) and prints itself in interval notation, and a failed check
//! hands back an [`OutOfRange`] (the dotted key, the value and the range, as text) that the
//! caller's error type takes in with a `From` impl.
//!
//! ```
//! use hopnav_config::range::{Interval, check_int, dotted_key};
//! let spacing = Interval::left_open(0.0, 1.0);
//! assert!(spacing.check("terrain", "spacing_m", 1.0).is_ok());
//! let rejected = spacing.check("terrain", "spacing_m", 2.0).unwrap_err();
//! assert_eq!(rejected.key, "terrain.spacing_m");
//! assert_eq!((rejected.value.as_str(), rejected.range.as_str()), ("2", "(0, 1]"));
//! assert!(Interval::closed(0.0, 1.0).check("", "gain", f64::NAN).is_err());
//! assert_eq!(check_int("craters", "count", 17, 0, 16).unwrap_err().range, "[0, 16]");
//! assert_eq!(dotted_key("terrain", "spacing_m"), "terrain.spacing_m");
//! assert_eq!(dotted_key("", "seed"), "seed");
//! ```
//!
//! A library whose keys all sit in one table, with closed ranges, checks them through a
//! [`Table`] and may use [`OutOfRange`] as its error as it is:
//!
//! ```
//! use hopnav_config::range::Table;
//! const KEYS: Table = Table::new("camera");
//! assert!(KEYS.real("fov_rad", 1.0, 0.1, 3.0).is_ok());
//! let rejected = KEYS.count("width_px", 0, 16, 4096).unwrap_err();
//! assert_eq!(rejected.to_string(), "camera.width_px must be in [16, 4096], got 0");
//! let rejected = KEYS.per_axis("offset_m", &[0.0, 9.0], -1.0, 1.0).unwrap_err();
//! assert_eq!(rejected.range, "[-1, 1] (per axis)");
//! ```

use std::fmt;

/// An interval of allowed real values; each end is open or closed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Interval {
    /// `[lo, hi]`.
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }

    /// `(lo, hi]`.
    pub const fn left_open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }

    /// `(lo, hi)`.
    pub const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: true,
        }
    }

    /// Whether `v` is finite and lies inside.
    pub fn contains(&self, v: f64) -> bool {
        let lo_ok = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        let hi_ok = if self.hi_open {
            v < self.hi
        } else {
            v <= self.hi
        };
        v.is_finite() && lo_ok && hi_ok
    }

    /// Checks `v`; the error names `prefix.field` (see [`dotted_key`]) and this interval.
    pub fn check(&self, prefix: &str, field: &str, v: f64) -> Result<(), OutOfRange> {
        if self.contains(v) {
            Ok(())
        } else {
            Err(OutOfRange {
                key: dotted_key(prefix, field),
                value: format!("{v}"),
                range: self.to_string(),
            })
        }
    }
}

/// Interval notation, e.g. `(0, 1]`.
impl fmt::Display for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}{}, {}{}",
            if self.lo_open { '(' } else { '[' },
            self.lo,
            self.hi,
            if self.hi_open { ')' } else { ']' }
        )
    }
}

/// A value that failed a range check.
///
/// Each configuration library turns it into its own documented error (a `From` impl), so `?`
/// carries it up with the key, the value and the range as they were found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutOfRange {
    /// Full dotted key, e.g. `terrain.spacing_m`.
    pub key: String,
    /// The rejected value as written, e.g. `2` or `NaN`.
    pub value: String,
    /// The allowed range in interval notation, e.g. `(0, 1]`.
    pub range: String,
}

impl OutOfRange {
    /// Adds a note to the range, e.g. `per axis` or what a bound comes from:
    /// `[0, 100] (0 disables)`.
    pub fn noted(mut self, note: &str) -> Self {
        self.range = format!("{} ({note})", self.range);
        self
    }
}

/// `key must be in range, got value`.
impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} must be in {}, got {}",
            self.key, self.range, self.value
        )
    }
}

impl std::error::Error for OutOfRange {}

/// The keys of one configuration table, checked against closed ranges; errors name
/// `table.field`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Table {
    name: &'static str,
}

impl Table {
    /// The table called `name`, e.g. `jumper_vo`.
    pub const fn new(name: &'static str) -> Self {
        Self { name }
    }

    /// Checks a real value against `[lo, hi]` (it must also be finite).
    pub fn real(&self, field: &str, v: f64, lo: f64, hi: f64) -> Result<(), OutOfRange> {
        Interval::closed(lo, hi).check(self.name, field, v)
    }

    /// Checks every component of a vector against `[lo, hi]`; the range says `per axis`.
    pub fn per_axis(&self, field: &str, v: &[f64], lo: f64, hi: f64) -> Result<(), OutOfRange> {
        for &component in v {
            self.real(field, component, lo, hi)
                .map_err(|rejected| rejected.noted("per axis"))?;
        }
        Ok(())
    }

    /// Checks a count against `[lo, hi]`.
    pub fn count(&self, field: &str, v: usize, lo: usize, hi: usize) -> Result<(), OutOfRange> {
        self.int(field, v as u64, lo as u64, hi as u64)
    }

    /// Checks an integer against `[lo, hi]`.
    pub fn int(&self, field: &str, v: u64, lo: u64, hi: u64) -> Result<(), OutOfRange> {
        check_int(self.name, field, v, lo, hi)
    }
}

/// Checks an integer against the inclusive range `[lo, hi]`; the error names `prefix.field`.
pub fn check_int(prefix: &str, field: &str, v: u64, lo: u64, hi: u64) -> Result<(), OutOfRange> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(OutOfRange {
            key: dotted_key(prefix, field),
            value: v.to_string(),
            range: format!("[{lo}, {hi}]"),
        })
    }
}

/// Joins a key prefix and a field name with a dot (an empty prefix gives the field alone).
pub fn dotted_key(prefix: &str, field: &str) -> String {
    if prefix.is_empty() {
        field.to_string()
    } else {
        format!("{prefix}.{field}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_open_and_closed() {
        assert!(Interval::closed(0.0, 1.0).contains(0.0));
        assert!(Interval::closed(0.0, 1.0).contains(1.0));
        assert!(!Interval::left_open(0.0, 1.0).contains(0.0));
        assert!(!Interval::open(0.0, 1.0).contains(1.0));
        assert!(!Interval::closed(f64::NEG_INFINITY, f64::INFINITY).contains(f64::INFINITY));
        assert_eq!(Interval::open(-0.5, 2.0).to_string(), "(-0.5, 2)");
    }

    #[test]
    fn integers_are_inclusive() {
        assert!(check_int("", "n", 0, 0, 16).is_ok());
        assert!(check_int("", "n", 16, 0, 16).is_ok());
        assert_eq!(
            check_int("a", "n", 17, 0, 16),
            Err(OutOfRange {
                key: "a.n".into(),
                value: "17".into(),
                range: "[0, 16]".into()
            })
        );
    }
}
