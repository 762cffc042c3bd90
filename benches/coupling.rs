//! Criterion bench: the elastic coupling solve of the accurate scheme, per N (issue 14).
//!
//! The coupling (I + K)·u3D = K·u0, K = κ·C·diag(φ²) (see `stickslip_core::sim::coupling`),
//! has **no preconditioner**: BiCGSTAB runs with the identity. Its acceleration is the first
//! guess instead. Each step the simulation extrapolates u3D quadratically from the last three
//! steps, and `CouplingSolver::solve` first checks that guess with one application of K: when
//! its residual already meets the tolerance the guess is kept (with a relaxed correction) and
//! no BiCGSTAB iteration runs; otherwise BiCGSTAB solves for the correction. So where issue 14
//! asks for "with and without the preconditioner", this bench compares guesses.
//!
//! Two groups, for N = 125 … 8000 (`BenchmarkId` parameter and element throughput = N):
//!
//! - `coupling_step/{elastic,rigid}/N`: one fixed time step of fig2 (accurate scheme, Δt =
//!   1e-8 s) with the elastic substrate and with `contact.substrate=rigid`, which solves no
//!   coupling at all. elastic − rigid is the coupling's cost per step: the extrapolation, the
//!   check of the guess and whatever BiCGSTAB iterations the step needs. Before timing, the mean
//!   BiCGSTAB iterations per step of the timed window, and the share of its steps whose guess
//!   was accepted without any, are printed.
//! - `coupling_solve/{cold,warm,extrapolated}/N`: `CouplingSolver::solve` alone on the system
//!   of one real stick-phase step (φ, u0 of step n + 1 of a warmed fig2 run), from three
//!   guesses: `cold` = zero (pure BiCGSTAB, what the first step does), `warm` = the solution of
//!   step n (a warm start without extrapolation), `extrapolated` = the quadratic extrapolation
//!   of steps n − 2, n − 1, n (what the simulation does). Tolerance as in the run:
//!   `numerics.coupling_tol` = 1e-10 and ρ = the lagged-sweep contraction at t = 0. Before
//!   timing, each guess's iterations, final residual and distance to the run's own solution of
//!   that step are printed. Each timed solve starts from a fresh copy of its guess (an O(N)
//!   copy, negligible beside one application of K).
//!
//! The state is fig2's first stick phase (first onset ≈ 0.6 ms), reached cheaply: fixed steps of
//! 1e-7 s to t = 0.3 ms, then 200 steps of 1e-8 s so that the last three solutions (the
//! extrapolation's history) and φ's lag behind its slaved equilibrium belong to the benched Δt.
//! The run library's driver steps it (`Driver::set_fixed_dt` switches from the warm-up step to
//! the benched one; `Driver::rewind` puts the warmed state back every 1000 steps, 10 µs of
//! simulated time, untimed): otherwise the fast small-N benches would step
//! through milliseconds of simulated time, slips included, and time a different mix of steps
//! per N and per substrate.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::time::{Duration, Instant};
use stickslip_benches::{Setting, scene};
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, Quadrature};
use stickslip_core::sim::SimState;
use stickslip_core::sim::coupling::{CouplingReport, CouplingSolver, CouplingTolerance};
use stickslip_run::driver::{Control, Driver, DriverState, Limit, NullSink};
use stickslip_run::keys::words::{Stepping, Substrate};
use stickslip_run::keys::{contact, output, time};

/// Node counts benched.
const SIZES: [usize; 7] = [125, 250, 500, 1000, 2000, 4000, 8000];

/// The benched time step, s (fig2's).
const DT_S: f64 = 1e-8;

/// Warm-up: fixed steps of this length, s …
const WARM_DT_S: f64 = 1e-7;

/// … up to this time, s (inside the first stick phase) …
const WARM_T_S: f64 = 3e-4;

/// … then this many steps of `DT_S`.
const SETTLE_STEPS: u64 = 200;

/// Steps timed from the warmed state before it is restored.
const WINDOW_STEPS: u64 = 1000;

/// A fig2 simulation warmed into its first stick phase, and that state.
struct Warmed {
    driver: Driver,
    start: SimState,
    start_driver: DriverState,
    /// Steps taken since `start`.
    taken: u64,
    /// The lagged-sweep contraction at t = 0 (the run's spectral bound of K).
    rho0: f64,
}

