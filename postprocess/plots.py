"""The figures of postprocess/ (matplotlib, no display needed: the Agg backend).

Every function draws one PNG and returns its description, read back from the figure itself
(pixel size, and per axes the title, axis labels and each drawn series with its number of
points), so that a test can check what was plotted and not only that a file exists.
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

SIZE = (8.0, 5.0)  # inches
DPI = 100          # -> 800 x 500 pixels


def describe(fig, path):
    axes = []
    for ax in fig.axes:
        series = [{"label": l.get_label(), "points": len(l.get_xdata())}
                  for l in ax.get_lines() if not l.get_label().startswith("_")]
        series += [{"label": c.get_label(), "points": len(c.patches)} for c in ax.containers]
        axes.append({"title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
                     "yscale": ax.get_yscale(), "series": series})
    width, height = (round(v) for v in fig.get_size_inches() * fig.dpi)
    return {"file": os.path.basename(path), "width": width, "height": height, "axes": axes}


def save(fig, path):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=DPI)
    info = describe(fig, path)
    plt.close(fig)
    return info


def gmres_and_active_set(run, path):
    """The seeds' result plot of the rings/tori runs: average (and largest) GMRES iterations per
    Newton step of each load/time step, with the number of active contact nodes on a second axis."""
    steps = run.steps()
    x = [s["load_step"] for s in steps]
    fig, ax = plt.subplots(figsize=SIZE)
    ax.plot(x, [s["gmres_average"] for s in steps], "o-", label="GMRES per Newton step (average)")
    ax.plot(x, [s["gmres_max"] for s in steps], "v:", label="GMRES per Newton step (largest)")
    ax.set_xlabel("load / time step")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_ylabel("GMRES iterations per Newton step")
    ax.set_ylim(bottom=0)
    ax.set_title(f"{run.name}: {run.preset or 'preset ?'}, {run.summary()['dofs']} DOFs")
    handles, labels = ax.get_legend_handles_labels()
    if any(s["active"] is not None for s in steps):
        ax2 = ax.twinx()
        ax2.plot(x, [s["active"] for s in steps], "s--", color="tab:red", label="active contact nodes")
        ax2.set_ylabel("active contact nodes")
        ax2.set_ylim(bottom=0)
        h2, l2 = ax2.get_legend_handles_labels()
        handles, labels = handles + h2, labels + l2
    ax.legend(handles, labels, loc="lower right")
    fig.tight_layout()
    return save(fig, path)


def newton_convergence(run, path):
    """Residual norm of each field over the Newton iterations of every accepted step, relative to
    the field's largest norm in that step (what the Newton test compares with its relative
    tolerance), log scale: quadratic convergence shows as the slope doubling per iteration."""
    fig, ax = plt.subplots(figsize=SIZE)
    accepted = {(s["load_step"], s["attempt"]) for s in run.steps()}
    styles = ["-", "--", ":", "-."]
    for (step, attempt), group in run.attempts():
        if (step, attempt) not in accepted:
            continue
        for k, field in enumerate(run.fields):
            norms = [l.get(f"residual_{field}", 0.0) for l in group]
            largest = max(norms) or 1.0
            values = [max(n / largest, 1e-17) for n in norms]
            ax.semilogy(range(len(values)), values, styles[k % len(styles)], marker=".",
                        color=f"C{(step - 1) % 10}", label=f"step {step}: {field}")
    ax.set_xlabel("Newton iteration")
    ax.set_ylabel("residual / largest residual of the step")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title(f"{run.name}: Newton convergence per load step")
    if len(ax.get_lines()) <= 24:
        ax.legend(fontsize="small", ncol=2)
    fig.tight_layout()
    return save(fig, path)


def solver_comparison(rows, path):
    """Bar chart over presets: average and largest GMRES per Newton step, and seconds."""
    labels = [r["label"] for r in rows]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=SIZE)
    x = range(len(rows))
    width = 0.4
    ax.bar([i - width / 2 for i in x], [r["gmres_average"] or 0 for r in rows], width, label="average")
    ax.bar([i + width / 2 for i in x], [r["gmres_max"] or 0 for r in rows], width, label="largest")
    ax.set_ylabel("GMRES iterations per Newton step")
    ax.set_title("iterations")
    ax2.bar([i - width / 2 for i in x], [r["setup_seconds"] or 0 for r in rows], width, label="setup")
    ax2.bar([i + width / 2 for i in x], [r["solve_seconds"] or 0 for r in rows], width, label="solve")
    ax2.set_ylabel("seconds (sum over Newton steps)")
    ax2.set_title("time")
    for a in (ax, ax2):
        a.set_xticks(list(x))
        a.set_xticklabels(labels, rotation=35, ha="right", fontsize="small")
        a.legend(fontsize="small")
    fig.tight_layout()
    return save(fig, path)


def weak_scaling(rows, path, title):
    """Iterations, seconds and parallel efficiency against the number of ranks (log2 axis).
    Efficiency of a weak-scaling run: E(p) = T(1) / T(p), 1 when the time stays constant; per
    Newton step (T(1) / N(1)) / (T(p) / N(p)), which does not count a different Newton path."""
    rows = sorted(rows, key=lambda r: r["ranks"])
    ranks = [r["ranks"] for r in rows]
    fig, axes = plt.subplots(1, 3, figsize=(12.0, 4.5))
    ax = axes[0]
    ax.plot(ranks, [r["gmres_average"] for r in rows], "o-", label="average")
    ax.plot(ranks, [r["gmres_max"] for r in rows], "v:", label="largest")
    if all(r.get("gmres_average_accepted") is not None for r in rows):
        ax.plot(ranks, [r["gmres_average_accepted"] for r in rows], "s--", label="average, accepted steps")
    ax.set_ylabel("GMRES iterations per Newton step")
    ax.set_ylim(bottom=0)
    ax.set_title("iterations")
    ax = axes[1]
    for key, label in (("setup_seconds", "setup"), ("solve_seconds", "solve"),
                       ("assembly_seconds", "assembly"), ("wall_seconds", "wall")):
        if all(r.get(key) is not None for r in rows):
            ax.plot(ranks, [r[key] for r in rows], "o-", label=label)
    ax.set_ylabel("seconds")
    ax.set_ylim(bottom=0)
    ax.set_title("time")
    ax = axes[2]
    for key, label in (("efficiency_wall", "wall"), ("efficiency_newton", "wall per Newton step"),
                       ("efficiency_solve", "setup + solve")):
        if all(r.get(key) is not None for r in rows):
            ax.plot(ranks, [r[key] for r in rows], "o-", label=label)
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set_ylabel("parallel efficiency T(1) / T(p)")
    ax.set_ylim(0, 1.2)
    ax.set_title("efficiency")
    for a in axes:
        a.set_xscale("log", base=2)
        a.set_xticks(ranks)
        a.set_xticklabels([str(p) + ("*" if r.get("oversubscribed") else "") for p, r in zip(ranks, rows)])
        a.set_xlabel("MPI ranks (* oversubscribed)")
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize="small")
    fig.suptitle(title)
    fig.tight_layout()
    return save(fig, path)
