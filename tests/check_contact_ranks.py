#!/usr/bin/python3
"""Runs contact_blocks with the same parameters on several rank counts (default 1 and 2,
oversubscribed where the machine has fewer cores) and checks that the partition changes nothing
but round-off and the preconditioner: every run converges the same steps at the same times with
the same Newton steps and the same number of active contact nodes in every Newton step (from
run_log.jsonl; with --newton-slack N a load step may take up to N Newton steps more or fewer if
its converged active set has the same size: GMRES solves to a relative 1e-8, so the iterates of
two partitions differ at about 1e-6, and a node at the threshold of the semi-smooth Newton
method's active-set decision can switch one Newton step later), its average GMRES iterations per
Newton step is within --gmres (relative, default 10 %) of the first run's, and its final
displacement norms (the app's "Displacement norms: l2 L, max M" line) agree to --norms
(relative, default 1e-8). With --variant S/E=V (repeatable) the runs on every rank count add
those settings and are compared with a run on the first rank count without them (e.g. a solver
option that must not change the Newton path); --min-reused N also requires at least N Newton
steps solved with a kept preconditioner ("preconditioner_reused"), each logged with zero set-up
seconds, and --min-transfers-reused N at least N solved with a hierarchy set up again on kept
transfers ("transfers_reused"), each logged with its (non-zero) set-up seconds. Prints the
figures; exit status 0 if all hold, 1 otherwise.

  check_contact_ranks.py --app build/apps/contact_blocks --mpiexec mpirun --prm apps/contact_rings_2d.prm
                         --out DIR [--ranks 1 2] [--gmres 0.1] [--norms 1e-8] [--newton-slack 0]
                         [--set S/E=V]...
"""
import argparse
import json
import os
import re
import subprocess
import sys

from app_runs import app_command


def run(args, ranks, variant=()):
    out = os.path.join(args.out, f"np{ranks}" + ("_variant" if variant else ""))
    command = app_command(args.mpiexec, ranks, args.app, args.prm, out, ["Output/VTK=false"] + args.set + list(variant))
    result = subprocess.run(command, capture_output=True, text=True)
    norms = re.search(r"Displacement norms: l2 (\S+), max (\S+)", result.stdout)
    if result.returncode != 0 or not norms or "; converged" not in result.stdout:
        print(f"the run on {ranks} ranks failed (exit {result.returncode}): {result.stderr[-600:]}")
        return None
    newton, steps, gmres, reused, reused_with_setup, transfers, transfers_without_setup = {}, [], [], 0, 0, 0, 0
    for line in open(os.path.join(out, "run_log.jsonl")):
        entry = json.loads(line)
        if "newton" in entry:
            key = (entry["load_step"], entry.get("attempt", 0))
            newton.setdefault(key, []).append(entry.get("active"))
            if "linear_iterations" in entry:
                gmres.append(entry["linear_iterations"])
            if entry.get("preconditioner_reused"):
                reused += 1
                reused_with_setup += entry.get("setup_seconds", 0) != 0
            if entry.get("transfers_reused"):
                transfers += 1
                transfers_without_setup += not entry.get("setup_seconds", 0) > 0
        elif "converged_step" in entry:
            steps.append((entry["converged_step"], round(entry["time"], 12)))
    return {"norms": tuple(float(x) for x in norms.groups()), "newton": newton, "steps": steps,
            "gmres": sum(gmres) / max(len(gmres), 1), "reused": reused, "reused_with_setup": reused_with_setup,
            "transfers": transfers, "transfers_without_setup": transfers_without_setup}


def same_newton_path(a, b, slack):
    """The active-set sizes of one load step's Newton iterates: equal, or (slack > 0) ending in the
    same converged size after at most `slack` Newton steps more or fewer."""
    if a == b:
        return True
    return slack > 0 and a is not None and b is not None and a[-1] == b[-1] and abs(len(a) - len(b)) <= slack


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--app", required=True)
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--gmres", type=float, default=0.1)
    parser.add_argument("--norms", type=float, default=1e-8)
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--variant", action="append", default=[])
    parser.add_argument("--min-reused", type=int, default=0)
    parser.add_argument("--min-transfers-reused", type=int, default=0)
    parser.add_argument("--newton-slack", type=int, default=0)
    args = parser.parse_args()
    first = args.ranks[0]
    ref = run(args, first)
    runs = {r: run(args, r, args.variant) if args.variant else (ref if r == first else run(args, r)) for r in args.ranks}
    if ref is None or any(v is None for v in runs.values()):
        return 1
    failures = []
    # What every run is compared with: the first rank count's run, without the variant if any.
    reference = f"{first} ranks" + (" without the variant" if args.variant else "")
    if args.variant:
        print(f"reference ({first} ranks, without {args.variant}): {len(ref['steps'])} steps, GMRES per Newton "
              f"step {ref['gmres']:.2f}, displacement l2 {ref['norms'][0]:.15g}, max {ref['norms'][1]:.15g}")
    for r in args.ranks:
        x = runs[r]
        iterates = sum(len(v) for v in x["newton"].values())
        print(f"{r} ranks: {len(x['steps'])} steps, {iterates} Newton iterates, GMRES per Newton step "
              f"{x['gmres']:.2f}, displacement l2 {x['norms'][0]:.15g}, max {x['norms'][1]:.15g}, "
              f"{x['reused']} solves with a kept preconditioner, {x['transfers']} with kept transfers")
        if x["reused"] < args.min_reused:
            failures.append(f"{r} ranks: {x['reused']} solves with a kept preconditioner (expected >= {args.min_reused})")
        if x["reused_with_setup"]:
            failures.append(f"{r} ranks: {x['reused_with_setup']} solves with a kept preconditioner log set-up seconds")
        if x["transfers"] < args.min_transfers_reused:
            failures.append(f"{r} ranks: {x['transfers']} solves with kept transfers "
                            f"(expected >= {args.min_transfers_reused})")
        if x["transfers_without_setup"]:
            failures.append(f"{r} ranks: {x['transfers_without_setup']} solves with kept transfers log no set-up")
        if x is ref:
            continue
        if x["steps"] != ref["steps"]:
            failures.append(f"{r} ranks: other converged steps/times than {reference}")
        differ = [k for k in sorted(set(x["newton"]) | set(ref["newton"]))
                  if not same_newton_path(x["newton"].get(k), ref["newton"].get(k), args.newton_slack)]
        if differ:
            failures.append(f"{r} ranks: Newton steps or active sets differ from {reference} in steps {differ[:5]}")
        elif x["newton"] != ref["newton"]:
            slack = [k for k in sorted(x["newton"]) if x["newton"][k] != ref["newton"][k]]
            print(f"{r} ranks: other Newton paths to the same converged active sets in steps {slack[:5]} "
                  f"(Newton iterates {[len(x['newton'][k]) for k in slack[:5]]} against "
                  f"{[len(ref['newton'][k]) for k in slack[:5]]}; allowed: {args.newton_slack} more or fewer)")
        ratio = x["gmres"] / ref["gmres"] - 1
        if abs(ratio) > args.gmres:
            failures.append(f"{r} ranks: GMRES per Newton step {ratio:+.1%} against {reference} (allowed {args.gmres:.0%})")
        for name, a, b in zip(("l2", "max"), ref["norms"], x["norms"]):
            rel = abs(a - b) / max(abs(a), 1e-300)
            if rel > args.norms:
                failures.append(f"{r} ranks: displacement {name} differs by {rel:.2e} (allowed {args.norms:.0e})")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print("rank check passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
