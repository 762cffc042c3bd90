//! The P1–P6 rows of the performance table and the P1, P4 and P5 sections of
//! `performance.md` (P2 and P3 are in [`super::report`]). Every number comes from the
//! measurements in [`Performance`] or the goals of [`super`].

use super::sweep::{EFFICIENCY_GOAL, OVERHEAD_GOAL};
use super::{
    P1_LITERAL_STEP_CAP_S, P1_ONSET_GOAL_US, P1_SPEEDUP_GOAL, P2_RATIO_GOAL, P3_GOAL_S,
    P4_TEST_RATIO_GOAL, P4_VALIDATE_GOAL_S, P6_RATIO_GOAL, Performance, T1_NODES, T2_GOAL_S, Timed,
    capped_literal_s,
};
use std::fmt::Write as _;
use stickslip_report::fmt::{opt, sig, tick};

/// A target's verdict in the report's words. (Here, not in `report`, which calls this module:
/// no two files of the performance report import each other.)
pub(super) fn verdict(ok: bool) -> &'static str {
    if ok { "**met**" } else { "**not met**" }
}

/// Seconds with three significant digits, comma-separated.
pub(super) fn seconds(ws: &[f64]) -> String {
    ws.iter().map(|w| sig(*w, 3)).collect::<Vec<_>>().join(", ")
}

/// The literal scheme's loop time per step on its window, µs.
fn literal_step_us(p: &Performance) -> f64 {
    let lit = &p.literal_window_run;
    1e6 * lit.loop_s / lit.steps.max(1) as f64
}

/// P1's ratio over the repeats of both its sides: the shipped run's walls, and the literal
/// window's, each extrapolated and capped as the median is ([`capped_literal_s`]; a repeat's
/// loop time is its wall less the median run's set-up). The yardstick is a median of three
/// whose own spread (1.87–2.20 s in one run) is as wide as the shipped run's, so leaving it
/// out would call a ratio met or not met that another run on this host could turn.
fn p1_span(p: &Performance) -> (f64, f64) {
    let whole_steps = stickslip_run::scene::step_count(p.scene_end_s, p.paper_dt_s);
    p1_span_of(&p.literal_window_run, &p.shipped, whole_steps)
}

/// [`p1_span`] of the literal window `lit` and the shipped run, the whole run `whole_steps`
/// long.
fn p1_span_of(lit: &Timed, shipped: &Timed, whole_steps: u64) -> (f64, f64) {
    let setup_s = lit.wall_s - lit.loop_s;
    let capped: Vec<f64> = lit
        .walls_s
        .iter()
        .map(|&w| {
            let loop_s = (w - setup_s).max(0.0);
            capped_literal_s(
                setup_s,
                loop_s,
                lit.steps,
                whole_steps,
                P1_LITERAL_STEP_CAP_S,
            )
        })
        .collect();
    let (lit_lo, lit_hi) = super::spread::min_max(&capped);
    let (lo, hi) = super::spread::min_max(&shipped.walls_s);
    (lit_lo / hi, lit_hi / lo)
}

