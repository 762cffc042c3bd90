//! The compliance back(forward(τ)) of the fast form on two threads: the calling thread
//! applies both transforms to the first half of the rows, a helper thread to the second
//! ([`super::hodlr::Half`]), and the halves exchange only the root's r coefficients per
//! transform. Same bits as the one-thread apply: every output element is summed by the same
//! panels in the same order.
//!
//! Why: at N = 2000 the two transforms' factors (about 2.4 MB) exceed one core's L2
//! (2 MB on this project's reference machine), so one thread streams them from L3 at every
//! apply, and the coupling solve applies the compliance once or more per step. Split,
//! each core keeps its half of both in L2.
//!
//! The helper waits for work spinning (a step's other work takes tens of µs, and a sleeping
//! thread takes about as long to wake), and parks after [`IDLE_SPIN`] without any. It is
//! used only where it has a core to itself: not from a rayon worker (a sweep's or a fit's
//! runs fill the pool already), not with a budget of one thread (`RAYON_NUM_THREADS=1`, or
//! one CPU), and not below [`PAIR_MIN_NODES`].

use super::hodlr::{Half, HodlrOperator, HodlrScratch};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Below this many nodes the two transforms fit one core's cache and the hand-offs
/// (a few 100 ns each) would cost more than they save.
pub const PAIR_MIN_NODES: usize = 1000;

/// How long the idle helper spins for the next apply before it parks.
pub const IDLE_SPIN: Duration = Duration::from_micros(300);

/// What the helper reads and writes: the input's, q's and the output's second halves
/// (full-length vectors, only [mid, N) used), and its own scratch.
struct HelperIo {
    x: Vec<f64>,
    q: Vec<f64>,
    out: Vec<f64>,
    forward: HodlrScratch,
    back: HodlrScratch,
}

/// The root coefficients one half hands the other, per transform, with the job's number
/// once they are in.
struct Mailbox {
    coeffs: Mutex<Vec<f64>>,
    ready: AtomicU64,
}

struct Shared {
    forward: Arc<HodlrOperator>,
    back: Arc<HodlrOperator>,
    /// The number of the last job posted (the caller) and finished (the helper).
    posted: AtomicU64,
    finished: AtomicU64,
    exit: AtomicBool,
    io: Mutex<HelperIo>,
    /// Forward's and back's exchanged coefficients.
    mail: [Mailbox; 2],
}

/// The two-thread compliance (see the module docs).
pub(super) struct PairedCompliance {
    shared: Arc<Shared>,
    helper: Option<JoinHandle<()>>,
    mid: usize,
    jobs: u64,
    /// The process that started the helper: a child forked after it (Python's
    /// multiprocessing) inherits the pair but not the thread, and must not post to it.
    pid: u32,
}

