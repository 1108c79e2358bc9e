//! Lineage tracing on a dividing line ([`Lineage`]): every cell's identity and the initial
//! cell it descends from (its clone), carried through every division. [`super::Dividing`]
//! keeps one for a discrete line or ring; each division record then names the dividing cell
//! and its daughters ([`crate::observe::DivisionRecord::cell`], `daughters`), and the profiles
//! carry `id` and `ancestor` per cell, so a clone can be followed through the tissue (as a
//! cell-based simulator's cell-identity and ancestor outputs do). The proliferating continua
//! have no individual cells and keep none.

use super::reindex::expand_in_place;

/// Identity and clone of every cell of a dividing line, in the line's order.
///
/// ```
/// use celltissue::events::Lineage;
/// let mut l = Lineage::new(3);
/// // cells 0 and 2 divide at one event: daughters numbered in line order from 3
/// assert_eq!(l.divide(&[0, 2]), [(0, [3, 4]), (2, [5, 6])]);
/// assert_eq!(l.id, [3, 4, 1, 5, 6]);
/// assert_eq!(l.ancestor, [0, 0, 1, 2, 2]);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lineage {
    /// Each cell's identity: the initial cells are `0..N₀`, each division numbers its two
    /// daughters with the next unused identities.
    pub id: Vec<u64>,
    /// The initial cell each cell descends from.
    pub ancestor: Vec<u64>,
    /// The next unused identity.
    next: u64,
}

impl Lineage {
    /// The lineage of `n` initial cells, each its own ancestor.
    ///
    /// ```
    /// assert_eq!(celltissue::events::Lineage::new(2).ancestor, [0, 1]);
    /// ```
    pub fn new(n: usize) -> Self {
        let id: Vec<u64> = (0..n as u64).collect();
        Self {
            ancestor: id.clone(),
            next: n as u64,
            id,
        }
    }

    /// Splits the cells at the 0-based, strictly increasing positions `at` (one event) in
    /// place: each becomes two daughters with new identities and the parent's ancestor.
    /// Returns, in the order of `at`, each parent's identity and its daughters'.
    ///
    /// ```
    /// let mut l = celltissue::events::Lineage::new(1);
    /// assert_eq!(l.divide(&[0]), [(0, [1, 2])]);
    /// assert_eq!(l.divide(&[1]), [(2, [3, 4])]);
    /// assert_eq!((l.id.clone(), l.ancestor.clone()), (vec![1, 3, 4], vec![0, 0, 0]));
    /// ```
    pub fn divide(&mut self, at: &[usize]) -> Vec<(u64, [u64; 2])> {
        let next = self.next;
        let made: Vec<(u64, [u64; 2])> = at
            .iter()
            .enumerate()
            .map(|(e, &i)| {
                let first = next + 2 * e as u64;
                (self.id[i], [first, first + 1])
            })
            .collect();
        expand_in_place(&mut self.id, at, |e, _| made[e].1);
        expand_in_place(&mut self.ancestor, at, |e, v| [v[at[e]]; 2]);
        self.next += 2 * at.len() as u64;
        made
    }

    /// The profile fields `id` and `ancestor` (as floating-point numbers, exact below 2⁵³).
    ///
    /// ```
    /// let f = celltissue::events::Lineage::new(2).profile_fields();
    /// assert_eq!(f[1], ("ancestor", vec![0.0, 1.0]));
    /// ```
    pub fn profile_fields(&self) -> [(&'static str, Vec<f64>); 2] {
        let f = |v: &[u64]| v.iter().map(|&i| i as f64).collect();
        [("id", f(&self.id)), ("ancestor", f(&self.ancestor))]
    }
}
