//! The division event log: one [`DivisionRecord`] per division (time, parent index, position of
//! the new boundary, position over length, `N` after), its CSV form, and summaries used by the
//! validation tests and reports (first/last division, `N(t)`, median `x_d/l`).

use crate::observe::DivisionRecord;

/// Division records in event order (written by [`crate::output::files::divisions_csv`]).
///
/// ```
/// use celltissue::events::DivisionLog;
/// use celltissue::observe::DivisionRecord;
/// let mut log = DivisionLog::default();
/// log.push(DivisionRecord { t: 2.0, parent: 3, x: 2.5, x_over_length: 0.5, cells_after: 6, ..Default::default() });
/// log.push(DivisionRecord { t: 2.4, parent: 1, x: 0.5, x_over_length: 0.1, cells_after: 7, ..Default::default() });
/// assert_eq!((log.len(), log.cells_at(5, 2.1), log.cells_at(5, 3.0)), (2, 6, 7));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DivisionLog {
    /// The records.
    pub records: Vec<DivisionRecord>,
}

impl DivisionLog {
    /// Appends a record.
    ///
    /// ```
    /// use celltissue::events::DivisionLog;
    /// use celltissue::observe::DivisionRecord;
    /// let mut log = DivisionLog::default();
    /// log.push(DivisionRecord { t: 1.0, parent: 3, x: 4.0, x_over_length: 0.8, cells_after: 11, ..Default::default() });
    /// assert_eq!((log.len(), log.is_empty()), (1, false));
    /// ```
    pub fn push(&mut self, r: DivisionRecord) {
        self.records.push(r);
    }

    /// Number of divisions.
    ///
    /// ```
    /// assert_eq!(celltissue::events::DivisionLog::default().len(), 0);
    /// ```
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// Whether no division happened.
    ///
    /// ```
    /// assert!(celltissue::events::DivisionLog::default().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Number of cells at time `t` (right-continuous: divisions at `t` count), given `n0`.
    ///
    /// ```
    /// use celltissue::events::DivisionLog;
    /// use celltissue::observe::DivisionRecord;
    /// let mut log = DivisionLog::default();
    /// for (i, t) in [1.0, 2.0, 2.0].into_iter().enumerate() {
    ///     log.push(DivisionRecord { t, parent: 1, x: 1.0, x_over_length: 0.5, cells_after: 11 + i, ..Default::default() });
    /// }
    /// assert_eq!((log.cells_at(10, 0.5), log.cells_at(10, 1.0), log.cells_at(10, 2.0)), (10, 11, 13));
    /// ```
    pub fn cells_at(&self, n0: usize, t: f64) -> usize {
        cells_at(&self.records, n0, t)
    }

    /// Median of `x_d/l` over the divisions with `t_d ∈ [t0, t1]` (`None` if there are none).
    ///
    /// ```
    /// use celltissue::events::DivisionLog;
    /// use celltissue::observe::DivisionRecord;
    /// let mut log = DivisionLog::default();
    /// for (t, f) in [(1.0, 0.2), (2.0, 0.9), (3.0, 0.95)] {
    ///     log.push(DivisionRecord { t, parent: 1, x: f, x_over_length: f, cells_after: 2, ..Default::default() });
    /// }
    /// assert_eq!(log.median_x_over_length(1.5, 3.0), Some(0.925)); // late divisions at the rim
    /// assert_eq!(log.median_x_over_length(5.0, 6.0), None);
    /// ```
    pub fn median_x_over_length(&self, t0: f64, t1: f64) -> Option<f64> {
        median_x_over_length(&self.records, t0, t1)
    }
}

/// Number of cells at `t` from division records (right-continuous: the last record at or
/// before `t` gives its `cells_after`), `n0` before the first.
///
/// ```
/// use celltissue::events::log::cells_at;
/// use celltissue::observe::DivisionRecord;
/// let d = |t, n| DivisionRecord { t, parent: 1, x: 0.5, x_over_length: 0.5, cells_after: n, ..Default::default() };
/// let records = [d(1.0, 11), d(2.0, 12), d(2.0, 13)];
/// assert_eq!(cells_at(&records, 10, 0.5), 10);
/// assert_eq!(cells_at(&records, 10, 2.0), 13); // the divisions at t = 2 count
/// ```
pub fn cells_at(records: &[DivisionRecord], n0: usize, t: f64) -> usize {
    records
        .iter()
        .take_while(|r| r.t <= t)
        .last()
        .map_or(n0, |r| r.cells_after)
}

