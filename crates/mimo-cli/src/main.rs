//! The `mimo` binary: a thin shell over [`mimo_cli::run`], mapping errors to exit codes
//! (0 success, 2 bad input or usage, 1 any other failure).

fn main() {
    std::process::exit(mimo_cli::main_with_args(std::env::args_os()));
}
