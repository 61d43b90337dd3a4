"""Writing a script's results so that an interrupted run never leaves a truncated JSON file:
the data go to FILE.tmp first and replace FILE in one rename."""
import json
import os


def write_json_atomically(path, data):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(tmp, path)
