//! Scene resolution through the library: documented defaults, Eq. 9, `--set` value parsing,
//! the printed resolved scene reading back the same, and no panic on garbage input.

use stickslip_core::config::{ContactModel, Scheme, Substrate};
use stickslip_core::drive::{Drive, Integrator};
use stickslip_core::landau::Temperature;
use stickslip_core::noise::NoiseKind;
use stickslip_run::scene::{Scene, SceneError};

const MINIMAL: &str = r#"
name = "minimal"
[lubricant]
tau_max = 1e6
eps_max = 1
a = 1e6
gamma = 10
[contact]
radius = 2e-5
film_thickness = 1e-7
g_eff = 1e9
[drive]
stiffness = 500
mass = 0.1
velocity = 1
[time]
end = 1e-3
"#;

const NONE: &[&str] = &[];

#[test]
fn defaults_are_filled_in() {
    let r = Scene::from_toml_str(MINIMAL, NONE).unwrap();
    let c = &r.config;
    assert_eq!(c.melt_threshold, 0.01);
    assert_eq!(c.noise, NoiseKind::Floor { floor: 1e-6 });
    assert_eq!(c.temperature, Temperature::Constant { a_coeff_pa: 1.5e6 });
    assert_eq!(c.contact.nodes, 200);
    assert_eq!(c.contact.model, ContactModel::Radial);
    assert_eq!(c.contact.substrate, Substrate::Elastic);
    assert!(matches!(c.drive, Drive::Spring(_)));
    assert_eq!(c.integrator, Integrator::Split);
    assert_eq!(c.time.dt_s, 1e-8);
    assert_eq!(c.time.scheme, Scheme::Accurate);
    // Adaptive by default: the coupling is solved to a hundredth of the step tolerance.
    assert!((c.numerics.coupling_tol / 5e-7 - 1.0).abs() < 1e-12);
    assert_eq!(c.numerics.runaway_stress_factor, 10.0);
    assert_eq!(r.output.profile_times_s, vec![1e-3]);
    assert!(r.output.probe_radii_m.is_empty());
    assert_eq!(c.events.merge_gap_s, 0.0);
    assert_eq!(c.events.recovery_factor, 2.0);
    assert_eq!(r.max_events, None);
    assert_eq!(r.output.series_interval_s, 1e-7);
    assert_eq!(r.steps, 100_000);
    assert!((r.derived.eps_c - 3f64.sqrt()).abs() < 1e-15);
}

#[test]
fn gaussian_noise_defaults() {
    let r = Scene::from_toml_str(MINIMAL, &["lubricant.noise.kind=gaussian"]).unwrap();
    assert_eq!(
        r.config.noise,
        NoiseKind::Gaussian {
            sigma_per_sqrt_s: 1.0,
            seed: 1
        }
    );
}

#[test]
fn modulus_from_eq_9() {
    let text = MINIMAL.replace("g_eff = 1e9", "g1 = 1e9\nnu1 = 0.5\ng2 = 2e9\nnu2 = 0.0");
    let r = Scene::from_toml_str(&text, NONE).unwrap();
    // ((2 − 0.5)/(4·1e9) + 2/(4·2e9))^−1 = (3.75e-10 + 2.5e-10)^−1 = 1.6e9
    assert!((r.config.contact.g_eff_pa - 1.6e9).abs() < 1.0);
}

#[test]
fn set_values_parse_as_toml_or_as_bare_strings() {
    let r = Scene::from_toml_str(
        MINIMAL,
        &[
            "time.scheme=literal",
            "time.dt = 2e-8",
            "contact.nodes=200",
            "output.probe_radii=[2e-6, 4e-6]",
            "temperature.law=\"relaxation\"",
            "temperature.A0=-1e5",
            "temperature.t_relax=1e-3",
            "drive.integrator=rk4",
        ],
    )
    .unwrap();
    assert_eq!(r.config.time.scheme, Scheme::Literal);
    assert_eq!(r.config.time.dt_s, 2e-8);
    assert_eq!(r.config.contact.nodes, 200);
    assert_eq!(r.output.probe_radii_m, vec![2e-6, 4e-6]);
    assert_eq!(
        r.config.temperature,
        Temperature::Relaxation {
            a0_pa: -1e5,
            t_relax_s: 1e-3
        }
    );
    assert_eq!(r.config.integrator, Integrator::Rk4);
    // The profile time defaults to the overridden end.
    let r = Scene::from_toml_str(MINIMAL, &["time.end=5e-4"]).unwrap();
    assert_eq!(r.output.profile_times_s, vec![5e-4]);
}

