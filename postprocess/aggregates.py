#!/usr/bin/python3
"""The AMG aggregates of a run (the seeds' aggregation pictures), checked and rendered.

A run with `Output/Export aggregates = true` (or `solve_block_system --export-aggregates P`)
writes, per Newton step, a VTK point set of every field's fine-level nodes with the point arrays
`field` (block index: contact 0 = displacements, 1 = multipliers at their slave nodes; FSI 0/1/2 =
structure/fluid/ALE; beam/solid 0/1 = beams/solid), `body` (the primal node's body label, -1 for
other fields), `rank` and `aggregate_level_L` (the global id of the level-L aggregate holding the
node, -1 for none). This tool

  * checks them: per field and level the number of aggregates and of nodes in none, and for the
    primal field of a contact system the aggregates that contain nodes of two bodies (the
    segregated aggregation must give none: no aggregate crosses a contact interface);
  * renders one field's aggregates of one level: each node a dot coloured by its aggregate
    (neighbouring aggregates get different colours), the other fields' nodes grey.

  postprocess/aggregates.py RUN/aggregates/step1-newton0.pvtu --level 1 --out level1.png
  postprocess/aggregates.py RUN --check            # RUN's last aggregates file; exit 1 if one crosses

Input: a .pvtu/.vtu, or a run directory (its aggregates/ folder: the last file in name order).
Exit status 0; 1 when --check finds an aggregate with nodes of two bodies; 2 for bad input.
Rendering needs an X server: without DISPLAY the tool runs itself under `xvfb-run -a`.
"""
import argparse
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import render_vtk  # noqa: E402
from runlog import InputError  # noqa: E402

# Twelve well-separated colours; aggregate ids are scrambled before picking one, so neighbouring
# aggregates (consecutive ids) rarely share a colour.
PALETTE = [(0.90, 0.10, 0.10), (0.12, 0.47, 0.71), (0.20, 0.63, 0.17), (1.00, 0.50, 0.00),
           (0.42, 0.24, 0.60), (0.65, 0.34, 0.16), (0.97, 0.51, 0.75), (0.10, 0.75, 0.75),
           (0.74, 0.74, 0.13), (0.00, 0.00, 0.55), (0.55, 0.00, 0.00), (0.00, 0.45, 0.30)]


def aggregates_file(path):
    """A .pvtu/.vtu as it is; a run directory: the last file of its aggregates/ folder."""
    if os.path.isdir(path):
        files = sorted(glob.glob(os.path.join(path, "aggregates", "*.pvtu")))
        if not files:
            raise InputError(f"{path}: no aggregates/*.pvtu (run with Output/Export aggregates = true)")
        return files[-1]
    if not os.path.exists(path):
        raise InputError(f"{path}: file not found")
    return path


def read_points(path):
    """(grid, {array name: numpy array}) of an aggregates point set."""
    from vtk.util.numpy_support import vtk_to_numpy
    grid = render_vtk.read_grid(path)
    data = grid.GetPointData()
    arrays = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)) for i in range(data.GetNumberOfArrays())}
    if "field" not in arrays:
        raise InputError(f"{path}: no 'field' array (not an aggregates file)")
    if not any(n.startswith("aggregate_level_") for n in arrays):
        raise InputError(f"{path}: the hierarchy has no coarse level (the system was solved on one level; "
                         "lower the preset's coarse size to see aggregates)")
    return grid, arrays


def levels_of(arrays):
    return sorted(int(n.rsplit("_", 1)[1]) for n in arrays if n.startswith("aggregate_level_"))


def check(arrays):
    """Per field and level: aggregates, nodes in none, and (primal field with body labels) the
    aggregates holding nodes of two bodies."""
    import numpy as np
    result = []
    for field in sorted(set(arrays["field"].tolist())):
        mask = arrays["field"] == field
        for level in levels_of(arrays):
            ids = arrays[f"aggregate_level_{level}"][mask]
            entry = {"field": int(field), "level": level, "nodes": int(mask.sum()),
                     "aggregates": int(len(np.unique(ids[ids >= 0]))), "unaggregated": int((ids < 0).sum())}
            bodies = arrays["body"][mask] if "body" in arrays else None
            if bodies is not None and (bodies >= 0).any():
                pairs = np.unique(np.stack([ids, bodies], axis=1)[(ids >= 0) & (bodies >= 0)], axis=0)
                per_aggregate = np.unique(pairs[:, 0], return_counts=True)[1]
                entry["bodies"] = int(len(np.unique(bodies[bodies >= 0])))
                entry["crossing_bodies"] = int((per_aggregate > 1).sum())
            result.append(entry)
    return result


