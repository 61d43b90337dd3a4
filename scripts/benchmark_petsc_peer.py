#!/usr/bin/python3
"""A peer code on the same matrices: PETSc (Debian's petsc4py) beside the project's presets.

Reads exported BlockSystem directories (manifest.txt + Matrix Market: `contact_blocks` with
`Output/Export systems = true`, or `solve_block_system --export-system`) and solves each one

  petsc fieldsplit-schur(gamg)  GMRES + PCFIELDSPLIT, Schur complement, full factorization,
                                Schur preconditioner "selfp" (A11 - A10 diag(A00)^-1 A01) with
                                block Jacobi/ILU(0); GAMG on the displacement block with the
                                block's near-nullspace (rigid-body modes from the export)
  petsc lu(mumps)               a direct LU (MUMPS), as PETSc's own LU needs a stored diagonal in
                                every row, which the contact constraint rows lack
  project PRESET                solve_block_system --system DIR --preset PRESET (--json)

with right-preconditioned GMRES(100) to a relative residual TOL and prints iterations, setup and
solve seconds and the true relative residual ||b - K x|| / ||b|| of each, side by side.

    scripts/benchmark_petsc_peer.py DIR [DIR ...] [--presets "cheapsimple(sa-amg)" ...]
        [--solver build/apps/solve_block_system] [--ranks 1] [--json FILE] [--check]
    scripts/benchmark_petsc_peer.py --contact-levels 1 2 3 --build build --out DIR [--presets ...]

The second form first runs `contact_blocks apps/contact_blocks_3d.prm` (2 ranks) at each Gmsh
refinement with `Export systems = true` into DIR/levelL and compares on its next-to-last Newton
system: the last one's right-hand side is 7e-5 of the load step's first (Newton converges
quadratically), so 1e-8 relative to it is close to what rounding allows on these badly scaled
rows (pa-amg(cheapsimple) at 66 k DOFs reaches GMRES's tolerance there with a true residual of
4e-7, on the Newton system before it 5e-9).

With --check (the small default-suite test) the exit status is 1 unless every PETSc solve
converged to TOL with a true residual below 10 TOL.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
import scipy.io

import block_system_files  # scripts/, beside this file


def read_system(d):
    """K (CSR), b, block sizes and the first block's near-nullspace (or None)."""
    K, b, blocks = block_system_files.read_system(d, n_blocks=2)
    nullspace = np.asarray(scipy.io.mmread(blocks[0]["nullspace"])) if blocks[0]["nullspace"] else None
    return K, b, blocks, nullspace


