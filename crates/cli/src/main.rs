//! The `junta` binary: the whole command line is in the `junta_cli` library.

fn main() -> std::process::ExitCode {
    junta_cli::main()
}
