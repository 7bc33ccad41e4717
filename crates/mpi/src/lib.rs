//! # junta-mpi
//!
//! Junta over MPI, on PETSc: the collective operations of the ranks
//! ([`collective::MpiCollective`], installed as
//! [`junta_core::distributed::collective`]), and the linear solver `petsc`
//! ([`petsc_solver::PetscSolver`]): PETSc's parallel AIJ matrix, assembled
//! from every rank's part of the tangent, solved by MUMPS (Cholesky or
//! LDL^T with its inertia, or LU), GAMG with the rigid-body near-null
//! space, or hypre BoomerAMG.
//!
//! The crate is empty unless built with its feature `petsc` (the `junta`
//! binary's feature `mpi` turns it on), so that the rest of Junta builds
//! and tests without MPI. With it, the build compiles `shim.c` against the
//! installed PETSc 3.18 and OpenMPI (Debian: `petsc-dev libopenmpi-dev
//! openmpi-bin pkg-config`).
//!
//! What is distributed and what is replicated is said in
//! [`junta_core::distributed`]: every rank reads the input and keeps the
//! mesh, the displacements and the states; the elements' work and the
//! linear solve are split among the ranks.

#![cfg(feature = "petsc")]
#![warn(missing_docs)]

pub mod collective;
#[allow(missing_docs)]
pub mod ffi;
mod owned_rows;
pub mod petsc_solver;

use std::ffi::CString;

/// A failure to start MPI and PETSc.
#[derive(Debug, thiserror::Error)]
pub enum MpiError {
    /// PetscInitialize (and MPI_Init) failed.
    #[error("cannot start MPI and PETSc (PetscInitialize returned {code}: {text})")]
    Init {
        /// The PETSc error code.
        code: i32,
        /// Its text.
        text: String,
    },
}

/// MPI and PETSc started for this process; finalised when dropped.
#[derive(Debug)]
pub struct Session {
    rank: usize,
    size: usize,
}

/// Whether this process was started by an MPI launcher (`mpirun`,
/// `mpiexec`, `srun` with PMI or PMIx): its environment names a rank.
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

impl Session {
    /// Start MPI and PETSc when this process was started by an MPI
    /// launcher ([`launched`]); `None` otherwise (the ordinary,
    /// single-process run). Installs the ranks' collective operations,
    /// sets MUMPS to report the inertia (`-mat_mumps_icntl_13 1
    /// -mat_mumps_icntl_24 1`, unless the user's PETSc options set them),
    /// and, unless `RAYON_NUM_THREADS` is set, gives each rank its share of
    /// the cores (the cores over the ranks on this node).
    pub fn start_if_launched() -> Result<Option<Session>, MpiError> {
        if !launched() {
            return Ok(None);
        }
        share_cores();
        // SAFETY: called once, from the main thread, before any MPI use.
        let code = unsafe { ffi::junta_init() };
        if code != 0 {
            return Err(MpiError::Init {
                code,
                text: ffi::error_text(code),
            });
        }
        for name in ["-mat_mumps_icntl_13", "-mat_mumps_icntl_24"] {
            set_default_option(name, "1");
        }
        let c = collective::MpiCollective::world();
        let session = Session {
            rank: junta_core::distributed::Collective::rank(&c),
            size: junta_core::distributed::Collective::size(&c),
        };
        junta_core::distributed::install(Box::new(c));
        Ok(Some(session))
    }

    /// This process's rank.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Number of ranks.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether this is rank 0, the one that writes the outputs.
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        // SAFETY: PETSc was initialised by start_if_launched.
        unsafe { ffi::junta_finalize() };
    }
}

/// Set a PETSc option unless the user's options already name it.
pub(crate) fn set_default_option(name: &str, value: &str) {
    let (Ok(n), Ok(v)) = (CString::new(name), CString::new(value)) else {
        return;
    };
    let mut set = 0;
    // SAFETY: valid C strings; PETSc initialised.
    unsafe {
        if ffi::junta_has_option(n.as_ptr(), &mut set) == 0 && set == 0 {
            ffi::junta_set_option(n.as_ptr(), v.as_ptr());
        }
    }
}

/// Give this rank `cores / ranks on this node` rayon threads (at least
/// one), unless `RAYON_NUM_THREADS` is set: ranks x threads must not
/// oversubscribe the cores.
fn share_cores() {
    if std::env::var_os("RAYON_NUM_THREADS").is_some() {
        return;
    }
    let local = [
        "OMPI_COMM_WORLD_LOCAL_SIZE",
        "MPI_LOCALNRANKS",
        "SLURM_NTASKS_PER_NODE",
    ]
    .iter()
    .find_map(|v| std::env::var(v).ok()?.parse::<usize>().ok())
    .unwrap_or(1)
    .max(1);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::env::set_var("RAYON_NUM_THREADS", (cores / local).max(1).to_string());
}

/// End every rank of the run: print `message` with this rank's number and
/// call `MPI_Abort`, which stops all ranks (none is left waiting).
pub fn abort_all(message: &str) -> ! {
    let (rank, size) = match junta_core::distributed::collective() {
        Some(c) => (c.rank(), c.size()),
        None => (0, 1),
    };
    eprintln!("error (rank {rank} of {size}): {message}");
    // SAFETY: ends the process (and the others).
    unsafe { ffi::junta_abort(1) };
    std::process::exit(1)
}
