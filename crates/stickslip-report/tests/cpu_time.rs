//! A process's CPU time as `binary::invoke` measures it (the bench's CPU column): a busy
//! shell loop's CPU time is positive and no larger than its wall time on the cores there are,
//! and an idle process's is far below its wall time. One test in its own binary, so that no
//! other invocation overlaps it (an overlapped one reports none).

use std::path::Path;
use stickslip_report::binary::invoke;

#[test]
fn cpu_time_follows_the_work_not_the_wall_clock() {
    let sh = Path::new("/bin/sh");
    let busy = invoke(
        sh,
        &[
            "-c".into(),
            "i=0; while [ $i -lt 300000 ]; do i=$((i+1)); done".into(),
        ],
        &[],
    )
    .expect("sh runs");
    assert!(busy.ok());
    let cpu = busy.cpu_s.expect("measured when alone");
    let cores = std::thread::available_parallelism().map_or(1, usize::from) as f64;
    assert!(cpu > 0.02, "busy loop: {cpu} s CPU in {} s", busy.wall_s);
    assert!(
        cpu <= cores * busy.wall_s + 0.01,
        "{cpu} s CPU in {} s",
        busy.wall_s
    );
    let idle = invoke(sh, &["-c".into(), "sleep 0.3".into()], &[]).expect("sh runs");
    let cpu = idle.cpu_s.expect("measured when alone");
    assert!(
        idle.wall_s >= 0.3 && cpu < 0.1,
        "sleep: {cpu} s CPU in {} s",
        idle.wall_s
    );
}
