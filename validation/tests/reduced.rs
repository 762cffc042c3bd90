//! The committed `reports/summary.json` against the code, at reduced size: fig2 at N = 30,
//! Δt = 2e-8 s, end = 1 ms, run here in-process with the core (well under a second), while
//! `cargo xtask validate` ran the same through the `stickslip` binary. So this test fails when
//! the reports are stale, and also when the command line stops recording what the core
//! computes. Plus an insta snapshot of the same qualitative features (event count, onsets to
//! 0.1 µs, first radii, step count, verdicts).

use std::path::Path;
use std::sync::OnceLock;
use stickslip_core::config::{Scheme, SimConfig};
use stickslip_core::drive::Drive;
use stickslip_core::sim::Simulation;
use stickslip_validation::data::{Event, Events, RunInfo, RunOutput, Series};
use stickslip_validation::reduced::{
    DT_S, END_S, Features, MERGE_GAP_S, NODES, RECORD_EVERY, features,
};

/// The reduced configuration, equal to `fig2.toml` with `reduced::cli_overrides()`.
fn config() -> SimConfig {
    let mut c = SimConfig::fig2(Scheme::Accurate);
    c.contact.nodes = NODES;
    c.time.dt_s = DT_S;
    c.time.end_s = END_S;
    c
}

/// Runs [`config`] in-process and records it as the binary would (rows every 1e-7 s).
fn run() -> RunOutput {
    let config = config();
    let steps = (END_S / DT_S).round() as u64;
    let mut sim = Simulation::new(config.clone()).expect("valid reduced config");
    let mut series = Series::default();
    let mut record = |sim: &mut Simulation| {
        let o = sim.observables();
        series.t_s.push(o.t_s);
        series.x_m.push(o.x_m);
        series.v_m_per_s.push(o.v_m_per_s);
        series.f_n.push(o.f_n);
        series.f_1d_n.push(o.f_1d_n);
        series.phi_mean.push(o.phi_mean);
        series.eps_mean.push(o.eps_mean);
        series.melted_fraction.push(o.melted_fraction);
    };
    record(&mut sim);
    for s in 1..=steps {
        sim.step(DT_S).expect("the reduced fig2 run is stable");
        if s % RECORD_EVERY == 0 {
            record(&mut sim);
        }
    }
    let events = sim
        .events()
        .iter()
        .map(|e| Event {
            k: e.k,
            t_onset_s: e.t_onset_s,
            r_first_m: e.r_first_m,
            x_onset_m: e.x_onset_m,
            f_peak_n: e.f_peak_n,
            r_min_m: Some(e.r_min_m),
            t_center_s: e.t_center_s,
            t_end_s: e.t_end_s,
            max_melted_fraction: Some(e.max_melted_fraction),
        })
        .collect();
    let Drive::Spring(spring) = config.drive else {
        panic!("fig2 has a spring drive")
    };
    RunOutput {
        name: "fig2_reduced".into(),
        series,
        events: Events {
            events,
            has_front_columns: true,
        },
        probes: None,
        profiles: Vec::new(),
        info: RunInfo {
            radius_m: config.contact.radius_m,
            melt_threshold: config.melt_threshold,
            velocity_m_per_s: spring.velocity_m_per_s,
            stiffness_n_per_m: Some(spring.stiffness_n_per_m),
            mass_kg: Some(spring.mass_kg),
            tau_max_pa: config.lubricant.tau_max_pa,
            nodes: NODES,
            scheme: "accurate".into(),
            dt_s: DT_S,
            end_s: END_S,
            steps: sim.state().step,
            wall_seconds: f64::NAN,
            status: "ok".into(),
        },
    }
}

fn fresh() -> &'static Features {
    static FEATURES: OnceLock<Features> = OnceLock::new();
    FEATURES.get_or_init(|| features(&run()))
}

#[test]
fn committed_summary_matches_the_code_at_reduced_size() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../reports/summary.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; the reports are generated: run `cargo xtask validate`",
            path.display()
        )
    });
    let summary: serde_json::Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let committed: Features = serde_json::from_value(summary["reduced"].clone())
        .expect("summary.json has a `reduced` block: run `cargo xtask validate`");
    assert_eq!(
        fresh(),
        &committed,
        "reports/summary.json is stale: the core now gives different reduced-size results than \
         the committed reports (or the CLI recorded something else than the core computes). \
         Run `cargo xtask validate` and commit reports/."
    );
}

#[test]
fn reduced_fig2_features_snapshot() {
    insta::assert_json_snapshot!("reduced_fig2", fresh());
}
