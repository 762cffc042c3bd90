//! The verify check's own rules (without running anything): sfa.toml is fig2's film on the
//! apparatus's contact, a quantity is covered by its uncertainty or by an honest verdict only,
//! the summary block and `--check` see a lost coverage, and the report says so.

use std::path::Path;
use stickslip_core::drive::Drive;
use stickslip_run::Scene;
use stickslip_studies::verify::Verdict;
use stickslip_validation::verify_check::{
    SUBJECTS, SceneCheck, VerifyCheck, all_covered, compare, markdown, sentence, to_json,
};

fn scene(stem: &str) -> stickslip_run::ResolvedScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{stem}.toml"));
    Scene::from_path(&path, &[] as &[&str]).expect("the scene resolves")
}

#[test]
fn sfa_is_fig2s_film_on_the_apparatuss_contact() {
    let (fig2, sfa) = (scene("fig2").config, scene("sfa").config);
    assert_eq!(sfa.lubricant, fig2.lubricant);
    assert_eq!(sfa.melt_threshold, fig2.melt_threshold);
    assert_eq!(sfa.noise, fig2.noise);
    assert_eq!(sfa.temperature, fig2.temperature);
    assert_eq!(sfa.integrator, fig2.integrator);
    assert_eq!(sfa.numerics, fig2.numerics);
    assert_eq!(sfa.events, fig2.events);
    let (c, f) = (&sfa.contact, &fig2.contact);
    assert_eq!(
        (c.radius_m, c.g_eff_pa, c.model, c.substrate),
        (f.radius_m, f.g_eff_pa, f.model, f.substrate)
    );
    assert_eq!((c.film_thickness_m, c.nodes), (1e-9, 200));
    let (t, g) = (&sfa.time, &fig2.time);
    assert_eq!((t.scheme, t.dt_s), (g.scheme, g.dt_s));
    // The default adaptive stepping (its longest step defaults to the end time).
    let (a, b) = (t.adaptive.expect("adaptive"), g.adaptive.expect("adaptive"));
    assert_eq!((a.tolerance, a.dt_min_s), (b.tolerance, b.dt_min_s));
    assert_eq!((a.dt_max_s, b.dt_max_s), (t.end_s, g.end_s));
    assert_eq!(t.end_s, 0.11);
    let Drive::Spring(d) = sfa.drive else {
        panic!("a spring drive")
    };
    assert_eq!(
        (d.stiffness_n_per_m, d.mass_kg, d.velocity_m_per_s),
        (5000.0, 0.1, 1e-6)
    );
}

fn row(
    name: &str,
    uncertainty: f64,
    verdict: Verdict,
    true_error: f64,
) -> stickslip_validation::verify_check::Row {
    stickslip_validation::verify_check::Row {
        name: name.to_string(),
        unit: "s".to_string(),
        value: 1.0 + true_error,
        reference: 1.0,
        uncertainty,
        verdict,
        true_error,
        covered: uncertainty >= true_error
            || stickslip_validation::verify_check::says_unconverged(verdict),
    }
}

fn check(rows: Vec<stickslip_validation::verify_check::Row>) -> Vec<VerifyCheck> {
    vec![VerifyCheck {
        subject: SUBJECTS[1],
        command: "stickslip verify validation/scenes/sfa.toml".to_string(),
        result: Ok(SceneCheck {
            levels: Vec::new(),
            reference_nodes: 3200,
            reference_stepping: "adaptive steps".to_string(),
            reference_steps: 1,
            reference_wall_s: 0.0,
            rows,
            not_in_reference: vec!["onset_3".to_string()],
        }),
    }]
}

#[test]
fn a_small_uncertainty_far_from_the_truth_is_not_covered_and_fails() {
    let good = check(vec![
        row("t_first_onset", 2e-3, Verdict::Outside, 1e-3),
        row("f_mean", 1e-9, Verdict::NotConverged, 1e-3),
        row("onset_2", f64::INFINITY, Verdict::Changed, 1e-3),
    ]);
    let bad = check(vec![
        row("t_first_onset", 2e-3, Verdict::Outside, 1e-3),
        row("f_mean", 1e-9, Verdict::Within, 1e-3),
        row("onset_2", 1e-9, Verdict::Outside, 1e-3),
    ]);
    assert!(all_covered(&good));
    assert!(!all_covered(&bad));
    let s = bad[0].result.as_ref().unwrap();
    assert_eq!(s.covered(), 1);
    assert_eq!(s.uncovered(), ["f_mean", "onset_2"]);
    assert!(
        sentence(s).contains("**1 of 3 quantities**"),
        "{}",
        sentence(s)
    );
    assert!(sentence(s).contains("not covered: f_mean, onset_2"));
    let g = sentence(good[0].result.as_ref().unwrap());
    // An infinite uncertainty covers by itself.
    assert!(
        g.contains("(2 by the uncertainty, 1 by the verdict alone)"),
        "{g}"
    );
    assert!(markdown(&bad).contains("❌ NO"));
    assert!(markdown(&bad).contains("**Not every quantity is covered.**"));
    // An infinite uncertainty is null in the summary; a failed comparison fails too.
    let j = to_json(&good);
    assert!(j["scenes"]["sfa"]["rows"][2]["uncertainty"].is_null());
    let failed = vec![VerifyCheck {
        result: Err("verify failed".into()),
        ..good[0].clone()
    }];
    assert!(!all_covered(&failed) && !all_covered(&[]));
}

#[test]
fn check_sees_a_lost_coverage() {
    let wrap = |c: &[VerifyCheck]| serde_json::json!({ "verify_check": to_json(c) });
    let good = wrap(&check(vec![row("f_mean", 1.0, Verdict::Within, 0.5)]));
    let bad = wrap(&check(vec![row("f_mean", 0.1, Verdict::Within, 0.5)]));
    assert!(compare(&good, &good).is_empty());
    let d = compare(&bad, &good);
    assert!(
        d.iter().any(|l| l.contains("all covered now false")),
        "{d:?}"
    );
    assert!(d.iter().any(|l| l.contains("sfa: covered now 0")), "{d:?}");
    assert!(
        d.iter().any(|l| l.contains("uncovered now [\"f_mean\"]")),
        "{d:?}"
    );
}
