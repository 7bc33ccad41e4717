//! With the `petsc` feature: compile `src/shim.c` against the installed
//! PETSc and MPI headers (found by `pkg-config PETSc` and `mpicc
//! --showme`), and link both. Without it: nothing.

use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=src/shim.c");
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_PETSC").is_none() {
        return;
    }
    let petsc_cflags = tool_output("pkg-config", &["--cflags", "PETSc"]);
    let petsc_libs = tool_output("pkg-config", &["--libs", "PETSc"]);
    let mpi_compile = tool_output("mpicc", &["--showme:compile"]);
    let mpi_link = tool_output("mpicc", &["--showme:link"]);
    let mut build = cc::Build::new();
    build.file("src/shim.c").warnings(false);
    for flag in petsc_cflags
        .split_whitespace()
        .chain(mpi_compile.split_whitespace())
    {
        if let Some(dir) = flag.strip_prefix("-I") {
            build.include(dir);
        }
    }
    build.compile("junta_shim");
    for flag in petsc_libs
        .split_whitespace()
        .chain(mpi_link.split_whitespace())
    {
        if let Some(dir) = flag.strip_prefix("-L") {
            println!("cargo:rustc-link-search=native={dir}");
            println!("cargo:rustc-link-arg=-Wl,-rpath,{dir}");
        } else if let Some(lib) = flag.strip_prefix("-l") {
            println!("cargo:rustc-link-lib=dylib={lib}");
        }
    }
}

/// The standard output of `program args`, or a build failure that says
/// which Debian packages provide it.
fn tool_output(program: &str, args: &[&str]) -> String {
    match Command::new(program).args(args).output() {
        Ok(out) if out.status.success() => String::from_utf8_lossy(&out.stdout).into_owned(),
        _ => panic!(
            "junta-mpi (feature `petsc`): `{program} {}` failed; install PETSc and OpenMPI: \
             apt-get install petsc-dev libopenmpi-dev openmpi-bin pkg-config",
            args.join(" ")
        ),
    }
}
