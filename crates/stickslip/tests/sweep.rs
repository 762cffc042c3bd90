//! `stickslip sweep`: bad sweep files exit 2 naming the key and write nothing; results do not
//! depend on jobs or shards; a killed sweep reruns only its missing points and ends with the
//! same map; failed and refused points are rows, and the exit status says so.

use crate::common;

use common::{bin, run, texts};
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};
use stickslip_studies::sweep::map::MapTable;

/// A small sweep over the rigid drive: 3 speeds × 3 values of A0, N = 20, six events.
fn sweep_text(scene: &Path, extra_axis: &str) -> String {
    format!(
        r#"name = "small"
scene = "{}"
[set]
"contact.nodes" = 20
"time.max_events" = 6
"time.max_open_event" = 2e-5
"time.end" = 1e-3
[[axis]]
key = "drive.velocity"
range = {{ from = 0.01, to = 1.0, count = 3, scale = "log" }}
[[axis]]
key = "temperature.A0"
values = [-1e5, 5e5, 1.5e6]
{extra_axis}"#,
        scene.display()
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn sweep(args: &[&str]) -> std::process::Output {
    let mut all = vec!["sweep"];
    all.extend_from_slice(args);
    run(&all)
}

/// map.csv without the wall_s column.
fn map_without_wall(dir: &Path) -> Vec<String> {
    let table = MapTable::read(dir).unwrap();
    let header = table.header();
    let wall = header.iter().position(|h| h == "wall_s").unwrap();
    table
        .to_csv()
        .lines()
        .map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells.remove(wall);
            cells.join(",")
        })
        .collect()
}

#[test]
fn results_do_not_depend_on_jobs_or_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write(
        tmp.path(),
        "s.toml",
        &sweep_text(&common::scene("rigid"), ""),
    );
    let f = file.to_str().unwrap();
    let one = tmp.path().join("one");
    let out = sweep(&[
        "run",
        f,
        "--out",
        one.to_str().unwrap(),
        "--jobs",
        "1",
        "--quiet",
    ]);
    assert!(out.status.success(), "{}", texts(&out).1);
    let two = tmp.path().join("two");
    let out = sweep(&[
        "run",
        f,
        "--out",
        two.to_str().unwrap(),
        "--jobs",
        "2",
        "--quiet",
    ]);
    assert!(out.status.success(), "{}", texts(&out).1);
    let sharded = tmp.path().join("sharded");
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = sweep(&[
            "run",
            f,
            "--out",
            sharded.to_str().unwrap(),
            "--shard",
            &shard,
            "--quiet",
        ]);
        assert!(out.status.success(), "{}", texts(&out).1);
        let done = sharded.join("map.csv").exists();
        assert_eq!(done, i == 2, "map.csv appears with the last shard");
    }
    let merged = sweep(&["merge", sharded.to_str().unwrap()]);
    assert!(merged.status.success(), "{}", texts(&merged).1);
    let reference = map_without_wall(&one);
    assert_eq!(reference.len(), 10);
    assert_eq!(map_without_wall(&two), reference);
    assert_eq!(map_without_wall(&sharded), reference);
    let table = MapTable::read(&one).unwrap();
    // A0 < 0: sliding; the slow drive at full A0: stick-slip.
    assert_eq!(table.rows[0].summary.regime.name(), "sliding");
    assert_eq!(table.rows[2].summary.regime.name(), "stick_slip");
    let plotted = sweep(&["plot", one.to_str().unwrap(), "--quantity", "period_last"]);
    assert!(plotted.status.success(), "{}", texts(&plotted).1);
    let svg = std::fs::read_to_string(one.join("map_period_last.svg")).unwrap();
    assert!(svg.contains("stick_slip") && svg.contains("drive.velocity [m/s]"));
    // Every numeric column is a quantity (f_mean was refused once); a colour bar, no swatches.
    let plotted = sweep(&["plot", one.to_str().unwrap(), "--quantity", "f_mean"]);
    assert!(plotted.status.success(), "{}", texts(&plotted).1);
    let bogus = sweep(&["plot", one.to_str().unwrap(), "--quantity", "bogus"]);
    assert_eq!(bogus.status.code(), Some(2));
    assert!(texts(&bogus).1.contains("f_mean"), "{}", texts(&bogus).1);
    // An unfinished sweep plots from its point records, the missing points marked.
    let partial = tmp.path().join("partial");
    copy_dir(&one, &partial);
    for f in ["map.csv", "map.json"] {
        std::fs::remove_file(partial.join(f)).unwrap();
    }
    let _ = std::fs::remove_dir_all(partial.join("shards"));
    std::fs::remove_file(partial.join("points").join("0000001.json")).unwrap();
    let plotted = sweep(&["plot", partial.to_str().unwrap()]);
    assert!(plotted.status.success(), "{}", texts(&plotted).1);
    assert!(
        texts(&plotted).0.contains("8 of 9 points so far"),
        "{}",
        texts(&plotted).0
    );
    let svg = std::fs::read_to_string(partial.join("map_recovery.svg")).unwrap();
    assert!(svg.contains("not run yet (1)") && svg.contains("partial, 8 of 9 points"));
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

