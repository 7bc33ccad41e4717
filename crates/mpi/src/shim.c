/*
 * The C side of junta-mpi: what Rust cannot take from PETSc's and MPI's
 * headers without a binding generator (the communicator, enums, macros such
 * as MATAIJ, PETSC_DEFAULT), wrapped in functions of plain C types. Every
 * function returns a PetscErrorCode (0: success); the Rust side turns a
 * non-zero code into a typed error with junta_error_text().
 *
 * A "system" is one linear system distributed over PETSC_COMM_WORLD: the
 * parallel AIJ matrix (rows owned in contiguous ranges, each rank giving
 * its own rows in CSR form, summed beforehand: owned_rows.rs), its solver (KSP and PC), a
 * right-hand side, a solution, and the scatter that gives every rank the
 * whole solution.
 */
#include <petscksp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  Mat A;
  KSP ksp;
  Vec b, x, xall;
  VecScatter toall;
  PetscInt nlocal, n;
} junta_system;

int junta_init(void) {
  int argc = 0;
  char **argv = NULL;
  PetscErrorCode ierr = PetscInitialize(&argc, &argv, NULL, NULL);
  if (ierr) return ierr;
  /* errors come back as codes, without PETSc's traceback on stderr */
  return PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
}

int junta_finalize(void) { return PetscFinalize(); }

int junta_rank(void) {
  PetscMPIInt r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int junta_size(void) {
  PetscMPIInt s = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &s);
  return s;
}

void junta_abort(int code) { MPI_Abort(PETSC_COMM_WORLD, code); }

const char *junta_error_text(int code) {
  const char *text = NULL;
  if (PetscErrorMessage(code, &text, NULL) || !text) return "unknown PETSc error";
  return text;
}

/* MPI counts are int: long arrays go in chunks */
#define CHUNK (1 << 28)

/* Sum over the ranks, identical on every rank: reduce to rank 0 (one fixed
 * order), then broadcast. */
