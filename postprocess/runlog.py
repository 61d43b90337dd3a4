"""Reading what an app leaves in its output directory: the JSON-lines run log (`run_log.jsonl`)
and the parameters of the run (`used_parameters.prm`).

The log (physics/common/newton_solver.cc, step_driver.cc, solver_parameters.cc) has
- one line per Newton iteration: `load_step`, `attempt` (absent for the first try of a step),
  `time`, `newton` (iteration number, 0 = the residual at the step's start), `residual`,
  `residual_<field>`, `assembly_seconds`, `converged`; contact adds `active` (active slave nodes)
  and `active_changed`; a line that was followed by a linear solve also has `linear_iterations`,
  `linear_converged`, `setup_seconds`, `solve_seconds`, `global_size`, `operator_complexity`,
  `peak_memory_mb` (the largest VmHWM over the ranks), and on the run's first set-up of a fully
  coupled preset `smoother_check_seconds` (its level smoother's check, not in `setup_seconds`);
- event lines (`"event"`: `step_cut`, `step_grown`, `run_stopped`, and `timers` at the end, with
  `<section>_seconds` and `peak_memory_mb_max` / `peak_memory_mb_mean`, the peak resident memory
  per rank, largest and mean over the ranks, and `peak_memory_mb_max_rank`, the rank of the largest);
- energy lines of dynamic runs (`time_step`, `kinetic_energy`, `strain_energy`, `total_energy`).

Bad input (a missing or unreadable log) raises InputError with one line naming the file.
"""
import json
import os


class InputError(Exception):
    """A file the tools were given cannot be used; the message names it."""


def read_json_lines(path):
    try:
        with open(path) as f:
            text = f.read()
    except OSError as e:
        raise InputError(f"{path}: cannot read the run log ({e.strerror})")
    lines = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            lines.append(json.loads(line))
        except ValueError:
            raise InputError(f"{path}:{number}: not a JSON object (expected one per line)")
    return lines


def read_parameters(path):
    """deal.II's ParameterHandler listing -> {"Section/Sub/Entry": "value"}; {} if absent."""
    if not os.path.exists(path):
        return {}
    values, sections = {}, []
    with open(path) as f:
        for raw in f:
            line = raw.split("#", 1)[0].strip()
            if line.startswith("subsection "):
                sections.append(line[len("subsection "):].strip())
            elif line == "end" and sections:
                sections.pop()
            elif line.startswith("set ") and "=" in line:
                key, value = line[4:].split("=", 1)
                values["/".join(sections + [key.strip()])] = value.strip()
    return values


def mean(values):
    return sum(values) / len(values) if values else None


class RunLog:
    """One run: its Newton lines, events, timers and parameters, and figures derived from them."""

    def __init__(self, directory):
        self.directory = directory
        self.log_file = os.path.join(directory, "run_log.jsonl")
        lines = read_json_lines(self.log_file)
        if not lines:
            raise InputError(f"{self.log_file}: the run log is empty")
        self.parameters = read_parameters(os.path.join(directory, "used_parameters.prm"))
        self.newton = [l for l in lines if "newton" in l]
        self.events = [l for l in lines if "event" in l and l["event"] != "timers"]
        self.energy = [l for l in lines if "total_energy" in l]
        timers = [l for l in lines if l.get("event") == "timers"]
        self.timers = timers[-1] if timers else None
        self.solves = [l for l in self.newton if "linear_iterations" in l]
        self.fields = sorted({k[len("residual_"):] for l in self.newton for k in l if k.startswith("residual_")})

    @property
    def problem_class(self):
        if any("Fibres" in k.split("/")[0] for k in self.parameters) or "beam" in self.fields:
            return "beam_solid"
        if any("active" in l for l in self.newton):
            return "contact"
        return "unknown"

    @property
    def preset(self):
        return self.parameters.get("Linear solver/Preset")

    @property
    def name(self):
        return os.path.basename(os.path.normpath(self.directory))

    def attempts(self):
        """Newton lines grouped by (load_step, attempt), in log order: each group is one try."""
        groups = {}
        for l in self.newton:
            groups.setdefault((l.get("load_step", 0), l.get("attempt", 0)), []).append(l)
        return list(groups.items())

    def steps(self):
        """The accepted (converged) tries, one per load or time step: number, time, the GMRES
        count of each Newton step, the active set at convergence (None without contact)."""
        result = []
        for (step, attempt), group in self.attempts():
            if not group[-1].get("converged"):
                continue
            its = [l["linear_iterations"] for l in group if "linear_iterations" in l]
            result.append({"load_step": step, "attempt": attempt, "time": group[-1].get("time"),
                           "newton_steps": len(its), "gmres": its,
                           "gmres_average": mean(its), "gmres_max": max(its) if its else None,
                           "active": group[-1].get("active")})
        return result

    def summary(self):
        """The figures the comparison and weak-scaling tables show (None where the log lacks them)."""
        s = self.solves
        its = [l["linear_iterations"] for l in s]

        def total(key):
            return sum(l[key] for l in s) if s and all(key in l for l in s) else None

        def largest(key):
            values = [l[key] for l in s if key in l]
            return max(values) if values else None

        last = self.newton[-1] if self.newton else {}
        return {
            "run": self.name, "directory": os.path.abspath(self.directory),
            "problem_class": self.problem_class, "preset": self.preset,
            "dofs": s[0].get("global_size") if s else None,
            "load_steps": len(self.steps()), "newton_steps": len(s),
            "gmres_average": mean(its), "gmres_max": max(its) if its else None,
            # Over the accepted tries only: a cut step's tries (Newton from a bad active set) can
            # take many times the iterations of the converged ones, and where a step is cut
            # depends on the problem's size, so this is the figure that compares sizes.
            "gmres_average_accepted": mean([i for step in self.steps() for i in step["gmres"]]),
            "gmres_all_converged": all(l.get("linear_converged") for l in s),
            "converged": bool(last.get("converged")) and not any(e["event"] == "run_stopped" for e in self.events),
            "step_cuts": sum(1 for e in self.events if e["event"] == "step_cut"),
            # The run's preconditioner seconds: every set-up and the one check of the level smoother.
            "setup_seconds": None if total("setup_seconds") is None else
            total("setup_seconds") + sum(l.get("smoother_check_seconds", 0.0) for l in s),
            "solve_seconds": total("solve_seconds"),
            "assembly_seconds": sum(l.get("assembly_seconds", 0.0) for l in self.newton) if self.newton else None,
            "operator_complexity": largest("operator_complexity"),
            # The closing timers line has the run's peak per rank (largest and mean over the
            # ranks); older logs only the largest, after each solve.
            "peak_memory_mb_max": (self.timers or {}).get("peak_memory_mb_max", largest("peak_memory_mb")),
            "peak_memory_mb_mean": (self.timers or {}).get("peak_memory_mb_mean"),
            "peak_memory_max_rank": (self.timers or {}).get("peak_memory_mb_max_rank"),
            "active_final": last.get("active"),
            "timers": {k: v for k, v in (self.timers or {}).items() if k != "event"},
        }


def find_runs(root):
    """Every directory at or below `root` that holds a run_log.jsonl, sorted."""
    found = []
    for d, _, files in os.walk(root):
        if "run_log.jsonl" in files:
            found.append(d)
    return sorted(found)
