//! The drive's dashpot (`drive.damping`, docs/model.md#the-drive): 0 is the paper's model byte
//! for byte, and a sliding (liquid) film under a damped spring follows the exact damped free
//! motion through the whole simulation.

use crate::common;

use stickslip_core::drive::{Drive, free_spring_exact};
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::{DirOptions, ResolvedScene, Scene, run_to_dir};

fn scene(sets: &[&str]) -> ResolvedScene {
    Scene::from_path(&common::scene("fig2"), sets).unwrap()
}

#[test]
fn zero_damping_is_the_papers_drive_byte_for_byte() {
    // Through the first event and into the second stick phase, for each integrator.
    for integrator in ["split", "verlet", "rk4"] {
        let integrator_set = format!("drive.integrator={integrator}");
        let base = [
            "contact.nodes=40",
            "time.end=7e-4",
            "output.profile_times=[6.5e-4, 7e-4]",
            integrator_set.as_str(),
        ];
        let tmp = tempfile::tempdir().unwrap();
        let mut runs = Vec::new();
        for extra in [None, Some("drive.damping=0"), Some("drive.damping=-0.0")] {
            let mut sets: Vec<&str> = base.to_vec();
            sets.extend(extra);
            let s = scene(&sets);
            let dir = tmp.path().join(format!("run{}", runs.len()));
            let options = DirOptions {
                force: false,
                checkpoint_every_s: 0.0,
            };
            run_to_dir(&s, &dir, &options, &mut Control::default()).unwrap();
            runs.push((s, common::outputs(&dir)));
        }
        let (plain, files) = &runs[0];
        assert!(files.iter().any(|(n, _)| n == "events.csv"));
        let drive = plain.resolved.drive.as_ref().unwrap();
        assert_eq!(drive.damping.map(f64::to_bits), Some(0.0f64.to_bits()));
        for (s, other) in &runs[1..] {
            assert_eq!(s.config, plain.config);
            assert_eq!(s.resolved, plain.resolved);
            assert_eq!(other.len(), files.len());
            for ((name, a), (_, b)) in files.iter().zip(other) {
                assert!(
                    a == b,
                    "{integrator}: {name} differs with drive.damping = 0"
                );
            }
        }
    }
}

#[test]
fn a_sliding_film_under_a_damped_spring_follows_the_exact_damped_motion() {
    // A ≤ 0: the film is liquid, F = 0, and the stamp moves as the damped spring alone. With
    // c_d = 100 N·s/m (ζ ≈ 7.1) the dashpot dominates the start: X ≈ (c_d/m)·V0·t²/2.
    for (scheme, integrator) in [
        ("accurate", "split"),
        ("literal", "split"),
        ("accurate", "verlet"),
        ("accurate", "rk4"),
    ] {
        let s = scene(&[
            "temperature.A0=-1e5",
            "contact.nodes=20",
            "drive.damping=100",
            &format!("time.scheme={scheme}"),
            &format!("drive.integrator={integrator}"),
            "time.stepping=fixed",
            "time.dt=2e-8",
        ]);
        let Drive::Spring(spring) = s.config.drive else {
            unreachable!()
        };
        assert!((spring.damping_ratio() - 100.0 / (2.0 * 50f64.sqrt())).abs() < 1e-14);
        let mut driver = Driver::start(&s, &mut NullSink).unwrap();
        let stop = driver
            .advance(&mut NullSink, &mut Control::default(), Limit::Time(2e-4))
            .unwrap();
        assert_eq!(stop, None);
        let sim = driver.simulation();
        let st = &sim.state().physical;
        assert_eq!(st.force_n, 0.0);
        let (x, v) = free_spring_exact(&spring, sim.time_s());
        let undamped = stickslip_core::drive::SpringDrive {
            damping_n_s_per_m: 0.0,
            ..spring
        };
        let (x_undamped, _) = free_spring_exact(&undamped, sim.time_s());
        // The split flow is exact: rounding only, over 10⁴ steps; Verlet second order, RK4
        // fourth, at (c_d/m)·Δt = 2e-5.
        let tol = if integrator == "split" { 1e-11 } else { 1e-9 };
        let (ex, ev) = ((st.drive.x_m - x) / x, (st.drive.v_m_per_s - v) / v);
        eprintln!("{scheme}/{integrator}: relative error of X {ex:.2e}, of V {ev:.2e}");
        assert!(
            ex.abs() <= tol && ev.abs() <= tol,
            "{scheme}/{integrator}: {ex:e} {ev:e}"
        );
        assert!(
            x > 1e3 * x_undamped,
            "the dashpot drives the stamp: {x} vs {x_undamped}"
        );
    }
}
