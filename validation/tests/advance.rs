//! The advance-per-cycle criterion on real runs at reduced size (fig2 and the rigid drive at
//! N = 100, in-process): it holds, an estimate that leaves the kinetics out misses, and a film
//! with another γ than the estimate's fails it.

use std::path::Path;
use stickslip_run::keys::{Setting, contact, lubricant, output, time};
use stickslip_run::{Control, RunOutput, RunStatus, Scene, run_in_memory};
use stickslip_validation::advance::{MAX_REL_DEV, of_run, of_run_with};
use stickslip_validation::hysteresis::Film;

fn run(scene: &str, sets: &[Setting]) -> RunOutput {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{scene}.toml"));
    let sets: Vec<String> = sets.iter().map(ToString::to_string).collect();
    let scene = Scene::from_path(&path, &sets).expect("the scene resolves");
    let (outcome, output) = run_in_memory(&scene, &mut Control::default()).expect("starts");
    assert_eq!(outcome.status(), RunStatus::Ok, "{:?}", outcome.failure);
    output
}

fn small(end_s: f64) -> Vec<Setting> {
    vec![
        contact::NODES.set(100_i64),
        time::END.set(end_s),
        output::PROFILE_TIMES.set(vec![end_s]),
    ]
}

#[test]
fn the_advance_per_cycle_meets_its_estimate_and_the_fold_alone_does_not() {
    for (scene, end) in [("fig2", 1.0e-3), ("rigid", 6e-4)] {
        let out = run(scene, &small(end));
        let a = of_run(scene, &out).expect("cycles");
        eprintln!(
            "{scene}: {} cycles, largest deviation {}",
            a.cycles.len(),
            a.max_dev()
        );
        assert!(a.cycles.len() >= 3, "{scene}: {} cycles", a.cycles.len());
        assert!(
            a.max_dev() <= MAX_REL_DEV,
            "{scene}: largest deviation {}",
            a.max_dev()
        );
        for c in &a.cycles {
            // Without the kinetic delay every cycle is missed by more than the threshold.
            assert!(c.fold_only > MAX_REL_DEV, "{scene} cycle {}: {c:?}", c.k);
        }
    }
}

#[test]
fn a_film_slower_than_the_estimate_s_fails_it() {
    // The run's film relaxes 4× slower (γ/4): it lags further behind its branch, melts later,
    // and the estimate made with the scene's γ misses it.
    let out = run(
        "fig2",
        &[small(1.0e-3), vec![lubricant::GAMMA.set(2.5)]].concat(),
    );
    let mut film = Film::of(&out).expect("film");
    film.params.gamma_per_pa_s = 10.0;
    let a = of_run_with("fig2", &out, &film).expect("cycles");
    eprintln!(
        "γ/4 judged with γ: {}; with its own: {}",
        a.max_dev(),
        of_run("fig2", &out).expect("cycles").max_dev()
    );
    assert!(
        a.max_dev() > MAX_REL_DEV,
        "largest deviation {}",
        a.max_dev()
    );
    let honest = of_run("fig2", &out).expect("cycles");
    assert!(
        honest.max_dev() <= MAX_REL_DEV,
        "with its own γ: {}",
        honest.max_dev()
    );
}