int junta_sum(double *v, int64_t n) {
  int rank = junta_rank();
  for (int64_t s = 0; s < n; s += CHUNK) {
    int c = (int)((n - s) < CHUNK ? (n - s) : CHUNK);
    int e = rank == 0 ? MPI_Reduce(MPI_IN_PLACE, v + s, c, MPI_DOUBLE, MPI_SUM, 0, PETSC_COMM_WORLD)
                      : MPI_Reduce(v + s, NULL, c, MPI_DOUBLE, MPI_SUM, 0, PETSC_COMM_WORLD);
    if (e) return e;
    e = MPI_Bcast(v + s, c, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    if (e) return e;
  }
  return 0;
}

int junta_max(double *v, int64_t n) {
  for (int64_t s = 0; s < n; s += CHUNK) {
    int c = (int)((n - s) < CHUNK ? (n - s) : CHUNK);
    int e = MPI_Allreduce(MPI_IN_PLACE, v + s, c, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    if (e) return e;
  }
  return 0;
}

int junta_min_u64(uint64_t *v, int64_t n) {
  for (int64_t s = 0; s < n; s += CHUNK) {
    int c = (int)((n - s) < CHUNK ? (n - s) : CHUNK);
    int e = MPI_Allreduce(MPI_IN_PLACE, v + s, c, MPI_UINT64_T, MPI_MIN, PETSC_COMM_WORLD);
    if (e) return e;
  }
  return 0;
}

int junta_any(int flag, int *any) {
  *any = flag;
  return MPI_Allreduce(MPI_IN_PLACE, any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
}

int junta_bcast(void *data, int64_t bytes, int root) {
  for (int64_t s = 0; s < bytes; s += CHUNK) {
    int c = (int)((bytes - s) < CHUNK ? (bytes - s) : CHUNK);
    int e = MPI_Bcast((char *)data + s, c, MPI_BYTE, root, PETSC_COMM_WORLD);
    if (e) return e;
  }
  return 0;
}

/* Each rank sends send_bytes[r] bytes of send (in rank order) to rank r and
 * receives received_bytes[r] from it (the counts exchanged first by
 * junta_alltoall_counts); the totals fit an int (checked by the caller). */
int junta_alltoall_counts(const int64_t *send, int64_t *received) {
  return MPI_Alltoall(send, 1, MPI_INT64_T, received, 1, MPI_INT64_T, PETSC_COMM_WORLD);
}

int junta_alltoallv_bytes(const void *send, const int64_t *send_bytes, void *received,
                          const int64_t *received_bytes) {
  int size = junta_size(), e;
  int *counts = malloc(4 * (size_t)size * sizeof(int));
  if (!counts) return MPI_ERR_NO_MEM;
  int *sc = counts, *sd = counts + size, *rc = counts + 2 * size, *rd = counts + 3 * size;
  for (int r = 0, so = 0, ro = 0; r < size; r++) {
    sc[r] = (int)send_bytes[r];
    rc[r] = (int)received_bytes[r];
    sd[r] = so;
    rd[r] = ro;
    so += sc[r];
    ro += rc[r];
  }
  e = MPI_Alltoallv(send, sc, sd, MPI_BYTE, received, rc, rd, MPI_BYTE, PETSC_COMM_WORLD);
  free(counts);
  return e;
}

/* PETSc options: a string such as "-ksp_monitor -pc_gamg_threshold 0.02" */
int junta_insert_options(const char *text) { return PetscOptionsInsertString(NULL, text); }

int junta_has_option(const char *name, int *set) {
  PetscBool b = PETSC_FALSE;
  PetscErrorCode ierr = PetscOptionsHasName(NULL, NULL, name, &b);
  *set = b ? 1 : 0;
  return ierr;
}

int junta_set_option(const char *name, const char *value) {
  return PetscOptionsSetValue(NULL, name, value);
}

/* The matrix (nlocal of n rows here) from the CSR pattern of this rank's
 * rows (global 0-based columns, sorted within each row; values zero) and
 * its vectors. The scatter to every rank comes with the first solve, after
 * the preconditioner's set-up, whose memory peaks. */
int junta_system_create(PetscInt nlocal, PetscInt n, const PetscInt *row_ptr,
                        const PetscInt *columns, junta_system **out) {
  junta_system *s;
  PetscCall(PetscCalloc1(1, &s));
  s->nlocal = nlocal;
  s->n = n;
  PetscCall(MatCreateMPIAIJWithArrays(PETSC_COMM_WORLD, nlocal, nlocal, n, n, row_ptr, columns,
                                      NULL, &s->A));
  PetscCall(MatCreateVecs(s->A, &s->x, &s->b));
  PetscCall(KSPCreate(PETSC_COMM_WORLD, &s->ksp));
  *out = s;
  return 0;
}

/* The solver: ksp_type ("preonly", "cg", "gmres"), pc_type ("cholesky",
 * "lu", "gamg", "hypre"), the factor package ("mumps") or NULL, the
 * relative tolerance and iteration limit of an iterative method. PETSc's
 * options database (PETSC_OPTIONS, [solver] options) comes last. */
int junta_system_solver(junta_system *s, const char *ksp_type, const char *pc_type,
                        const char *package, double rtol, PetscInt max_it) {
  PC pc;
  PetscCall(KSPSetOperators(s->ksp, s->A, s->A));
  PetscCall(KSPSetType(s->ksp, ksp_type));
  PetscCall(KSPGetPC(s->ksp, &pc));
  PetscCall(PCSetType(pc, pc_type));
  if (package) PetscCall(PCFactorSetMatSolverType(pc, package));
  if (!strcmp(pc_type, PCHYPRE)) PetscCall(PCHYPRESetType(pc, "boomeramg"));
  PetscCall(KSPSetTolerances(s->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, max_it));
  PetscCall(KSPSetFromOptions(s->ksp));
  return 0;
}

/* The near-null space of the matrix (for GAMG): nvec orthonormal vectors,
 * each given by its nlocal entries on this rank, one after another. */
int junta_system_near_null_space(junta_system *s, PetscInt nvec, const double *local) {
  Vec *v;
  MatNullSpace nsp;
  PetscCall(PetscMalloc1(nvec, &v));
  for (PetscInt k = 0; k < nvec; k++) {
    PetscScalar *a;
    PetscCall(VecDuplicate(s->x, &v[k]));
    PetscCall(VecGetArray(v[k], &a));
    PetscCall(PetscArraycpy(a, local + k * s->nlocal, s->nlocal));
    PetscCall(VecRestoreArray(v[k], &a));
  }
  PetscCall(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, nvec, v, &nsp));
  PetscCall(MatSetNearNullSpace(s->A, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  for (PetscInt k = 0; k < nvec; k++) PetscCall(VecDestroy(&v[k]));
  PetscCall(PetscFree(v));
  return 0;
}

/* New values of this rank's rows, in the order of the CSR pattern. */
int junta_system_values(junta_system *s, const double *values, int symmetric) {
  PetscCall(MatUpdateMPIAIJWithArray(s->A, values));
  PetscCall(MatSetOption(s->A, MAT_SYMMETRIC, symmetric ? PETSC_TRUE : PETSC_FALSE));
  if (symmetric) PetscCall(MatSetOption(s->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  PetscCall(KSPSetOperators(s->ksp, s->A, s->A));
  return 0;
}

/* Factorise (direct) or set up the preconditioner; *failed is the PC's
 * failure reason (0 none, 2 a zero pivot, ...). */
int junta_system_setup(junta_system *s, int *failed) {
  PC pc;
  PCFailedReason r = PC_NOERROR;
  PetscCall(KSPSetUp(s->ksp));
  PetscCall(KSPGetPC(s->ksp, &pc));
  PetscCall(PCGetFailedReason(pc, &r));
  *failed = (int)r;
  return 0;
}

/* Inertia of the factor (direct solvers; MUMPS needs ICNTL(13) = 1). */
int junta_system_inertia(junta_system *s, PetscInt *neg, PetscInt *zero, PetscInt *pos) {
  PC pc;
  Mat F;
  PetscCall(KSPGetPC(s->ksp, &pc));
  PetscCall(PCFactorGetMatrix(pc, &F));
  PetscCall(MatGetInertia(F, neg, zero, pos));
  return 0;
}

/* Solve with this rank's nlocal right-hand-side entries; every rank gets
 * the whole solution (n entries). reason: KSPConvergedReason (negative:
 * diverged). */
int junta_system_solve(junta_system *s, const double *b_local, double *x_all, int *reason,
                       PetscInt *its, double *rnorm) {
  PetscScalar *a;
  const PetscScalar *xa;
  KSPConvergedReason r;
  PetscCall(VecGetArray(s->b, &a));
  PetscCall(PetscArraycpy(a, b_local, s->nlocal));
  PetscCall(VecRestoreArray(s->b, &a));
  PetscCall(KSPSolve(s->ksp, s->b, s->x));
  PetscCall(KSPGetConvergedReason(s->ksp, &r));
  PetscCall(KSPGetIterationNumber(s->ksp, its));
  PetscCall(KSPGetResidualNorm(s->ksp, rnorm));
  *reason = (int)r;
  if (!s->toall) PetscCall(VecScatterCreateToAll(s->x, &s->toall, &s->xall));
  PetscCall(VecScatterBegin(s->toall, s->x, s->xall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(s->toall, s->x, s->xall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(s->xall, &xa));
  PetscCall(PetscArraycpy(x_all, xa, s->n));
  PetscCall(VecRestoreArrayRead(s->xall, &xa));
  return 0;
}

/* The KSP and PC types in use, e.g. "preonly/cholesky (mumps)". */
int junta_system_describe(junta_system *s, char *buf, size_t len) {
  KSPType kt;
  PCType pt;
  PC pc;
  MatSolverType package = NULL;
  PetscCall(KSPGetType(s->ksp, &kt));
  PetscCall(KSPGetPC(s->ksp, &pc));
  PetscCall(PCGetType(pc, &pt));
  if (pt && (!strcmp(pt, PCLU) || !strcmp(pt, PCCHOLESKY))) PetscCall(PCFactorGetMatSolverType(pc, &package));
  snprintf(buf, len, "%s/%s%s%s%s", kt ? kt : "?", pt ? pt : "?", package ? " (" : "",
           package ? package : "", package ? ")" : "");
  return 0;
}

int junta_system_destroy(junta_system *s) {
  if (!s) return 0;
  PetscCall(KSPDestroy(&s->ksp));
  PetscCall(VecScatterDestroy(&s->toall));
  PetscCall(VecDestroy(&s->xall));
  PetscCall(VecDestroy(&s->x));
  PetscCall(VecDestroy(&s->b));
  PetscCall(MatDestroy(&s->A));
  PetscCall(PetscFree(s));
  return 0;
}
