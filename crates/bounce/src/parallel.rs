//! Running work on one thread or many with the same result.
//!
//! Everything the step does in parallel is split into pieces whose boundaries depend on the
//! data only (grid blocks, fixed-size particle chunks), never on the thread count, and partial
//! results are combined in piece order. So a run on 8 threads is bit-identical to a run on 1.

use std::ops::Range;
use std::sync::Arc;

use rayon::prelude::*;

/// Particles per chunk for per-particle sweeps. Partial sums are taken per chunk and added in
/// chunk order, so floating-point sums do not depend on the thread count.
pub(crate) const CHUNK: usize = 4096;

/// Work below this size (about one unit per disc) runs on the calling thread by default:
/// waking the pool costs more than it saves. Results never depend on where work runs.
/// (A world this large runs its whole step on the pool, see `Installer`, so no hand-over
/// is paid per stage: from a few ten thousand discs on a second thread pays, near 10,000 it
/// breaks even or loses; BENCHMARKS.md has the gas at 10k and 100k.) See
/// [`crate::World::set_parallel_min_work`] for an example.
pub const DEFAULT_PARALLEL_MIN_WORK: usize = 8_192;

/// Where the step's work runs: the calling thread, or a rayon pool of a fixed size.
#[derive(Debug)]
pub(crate) struct Executor {
    pool: Option<Arc<rayon::ThreadPool>>,
    /// Work below this runs on the calling thread.
    pub(crate) min_work: usize,
}

impl Default for Executor {
    fn default() -> Self {
        Executor {
            pool: None,
            min_work: DEFAULT_PARALLEL_MIN_WORK,
        }
    }
}

/// The thread pool could not be created. See [`crate::World::set_threads`] for an example.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cannot start {threads} worker threads: {reason}")]
pub struct ThreadsError {
    /// The requested thread count.
    pub threads: usize,
    /// What the operating system said.
    pub reason: String,
}

impl Executor {
    /// An executor with `threads` workers; 0 or 1 runs everything on the calling thread.
    pub(crate) fn new(threads: usize) -> Result<Self, ThreadsError> {
        if threads <= 1 {
            return Ok(Executor::default());
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("bounce-{i}"))
            .build()
            .map_err(|e| ThreadsError {
                threads,
                reason: e.to_string(),
            })?;
        Ok(Executor {
            pool: Some(Arc::new(pool)),
            min_work: DEFAULT_PARALLEL_MIN_WORK,
        })
    }

