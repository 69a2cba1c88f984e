//! The pair-sweep driver: scheduling of the half sweep over cell-sorted blocks, batching,
//! neighbour-list filling; every `unsafe` line of the solver is here.

mod pairs;
pub(crate) use pairs::*;

use crate::neighbours::CellGrid;
use crate::sim::*;
use rayon::prelude::*;

/// The brand of one sweep: an invariant lifetime that no other sweep shares, so that a
/// [`Slot`] of one sweep cannot index the arrays of another (a generative lifetime, as in
/// Yanovski et al. 2021, *GhostCell*, ICFP).
type Brand<'id> = std::marker::PhantomData<fn(&'id ()) -> &'id ()>;

/// The slots `0..n_slots` of one pair sweep. Its arrays ([`Sweep::slots`]) are checked
/// against `n_slots` once, when they are borrowed, and its blocks hand out slots below
/// `n_slots` only, so a write needs no further check on the array's length.
#[derive(Clone, Copy)]
pub(crate) struct Sweep<'id> {
    n_slots: usize,
    _brand: Brand<'id>,
}

impl Sweep<'_> {
    /// Runs `f` with a sweep over `n_slots` slots, under a brand of its own.
    pub(crate) fn scope<R>(n_slots: usize, f: impl for<'id> FnOnce(Sweep<'id>) -> R) -> R {
        f(Sweep {
            n_slots,
            _brand: std::marker::PhantomData,
        })
    }
}

impl<'id> Sweep<'id> {
    /// The slots of `values`, borrowed for this sweep; panics if `values` is shorter than
    /// the sweep (a broken caller, checked once per array and sweep).
    pub(crate) fn slots<'a, T: Copy>(self, values: &'a mut [T]) -> SweepSlots<'a, 'id, T> {
        if values.len() < self.n_slots {
            slots_too_short(values.len(), self.n_slots);
        }
        SweepSlots {
            ptr: values.as_mut_ptr(),
            _borrow: std::marker::PhantomData,
            _brand: std::marker::PhantomData,
        }
    }

    /// The block of the one slot `i`, for a pass that writes each particle's slot alone;
    /// panics if `i` is not a slot of this sweep.
    pub(crate) fn single(self, i: usize) -> Block<'id> {
        if i >= self.n_slots {
            slot_outside_sweep(i, self.n_slots);
        }
        Block {
            index: 0,
            begin: i,
            end: i + 1,
            writable: 1,
            _brand: std::marker::PhantomData,
        }
    }
}

/// A block of a [`colour_sweep`] while it runs: its slots `begin..end`, and the end of the
/// slots it may write (its own and the next block's).
pub(crate) struct Block<'id> {
    /// Block number (0-based, in slot order).
    pub(crate) index: usize,
    /// First slot of the block.
    pub(crate) begin: usize,
    /// One past the last slot of the block.
    pub(crate) end: usize,
    /// Number of slots from `begin` the block may write: up to the end of the next block,
    /// at most to the number of slots of its sweep.
    writable: usize,
    _brand: Brand<'id>,
}

/// A slot the running [`Block`] may write, checked once ([`Block::slot`]) for every array
/// of the sweep it is used with.
pub(crate) struct Slot<'b, 'id> {
    index: usize,
    _block: std::marker::PhantomData<&'b Block<'id>>,
}

impl<'id> Block<'id> {
    /// Slot `i` of this block or the next; panics for any other.
    #[inline(always)]
    pub(crate) fn slot(&self, i: usize) -> Slot<'_, 'id> {
        // One unsigned comparison for begin ≤ i < begin + writable.
        if i.wrapping_sub(self.begin) >= self.writable {
            slot_outside_block(i, self);
        }
        Slot {
            index: i,
            _block: std::marker::PhantomData,
        }
    }
}

/// Indices of fluid particles paired with a running [`Block`]'s particle, all checked at once
/// to be slots the block may write ([`Block::check_list`]): each gives its slot without a
/// check of its own.
#[derive(Clone, Copy)]
pub(crate) struct CheckedList<'b, 'id> {
    indices: &'b [u32],
    _block: std::marker::PhantomData<&'b Block<'id>>,
}

