//! A `junta` that also knows the `bimodular_penalty` law of `law.rs`.
mod law;
fn main() -> std::process::ExitCode {
    junta_cli::main()
}
