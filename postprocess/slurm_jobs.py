"""SLURM batch scripts of a weak-scaling study: one `sbatch` script per size, an array job that
runs all sizes, and submit_all.sh. Each run writes what a local run writes (run directory with
run_log.jsonl, and job.json with the exit status and the wall seconds), so that
`weak_scaling.py collect` reads cluster and local studies alike."""
import math
import os
import shlex


def header(name, nodes, tasks, tasks_per_node, time, output, partition, account, extra=()):
    lines = ["#!/bin/bash", f"#SBATCH --job-name={name}", f"#SBATCH --nodes={nodes}",
             f"#SBATCH --ntasks={tasks}", f"#SBATCH --ntasks-per-node={tasks_per_node}",
             f"#SBATCH --time={time}", f"#SBATCH --output={output}"]
    if partition:
        lines.append(f"#SBATCH --partition={partition}")
    if account:
        lines.append(f"#SBATCH --account={account}")
    return lines + list(extra)


def nodes_for(ranks, tasks_per_node):
    return max(1, math.ceil(ranks / tasks_per_node))


RUN_FUNCTION = r'''
# run_size RANKS RUN_DIR ARGS...: the app on RANKS ranks; job.json records the exit status and the
# wall seconds (the run log has no total time).
run_size() {
  local ranks="$1" run_dir="$2"; shift 2
  mkdir -p "$run_dir"
  local start end status
  start=$(date +%s.%N)
  set +e
  ${LAUNCHER} "$ranks" "$@" --set "Output/Directory=$run_dir" > "$run_dir/console.txt" 2>&1
  status=$?
  set -e
  end=$(date +%s.%N)
  printf '{"ranks": %d, "exit_status": %d, "wall_seconds": %s, "oversubscribed": false, "launcher": "slurm"}\n' \
    "$ranks" "$status" "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" > "$run_dir/job.json"
  return "$status"
}
'''


def launcher_line(launcher):
    if launcher == "srun":
        return 'LAUNCHER="${LAUNCHER:-srun --ntasks}"'
    return 'LAUNCHER="${LAUNCHER:-mpirun -np}"'


def app_command(app_path, prm_path, settings):
    words = [app_path, prm_path]
    for key, value in settings.items():
        words += ["--set", f"{key}={value}"]
    return " ".join(shlex.quote(w) for w in words)


def write_scripts(study, out, options):
    """study: the study description (weak_scaling.study_description); options: tasks_per_node,
    time, partition, account, launcher. Returns the paths written."""
    written = []
    tpn = options.tasks_per_node
    common = ["set -euo pipefail", launcher_line(options.launcher), RUN_FUNCTION.strip()]
    for entry in study["runs"]:
        p = entry["ranks"]
        run_dir = os.path.join(study["directory"], entry["run"])
        lines = header(f"{study['class']}-np{p}", nodes_for(p, tpn), p, min(p, tpn), options.time,
                       os.path.join(study["directory"], f"slurm-{entry['run']}-%j.out"), options.partition,
                       options.account)
        lines += [f"# {study['description']}: {entry['mesh']}, {entry['dofs']} DOFs on {p} ranks "
                  f"({entry['dofs_per_rank']:.0f} DOFs per rank)"] + common
        lines.append(f"run_size {p} {shlex.quote(run_dir)} {app_command(study['app_path'], study['prm_path'], entry['settings'])}")
        path = os.path.join(out, f"job_{entry['run']}.sbatch")
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
        written.append(path)
    written.append(write_array_job(study, out, options, common))
    submit = os.path.join(out, "submit_all.sh")
    with open(submit, "w") as f:
        f.write("#!/bin/bash\n# One job per size (each with its own allocation).\nset -euo pipefail\n"
                'cd "$(dirname "$0")"\n' + "".join(f"sbatch {os.path.basename(w)}\n" for w in written[:-1]))
    os.chmod(submit, 0o755)
    written.append(submit)
    return written


def write_array_job(study, out, options, common):
    """All sizes as one array job. SLURM gives every task of an array the same allocation, so each
    task asks for the largest size's nodes and runs its own rank count in it: simpler to submit,
    but the small sizes hold idle nodes (submit_all.sh's one job per size does not)."""
    runs = study["runs"]
    largest = max(e["ranks"] for e in runs)
    tpn = options.tasks_per_node
    lines = header(f"{study['class']}-weak", nodes_for(largest, tpn), largest, min(largest, tpn), options.time,
                   os.path.join(study["directory"], "slurm-array-%A_%a.out"), options.partition, options.account,
                   [f"#SBATCH --array=0-{len(runs) - 1}"])
    lines += [f"# {study['description']}: every size of the study, task i runs size i on its own rank count",
              "# (each task holds the largest size's allocation; submit_all.sh submits one job per size instead)."]
    lines += common
    lines.append("RANKS=(" + " ".join(str(e["ranks"]) for e in runs) + ")")
    lines.append("DIRS=(" + " ".join(shlex.quote(os.path.join(study["directory"], e["run"])) for e in runs) + ")")
    lines.append('case "${SLURM_ARRAY_TASK_ID:?not an array task}" in')
    for i, e in enumerate(runs):
        lines.append(f"  {i}) run_size \"${{RANKS[{i}]}}\" \"${{DIRS[{i}]}}\" "
                     f"{app_command(study['app_path'], study['prm_path'], e['settings'])} ;;")
    lines.append('  *) echo "no size for array task $SLURM_ARRAY_TASK_ID" >&2; exit 2 ;;')
    lines.append("esac")
    path = os.path.join(out, "array_job.sbatch")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path