impl<'id> Block<'id> {
    /// `indices` as slots of this block or the next: one pass of unsigned maxima over the
    /// list (vectorised) and one branch, where [`Self::slot`] takes a branch per index;
    /// panics if any index lies elsewhere.
    #[inline(always)]
    pub(crate) fn check_list<'b>(&'b self, indices: &'b [u32]) -> CheckedList<'b, 'id> {
        // j − begin (mod 2³²) is below `writable` exactly for begin ≤ j < begin + writable
        // when begin + writable ≤ 2³² (an index below begin wraps to ≥ 2³² − begin).
        let begin = self.begin as u32;
        let farthest = indices
            .iter()
            .fold(0u32, |far, &j| far.max(j.wrapping_sub(begin)));
        let fits_u32 = (self.begin + self.writable) as u64 <= 1 << 32;
        if !fits_u32 || (!indices.is_empty() && farthest as usize >= self.writable) {
            let j = indices
                .iter()
                .find(|&&j| (j as usize).wrapping_sub(self.begin) >= self.writable)
                .map_or(self.begin + self.writable, |&j| j as usize);
            slot_outside_block(j, self);
        }
        CheckedList {
            indices,
            _block: std::marker::PhantomData,
        }
    }
}

impl<'b, 'id> CheckedList<'b, 'id> {
    /// The indices.
    #[inline(always)]
    pub(crate) fn indices(&self) -> &'b [u32] {
        self.indices
    }

    /// Each index with its slot.
    #[inline(always)]
    pub(crate) fn iter(&self) -> impl Iterator<Item = (usize, Slot<'b, 'id>)> + 'b {
        self.indices.iter().map(|&j| {
            (
                j as usize,
                Slot {
                    index: j as usize,
                    _block: std::marker::PhantomData,
                },
            )
        })
    }

    /// The list in runs of at most `n` indices, each still checked.
    #[inline(always)]
    pub(crate) fn chunks(&self, n: usize) -> impl Iterator<Item = CheckedList<'b, 'id>> + 'b {
        self.indices.chunks(n).map(|indices| CheckedList {
            indices,
            _block: std::marker::PhantomData,
        })
    }
}

/// An array that the running blocks of a [`colour_sweep`] add to, each at the slots of its
/// [`Block`] and the next block, which no other running block touches. Made by
/// [`Sweep::slots`], it takes the slots of its own sweep only (the brand `'id`), which lie
/// within it, so the sweeps that use it hold no `unsafe` code.
pub(crate) struct SweepSlots<'a, 'id, T> {
    ptr: *mut T,
    _borrow: std::marker::PhantomData<&'a mut [T]>,
    _brand: Brand<'id>,
}

// SAFETY: a SweepSlots is only accessed at slots of the running block or the next one
// (checked in `slot`), which no other thread touches while the block runs (`colour_sweep`);
// the element type itself moves between threads.
unsafe impl<T: Send> Send for SweepSlots<'_, '_, T> {}
unsafe impl<T: Send> Sync for SweepSlots<'_, '_, T> {}

/// The panic of a write outside the running block (a broken sweep schedule): out of the hot
/// path, so that the check costs one predictable branch.
#[cold]
#[inline(never)]
fn slot_outside_block(i: usize, block: &Block) -> ! {
    panic!(
        "pair sweep: slot {i} outside block {} ({}..{})",
        block.index,
        block.begin,
        block.begin + block.writable
    )
}

/// The panic of a slot beyond the sweep.
#[cold]
#[inline(never)]
fn slot_outside_sweep(i: usize, n_slots: usize) -> ! {
    panic!("pair sweep: slot {i} outside a sweep over {n_slots}")
}

/// The panic of an array shorter than the sweep it is written by.
#[cold]
#[inline(never)]
fn slots_too_short(len: usize, n_slots: usize) -> ! {
    panic!("pair sweep: an array of {len} slots written by a sweep over {n_slots}")
}