/// The rows P1–P6, M1–M2 and V1–V2 of the targets table.
pub(super) fn targets_table(m: &mut String, p: &Performance) {
    let sh = &p.shipped;
    let _ = writeln!(
        m,
        "| P1 fig2 as shipped (N = {}, default adaptive accurate scheme) against the literal \
         scheme (N = {}, dt = {:e} s), its loop time per step capped at {} ms | ≥ {}×, onsets \
         within {} µs | {}× capped ({} s against {} s; literal step {} µs), {}× as measured \
         ({} s extrapolated); largest onset error {} µs | {} |",
        sh.resolved.nodes,
        p.paper_nodes,
        p.paper_dt_s,
        tick(1e3 * P1_LITERAL_STEP_CAP_S),
        tick(P1_SPEEDUP_GOAL),
        tick(P1_ONSET_GOAL_US),
        sig(p.shipped_speedup_capped, 3),
        sig(sh.wall_s, 3),
        sig(p.fig2_literal_capped_s, 3),
        sig(literal_step_us(p), 3),
        sig(p.shipped_speedup, 3),
        sig(p.fig2_literal_extrapolated_s, 3),
        sig(sh.max_onset_error_us, 2),
        super::spread::verdict(
            p.shipped_speedup_capped >= P1_SPEEDUP_GOAL
                && sh.max_onset_error_us <= P1_ONSET_GOAL_US,
            super::spread::within_noise(p1_span(p), P1_SPEEDUP_GOAL)
        )
    );
    let ratio = p
        .rigid_full
        .as_ref()
        .map(|r| p.full_resolution_s / r.wall_s);
    let _ = writeln!(
        m,
        "| P2 N = {}, fixed dt = {:e} s: elastic against rigid substrate, whole run | ≤ {}×, \
         ≤ {} s | {}; {} s ({}) | {} |",
        p.paper_nodes,
        p.paper_dt_s,
        tick(P2_RATIO_GOAL),
        tick(T2_GOAL_S),
        ratio.map_or_else(
            || "ratio not measured".into(),
            |r| format!("{}×", sig(r, 3))
        ),
        sig(p.full_resolution_s, 3),
        if p.full_resolution_measured {
            "measured in full".to_string()
        } else {
            format!(
                "extrapolated from a {} µs window",
                sig(p.full_resolution_window_s * 1e6, 2)
            )
        },
        verdict(ratio.is_some_and(|r| r <= P2_RATIO_GOAL) && p.full_resolution_s <= T2_GOAL_S)
    );
    let _ = writeln!(
        m,
        "| P3 fig2, default settings, N = {T1_NODES}, whole process | ≤ {} s | {} s (2 threads), \
         {} s (1 thread); against a same-N reference: onsets within {} µs, t_end within {} µs, \
         f_peak within {} relative | {} |",
        tick(P3_GOAL_S),
        sig(p.fig2_accurate_s, 3),
        sig(p.fig2_accurate_1thread_s, 3),
        sig(p.fig2_accurate_max_onset_error_us, 2),
        opt(p.fig2_accurate_errors.max_t_end_s.map(|e| e * 1e6), 2),
        opt(p.fig2_accurate_errors.max_f_peak_rel, 2),
        super::spread::verdict(
            p.fig2_accurate_s <= P3_GOAL_S,
            p.fig2_accurate_runs.first().is_some_and(|t| {
                super::spread::within_noise(super::spread::min_max(&t.walls_s), P3_GOAL_S)
            })
        )
    );
    match &p.build {
        Some(b) => {
            let ratio = b.test_s / b.validate_s;
            let _ = writeln!(
                m,
                "| P4 fresh clone: the test command after `cargo xtask validate`; validate itself \
                 | ≤ {}× validate, validate ≤ {} s | {} s = {}× validate ({} s){} | {} |",
                tick(P4_TEST_RATIO_GOAL),
                tick(P4_VALIDATE_GOAL_S),
                sig(b.test_s, 3),
                sig(ratio, 2),
                sig(b.validate_s, 3),
                if b.validate_ok && b.test_ok {
                    ""
                } else {
                    "; a command FAILED"
                },
                verdict(
                    b.validate_ok
                        && b.test_ok
                        && ratio <= P4_TEST_RATIO_GOAL
                        && b.validate_s <= P4_VALIDATE_GOAL_S
                )
            );
        }
        None => {
            let _ = writeln!(
                m,
                "| P4 fresh clone: test command after validate | ≤ {}× validate, validate ≤ {} s \
                 | not measured (`cargo xtask build-timing`) | **not measured** |",
                tick(P4_TEST_RATIO_GOAL),
                tick(P4_VALIDATE_GOAL_S)
            );
        }
    }
    let sw = &p.sweep;
    let overhead = sw.run(1).map_or(f64::NAN, super::sweep::SweepRun::overhead);
    let _ = writeln!(
        m,
        "| P5 friction map, {} points at N = {} | overhead ≤ {} %, parallel efficiency ≥ {} \
         | {} ms per point (2 jobs), overhead {} %, efficiency {} | {} |",
        sw.points,
        sw.nodes,
        tick(100.0 * OVERHEAD_GOAL),
        tick(EFFICIENCY_GOAL),
        sig(1e3 * sw.cost_per_point_s(), 3),
        sig(100.0 * overhead, 2),
        sig(sw.efficiency(), 3),
        verdict(overhead <= OVERHEAD_GOAL && sw.efficiency() >= EFFICIENCY_GOAL)
    );
    let rf = &p.refine;
    let _ = writeln!(
        m,
        "| M1 the rigid speed × temperature map refined to the resolution of a {side} × {side} \
         grid ({} levels) | ≤ {} % of that grid's points, the same regime at every point both \
         have | {} points = {} % ({} s); against a {} × {} uniform sample: {} shared points \
         ({} differ), {} inside refined cells ({} differ) | {} |",
        rf.levels,
        tick(100.0 * super::refine::M1_FRACTION_GOAL),
        rf.refined_points,
        sig(100.0 * rf.fraction(), 2),
        sig(rf.refined_wall_s, 3),
        (rf.sample_points as f64).sqrt().round(),
        (rf.sample_points as f64).sqrt().round(),
        rf.shared,
        rf.shared_differ,
        rf.inferred,
        rf.inferred_differ,
        verdict(
            rf.fraction() <= super::refine::M1_FRACTION_GOAL
                && rf.shared > 0
                && rf.shared_differ == 0
                && rf.inferred_differ == 0
                && rf.off_grid == 0
        ),
        side = (rf.uniform_points as f64).sqrt().round(),
    );
    let _ = writeln!(
        m,
        "| M2 `boundary`: the rigid drive's critical speed at A0 = {} Pa to {} relative | ≤ {} \
         runs | {} runs ({} s): V_c = {} m/s, bracket {} relative, {} below, {} above | {} |",
        tick(super::refine::M2_A0_PA),
        tick(super::refine::M2_RTOL),
        super::refine::M2_RUNS_GOAL,
        rf.boundary_runs,
        sig(rf.boundary_wall_s, 3),
        sig(rf.critical_speed, 4),
        sig(rf.bracket_rel, 2),
        rf.boundary_regimes.0,
        rf.boundary_regimes.1,
        verdict(
            rf.boundary_runs <= super::refine::M2_RUNS_GOAL
                && rf.bracket_rel <= super::refine::M2_RTOL
        )
    );
    let v = &p.verify_cost;
    let _ = writeln!(
        m,
        "| V1 `stickslip verify` of fig2 at N = {} (5 levels, 2 jobs) against the finest run it \
         makes | ≤ {}× | {}× ({} s against {} s at 4N and {} s at a hundredth of the tolerance, \
         each alone) | {} |",
        super::verify_cost::V1_NODES,
        tick(super::verify_cost::V1_RATIO_GOAL),
        sig(v.v1_ratio(), 3),
        sig(v.verify_wall_s, 3),
        sig(v.finest_space_s, 3),
        sig(v.finest_time_s, 3),
        verdict(v.v1_ratio() <= super::verify_cost::V1_RATIO_GOAL)
    );
    let _ = writeln!(
        m,
        "| V2 a {side} × {side} map ({} points, N = 50) with `[verify] sample = {}` against the \
         map alone, 2 jobs | ≤ {}× | {}× ({} s against {} s; {} points checked, {} changed \
         regime; with every boundary point too: {} checked, {} changed, {}×) | {} |",
        v.map_points,
        super::verify_cost::V2_SAMPLE,
        tick(super::verify_cost::V2_RATIO_GOAL),
        sig(v.v2_ratio(), 3),
        sig(v.map_sampled_s, 3),
        sig(v.map_s, 3),
        v.sampled_checked,
        v.sampled_changed,
        v.boundaries_checked,
        v.boundaries_changed,
        sig(v.map_boundaries_s / v.map_s, 3),
        verdict(v.v2_ratio() <= super::verify_cost::V2_RATIO_GOAL),
        side = super::verify_cost::V2_SIDE,
    );
    let (fo, so) = (&p.first_order, &p.fig2_accurate_runs[0]);
    let ratio = fo.wall_s / so.wall_s;
    let _ = writeln!(
        m,
        "| P6 fig2 at N = {T1_NODES} with the first-order film (b₃ = {} Pa of {}) against b₃ = 0, \
         whole process | ≤ {}× | {}× ({} s against {} s); per step evaluation {}× ({} µs against \
         {} µs; {} against {} evaluations, {} against {} events) | {} |",
        sig(p.first_order_cubic_pa, 4),
        super::P6_SCENE,
        tick(P6_RATIO_GOAL),
        sig(ratio, 3),
        sig(fo.wall_s, 3),
        sig(so.wall_s, 3),
        sig(fo.us_per_evaluation() / so.us_per_evaluation(), 3),
        sig(fo.us_per_evaluation(), 3),
        sig(so.us_per_evaluation(), 3),
        fo.evaluations(),
        so.evaluations(),
        fo.events,
        so.events,
        super::spread::verdict(
            ratio <= P6_RATIO_GOAL,
            super::spread::within_noise(super::spread::ratio_span(fo, so), P6_RATIO_GOAL)
        )
    );
}