#[test]
fn a_killed_sweep_reruns_only_missing_or_damaged_points_and_ends_with_the_same_map() {
    let tmp = tempfile::tempdir().unwrap();
    // More points (a third axis), so the kill lands mid-way.
    let axis =
        "[[axis]]\nkey = \"contact.film_thickness\"\nvalues = [8e-8, 1e-7, 1.2e-7, 1.4e-7]\n";
    let file = write(
        tmp.path(),
        "s.toml",
        &sweep_text(&common::scene("rigid"), axis),
    );
    let f = file.to_str().unwrap();
    let reference = tmp.path().join("reference");
    let out = sweep(&[
        "run",
        f,
        "--out",
        reference.to_str().unwrap(),
        "--jobs",
        "2",
        "--quiet",
    ]);
    assert!(out.status.success(), "{}", texts(&out).1);
    let dir = tmp.path().join("killed");
    let mut child = bin()
        .args([
            "sweep",
            "run",
            f,
            "--out",
            dir.to_str().unwrap(),
            "--jobs",
            "1",
            "--quiet",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let points = dir.join("points");
    // Finished records (a killed write leaves only a hidden temporary file).
    let records = |p: &Path| {
        std::fs::read_dir(p).map_or(0, |d| {
            d.filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| !e.file_name().to_string_lossy().starts_with('.'))
            })
            .count()
        })
    };
    let start = Instant::now();
    while records(&points) < 5 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no points written"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done = records(&points);
    assert!(
        done < 36,
        "the sweep finished before the kill ({done} points)"
    );
    assert!(!dir.join("map.csv").exists());
    // Records are written unsynced: a power loss may leave one cut short or empty. Such a
    // record counts as not finished, and its point runs again.
    let mut finished: Vec<PathBuf> = std::fs::read_dir(&points)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
        .collect();
    finished.sort();
    let cut = std::fs::read(&finished[0]).unwrap();
    std::fs::write(&finished[0], &cut[..cut.len() / 2]).unwrap();
    std::fs::write(&finished[1], b"").unwrap();
    let rerun = sweep(&[
        "run",
        f,
        "--out",
        dir.to_str().unwrap(),
        "--jobs",
        "2",
        "--quiet",
    ]);
    let stdout = texts(&rerun).0;
    assert!(rerun.status.success(), "{}", texts(&rerun).1);
    assert!(
        stdout.contains(&format!("{} already done", done - 2)),
        "{stdout}"
    );
    assert_eq!(map_without_wall(&dir), map_without_wall(&reference));
}

