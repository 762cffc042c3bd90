//! The `stickslip` command line (run, check, resume); the engine arrives with the scenes issue.

fn main() {
    eprintln!("stickslip: the simulation engine and scene files are not built yet (see README.md)");
    std::process::exit(2);
}
