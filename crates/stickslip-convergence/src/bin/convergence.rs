//! `convergence`: the full convergence study (same as `cargo xtask convergence`).

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    stickslip_convergence::run_convergence_cli(&args)
}
