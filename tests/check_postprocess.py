#!/usr/bin/python3
"""Checks of postprocess/ on real run output (ctest): the tools run, and what they draw is checked,
not only their exit status.

  check_postprocess.py render RUN_DIR... --work DIR [--picture] [--active] [--comparison]
      render_all.py on each run (or on the parent of several: --comparison), then every PNG of
      the manifest: a PNG of the size the manifest says, not blank (enough pixels off the
      background, enough colours), the plots' series as long as the log's accepted steps, the
      active-set series present for contact (--active), a picture of the VTK output (--picture)
      in colour, a picture of the level-1 aggregates with none across two bodies (--aggregates)
  check_postprocess.py weak --work DIR --build BUILD --class C --dofs-per-rank N --ranks 1 2
      a tiny weak-scaling study run here, collected (DOFs as the class's model predicts, one row
      per size, the figures present) and rendered
  check_postprocess.py slurm --work DIR [--build BUILD]
      SLURM scripts of both classes and of the seeds' largest configurations: `bash -n` on each,
      the #SBATCH tasks and nodes, the printed DOFs per rank; with --build, a tiny study's
      one-rank job script run here by bash (LAUNCHER="mpirun -np") and collected
  check_postprocess.py aggregates --work DIR --build BUILD [--ranks N]
      solve_block_system --export-aggregates on the four-ring contact system, then aggregates.py:
      the counts agree with the hierarchy's levels, no aggregate holds two rings, the picture is
      drawn, and a node given another ring's label is found
  check_postprocess.py cli --work DIR
      --help of every tool; each tool on a missing directory: exit status 2 and one line naming it

Exit status 0 if every check passes, 1 otherwise (one line per failed check).
"""
import argparse
import json
import math
import os
import re
import statistics
import struct
import subprocess
import sys

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
POST = os.path.join(SOURCE, "postprocess")
sys.path.insert(0, POST)
from runlog import RunLog, find_runs  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def tool(name, *args, expect=0):
    cmd = [sys.executable, os.path.join(POST, name)] + [str(a) for a in args]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    check(proc.returncode == expect, f"{name} {' '.join(map(str, args))}: exit {proc.returncode}, expected {expect}\n"
          f"{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    return proc


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return struct.unpack(">II", head[16:24])


def check_png(path, width, height, picture=False):
    """A PNG of the given size whose pixels are not one background colour: at least 2 % of them
    differ from the corner pixel, and there are enough distinct colours (a rendered colour map
    has many; a plot at least lines, text and background)."""
    import matplotlib.image
    import numpy as np
    if not check(os.path.exists(path) and os.path.getsize(path) > 0, f"{path}: missing or empty"):
        return
    size = png_size(path)
    if not check(size == (width, height), f"{path}: {size} pixels, expected {(width, height)}"):
        return
    rgb = matplotlib.image.imread(path)[:, :, :3]
    off = np.any(np.abs(rgb - rgb[0, 0]) > 0.02, axis=2).mean()
    colours = len(np.unique((rgb * 255).astype(np.uint8).reshape(-1, 3), axis=0))
    check(0.02 < off < 0.98, f"{path}: {100 * off:.1f} % of the pixels differ from the background (blank?)")
    check(colours >= (64 if picture else 8), f"{path}: only {colours} colours")
    if picture:
        saturated = (rgb.max(axis=2) - rgb.min(axis=2) > 0.3).mean()
        check(saturated > 0.05, f"{path}: only {100 * saturated:.1f} % coloured pixels (expected a colour map)")


def render(args):
    roots = args.runs
    if args.comparison:
        parents = {os.path.dirname(os.path.abspath(r)) for r in roots}
        check(len(parents) == 1, f"--comparison needs runs of one parent directory, got {parents}")
        roots = [parents.pop()]
    for root in roots:
        out = os.path.join(args.work, os.path.basename(os.path.abspath(root)))
        tool("render_all.py", root, "--out", out)
        manifest_file = os.path.join(out, "manifest.json")
        if not check(os.path.exists(manifest_file), f"{manifest_file}: not written"):
            continue
        with open(manifest_file) as f:
            images = json.load(f)["images"]
        check(os.path.getsize(os.path.join(out, "report.md")) > 0, f"{out}/report.md: empty")
        report_text = open(os.path.join(out, "report.md")).read()
        for info in images:
            picture = "source" in info
            check_png(os.path.join(out, info["file"]), info["width"], info["height"], picture)
            check(f"({info['file']})" in report_text, f"{out}/report.md does not show {info['file']}")
        check_plot_content(root, images, args)
        if args.aggregates:
            drawn = [i for i in images if "level" in i]
            check(len(drawn) == 1 and drawn[0].get("crossing_bodies") == 0 and drawn[0]["aggregates"] > 0,
                  f"{out}: expected one picture of the level-1 aggregates, none across bodies: {drawn}")


def check_plot_content(root, images, args):
    names = [i["file"] for i in images]
    runs = find_runs(root)
    for run_dir in runs:
        run = RunLog(run_dir)
        steps = run.steps()
        gmres = [i for i in images if i["file"].endswith("_gmres.png") and run.name in i["file"]]
        if not check(gmres, f"{root}: no GMRES plot of {run.name} (images: {names})"):
            continue
        series = {s["label"]: s["points"] for ax in gmres[0]["axes"] for s in ax["series"]}
        check(series.get("GMRES per Newton step (average)") == len(steps),
              f"{gmres[0]['file']}: {series} points, the log has {len(steps)} accepted steps")
        if args.active:
            check(series.get("active contact nodes") == len(steps),
                  f"{gmres[0]['file']}: no active-set series of {len(steps)} points ({series})")
        newton = [i for i in images if i["file"].endswith("_newton.png") and run.name in i["file"]]
        if check(newton, f"{root}: no Newton plot of {run.name}"):
            axis = newton[0]["axes"][0]
            check(axis["yscale"] == "log" and len(axis["series"]) == len(steps) * len(run.fields),
                  f"{newton[0]['file']}: {len(axis['series'])} series, expected {len(steps)} steps x {run.fields}")
    if args.picture:
        check(any("source" in i for i in images), f"{root}: no picture of the VTK output (images: {names})")
    if args.comparison:
        bars = [i for i in images if i["file"].startswith("solver_comparison_")]
        if check(bars, f"{root}: no solver comparison chart"):
            points = [s["points"] for s in bars[0]["axes"][0]["series"]]
            check(points == [len(runs)] * 2, f"{bars[0]['file']}: bars {points}, expected {len(runs)} runs x 2")


def weak(args):
    import study_classes
    study = os.path.join(args.work, "study")
    tool("weak_scaling.py", "run", args.problem_class, "--dofs-per-rank", args.dofs_per_rank, "--ranks", *args.ranks,
         "--build", args.build, "--cores", 1, "--out", study, "--repeat", args.repeat,
         *sum((["--set", s] for s in args.set), []))
    collection = os.path.join(study, "weak_scaling.json")
    if not check(os.path.exists(collection), f"{collection}: not written"):
        return
    with open(collection) as f:
        result = json.load(f)
    rows = sorted(result["rows"], key=lambda r: r["ranks"])
    check([r["ranks"] for r in rows] == args.ranks, f"{collection}: ranks {[r['ranks'] for r in rows]}")
    cls = study_classes.CLASSES[args.problem_class]
    for r in rows:
        size = study_classes.size_for(cls, args.dofs_per_rank * r["ranks"])
        check(r["dofs"] == cls.dofs(size)["total"],
              f"{collection}: np{r['ranks']} has {r['dofs']} DOFs, the class's model says {cls.dofs(size)['total']}")
        check(r["exit_status"] == 0 and r["converged"], f"{collection}: np{r['ranks']} did not converge")
        for key in ("newton_steps", "step_cuts", "gmres_average", "gmres_max", "gmres_average_accepted",
                    "setup_seconds", "solve_seconds", "assembly_seconds", "wall_seconds", "peak_memory_mb_max", "peak_memory_mb_mean",
                    "operator_complexity"):
            check(r.get(key) is not None, f"{collection}: np{r['ranks']} lacks {key}")
        if r["step_cuts"] == 0:
            check(abs(r["gmres_average_accepted"] - r["gmres_average"]) < 1e-9,
                  f"{collection}: np{r['ranks']} has no cut step but accepted-steps GMRES {r['gmres_average_accepted']}"
                  f" != {r['gmres_average']}")
        check(r["peak_memory_max_rank"] in range(r["ranks"]),
              f"{collection}: np{r['ranks']}: the largest peak memory on rank {r['peak_memory_max_rank']}")
        check(r["peak_memory_mb_mean"] <= r["peak_memory_mb_max"] + 1e-9,
              f"{collection}: np{r['ranks']} mean peak memory above the largest")
        check(r["oversubscribed"] == (r["ranks"] > 1), f"{collection}: np{r['ranks']} oversubscribed flag wrong")
    check(rows[0]["efficiency_wall"] == 1.0, f"{collection}: efficiency of the first size {rows[0]['efficiency_wall']}")
    for r in rows:
        expected = (rows[0]["wall_seconds"] / rows[0]["newton_steps"]) / (r["wall_seconds"] / r["newton_steps"])
        check(r.get("efficiency_newton") is not None and abs(r["efficiency_newton"] - expected) < 1e-9 * expected,
              f"{collection}: np{r['ranks']} efficiency per Newton step {r.get('efficiency_newton')}, expected {expected}")
    check(not result["missing"], f"{collection}: figures missing from the logs: {result['missing']}")
    check_repeats(study, rows, args.repeat)
    out = os.path.join(args.work, "rendered")
    tool("render_all.py", study, "--out", out)
    with open(os.path.join(out, "manifest.json")) as f:
        images = json.load(f)["images"]
    scaling = [i for i in images if i["file"] == "weak_scaling.png"]
    if check(scaling, f"{out}: no weak_scaling.png"):
        info = scaling[0]
        check_png(os.path.join(out, info["file"]), info["width"], info["height"])
        titles = [a["title"] for a in info["axes"]]
        check(titles == ["iterations", "time", "efficiency"], f"{info['file']}: axes {titles}")
        check(all(s["points"] == len(rows) for a in info["axes"] for s in a["series"]),
              f"{info['file']}: series lengths {[[s['points'] for s in a['series']] for a in info['axes']]}")
    report_text = open(os.path.join(out, "report.md")).read()
    check("oversubscribed" in report_text, f"{out}/report.md: no oversubscription mark")
    sections = re.findall(r"^## Run `([^`]+)`", report_text, re.M)
    check(sorted(sections) == sorted(r["run"] for r in rows),
          f"{out}/report.md: run sections {sections}, expected the table's runs {[r['run'] for r in rows]}")


def check_repeats(study, rows, repeat):
    """Every round ran into its own directory; a size's row is its fastest round, with the median
    of all rounds and the efficiency of the medians."""
    for r in rows:
        names = [f"np{r['ranks']}"] + [f"np{r['ranks']}-{k}" for k in range(2, repeat + 1)]
        walls = []
        for name in names:
            job = os.path.join(study, name, "job.json")
            if check(os.path.exists(job), f"{study}: round {name} has no job.json"):
                walls.append(json.load(open(job))["wall_seconds"])
        check(r["repeats"] == repeat and r["wall_seconds_runs"] == walls,
              f"np{r['ranks']}: repeats {r['repeats']}, rounds' wall seconds {r['wall_seconds_runs']}, job files {walls}")
        check(walls and r["wall_seconds"] == min(walls) and r["run"] == names[walls.index(min(walls))],
              f"np{r['ranks']}: row from {r['run']} ({r['wall_seconds']} s), rounds {walls}")
        check(walls and abs(r["wall_seconds_median"] - statistics.median(walls)) < 1e-12,
              f"np{r['ranks']}: median {r['wall_seconds_median']}, rounds {walls}")
        expected = rows[0]["wall_seconds_median"] / r["wall_seconds_median"]
        check(abs(r["efficiency_wall_median"] - expected) < 1e-12 * expected,
              f"np{r['ranks']}: efficiency of the medians {r['efficiency_wall_median']}, expected {expected}")
        check(r["repeats_agree"], f"np{r['ranks']}: the rounds took different Newton paths")


def sbatch_values(path):
    values = {}
    for line in open(path):
        m = re.match(r"#SBATCH --([a-z-]+)=(\S+)", line)
        if m:
            values[m.group(1)] = m.group(2)
    return values


def slurm(args):
    scripts = []
    for cls, dofs, ranks in (("contact3d", 20000, [1, 2, 4, 8, 64]), ("beam_solid", 20000, [1, 2, 4, 8, 64]),
                             ("fsi", 20000, [1, 2, 4, 8, 64])):
        out = os.path.join(args.work, cls)
        proc = tool("weak_scaling.py", "slurm", cls, "--dofs-per-rank", dofs, "--ranks", *ranks,
                    "--tasks-per-node", 16, "--out", out, "--partition", "batch")
        for p in ranks:
            path = os.path.join(out, f"job_np{p}.sbatch")
            if check(os.path.exists(path), f"{path}: not written"):
                v = sbatch_values(path)
                check(v.get("ntasks") == str(p) and v.get("nodes") == str(math.ceil(p / 16)),
                      f"{path}: ntasks {v.get('ntasks')}, nodes {v.get('nodes')} for {p} ranks")
                check(v.get("partition") == "batch", f"{path}: no partition line")
                scripts.append(path)
        array = os.path.join(out, "array_job.sbatch")
        if check(os.path.exists(array), f"{array}: not written"):
            check(sbatch_values(array).get("array") == f"0-{len(ranks) - 1}", f"{array}: wrong --array")
            scripts.append(array)
        scripts.append(os.path.join(out, "submit_all.sh"))
        check(re.search(r"\(oversubscribed\)", proc.stdout) is None, "slurm plan marked oversubscribed runs")
    seeds = os.path.join(args.work, "seeds")
    proc = tool("weak_scaling.py", "seeds", "--out", seeds)
    for pattern in (r"7900000 +158 +50000 .*per rank", r"26398995 +1000 +26399 .*per rank",
                    r"15800000 +316 +50000 .*26029 cells along: 15800210 DOFs, 50001 per rank"):
        check(re.search(pattern, proc.stdout), f"seeds: no line matching '{pattern}' in\n{proc.stdout}")
    scripts += [os.path.join(seeds, "contact3d", "job_np158.sbatch"), os.path.join(seeds, "beam_solid", "job_np1000.sbatch"),
                os.path.join(seeds, "fsi", "job_np316.sbatch")]
    for path in scripts:
        if check(os.path.exists(path), f"{path}: not written"):
            proc = subprocess.run(["bash", "-n", path], capture_output=True, text=True)
            check(proc.returncode == 0, f"bash -n {path}: {proc.stderr.strip()}")
    check(len(scripts) >= 24, f"only {len(scripts)} scripts checked")
    if args.build:
        run_job_script(args)


def run_job_script(args):
    """A generated job script is a working script: run a tiny one here as SLURM would (bash)."""
    out = os.path.join(args.work, "local_job")
    tool("weak_scaling.py", "slurm", "beam_solid", "--dofs-per-rank", 150, "--ranks", 1, "--build", args.build,
         "--out", out)
    env = dict(os.environ, LAUNCHER="mpirun -np", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    proc = subprocess.run(["bash", os.path.join(out, "job_np1.sbatch")], capture_output=True, text=True, env=env)
    check(proc.returncode == 0, f"job_np1.sbatch run by bash: exit {proc.returncode} {proc.stderr[-1000:]}")
    tool("weak_scaling.py", "collect", out)
    collection = os.path.join(out, "weak_scaling.json")
    if check(os.path.exists(collection), f"{collection}: not written"):
        row = json.load(open(collection))["rows"][0]
        check(row["exit_status"] == 0 and row["converged"] and row["wall_seconds"] > 0 and row["dofs"] == 165,
              f"{collection}: the job's run: {row}")


TOOLS = ["render_all.py", "plot_run.py", "compare_solvers.py", "weak_scaling.py", "render_vtk.py", "aggregates.py"]


def cli(args):
    for name in TOOLS:
        proc = tool(name, "--help")
        check(proc.stdout.startswith("usage: "), f"{name} --help: no usage line first")
    missing = os.path.join(args.work, "nonexistent")
    for name, extra in (("render_all.py", []), ("plot_run.py", []), ("compare_solvers.py", []),
                        ("weak_scaling.py", ["collect"]), ("render_vtk.py", ["--out", os.path.join(args.work, "x.png")]),
                        ("aggregates.py", [])):
        target = missing if name != "render_vtk.py" else missing + ".pvd"
        words = extra[:1] + [target] + extra[1:] if name == "weak_scaling.py" else [target] + extra
        proc = tool(name, *words, expect=2)
        lines = proc.stderr.strip().splitlines()
        check(len(lines) == 1 and "nonexistent" in proc.stderr and "Traceback" not in proc.stderr,
              f"{name}: stderr is not one line naming the input: {proc.stderr!r}")
    # The rings count their DOFs on gmsh's mesh: a gmsh that fails (here one that only exits 1)
    # is one line naming the mesh, exit 1.
    fake = os.path.join(args.work, "failing_gmsh")
    os.makedirs(fake, exist_ok=True)
    with open(os.path.join(fake, "gmsh"), "w") as f:
        f.write("#!/bin/sh\necho 'Error   : no mesh today'\nexit 1\n")
    os.chmod(os.path.join(fake, "gmsh"), 0o755)
    cmd = [sys.executable, os.path.join(POST, "weak_scaling.py"), "plan", "rings", "--dofs-per-rank", "5000"]
    env = dict(os.environ, PATH=fake + os.pathsep + os.environ["PATH"])
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    lines = proc.stderr.strip().splitlines()
    check(proc.returncode == 1 and len(lines) == 1 and "rings_2d.geo" in lines[0] and "no mesh today" in lines[0],
          f"weak_scaling.py plan rings with a failing gmsh: exit {proc.returncode}, stderr {proc.stderr!r}")


def aggregates(args):
    """solve_block_system --export-aggregates on the four-ring contact system: the exported
    aggregates agree with the hierarchy (aggregates x nullspace dimension = the level's block
    rows), none contains nodes of two rings on any level, the picture is drawn, and the check
    does find a crossing once one node's body label is changed."""
    data = os.path.join(SOURCE, "tests", "data", "rings_four_bodies_step28")
    prefix = os.path.join(args.work, f"rings_np{args.ranks}")
    cmd = ["mpirun", "-np", str(args.ranks), "--oversubscribe", os.path.join(args.build, "apps", "solve_block_system"),
           "--system", data, "--preset", "emin(cheapsimple)", "--set", "template parameters/COARSE_MAX_SIZE=300",
           "--export-aggregates", prefix]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if not check(proc.returncode == 0, f"{' '.join(cmd)}: exit {proc.returncode}\n{proc.stdout}{proc.stderr}"):
        return
    # The hierarchy's block rows per level: "  1   412   11938  276 + 136".
    rows = {int(m.group(1)): (int(m.group(2)), int(m.group(3)))
            for m in re.finditer(r"^\s+(\d+)\s+\d+\s+\d+\s+(\d+) \+ (\d+)(?:  \(on \d+ of \d+ ranks\))?$", proc.stdout, re.M)}
    check(len(rows) >= 2, f"solve_block_system: expected a coarse level in the report, got {rows}")
    check(len(re.findall(r"level \d: 0 primal aggregates contain nodes of two bodies", proc.stdout)) == len(rows) - 1,
          f"solve_block_system: not every level reports 0 aggregates across bodies:\n{proc.stdout}")
    result = json.loads(tool("aggregates.py", prefix + ".pvtu", "--check", "--json").stdout)
    for c in result["levels"]:
        block_rows = rows.get(c["level"], (0, 0))[c["field"]]
        dimension = 3 if c["field"] == 0 else 2  # 2D rigid-body modes / the multipliers' translations
        check(c["aggregates"] * dimension == block_rows,
              f"field {c['field']} level {c['level']}: {c['aggregates']} aggregates x {dimension} != {block_rows} rows")
        if c["field"] == 0:
            check(c.get("crossing_bodies") == 0 and c.get("bodies") == 4,
                  f"field 0 level {c['level']}: {c.get('crossing_bodies')} aggregates across bodies, "
                  f"{c.get('bodies')} bodies (expected 0 and 4)")
            check(c["unaggregated"] == 0, f"field 0 level {c['level']}: {c['unaggregated']} nodes in no aggregate")
    png = prefix + "_level1.png"
    tool("aggregates.py", prefix + ".pvtu", "--level", "1", "--out", png)
    check_png(png, 1000, 700, picture=False)
    # The check must be able to fail: give one node of rank 0's piece the body of another node of
    # its aggregate's neighbour, so that its level-1 aggregate holds two bodies.
    crossed = os.path.join(args.work, f"crossed_np{args.ranks}")
    os.makedirs(crossed, exist_ok=True)
    stem = os.path.basename(prefix)
    for name in os.listdir(args.work):
        if name.startswith(stem + "_rank") and name.endswith(".vtu") or name == stem + ".pvtu":
            text = open(os.path.join(args.work, name)).read()
            if name == stem + "_rank0.vtu":
                head, body = text.split('Name="body" format="ascii">\n', 1)
                values, tail = body.split("\n", 1)
                labels = values.split()
                other = next(v for v in labels if v != labels[0] and v != "-1")
                text = head + 'Name="body" format="ascii">\n' + " ".join([other] + labels[1:]) + "\n" + tail
            open(os.path.join(crossed, name), "w").write(text)
    proc = tool("aggregates.py", os.path.join(crossed, stem + ".pvtu"), "--check", expect=1)
    check("1 contain nodes of two bodies" in proc.stdout, f"the changed label is not found:\n{proc.stdout}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("render")
    p.add_argument("runs", nargs="+")
    p.add_argument("--picture", action="store_true")
    p.add_argument("--active", action="store_true")
    p.add_argument("--comparison", action="store_true")
    p.add_argument("--aggregates", action="store_true")
    p = sub.add_parser("weak")
    p.add_argument("--build", required=True)
    p.add_argument("--class", dest="problem_class", required=True)
    p.add_argument("--dofs-per-rank", type=float, required=True)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--repeat", type=int, default=1)
    p = sub.add_parser("slurm")
    p.add_argument("--build")
    p = sub.add_parser("aggregates")
    p.add_argument("--build", required=True)
    p.add_argument("--ranks", type=int, default=1)
    sub.add_parser("cli")
    for p in sub.choices.values():
        p.add_argument("--work", required=True)
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    {"render": render, "weak": weak, "slurm": slurm, "cli": cli, "aggregates": aggregates}[args.mode](args)
    for f in failures:
        print(f"check_postprocess {args.mode}: {f}")
    if not failures:
        print(f"check_postprocess {args.mode}: all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
