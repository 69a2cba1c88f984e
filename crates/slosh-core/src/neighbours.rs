//! Neighbour search behind one trait, with two implementations: a uniform cell grid
//! (counting sort, the default) and a kiddo k-d tree. Both index the moving fluid particles
//! (rebuilt every step) and the fixed wall particles (built once).

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::SVector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Which neighbour-search implementation the solver uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum NeighbourBackend {
    /// Uniform grid of cells of the kernel support size, filled by a counting sort.
    CellGrid,
    /// kiddo k-d trees (fluid rebuilt each step, walls built once).
    KdTree,
}

/// Finds the particles that may lie within the kernel support of a point.
///
/// `for_each_*_candidate` may visit particles farther than the radius given at construction
/// (the grid visits whole cells); callers test the distance themselves. Each candidate is
/// visited exactly once.
pub trait NeighbourSearch<const D: usize>: Send + Sync {
    /// Re-index the fluid particles after they moved.
    fn rebuild_fluid(&mut self, fluid: &[SVector<f64, D>]);
    /// Visit the fluid particles near `x` (indices into the fluid arrays).
    fn for_each_fluid_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, visit: F);
    /// Visit the wall particles near `x` (indices into the wall arrays).
    fn for_each_wall_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, visit: F);
}

/// Uniform cell grid over a fixed box; particles outside the box are put in the border cells
/// (the solver stops a run whose particles leave the box).
#[derive(Clone, Debug)]
pub struct CellGrid<const D: usize> {
    /// The grid's axes: grid axis k is the space axis `axes[k]`. Grid axis 0 varies fastest
    /// in the cell order (rows of cells along it are contiguous), the last one slowest.
    axes: [usize; D],
    /// Lower corner, in grid axis order.
    origin: SVector<f64, D>,
    inv_cell: f64,
    /// Cells visited on each side of a point's cell (cells are support/REACH wide).
    reach: usize,
    /// Cells along each grid axis.
    dims: [usize; D],
    /// cell_start[c]..cell_start[c+1] is the range of `fluid_entries` in cell c.
    fluid_cell_start: Vec<u32>,
    fluid_entries: Vec<u32>,
    wall_cell_start: Vec<u32>,
    wall_entries: Vec<u32>,
    /// Per cell: whether its search stencil holds any wall particle (most fluid particles are
    /// far from the walls; their wall search then ends at this flag).
    wall_near: Vec<bool>,
    /// Scratch: cell of each fluid particle.
    fluid_cell: Vec<u32>,
}

/// Advances the row offsets in axes 1..D (axis 1 fastest) to the next row of the stencil,
/// each within ±`reach`; false when every row has been visited.
#[inline(always)]
fn next_row<const D: usize>(offsets: &mut [i64; D], reach: i64) -> bool {
    for o in offsets.iter_mut().skip(1) {
        *o += 1;
        if *o <= reach {
            return true;
        }
        *o = -reach;
    }
    false
}

impl<const D: usize> CellGrid<D> {
    /// Grid for neighbours within `support` (m) covering [lower, upper], with the fixed wall
    /// particles indexed once. Cells are half the support wide and a search visits two cells
    /// on each side: in 3D the 5³ cells of side h hold 42 % fewer candidates than the 3³ cells
    /// of side 2h (2D: 30 % fewer), for the same exact neighbour set.
    pub fn new(
        lower: SVector<f64, D>,
        upper: SVector<f64, D>,
        support: f64,
        walls: &[SVector<f64, D>],
    ) -> Self {
        Self::with_slow_axis(lower, upper, support, walls, D - 1)
    }