    /// Number of threads the work runs on.
    pub(crate) fn threads(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    /// A handle to the pool for [`Installer::install`], when there is one and `work` is
    /// worth it (below that the work runs where it is called).
    pub(crate) fn installer(&self, work: usize) -> Installer {
        Installer(self.pool_for(work).and(self.pool.clone()))
    }

    /// Whether `work` runs on the pool (there is one and the work is worth it).
    pub(crate) fn is_parallel(&self, work: usize) -> bool {
        self.pool_for(work).is_some()
    }

    /// The pool, when there is one and `work` is worth it.
    fn pool_for(&self, work: usize) -> Option<&rayon::ThreadPool> {
        self.pool.as_deref().filter(|_| work >= self.min_work)
    }

    /// Calls `f(i, item)` for each item; in parallel when there is a pool and `work` (about
    /// one unit per disc) is large enough.
    pub(crate) fn for_each_mut<T: Send>(
        &self,
        work: usize,
        items: &mut [T],
        f: impl Fn(usize, &mut T) + Sync,
    ) {
        match self.pool_for(work) {
            None => items.iter_mut().enumerate().for_each(|(i, t)| f(i, t)),
            Some(pool) => {
                pool.install(|| items.par_iter_mut().enumerate().for_each(|(i, t)| f(i, t)))
            }
        }
    }

    /// Maps each item (with its index) to a value, in item order; in parallel when there is
    /// a pool.
    pub(crate) fn map_mut<T: Send, R: Send>(
        &self,
        work: usize,
        items: &mut [T],
        f: impl Fn(usize, &mut T) -> R + Sync,
    ) -> Vec<R> {
        match self.pool_for(work) {
            None => items.iter_mut().enumerate().map(|(i, t)| f(i, t)).collect(),
            Some(pool) => pool.install(|| {
                items
                    .par_iter_mut()
                    .enumerate()
                    .map(|(i, t)| f(i, t))
                    .collect()
            }),
        }
    }

    /// Sorts by a key; callers use keys that are unique, so the result is the same whichever
    /// sort runs.
    pub(crate) fn sort_unstable_by_key<T: Send, K: Ord>(
        &self,
        items: &mut [T],
        key: impl Fn(&T) -> K + Sync + Send,
    ) {
        match self.pool_for(items.len()) {
            Some(pool) => pool.install(|| items.par_sort_unstable_by_key(key)),
            _ => items.sort_unstable_by_key(key),
        }
    }

    /// Maps each index of `range` to a value, in index order.
    pub(crate) fn map_index<T: Send>(
        &self,
        work: usize,
        range: Range<usize>,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Vec<T> {
        match self.pool_for(work) {
            None => range.map(f).collect(),
            Some(pool) => pool.install(|| range.into_par_iter().map(f).collect()),
        }
    }
}

/// Where a step's body runs: see [`Installer::install`].
pub(crate) struct Installer(Option<Arc<rayon::ThreadPool>>);

impl Installer {
    /// Runs `f` on one of the pool's threads (on the calling thread without a pool), so the
    /// parallel parts inside it share their work with the other workers instead of handing
    /// it over: a hand-over from outside the pool wakes a worker and puts the caller to
    /// sleep until it is done, two wake-ups per parallel part.
    pub(crate) fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.0 {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }
}

/// A mutable slice shared between threads that promise to touch disjoint indices.
///
/// The collision solver needs this: a block's contacts write particles of the block and its
/// one-cell ring, which are not contiguous in memory. The block colouring in `contacts`
/// guarantees that pieces resolved at the same time touch disjoint particles.
pub(crate) struct SharedSlice<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: std::marker::PhantomData<&'a mut [T]>,
}

// SAFETY: access goes through the unsafe `get`/`set`, whose callers guarantee that no index is
// written by one thread while another reads or writes it.
unsafe impl<T: Send> Send for SharedSlice<'_, T> {}
// SAFETY: as for `Send`: shared references only reach the unsafe `get`/`set`.
unsafe impl<T: Send> Sync for SharedSlice<'_, T> {}

impl<'a, T: Copy> SharedSlice<'a, T> {
    pub(crate) fn new(slice: &'a mut [T]) -> Self {
        SharedSlice {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _borrow: std::marker::PhantomData,
        }
    }

    /// Reads index `i`.
    ///
    /// # Safety
    /// `i < len`, and no other thread writes index `i` at the same time.
    #[inline(always)]
    pub(crate) unsafe fn get(&self, i: usize) -> T {
        debug_assert!(i < self.len);
        // SAFETY: in bounds and not concurrently written, by the caller's promise.
        unsafe { *self.ptr.add(i) }
    }

    /// Where index `i` is, for [`prefetch`] (not dereferenced).
    #[inline(always)]
    pub(crate) fn address(&self, i: usize) -> *const T {
        self.ptr.wrapping_add(i)
    }

    /// Writes index `i`.
    ///
    /// # Safety
    /// `i < len`, and no other thread reads or writes index `i` at the same time.
    #[inline(always)]
    pub(crate) unsafe fn set(&self, i: usize, value: T) {
        debug_assert!(i < self.len);
        // SAFETY: in bounds and exclusively accessed, by the caller's promise.
        unsafe { *self.ptr.add(i) = value }
    }
}

/// Asks the CPU to start loading the cache line of `*ptr` (x86-64; a no-op elsewhere). Never
/// faults, whatever `ptr` is.
#[inline(always)]
pub(crate) fn prefetch<T>(ptr: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch is a hint; it does not access memory architecturally.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(ptr.cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = ptr;
}
