#!/usr/bin/python3
"""Solver comparison on the 3D two-block contact benchmark (issue 3, item 4).

Runs apps/contact_blocks_3d.prm at several gmsh refinement levels with each preset and reads the
run logs (JSON lines): average and maximum GMRES iterations per Newton step, Newton steps, and
setup/solve seconds. Writes one JSON file and prints a table. Timings are from one shared machine:
compare presets within one run of this script, as ratios.

  scripts/benchmark_contact_solvers.py --build build --levels 1 2 3 --ranks 2 --out FILE
      [--presets P ...] [--set PATH=VALUE ...]

A preset given as `NAME@OVERRIDE;OVERRIDE` runs with those `Linear solver/Overrides` added (a variant
of the preset, e.g. the seeds' table settings against the shipped defaults, measured in one run):
  "pa-amg(cheapsimple)@template parameters/PREDICTOR_SWEEPS=3"
`--set` passes further app parameters to every run (e.g. "Loading/Load steps=1").
"""
import argparse
import json
import os
import subprocess
import sys
import time

from json_output import write_json_atomically

PRESETS = ["fully-coupled-sa-amg(simple)", "emin(cheapsimple)", "sa-amg(cheapsimple)", "pa-amg(cheapsimple)", "sa-amg(braess-sarazin)",
           "cheapsimple(sa-amg)", "cheapsimplec(sgs)", "direct(superlu)"]


def run(build, level, preset, variant_overrides, ranks, out_dir, extra_settings, index):
    directory = os.path.join(out_dir, f"level{level}-{index:02d}-{preset.replace('(', '_').replace(')', '')}")
    overrides = "template parameters/COARSE_MAX_SIZE=1000" if "template" in open_preset_kind(preset) else ""
    overrides = ";".join(o for o in (overrides, variant_overrides) if o)
    cmd = ["mpirun", "-np", str(ranks), "--oversubscribe", os.path.join(build, "apps", "contact_blocks"),
           "apps/contact_blocks_3d.prm", "--set", f"Mesh/Gmsh refinement={level}",
           "--set", f"Linear solver/Preset={preset}", "--set", f"Linear solver/Overrides={overrides}",
           "--set", "Linear solver/Maximum iterations=1000", "--set", f"Output/Directory={directory}",
           "--set", "Output/VTK=false"]
    for setting in extra_settings:
        cmd += ["--set", setting]
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - start
    rows = []
    log = os.path.join(directory, "run_log.jsonl")
    if os.path.exists(log):
        rows = [json.loads(line) for line in open(log) if line.strip()]
    solves = [r for r in rows if "linear_iterations" in r]
    its = [r["linear_iterations"] for r in solves]
    return {
        "level": level, "preset": preset, "variant_overrides": variant_overrides, "exit": proc.returncode, "wall_seconds": round(wall, 2),
        "dofs": solves[0]["global_size"] if solves else None,
        "newton_steps": len(solves), "gmres_average": round(sum(its) / len(its), 1) if its else None,
        "gmres_max": max(its) if its else None,
        "gmres_all_converged": all(r["linear_converged"] for r in solves),
        "setup_seconds": round(sum(r["setup_seconds"] for r in solves), 2),
        "solve_seconds": round(sum(r["solve_seconds"] for r in solves), 2),
        "operator_complexity": round(max(r.get("operator_complexity", 1.0) for r in solves), 2) if solves else None,
        "peak_memory_mb": round(max(r.get("peak_memory_mb", 0.0) for r in solves)) if solves else None,
    }


def open_preset_kind(preset):
    # Presets built from the saddle-point template accept "template parameters/..." overrides.
    return "template" if preset.endswith("(cheapsimple)") or preset.startswith(("sa-amg(", "fully-coupled")) else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--levels", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--presets", nargs="+", default=PRESETS)
    ap.add_argument("--out", default="output/benchmark_contact_solvers.json")
    ap.add_argument("--set", action="append", default=[], dest="settings",
                    help="further app parameter PATH=VALUE for every run")
    args = ap.parse_args()
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    out_dir = os.path.join(os.path.dirname(os.path.abspath(args.out)), "benchmark_contact_runs")
    results = []
    print(f"{'level':>5} {'DOFs':>8} {'preset':<24} {'Newton':>6} {'GMRES avg':>9} {'max':>5} {'setup s':>8} "
          f"{'solve s':>8} {'op.cx':>5} {'peak MB':>7} {'exit':>4}")
    for level in args.levels:
        for index, variant in enumerate(args.presets):
            preset, _, variant_overrides = variant.partition("@")
            r = run(args.build, level, preset, variant_overrides, args.ranks, out_dir, args.settings, index)
            results.append(r)
            print(f"{r['level']:>5} {str(r['dofs']):>8} {preset:<24} {r['newton_steps']:>6} "
                  f"{str(r['gmres_average']):>9} {str(r['gmres_max']):>5} {r['setup_seconds']:>8} "
                  f"{r['solve_seconds']:>8} {str(r['operator_complexity']):>5} {str(r['peak_memory_mb']):>7} "
                  f"{r['exit']:>4}" + (f"  with {variant_overrides}" if variant_overrides else ""), flush=True)
    write_json_atomically(args.out, {"ranks": args.ranks, "results": results})
    return 0 if all(r["exit"] == 0 for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