/// P1: fig2 as shipped, the literal window, and what bounds the ratio (with its profile: the
/// same run on a rigid substrate and the approach to the first onset).
pub(super) fn p1_section(m: &mut String, p: &Performance) {
    let sh = &p.shipped;
    let lit = &p.literal_window_run;
    let accepted = sh.steps;
    let lit_us = literal_step_us(p);
    let needed_s = p.fig2_literal_capped_s / P1_SPEEDUP_GOAL;
    let cap_us = 1e6 * P1_LITERAL_STEP_CAP_S;
    let _ = writeln!(
        m,
        "## P1 — fig2 as shipped against the paper's algorithm\n\n\
         `stickslip run validation/scenes/fig2.toml` as shipped (N = {}, the {} scheme with {} \
         steps, operator `{}`), whole process, {} runs on 2 threads: [{}] s; {} accepted steps, \
         {} rejected, {} events; largest onset difference to the reference ({}) {} µs.\n\n\
         The literal scheme was timed on t ∈ [0, {} µs] ({} steps, loop {} s, {} µs per step, \
         process {} s) and extrapolated per simulated second to {} ms: {} s, {}× the shipped \
         run. Its step is memory-bound and its time swings with the host, so the verdict caps \
         its loop time per step at {} µs: {} s over the run's {} steps ({}), {}× the shipped \
         run; {}× needs the shipped run in {} s.\n",
        sh.resolved.nodes,
        sh.resolved.scheme,
        sh.resolved.stepping,
        sh.resolved.operator,
        sh.walls_s.len(),
        seconds(&sh.walls_s),
        accepted,
        sh.rejected_steps,
        sh.events,
        p.shipped_reference_settings.join(", "),
        sig(sh.max_onset_error_us, 2),
        sig(p.literal_window_s * 1e6, 3),
        lit.steps,
        sig(lit.loop_s, 3),
        sig(lit_us, 3),
        sig(lit.wall_s, 3),
        tick(p.scene_end_s * 1e3),
        sig(p.fig2_literal_extrapolated_s, 3),
        sig(p.shipped_speedup, 3),
        tick(cap_us),
        sig(p.fig2_literal_capped_s, 3),
        stickslip_run::scene::step_count(p.scene_end_s, p.paper_dt_s),
        if lit_us > cap_us {
            format!("the measured {} µs capped", sig(lit_us, 3))
        } else {
            "below the cap: as measured".to_string()
        },
        sig(p.shipped_speedup_capped, 3),
        tick(P1_SPEEDUP_GOAL),
        sig(needed_s, 3),
    );
    p1_profile(m, p, needed_s);
}