impl Warmed {
    /// fig2 with `contact.nodes = n` and `extra` overrides, warmed (see the module doc).
    fn new(n: usize, extra: &[Setting]) -> Self {
        let mut sets = vec![
            contact::NODES.set(n as i64),
            time::DT.set(1e-7),
            time::END.set(1.0),
            time::STEPPING.set(Stepping::Fixed),
            output::SERIES_INTERVAL.set(1.0),
            output::PROFILE_TIMES.set(vec![1.0]),
        ];
        sets.extend_from_slice(extra);
        let scene = scene("fig2", &sets);
        assert_eq!(scene.config.time.dt_s, WARM_DT_S);
        let mut driver = Driver::start(&scene, &mut NullSink).expect("valid scene");
        // The run's bound of K's spectrum (φ at t = 0), as the simulation stores it.
        let rho0 = driver.preflight().lagged_sweep_contraction;
        advance(&mut driver, Limit::Time(WARM_T_S));
        driver.set_fixed_dt(DT_S);
        advance(&mut driver, Limit::Steps(SETTLE_STEPS));
        assert!(
            driver.simulation().events().is_empty(),
            "the warm-up reached a slip"
        );
        let snapshot = driver.snapshot();
        let (start, start_driver) = (snapshot.sim.clone(), snapshot.driver.clone());
        Self {
            driver,
            start,
            start_driver,
            taken: 0,
            rho0,
        }
    }

    fn restore(&mut self) {
        self.driver
            .rewind(self.start.clone(), self.start_driver.clone())
            .expect("the state of this simulation");
        self.taken = 0;
    }

    /// Steps through the window once (untimed) and restores: mean BiCGSTAB iterations per step
    /// and the fraction of steps that needed none (the guess accepted).
    fn window_iterations(&mut self) -> (f64, f64) {
        self.restore();
        let mut accepted = 0u64;
        for _ in 0..WINDOW_STEPS {
            let before = self
                .driver
                .simulation()
                .state()
                .counters
                .coupling_iterations;
            advance(&mut self.driver, Limit::Steps(1));
            if self
                .driver
                .simulation()
                .state()
                .counters
                .coupling_iterations
                == before
            {
                accepted += 1;
            }
        }
        let sim = self.driver.simulation();
        assert!(sim.events().is_empty(), "the window reached a slip");
        let iterations =
            sim.state().counters.coupling_iterations - self.start.counters.coupling_iterations;
        self.restore();
        let per_step = |k: u64| k as f64 / WINDOW_STEPS as f64;
        (per_step(iterations), per_step(accepted))
    }

    /// Time of `iters` steps of `DT_S`, restoring the warmed state (untimed) every window.
    fn time_steps(&mut self, iters: u64) -> Duration {
        let mut total = Duration::ZERO;
        let mut left = iters;
        while left > 0 {
            if self.taken == WINDOW_STEPS {
                self.restore();
            }
            let k = left.min(WINDOW_STEPS - self.taken);
            let t0 = Instant::now();
            advance(&mut self.driver, Limit::Steps(k));
            total += t0.elapsed();
            self.taken += k;
            left -= k;
        }
        total
    }
}

/// Advances the driver to `limit`; the stick phase has no stop before it.
fn advance(driver: &mut Driver, limit: Limit) {
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), limit)
        .expect("no I/O");
    assert!(stop.is_none(), "the run stopped: {stop:?}");
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("coupling_step");
    for n in SIZES {
        group.throughput(Throughput::Elements(n as u64));
        for (name, extra) in [
            ("elastic", vec![]),
            ("rigid", vec![contact::SUBSTRATE.set(Substrate::Rigid)]),
        ] {
            let mut warmed = Warmed::new(n, &extra);
            // Also checks that the window stays in the stick phase.
            let (iterations, accepted) = warmed.window_iterations();
            if extra.is_empty() {
                eprintln!(
                    "coupling_step/{name}/{n}: {iterations:.3} BiCGSTAB iterations per step, \
                     guess accepted without any at {:.1} % of the steps (over the \
                     {WINDOW_STEPS} timed steps from t = {:.4e} s)",
                    100.0 * accepted,
                    warmed.start.physical.drive.t_s,
                );
            }
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter_custom(|iters| warmed.time_steps(iters));
            });
        }
    }
    group.finish();
}

