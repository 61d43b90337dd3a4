#!/usr/bin/python3
"""An exported system is the system that was solved, whatever the rank counts.

Two cases (each a ctest):

  builtin     solve_block_system exports the built-in tied-blocks system on 2 ranks and writes
              the solution it found there (--write-solution). The files are solved again on 1
              and on 3 ranks and, independently of our reader, by scipy (spsolve on matrix.mm /
              rhs.mm). All four solutions agree, each one solves the system of the files
              (||A x - b|| / ||b|| from scipy), and the nullspace file is the rigid-body modes of
              the coordinates file, node by node.
  beam_solid  the beam_solid app (cube case) exports its first Newton system on 1 rank and on 2
              ranks (the DOF numbering differs between rank counts, so only numbering-independent
              numbers are compared: the norm of every block of b and of the scipy solution). The
              2-rank files are then solved on 1 and 3 ranks by solve_block_system and by scipy.
  contact     the same with the contact_blocks app (2D two-block benchmark, coarse mesh, one
              load step): there every rank owns displacements and multipliers, so a file in
              rank order mixes the blocks.

A right-hand side written in rank order (rank 0's rows of every block, then rank 1's) is a
permutation of the true one: same ||b||, but the wrong b_k per block and the wrong solution,
which every check above sees. Exit status 0 when all checks pass, 1 otherwise.
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import scipy.io
import scipy.sparse.linalg

TOL = 1e-8
failures = []

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import block_system_files  # noqa: E402  (the repository's scripts/)


def check(ok, what):
    print(("ok:     " if ok else "FAILED: ") + what, flush=True)
    if not ok:
        failures.append(what)


def run(cmd, ranks, mpiexec):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    full = [mpiexec, "-np", str(ranks), "--oversubscribe"] + cmd
    proc = subprocess.run(full, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        sys.exit(f"'{' '.join(full)}' exited with {proc.returncode}:\n{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
    return proc.stdout


def read_system(d):
    """matrix (CSR), rhs and block sizes of a manifest directory, read with scipy alone."""
    return block_system_files.read_system(d)


def block_norms(v, blocks):
    out, start = [], 0
    for blk in blocks:
        out.append(float(np.linalg.norm(v[start:start + blk["size"]])))
        start += blk["size"]
    return out


def relative(a, b):
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-300))


def solve_files(system_dir, out, tag, args, tol="1e-10"):
    """solve_block_system on 1 and 3 ranks from the files: {ranks: (solution, JSON report)}."""
    results = {}
    for ranks in (1, 3):
        x_file, json_file = f"{out}/{tag}_x_np{ranks}.mm", f"{out}/{tag}_report_np{ranks}.json"
        run([args.solver, "--system", system_dir, "--preset", "direct(superlu)", "--tol", tol,
             "--write-solution", x_file, "--json", json_file], ranks, args.mpiexec)
        with open(json_file) as f:
            results[ranks] = (np.asarray(scipy.io.mmread(x_file)).ravel(), json.load(f))
    return results


def check_solutions(A, b, reference, solutions, label, tol=TOL):
    """Every solution equals scipy's (to `tol`: the conditioning of A) and solves the files' system."""
    for name, x in solutions.items():
        check(x.shape == reference.shape and relative(x, reference) < tol,
              f"{label}: {name} equals scipy's spsolve solution (relative difference "
              f"{relative(x, reference) if x.shape == reference.shape else 'shape mismatch':})")
        r = float(np.linalg.norm(A @ x - b) / np.linalg.norm(b)) if x.shape == b.shape else float("inf")
        check(r < TOL, f"{label}: {name} solves the files' system, ||A x - b|| / ||b|| = {r:.3e} (scipy)")


def case_builtin(args, out):
    system_dir = f"{out}/tied_blocks_np2"
    run([args.solver, "--builtin", "tied-blocks-2d:0", "--preset", "direct(superlu)", "--tol", "1e-10",
         "--export-system", system_dir, "--write-solution", f"{out}/x_np2.mm", "--json", f"{out}/report_np2.json"],
        2, args.mpiexec)
    with open(f"{out}/report_np2.json") as f:
        report2 = json.load(f)
    A, b, blocks = read_system(system_dir)
    reference = scipy.sparse.linalg.spsolve(A.tocsc(), b)
    solutions = {"2-rank solve in memory": np.asarray(scipy.io.mmread(f"{out}/x_np2.mm")).ravel()}
    runs = solve_files(system_dir, out, "tied_blocks", args)
    for ranks, (x, report) in runs.items():
        solutions[f"{ranks}-rank solve of the files"] = x
        check(report["converged"] and report["relative_residual"] < TOL,
              f"{ranks}-rank solve converged, reported ||A x - b|| / ||b|| = {report['relative_residual']:.3e}"
              f" (2 ranks in memory: {report2['relative_residual']:.3e})")
    print(f"||b|| = {np.linalg.norm(b):.12e}, block norms {block_norms(b, blocks)}")
    check_solutions(A, b, reference, solutions, "tied-blocks-2d:0")

    # Nullspace against coordinates: translations and the rotation (-y, x) at every node.
    primal = blocks[0]
    if not (primal["nullspace"] and primal["coordinates"]):
        check(False, f"manifest names a nullspace and a coordinates file for block '{primal['name']}'")
        return
    nsp = np.asarray(scipy.io.mmread(os.path.join(system_dir, primal["nullspace"])))
    xyz = np.asarray(scipy.io.mmread(os.path.join(system_dir, primal["coordinates"])))
    expected = np.zeros_like(nsp)
    expected[0::2, 0], expected[1::2, 1] = 1.0, 1.0
    expected[0::2, 2], expected[1::2, 2] = -xyz[:, 1], xyz[:, 0]
    check(np.abs(nsp - expected).max() < 1e-12, "nullspace file = rigid-body modes of the coordinates file")


def exported(run_dir):
    """The exported systems of one app run, by name, in (load step, Newton step) order."""
    dirs = [d for d in glob.glob(f"{run_dir}/systems/*") if os.path.isfile(f"{d}/manifest.txt")]
    return sorted(dirs, key=lambda d: [int(n) for n in re.findall(r"\d+", os.path.basename(d))])


APPS = {
    "beam_solid": [],
    "contact": ["--set", "Mesh/Gmsh refinement=2", "--set", "Loading/Load steps=1",
                "--set", "Linear solver/Overrides="],
}


def case_app(args, out):
    """The first Newton system of an app, exported on 1 and on 2 ranks."""
    exe = os.path.join(args.build, "apps", "beam_solid" if args.case == "beam_solid" else "contact_blocks")
    settings = list(APPS[args.case])
    if args.mesh:
        settings += ["--set", f"Mesh/Mesh file={args.mesh}"]
    systems = {}
    for ranks in (1, 2):
        run_dir = f"{out}/{args.case}_np{ranks}"
        run([exe, args.prm, "--set", "Output/Export systems=true", "--set", "Output/VTK=false",
             "--set", "Linear solver/Preset=direct(superlu)", "--set", f"Output/Directory={run_dir}"] + settings,
            ranks, args.mpiexec)
        found = exported(run_dir)
        if not found:
            sys.exit(f"{run_dir}: no exported systems (systems/*/manifest.txt)")
        systems[ranks] = found[0]
    print(f"first Newton system: {systems[1]} (1 rank) and {systems[2]} (2 ranks)")
    A1, b1, blocks1 = read_system(systems[1])
    A2, b2, blocks2 = read_system(systems[2])
    check([k["size"] for k in blocks1] == [k["size"] for k in blocks2], "same block sizes on 1 and 2 ranks")
    n1, n2 = block_norms(b1, blocks1), block_norms(b2, blocks2)
    names = [k["name"] for k in blocks1]
    for k, name in enumerate(names):
        check(abs(n1[k] - n2[k]) <= 1e-10 * max(n1), f"||b_{name}||: {n1[k]:.12e} (1 rank), {n2[k]:.12e} (2 ranks)")
    x1 = scipy.sparse.linalg.spsolve(A1.tocsc(), b1)
    x2 = scipy.sparse.linalg.spsolve(A2.tocsc(), b2)
    m1, m2 = block_norms(x1, blocks1), block_norms(x2, blocks2)
    for k, name in enumerate(names):
        check(abs(m1[k] - m2[k]) <= TOL * max(m1),
              f"||x_{name}|| (scipy): {m1[k]:.12e} (1-rank export), {m2[k]:.12e} (2-rank export)")
    # The apps' Newton systems are less well conditioned than the model problem (contact: SuperLU
    # leaves 2.5e-9 relative, and its solution differs from scipy's by 2e-8, the multipliers
    # being 1e6 and the displacements 0.2): GMRES to 1e-8, solutions against scipy's to 1e-6,
    # against each other (same solver, 1 and 3 ranks) to 1e-8.
    runs = solve_files(systems[2], out, args.case, args, tol="1e-8")
    check_solutions(A2, b2, x2, {f"{r}-rank solve of the 2-rank files": x for r, (x, _) in runs.items()},
                    args.case, tol=1e-6)
    d = relative(runs[3][0], runs[1][0])
    check(d < TOL, f"{args.case}: 3-rank and 1-rank solutions of the 2-rank files agree (relative difference {d:.3e})")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", choices=["builtin", "beam_solid", "contact"])
    parser.add_argument("--build", required=True, help="build directory (apps/ holds the executables)")
    parser.add_argument("--out", required=True, help="scratch directory (replaced)")
    parser.add_argument("--prm", help="beam_solid, contact: the app's parameter file")
    parser.add_argument("--mesh", help="contact: the mesh file (the parameter file names it relative to the repository)")
    parser.add_argument("--mpiexec", default="mpirun")
    args = parser.parse_args()
    args.solver = os.path.join(args.build, "apps", "solve_block_system")
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    (case_builtin if args.case == "builtin" else case_app)(args, args.out)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
