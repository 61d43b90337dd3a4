#!/usr/bin/python3
"""Checks a ParaView series an app wrote (what a user opens in ParaView):
  - the .pvd parses and lists STEPS datasets (if given), each of which exists and parses as XML
    (a file cut short by an interrupted run would not);
  - a .pvtu declares the point arrays ARRAYS and every piece it names exists, parses and has
    points and cells; a .vtu has the point arrays ARRAYS, points and cells;
  - with --cell-types, every ascii "types" array holds only those VTK cell types (4 = poly-line);
  - no temporary file (*.tmp, *.partial) is left in the directory.
Exit status 0 if all holds, 1 with one line per problem otherwise.

  tests/check_vtk_series.py DIR/solid.pvd --arrays displacement,von_mises [--steps 1]
  tests/check_vtk_series.py DIR/beams.pvd --arrays displacement,coupling_line_load --cell-types 4
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET


def parse(path, problems):
    if not os.path.isfile(path):
        problems.append(f"{path}: missing")
        return None
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as e:
        problems.append(f"{path}: not valid XML ({e})")
        return None


def check_piece(path, arrays, cell_types, problems):
    root = parse(path, problems)
    if root is None:
        return
    piece = root.find("./UnstructuredGrid/Piece")
    if piece is None:
        problems.append(f"{path}: no UnstructuredGrid piece")
        return
    if int(piece.get("NumberOfPoints", 0)) <= 0 or int(piece.get("NumberOfCells", 0)) <= 0:
        problems.append(f"{path}: no points or no cells")
    names = {a.get("Name") for a in piece.findall("./PointData/DataArray")}
    for name in arrays:
        if name not in names:
            problems.append(f"{path}: point array '{name}' missing (has {sorted(names)})")
    if cell_types:
        for a in piece.findall("./Cells/DataArray[@Name='types']"):
            if a.get("format") == "ascii":
                found = {int(t) for t in a.text.split()}
                if not found <= cell_types:
                    problems.append(f"{path}: cell types {sorted(found)}, expected {sorted(cell_types)}")


def check_dataset(path, arrays, cell_types, problems):
    if path.endswith(".pvtu"):
        root = parse(path, problems)
        if root is None:
            return
        names = {a.get("Name") for a in root.findall("./PUnstructuredGrid/PPointData/PDataArray")}
        for name in arrays:
            if name not in names:
                problems.append(f"{path}: point array '{name}' not declared (has {sorted(names)})")
        pieces = root.findall("./PUnstructuredGrid/Piece")
        if not pieces:
            problems.append(f"{path}: no pieces")
        for p in pieces:
            check_piece(os.path.join(os.path.dirname(path), p.get("Source")), arrays, cell_types, problems)
    else:
        check_piece(path, arrays, cell_types, problems)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pvd")
    ap.add_argument("--arrays", default="", help="comma-separated point arrays every dataset must have")
    ap.add_argument("--cell-types", default="", help="comma-separated VTK cell types allowed in ascii types arrays")
    ap.add_argument("--steps", type=int, default=None, help="number of datasets the series must list")
    args = ap.parse_args()
    arrays = [a for a in args.arrays.split(",") if a]
    cell_types = {int(t) for t in args.cell_types.split(",") if t}
    problems = []
    root = parse(args.pvd, problems)
    if root is not None:
        datasets = root.findall("./Collection/DataSet")
        if args.steps is not None and len(datasets) != args.steps:
            problems.append(f"{args.pvd}: {len(datasets)} datasets, expected {args.steps}")
        if not datasets:
            problems.append(f"{args.pvd}: empty series")
        for d in datasets:
            check_dataset(os.path.join(os.path.dirname(args.pvd), d.get("file")), arrays, cell_types, problems)
    directory = os.path.dirname(os.path.abspath(args.pvd))
    if os.path.isdir(directory):
        for name in sorted(os.listdir(directory)):
            if name.endswith(".tmp") or name.endswith(".partial"):
                problems.append(f"{os.path.join(directory, name)}: temporary file left behind")
    for p in problems:
        print(p)
    if not problems:
        print(f"{args.pvd}: series complete")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