/// The P1 profile's coupling cell: the elastic run's time loop per evaluation less the rigid
/// run's. That difference resolves the coupling only when it is positive: the two runs take
/// different evaluations (the rigid one fewer and longer steps, with the run's fixed costs per
/// output row spread over fewer of them), and the elastic run's compliance runs on two threads.
fn coupling_cell(coupling_us: f64, per_eval_us: f64, rigid_evals: u64, evals: u64) -> String {
    let share = format!(
        "{} µs per evaluation ({} %)",
        sig(coupling_us, 2),
        sig(100.0 * coupling_us / per_eval_us, 2)
    );
    if coupling_us > 0.0 {
        share
    } else {
        format!(
            "{share}: not resolved by this difference, whose runs take different evaluations \
             ({rigid_evals} against {evals}, the fixed costs of each output row spread over \
             fewer of them) and whose elastic compliance runs on two threads; the roofline \
             row splits one evaluation instead"
        )
    }
}

/// P1's profile: where the shipped run's time goes and what the goal would need.
fn p1_profile(m: &mut String, p: &Performance, needed_s: f64) {
    let sh = &p.shipped;
    let rigid = &p.shipped_rigid;
    let approach = &p.shipped_approach;
    let event = &p.shipped_first_event;
    let cycle = &p.shipped_first_cycle;
    let setup_s = sh.wall_s - sh.loop_s;
    let evaluations = sh.evaluations();
    let per_eval_us = sh.us_per_evaluation();
    let rigid_us = rigid.us_per_evaluation();
    let coupling_us = per_eval_us - rigid_us;
    let iterations = sh.coupling_iterations as f64 / evaluations.max(1) as f64;
    let budget_s = needed_s - setup_s;
    let max_evaluations = 1e6 * budget_s / per_eval_us;
    let max_us = 1e6 * budget_s / evaluations.max(1) as f64;
    let approach_end_s = approach.resolved.end_s;
    let _ = writeln!(
        m,
        "What bounds it, measured in the same run:\n\n\
         | part | measured | target |\n|---|---|---|\n\
         | start-up (the scene, the MDR operators of N = {} built and compressed) | {} s, {} % \
         of the run | ≤ 20 % |\n\
         | step evaluations (accepted {} + rejected {} + retaken to end at a located onset {}) \
         | {}, {} per accepted step | ≤ 1.5 per accepted step |\n\
         | time loop per evaluation, elastic substrate | {} µs ({} coupling iterations per \
         evaluation) | |\n\
         | the same scene on a rigid substrate (the exact Landau step of {} nodes, the error \
         estimate, the drive, output) | {} µs per evaluation ({} evaluations) | |\n\
         | hence the elastic coupling | {} | |\n\
         | the approach to the first onset (t < {} µs, {} % of the simulated time) | {} \
         evaluations, {} % of the run's | |\n\
         | the first event, onset to end ({} µs) | {} evaluations | |\n\
         | the stick phase after it, up to the second onset ({} µs) | {} evaluations | |\n",
        sh.resolved.nodes,
        sig(setup_s, 2),
        sig(100.0 * setup_s / sh.wall_s, 2),
        sh.steps,
        sh.rejected_steps,
        sh.onset_retakes,
        evaluations,
        sig(evaluations as f64 / sh.steps.max(1) as f64, 3),
        sig(per_eval_us, 3),
        sig(iterations, 2),
        sh.resolved.nodes,
        sig(rigid_us, 3),
        rigid.evaluations(),
        coupling_cell(coupling_us, per_eval_us, rigid.evaluations(), evaluations),
        sig(approach_end_s * 1e6, 4),
        sig(100.0 * approach_end_s / p.scene_end_s, 2),
        approach.evaluations(),
        sig(
            100.0 * approach.evaluations() as f64 / evaluations.max(1) as f64,
            2
        ),
        sig(1e6 * (event.resolved.end_s - approach_end_s), 3),
        event.evaluations().saturating_sub(approach.evaluations()),
        sig(1e6 * (cycle.resolved.end_s - event.resolved.end_s), 3),
        cycle.evaluations().saturating_sub(event.evaluations()),
    );
    let verdict = if budget_s <= 0.0 {
        "the start-up alone exceeds it".to_string()
    } else if max_us < rigid_us {
        format!(
            "at today's {evaluations} evaluations that allows {} µs each, below even the rigid \
             substrate's {} µs: no coupling solver, however cheap, reaches the goal without \
             fewer evaluations; at today's {} µs per evaluation it allows {} evaluations ({}× \
             fewer)",
            sig(max_us, 2),
            sig(rigid_us, 3),
            sig(per_eval_us, 3),
            sig(max_evaluations, 2),
            sig(evaluations as f64 / max_evaluations, 2)
        )
    } else {
        format!(
            "at today's {evaluations} evaluations that allows {} µs each (the rigid substrate \
             costs {} µs: the coupling would have to cost at most {} µs); at today's {} µs \
             per evaluation it allows {} evaluations",
            sig(max_us, 2),
            sig(rigid_us, 3),
            sig(max_us - rigid_us, 2),
            sig(per_eval_us, 3),
            sig(max_evaluations, 2)
        )
    };
    let _ = writeln!(
        m,
        "The goal leaves a time loop of {} s after today's start-up: {verdict}. The number of \
         evaluations is set by the default tolerance, which the accuracy half of P1 (onsets \
         within {} µs of the same-N reference; today's largest onset error {} µs) bounds from \
         above: the convergence report's tolerance study gives the errors' slopes against the \
         tolerance, while the evaluations fall only as its cube root. The cost of an \
         evaluation is the film's exact step at every node and the coupling's transforms. One \
         step of the literal scheme costs {} µs.\n",
        sig(budget_s, 2),
        tick(P1_ONSET_GOAL_US),
        sig(p.shipped.max_onset_error_us, 2),
        sig(literal_step_us(p), 3),
    );
}