/// The coupling system of one stick-phase step and three first guesses for it.
struct SolveProblem {
    ops: MdrOperators,
    phi_sq: Vec<f64>,
    u0: Vec<f64>,
    kappa: f64,
    tolerance: CouplingTolerance,
    /// (name, guess) for cold, warm and extrapolated.
    guesses: [(&'static str, Vec<f64>); 3],
    /// The run's own u3D after the step, and its BiCGSTAB iterations there.
    reference: Vec<f64>,
    run_iterations: u64,
}

impl SolveProblem {
    /// Step n = the warmed state of fig2 with `n` nodes; the system is that of step n + 1.
    fn new(n: usize) -> Self {
        let mut warmed = Warmed::new(n, &[]);
        let before = warmed.start.clone();
        advance(&mut warmed.driver, Limit::Steps(1));
        let after = warmed.driver.simulation().state();
        // φ and u0 are final before the coupling solve of a step, which changes only u3D.
        let phi_sq = after.physical.phi.iter().map(|p| p * p).collect();
        let u0 = after.physical.u0_m.clone();
        let reference = after.physical.u3d_m.clone();
        let run_iterations =
            after.counters.coupling_iterations - before.counters.coupling_iterations;
        let config = warmed.driver.simulation().config().clone();
        let rho0 = warmed.rho0;
        drop(warmed);

        // The quadratic extrapolation of `Simulation` (Lagrange weights at t_n + Δt through
        // t_n, t_n − h_last, t_n − h_last − h_prev).
        let (x, a) = (DT_S, before.stepper.last_dt_s);
        let b = a + before.stepper.prev_dt_s;
        assert!(
            before.stepper.last_dt_s > 0.0
                && before.stepper.prev_dt_s > 0.0
                && before.stepper.u3d_prev2_m.len() == n,
            "three steps of history"
        );
        let w0 = (x + a) * (x + b) / (a * b);
        let w1 = -x * (x + b) / (a * (b - a));
        let w2 = x * (x + a) / (b * (b - a));
        let extrapolated = (0..n)
            .map(|i| {
                w0 * before.physical.u3d_m[i]
                    + w1 * before.stepper.u3d_prev_m[i]
                    + w2 * before.stepper.u3d_prev2_m[i]
            })
            .collect();

        let grid = Grid::new(config.contact.radius_m, n).expect("valid grid");
        let ops = MdrOperators::with_form(grid, Quadrature::Product, config.operator_form());
        Self {
            ops,
            phi_sq,
            u0,
            kappa: config.lubricant.a_pa
                / (config.contact.film_thickness_m * config.contact.g_eff_pa),
            tolerance: CouplingTolerance {
                rel_tol: config.numerics.coupling_tol,
                // The relative criterion alone, so that the guesses compare on one criterion
                // (adaptive runs also accept a residual below their absolute floor).
                abs_rms_m: 0.0,
                spectral_bound: rho0,
                // One solve from each guess, as a single step of a run takes it.
                deepen_near_misses: false,
            },
            guesses: [
                ("cold", vec![0.0; n]),
                ("warm", before.physical.u3d_m),
                ("extrapolated", extrapolated),
            ],
            reference,
            run_iterations,
        }
    }

    /// ‖K·(u0 − u) − u‖ / ‖u‖, recomputed here: the report's `rel_residual` is relative to
    /// the guess's norm, which a zero guess makes meaningless.
    fn rel_residual(&self, u: &[f64]) -> f64 {
        let n = u.len();
        let dx: Vec<f64> = (0..n)
            .map(|i| self.kappa * self.phi_sq[i] * (self.u0[i] - u[i]))
            .collect();
        let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
        self.ops.compliance(&dx, &mut q, &mut y);
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
        norm(&mut y.iter().zip(u).map(|(y, u)| y - u)) / norm(&mut u.iter().copied())
    }

    /// Solves from `guess` into `u`.
    fn solve(&self, solver: &mut CouplingSolver, guess: &[f64], u: &mut [f64]) -> CouplingReport {
        u.copy_from_slice(guess);
        solver.solve(
            &self.ops,
            &self.phi_sq,
            self.kappa,
            &self.u0,
            u,
            self.tolerance,
        )
    }
}

fn solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("coupling_solve");
    for n in SIZES {
        let problem = SolveProblem::new(n);
        let mut solver = CouplingSolver::new(n);
        let mut u = vec![0.0; n];
        let scale = problem
            .reference
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        group.throughput(Throughput::Elements(n as u64));
        for (name, guess) in &problem.guesses {
            let report = problem.solve(&mut solver, guess, &mut u);
            let distance = u
                .iter()
                .zip(&problem.reference)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            eprintln!(
                "coupling_solve/{name}/{n}: {} BiCGSTAB iterations, converged {}, \
                 |K(u0 - u) - u| / |u| = {:.2e}; max|u - run's u| / max|u| = {:.2e} (the run's \
                 step: {} iterations; tolerance {:e}, rho {:.3})",
                report.iterations,
                report.converged,
                problem.rel_residual(&u),
                distance / scale,
                problem.run_iterations,
                problem.tolerance.rel_tol,
                problem.tolerance.spectral_bound,
            );
            group.bench_with_input(BenchmarkId::new(*name, n), &n, |b, _| {
                b.iter(|| problem.solve(&mut solver, guess, &mut u));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, step, solve);
criterion_main!(benches);