#[test]
fn failed_and_refused_points_are_rows_and_exit_4() {
    let tmp = tempfile::tempdir().unwrap();
    // The literal scheme: a soft substrate is refused (lagged sweep diverges), a stiff film
    // kinetics makes explicit Euler fail; the rest runs.
    let text = format!(
        r#"name = "literal"
scene = "{}"
[set]
"contact.nodes" = 20
"time.scheme" = "literal"
"time.end" = 2e-6
"output.profile_times" = [2e-6]
[[axis]]
key = "contact.g_eff"
values = [1e8, 1e9]
[[axis]]
key = "lubricant.gamma"
values = [10.0, 1e5]
"#,
        common::scene("fig2").display()
    );
    let file = write(tmp.path(), "s.toml", &text);
    let dir = tmp.path().join("out");
    let out = sweep(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
    ]);
    let (stdout, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(4), "{stdout}{stderr}");
    assert!(
        stderr.contains("3 points failed or were refused"),
        "{stderr}"
    );
    let table = MapTable::read(&dir).unwrap();
    let statuses: Vec<&str> = table.rows.iter().map(|r| r.status.name()).collect();
    assert_eq!(statuses, ["refused", "refused", "ok", "failed"]);
    assert!(
        table.rows[0]
            .message
            .contains("lagged-sweep contraction factor")
    );
    assert!(table.rows[3].message.contains("explicit Euler"));
}

struct Bad {
    name: &'static str,
    /// Replaces the axes and [set] of a valid sweep file (the scene line is prepended).
    body: &'static str,
    /// The key the message must name.
    key: &'static str,
    args: &'static [&'static str],
}

const BAD: &[Bad] = &[
    Bad {
        name: "verify sample 0",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[verify]\nsample = 0.0\n",
        key: "verify.sample",
        args: &[],
    },
    Bad {
        name: "verify sample and points",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[verify]\nsample = 0.5\npoints = 3\n",
        key: "verify.points",
        args: &[],
    },
    Bad {
        name: "verify points 0",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[verify]\npoints = 0\n",
        key: "verify.points",
        args: &[],
    },
    Bad {
        name: "verify nothing to check",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[verify]\nboundaries = false\n",
        key: "verify.boundaries",
        args: &[],
    },
    Bad {
        name: "verify unknown key",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[verify]\nfraction = 0.1\n",
        key: "verify.fraction",
        args: &[],
    },
    Bad {
        name: "unknown key in an axis",
        body: "[[axis]]\nkey = \"drive.speed\"\nvalues = [1.0]\n",
        key: "axis[0].key",
        args: &[],
    },
    Bad {
        name: "empty values",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = []\n",
        key: "axis[0].values",
        args: &[],
    },
    Bad {
        name: "count < 1",
        body: "[[axis]]\nkey = \"drive.velocity\"\nrange = { from = 1, to = 2, count = 0 }\n",
        key: "axis[0].range.count",
        args: &[],
    },
    Bad {
        name: "log scale with a bound <= 0",
        body: "[[axis]]\nkey = \"temperature.A0\"\nrange = { from = -1, to = 2, count = 3, scale = \"log\" }\n",
        key: "axis[0].range",
        args: &[],
    },
    Bad {
        name: "unknown scale",
        body: "[[axis]]\nkey = \"drive.velocity\"\nrange = { from = 1, to = 2, count = 3, scale = \"cubic\" }\n",
        key: "axis[0].range.scale",
        args: &[],
    },
    Bad {
        name: "duplicate axis",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [2.0]\n",
        key: "axis[1].key",
        args: &[],
    },
    Bad {
        name: "values and range",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\nrange = { from = 1, to = 2, count = 3 }\n",
        key: "axis[0] (drive.velocity)",
        args: &[],
    },
    Bad {
        name: "no axis",
        body: "",
        key: "axis",
        args: &[],
    },
    Bad {
        name: "axis without key",
        body: "[[axis]]\nvalues = [1.0]\n",
        key: "axis[0].key",
        args: &[],
    },
    Bad {
        name: "value outside the key's range",
        body: "[[axis]]\nkey = \"contact.radius\"\nvalues = [2e-5, -1.0]\n",
        key: "contact.radius",
        args: &[],
    },
    Bad {
        name: "word axis with a bad word",
        body: "[[axis]]\nkey = \"contact.model\"\nvalues = [\"radial\", \"flat\"]\n",
        key: "axis[0].values",
        args: &[],
    },
    Bad {
        name: "range over a word key",
        body: "[[axis]]\nkey = \"contact.model\"\nrange = { from = 1, to = 2, count = 2 }\n",
        key: "axis[0].range",
        args: &[],
    },
    Bad {
        name: "unknown key in [set]",
        body: "[set]\n\"contact.nodez\" = 10\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "set.\"contact.nodez\"",
        args: &[],
    },
    Bad {
        name: "a base scene that is itself invalid",
        body: "[set]\n\"contact.nodes\" = 0\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "contact.nodes",
        args: &[],
    },
    Bad {
        name: "axis also fixed by [set]",
        body: "[set]\n\"drive.velocity\" = 1.0\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "axis[0].key",
        args: &[],
    },
    Bad {
        name: "too many points without --allow-large",
        body: "[[axis]]\nkey = \"drive.velocity\"\nrange = { from = 1, to = 2, count = 400 }\n[[axis]]\nkey = \"temperature.A0\"\nrange = { from = 1e6, to = 2e6, count = 400 }\n",
        key: "axis",
        args: &[],
    },
    Bad {
        name: "unknown top-level key",
        body: "speed = 3\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "speed",
        args: &[],
    },
    Bad {
        name: "bad regime threshold",
        body: "[regime]\nstick_slip_recovery = 2.0\n[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "regime.stick_slip_recovery",
        args: &[],
    },
    Bad {
        name: "refine: negative levels",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = -1\n",
        key: "refine.levels",
        args: &[],
    },
    Bad {
        name: "refine: non-integer levels",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2.5\n",
        key: "refine.levels",
        args: &[],
    },
    Bad {
        name: "refine: too many levels",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 99\n",
        key: "refine.levels",
        args: &[],
    },
    Bad {
        name: "refine: unknown column",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2\non = \"speed\"\nthreshold = 0.1\n",
        key: "refine.on",
        args: &[],
    },
    Bad {
        name: "refine: non-numeric column",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2\non = \"message\"\nthreshold = 0.1\n",
        key: "refine.on",
        args: &[],
    },
    Bad {
        name: "refine: threshold <= 0",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2\non = \"recovery\"\nthreshold = -0.1\n",
        key: "refine.threshold",
        args: &[],
    },
    Bad {
        name: "refine: threshold missing",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2\non = \"recovery\"\n",
        key: "refine.threshold",
        args: &[],
    },
    Bad {
        name: "refine: unknown key",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0, 2.0]\n[refine]\nlevels = 2\nlevel = 3\n",
        key: "refine.level",
        args: &[],
    },
    Bad {
        name: "refine: a word axis",
        body: "[[axis]]\nkey = \"contact.model\"\nvalues = [\"radial\", \"homogeneous\"]\n[refine]\nlevels = 1\n",
        key: "refine",
        args: &[],
    },
    Bad {
        name: "a bad shard",
        body: "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n",
        key: "3/2",
        args: &["--shard", "3/2"],
    },
];