impl<'id, T: Copy> SweepSlots<'_, 'id, T> {
    /// The element of `slot`: within this array, since the slot is below the number of
    /// slots of the sweep (`Block::slot`, `Sweep::single`) and the array no shorter
    /// (`Sweep::slots`), both of the sweep this array's brand names.
    #[inline(always)]
    fn at(&self, slot: &Slot<'_, 'id>) -> *mut T {
        self.ptr.wrapping_add(slot.index)
    }
    /// Sets `slot` to `value`.
    #[inline(always)]
    pub(crate) fn set(&self, slot: &Slot<'_, 'id>, value: T) {
        let p = self.at(slot);
        // SAFETY: the slot belongs to the running block or the next, which no other thread
        // accesses while this block runs (`Block::slot`), and lies within this array (`at`).
        unsafe { *p = value }
    }

    /// Adds `value` to `slot`.
    #[inline(always)]
    pub(crate) fn add(&self, slot: &Slot<'_, 'id>, value: T)
    where
        T: std::ops::AddAssign,
    {
        let p = self.at(slot);
        // SAFETY: as in `set`.
        unsafe { *p += value }
    }

    /// Subtracts `value` from `slot`.
    #[inline(always)]
    pub(crate) fn sub(&self, slot: &Slot<'_, 'id>, value: T)
    where
        T: std::ops::SubAssign,
    {
        let p = self.at(slot);
        // SAFETY: as in `set`.
        unsafe { *p -= value }
    }
}

/// Runs `block` for every block of slots given by `bounds` (see
/// [`CellGrid::colour_blocks`]). A block may write its own slots and those of the next block,
/// so two neighbouring blocks never run at the same time, and each slot receives its shares
/// in one fixed order: the even blocks come first (each may run at any time), and an odd
/// block runs once both its even neighbours are done. The result is therefore that of a
/// sweep over all even blocks followed by one over all odd blocks, whatever the number of
/// threads, but without a barrier between the two colours: a thread that finds no block
/// ready waits only for the neighbours of the next one (with two threads on 32 blocks, the
/// barrier between colours left each thread idle ≈ 10 % of a sweep).
pub(crate) fn colour_sweep<'id, F: Fn(&Block<'id>) + Sync>(
    sweep: Sweep<'id>,
    bounds: &[u32],
    block: F,
) {
    colour_sweep_listing(sweep, bounds, &mut [], 0, |b, _| block(b));
}

/// The neighbour-list entries of a [`colour_sweep_listing`], shared by its running blocks,
/// each of which takes its own share (see there).
struct SharedEntries(*mut u32);

// SAFETY: the blocks take disjoint shares of the entries (see `colour_sweep_listing`).
unsafe impl Sync for SharedEntries {}

impl SharedEntries {
    /// The first entry (the closures of a sweep capture the whole `SharedEntries` through
    /// this call, and with it its `Sync`).
    #[inline(always)]
    fn base(&self) -> *mut u32 {
        self.0
    }
}

/// [`colour_sweep`] for a sweep that fills neighbour lists: each block also gets its share
/// of `entries`, the `capacity` entries of each of its particles
/// (`entries[begin·capacity..end·capacity]`), to pack its lists into.
pub(crate) fn colour_sweep_listing<'id, F: Fn(&Block<'id>, &mut [u32]) + Sync>(
    sweep: Sweep<'id>,
    bounds: &[u32],
    entries: &mut [u32],
    capacity: usize,
    block: F,
) {
    let n_blocks = bounds.len().saturating_sub(1);
    let n_slots = sweep.n_slots;
    // Checked once per sweep (at most a few hundred bounds): ascending bounds make the
    // blocks' slots and shares of the entries disjoint, and the last bound keeps every slot
    // a block hands out within the sweep.
    assert!(
        bounds.windows(2).all(|w| w[0] <= w[1])
            && bounds.last().is_none_or(|&b| b as usize <= n_slots),
        "pair sweep: block bounds not ascending within the sweep's {n_slots} slots"
    );
    assert!(
        entries.len() >= n_slots * capacity,
        "neighbour lists too short for the sweep"
    );
    let lists = SharedEntries(entries.as_mut_ptr());
    let run = |b: usize| {
        let (begin, end) = (bounds[b] as usize, bounds[b + 1] as usize);
        let this = Block {
            index: b,
            begin,
            end,
            writable: bounds.get(b + 2).map_or(end, |&e| e as usize) - begin,
            _brand: std::marker::PhantomData,
        };
        let region: &mut [u32] = if capacity == 0 {
            &mut []
        } else {
            // SAFETY: blocks cover disjoint slot ranges, so their shares of the entries
            // (begin·capacity..end·capacity, within `entries` by the assertion above) are
            // disjoint, and each block takes its share once.
            unsafe {
                std::slice::from_raw_parts_mut(
                    lists.base().add(begin * capacity),
                    (end - begin) * capacity,
                )
            }
        };
        block(&this, region)
    };
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
    rho: Vec<f64>,
    /// Σ (m/ρ_j) W per set and wall particle.
    kernel_sum: Vec<f64>,
    /// Squared distance of the nearest fluid particle per set and wall particle.
    nearest_r2: Vec<f64>,
    /// That fluid particle (u32::MAX: none).
    nearest: Vec<u32>,
    /// The sets added up per wall particle by [`Self::drain`]: Σ m W, Σ (m/ρ_j) W and the
    /// nearest fluid particle (squared distance, index).
    totals: Vec<(f64, f64, (f64, u32))>,
}