def colour_table(ids):
    """RGB per node: a scrambled palette index per aggregate id, grey for nodes in none."""
    import numpy as np
    scrambled = (ids.astype(np.int64) * 2654435761) % 2 ** 32 % len(PALETTE)
    rgb = np.array(PALETTE)[scrambled]
    rgb[ids < 0] = (0.6, 0.6, 0.6)
    return (rgb * 255).astype(np.uint8)


def point_actor(grid, mask, rgb, size):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk
    points = vtk.vtkPoints()
    coords = render_vtk_points(grid)[mask]
    points.SetData(numpy_to_vtk(coords.copy(), deep=True))
    poly = vtk.vtkPolyData()
    poly.SetPoints(points)
    colours = numpy_to_vtk(rgb.copy(), deep=True)
    colours.SetName("colour")
    poly.GetPointData().SetScalars(colours)
    glyphs = vtk.vtkVertexGlyphFilter()
    glyphs.SetInputData(poly)
    glyphs.Update()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(glyphs.GetOutput())
    mapper.SetColorModeToDirectScalars()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetPointSize(size)
    actor.GetProperty().RenderPointsAsSpheresOn()
    return actor


def render_vtk_points(grid):
    from vtk.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(grid.GetPoints().GetData())


def render(path, out, level=1, field=0, point_size=6.0):
    import numpy as np
    grid, arrays = read_points(path)
    if level not in levels_of(arrays):
        raise InputError(f"{path}: no aggregates of level {level} (levels: {levels_of(arrays)})")
    if field not in set(arrays["field"].tolist()):
        raise InputError(f"{path}: no field {field} (fields: {sorted(set(arrays['field'].tolist()))})")
    ids = arrays[f"aggregate_level_{level}"]
    mine = arrays["field"] == field
    actors = [point_actor(grid, mine, colour_table(ids[mine]), point_size)]
    others = ~mine
    if others.any():
        grey = np.full((int(others.sum()), 3), 200, dtype=np.uint8)
        actors.append(point_actor(grid, others, grey, 0.5 * point_size))
    summary = [c for c in check(arrays) if c["field"] == field and c["level"] == level][0]
    caption = (f"{os.path.basename(path)}: field {field}, level {level}: {summary['aggregates']} aggregates "
               f"of {summary['nodes']} nodes")
    if "crossing_bodies" in summary:
        caption += f", {summary['crossing_bodies']} with nodes of two bodies ({summary['bodies']} bodies)"
    render_vtk.render(actors, [], render_vtk.is_planar(grid), out, caption)
    return {"file": os.path.basename(out), "width": render_vtk.WIDTH, "height": render_vtk.HEIGHT,
            "source": path, "level": level, "field": field, **{k: summary[k] for k in summary if k not in
                                                                ("field", "level")}}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help="an aggregates .pvtu/.vtu, or a run directory")
    ap.add_argument("--level", type=int, default=1, help="the level to render (default 1, the first coarse level)")
    ap.add_argument("--field", type=int, default=0, help="the field (block) to render (default 0)")
    ap.add_argument("--out", help="PNG to write (default: no picture, only the check)")
    ap.add_argument("--check", action="store_true", help="exit 1 if an aggregate holds nodes of two bodies")
    ap.add_argument("--json", action="store_true", help="print the check as JSON")
    args = ap.parse_args(argv)
    if args.out and render_vtk.needs_display():
        return render_vtk.rerun_under_xvfb(argv, script=os.path.abspath(__file__))
    try:
        path = aggregates_file(args.input)
        _, arrays = read_points(path)
        result = check(arrays)
        if args.out:
            render(path, args.out, args.level, args.field)
    except InputError as e:
        print(f"aggregates: {e}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps({"file": path, "levels": result}))
    else:
        print(f"aggregates: {path}")
        for c in result:
            line = (f"  field {c['field']} level {c['level']}: {c['aggregates']} aggregates of {c['nodes']} nodes, "
                    f"{c['unaggregated']} in none")
            if "crossing_bodies" in c:
                line += f"; {c['crossing_bodies']} contain nodes of two bodies ({c['bodies']} bodies)"
            print(line)
        if args.out:
            print(f"aggregates: wrote {args.out}")
    crossing = sum(c.get("crossing_bodies", 0) for c in result)
    return 1 if args.check and crossing > 0 else 0


if __name__ == "__main__":
    sys.exit(main())
