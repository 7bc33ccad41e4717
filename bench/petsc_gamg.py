#!/usr/bin/python3
"""PETSc GAMG as the yardstick for Junta's AMG (issue 28, part 4).

Solves the system Junta exports with `junta run DECK -o OUT --solver type=cg
--solver preconditioner=amg --export-matrix DIR` with PETSc's CG + GAMG,
sequentially (one process, no MPI launcher; run it with OMP_NUM_THREADS=1 and
OPENBLAS_NUM_THREADS=1 so that BLAS stays on one core too). Run it with
/usr/bin/python3: Debian's python3-petsc4py and python3-scipy are installed
for the system interpreter, not for a pyenv/pip one.

Usage: petsc_gamg.py EXPORT_DIR [[LABEL=]junta_summary.json ...] [--bs3]
                     [--repeat N] [-- PETSc options...]

Reads (scipy.io.mmread) DIR/K.mtx (stiffness of the free dofs, stored
"symmetric": one triangle, expanded here to the full AIJ matrix), DIR/b.mtx
(load vector) and DIR/B.mtx (rigid-body modes, 6 columns, one row per
equation). What is measured, with the source of each setting:
  * matrix: MATSEQAIJ, block size 1 (the exported system has only the free
    dofs, so it is not in blocks of 3: on the cube decks the top nodes, whose
    z is prescribed, keep 2 dofs). `--bs3` instead pads the system back to
    3 dofs per node (DIR/layout.csv gives node and component of each
    equation): each missing dof gets a decoupled row with the mean diagonal of
    K and a zero right-hand side (as PETSc's ksp/tutorials/ex56 keeps its
    Dirichlet rows), block size 3, and the near-null space is built by
    MatNullSpaceCreateRigidBody from the node coordinates in layout.csv.
  * near-null space (MatSetNearNullSpace): the 6 columns of B, orthonormalised
    with numpy QR (MatNullSpaceCreate requires orthonormal vectors).
  * KSP: KSPCG, rtol 1e-10, atol 0, zero initial guess, and the
    UNPRECONDITIONED residual norm, so that the test is Junta's CG test
    ||b - A x|| / ||b|| <= 1e-10 (crates/solvers/src/cg.rs; PETSc's CG would
    otherwise test the preconditioned norm).
  * PC: PCGAMG with PETSc's default options (3.18: smoothed aggregation,
    threshold -1 (no dropping), graph squared on the first level, one
    prolongator smoothing step, Chebyshev(2)/Jacobi smoothers, LU on the
    coarsest level; see -ksp_view); options given after `--` (or
    in PETSC_OPTIONS) are passed to PETSc, e.g. `-- -pc_gamg_threshold 0.01`.
  * set-up s: wall time of KSPSetUp (which runs PCSetUp: the GAMG hierarchy)
    after KSPSetOperators; solve s: wall time of KSPSolve. Reading the files
    and building the PETSc matrix are not timed (Junta's summary.json
    timings.factor and timings.solve exclude assembly too). With --repeat N
    the set-up and solve are repeated N times on a fresh KSP and the medians
    are reported.
  * true relative residual ||b - A x|| / ||b||, computed with scipy from
    K.mtx and b.mtx (the exported, unpadded system).

Output: for each junta_summary.json, one markdown row
  | deck | equations | Junta AMG set-up s | Junta solve s | Junta its |
  PETSc GAMG set-up s | PETSc solve s | PETSc its | ratio |
where deck is LABEL (default: the deck's file name), Junta's numbers are
timings.factor (AMG set-up), timings.solve (CG) and solver.iterations of that
summary (a Junta run with `--solver type=cg --solver preconditioner=amg` on
the same deck), and ratio = (Junta set-up + solve) / (PETSc set-up +
solve); without any, one line with PETSc's numbers. The details (PETSc
version, levels, grid sizes, operator complexity, residual, per-repeat times)
go to stderr in either case.
"""
import glob
import json
import os
import statistics
import sys
import time

try:
    import petsc4py
except ImportError:
    # Debian's python3-petsc4py finds its build through /usr/lib/petsc (an
    # alternative that only petsc-dev installs) or PETSC_DIR; take the real
    # (double) build directly otherwise.
    for d in sorted(glob.glob("/usr/lib/petscdir/petsc3*/x86_64-linux-gnu-real/lib/python3/dist-packages")):
        sys.path.append(d)
    import petsc4py

args = sys.argv[1:]
petsc_args = []
if "--" in args:
    i = args.index("--")
    args, petsc_args = args[:i], args[i + 1:]
bs3 = "--bs3" in args
repeat = 1
if "--repeat" in args:
    i = args.index("--repeat")
    repeat = int(args[i + 1])
    del args[i:i + 2]
args = [a for a in args if a != "--bs3"]
if not args:
    sys.exit(__doc__)
petsc4py.init([sys.argv[0]] + petsc_args)
from petsc4py import PETSc  # noqa: E402
import numpy as np  # noqa: E402
import scipy.io  # noqa: E402
import scipy.sparse as sp  # noqa: E402

d = args[0]
K = sp.csr_matrix(scipy.io.mmread(f"{d}/K.mtx"))
K.sum_duplicates()
K.sort_indices()
b = np.asarray(scipy.io.mmread(f"{d}/b.mtx"), dtype=float).ravel()
B = np.asarray(scipy.io.mmread(f"{d}/B.mtx"), dtype=float)
n = K.shape[0]
assert b.shape == (n,) and B.shape == (n, 6), (K.shape, b.shape, B.shape)

