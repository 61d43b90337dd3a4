#!/usr/bin/python3
"""Everything a run directory holds, rendered in one command: for every run at or below DIR (a
directory with run_log.jsonl) the plots of plot_run.py and a picture of its last VTK step
(render_vtk.py: contact solution.pvd coloured by von Mises stress; beam/solid solid.pvd with the
beams as tubes, coloured by displacement); the AMG aggregates of the first coarse level where the
run exported them (aggregates.py); a solver comparison (compare_solvers.py) when DIR
holds several runs; the weak-scaling plot and table (weak_scaling.py plot) when DIR is a study;
and a Markdown report of all of it, report.md, with manifest.json describing every PNG.

  postprocess/render_all.py build/tests/contact_out/app --out pictures
  postprocess/render_all.py output/weak_contact3d              # a weak-scaling study

OUT defaults to DIR/postprocess. The pictures need an X server: without DISPLAY the command runs
itself under `xvfb-run -a` (Debian package xvfb). Exit status 0, 2 for bad input (one line).
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import aggregates  # noqa: E402
import compare_solvers  # noqa: E402
import plot_run  # noqa: E402
import render_vtk  # noqa: E402
import report  # noqa: E402
import weak_scaling  # noqa: E402
from runlog import InputError, RunLog, find_runs  # noqa: E402


def run_prefix(root, run_dir):
    rel = os.path.relpath(run_dir, root)
    return os.path.basename(os.path.abspath(root)) if rel == "." else rel.replace(os.sep, "_")


def pictures(run_dir, out, prefix):
    """The VTK series a run wrote, rendered: [(description, caption)]."""
    done = []
    solution, solid, beams = (os.path.join(run_dir, f) for f in ("solution.pvd", "solid.pvd", "beams.pvd"))
    if os.path.exists(solution):
        info = render_vtk.render_run_output(solution, os.path.join(out, f"{prefix}_solution.png"))
        done.append((info, f"last step, deformed, coloured by {info['field']}"))
    if os.path.exists(solid):
        info = render_vtk.render_run_output(solid, os.path.join(out, f"{prefix}_beam_solid.png"), field="displacement",
                                            beams=beams if os.path.exists(beams) else None)
        done.append((info, "last step, deformed solid (translucent) and beams as tubes, coloured by displacement"))
    if os.path.isdir(os.path.join(run_dir, "aggregates")):
        try:
            info = aggregates.render(aggregates.aggregates_file(run_dir), os.path.join(out, f"{prefix}_aggregates.png"))
        except InputError:  # e.g. a one-level hierarchy: nothing to draw
            return done
        crossing = (f", {info['crossing_bodies']} of them with nodes of two bodies"
                    if "crossing_bodies" in info else "")
        done.append((info, f"AMG aggregates of the first coarse level, field 0, last Newton system: "
                           f"{info['aggregates']} aggregates{crossing}"))
    return done


def run_section(run, out, prefix):
    s = run.summary()
    plot_infos = plot_run.plot_run(run, out, prefix) if run.solves else []
    picture_infos = pictures(run.directory, out, prefix)
    lines = [f"## Run `{prefix}` ({s['problem_class']})", "", f"Directory: `{s['directory']}`", "",
             report.table([s], report.RUN_COLUMNS), "", report.table(run.steps(), report.STEP_COLUMNS), ""]
    if s["problem_class"] == "contact" and not any(st["active"] is not None for st in run.steps()):
        lines.append("The log has no active-set sizes.")
    for e in run.events:
        lines.append(f"- event `{e['event']}` at load step {e.get('load_step')}: {e.get('reason', '')}")
    lines.append("")
    for info, caption in zip(plot_infos, ["GMRES per Newton step and active contact nodes", "Newton convergence"]):
        lines += [report.image(info, caption), ""]
    for info, caption in picture_infos:
        lines += [report.image(info, caption), ""]
    return "\n".join(lines), plot_infos + [i for i, _ in picture_infos]


def render_all(root, out):
    if not os.path.isdir(root):
        raise InputError(f"{root}: not a directory")
    runs = find_runs(root)
    is_study = os.path.exists(os.path.join(root, "study.json"))
    if not runs and not is_study:
        raise InputError(f"{root}: no run_log.jsonl at or below it and no study.json")
    os.makedirs(out, exist_ok=True)
    sections, manifest = [f"# Report: `{os.path.abspath(root)}`", ""], []
    if is_study:
        result, info, text = weak_scaling.plot(root, out)
        sections.append(text)
        manifest.append(info)
        # a study's repeated rounds: the runs its table shows, not every round
        shown = {os.path.join(os.path.abspath(root), r["run"]) for r in result["rows"]}
        runs = [r for r in runs if os.path.abspath(r) in shown]
    elif len(runs) > 1:
        text, infos = compare_solvers.compare(runs, out)
        sections.append(text)
        manifest += infos
    for run_dir in runs:
        text, infos = run_section(RunLog(run_dir), out, run_prefix(root, run_dir))
        sections.append(text)
        manifest += infos
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(sections) + "\n")
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump({"source": os.path.abspath(root), "images": manifest}, f, indent=1)
    return manifest


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory", help="a run directory, a directory of runs, or a weak-scaling study")
    ap.add_argument("--out", help="output directory (default: DIR/postprocess)")
    args = ap.parse_args(argv)
    if not os.path.isdir(args.directory):
        print(f"render_all: {args.directory}: not a directory", file=sys.stderr)
        return 2
    if render_vtk.needs_display():
        return render_vtk.rerun_under_xvfb(argv, script=os.path.abspath(__file__))
    out = args.out or os.path.join(args.directory, "postprocess")
    try:
        manifest = render_all(args.directory, out)
    except InputError as e:
        print(f"render_all: {e}", file=sys.stderr)
        return 2
    for info in manifest:
        print(os.path.join(out, info["file"]))
    print(os.path.join(out, "report.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
