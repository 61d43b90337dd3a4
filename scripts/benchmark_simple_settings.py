#!/usr/bin/python3
"""The SIMPLE level smoother's settings, one at a time, on the same exported systems.

For a fully coupled preset (default `pa-amg(cheapsimple)`, the rings table) and each exported
BlockSystem directory given, solves the system with every combination of
  UPDATE_INVERSE  the Â of SIMPLE's final update      diagonal (SIMPLE) | absolute-row-sum (SIMPLEC)
  SCHUR_INVERSE   the Â of the Schur complement       diagonal | absolute-row-sum | spai
  sweeps          PREDICTOR_SWEEPS (SGS on A) and SMOOTHER_SWEEPS (SIMPLE), each 1 or 3
(plus --set overrides common to all runs) and prints GMRES iterations (or "div" for a run that
did not converge), setup + solve seconds, in one table: rows = settings, columns = systems.

    scripts/benchmark_simple_settings.py DIR [DIR ...] [--preset NAME] [--set PATH=VALUE ...]
        [--solver build/apps/solve_block_system] [--ranks 1] [--json FILE]
"""
import argparse
import itertools
import json
import os
import subprocess
import tempfile


def run(solver, ranks, system, preset, overrides, max_iterations):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "report.json")
        cmd = [solver, "--system", system, "--preset", preset, "--json", out,
               "--max-iterations", str(max_iterations)]
        for o in overrides:
            cmd += ["--set", o]
        if ranks > 1:
            cmd = ["mpirun", "-np", str(ranks), "--oversubscribe"] + cmd
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if not os.path.exists(out):
            return {"error": (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no output"]}
        with open(out) as f:
            rep = json.load(f)
        return {"converged": rep["converged"], "iterations": rep["iterations"],
                "seconds": rep["setup_seconds"] + rep["solve_seconds"],
                "residual": rep["relative_residual"], "operator_complexity": rep["operator_complexity"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("systems", nargs="+")
    parser.add_argument("--preset", default="pa-amg(cheapsimple)")
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    parser.add_argument("--solver", default="build/apps/solve_block_system")
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--max-iterations", type=int, default=200)
    parser.add_argument("--updates", nargs="+", default=["diagonal", "absolute-row-sum"])
    parser.add_argument("--schurs", nargs="+", default=["diagonal", "absolute-row-sum", "spai"])
    parser.add_argument("--predictor-sweeps", nargs="+", type=int, default=[1, 3])
    parser.add_argument("--smoother-sweeps", nargs="+", type=int, default=[1, 3])
    parser.add_argument("--json")
    args = parser.parse_args()

    t = "template parameters/"
    rows = []
    print(f"preset {args.preset}, common overrides {args.overrides}; per system: GMRES iterations "
          f"(div: not converged in {args.max_iterations}) / setup + solve s")
    header = f"{'update':17s} {'schur':17s} {'pred':>4s} {'SIMPLE':>6s} " + " ".join(
        f"{os.path.basename(os.path.dirname(s.rstrip('/'))) + '/' + os.path.basename(s.rstrip('/')):>22s}"
        for s in args.systems)
    print(header, flush=True)
    for update, schur, pred, sweeps in itertools.product(args.updates, args.schurs, args.predictor_sweeps,
                                                         args.smoother_sweeps):
        overrides = args.overrides + [f"{t}UPDATE_INVERSE={update}", f"{t}SCHUR_INVERSE={schur}",
                                      f"{t}PREDICTOR_SWEEPS={pred}", f"{t}SMOOTHER_SWEEPS={sweeps}"]
        cells, results = [], []
        for system in args.systems:
            r = run(args.solver, args.ranks, system, args.preset, overrides, args.max_iterations)
            results.append(r)
            if "error" in r:
                cells.append("error")
            else:
                its = str(r["iterations"]) if r["converged"] else "div"
                cells.append(f"{its} / {r['seconds']:.2f}")
        rows.append({"update": update, "schur": schur, "predictor_sweeps": pred, "smoother_sweeps": sweeps,
                     "results": results})
        print(f"{update:17s} {schur:17s} {pred:4d} {sweeps:6d} " + " ".join(f"{c:>22s}" for c in cells), flush=True)
        for r in results:
            if "error" in r:
                print("    error:", r["error"][0][:200])
    if args.json:
        with open(args.json + ".partial", "w") as f:
            json.dump({"preset": args.preset, "overrides": args.overrides, "systems": args.systems, "rows": rows},
                      f, indent=1)
        os.replace(args.json + ".partial", args.json)


if __name__ == "__main__":
    main()