    /// As [`Self::new`], with space axis `slow` (≥ 1) slowest in the cell order instead of
    /// the last axis. The pair sweeps of the solver cut the sorted fluid into slabs across
    /// the slowest axis, each at least two cells thick: the axis of the largest extent gives
    /// the most slabs to share among threads. The x axis stays the fastest.
    pub fn with_slow_axis(
        lower: SVector<f64, D>,
        upper: SVector<f64, D>,
        support: f64,
        walls: &[SVector<f64, D>],
        slow: usize,
    ) -> Self {
        let reach = 2;
        let cell_size = support / reach as f64;
        let slow = if (1..D).contains(&slow) { slow } else { D - 1 };
        let mut axes = [0usize; D];
        for (a, axis) in (0..D).filter(|&a| a != slow).chain([slow]).enumerate() {
            axes[a] = axis;
        }
        let mut dims = [1usize; D];
        let mut origin = lower;
        for (k, dim) in dims.iter_mut().enumerate() {
            let a = axes[k];
            origin[k] = lower[a];
            *dim = (((upper[a] - lower[a]) / cell_size).ceil() as usize).max(1) + 1;
        }
        let n_cells: usize = dims.iter().product();
        let mut grid = CellGrid {
            axes,
            origin,
            inv_cell: 1.0 / cell_size,
            reach,
            dims,
            fluid_cell_start: vec![0; n_cells + 1],
            fluid_entries: Vec::new(),
            wall_cell_start: vec![0; n_cells + 1],
            wall_entries: Vec::new(),
            wall_near: vec![false; n_cells],
            fluid_cell: Vec::new(),
        };
        let mut wall_cell = vec![0u32; walls.len()];
        let mut wall_start = vec![0u32; n_cells + 1];
        let mut wall_entries = vec![0u32; walls.len()];
        grid.counting_sort(walls, &mut wall_cell, &mut wall_start, &mut wall_entries);
        grid.wall_cell_start = wall_start;
        grid.wall_entries = wall_entries;
        // A cell's stencil holds a wall particle when a wall particle's stencil holds the cell
        // (the stencil is symmetric).
        let mut wall_near = std::mem::take(&mut grid.wall_near);
        for x in walls {
            grid.for_each_row(x, |c0, c1| {
                wall_near[c0..c1].iter_mut().for_each(|f| *f = true);
            });
        }
        grid.wall_near = wall_near;
        grid
    }

    /// Visits the fluid particle indices in cell order (after `rebuild_fluid`).
    pub fn for_each_sorted<F: FnMut(usize)>(&self, mut visit: F) {
        for &i in &self.fluid_entries {
            visit(i as usize);
        }
    }

    /// Bytes of the grid's arrays (their capacities): cell starts and entries of the fluid
    /// and the walls, the per-cell wall flags and the fluid's cell scratch.
    pub fn heap_bytes(&self) -> usize {
        (self.fluid_cell_start.capacity()
            + self.fluid_entries.capacity()
            + self.wall_cell_start.capacity()
            + self.wall_entries.capacity()
            + self.fluid_cell.capacity())
            * size_of::<u32>()
            + self.wall_near.capacity() * size_of::<bool>()
    }

    /// Number of cells along each space axis.
    pub fn dims(&self) -> [usize; D] {
        let mut dims = [0; D];
        for k in 0..D {
            dims[self.axes[k]] = self.dims[k];
        }
        dims
    }

    /// Re-indexes the fluid particles and returns the cell order: `order[k]` is the index of
    /// the particle that goes to slot k when the fluid arrays are sorted by cell. After the
    /// caller has permuted its arrays by `order`, [`Self::mark_sorted`] makes the grid describe
    /// the sorted arrays (cell c holds the slots `cell_start[c]..cell_start[c + 1]`).
    pub fn sort_order(&mut self, fluid: &[SVector<f64, D>]) -> &[u32] {
        self.rebuild_fluid(fluid);
        &self.fluid_entries
    }

    /// Declares the fluid arrays sorted by the order of the last [`Self::sort_order`]: each
    /// cell's particles are then the contiguous range of its cell start.
    pub fn mark_sorted(&mut self) {
        self.fluid_entries
            .par_iter_mut()
            .enumerate()
            .with_min_len(4096)
            .for_each(|(k, e)| *e = k as u32);
    }

    /// Start of each cell's range of fluid slots (length cells + 1; valid for sorted arrays
    /// after [`Self::mark_sorted`]).
    pub fn fluid_cell_starts(&self) -> &[u32] {
        &self.fluid_cell_start
    }

    /// Largest difference of linear cell index between a cell and a cell of its search
    /// stencil.
    pub fn stencil_reach(&self) -> usize {
        let mut stride = 1;
        let mut reach = 0;
        for k in 0..D {
            reach += self.reach * stride;
            stride *= self.dims[k];
        }
        reach
    }