#[test]
fn bad_sweep_messages_say_the_value_and_what_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    let axis = "[[axis]]\nkey = \"drive.velocity\"\nvalues = [1.0]\n";
    let cases: [(&str, String, &[&str], &[&str]); 4] = [
        (
            "a float axis from = to",
            "[[axis]]\nkey = \"drive.velocity\"\nrange = { from = 1e-2, to = 1e-2, count = 3 }\n"
                .to_string(),
            &[
                "axis[0].range.count = 3",
                "gives 1e-2 twice",
                "bounds that differ",
            ],
            &["integers"],
        ),
        (
            "a bad regime threshold",
            format!("[regime]\nstick_slip_recovery = 2.0\n{axis}"),
            &[
                "regime.stick_slip_recovery = 2 ",
                "within [regime.smooth_recovery = ",
            ],
            &["(given)"],
        ),
        (
            "a date as the name",
            format!("name = 1979-05-27\n{axis}"),
            &["name = 1979-05-27", "a string"],
            &[],
        ),
        (
            "an axis of more values than allowed",
            "[[axis]]\nkey = \"drive.velocity\"\nrange = { from = 1, to = 2, count = 100001 }\n"
                .to_string(),
            &["at most 100000 values per axis"],
            &[],
        ),
    ];
    for (i, (what, body, has, lacks)) in cases.iter().enumerate() {
        let name = if body.starts_with("name") {
            ""
        } else {
            "name = \"bad\"\n"
        };
        let text = format!(
            "{name}scene = \"{}\"\n{body}",
            common::scene("rigid").display()
        );
        let file = write(tmp.path(), &format!("msg{i}.toml"), &text);
        let dir = tmp.path().join(format!("msg{i}"));
        let args = [
            "run",
            file.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
            "--allow-large",
        ];
        let out = sweep(&args);
        let stderr = texts(&out).1;
        assert_eq!(out.status.code(), Some(2), "{what}: {stderr}");
        for h in *has {
            assert!(stderr.contains(h), "{what}: lacks {h:?}: {stderr}");
        }
        for l in *lacks {
            assert!(!stderr.contains(l), "{what}: says {l:?}: {stderr}");
        }
    }
}

