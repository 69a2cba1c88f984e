//! The pair-sweep driver: scheduling of the half sweep over cell-sorted blocks, batching,
//! neighbour-list filling; every `unsafe` line of the solver is here.

use crate::neighbours::CellGrid;
use crate::sim::*;
use rayon::prelude::*;

/// A slice written through by the blocks of one colour of a pair sweep (`colour_sweep`),
/// which touch disjoint slots.
pub(crate) struct SharedSlice<T> {
    pub(crate) ptr: *mut T,
    pub(crate) len: usize,
}

// SAFETY: a SharedSlice is only dereferenced at slots that no other thread touches at the
// same time (see `at`); the element type itself moves between threads.
unsafe impl<T: Send> Send for SharedSlice<T> {}
unsafe impl<T: Send> Sync for SharedSlice<T> {}

impl<T> SharedSlice<T> {
    pub(crate) fn new(values: &mut [T]) -> Self {
        SharedSlice {
            ptr: values.as_mut_ptr(),
            len: values.len(),
        }
    }

    /// The element at `i`.
    ///
    /// # Safety
    /// No other thread may access slot `i` while the reference lives: in a colour sweep,
    /// slot `i` belongs to the running block or to the next one, and blocks of one colour are
    /// two apart.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn at(&self, i: usize) -> &mut T {
        debug_assert!(i < self.len);
        &mut *self.ptr.add(i)
    }

    /// The `len` elements from `start`.
    ///
    /// # Safety
    /// As for [`Self::at`], for every slot of the range.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn slice(&self, start: usize, len: usize) -> &mut [T] {
        debug_assert!(start + len <= self.len);
        std::slice::from_raw_parts_mut(self.ptr.add(start), len)
    }
}

/// Runs `block(b, begin, end)` for every block b of slots given by `bounds` (see
/// [`CellGrid::colour_blocks`]). A block may write its own slots and those of the next block,
/// so two neighbouring blocks never run at the same time, and each slot receives its shares
/// in one fixed order: the even blocks come first (each may run at any time), and an odd
/// block runs once both its even neighbours are done. The result is therefore that of a
/// sweep over all even blocks followed by one over all odd blocks, whatever the number of
/// threads, but without a barrier between the two colours: a thread that finds no block
/// ready waits only for the neighbours of the next one (with two threads on 32 blocks, the
/// barrier between colours left each thread idle ≈ 10 % of a sweep).
pub(crate) fn colour_sweep<F: Fn(usize, usize, usize) + Sync>(bounds: &[u32], block: F) {
    let n_blocks = bounds.len().saturating_sub(1);
    let run = |b: usize| block(b, bounds[b] as usize, bounds[b + 1] as usize);
    if rayon::current_num_threads() <= 1 || n_blocks <= 2 {
        (0..n_blocks)
            .step_by(2)
            .chain((1..n_blocks).step_by(2))
            .for_each(run);
        return;
    }
    if n_blocks > BlockStates::MAX_BLOCKS {
        for parity in 0..2 {
            (parity..n_blocks)
                .into_par_iter()
                .step_by(2)
                .with_max_len(1)
                .for_each(run);
        }
        return;
    }
    let states = BlockStates::new(n_blocks);
    rayon::broadcast(|ctx| {
        while let Some(b) = states.claim(ctx.index(), ctx.num_threads()) {
            run(b);
            states.finish(b);
        }
    });
}

/// The progress of the blocks of one [`colour_sweep`], shared by its threads (no allocation:
/// at most [`Self::MAX_BLOCKS`] blocks, which `colour_blocks` with ≈ n/32 particles a block
/// never exceeds).
pub(crate) struct BlockStates {
    /// Per block: `TODO`, `RUNNING` or `DONE`.
    pub(crate) state: [std::sync::atomic::AtomicU8; Self::MAX_BLOCKS],
    pub(crate) n_blocks: usize,
}

impl BlockStates {
    const MAX_BLOCKS: usize = 128;
    const TODO: u8 = 0;
    const RUNNING: u8 = 1;
    const DONE: u8 = 2;

    pub(crate) fn new(n_blocks: usize) -> Self {
        BlockStates {
            state: std::array::from_fn(|_| std::sync::atomic::AtomicU8::new(Self::TODO)),
            n_blocks,
        }
    }

