//! Square grids addressed by `[row, col]`, the one array type every layer, mask and distance field
//! uses, so that the map model, the planner and the evaluator agree on indexing without copies.
//!
//! Row follows world z and col follows world x, as in the Map2Route maps. Storage is row-major.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A grid cell `[row, col]`. Serialized as a two-element JSON array, as in every Map2Route file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    pub row: u32,
    pub col: u32,
}

impl Cell {
    pub const fn new(row: u32, col: u32) -> Self {
        Cell { row, col }
    }

    /// Euclidean distance between cell centres, in cells.
    pub fn dist(self, other: Cell) -> f64 {
        let dr = self.row as f64 - other.row as f64;
        let dc = self.col as f64 - other.col as f64;
        dr.hypot(dc)
    }

    /// Squared Euclidean distance in cells, exact: nearest-cell searches compare these and take
    /// one square root at the end instead of one per pair.
    pub fn dist_sq(self, other: Cell) -> u64 {
        let dr = self.row.abs_diff(other.row) as u64;
        let dc = self.col.abs_diff(other.col) as u64;
        dr * dr + dc * dc
    }

    /// Distance to the nearest of `cells`, in cells (infinite for none).
    pub fn nearest_dist(self, cells: &[Cell]) -> f64 {
        cells
            .iter()
            .map(|c| self.dist_sq(*c))
            .min()
            .map_or(f64::INFINITY, |d| (d as f64).sqrt())
    }
}

impl Serialize for Cell {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        [self.row, self.col].serialize(s)
    }
}

impl<'de> Deserialize<'de> for Cell {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [row, col] = <[u32; 2]>::deserialize(d)?;
        Ok(Cell { row, col })
    }
}

/// An N×N array of `T`, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid<T> {
    n: usize,
    data: Vec<T>,
}

impl<T: Clone> Grid<T> {
    pub fn new(n: usize, fill: T) -> Self {
        Grid {
            n,
            data: vec![fill; n * n],
        }
    }
}

impl<T> Grid<T> {
    /// Builds a grid from row-major data; `None` when the length is not `n * n`.
    pub fn from_vec(n: usize, data: Vec<T>) -> Option<Self> {
        (data.len() == n * n).then_some(Grid { n, data })
    }

    /// Side length N.
    pub fn n(&self) -> usize {
        self.n
    }

    pub fn data(&self) -> &[T] {
        &self.data
    }

    pub fn data_mut(&mut self) -> &mut [T] {
        &mut self.data
    }

    pub fn into_vec(self) -> Vec<T> {
        self.data
    }

    pub fn contains(&self, row: i64, col: i64) -> bool {
        row >= 0 && col >= 0 && (row as usize) < self.n && (col as usize) < self.n
    }

    pub fn index(&self, cell: Cell) -> usize {
        cell.row as usize * self.n + cell.col as usize
    }

    pub fn cell(&self, index: usize) -> Cell {
        Cell::new((index / self.n) as u32, (index % self.n) as u32)
    }

    /// The value at `cell`, or `None` outside the grid.
    pub fn get(&self, cell: Cell) -> Option<&T> {
        if (cell.row as usize) < self.n && (cell.col as usize) < self.n {
            self.data.get(self.index(cell))
        } else {
            None
        }
    }

    pub fn get_mut(&mut self, cell: Cell) -> Option<&mut T> {
        if (cell.row as usize) < self.n && (cell.col as usize) < self.n {
            let i = self.index(cell);
            self.data.get_mut(i)
        } else {
            None
        }
    }

    /// Sets the value at `cell`; cells outside the grid are ignored.
    pub fn set(&mut self, cell: Cell, value: T) {
        if let Some(slot) = self.get_mut(cell) {
            *slot = value;
        }
    }

    /// One row as a slice.
    pub fn row(&self, row: usize) -> &[T] {
        &self.data[row * self.n..(row + 1) * self.n]
    }

    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid<U> {
        Grid {
            n: self.n,
            data: self.data.iter().map(f).collect(),
        }
    }

    /// Iterates `(cell, &value)` in row-major order.
    pub fn iter_cells(&self) -> impl Iterator<Item = (Cell, &T)> {
        let n = self.n;
        self.data
            .iter()
            .enumerate()
            .map(move |(i, v)| (Cell::new((i / n) as u32, (i % n) as u32), v))
    }
}