/// P4: the fresh clone's times, stage by stage.
pub(super) fn p4_section(m: &mut String, p: &Performance) {
    let _ = writeln!(m, "## P4 — a fresh clone's build\n");
    let Some(b) = &p.build else {
        let _ = writeln!(
            m,
            "Not measured: `cargo xtask build-timing` writes reports/build-timing.json.\n"
        );
        return;
    };
    let _ = writeln!(
        m,
        "`cargo xtask build-timing` cloned commit `{}` into an empty directory (its own empty \
         `target/`; the cargo registry's sources {} on a machine with {} logical CPUs) and ran \
         the README's two commands there: `cargo xtask validate` {} s ({}), then `cargo xtask \
         test` {} s ({}), {}× validate's time. The test command's stages:\n\n\
         | stage | s | share | result |\n|---|---|---|---|",
        &b.commit[..b.commit.len().min(10)],
        if b.registry_warm {
            "were already downloaded"
        } else {
            "were downloaded too"
        },
        b.cpus,
        sig(b.validate_s, 3),
        if b.validate_ok { "ok" } else { "FAILED" },
        sig(b.test_s, 3),
        if b.test_ok { "ok" } else { "FAILED" },
        sig(b.test_s / b.validate_s, 2)
    );
    for s in &b.test_stages {
        let _ = writeln!(
            m,
            "| {} | {} | {} % | {} |",
            s.name,
            sig(s.seconds, 3),
            sig(100.0 * s.seconds / b.test_s, 2),
            if s.ok { "ok" } else { "FAILED" }
        );
    }
    let _ = writeln!(
        m,
        "\nOne build serves both commands: everything is built in the release profile (xtask, \
         the CLI that validation runs, `cargo test --release`, and maturin's build of the \
         Python extension), and the crate `stickslip-unify` pins the features of the \
         dependencies that the commands' graphs would otherwise resolve differently, so the \
         test command compiles only test targets and the extension's own crates. Those are \
         kept few and cheap: one integration-test binary per package (the core, the run \
         library and the CLI each link `tests/integration.rs`, whose modules are the other \
         test files), the test-only dependencies unoptimised, the report generators and the \
         kit at opt-level 1.\n"
    );
}

