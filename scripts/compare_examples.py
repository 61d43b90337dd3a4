#!/usr/bin/python3
"""Runs every shipped example (apps/*.prm) on 1 and 2 ranks and records what a change of the
code must not alter: Newton steps per load step, GMRES iterations per Newton step, and the final
displacement norms the apps print in full precision. Two such records (before / after a change,
e.g. from two build trees) are compared with `compare`: same Newton steps, displacements within
1e-8 relative, GMRES counts within 10 %.

  scripts/compare_examples.py run --bin build/apps --out after.json
  scripts/compare_examples.py run --bin /tmp/old/apps --out before.json --cases contact_blocks_2d
  scripts/compare_examples.py compare before.json after.json

Run from the repository root (mesh files are passed as absolute paths, so builds of older and
newer parameter-file conventions read the same meshes).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from json_output import write_json_atomically  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name: (app, parameter file, extra --set arguments). The 3D benchmark runs at level 1 so the
# whole table stays short; the impact runs 20 of its 80 time steps; fsi its 10 time steps (its
# "Displacement norms": structure l2 and max, ALE l2, fluid l2).
CASES = {
    "contact_blocks_2d": ("contact_blocks", "apps/contact_blocks_2d.prm", []),
    "contact_blocks_3d_l1": ("contact_blocks", "apps/contact_blocks_3d.prm", ["Mesh/Gmsh refinement=1"]),
    "contact_blocks_3d_l1_cheapsimple": ("contact_blocks", "apps/contact_blocks_3d.prm",
                                         ["Mesh/Gmsh refinement=1", "Linear solver/Preset=fully-coupled-sa-amg(simple)",
                                          "Linear solver/Overrides="]),
    "contact_hertz_2d": ("contact_blocks", "apps/contact_hertz_2d.prm", []),
    "contact_patch_2d": ("contact_blocks", "apps/contact_patch_2d.prm", []),
    "contact_impact_2d": ("contact_blocks", "apps/contact_impact_2d.prm", ["Loading/Load steps=20"]),
    "beam_solid_cube": ("beam_solid", "apps/beam_solid_cube.prm", []),
    "beam_solid_block": ("beam_solid", "apps/beam_solid_block.prm", []),
    "fsi_channel_2d": ("fsi", "apps/fsi_channel_2d.prm", []),
}


def mesh_file(prm):
    """The Mesh file of a parameter file as an absolute path in meshes/ (None if it has none)."""
    for line in open(os.path.join(ROOT, prm)):
        m = re.match(r"\s*set\s+Mesh file\s*=\s*(\S+)", line)
        if m:
            return os.path.join(ROOT, "meshes", os.path.basename(m.group(1)))
    return None


def run_case(bin_dir, name, ranks, out_root):
    app, prm, sets = CASES[name]
    directory = os.path.join(out_root, f"{name}-np{ranks}")
    args = [os.path.join(bin_dir, app), os.path.join(ROOT, prm), "--set", f"Output/Directory={directory}",
            "--set", "Output/VTK=false"]
    mesh = mesh_file(prm)
    if mesh:
        args += ["--set", f"Mesh/Mesh file={mesh}"]
    for s in sets:
        args += ["--set", s]
    cmd = ["mpirun", "-np", str(ranks), "--oversubscribe"] + args
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
    result = {"case": name, "ranks": ranks, "exit": proc.returncode, "wall_seconds": round(time.time() - start, 2)}
    m = re.search(r"Displacement norms: (.*)", proc.stdout)
    result["norms"] = [float(v) for v in re.findall(r"[-+0-9.eE]+(?=,|$)", m.group(1))] if m else None
    log = os.path.join(directory, "run_log.jsonl")
    rows = [json.loads(l) for l in open(log) if l.strip()] if os.path.exists(log) else []
    solves = [r for r in rows if "linear_iterations" in r]
    result["gmres"] = [r["linear_iterations"] for r in solves]
    per_step = {}
    for r in solves:
        per_step[r["load_step"]] = per_step.get(r["load_step"], 0) + 1
    result["newton_per_step"] = [per_step[k] for k in sorted(per_step)]
    if proc.returncode != 0:
        result["stderr"] = proc.stderr.strip().splitlines()[-1:] if proc.stderr.strip() else []
    return result


def cmd_run(args):
    out_root = args.work or os.path.join(ROOT, "output", "compare_examples")
    results = []
    for name in args.cases or CASES:
        for ranks in args.ranks:
            r = run_case(os.path.abspath(args.bin), name, ranks, out_root)
            results.append(r)
            print(f"{name:34s} np{ranks}: exit {r['exit']}, Newton {sum(r['newton_per_step'])}, "
                  f"GMRES {sum(r['gmres'])}, norms {r['norms']}, {r['wall_seconds']} s", flush=True)
    write_json_atomically(args.out, {"results": results})
    return 0 if all(r["exit"] == 0 for r in results) else 1


def cmd_compare(args):
    before = {(r["case"], r["ranks"]): r for r in json.load(open(args.before))["results"]}
    after = {(r["case"], r["ranks"]): r for r in json.load(open(args.after))["results"]}
    ok = True
    print("| case | ranks | Newton steps before / after | GMRES total before / after (ratio) "
          "| largest relative displacement difference | verdict |")
    print("|---|---|---|---|---|---|")
    for key in sorted(before.keys() & after.keys()):
        b, a = before[key], after[key]
        same_newton = b["newton_per_step"] == a["newton_per_step"]
        gb, ga = sum(b["gmres"]), sum(a["gmres"])
        ratio = ga / gb if gb else (1.0 if ga == 0 else float("inf"))
        if b["norms"] and a["norms"] and len(b["norms"]) == len(a["norms"]):
            diff = max(abs(x - y) / max(abs(x), 1e-300) for x, y in zip(b["norms"], a["norms"]))
        else:
            diff = float("inf")
        good = b["exit"] == a["exit"] == 0 and same_newton and abs(ratio - 1) <= 0.1 and diff <= 1e-8
        ok = ok and good
        print(f"| {key[0]} | {key[1]} | {sum(b['newton_per_step'])} / {sum(a['newton_per_step'])}"
              f"{'' if same_newton else ' (per step ' + str(b['newton_per_step']) + ' / ' + str(a['newton_per_step']) + ')'}"
              f" | {gb} / {ga} ({ratio:.3f}) | {diff:.1e} | {'same' if good else 'DIFFERENT'} |")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run the examples with the apps in --bin")
    r.add_argument("--bin", default="build/apps", help="directory holding contact_blocks, beam_solid and fsi")
    r.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    r.add_argument("--cases", nargs="+", choices=sorted(CASES), help="default: all")
    r.add_argument("--work", help="output directory of the runs (default output/compare_examples)")
    r.add_argument("--out", required=True, help="JSON record to write")
    c = sub.add_parser("compare", help="compare two records: before after")
    c.add_argument("before")
    c.add_argument("after")
    args = ap.parse_args()
    return cmd_run(args) if args.command == "run" else cmd_compare(args)


if __name__ == "__main__":
    sys.exit(main())
