//! The C functions of `shim.c` (plain C types only; a system is an opaque
//! pointer). Every function but the process ones returns a PETSc error
//! code, 0 on success.

use std::ffi::{c_char, c_int, c_void};

/// PETSc's `PetscInt` in the Debian build: 32 bits.
pub type PetscInt = i32;

extern "C" {
    pub fn junta_init() -> c_int;
    pub fn junta_finalize() -> c_int;
    pub fn junta_rank() -> c_int;
    pub fn junta_size() -> c_int;
    pub fn junta_abort(code: c_int);
    pub fn junta_error_text(code: c_int) -> *const c_char;
    pub fn junta_sum(v: *mut f64, n: i64) -> c_int;
    pub fn junta_max(v: *mut f64, n: i64) -> c_int;
    pub fn junta_min_u64(v: *mut u64, n: i64) -> c_int;
    pub fn junta_any(flag: c_int, any: *mut c_int) -> c_int;
    pub fn junta_bcast(data: *mut c_void, bytes: i64, root: c_int) -> c_int;
    pub fn junta_alltoall_counts(send: *const i64, received: *mut i64) -> c_int;
    pub fn junta_alltoallv_bytes(
        send: *const c_void,
        send_bytes: *const i64,
        received: *mut c_void,
        received_bytes: *const i64,
    ) -> c_int;
    pub fn junta_insert_options(text: *const c_char) -> c_int;
    pub fn junta_has_option(name: *const c_char, set: *mut c_int) -> c_int;
    pub fn junta_set_option(name: *const c_char, value: *const c_char) -> c_int;
    pub fn junta_system_create(
        nlocal: PetscInt,
        n: PetscInt,
        row_ptr: *const PetscInt,
        columns: *const PetscInt,
        out: *mut *mut c_void,
    ) -> c_int;
    pub fn junta_system_solver(
        s: *mut c_void,
        ksp_type: *const c_char,
        pc_type: *const c_char,
        package: *const c_char,
        rtol: f64,
        max_it: PetscInt,
    ) -> c_int;
    pub fn junta_system_near_null_space(s: *mut c_void, nvec: PetscInt, local: *const f64)
        -> c_int;
    pub fn junta_system_values(s: *mut c_void, values: *const f64, symmetric: c_int) -> c_int;
    pub fn junta_system_setup(s: *mut c_void, failed: *mut c_int) -> c_int;
    pub fn junta_system_inertia(
        s: *mut c_void,
        neg: *mut PetscInt,
        zero: *mut PetscInt,
        pos: *mut PetscInt,
    ) -> c_int;
    pub fn junta_system_solve(
        s: *mut c_void,
        b_local: *const f64,
        x_all: *mut f64,
        reason: *mut c_int,
        its: *mut PetscInt,
        rnorm: *mut f64,
    ) -> c_int;
    pub fn junta_system_describe(s: *mut c_void, buf: *mut c_char, len: usize) -> c_int;
    pub fn junta_system_destroy(s: *mut c_void) -> c_int;
}

/// The text of a PETSc error code.
pub fn error_text(code: c_int) -> String {
    // SAFETY: the shim returns a static C string.
    unsafe { std::ffi::CStr::from_ptr(junta_error_text(code)) }
        .to_string_lossy()
        .into_owned()
}
