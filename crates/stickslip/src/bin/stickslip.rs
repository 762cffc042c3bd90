//! The `stickslip` binary: the program is the library's (`lib.rs`), run with this process's
//! arguments.

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(stickslip::main_from(std::env::args_os()))
}