    pub(crate) fn is_done(&self, b: usize) -> bool {
        b >= self.n_blocks || self.state[b].load(std::sync::atomic::Ordering::Acquire) == Self::DONE
    }

    /// Claims block `b` if it is still to do and may run now (an odd block reads what its
    /// even neighbours wrote into its slots, so it waits until both are done).
    pub(crate) fn try_claim(&self, b: usize) -> bool {
        use std::sync::atomic::Ordering;
        self.state[b].load(Ordering::Relaxed) == Self::TODO
            && (b.is_multiple_of(2) || (self.is_done(b - 1) && self.is_done(b + 1)))
            && self.state[b]
                .compare_exchange(
                    Self::TODO,
                    Self::RUNNING,
                    Ordering::Acquire,
                    Ordering::Relaxed,
                )
                .is_ok()
    }

    /// Claims a block for thread `thread` of `threads`, waiting while blocks remain but none
    /// may run; `None` once every block is claimed. Each thread has a home range of blocks,
    /// the same in every sweep (`thread`/`threads` of the slots), which it takes lowest
    /// first, so that its particles stay in its core's cache from sweep to sweep; with its
    /// range exhausted it takes the highest block that may run elsewhere, the one its owner
    /// would reach last.
    pub(crate) fn claim(&self, thread: usize, threads: usize) -> Option<usize> {
        let n = self.n_blocks;
        let (home_lo, home_hi) = (thread * n / threads, (thread + 1) * n / threads);
        let mut spins = 0u32;
        loop {
            if let Some(b) = (home_lo..home_hi).find(|&b| self.try_claim(b)) {
                return Some(b);
            }
            if let Some(b) = (home_hi..n)
                .chain(0..home_lo)
                .rev()
                .find(|&b| self.try_claim(b))
            {
                return Some(b);
            }
            let any_todo = (0..n)
                .any(|b| self.state[b].load(std::sync::atomic::Ordering::Relaxed) == Self::TODO);
            if !any_todo {
                return None;
            }
            spins += 1;
            if spins < 64 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }

    /// Marks block `b` done: its writes become visible to the threads that see the mark.
    pub(crate) fn finish(&self, b: usize) {
        self.state[b].store(Self::DONE, std::sync::atomic::Ordering::Release);
    }
}

/// One particle's consumer of its forward fluid pairs in the sorted sweeps, fed by
/// [`forward_pairs_batched`].
pub(crate) trait ForwardPairBatch {
    /// A batch of at most [`BATCH`] pairs within the support: neighbour indices and squared
    /// distances (m²).
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]);
}

/// Hands the forward fluid neighbours of sorted particle `i` (those it finds in its forward
/// half stencil) within the support (`support_sq`, m²) to `sink`, in batches of [`BATCH`] and
/// a last, shorter one. The candidate loop has no unpredictable branch: every candidate is
/// written into the batch and only those within the support advance its fill.
#[inline(always)]
pub(crate) fn forward_pairs_batched<const D: usize, S: ForwardPairBatch>(
    grid: &CellGrid<D>,
    pos: &[Vector<D>],
    i: usize,
    support_sq: f64,
    sink: &mut S,
) {
    let xi = pos[i];
    let mut batch_j = [0u32; BATCH];
    let mut batch_r2 = [0.0f64; BATCH];
    let mut batched = 0usize;
    grid.for_each_forward_range(i, &xi, |j0, j1| {
        for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
            let r2 = (xi - xj).norm_squared();
            batch_j[batched] = j as u32;
            batch_r2[batched] = r2;
            batched += (r2 < support_sq) as usize;
            if batched == BATCH {
                sink.batch(&batch_j, &batch_r2);
                batched = 0;
            }
        }
    });
    sink.batch(&batch_j[..batched], &batch_r2[..batched]);
}

/// How far a neighbour list is filled, and whether an entry did not fit.
#[derive(Clone, Copy, Default)]
pub(crate) struct ListFill {
    pub(crate) listed: usize,
    pub(crate) overflow: bool,
}

impl ListFill {
    /// Appends `entry` if `list` has room.
    #[inline(always)]
    pub(crate) fn push(&mut self, list: &mut [u32], entry: u32) {
        if self.listed < list.len() {
            list[self.listed] = entry;
            self.listed += 1;
        } else {
            self.overflow = true;
        }
    }