#[test]
fn bad_sweep_files_exit_2_name_the_key_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (i, case) in BAD.iter().enumerate() {
        let text = format!(
            "name = \"bad\"\nscene = \"{}\"\n{}",
            common::scene("rigid").display(),
            case.body
        );
        let file = write(tmp.path(), &format!("bad{i}.toml"), &text);
        let dir = tmp.path().join(format!("out{i}"));
        let mut args = vec![
            "run",
            file.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
            "--quiet",
        ];
        args.extend_from_slice(case.args);
        let out = sweep(&args);
        let stderr = texts(&out).1;
        if out.status.code() != Some(2) {
            failures.push(format!(
                "{}: exit {:?}: {stderr}",
                case.name,
                out.status.code()
            ));
        } else if !stderr.contains(case.key) {
            failures.push(format!(
                "{}: message lacks {:?}: {stderr}",
                case.name, case.key
            ));
        } else if dir.exists() {
            failures.push(format!("{}: wrote {}", case.name, dir.display()));
        }
    }
    assert!(BAD.len() >= 24);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `stickslip sweep slurm FILE --out DIR --tasks TASKS ARG`.
fn slurm(file: &Path, dir: &Path, tasks: &str, arg: &str) -> std::process::Output {
    sweep(&[
        "slurm",
        file.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--tasks",
        tasks,
        arg,
    ])
}

#[test]
fn slurm_writes_a_job_array_script() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write(
        tmp.path(),
        "s.toml",
        &sweep_text(&common::scene("rigid"), ""),
    );
    let dir = tmp.path().join("out");
    let out = slurm(&file, &dir, "4", "--sbatch-arg=--time=00:10:00");
    assert!(out.status.success(), "{}", texts(&out).1);
    let script = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=0-3"), "{script}");
    assert!(script.contains("#SBATCH --time=00:10:00"), "{script}");
    assert!(
        script.contains("--shard \"${SLURM_ARRAY_TASK_ID}/4\""),
        "{script}"
    );
}

#[test]
fn slurm_refuses_an_sbatch_arg_that_would_inject_a_line_and_quotes_one_with_spaces() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write(
        tmp.path(),
        "s.toml",
        &sweep_text(&common::scene("rigid"), ""),
    );
    for bad in [
        "--x\n#SBATCH --evil\necho injected",
        "--comment=a\rb",
        "--comment=\"q\"",
        "",
    ] {
        let dir = tmp.path().join("bad");
        let out = slurm(&file, &dir, "2", &format!("--sbatch-arg={bad}"));
        let stderr = texts(&out).1;
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {stderr}");
        assert!(stderr.contains("--sbatch-arg"), "{stderr}");
        assert!(!dir.exists(), "{bad:?}: wrote {}", dir.display());
    }
    let dir = tmp.path().join("ok");
    let out = slurm(&file, &dir, "2", "--sbatch-arg=--comment=two words");
    assert!(out.status.success(), "{}", texts(&out).1);
    let script = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    assert!(
        script.contains("#SBATCH \"--comment=two words\"\n"),
        "{script}"
    );
}