/// Median of `x_d/l` over records with `t_d ∈ [t0, t1]`.
///
/// ```
/// use celltissue::events::log::median_x_over_length;
/// use celltissue::observe::DivisionRecord;
/// let d = |t, f| DivisionRecord { t, parent: 1, x: 0.0, x_over_length: f, cells_after: 0, ..Default::default() };
/// let records = [d(1.0, 0.2), d(5.0, 0.9), d(6.0, 0.95), d(7.0, 0.99)];
/// assert_eq!(median_x_over_length(&records, 4.0, 10.0), Some(0.95)); // the rim
/// assert_eq!(median_x_over_length(&records, 20.0, 30.0), None);
/// ```
pub fn median_x_over_length(records: &[DivisionRecord], t0: f64, t1: f64) -> Option<f64> {
    let mut v: Vec<f64> = records
        .iter()
        .filter(|r| r.t >= t0 && r.t <= t1)
        .map(|r| r.x_over_length)
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len();
    Some(if m % 2 == 1 {
        v[m / 2]
    } else {
        0.5 * (v[m / 2 - 1] + v[m / 2])
    })
}

/// One column of division records: numbers or whole numbers (indices, counts, identities).
#[derive(Clone, Debug, PartialEq)]
pub enum DivisionColumn {
    /// Times, positions, ages.
    F64(Vec<f64>),
    /// Indices, cell counts, identities.
    I64(Vec<i64>),
}

/// The columns of `records` by name, in the order of `divisions_<label>.csv`: `t`, `parent`,
/// `x`, `x_over_length`, `cells_after`, then `age` and `cell`, `daughter_1`, `daughter_2` when
/// every record has them (a model that follows individual cells, one that traces their
/// lineage; none of these without records). The CSV, the `.npz` and Python's
/// `Run.divisions` all read these.
///
/// ```
/// use celltissue::events::log::{division_columns, DivisionColumn};
/// use celltissue::observe::DivisionRecord;
/// let d = DivisionRecord { t: 2.0, parent: 1, x: 0.5, x_over_length: 0.5, cells_after: 11,
///                          age: Some(2.0), ..Default::default() };
/// let columns = division_columns(&[d]);
/// let names: Vec<_> = columns.iter().map(|c| c.0).collect();
/// assert_eq!(names, ["t", "parent", "x", "x_over_length", "cells_after", "age"]);
/// assert_eq!(columns[4].1, DivisionColumn::I64(vec![11]));
/// ```
pub fn division_columns(records: &[DivisionRecord]) -> Vec<(&'static str, DivisionColumn)> {
    let f = |g: fn(&DivisionRecord) -> f64| DivisionColumn::F64(records.iter().map(g).collect());
    let i = |g: fn(&DivisionRecord) -> usize| {
        DivisionColumn::I64(records.iter().map(|r| g(r) as i64).collect())
    };
    let mut out = vec![
        ("t", f(|r| r.t)),
        ("parent", i(|r| r.parent)),
        ("x", f(|r| r.x)),
        ("x_over_length", f(|r| r.x_over_length)),
        ("cells_after", i(|r| r.cells_after)),
    ];
    if records.is_empty() {
        return out;
    }
    if let Some(ages) = records.iter().map(|r| r.age).collect() {
        out.push(("age", DivisionColumn::F64(ages)));
    }
    let ids = |g: fn(&DivisionRecord) -> Option<u64>| {
        records
            .iter()
            .map(|r| g(r).map(|v| v as i64))
            .collect::<Option<Vec<i64>>>()
    };
    if let (Some(cell), Some(first), Some(second)) = (
        ids(|r| r.cell),
        ids(|r| r.daughters.map(|d| d[0])),
        ids(|r| r.daughters.map(|d| d[1])),
    ) {
        out.push(("cell", DivisionColumn::I64(cell)));
        out.push(("daughter_1", DivisionColumn::I64(first)));
        out.push(("daughter_2", DivisionColumn::I64(second)));
    }
    out
}