impl WallScatter {
    /// Sets: blocks b and b + 4 of one colour are ≥ 3 stencil reaches apart, while two fluid
    /// neighbours of one wall particle are at most 2 apart.
    const SETS: usize = 4;

    /// Empty sums for `n_wall` wall particles.
    pub(crate) fn new(n_wall: usize) -> Self {
        let len = Self::SETS * n_wall;
        WallScatter {
            rho: vec![0.0; len],
            kernel_sum: vec![0.0; len],
            nearest_r2: vec![f64::INFINITY; len],
            nearest: vec![u32::MAX; len],
            totals: vec![(0.0, 0.0, (f64::INFINITY, u32::MAX)); n_wall],
        }
    }

    /// Bytes held.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.rho.len() * 28 + self.totals.len() * std::mem::size_of::<(f64, f64, (f64, u32))>()
    }

    /// The sums, for the running blocks of a density sweep to add to.
    pub(crate) fn slots(&mut self) -> WallScatterSlots<'_> {
        WallScatterSlots {
            n_wall: self.totals.len(),
            rho: self.rho.as_mut_ptr(),
            kernel_sum: self.kernel_sum.as_mut_ptr(),
            nearest_r2: self.nearest_r2.as_mut_ptr(),
            nearest: self.nearest.as_mut_ptr(),
            _borrow: std::marker::PhantomData,
        }
    }

    /// Adds up the sets of each wall particle, in a fixed order, into [`Self::totals`] and
    /// empties the sets for the next sweep.
    pub(crate) fn drain(&mut self) {
        let n_wall = self.totals.len();
        let (rho, ksum, near_r2, near) =
            (&self.rho, &self.kernel_sum, &self.nearest_r2, &self.nearest);
        self.totals
            .par_iter_mut()
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(|(w, total)| {
                let (mut rho_sum, mut kernel_sum) = (0.0, 0.0);
                let mut nearest = (f64::INFINITY, u32::MAX);
                for s in 0..Self::SETS {
                    let k = s * n_wall + w;
                    rho_sum += rho[k];
                    kernel_sum += ksum[k];
                    let candidate = (near_r2[k], near[k]);
                    if candidate.0 < nearest.0
                        || (candidate.0 == nearest.0 && candidate.1 < nearest.1)
                    {
                        nearest = candidate;
                    }
                }
                *total = (rho_sum, kernel_sum, nearest);
            });
        self.rho
            .par_iter_mut()
            .zip(self.kernel_sum.par_iter_mut())
            .zip(self.nearest_r2.par_iter_mut())
            .zip(self.nearest.par_iter_mut())
            .with_min_len(4 * PAR_CHUNK)
            .for_each(|(((r, k), d), j)| {
                (*r, *k, *d, *j) = (0.0, 0.0, f64::INFINITY, u32::MAX);
            });
    }

    /// Wall particle `w`'s sums over the fluid after [`Self::drain`]: Σ m W, Σ (m/ρ_j) W and
    /// the nearest fluid particle (squared distance, index; u32::MAX when none).
    #[inline(always)]
    pub(crate) fn total(&self, w: usize) -> (f64, f64, (f64, u32)) {
        self.totals[w]
    }
}

/// The sums of a [`WallScatter`] while a density sweep adds to them.
pub(crate) struct WallScatterSlots<'a> {
    n_wall: usize,
    rho: *mut f64,
    kernel_sum: *mut f64,
    nearest_r2: *mut f64,
    nearest: *mut u32,
    _borrow: std::marker::PhantomData<&'a mut WallScatter>,
}