/// A refined sweep over the rigid drive: 3 × 3 base points (velocity × A0), 3 levels.
fn refined_text(scene: &Path) -> String {
    format!(
        r#"name = "refined"
scene = "{}"
[set]
"contact.nodes" = 20
"time.max_events" = 6
"time.max_open_event" = 2e-5
"time.end" = 1e-3
[[axis]]
key = "drive.velocity"
range = {{ from = 1e-3, to = 1e-2, count = 3, scale = "log" }}
[[axis]]
key = "temperature.A0"
range = {{ from = -2e5, to = 1.4e6, count = 3 }}
[refine]
levels = 3
"#,
        scene.display()
    )
}

#[test]
fn a_refined_sweep_killed_or_sharded_ends_with_the_same_map_and_plots_its_cells() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write(tmp.path(), "r.toml", &refined_text(&common::scene("rigid")));
    let f = file.to_str().unwrap();
    let reference = tmp.path().join("reference");
    let out = sweep(&["run", f, "--out", reference.to_str().unwrap(), "--quiet"]);
    assert!(out.status.success(), "{}", texts(&out).1);
    let expected = map_without_wall(&reference);
    let table = MapTable::read(&reference).unwrap();
    assert!(table.header().iter().any(|h| h == "level"));
    assert!(table.rows.iter().any(|r| r.level == 3));
    // SIGKILLed at three instants (after 5, 25 and 45 finished points), rerun each time.
    let dir = tmp.path().join("killed");
    let records = |p: &Path| {
        std::fs::read_dir(p).map_or(0, |d| {
            d.filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| !e.file_name().to_string_lossy().starts_with('.'))
            })
            .count()
        })
    };
    let mut killed_at = Vec::new();
    for threshold in [5, 25, 45] {
        let mut child = bin()
            .args([
                "sweep",
                "run",
                f,
                "--out",
                dir.to_str().unwrap(),
                "--jobs",
                "1",
                "--quiet",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while records(&dir.join("points")) < threshold && child.try_wait().unwrap().is_none() {
            assert!(start.elapsed() < Duration::from_secs(60), "no progress");
            std::thread::sleep(Duration::from_millis(1));
        }
        child.kill().unwrap();
        child.wait().unwrap();
        killed_at.push(records(&dir.join("points")));
    }
    let rerun = sweep(&["run", f, "--out", dir.to_str().unwrap(), "--quiet"]);
    assert!(rerun.status.success(), "{}", texts(&rerun).1);
    assert_eq!(map_without_wall(&dir), expected, "killed at {killed_at:?}");
    println!("refined sweep killed with {killed_at:?} records written");
    // Three shards in rounds: a shard waits at a level whose other points are missing.
    let sharded = tmp.path().join("sharded");
    let mut waited = false;
    for _round in 0..5 {
        for i in 0..3 {
            let shard = format!("{i}/3");
            let out = sweep(&[
                "run",
                f,
                "--out",
                sharded.to_str().unwrap(),
                "--shard",
                &shard,
                "--quiet",
            ]);
            assert!(out.status.success(), "{}", texts(&out).1);
            waited |= texts(&out).0.contains("waits at level");
        }
        if sharded.join("map.csv").exists() {
            break;
        }
    }
    assert!(waited);
    assert_eq!(map_without_wall(&sharded), expected);
    // The plot: cells at their levels' sizes and the boundary.
    let plotted = sweep(&["plot", reference.to_str().unwrap()]);
    assert!(plotted.status.success(), "{}", texts(&plotted).1);
    let svg = std::fs::read_to_string(reference.join("map_recovery.svg")).unwrap();
    assert!(svg.contains("regime boundary"));
    // The Slurm script says it goes once per level.
    let slurm_dir = tmp.path().join("slurm");
    let out = sweep(&[
        "slurm",
        f,
        "--out",
        slurm_dir.to_str().unwrap(),
        "--tasks",
        "2",
    ]);
    assert!(out.status.success(), "{}", texts(&out).1);
    let script = std::fs::read_to_string(slurm_dir.join("sweep.sbatch")).unwrap();
    assert!(script.contains("submit this script 4 times"), "{script}");
    assert!(
        texts(&out).0.contains("--dependency=afterok"),
        "{}",
        texts(&out).0
    );
}
