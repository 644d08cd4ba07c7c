//! The entry every best-first search here keeps in its `BinaryHeap`: a priority, an insertion
//! counter and a state index. One type so that all searches break ties the same way (first
//! pushed, first popped), which is what keeps their routes byte-identical from run to run.

use std::cmp::Ordering;

#[derive(Clone, Copy)]
pub(crate) struct OpenEntry {
    /// What the search orders by (g, or g + h).
    pub key: f64,
    /// Insertion order, the tie-break.
    pub seq: u64,
    pub state: u32,
}

impl PartialEq for OpenEntry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for OpenEntry {}
impl PartialOrd for OpenEntry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for OpenEntry {
    /// Reversed so that `BinaryHeap` (a max-heap) pops the smallest `(key, seq)` first.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .key
            .total_cmp(&self.key)
            .then_with(|| other.seq.cmp(&self.seq))
    }
}