#[test]
fn rigid_drive_without_stiffness_and_mass() {
    let text = MINIMAL.replace("stiffness = 500\nmass = 0.1\n", "kind = \"rigid\"\n");
    let r = Scene::from_toml_str(&text, NONE).unwrap();
    assert!(matches!(r.config.drive, Drive::Rigid(_)));
    assert_eq!(r.derived.omega_rad_per_s, 0.0);
}

#[test]
fn printed_resolved_scene_reads_back_the_same() {
    for sets in [
        &[][..],
        &["lubricant.noise.kind=gaussian", "output.probe_radii=[1e-6]"][..],
        &[
            "temperature.law=relaxation",
            "temperature.A0=1.5e6",
            "temperature.t_relax=1e-3",
        ][..],
    ] {
        let r = Scene::from_toml_str(MINIMAL, sets).unwrap();
        let text = r.resolved.to_toml_string();
        let again = Scene::from_toml_str(&text, NONE).unwrap();
        assert_eq!(again.config, r.config, "{text}");
        assert_eq!(again.output, r.output);
        assert_eq!(again.resolved, r.resolved);
    }
}

#[test]
fn errors_name_their_key() {
    let e = Scene::from_toml_str(MINIMAL, &["contact.radius=-1"]).unwrap_err();
    assert_eq!(e.key(), Some("contact.radius"));
    let e = Scene::from_toml_str(MINIMAL, &["contact.colour=1"]).unwrap_err();
    assert!(matches!(e, SceneError::UnknownKey { ref key, .. } if key == "contact.colour"));
}

/// A small deterministic generator (xorshift64*), enough to scramble inputs.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

#[test]
fn garbage_never_panics() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let alphabet: &[u8] = b"[]{}=\"'.,#\n \t0123456789eE+-_abcdefghijklmnopqrstuvwxyz\\";
    let base = MINIMAL.as_bytes();
    for _ in 0..3000 {
        // Either random text from a TOML-ish alphabet or the valid scene with mutations.
        let bytes: Vec<u8> = if rng.next().is_multiple_of(2) {
            let n = (rng.next() % 200) as usize;
            (0..n)
                .map(|_| alphabet[(rng.next() % alphabet.len() as u64) as usize])
                .collect()
        } else {
            let mut b = base.to_vec();
            for _ in 0..1 + rng.next() % 4 {
                let i = (rng.next() % b.len() as u64) as usize;
                b[i] = alphabet[(rng.next() % alphabet.len() as u64) as usize];
            }
            b
        };
        let text = String::from_utf8_lossy(&bytes);
        let _ = Scene::from_toml_str(&text, NONE);
        let set = format!(
            "contact.{}",
            String::from_utf8_lossy(&bytes[..bytes.len().min(12)])
        );
        let _ = Scene::from_toml_str(MINIMAL, &[set.as_str()]);
    }
}

#[test]
fn unset_keys_turn_a_spring_scene_rigid_without_editing_the_file() {
    let fig2 = crate::common::scene("fig2");
    // The file sets a stiffness: the rigid drive is refused with it.
    let refused = Scene::from_path(&fig2, &["drive.kind=rigid"]).unwrap_err();
    assert!(refused.to_string().contains("drive.stiffness"), "{refused}");
    let rigid = Scene::from_path_unsetting(
        &fig2,
        &["drive.stiffness", "drive.mass", "drive.integrator"],
        &["drive.kind=rigid"],
    )
    .unwrap();
    assert!(matches!(
        rigid.config.drive,
        stickslip_core::drive::Drive::Rigid(_)
    ));
    // A key the file does not set is no error; a name that is no key is.
    assert!(Scene::from_path_unsetting(&fig2, &["drive.damping"], &[] as &[&str]).is_ok());
    let e = Scene::from_path_unsetting(&fig2, &["drive.speed"], &[] as &[&str]).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("--unset \"drive.speed\": no such scene key"),
        "{e}"
    );
}