def petsc_solve(PETSc, K, b, blocks, nullspace, method, tol):
    """One PETSc solve; returns its report (iterations, seconds, true residual, convergence)."""
    comm = PETSc.COMM_WORLD
    n, n1 = K.shape[0], blocks[0]["size"]
    # Row ownership: PETSc's default split of the rows.
    A = PETSc.Mat().create(comm=comm)
    A.setSizes([n, n])
    A.setType("aij")
    A.setUp()
    begin, end = A.getOwnershipRange()
    local = K[begin:end]
    A.setPreallocationCSR((local.indptr, local.indices))
    A.setValuesCSR(local.indptr, local.indices, local.data)
    A.assemble()
    x, rhs = A.createVecs()
    rhs.setArray(b[begin:end])

    ksp = PETSc.KSP().create(comm=comm)
    ksp.setOperators(A)
    ksp.setType("gmres")
    ksp.setGMRESRestart(100)
    ksp.setPCSide(PETSc.PC.Side.RIGHT)
    ksp.setTolerances(rtol=tol, atol=0.0, max_it=1000)
    pc = ksp.getPC()
    opts = PETSc.Options()
    if method == "lu(mumps)":
        ksp.setType("preonly")
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
    else:
        pc.setType("fieldsplit")
        displacements = PETSc.IS().createStride(max(0, min(end, n1) - begin), first=begin, step=1, comm=comm)
        multipliers = PETSc.IS().createStride(max(0, end - max(begin, n1)), first=max(begin, n1), step=1,
                                              comm=comm)
        if nullspace is not None:
            # the rigid-body modes of the displacement rows this rank owns, orthonormalized
            rows = slice(begin, min(end, n1))
            vectors = []
            for k in usable_columns(nullspace):
                v = PETSc.Vec().createMPI((max(0, min(end, n1) - begin), n1), comm=comm)
                v.setArray(nullspace[rows, k] if begin < n1 else np.zeros(0))
                vectors.append(v)
            orthonormalize(vectors)
            displacements.compose("nearnullspace", PETSc.NullSpace().create(vectors=vectors, comm=comm))
        pc.setFieldSplitIS(("0", displacements), ("1", multipliers))
        opts["pc_fieldsplit_type"] = "schur"
        opts["pc_fieldsplit_schur_fact_type"] = "full"
        opts["pc_fieldsplit_schur_precondition"] = "selfp"
        opts["fieldsplit_0_ksp_type"] = "preonly"
        opts["fieldsplit_0_pc_type"] = "gamg"
        opts["fieldsplit_0_pc_gamg_type"] = "agg"
        opts["fieldsplit_0_mg_levels_ksp_type"] = "chebyshev"
        opts["fieldsplit_0_mg_levels_pc_type"] = "jacobi"
        opts["fieldsplit_1_ksp_type"] = "preonly"
        opts["fieldsplit_1_pc_type"] = "bjacobi"
        opts["fieldsplit_1_sub_pc_type"] = "ilu"
        A.setBlockSize(1)
    pc.setFromOptions()
    ksp.setFromOptions()

    start = time.perf_counter()
    ksp.setUp()
    setup = time.perf_counter() - start
    start = time.perf_counter()
    ksp.solve(rhs, x)
    solve = time.perf_counter() - start
    r = rhs.duplicate()
    A.mult(x, r)
    r.aypx(-1.0, rhs)
    residual = r.norm() / rhs.norm()
    for key in list(opts.getAll().keys()):
        opts.delValue(key)
    iterations = ksp.getIterationNumber() if method != "lu(mumps)" else 1
    converged = ksp.getConvergedReason() > 0 and residual <= 10 * tol
    complexity = None
    if method != "lu(mumps)":
        complexity = gamg_complexity(pc)
    return {"solver": "petsc " + method, "iterations": iterations, "setup_seconds": setup,
            "solve_seconds": solve, "true_residual": residual, "converged": bool(converged),
            "operator_complexity": complexity}


def usable_columns(nullspace):
    """The columns of the near-nullspace that are not zero (an export whose coordinates were never
    set has zero rotations: they are left out, and said so)."""
    norms = np.linalg.norm(nullspace, axis=0)
    zero = [k for k in range(nullspace.shape[1]) if norms[k] == 0]
    if zero:
        print(f"warning: near-nullspace columns {zero} are zero (no coordinates in the export): left out",
              file=sys.stderr)
    return [k for k in range(nullspace.shape[1]) if norms[k] > 0]


def orthonormalize(vectors):
    """Modified Gram-Schmidt (PETSc's NullSpace wants orthonormal vectors)."""
    for i, v in enumerate(vectors):
        for w in vectors[:i]:
            v.axpy(-v.dot(w), w)
        v.scale(1.0 / v.norm())


def gamg_complexity(pc):
    """Operator complexity of the GAMG hierarchy on the displacement block (sum of nonzeros over
    the finest level's), or None."""
    try:
        sub = pc.getFieldSplitSubKSP()[0].getPC()
        levels = sub.getMGLevels()
        total = 0.0
        fine = None
        for level in range(levels):
            op = sub.getMGSmoother(level).getOperators()[0]
            nnz = op.getInfo(PETSc_module().Mat.InfoType.GLOBAL_SUM)["nz_used"]
            total += nnz
            if level == levels - 1:
                fine = nnz
        return total / fine if fine else None
    except Exception:  # complexity is a nicety, never a reason to fail the benchmark
        return None


_petsc = None


def PETSc_module():
    return _petsc


def project_solve(solver, ranks, d, preset, tol, out_dir):
    """solve_block_system on the same files; its JSON report."""
    json_file = os.path.join(out_dir, "project_" + "".join(c if c.isalnum() else "_" for c in preset) + ".json")
    cmd = [solver, "--system", d, "--preset", preset, "--tol", str(tol), "--json", json_file]
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks), "--oversubscribe"] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode not in (0, 1) or not os.path.exists(json_file):
        return {"solver": "project " + preset, "converged": False, "error": (proc.stderr or proc.stdout)[-300:]}
    with open(json_file) as f:
        rep = json.load(f)
    return {"solver": "project " + preset, "iterations": rep.get("iterations"),
            "setup_seconds": rep.get("setup_seconds"), "solve_seconds": rep.get("solve_seconds"),
            "true_residual": rep.get("true_relative_residual", rep.get("relative_residual")),
            "converged": bool(rep.get("converged")), "operator_complexity": rep.get("operator_complexity")}