// SAFETY: the running blocks of a colour sweep write the set of their block number modulo
// `WallScatter::SETS` (see `add`); blocks using one set are ≥ 3 stencil reaches apart while
// two fluid neighbours of one wall particle are at most 2 apart, so no entry is written by
// two threads at once.
unsafe impl Send for WallScatterSlots<'_> {}
unsafe impl Sync for WallScatterSlots<'_> {}

impl WallScatterSlots<'_> {
    /// Adds the pair of fluid particle `i` and wall particle `w` at squared distance `r2`
    /// (m²) to the wall particle's sums: m W (`rho`), (m/ρ_i) W (`kernel_sum`), and i as
    /// its nearest fluid particle if it is nearer than those seen.
    #[inline(always)]
    pub(crate) fn add(
        &self,
        block: &Block<'_>,
        w: usize,
        rho: f64,
        kernel_sum: f64,
        r2: f64,
        i: u32,
    ) {
        assert!(w < self.n_wall, "wall particle {w} out of range");
        let k = (block.index % WallScatter::SETS) * self.n_wall + w;
        // SAFETY: k < SETS · n_wall, the length of each array; no other running block
        // writes entry k (see the Sync impl).
        unsafe {
            *self.rho.add(k) += rho;
            *self.kernel_sum.add(k) += kernel_sum;
            let near = self.nearest_r2.add(k);
            if r2 < *near {
                *near = r2;
                *self.nearest.add(k) = i;
            }
        }
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
    use super::{colour_sweep, Sweep};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// An array shorter than its sweep is refused when it is borrowed, before any write.
    #[test]
    #[should_panic(expected = "an array of 3 slots written by a sweep over 4")]
    fn an_array_shorter_than_its_sweep_is_refused() {
        let mut short = [0.0f64; 3];
        Sweep::scope(4, |sweep| {
            let _ = sweep.slots(&mut short);
        });
    }

    /// One thread, so that a block's panic reaches the test instead of leaving the other
    /// threads waiting for the block.
    fn one_thread(f: impl FnOnce() + Send) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(f);
    }

    /// A list of indices within a block and the next is taken as it is, each index with its
    /// own slot.
    #[test]
    fn a_list_within_the_block_and_the_next_gives_its_slots() {
        let mut hits = [0u32; 30];
        one_thread(|| {
            Sweep::scope(30, |sweep| {
                let slots = sweep.slots(&mut hits);
                colour_sweep(sweep, &[0, 10, 20, 30], |blk| {
                    if blk.index == 1 {
                        for (j, slot) in blk.check_list(&[10, 29, 15, 15]).iter() {
                            assert_eq!(slot.index, j);
                            slots.add(&slot, 1);
                        }
                    }
                });
            })
        });
        assert_eq!(
            (hits[10], hits[15], hits[29], hits.iter().sum::<u32>()),
            (1, 2, 1, 4)
        );
    }

    /// An index before the block (it would wrap below zero) or past the next block is
    /// refused, and named.
    #[test]
    #[should_panic(expected = "slot 9 outside block 1 (10..30)")]
    fn a_list_reaching_before_the_block_is_refused() {
        one_thread(|| {
            Sweep::scope(30, |sweep| {
                colour_sweep(sweep, &[0, 10, 20, 30], |blk| {
                    if blk.index == 1 {
                        let _ = blk.check_list(&[12, 9, 30]);
                    }
                });
            })
        });
    }

    #[test]
    #[should_panic(expected = "slot 30 outside block 0 (0..20)")]
    fn a_list_reaching_past_the_next_block_is_refused() {
        one_thread(|| {
            Sweep::scope(40, |sweep| {
                colour_sweep(sweep, &[0, 10, 20, 30, 40], |blk| {
                    if blk.index == 0 {
                        let _ = blk.check_list(&[0, 19, 30]);
                    }
                });
            })
        });
    }

    /// Block bounds beyond the sweep's slots are refused before any block runs.
    #[test]
    #[should_panic(expected = "block bounds not ascending within the sweep's 10 slots")]
    fn blocks_beyond_the_sweep_are_refused() {
        Sweep::scope(10, |sweep| colour_sweep(sweep, &[0, 5, 12], |_| {}));
    }

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
                Sweep::scope(10 * n_blocks, |sweep| {
                    colour_sweep(sweep, &bounds, |blk| {
                        let (b, begin, stop) = (blk.index, blk.begin, blk.end);
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
