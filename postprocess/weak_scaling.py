#!/usr/bin/python3
"""Weak-scaling studies: the same DOFs per rank on 1, 2, 4, 8, ... ranks.

  weak_scaling.py plan    CLASS --dofs-per-rank N [--ranks 1 2 4 8]      the sizes, printed
  weak_scaling.py run     CLASS --dofs-per-rank N --out DIR [--build build] [--repeat K]
                          runs every size here with mpirun (--oversubscribe past the cores,
                          which the table marks), then collects and plots; --repeat K runs the
                          whole sequence of sizes K times, one round after the other
  weak_scaling.py slurm   CLASS --dofs-per-rank N --out DIR [--tasks-per-node 32 --time 01:00:00]
                          writes DIR/job_npR.sbatch per size, DIR/array_job.sbatch, DIR/submit_all.sh
  weak_scaling.py collect DIR      DIR/weak_scaling.json and .csv from the runs' logs, a table
  weak_scaling.py plot    DIR      DIR/weak_scaling.png and DIR/weak_scaling.md
  weak_scaling.py seeds   --out DIR   SLURM scripts of the seeds' largest configurations and the
                          DOFs per rank they imply

CLASS: contact3d (3D two-block contact benchmark, meshes/two_blocks_3d_weak.geo), rings (the
collapsing rings made wider: n columns of 4 rings, meshes/rings_2d.geo with Mesh/Gmsh variables =
nx=n, ny=4; the first 10 time steps; DOFs counted on gmsh's mesh), beam_solid (fibres in a block,
apps/beam_solid_block.prm, with Newton's line search) or fsi (the pressure-wave tube made longer at
a fixed cross-section, meshes/fsi_tube_3d.geo with Mesh/Gmsh variables = length=L; 3 time steps).
Every run has its own directory DIR/npR with the app's run_log.jsonl and job.json (ranks, exit
status, wall seconds, oversubscribed). Extra settings for every run: --set "Section/Entry=value"
(e.g. "Linear solver/Preset=..."). Exit status: 0, 1 if a run failed (or gmsh could not mesh a
rings size; one line), 2 for bad input (one line).

Figures per run: DOFs, ranks, Newton steps, step cuts, average/largest GMRES per Newton step (and
the average over the accepted steps' Newton steps only, which compares sizes whose steps were cut at
different places), setup, solve and assembly seconds (sums over the Newton steps), wall seconds,
operator complexity (largest), peak memory per rank (the largest, the rank holding it, the mean),
parallel efficiency T(1)/T(p) of the wall time and of setup + solve, and of the wall time per
Newton step (T(1)/N(1)) / (T(p)/N(p)): sizes whose Newton paths differ (a step cut at one size and
not at another, which the rings' active-set cycling does) are compared on the cost of a step.

Repeats (--repeat K, for shared machines whose speed drifts by tens of percent within minutes):
round k writes DIR/npR (k = 1) or DIR/npR-k, the rounds alternate the sizes, so that a slow
spell of the machine falls on every size alike. A size's row is its fastest run that exited 0 (its
log's figures, its wall time: interference from other jobs only ever adds time), with every
round's wall time, their median and the efficiency of the medians beside it; the row says when
the rounds took different Newton paths.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import plots  # noqa: E402
import report  # noqa: E402
import slurm_jobs  # noqa: E402
import study_classes  # noqa: E402
from runlog import InputError, RunLog  # noqa: E402

SOURCE = os.path.dirname(HERE)
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
FIELDS = ["ranks", "oversubscribed", "dofs", "dofs_per_rank", "mesh", "load_steps", "newton_steps",
          "step_cuts", "gmres_average", "gmres_max", "gmres_average_accepted", "setup_seconds", "solve_seconds",
          "assembly_seconds", "wall_seconds", "repeats", "wall_seconds_median", "efficiency_wall_median",
          "operator_complexity", "peak_memory_mb_max", "peak_memory_max_rank",
          "peak_memory_mb_mean", "efficiency_wall", "efficiency_newton", "efficiency_solve", "converged",
          "exit_status", "run"]
# What a study needs per run and where it comes from when the log lacks it.
NOT_IN_LOGS = {"ranks": "the study plan (study.json)", "wall_seconds": "job.json (measured by the launcher)"}


def parse_settings(items):
    settings = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or "/" not in key:
            raise InputError(f"--set '{item}': expected \"Section/Entry=value\"")
        settings[key] = value
    return settings


def study_description(args, cls, local=True):
    """What a study runs: the class, the app and parameter file, one entry per size (`local`: run
    here, where ranks past the cores are oversubscribed; a cluster job has a core per rank)."""
    if args.dofs_per_rank <= 0:
        raise InputError(f"--dofs-per-rank {args.dofs_per_rank}: expected a positive number")
    if any(p < 1 for p in args.ranks):
        raise InputError(f"--ranks {args.ranks}: expected positive rank counts")
    data_dir = os.path.abspath(args.data_dir)
    extra = parse_settings(args.set)
    runs = []
    for entry in study_classes.plan(cls, args.dofs_per_rank, args.ranks):
        settings = cls.settings(entry["size"], data_dir)
        settings.update({"Output/VTK": "true" if args.vtk else "false"})
        settings.update(extra)
        entry.update({"run": f"np{entry['ranks']}", "settings": settings,
                      "oversubscribed": local and entry["ranks"] > args.cores})
        runs.append(entry)
    return {"class": cls.name, "description": cls.description, "dofs_per_rank_target": args.dofs_per_rank,
            "cores": args.cores, "repeat": getattr(args, "repeat", 1),
            "directory": os.path.abspath(args.out) if args.out else None,
            "app_path": os.path.join(os.path.abspath(args.app_dir), cls.app),
            "prm_path": os.path.join(data_dir, cls.prm), "runs": runs}


def print_plan(study):
    print(f"{study['description']} ({study['class']}), target {study['dofs_per_rank_target']:.0f} DOFs per rank")
    print(f"{'ranks':>6} {'DOFs':>10} {'DOFs/rank':>10}  mesh")
    for e in study["runs"]:
        mark = "  (oversubscribed)" if e["oversubscribed"] else ""
        print(f"{e['ranks']:>6} {e['dofs']:>10} {e['dofs_per_rank']:>10.0f}  {e['mesh']}{mark}")


def write_study(study):
    os.makedirs(study["directory"], exist_ok=True)
    with open(os.path.join(study["directory"], "study.json"), "w") as f:
        json.dump(study, f, indent=1)


def round_directory(run, k):
    """The directory of round k (1, 2, ...) of a size's run: npR, then npR-2, npR-3, ..."""
    return run if k == 1 else f"{run}-{k}"