/// P5: the sweep's cost, overhead and parallel efficiency, and what larger maps take.
pub(super) fn p5_section(m: &mut String, p: &Performance) {
    let sw = &p.sweep;
    let _ = writeln!(
        m,
        "## P5 — friction maps: cost per point and scaling\n\n\
         A {} × {} map of the rigid drive (maps/rigid.toml's axes: V0 log-spaced over 1e-3 … \
         3 m/s × A0 over −3e5 … 1.5e6 Pa; N = {}; regimes: {}) run by `stickslip sweep run` \
         in-process with 1 and 2 jobs:\n\n\
         | jobs | wall (s) | Σ run (s) | Σ point (s) | overhead | points not ok |\n\
         |---|---|---|---|---|---|",
        (sw.points as f64).sqrt().round(),
        (sw.points as f64).sqrt().round(),
        sw.nodes,
        sw.regimes
            .iter()
            .map(|(r, n)| format!("{r} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for r in &sw.runs {
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} % | {} |",
            r.jobs,
            sig(r.wall_s, 3),
            sig(r.sum_run_s, 3),
            sig(r.sum_point_wall_s, 3),
            sig(100.0 * r.overhead(), 2),
            r.not_ok
        );
    }
    let per_point = sw.core_s_per_point();
    let eff = sw.efficiency();
    let _ = writeln!(
        m,
        "\nOverhead = (jobs × wall − Σ run) / Σ run: everything beyond building and stepping the \
         simulations (process start, resolving and validating all points first, records, \
         merge, a worker idle at the end). Parallel efficiency = wall(1 job) / (2 × wall(2 \
         jobs)) = {}.\n\n\
         Points are independent and the per-point cost does not depend on the map's size, so \
         a map costs points × {} core-seconds (this map's mean; it depends on the axes: slow \
         drives and long `time.end` cost more, sliding points less). On this machine (2 \
         cores, efficiency {}):\n\n\
         | points | 2 cores here | cluster of K nodes × c cores |\n|---|---|---|",
        sig(eff, 3),
        sig(per_point, 3),
        sig(eff, 3)
    );
    for points in [1e4_f64, 1e5, 1e6] {
        let here_s = points * per_point / (2.0 * eff);
        let _ = writeln!(
            m,
            "| {} | {} | {} h / (K·c) (e.g. K = 10 nodes × c = 32 cores: {}) |",
            tick(points),
            duration(here_s),
            sig(points * per_point / 3600.0, 3),
            duration(points * per_point / 320.0)
        );
    }
    let _ = writeln!(
        m,
        "\nOn a cluster, `stickslip sweep slurm --tasks T` splits the points into T shards of \
         an array job; each task runs its shard with all its cores, so the time is the largest \
         shard's: for T ≥ K·c the estimate above holds when the shards balance (points are \
         dealt round-robin, index mod T, so neighbours in the map — similar costs — land in \
         different shards). Merging reads one small record per point.\n"
    );
}