    /// Splits the sorted fluid into blocks of whole cells for the two-colour pair sweeps:
    /// `bounds` receives the first slot of each block and finally the particle count. Every
    /// block but the last spans at least [`Self::stencil_reach`] cells, so the pairs a block
    /// finds in the forward half stencil (see [`Self::for_each_forward_range`]) touch only
    /// its own slots and those of the next block: blocks of equal parity never touch the
    /// same slot. Blocks hold about `target` particles where the reach allows it.
    pub fn colour_blocks(&self, target: usize, bounds: &mut Vec<u32>) {
        bounds.clear();
        let starts = &self.fluid_cell_start;
        let n_cells = starts.len() - 1;
        let min_cells = self.stencil_reach();
        let n = starts[n_cells];
        let mut c0 = 0usize;
        bounds.push(0);
        loop {
            let mut c1 = (c0 + min_cells).min(n_cells);
            while c1 < n_cells && ((starts[c1] - starts[c0]) as usize) < target {
                c1 += 1;
            }
            // The rest is too short to stand alone: it joins this block.
            if c1 + min_cells >= n_cells || starts[c1] == n {
                bounds.push(n);
                return;
            }
            bounds.push(starts[c1]);
            c0 = c1;
        }
    }

    /// For the particle in slot `i` at `x` of sorted arrays (after [`Self::mark_sorted`]):
    /// calls `visit(begin, end)` for the slot ranges of the forward half of its stencil, the
    /// slots after `i` in its own cell and the cells of higher linear index. Each pair of
    /// particles within reach is then seen from exactly one of its two particles.
    #[inline(always)]
    pub fn for_each_forward_range<F: FnMut(usize, usize)>(
        &self,
        i: usize,
        x: &SVector<f64, D>,
        mut visit: F,
    ) {
        let starts = &self.fluid_cell_start;
        let c = self.cell_coords(x);
        let reach = self.reach as i64;
        let x_lo = c[0].saturating_sub(self.reach);
        let x_hi = (c[0] + self.reach).min(self.dims[0] - 1);
        // The own row from the slot after i, then the rows of higher index in axes 1..D
        // (offsets compared with the last axis most significant).
        let mut offsets = [0i64; D];
        let mut first = true;
        loop {
            if let Some(row) = self.row_start(&c, &offsets) {
                let end = starts[row + x_hi + 1] as usize;
                // One call site, so that the compiler inlines `visit`.
                let begin = if first {
                    i + 1
                } else {
                    starts[row + x_lo] as usize
                };
                visit(begin, end);
            }
            first = false;
            if !next_row(&mut offsets, reach) {
                return;
            }
        }
    }

    /// Linear index of the first cell of the row through cell `c` shifted by `offsets` in
    /// axes 1..D (the row runs along axis 0), or `None` when that row is outside the grid.
    #[inline(always)]
    fn row_start(&self, c: &[usize; D], offsets: &[i64; D]) -> Option<usize> {
        let mut base = 0usize;
        for k in (1..D).rev() {
            let ck = c[k] as i64 + offsets[k];
            if ck < 0 || ck >= self.dims[k] as i64 {
                return None;
            }
            base = base * self.dims[k] + ck as usize;
        }
        Some(base * self.dims[0])
    }

    /// Integer cell coordinates of a point, clamped to the grid.
    #[inline(always)]
    fn cell_coords(&self, x: &SVector<f64, D>) -> [usize; D] {
        let mut c = [0usize; D];
        for k in 0..D {
            // Truncation is the floor for positive values (and cheaper than `floor`).
            let f = (x[self.axes[k]] - self.origin[k]) * self.inv_cell;
            c[k] = if f > 0.0 {
                (f as usize).min(self.dims[k] - 1)
            } else {
                0 // negative, or NaN
            };
        }
        c
    }

    /// Linear cell index (x fastest) of a point.
    #[inline(always)]
    pub fn cell_index(&self, x: &SVector<f64, D>) -> usize {
        let c = self.cell_coords(x);
        let mut idx = 0;
        for k in (0..D).rev() {
            idx = idx * self.dims[k] + c[k];
        }
        idx
    }

