"""Writing a script's results so that an interrupted run never leaves a truncated JSON file:
the data go to a temporary beside FILE first (a name of its own, so two processes writing FILE at
once never share it) and replace FILE in one rename."""
import json
import os
import tempfile


def write_json_atomically(path, data):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)),
                               prefix=os.path.basename(path) + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, indent=1)
        umask = os.umask(0)  # mkstemp makes the file private; give it the permissions open() would
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
