//! Running a scenario's runs in parallel and in shards.
//!
//! - [`run_parallel`] runs a chosen subset of a scenario's [`RunSpec`]s on a rayon pool of
//!   `jobs` threads and returns the records **in scenario order**, whatever order they finish
//!   in, so every output written from them is the same as with one job (timing fields aside).
//! - [`Shard`] picks one share of a sweep's runs (`--shard i/n`, or a SLURM job array's task
//!   id and count with `--shard auto`); the shards' records are put back together in scenario
//!   order by `celltissue merge`.
//!
//! No I/O here beyond what a runner does.

use super::load::{RunSpec, Scenario};
use crate::observe::RunRecord;
use std::sync::Mutex;
use thiserror::Error;

/// Why runs could not be scheduled.
///
/// ```
/// use celltissue::scenario::parallel::{ParallelError, Shard};
/// let e: ParallelError = "3/2".parse::<Shard>().unwrap_err();
/// assert!(matches!(e, ParallelError::Shard(_)));
/// assert!(e.to_string().starts_with("`--shard`:"), "{e}");
/// ```
#[derive(Debug, Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParallelError {
    /// `jobs` must be at least one.
    #[error("`--jobs`: must be an integer ≥ 1 (got {0})")]
    Jobs(usize),
    /// The thread pool could not be created.
    #[error("cannot start {jobs} worker threads: {message}")]
    Pool {
        /// Threads asked for.
        jobs: usize,
        /// The system's reason.
        message: String,
    },
    /// A shard specification is malformed or out of range.
    #[error("`--shard`: {0}")]
    Shard(String),
}

/// One share of a sweep: shard `index` (0-based) of `count`.
///
/// Run `k` of the scenario (in scenario order) belongs to shard `k mod count`, so every
/// shard of a sweep of equal runs gets the same amount of work whatever the order of runs.
///
/// ```
/// use celltissue::scenario::parallel::Shard;
/// let s: Shard = "1/3".parse()?;
/// assert_eq!(s.indices(7), vec![1, 4]);
/// assert!("3/3".parse::<Shard>().is_err());
/// # Ok::<(), celltissue::scenario::parallel::ParallelError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard, `0 ≤ index < count`.
    pub index: usize,
    /// Number of shards, `≥ 1`.
    pub count: usize,
}

impl Shard {
    /// Shard `index` of `count`, checked.
    ///
    /// ```
    /// use celltissue::scenario::parallel::Shard;
    /// assert!(Shard::new(1, 3).is_ok());
    /// assert!(Shard::new(3, 3).is_err()); // 0-based: 0, 1, 2
    /// ```
    pub fn new(index: usize, count: usize) -> Result<Shard, ParallelError> {
        if count == 0 {
            return Err(ParallelError::Shard(format!(
                "the number of shards must be ≥ 1 (got {index}/{count})"
            )));
        }
        if index >= count {
            return Err(ParallelError::Shard(format!(
                "the shard index must be from 0 to {} (got {index}/{count}; shards count from 0)",
                count - 1
            )));
        }
        Ok(Shard { index, count })
    }

    /// The shard of a SLURM job array task, from `SLURM_ARRAY_TASK_ID` and
    /// `SLURM_ARRAY_TASK_COUNT` (with `--array=0-(n-1)`; the task id is taken relative to
    /// `SLURM_ARRAY_TASK_MIN` when that is set, so `--array=1-n` works as well).
    ///
    /// ```
    /// use celltissue::scenario::parallel::Shard;
    /// // `sbatch --array=1-4`: task 3 of 4, ids from 1
    /// let env = |k: &str| match k {
    ///     "SLURM_ARRAY_TASK_ID" => Some("3".to_string()),
    ///     "SLURM_ARRAY_TASK_COUNT" => Some("4".to_string()),
    ///     "SLURM_ARRAY_TASK_MIN" => Some("1".to_string()),
    ///     _ => None,
    /// };
    /// assert_eq!(Shard::from_slurm(env)?, Shard { index: 2, count: 4 });
    /// assert!(Shard::from_slurm(|_| None).is_err());
    /// # Ok::<(), celltissue::scenario::parallel::ParallelError>(())
    /// ```
    pub fn from_slurm(var: impl Fn(&str) -> Option<String>) -> Result<Shard, ParallelError> {
        let get = |name: &str| -> Result<usize, ParallelError> {
            let v = var(name).ok_or_else(|| {
                ParallelError::Shard(format!(
                    "`auto` needs the environment variable {name} (set by `sbatch --array`)"
                ))
            })?;
            v.trim().parse().map_err(|_| {
                ParallelError::Shard(format!("{name} = `{v}` is not a non-negative integer"))
            })
        };
        let id = get("SLURM_ARRAY_TASK_ID")?;
        let count = get("SLURM_ARRAY_TASK_COUNT")?;
        let min = match var("SLURM_ARRAY_TASK_MIN") {
            Some(_) => get("SLURM_ARRAY_TASK_MIN")?,
            None => 0,
        };
        Shard::new(id.saturating_sub(min), count)
    }

    /// The indices (in scenario order) of the runs of a scenario with `total` runs that
    /// belong to this shard.
    ///
    /// ```
    /// use celltissue::scenario::parallel::Shard;
    /// assert_eq!(Shard::new(1, 3)?.indices(8), [1, 4, 7]);
    /// # Ok::<(), celltissue::scenario::parallel::ParallelError>(())
    /// ```
    pub fn indices(&self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }
}