#[test]
fn every_missing_required_key_is_named_at_once() {
    // A scene without [contact]: one error names all three of its required keys, so one edit
    // fixes it (it used to take three edit–rerun rounds).
    let without_contact = MINIMAL.replace(
        "[contact]\nradius = 2e-5\nfilm_thickness = 1e-7\ng_eff = 1e9\n",
        "",
    );
    assert_ne!(without_contact, MINIMAL);
    let e = Scene::from_toml_str(&without_contact, NONE)
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing required key `contact.radius`"), "{e}");
    assert!(
        e.contains("also missing: contact.film_thickness, contact.g_eff"),
        "{e}"
    );
    // Only the name: every required key, and the spring's two.
    let e = Scene::from_toml_str("name = \"x\"", NONE)
        .unwrap_err()
        .to_string();
    for key in [
        "lubricant.eps_max",
        "lubricant.gamma",
        "contact.radius",
        "drive.velocity",
        "drive.stiffness",
        "drive.mass",
        "time.end",
    ] {
        assert!(e.contains(key), "{key}: {e}");
    }
    // g_eff is not asked for when the four moduli of Eq. 9 stand for it.
    let eq9 = without_contact.replace(
        "[drive]",
        "[contact]\nfilm_thickness = 1e-7\ng1 = 1e9\nnu1 = 0.3\ng2 = 1e9\nnu2 = 0.3\n[drive]",
    );
    let e = Scene::from_toml_str(&eq9, NONE).unwrap_err().to_string();
    assert!(
        e.contains("`contact.radius`") && !e.contains("g_eff"),
        "{e}"
    );
    // One missing key: the message as before.
    let one = MINIMAL.replace("gamma = 10\n", "");
    let e = Scene::from_toml_str(&one, NONE).unwrap_err().to_string();
    assert!(
        e.contains("`lubricant.gamma`") && !e.contains("also missing"),
        "{e}"
    );
}

#[test]
fn time_travel_ends_the_run_when_the_drive_has_advanced_that_far() {
    let travel = MINIMAL.replace("end = 1e-3", "travel = 2e-4");
    let r = Scene::from_toml_str(&travel, NONE).unwrap();
    // V0 = 1 m/s: 2e-4 m takes 2e-4 s; the derived end follows the velocity.
    assert!((r.config.time.end_s / 2e-4 - 1.0).abs() < 1e-15);
    let slow = r.with_overrides(&["drive.velocity=1e-2"]).unwrap();
    assert!((slow.config.time.end_s / 2e-2 - 1.0).abs() < 1e-15);
    // Its derived defaults follow the end, and the printed scene reads back the same.
    assert_eq!(slow.output.profile_times_s, vec![slow.config.time.end_s]);
    let back = Scene::from_toml_str(&slow.resolved.to_toml_string(), NONE).unwrap();
    assert_eq!(back.config, slow.config);
    // With time.end too, the earlier ends the run.
    let both = MINIMAL.replace("end = 1e-3", "end = 1e-3\ntravel = 2e-4");
    let r = Scene::from_toml_str(&both, NONE).unwrap();
    assert!((r.config.time.end_s / 2e-4 - 1.0).abs() < 1e-15);
    let r = r.with_overrides(&["time.travel=1"]).unwrap();
    assert_eq!(r.config.time.end_s, 1e-3);
    // A drive that does not advance, or an end beyond the doubles, names time.travel with the
    // value the user gave, not a derived time.end = inf.
    let e = Scene::from_toml_str(&travel, &["drive.velocity=0"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("time.travel = 2e-4"), "{e}");
    assert!(!e.contains("time.end = inf"), "{e}");
    // Neither given: time.end is missing, and the message offers time.travel.
    let neither = MINIMAL.replace("end = 1e-3", "");
    let e = Scene::from_toml_str(&neither, NONE)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`time.end`") && e.contains("time.travel"), "{e}");
}

#[test]
fn a_default_the_user_never_gave_is_named_as_one_with_the_key_that_broke_it() {
    // time.end = 1e10 s: the default series interval is too fine for it; the message says it
    // is the default and names time.end.
    let e = Scene::from_toml_str(MINIMAL, &["time.end=1e10"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("output.series_interval = 1e-7 (its default)"),
        "{e}"
    );
    assert!(e.contains("or a shorter time.end (now 1e10 s)"), "{e}");
}