    /// Appends `found` as far as `list` has room.
    #[inline(always)]
    pub(crate) fn append(&mut self, list: &mut [u32], found: &[u32]) {
        let room = found.len().min(list.len() - self.listed);
        list[self.listed..self.listed + room].copy_from_slice(&found[..room]);
        self.listed += room;
        self.overflow |= room < found.len();
    }

    /// The count stored for the list: its fill, or [`LIST_OVERFLOW`].
    #[inline(always)]
    pub(crate) fn stored_count(self) -> u16 {
        if self.overflow {
            LIST_OVERFLOW
        } else {
            self.listed as u16
        }
    }
}

/// The fluid particles' shares of the wall particles' density sums (Eq. 19 at walls),
/// scattered by the density sweep: one set of sums per block residue modulo [`Self::SETS`],
/// so that blocks running at the same time never add to the same entry.
#[derive(Clone, Debug, Default)]
pub(crate) struct WallScatter {
    /// Σ m W per set and wall particle (set-major).
    pub(crate) rho: Vec<f64>,
    /// Σ (m/ρ_j) W per set and wall particle.
    pub(crate) kernel_sum: Vec<f64>,
    /// Squared distance of the nearest fluid particle per set and wall particle.
    pub(crate) nearest_r2: Vec<f64>,
    /// That fluid particle (u32::MAX: none).
    pub(crate) nearest: Vec<u32>,
}

impl WallScatter {
    /// Sets: blocks b and b + 4 of one colour are ≥ 3 stencil reaches apart, while two fluid
    /// neighbours of one wall particle are at most 2 apart.
    pub(crate) const SETS: usize = 4;

    pub(crate) fn new(n_wall: usize) -> Self {
        let len = Self::SETS * n_wall;
        WallScatter {
            rho: vec![0.0; len],
            kernel_sum: vec![0.0; len],
            nearest_r2: vec![f64::INFINITY; len],
            nearest: vec![u32::MAX; len],
        }
    }

    /// Bytes held.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.rho.len() * 28
    }
}

/// A neighbour list of the sorted sweeps split into its fluid neighbours (first) and its
/// wall neighbours (flagged, last).
#[inline(always)]
pub(crate) fn split_walls(list: &[u32]) -> (&[u32], &[u32]) {
    list.split_at(list.partition_point(|&e| e & WALL_NEIGHBOUR == 0))
}

#[cfg(test)]
mod sweep_tests {
    use super::colour_sweep;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// The schedule of `colour_sweep` on three threads: every block runs once, no two
    /// neighbouring blocks overlap in time, and an odd block starts only after both its even
    /// neighbours have ended; for the dependency schedule (9 and 40 blocks) and the
    /// two-barrier fallback beyond `BlockStates::MAX_BLOCKS` (200 blocks).
    #[test]
    pub(crate) fn blocks_respect_their_neighbours() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        for n_blocks in [9usize, 40, 200] {
            let bounds: Vec<u32> = (0..=n_blocks as u32).map(|b| 10 * b).collect();
            let clock = AtomicUsize::new(0);
            let runs: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            let start: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            let end: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            pool.install(|| {
                colour_sweep(&bounds, |b, begin, stop| {
                    assert_eq!((begin, stop), (10 * b, 10 * b + 10));
                    start[b].store(clock.fetch_add(1, Ordering::SeqCst), Ordering::SeqCst);
                    runs[b].fetch_add(1, Ordering::SeqCst);
                    // Some work, so that threads overlap.
                    let mut x = b as f64;
                    for _ in 0..20_000 {
                        x = std::hint::black_box(x.sin());
                    }
                    end[b].store(clock.fetch_add(1, Ordering::SeqCst), Ordering::SeqCst);
                })
            });
            let get = |v: &Vec<AtomicUsize>, b: usize| v[b].load(Ordering::SeqCst);
            for b in 0..n_blocks {
                assert_eq!(get(&runs, b), 1, "{n_blocks} blocks: block {b} ran once");
                if b % 2 == 1 {
                    assert!(get(&start, b) > get(&end, b - 1), "{n_blocks}: block {b}");
                    if b + 1 < n_blocks {
                        assert!(get(&start, b) > get(&end, b + 1), "{n_blocks}: block {b}");
                    }
                }
            }
        }
    }
}
