//! Size limits checked before a run: a scenario whose arrays cannot be allocated is rejected by
//! `validate` with the memory it would need, instead of aborting on a capacity overflow or an
//! allocation failure half-way through a sweep.
//!
//! Two limits apply to every size (cells, continuum nodes, sheet grids, division caps):
//!
//! * a fixed maximum ([`MAX_LINE_CELLS`], [`MAX_SHEET_CELLS`]), the same on every machine;
//! * the memory a run needs, estimated from measured peak memory per cell
//!   ([`LINE_BYTES_PER_CELL`], [`SHEET_BYTES_PER_CELL`]), against the memory the machine has
//!   available (`MemAvailable` in `/proc/meminfo`; skipped where that is not readable).
//!
//! ```
//! use celltissue::scenario::limits::{check_cells, LINE_BYTES_PER_CELL, MAX_LINE_CELLS};
//! assert!(check_cells("model.cells", 100.0, LINE_BYTES_PER_CELL, MAX_LINE_CELLS).is_ok());
//! let e = check_cells("model.cells", 1e18, LINE_BYTES_PER_CELL, MAX_LINE_CELLS).unwrap_err();
//! assert_eq!(e.key_name(), Some("model.cells"));
//! assert!(e.to_string().contains("EB"), "{e}"); // 1e18 cells need ~500 EB
//! ```

use super::error::ScenarioError;

/// Most cells (or continuum segments) of a line, a ring or a shear column: 10⁸ (≈ 50 GB).
pub const MAX_LINE_CELLS: f64 = 1e8;

/// Most cells (or continuum grid points) of a sheet, `cells_x · cells_y`: 10⁷ (≈ 80 GB).
pub const MAX_SHEET_CELLS: f64 = 1e7;

/// Peak memory of a line run per cell, in bytes. Measured (peak RSS of `celltissue run` on a
/// line with K = 1, series and one profile): 53 MB at N = 10⁵, 478 MB at N = 10⁶.
pub const LINE_BYTES_PER_CELL: f64 = 500.0;

/// Peak memory of a sheet run per cell, in bytes (sparse LU fill-in dominates). Measured:
/// 11 MB at 20 × 20, 77 MB at 100 × 100 (discrete, direct solver).
pub const SHEET_BYTES_PER_CELL: f64 = 8000.0;

/// Memory per recorded profile value (one cell or grid point at one profile time), in bytes.
/// Measured: a 10⁴-cell line with 1 000 profile times peaked at 1.73 GB against 36 MB with 10
/// (170 B per cell and time: the record's fields, the cell lengths among them, and the
/// `.npz` written from them).
pub const PROFILE_BYTES_PER_VALUE: f64 = 175.0;

/// Checks the profiles a set of runs would record: `values` cells (or grid points) summed over
/// the runs and profile times, `runs` of them, must fit the machine's available memory at
/// [`PROFILE_BYTES_PER_VALUE`]. The error names `output.profiles` and the memory needed.
///
/// ```
/// use celltissue::scenario::limits::check_profiles;
/// assert!(check_profiles(1e6, 4).is_ok()); // 160 MB
/// let e = check_profiles(1e12, 4).unwrap_err(); // a 10⁶-cell line at 10⁶ profile times
/// assert_eq!(e.key_name(), Some("output.profiles"));
/// ```
pub fn check_profiles(values: f64, runs: usize) -> Result<(), ScenarioError> {
    let need = values * PROFILE_BYTES_PER_VALUE;
    let avail = available_memory().unwrap_or(f64::INFINITY);
    // a fixed limit as well, so that the answer does not depend on the machine for absurd sizes
    let max = 1e10;
    if values > max || need > avail {
        let limit = if values > max {
            format!("the limit is {} values", count_words(max))
        } else {
            format!("{} is available", bytes_words(avail))
        };
        return Err(ScenarioError::key(
            "output.profiles",
            format!(
                "asks for more than memory holds: {} would record {} cell values at their \
                 profile times, about {} of memory ({} each), and {limit}; ask for fewer \
                 profile times or fewer cells",
                if runs == 1 {
                    "the run".to_string()
                } else {
                    format!("{runs} runs")
                },
                count_words(values),
                bytes_words(need),
                bytes_words(PROFILE_BYTES_PER_VALUE)
            ),
        ));
    }
    Ok(())
}