impl std::str::FromStr for Shard {
    type Err = ParallelError;

    /// Parses `i/n` (0-based `i`).
    fn from_str(s: &str) -> Result<Shard, ParallelError> {
        let bad = || {
            ParallelError::Shard(format!(
                "`{s}` is not `i/n` with integers 0 ≤ i < n (or `auto`)"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let i = i.trim().parse().map_err(|_| bad())?;
        let n = n.trim().parse().map_err(|_| bad())?;
        Shard::new(i, n)
    }
}

/// Runs the specs `indices` of `scenario` with `runner` on `jobs` threads; returns the records
/// in the order of `indices`. `progress` is called once per finished run (in finishing order,
/// one call at a time).
///
/// With `jobs == 1` the runs go one after another on the calling thread. Each run is
/// independent (its own problem, integrator and outputs), so the records do not depend on
/// `jobs`; only their `wall_seconds` do.
///
/// ```
/// use celltissue::scenario::{load_str, parallel::run_parallel, execute::run_spec};
/// let text = r#"
/// name = "tiny"
/// [output]
/// series = [0, 1]
/// [model]
/// kind = "line"
/// models = ["discrete"]
/// cells = 4
/// [sweep]
/// parameter = "K"
/// values = [1, 2, 3]
/// "#;
/// let s = load_str(text, "tiny.toml".as_ref(), &[])?;
/// let recs = run_parallel(&s, &[0, 1, 2], 2, run_spec, |_| {})?;
/// assert_eq!(recs.iter().map(|r| r.label.as_str()).collect::<Vec<_>>(),
///            ["discrete K=1", "discrete K=2", "discrete K=3"]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_parallel(
    scenario: &Scenario,
    indices: &[usize],
    jobs: usize,
    runner: impl Fn(&RunSpec) -> RunRecord + Sync,
    progress: impl FnMut(&RunRecord) + Send,
) -> Result<Vec<RunRecord>, ParallelError> {
    if jobs == 0 {
        return Err(ParallelError::Jobs(jobs));
    }
    let specs: Vec<&RunSpec> = indices.iter().map(|&k| &scenario.runs[k]).collect();
    if jobs == 1 || specs.len() <= 1 {
        let mut progress = progress;
        return Ok(specs
            .into_iter()
            .map(|spec| {
                let rec = runner(spec);
                progress(&rec);
                rec
            })
            .collect());
    }
    use rayon::prelude::*;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.min(specs.len()))
        .build()
        .map_err(|e| ParallelError::Pool {
            jobs,
            message: e.to_string(),
        })?;
    let progress = Mutex::new(progress);
    Ok(pool.install(|| {
        specs
            .par_iter()
            // one run per task: runs are long and of unequal length
            .with_max_len(1)
            .map(|spec| {
                let rec = runner(spec);
                if let Ok(mut p) = progress.lock() {
                    p(&rec);
                }
                rec
            })
            .collect()
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_runs() {
        for total in 0..12 {
            for count in 1..5 {
                let mut all: Vec<usize> = (0..count)
                    .flat_map(|i| Shard::new(i, count).unwrap().indices(total))
                    .collect();
                all.sort_unstable();
                assert_eq!(all, (0..total).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn bad_shards_are_rejected_with_the_range() {
        for s in ["", "1", "a/2", "1/0", "2/2", "-1/2", "1/2/3"] {
            let e = s.parse::<Shard>().unwrap_err();
            assert!(e.to_string().starts_with("`--shard`"), "{s}: {e}");
        }
        assert!("2/2"
            .parse::<Shard>()
            .unwrap_err()
            .to_string()
            .contains("from 0 to 1"));
    }

    #[test]
    fn slurm_variables() {
        let env = |id: &'static str, n: &'static str, min: Option<&'static str>| {
            move |k: &str| match k {
                "SLURM_ARRAY_TASK_ID" => Some(id.to_string()),
                "SLURM_ARRAY_TASK_COUNT" => Some(n.to_string()),
                "SLURM_ARRAY_TASK_MIN" => min.map(str::to_string),
                _ => None,
            }
        };
        assert_eq!(
            Shard::from_slurm(env("2", "4", None)).unwrap(),
            Shard::new(2, 4).unwrap()
        );
        assert_eq!(
            Shard::from_slurm(env("4", "4", Some("1"))).unwrap(),
            Shard::new(3, 4).unwrap()
        );
        assert!(Shard::from_slurm(env("4", "4", None)).is_err());
        assert!(Shard::from_slurm(env("x", "4", None))
            .unwrap_err()
            .to_string()
            .contains("SLURM_ARRAY_TASK_ID"));
        assert!(Shard::from_slurm(|_| None)
            .unwrap_err()
            .to_string()
            .contains("sbatch --array"));
    }

    #[test]
    fn zero_jobs_is_an_error() {
        let s = crate::scenario::load_str(
            "name = \"x\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\ncells = 3\n",
            "x.toml".as_ref(),
            &[],
        )
        .unwrap();
        let r = run_parallel(&s, &[0], 0, crate::scenario::execute::run_spec, |_| {});
        assert_eq!(r.unwrap_err(), ParallelError::Jobs(0));
    }
}