/// A duration in s, min or h with three significant digits.
fn duration(s: f64) -> String {
    if s < 120.0 {
        format!("{} s", sig(s, 3))
    } else if s < 7200.0 {
        format!("{} min", sig(s / 60.0, 3))
    } else {
        format!("{} h", sig(s / 3600.0, 3))
    }
}

/// V1–V2: what verify and a map's spot checks cost, and what bounds V2.
pub(super) fn v_section(m: &mut String, p: &Performance) {
    let v = &p.verify_cost;
    let levels: Vec<String> = v
        .levels
        .iter()
        .map(|(what, steps, wall)| format!("{what}: {steps} steps, {} s", sig(*wall, 3)))
        .collect();
    // Each check's cost in runs of its point: the time the sample added, over the map's time
    // per point, per checked point.
    let per_check = if v.sampled_checked > 0 && v.map_points > 0 {
        (v.map_sampled_s - v.map_s) / (v.map_s / v.map_points as f64) / v.sampled_checked as f64
    } else {
        f64::NAN
    };
    let share = super::verify_cost::V2_SAMPLE;
    let goal = super::verify_cost::V2_RATIO_GOAL;
    let _ = write!(
        m,
        "\n## V1–V2 — what a number's error costs\n\n\
         V1: `stickslip verify` of fig2 at N = {} ran {} levels ({}) in {} s with 2 jobs; {} of \
         {} quantities within its rtol. Its finest runs alone take {} s (4N) and {} s (a \
         hundredth of the tolerance): verify costs {}× the costlier.\n\n\
         V2 (medians of {} runs of each variant): the sample of {} points added {} s to the \
         map's {} s: each check (a rerun at 2N and one at a tenth of the tolerance) cost about \
         {} runs of its point. A share s of the points then adds about {}·s to the map, so a {} \
         sample gives {}× and the goal of {}× holds for samples up to about {}. What bounds it is the refinements' own scaling: \
         a run's cost grows about linearly with N, and its steps as tolerance^(−1/3) (the \
         embedded pair's order), so without per-run fixed costs the two reruns cost 2 + \
         10^(1/3) ≈ 4.2 runs and a {} sample adds {} % — above the goal's {} %; only fixed \
         costs, which make the refined runs relatively cheaper and which faster code removes, \
         bring the measured figure below that. The goal needs a smaller sample, or the checks' \
         two refinements in one run (which costs their product, not less).\n\n",
        super::verify_cost::V1_NODES,
        v.levels.len(),
        levels.join("; "),
        sig(v.verify_wall_s, 3),
        v.within.0,
        v.within.1,
        sig(v.finest_space_s, 3),
        sig(v.finest_time_s, 3),
        sig(v.v1_ratio(), 3),
        v.repeats,
        v.sampled_checked,
        sig(v.map_sampled_s - v.map_s, 3),
        sig(v.map_s, 3),
        sig(per_check, 2),
        sig(per_check, 2),
        tick(share),
        sig(1.0 + per_check * share, 3),
        tick(goal),
        sig((goal - 1.0) / per_check, 2),
        tick(share),
        sig(100.0 * share * (2.0 + 10f64.cbrt()), 2),
        sig(100.0 * (goal - 1.0), 2),
    );
}