/// Checks a size: `count` (as given; may be huge or fractional before conversion) must be at
/// most `max`, and `count · bytes_per_cell` must fit the machine's available memory. The error
/// names `key`, the limit and the memory the run would need.
///
/// ```
/// use celltissue::scenario::limits::{check_cells, MAX_SHEET_CELLS, SHEET_BYTES_PER_CELL};
/// // a 4096 × 4096 sheet is past the fixed limit of 10⁷ cells, whatever the machine
/// let e = check_cells("model.cells_x", 4096.0 * 4096.0, SHEET_BYTES_PER_CELL, MAX_SHEET_CELLS)
///     .unwrap_err();
/// assert_eq!(e.key_name(), Some("model.cells_x"));
/// ```
pub fn check_cells(
    key: &str,
    count: f64,
    bytes_per_cell: f64,
    max: f64,
) -> Result<(), ScenarioError> {
    let need = count * bytes_per_cell;
    if count > max {
        return Err(ScenarioError::key(
            key,
            format!(
                "= {} is too large: a run would need about {} of memory \
                 ({} per cell); the limit is {} cells",
                count_words(count),
                bytes_words(need),
                bytes_words(bytes_per_cell),
                count_words(max)
            ),
        ));
    }
    if let Some(avail) = available_memory() {
        if need > avail {
            return Err(ScenarioError::key(
                key,
                format!(
                    "= {} is too large for this machine: a run would need about {} of \
                     memory ({} per cell) and {} is available",
                    count_words(count),
                    bytes_words(need),
                    bytes_words(bytes_per_cell),
                    bytes_words(avail)
                ),
            ));
        }
    }
    Ok(())
}

/// `MemAvailable` from `/proc/meminfo`, in bytes (`None` where unavailable).
///
/// ```
/// let avail = celltissue::scenario::limits::available_memory();
/// assert!(avail.is_none_or(|b| b > 0.0));
/// ```
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// A count as an integer when it is one of moderate size, else in scientific notation.
fn count_words(n: f64) -> String {
    if n.fract() == 0.0 && n.abs() < 1e15 {
        format!("{n:.0}")
    } else {
        format!("{n:e}")
    }
}

/// Bytes in the largest unit (up to EB) that keeps the number below 1000, to three digits.
fn bytes_words(b: f64) -> String {
    const UNITS: [&str; 7] = ["B", "kB", "MB", "GB", "TB", "PB", "EB"];
    let (mut v, mut i) = (b, 0);
    while v >= 1000.0 && i + 1 < UNITS.len() {
        v /= 1000.0;
        i += 1;
    }
    let unit = UNITS[i];
    if v >= 100.0 {
        format!("{v:.0} {unit}")
    } else if v >= 10.0 {
        format!("{v:.1} {unit}")
    } else {
        format!("{v:.2} {unit}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_units() {
        assert_eq!(bytes_words(500.0), "500 B");
        assert_eq!(bytes_words(5e10), "50.0 GB");
        assert_eq!(bytes_words(4.6e21), "4600 EB");
        assert_eq!(bytes_words(2.5e6), "2.50 MB");
    }

    #[test]
    fn limits_name_the_memory() {
        let e = check_cells("model.cells", 9.223372036854776e18, 500.0, MAX_LINE_CELLS)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("model.cells") && e.contains("limit is 100000000"),
            "{e}"
        );
        assert!(e.contains("4612 EB"), "{e}");
    }
}