    /// Counting sort of `points` by cell: afterwards `entries[start[c]..start[c + 1]]` lists
    /// the points of cell c in increasing index order.
    fn counting_sort(
        &self,
        points: &[SVector<f64, D>],
        cell_of: &mut [u32],
        start: &mut [u32],
        entries: &mut [u32],
    ) {
        start.iter_mut().for_each(|s| *s = 0);
        // The cells in parallel (the floating-point half of the work), the counts serially.
        cell_of
            .par_iter_mut()
            .zip(points.par_iter())
            .with_min_len(4096)
            .for_each(|(c, p)| *c = self.cell_index(p) as u32);
        for &c in cell_of.iter() {
            start[c as usize + 1] += 1;
        }
        for c in 0..start.len() - 1 {
            start[c + 1] += start[c];
        }
        // Place each point at its cell's cursor; afterwards start[c] is the end of cell c.
        for (i, &c) in cell_of.iter().enumerate() {
            let c = c as usize;
            entries[start[c] as usize] = i as u32;
            start[c] += 1;
        }
        for c in (1..start.len()).rev() {
            start[c] = start[c - 1];
        }
        start[0] = 0;
    }

    /// Calls `visit(begin, end)` for each contiguous run of cells around `x` (one run per
    /// row of 2·reach + 1 cells along the first axis).
    #[inline(always)]
    fn for_each_row<F: FnMut(usize, usize)>(&self, x: &SVector<f64, D>, mut visit: F) {
        let c = self.cell_coords(x);
        let reach = self.reach as i64;
        let x_lo = c[0].saturating_sub(self.reach);
        let x_hi = (c[0] + self.reach).min(self.dims[0] - 1);
        // Iterate over the (2·reach + 1)^(D-1) rows in the other axes.
        let mut offsets = [0i64; D];
        for o in offsets.iter_mut().skip(1) {
            *o = -reach;
        }
        loop {
            if let Some(row) = self.row_start(&c, &offsets) {
                visit(row + x_lo, row + x_hi + 1);
            }
            if !next_row(&mut offsets, reach) {
                return;
            }
        }
    }
}

impl<const D: usize> NeighbourSearch<D> for CellGrid<D> {
    fn rebuild_fluid(&mut self, fluid: &[SVector<f64, D>]) {
        self.fluid_cell.resize(fluid.len(), 0);
        self.fluid_entries.resize(fluid.len(), 0);
        let mut cell = std::mem::take(&mut self.fluid_cell);
        let mut start = std::mem::take(&mut self.fluid_cell_start);
        let mut entries = std::mem::take(&mut self.fluid_entries);
        self.counting_sort(fluid, &mut cell, &mut start, &mut entries);
        self.fluid_cell = cell;
        self.fluid_cell_start = start;
        self.fluid_entries = entries;
    }

    #[inline(always)]
    fn for_each_fluid_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, mut visit: F) {
        self.for_each_row(x, |c0, c1| {
            let (b, e) = (
                self.fluid_cell_start[c0] as usize,
                self.fluid_cell_start[c1] as usize,
            );
            for &j in &self.fluid_entries[b..e] {
                visit(j as usize);
            }
        });
    }

    #[inline(always)]
    fn for_each_wall_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, mut visit: F) {
        if !self.wall_near[self.cell_index(x)] {
            return;
        }
        self.for_each_row(x, |c0, c1| {
            let (b, e) = (
                self.wall_cell_start[c0] as usize,
                self.wall_cell_start[c1] as usize,
            );
            for &j in &self.wall_entries[b..e] {
                visit(j as usize);
            }
        });
    }
}

/// kiddo k-d trees: the fluid tree is rebuilt every step, the wall tree once.
pub struct KdTreeSearch<const D: usize> {
    radius_sq: f64,
    fluid_tree: Option<ImmutableKdTree<f64, D>>,
    wall_tree: Option<ImmutableKdTree<f64, D>>,
    scratch: Vec<[f64; D]>,
}

