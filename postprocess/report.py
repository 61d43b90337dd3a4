"""Markdown pieces of the reports: tables of run summaries and weak-scaling collections."""


def fmt(value, digits=3):
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if value == int(value) and abs(value) < 1e6 and digits == 0:
            return str(int(value))
        return f"{value:.{digits}g}" if abs(value) >= 1e-3 or value == 0 else f"{value:.2e}"
    return str(value)


def table(rows, columns):
    """columns: [(header, key, digits)] -> Markdown table of rows (dicts)."""
    head = "| " + " | ".join(c[0] for c in columns) + " |"
    rule = "|" + "|".join("---" for _ in columns) + "|"
    body = ["| " + " | ".join(fmt(r.get(key), digits) for _, key, digits in columns) + " |" for r in rows]
    return "\n".join([head, rule] + body)


RUN_COLUMNS = [("run", "run", 0), ("preset", "preset", 0), ("DOFs", "dofs", 0),
               ("load steps", "load_steps", 0), ("Newton steps", "newton_steps", 0),
               ("GMRES avg", "gmres_average", 3), ("GMRES max", "gmres_max", 0),
               ("setup s", "setup_seconds", 3), ("solve s", "solve_seconds", 3),
               ("assembly s", "assembly_seconds", 3), ("op. complexity", "operator_complexity", 3),
               ("peak MB/rank (max)", "peak_memory_mb_max", 4), ("converged", "converged", 0)]

STEP_COLUMNS = [("step", "load_step", 0), ("time", "time", 4), ("Newton steps", "newton_steps", 0),
                ("GMRES avg", "gmres_average", 3), ("GMRES max", "gmres_max", 0), ("active nodes", "active", 0)]

SCALING_COLUMNS = [("ranks", "ranks", 0), ("oversubscribed", "oversubscribed", 0), ("DOFs", "dofs", 0),
                   ("DOFs/rank", "dofs_per_rank", 4), ("mesh", "mesh", 0), ("Newton", "newton_steps", 0),
                   ("cuts", "step_cuts", 0), ("GMRES avg", "gmres_average", 3), ("GMRES max", "gmres_max", 0),
                   ("GMRES avg accepted", "gmres_average_accepted", 3),
                   ("setup s", "setup_seconds", 3), ("solve s", "solve_seconds", 3),
                   ("assembly s", "assembly_seconds", 3), ("wall s", "wall_seconds", 3),
                   ("op. cx", "operator_complexity", 3), ("peak MB/rank max", "peak_memory_mb_max", 4),
                   ("on rank", "peak_memory_max_rank", 0),
                   ("peak MB/rank mean", "peak_memory_mb_mean", 4),
                   ("eff. wall", "efficiency_wall", 3), ("eff. wall per Newton step", "efficiency_newton", 3),
                   ("eff. setup+solve", "efficiency_solve", 3),
                   ("exit", "exit_status", 0)]


REPEAT_COLUMNS = [("wall s median", "wall_seconds_median", 3), ("eff. wall median", "efficiency_wall_median", 3)]


def scaling_columns(rows):
    """SCALING_COLUMNS, with the repeats' median wall time and efficiency after the efficiencies
    when a study ran its sizes more than once."""
    if not any((r.get("repeats") or 1) > 1 for r in rows):
        return SCALING_COLUMNS
    at = [key for _, key, _ in SCALING_COLUMNS].index("efficiency_solve") + 1
    return SCALING_COLUMNS[:at] + REPEAT_COLUMNS + SCALING_COLUMNS[at:]


def image(info, caption):
    return f"![{caption}]({info['file']})"
