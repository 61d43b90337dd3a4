"""The command line the test scripts run an app with (check_restart.py, check_contact_ranks.py,
check_fsi_ranks.py): mpirun on `ranks` ranks (oversubscribed where the machine has fewer cores)
of APP PRM, its output in `out`, then each "Section/Entry=value" of `sets` as --set and `extra`."""


def app_command(mpiexec, ranks, app, prm, out, sets=(), extra=()):
    command = [mpiexec, "-np", str(ranks), "--oversubscribe", app, prm, "--set", f"Output/Directory={out}"]
    for s in sets:
        command += ["--set", s]
    return command + list(extra)