impl<const D: usize> KdTreeSearch<D> {
    /// Trees answering queries within `radius` (m), with the wall particles indexed once.
    pub fn new(radius: f64, walls: &[SVector<f64, D>]) -> Self {
        let pts: Vec<[f64; D]> = walls.iter().map(|p| (*p).into()).collect();
        KdTreeSearch {
            radius_sq: radius * radius,
            fluid_tree: None,
            wall_tree: ImmutableKdTree::new_from_slice(&pts).ok(),
            scratch: Vec::new(),
        }
    }
}

impl<const D: usize> NeighbourSearch<D> for KdTreeSearch<D> {
    fn rebuild_fluid(&mut self, fluid: &[SVector<f64, D>]) {
        self.scratch.clear();
        self.scratch
            .extend(fluid.iter().map(|p| <[f64; D]>::from(*p)));
        self.fluid_tree = ImmutableKdTree::new_from_slice(&self.scratch).ok();
    }

    fn for_each_fluid_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, mut visit: F) {
        if let Some(tree) = &self.fluid_tree {
            let q: [f64; D] = (*x).into();
            tree.query(&q)
                .within::<SquaredEuclidean<f64>>(self.radius_sq)
                .unsorted()
                .visit(|r| visit(r.item as usize));
        }
    }

    fn for_each_wall_candidate<F: FnMut(usize)>(&self, x: &SVector<f64, D>, mut visit: F) {
        if let Some(tree) = &self.wall_tree {
            let q: [f64; D] = (*x).into();
            tree.query(&q)
                .within::<SquaredEuclidean<f64>>(self.radius_sq)
                .unsorted()
                .visit(|r| visit(r.item as usize));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sorted indices within `radius` of `x` found through a backend's candidates.
    fn within<const D: usize, S: NeighbourSearch<D>>(
        search: &S,
        points: &[SVector<f64, D>],
        x: &SVector<f64, D>,
        radius: f64,
        fluid: bool,
    ) -> Vec<usize> {
        let mut found = Vec::new();
        let mut visit = |j: usize| {
            if (points[j] - x).norm_squared() < radius * radius {
                found.push(j);
            }
        };
        if fluid {
            search.for_each_fluid_candidate(x, &mut visit);
        } else {
            search.for_each_wall_candidate(x, &mut visit);
        }
        found.sort_unstable();
        found
    }

    /// Brute force: every point within the radius.
    fn brute<const D: usize>(
        points: &[SVector<f64, D>],
        x: &SVector<f64, D>,
        radius: f64,
    ) -> Vec<usize> {
        (0..points.len())
            .filter(|&j| (points[j] - x).norm_squared() < radius * radius)
            .collect()
    }

    /// Deterministic pseudo-random numbers in [0, 1) (xorshift), so the test needs no crate.
    fn random_points<const D: usize>(n: usize, size: f64, seed: u64) -> Vec<SVector<f64, D>> {
        let mut state = seed;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| SVector::<f64, D>::from_fn(|_, _| next() * size))
            .collect()
    }

    /// Both backends return exactly the brute-force neighbour lists (exact: integer sets), for
    /// random points and for lattice points (many exact ties at cell borders), in 2D and 3D,
    /// as fluid and as wall sets.
    fn check<const D: usize>(
        points: Vec<SVector<f64, D>>,
        queries: &[SVector<f64, D>],
        radius: f64,
    ) {
        let lo = SVector::<f64, D>::from_element(-0.1);
        let hi = SVector::<f64, D>::from_element(1.1);
        let mut grid = CellGrid::new(lo, hi, radius, &points);
        grid.rebuild_fluid(&points);
        // The same grid with the y axis slowest in the cell order.
        let mut grid_y = CellGrid::with_slow_axis(lo, hi, radius, &points, 1);
        grid_y.rebuild_fluid(&points);
        let mut tree = KdTreeSearch::new(radius, &points);
        tree.rebuild_fluid(&points);
        for x in queries {
            let expected = brute(&points, x, radius);
            for fluid in [true, false] {
                assert_eq!(within(&grid, &points, x, radius, fluid), expected);
                assert_eq!(within(&grid_y, &points, x, radius, fluid), expected);
                assert_eq!(within(&tree, &points, x, radius, fluid), expected);
            }
        }
    }

    /// On cell-sorted points the forward ranges find every pair within the radius exactly
    /// once (from its lower slot), and the pairs found from a colour block stay within that
    /// block and the next.
    #[test]
    fn forward_ranges_find_each_pair_once() {
        let radius = 0.12;
        let lo = SVector::<f64, 3>::from_element(-0.1);
        let hi = SVector::<f64, 3>::from_element(1.1);
        let points = random_points::<3>(4000, 1.0, 23);
        let mut grid = CellGrid::with_slow_axis(lo, hi, radius, &[], 1);
        let order = grid.sort_order(&points).to_vec();
        let sorted: Vec<SVector<f64, 3>> = order.iter().map(|&i| points[i as usize]).collect();
        grid.mark_sorted();
        let mut bounds = Vec::new();
        grid.colour_blocks(300, &mut bounds);
        assert!(bounds.len() > 3, "too few blocks: {bounds:?}");
        let mut found = 0usize;
        for b in 0..bounds.len() - 1 {
            let limit = bounds
                .get(b + 2)
                .copied()
                .unwrap_or(bounds[bounds.len() - 1]) as usize;
            for i in bounds[b] as usize..bounds[b + 1] as usize {
                grid.for_each_forward_range(i, &sorted[i], |j0, j1| {
                    assert!(
                        j0 > i && j1 <= limit,
                        "slot {i}: range {j0}..{j1}, limit {limit}"
                    );
                    for j in j0..j1 {
                        if (sorted[i] - sorted[j]).norm_squared() < radius * radius {
                            found += 1;
                        }
                    }
                });
            }
        }
        let mut expected = 0usize;
        for i in 0..sorted.len() {
            for j in i + 1..sorted.len() {
                if (sorted[i] - sorted[j]).norm_squared() < radius * radius {
                    expected += 1;
                }
            }
        }
        assert_eq!(found, expected);
    }

    #[test]
    fn grid_and_kdtree_match_brute_force() {
        let radius = 0.052;
        // Random points in 2D and 3D.
        let p2 = random_points::<2>(3000, 1.0, 7);
        let q2 = random_points::<2>(300, 1.0, 11);
        check(p2, &q2, radius);
        let p3 = random_points::<3>(4000, 1.0, 13);
        let q3 = random_points::<3>(2000, 1.0, 17);
        check(p3, &q3, 0.12);
        // A lattice of spacing 0.02 queried at its own points.
        let lattice: Vec<SVector<f64, 2>> = (0..50)
            .flat_map(|i| {
                (0..50).map(move |j| {
                    SVector::<f64, 2>::new(0.01 + 0.02 * i as f64, 0.01 + 0.02 * j as f64)
                })
            })
            .collect();
        let queries: Vec<SVector<f64, 2>> = lattice.iter().step_by(7).copied().collect();
        check(lattice, &queries, radius);
        // A 3D lattice of spacing 0.03 (a support of 4 spacings, 0.12 m, ties at every cell
        // border) queried at its own points.
        let lattice: Vec<SVector<f64, 3>> = (0..30 * 30 * 30)
            .map(|n| {
                SVector::<f64, 3>::new(
                    0.015 + 0.03 * (n % 30) as f64,
                    0.015 + 0.03 * (n / 30 % 30) as f64,
                    0.015 + 0.03 * (n / 900) as f64,
                )
            })
            .collect();
        let queries: Vec<SVector<f64, 3>> = lattice.iter().step_by(97).copied().collect();
        check(lattice, &queries, 0.12);
    }

    /// Points outside the grid's box (a run about to stop) sit in its border cells: the
    /// search still finds every neighbour, of points inside and outside alike.
    #[test]
    fn points_outside_the_box_keep_their_neighbours() {
        let shift = |v: SVector<f64, 3>| v * 1.6 - SVector::<f64, 3>::from_element(0.3);
        let points: Vec<SVector<f64, 3>> = random_points::<3>(6000, 1.0, 29)
            .into_iter()
            .map(shift)
            .collect();
        let queries: Vec<SVector<f64, 3>> = random_points::<3>(2000, 1.0, 31)
            .into_iter()
            .map(shift)
            .collect();
        assert!(
            points
                .iter()
                .filter(|p| p.min() < -0.1 || p.max() > 1.1)
                .count()
                > 1000
        );
        check(points, &queries, 0.12);
    }
}