impl std::fmt::Debug for PairedCompliance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PairedCompliance")
            .field("mid", &self.mid)
            .finish_non_exhaustive()
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Spins until `flag` reaches `seq`, yielding the core after a while (a helper descheduled
/// on a busy host); panics if the helper has died, and gives up once `exit` is set (the
/// caller went away mid-job: what the helper computes then is never read).
fn wait_for(flag: &AtomicU64, seq: u64, helper: Option<&JoinHandle<()>>, exit: &AtomicBool) {
    let mut spins = 0u32;
    while flag.load(Ordering::Acquire) < seq && !exit.load(Ordering::Relaxed) {
        std::hint::spin_loop();
        spins = spins.wrapping_add(1);
        if spins.is_multiple_of(1 << 12) {
            if helper.is_some_and(JoinHandle::is_finished) {
                panic!("the compliance's helper thread has ended");
            }
            if spins >= 1 << 16 {
                std::thread::yield_now();
            }
        }
    }
}

impl PairedCompliance {
    /// The pair for these operators when it pays here (see the module docs), else `None`.
    pub fn new_if_useful(forward: &Arc<HodlrOperator>, back: &Arc<HodlrOperator>) -> Option<Self> {
        // The global pool's size is the run's thread budget (RAYON_NUM_THREADS, else the
        // CPUs): one thread means one.
        if rayon::current_num_threads() < 2 || rayon::current_thread_index().is_some() {
            return None;
        }
        Self::new(forward, back, PAIR_MIN_NODES)
    }

    /// The pair, if both operators split at the same row and have at least `min_nodes`.
    pub fn new(
        forward: &Arc<HodlrOperator>,
        back: &Arc<HodlrOperator>,
        min_nodes: usize,
    ) -> Option<Self> {
        let n = forward.size();
        let mid = forward.split_row()?;
        if n < min_nodes || back.size() != n || back.split_row() != Some(mid) {
            return None;
        }
        let mailbox = |op: &HodlrOperator| Mailbox {
            coeffs: Mutex::new(vec![0.0; op.scratch().coefficient_len()]),
            ready: AtomicU64::new(0),
        };
        let shared = Arc::new(Shared {
            forward: Arc::clone(forward),
            back: Arc::clone(back),
            posted: AtomicU64::new(0),
            finished: AtomicU64::new(0),
            exit: AtomicBool::new(false),
            io: Mutex::new(HelperIo {
                x: vec![0.0; n],
                q: vec![0.0; n],
                out: vec![0.0; n],
                forward: forward.scratch(),
                back: back.scratch(),
            }),
            mail: [mailbox(forward), mailbox(back)],
        });
        let for_helper = Arc::clone(&shared);
        let helper = std::thread::Builder::new()
            .name("stickslip-compliance".into())
            .spawn(move || helper_loop(&for_helper))
            .ok()?;
        Some(Self {
            shared,
            helper: Some(helper),
            mid,
            jobs: 0,
            pid: std::process::id(),
        })
    }

    /// Whether this process has the helper (not a child forked after it started).
    pub fn usable(&self) -> bool {
        self.pid == std::process::id()
    }

    /// out = back(forward(τ)), q = forward(τ), with the caller's scratch for its half.
    pub fn compliance(
        &mut self,
        (tau, q, out): (&[f64], &mut [f64], &mut [f64]),
        (forward_scratch, back_scratch): (&mut HodlrScratch, &mut HodlrScratch),
    ) {
        let (mid, s) = (self.mid, &*self.shared);
        self.jobs += 1;
        let seq = self.jobs;
        lock(&s.io).x[mid..].copy_from_slice(&tau[mid..]);
        s.posted.store(seq, Ordering::Release);
        let helper = self.helper.as_ref();
        if let Some(h) = helper {
            h.thread().unpark();
        }
        let half = Half::First;
        s.forward.apply_up(half, tau, forward_scratch);
        exchange(s, 0, half, forward_scratch, (seq, helper));
        s.forward.apply_down(half, tau, q, forward_scratch);
        s.back.apply_up(half, q, back_scratch);
        exchange(s, 1, half, back_scratch, (seq, helper));
        s.back.apply_down(half, q, out, back_scratch);
        wait_for(&s.finished, seq, helper, &s.exit);
        let io = lock(&s.io);
        q[mid..].copy_from_slice(&io.q[mid..]);
        out[mid..].copy_from_slice(&io.out[mid..]);
    }
}

/// Between one transform's two parts: the target half waits for the source half's root
/// coefficients; the source half posts them.
fn exchange(
    s: &Shared,
    transform: usize,
    half: Half,
    scratch: &mut HodlrScratch,
    (seq, helper): (u64, Option<&JoinHandle<()>>),
) {
    let (op, mail) = match transform {
        0 => (&*s.forward, &s.mail[0]),
        _ => (&*s.back, &s.mail[1]),
    };
    if op.split_target() == half {
        let source = match half {
            Half::First => Half::Second,
            Half::Second => Half::First,
        };
        wait_for(&mail.ready, seq, helper, &s.exit);
        let coeffs = lock(&mail.coeffs);
        let dst = op.child_coefficients_mut(source, scratch);
        dst.copy_from_slice(&coeffs[..dst.len()]);
    } else {
        let src = op.child_coefficients(half, scratch);
        lock(&mail.coeffs)[..src.len()].copy_from_slice(src);
        mail.ready.store(seq, Ordering::Release);
    }
}

/// The helper: the second half of every posted job, until told to exit.
fn helper_loop(s: &Shared) {
    let mut done = 0u64;
    loop {
        let idle_since = Instant::now();
        let mut spins = 0u32;
        let seq = loop {
            if s.exit.load(Ordering::Acquire) {
                return;
            }
            let posted = s.posted.load(Ordering::Acquire);
            if posted > done {
                break posted;
            }
            spins = spins.wrapping_add(1);
            if spins.is_multiple_of(64) && idle_since.elapsed() > IDLE_SPIN {
                // Parked until the next post's unpark (or a timeout, for safety).
                std::thread::park_timeout(Duration::from_millis(50));
            } else {
                std::hint::spin_loop();
            }
        };
        let mut guard = lock(&s.io);
        let io = &mut *guard;
        let half = Half::Second;
        s.forward.apply_up(half, &io.x, &mut io.forward);
        exchange(s, 0, half, &mut io.forward, (seq, None));
        s.forward
            .apply_down(half, &io.x, &mut io.q, &mut io.forward);
        s.back.apply_up(half, &io.q, &mut io.back);
        exchange(s, 1, half, &mut io.back, (seq, None));
        s.back.apply_down(half, &io.q, &mut io.out, &mut io.back);
        drop(guard);
        done = seq;
        s.finished.store(seq, Ordering::Release);
    }
}

impl Drop for PairedCompliance {
    fn drop(&mut self) {
        if !self.usable() {
            // A forked child: no helper to stop or join.
            return;
        }
        self.shared.exit.store(true, Ordering::Release);
        if let Some(h) = self.helper.take() {
            h.thread().unpark();
            // A helper that panicked has nothing more to say here.
            let _ = h.join();
        }
    }
}
