"""Reading an exported BlockSystem directory (manifest.txt and its Matrix Market files, as written by
`Output/Export systems = true` or `solve_block_system --export-system`) with scipy alone; shared by the
scripts and tests that check or solve exported systems. Not a tool of its own (no command line)."""
import os
import sys

import numpy as np
import scipy.io
import scipy.sparse as sp


def read_manifest(d):
    """The blocks (name, size, dofs_per_node, nullspace and coordinates file paths or None) and the
    paths of the other files the manifest names (matrix, rhs), in manifest order."""
    blocks, files = [], {}
    with open(os.path.join(d, "manifest.txt")) as f:
        for line in f:
            w = line.split()
            if not w or w[0].startswith("#"):
                continue
            if w[0] == "block":
                optional = lambda k: os.path.join(d, w[k]) if len(w) > k and w[k] != "-" else None
                blocks.append({"name": w[1], "size": int(w[2]), "dofs_per_node": int(w[3]),
                               "nullspace": optional(4), "coordinates": optional(5)})
            elif w[0] in ("matrix", "rhs"):
                files[w[0]] = os.path.join(d, w[1])
    return blocks, files


def read_system(d, n_blocks=None, need_rhs=True):
    """The matrix (CSR), the right-hand side (None when not needed) and the blocks of directory d;
    exits with a one-line message naming the manifest when something expected is missing."""
    blocks, files = read_manifest(d)
    if "matrix" not in files or (need_rhs and "rhs" not in files) or (n_blocks and len(blocks) != n_blocks):
        sys.exit(f"{d}/manifest.txt: expected a matrix{', an rhs' if need_rhs else ''} and "
                 f"{n_blocks or 'some'} blocks, got {len(blocks)} blocks")
    A = sp.csr_matrix(scipy.io.mmread(files["matrix"]))
    b = np.asarray(scipy.io.mmread(files["rhs"])).ravel() if need_rhs else None
    return A, b, blocks