def run_locally(study, timeout):
    """Every size with mpirun here, one after the other (`repeat` rounds of them); job.json beside
    each run's log."""
    if not os.access(study["app_path"], os.X_OK):
        raise InputError(f"{study['app_path']}: no such app (build it, or name the build with --build)")
    env = dict(os.environ, **MPI_ENV)
    failed = 0
    rounds = study.get("repeat", 1)
    for k in range(1, rounds + 1):
        for e in study["runs"]:
            name = round_directory(e["run"], k)
            status, wall = run_one(study, e, os.path.join(study["directory"], name), env, timeout)
            print(f"{name}: exit {status}, {wall:.1f} s", flush=True)
            failed += status != 0
    return failed


def run_one(study, e, run_dir, env, timeout):
    """One run of size `e` into `run_dir`: the app's output, console.txt and job.json."""
    os.makedirs(run_dir, exist_ok=True)
    cmd = ["mpirun", "-np", str(e["ranks"])] + (["--oversubscribe"] if e["oversubscribed"] else [])
    cmd += [study["app_path"], study["prm_path"]]
    for key, value in dict(e["settings"], **{"Output/Directory": run_dir}).items():
        cmd += ["--set", f"{key}={value}"]
    start = time.time()
    with open(os.path.join(run_dir, "console.txt"), "w") as console:
        try:
            status = subprocess.run(cmd, stdout=console, stderr=subprocess.STDOUT, env=env, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            status = 124
    wall = time.time() - start
    with open(os.path.join(run_dir, "job.json"), "w") as f:
        json.dump({"ranks": e["ranks"], "exit_status": status, "wall_seconds": wall,
                   "oversubscribed": e["oversubscribed"], "launcher": "mpirun", "command": cmd}, f, indent=1)
    return status, wall


def load_study(directory):
    path = os.path.join(directory, "study.json")
    try:
        with open(path) as f:
            return json.load(f)
    except OSError:
        raise InputError(f"{path}: no study there (run 'weak_scaling.py run' or 'slurm' first)")
    except ValueError:
        raise InputError(f"{path}: not a JSON study description")


def run_row(directory, e, name):
    """The figures of one run of size `e` (directory `name`): the plan's ranks and mesh, the log's
    figures, the launcher's wall time."""
    run_dir = os.path.join(directory, name)
    row = {"ranks": e["ranks"], "oversubscribed": e["oversubscribed"], "mesh": e["mesh"], "run": name,
           "dofs_planned": e["dofs"]}
    job_file = os.path.join(run_dir, "job.json")
    if os.path.exists(job_file):
        with open(job_file) as f:
            job = json.load(f)
        row.update({"exit_status": job.get("exit_status"), "wall_seconds": job.get("wall_seconds")})
    if os.path.exists(os.path.join(run_dir, "run_log.jsonl")):
        s = RunLog(run_dir).summary()
        row.update({k: s[k] for k in ("dofs", "load_steps", "newton_steps", "step_cuts", "gmres_average",
                                      "gmres_max", "gmres_average_accepted", "setup_seconds", "solve_seconds",
                                      "assembly_seconds", "operator_complexity", "peak_memory_mb_max",
                                      "peak_memory_max_rank", "peak_memory_mb_mean", "converged")})
        row["preset"] = s["preset"]
        if row["dofs"] is not None:
            row["dofs_per_rank"] = row["dofs"] / e["ranks"]
    return row


def size_row(directory, e, rounds):
    """A size's row over its rounds: the fastest run that exited 0 (else the first round's), with
    every round's wall time and their median."""
    runs = [run_row(directory, e, round_directory(e["run"], k)) for k in range(1, rounds + 1)]
    runs = [r for r in runs if r.get("exit_status") is not None or r.get("gmres_average") is not None] or runs[:1]
    good = [r for r in runs if r.get("exit_status") == 0 and r.get("wall_seconds") is not None]
    row = dict(min(good, key=lambda r: r["wall_seconds"]) if good else runs[0])
    walls = sorted(r["wall_seconds"] for r in good)
    row["repeats"] = len(runs)
    row["wall_seconds_runs"] = [r.get("wall_seconds") for r in runs]
    row["wall_seconds_median"] = statistics.median(walls) if walls else None
    paths = {(r.get("newton_steps"), r.get("step_cuts"), r.get("gmres_average")) for r in good}
    row["repeats_agree"] = len(paths) <= 1
    return row


def collect(directory):
    """One row per size (the fastest of its repeated runs), the efficiencies, the CSV and JSON."""
    study = load_study(directory)
    missing = set()
    rows = [size_row(directory, e, study.get("repeat", 1)) for e in study["runs"]]
    add_efficiency(rows)
    without_log = [r["run"] for r in rows if r.get("gmres_average") is None]
    for row in rows:
        for key in FIELDS:
            row.setdefault(key, None)
            # what a finished run's log and job.json lack (not what a run not yet done lacks)
            if row[key] is None and row["run"] not in without_log and not key.startswith("efficiency_"):
                missing.add(key)
    result = {"class": study["class"], "description": study["description"],
              "dofs_per_rank_target": study["dofs_per_rank_target"], "cores": study["cores"], "rows": rows,
              "missing": sorted(missing), "not_in_logs": NOT_IN_LOGS, "runs_without_log": without_log}
    with open(os.path.join(directory, "weak_scaling.json"), "w") as f:
        json.dump(result, f, indent=1)
    with open(os.path.join(directory, "weak_scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS + ["preset", "dofs_planned"], extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    return result


def add_efficiency(rows):
    """Weak-scaling efficiency against the smallest rank count: T(p_min) / T(p) of the wall time
    (the fastest round's, and the median of the rounds), of setup + solve, and of the wall time per
    Newton step."""
    base = min(rows, key=lambda r: r["ranks"]) if rows else None
    for r in rows:
        for key, parts in (("efficiency_wall", ("wall_seconds",)), ("efficiency_solve", ("setup_seconds", "solve_seconds"))):
            if all(base.get(k) is not None and r.get(k) is not None for k in parts):
                t0, t = sum(base[k] for k in parts), sum(r[k] for k in parts)
                r[key] = t0 / t if t > 0 else None
        if base.get("wall_seconds_median") and r.get("wall_seconds_median"):
            r["efficiency_wall_median"] = base["wall_seconds_median"] / r["wall_seconds_median"]
        if r.get("efficiency_wall") is not None and base.get("newton_steps") and r.get("newton_steps"):
            r["efficiency_newton"] = r["efficiency_wall"] * r["newton_steps"] / base["newton_steps"]


def growth(rows, key):
    rows = sorted((r for r in rows if r.get(key)), key=lambda r: r["ranks"])
    return rows[-1][key] / rows[0][key] if len(rows) > 1 else None


def markdown(result, info):
    rows = sorted(result["rows"], key=lambda r: r["ranks"])
    done = [r for r in rows if r.get("gmres_average") is not None]
    lines = [f"## Weak scaling: {result['description']}", "", f"Target {result['dofs_per_rank_target']:.0f} DOFs per rank."]
    if any(r["oversubscribed"] for r in rows):
        lines.append(f"Run on {result['cores']} cores: the runs on more ranks are oversubscribed, "
                     "their times are not scaling figures.")
    lines += ["", report.table(rows, report.scaling_columns(rows)), ""]
    if any(r.get("repeats", 1) > 1 for r in rows):
        lines.append(f"Each size run {max(r['repeats'] for r in rows)} times, the rounds one after the other: "
                     "its row is its fastest run (wall s), `wall s median` and `eff. wall median` are over "
                     "every round; wall seconds of the rounds: "
                     + "; ".join(f"np{r['ranks']} " + ", ".join(f"{w:.1f}" for w in r["wall_seconds_runs"] if w is not None)
                                 for r in rows) + ".")
        differ = [f"np{r['ranks']}" for r in rows if not r.get("repeats_agree", True)]
        if differ:
            lines.append(f"The rounds took different Newton paths (steps, cuts or GMRES counts) at {', '.join(differ)}.")
    g, m = growth(done, "gmres_average"), growth(done, "peak_memory_mb_max")
    a = growth(done, "gmres_average_accepted")
    if g:
        lines.append(f"From {done[0]['ranks']} to {done[-1]['ranks']} ranks: GMRES per Newton step x {g:.2f}"
                     + (f" (accepted steps only: x {a:.2f})" if a else "")
                     + (f", largest peak memory per rank x {m:.2f}." if m else "."))
    if result["missing"]:
        lines.append(f"Not known for every run: {', '.join(result['missing'])}.")
    if result.get("runs_without_log"):
        lines.append(f"No run log (yet): {', '.join(result['runs_without_log'])}.")
    if info:
        lines += ["", report.image(info, "weak scaling")]
    return "\n".join(lines) + "\n"


def plot(directory, out=None):
    """Collects the study in `directory`, writes weak_scaling.png and weak_scaling.md into `out`
    (default: the study directory)."""
    result = collect(directory)
    done = [r for r in result["rows"] if r.get("gmres_average") is not None]
    if not done:
        raise InputError(f"{directory}: no run of the study has a run log yet (jobs not run or not finished?)")
    out = out or directory
    os.makedirs(out, exist_ok=True)
    info = plots.weak_scaling(done, os.path.join(out, "weak_scaling.png"),
                              f"weak scaling: {result['description']}, {result['dofs_per_rank_target']:.0f} DOFs/rank")
    text = markdown(result, info)
    with open(os.path.join(out, "weak_scaling.md"), "w") as f:
        f.write(text)
    return result, info, text


def print_collection(result):
    rows = sorted(result["rows"], key=lambda r: r["ranks"])
    print(report.table(rows, report.scaling_columns(rows)))
    if result["missing"]:
        print(f"missing from the logs or the study: {', '.join(result['missing'])}")
    if result["runs_without_log"]:
        print(f"runs without a run log (not run, not finished or failed early): {', '.join(result['runs_without_log'])}")


def seeds(args):
    """SLURM scripts of the seeds' largest configurations, and their DOFs per rank."""
    print(f"{'configuration':<58} {'DOFs':>11} {'ranks':>6} {'DOFs/rank':>10}  here")
    for c in study_classes.SEED_CONFIGURATIONS:
        ranks = c["ranks"] or round(c["dofs"] / args.dofs_per_rank)
        cls = study_classes.CLASSES[c["class"]]
        n = study_classes.size_for(cls, c["dofs"])
        sub = argparse.Namespace(**vars(args))
        sub.ranks, sub.out = [ranks], os.path.join(args.out, c["class"])
        sub.dofs_per_rank = cls.dofs(n)["total"] / ranks
        study = study_description(sub, cls, local=False)
        write_study(study)
        slurm_jobs.write_scripts(study, sub.out, args)
        e = study["runs"][0]
        print(f"{c['note']:<58} {c['dofs']:>11.0f} {ranks:>6} {c['dofs'] / ranks:>10.0f}  "
              f"{e['mesh']}: {e['dofs']} DOFs, {e['dofs_per_rank']:.0f} per rank, {sub.out}/job_np{ranks}.sbatch")
    return 0


def arguments():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)

    def study_options(p, needs_class=True):
        if needs_class:
            p.add_argument("problem_class", choices=sorted(study_classes.CLASSES))
            p.add_argument("--dofs-per-rank", type=float, required=True)
            p.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8])
        else:
            p.add_argument("--dofs-per-rank", type=float, default=50000)
        p.add_argument("--build", default=os.path.join(SOURCE, "build"), help="build tree (apps in BUILD/apps)")
        p.add_argument("--app-dir", help="directory of the apps (default BUILD/apps; an install: PREFIX/bin)")
        p.add_argument("--data-dir", default=SOURCE, help="directory with apps/*.prm and meshes/ (default: "
                       "this source tree; an install: PREFIX/share/saddle_point_multiphysics)")
        p.add_argument("--cores", type=int, default=os.cpu_count(), help="cores here (more ranks: oversubscribed)")
        p.add_argument("--set", action="append", default=[], help="Section/Entry=value for every run")
        p.add_argument("--vtk", action="store_true", help="keep the runs' VTK output (default: off)")

    def slurm_options(p):
        p.add_argument("--tasks-per-node", type=int, default=32)
        p.add_argument("--time", default="01:00:00", help="sbatch --time (default 01:00:00)")
        p.add_argument("--partition")
        p.add_argument("--account")
        p.add_argument("--launcher", choices=["srun", "mpirun"], default="srun")

    p = sub.add_parser("plan", help="print the sizes of a study")
    study_options(p)
    p.add_argument("--out")
    p = sub.add_parser("run", help="run a study here with mpirun, collect and plot it")
    study_options(p)
    p.add_argument("--out", required=True)
    p.add_argument("--timeout", type=float, default=3600, help="seconds per run (default 3600)")
    p.add_argument("--repeat", type=int, default=1, help="rounds of the whole sequence of sizes (default 1); "
                   "each size's row is its fastest round, with the median of the rounds beside it")
    p = sub.add_parser("slurm", help="write SLURM scripts of a study")
    study_options(p)
    slurm_options(p)
    p.add_argument("--out", required=True)
    for name in ("collect", "plot"):
        p = sub.add_parser(name, help=f"{name} a study directory")
        p.add_argument("directory")
    p = sub.add_parser("seeds", help="SLURM scripts of the seeds' largest configurations")
    study_options(p, needs_class=False)
    slurm_options(p)
    p.add_argument("--out", required=True)
    args = ap.parse_args()
    if hasattr(args, "build") and not args.app_dir:
        args.app_dir = os.path.join(args.build, "apps")
    return args


def main():
    args = arguments()
    try:
        if args.command in ("collect", "plot"):
            if args.command == "collect":
                result = collect(args.directory)
            else:
                result, _, _ = plot(args.directory)
                print(f"wrote {os.path.join(args.directory, 'weak_scaling.png')} and weak_scaling.md")
            print_collection(result)
            return 0
        if args.command == "seeds":
            return seeds(args)
        if getattr(args, "repeat", 1) < 1:
            raise InputError(f"--repeat {args.repeat}: expected a positive number of rounds")
        study = study_description(args, study_classes.CLASSES[args.problem_class], local=args.command != "slurm")
        print_plan(study)
        if args.command == "plan":
            return 0
        write_study(study)
        if args.command == "slurm":
            for path in slurm_jobs.write_scripts(study, args.out, args):
                print(path)
            return 0
        failed = run_locally(study, args.timeout)
        result, _, _ = plot(args.out)
        print_collection(result)
        return 1 if failed else 0
    except InputError as e:
        print(f"weak_scaling: {e}", file=sys.stderr)
        return 2
    except study_classes.MeshingError as e:
        print(f"weak_scaling: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