def newton_order(name):
    """stepS-newtonN as (S, N), for sorting the exported systems."""
    step, newton = name.split("-")
    return int(step[len("step"):]), int(newton[len("newton"):])


def export_contact_systems(build, source, levels, out):
    """The next-to-last Newton system of the 3D benchmark at each refinement level, exported by the app."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    systems = []
    for level in levels:
        directory = os.path.abspath(os.path.join(out, f"level{level}"))
        cmd = ["mpirun", "-np", "2", "--oversubscribe", os.path.join(build, "apps", "contact_blocks"),
               os.path.join(source, "apps", "contact_blocks_3d.prm"), "--set", f"Mesh/Gmsh refinement={level}",
               "--set", "Linear solver/Preset=cheapsimple(sa-amg)", "--set", "Linear solver/Overrides=",
               "--set", "Output/Export systems=true", "--set", "Output/VTK=false",
               "--set", f"Output/Directory={directory}"]
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if proc.returncode != 0:
            sys.exit(f"contact_blocks at refinement {level} failed ({proc.returncode}): {proc.stderr[-500:]}")
        exported = sorted((d for d in os.listdir(os.path.join(directory, "systems")) if "." not in d),
                          key=newton_order)
        systems.append(os.path.join(directory, "systems", exported[-2 if len(exported) > 1 else -1]))
    return systems


def main():
    global _petsc
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("systems", nargs="*")
    parser.add_argument("--contact-levels", type=int, nargs="*", default=[])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="petsc_peer")
    parser.add_argument("--tol", type=float, default=1e-8)
    parser.add_argument("--methods", nargs="+", default=["fieldsplit-schur(gamg)", "lu(mumps)"])
    parser.add_argument("--presets", nargs="*", default=[])
    parser.add_argument("--solver", default="build/apps/solve_block_system")
    parser.add_argument("--ranks", type=int, default=1, help="ranks of the project's runs")
    parser.add_argument("--json")
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()

    import petsc4py
    petsc4py.init(sys.argv[:1])
    from petsc4py import PETSc
    _petsc = PETSc
    rank = PETSc.COMM_WORLD.getRank()
    if args.contact_levels:
        source = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        args.systems += export_contact_systems(args.build, source, args.contact_levels, args.out)
        if args.solver == parser.get_default("solver"):
            args.solver = os.path.join(args.build, "apps", "solve_block_system")
    if not args.systems:
        sys.exit("give system directories or --contact-levels")

    results, ok = [], True
    for d in args.systems:
        K, b, blocks, nullspace = read_system(d)
        rows = []
        for method in args.methods:
            rep = petsc_solve(PETSc, K, b, blocks, nullspace, method, args.tol)
            ok &= rep["converged"]
            rows.append(rep)
        if rank == 0:
            out_dir = os.path.dirname(os.path.abspath(args.json)) if args.json else "/tmp"
            for preset in args.presets:
                rows.append(project_solve(args.solver, args.ranks, d, preset, args.tol, out_dir))
            print(f"\n{d}: {K.shape[0]} rows ({blocks[0]['size']} + {blocks[1]['size']}), {K.nnz} nonzeros")
            print(f"  {'solver':44s} {'its':>5s} {'setup s':>8s} {'solve s':>8s} {'total s':>8s} "
                  f"{'true res':>9s} {'op.cx':>6s} converged")
            for r in rows:
                if "error" in r:
                    print(f"  {r['solver']:44s} failed: {r['error']}")
                    continue
                total = (r["setup_seconds"] or 0) + (r["solve_seconds"] or 0)
                cx = f"{r['operator_complexity']:.2f}" if r.get("operator_complexity") else "-"
                print(f"  {r['solver']:44s} {r['iterations']:5d} {r['setup_seconds']:8.3f} "
                      f"{r['solve_seconds']:8.3f} {total:8.3f} {r['true_residual']:9.2e} {cx:>6s} "
                      f"{'yes' if r['converged'] else 'NO'}")
            results.append({"system": d, "rows": K.shape[0], "results": rows})
    if rank == 0 and args.json:
        tmp = args.json + ".partial"
        with open(tmp, "w") as f:
            json.dump(results, f, indent=1)
        os.replace(tmp, args.json)
    if args.check:
        if rank == 0:
            print("all PETSc solves converged" if ok else "FAILED: a PETSc solve did not converge")
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