#[cfg(test)]
mod p1_span_tests {
    use super::*;

    #[test]
    fn the_span_takes_both_sides_repeats() {
        // The literal window: 3400 steps, set-up 0.1 s, loops 1.8 / 2.0 / 2.2 s (530-647 µs
        // per step, below the cap); the whole run 130000 steps; the shipped run 0.16-0.17 s.
        let lit = Timed {
            wall_s: 2.1,
            loop_s: 2.0,
            walls_s: vec![1.9, 2.1, 2.3],
            steps: 3400,
            ..Timed::default()
        };
        let shipped = Timed {
            walls_s: vec![0.17, 0.16, 0.165],
            ..Timed::default()
        };
        let (lo, hi) = p1_span_of(&lit, &shipped, 130_000);
        let whole = |loop_s: f64| 0.1 + loop_s / 3400.0 * 130_000.0;
        assert!((lo - whole(1.8) / 0.17).abs() < 1e-9 * lo);
        assert!((hi - whole(2.2) / 0.16).abs() < 1e-9 * hi);
        // A window slower than the cap per step contributes the capped run alone.
        let slow = Timed {
            walls_s: vec![4.0, 4.1],
            ..lit
        };
        let (lo, hi) = p1_span_of(&slow, &shipped, 130_000);
        let capped = 0.1 + 1e-3 * 130_000.0;
        assert!((lo - capped / 0.17).abs() < 1e-9 * lo && (hi - capped / 0.16).abs() < 1e-9 * hi);
    }
}