if bs3:
    lay = np.genfromtxt(f"{d}/layout.csv", delimiter=",", names=True)
    node, comp = lay["node"].astype(np.int64), lay["component"].astype(np.int64)
    nodes, first = np.unique(node, return_index=True)
    order = np.argsort(first)  # node rank in equation order
    rank = np.empty(len(nodes), dtype=np.int64)
    rank[order] = np.arange(len(nodes))
    full = 3 * rank[np.searchsorted(nodes, node)] + comp  # padded index of each equation
    assert np.all(np.diff(full) > 0), "equations are not node-major"
    N = 3 * len(nodes)
    pad = np.setdiff1d(np.arange(N), full)
    P = sp.csr_matrix((np.ones(n), (full, np.arange(n))), shape=(N, n))
    Kp = (P @ K @ P.T).tocsr() + sp.csr_matrix((np.full(len(pad), K.diagonal().mean()), (pad, pad)), shape=(N, N))
    Kp.sort_indices()
    bp = P @ b
    xyz = np.zeros((len(nodes), 3))
    xyz[rank[np.searchsorted(nodes, node)]] = np.column_stack([lay["x"], lay["y"], lay["z"]])
    Am, rhs, bs = Kp, bp, 3
else:
    Am, rhs, bs = K, b, 1

A = PETSc.Mat().createAIJ(size=Am.shape, bsize=bs,
                          csr=(Am.indptr.astype(PETSc.IntType), Am.indices.astype(PETSc.IntType), Am.data))
A.assemble()
if bs3:
    coords = PETSc.Vec().createWithArray(xyz.ravel().copy())
    coords.setBlockSize(3)
    ns = PETSc.NullSpace().createRigidBody(coords)
else:
    Q, _ = np.linalg.qr(B)
    vecs = [PETSc.Vec().createWithArray(Q[:, j].copy()) for j in range(6)]
    ns = PETSc.NullSpace().create(constant=False, vectors=vecs)
A.setNearNullSpace(ns)
bv = A.createVecLeft()
bv.array[:] = rhs

runs = []
for r in range(repeat):
    ksp = PETSc.KSP().create()
    ksp.setType(PETSc.KSP.Type.CG)
    ksp.getPC().setType(PETSc.PC.Type.GAMG)
    ksp.setTolerances(rtol=1e-10, atol=0.0, max_it=10000)
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    ksp.setFromOptions()
    ksp.setOperators(A)
    x = A.createVecRight()
    t = time.perf_counter()
    ksp.setUp()
    ts = time.perf_counter() - t
    t = time.perf_counter()
    ksp.solve(bv, x)
    tsol = time.perf_counter() - t
    its, reason = ksp.getIterationNumber(), ksp.getConvergedReason()
    pc = ksp.getPC()
    nlev = pc.getMGLevels()
    sizes, nnz = [], []
    for lev in range(nlev - 1, -1, -1):  # level nlev-1 is the finest
        Al = pc.getMGSmoother(lev).getOperators()[0]
        sizes.append(Al.getSize()[0])
        nnz.append(Al.getInfo()["nz_used"])
    xs = x.array.copy()
    if bs3:
        xs = xs[full]
    res = np.linalg.norm(b - K @ xs) / np.linalg.norm(b)
    runs.append((ts, tsol, its, reason, sizes, sum(nnz) / nnz[0], res))
    if r + 1 < repeat:
        ksp.destroy()
    print(f"petsc_gamg: {d} run {r + 1}: set-up {ts:.2f} s, solve {tsol:.2f} s, {its} iterations "
          f"(reason {reason}), true rel. residual {res:.1e}", file=sys.stderr)

ts = statistics.median(r[0] for r in runs)
tsol = statistics.median(r[1] for r in runs)
its = statistics.median(r[2] for r in runs)
_, _, _, reason, sizes, oc, res = runs[-1]
opts = " ".join(petsc_args) or "defaults"
print(f"petsc_gamg: PETSc {'.'.join(map(str, PETSc.Sys.getVersion()))} (petsc4py {petsc4py.__version__}), "
      f"{'AIJ bs=3, padded to 3 dofs/node' if bs3 else 'AIJ bs=1'}, GAMG {opts}: {len(sizes)} levels {sizes}, "
      f"operator complexity {oc:.2f}, true rel. residual {res:.1e}", file=sys.stderr)
if reason <= 0:
    print(f"petsc_gamg: KSP did not converge (reason {reason})", file=sys.stderr)
    sys.exit(1)
for a in args[1:]:
    label, _, path = a.rpartition("=")
    s = json.load(open(path))
    deck = label or os.path.splitext(os.path.basename(s["input"]))[0]
    jf, js, ji = s["timings"]["factor"], s["timings"]["solve"], s["solver"]["iterations"]
    print(f"| {deck} | {n} | {jf:.2f} | {js:.2f} | {ji} | {ts:.2f} | {tsol:.2f} | {its:g} | {(jf + js) / (ts + tsol):.2f} |")
if len(args) == 1:
    print(f"{d}: equations {n}, PETSc GAMG set-up {ts:.2f} s, solve {tsol:.2f} s, {its:g} iterations, "
          f"levels {sizes}, true rel. residual {res:.1e}")
