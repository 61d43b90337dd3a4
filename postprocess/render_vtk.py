#!/usr/bin/python3
"""Renders a run's ParaView output to a PNG, offscreen, with Debian's VTK Python bindings
(python3-vtk9): the bodies in their deformed configuration (warped by the `displacement` point
array) coloured by a point array, and the beams of a beam/solid run as tubes.

  postprocess/render_vtk.py RUN/solution.pvd --out solution.png
  postprocess/render_vtk.py RUN/solid.pvd --beams RUN/beams.pvd --field displacement --out beam_solid.png

FIELD: a point array of the data set (a vector is shown by its magnitude); `auto` takes
von_mises, else the displacement magnitude. Contact runs also have contact_pressure (nonzero on
the contact surface only). VTK needs an X server to render: without DISPLAY the tool runs itself
under `xvfb-run -a` (package xvfb), which provides one. Exit status 0 on success, 2 for bad input.
"""
import argparse
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from runlog import InputError  # noqa: E402

WIDTH, HEIGHT = 1000, 700


def series_file(path, step):
    """A .pvd names one file per time step: pick `step` (-1: the last) and return its path;
    a .pvtu/.vtu is returned as it is."""
    if not path.endswith(".pvd"):
        return path
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise InputError(f"{path}: cannot read the ParaView series ({e})")
    files = [d.get("file") for d in root.iter("DataSet")]
    if not files:
        raise InputError(f"{path}: the series lists no data set")
    if not -len(files) <= step < len(files):
        raise InputError(f"{path}: --step {step} out of range (the series has {len(files)} steps)")
    return os.path.join(os.path.dirname(path), files[step])


def read_grid(path):
    import vtk
    if not os.path.exists(path):
        raise InputError(f"{path}: file not found")
    reader = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if grid is None or grid.GetNumberOfPoints() == 0:
        raise InputError(f"{path}: no points read (expected a .pvtu or .vtu with a mesh)")
    return grid


def warped(grid, scale):
    """The deformed configuration x = X + scale * u (u: the `displacement` point array, 2D
    vectors padded to 3 components by deal.II)."""
    import vtk
    if grid.GetPointData().GetArray("displacement") is None:
        return grid
    grid.GetPointData().SetActiveVectors("displacement")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(grid)
    warp.SetScaleFactor(scale)
    warp.Update()
    return warp.GetOutput()


def merged(grid):
    """deal.II writes every cell with its own copy of its vertices (and each .pvtu piece its own
    nodes), so every cell face would look like a boundary face: merge bitwise-equal points (after
    the warp, so that nodes of two bodies in contact, which move apart by round-off at least, are
    not merged) and keep the point data of the first copy. The surface is then the bodies' own."""
    import numpy as np
    import vtk
    from vtk.util import numpy_support as ns
    points = ns.vtk_to_numpy(grid.GetPoints().GetData())
    unique, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    cells = grid.GetCells()
    offsets = ns.vtk_to_numpy(cells.GetOffsetsArray())
    connectivity = inverse.reshape(-1)[ns.vtk_to_numpy(cells.GetConnectivityArray())]
    new_cells = vtk.vtkCellArray()
    new_cells.SetData(ns.numpy_to_vtkIdTypeArray(offsets.astype(np.int64), deep=True),
                      ns.numpy_to_vtkIdTypeArray(connectivity.astype(np.int64), deep=True))
    out = vtk.vtkUnstructuredGrid()
    new_points = vtk.vtkPoints()
    new_points.SetData(ns.numpy_to_vtk(np.ascontiguousarray(unique), deep=True))
    out.SetPoints(new_points)
    types = ns.vtk_to_numpy(grid.GetCellTypesArray()).astype(np.uint8)
    out.SetCells(ns.numpy_to_vtk(types, deep=True, array_type=vtk.VTK_UNSIGNED_CHAR), new_cells)
    data = grid.GetPointData()
    for i in range(data.GetNumberOfArrays()):
        values = ns.vtk_to_numpy(data.GetArray(i))[first]
        array = ns.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(data.GetArrayName(i))
        out.GetPointData().AddArray(array)
    return out


def choose_field(grid, field, path):
    names = [grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())]
    if field == "auto":
        field = "von_mises" if "von_mises" in names else "displacement"
    if field not in names:
        raise InputError(f"{path}: no point array '{field}' (arrays: {', '.join(names)})")
    return field


def colour_by(mapper, data, field):
    """Colour by the array's values (a vector by its magnitude) over its range, rainbow from blue."""
    array = data.GetPointData().GetArray(field)
    component = -1 if array.GetNumberOfComponents() > 1 else 0
    low, high = array.GetRange(component)
    if high <= low:
        high = low + 1.0
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(field)
    if component < 0:
        mapper.GetLookupTable().SetVectorModeToMagnitude()
    mapper.SetScalarRange(low, high)
    mapper.GetLookupTable().SetHueRange(0.667, 0.0)
    mapper.ScalarVisibilityOn()


def body_actor(grid, field, opacity):
    import vtk
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    surface.Update()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(surface.GetOutput())
    colour_by(mapper, surface.GetOutput(), field)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetOpacity(opacity)
    if opacity >= 1.0:
        actor.GetProperty().EdgeVisibilityOn()
        actor.GetProperty().SetEdgeColor(0.2, 0.2, 0.2)
        actor.GetProperty().SetLineWidth(0.5)
    return actor, mapper


def tube_actor(grid, field, radius):
    """Beams: the line cells of the beam output drawn as tubes of the given radius."""
    import vtk
    geometry = vtk.vtkGeometryFilter()
    geometry.SetInputData(grid)
    geometry.Update()
    tubes = vtk.vtkTubeFilter()
    tubes.SetInputData(geometry.GetOutput())
    tubes.SetRadius(radius)
    tubes.SetNumberOfSides(12)
    tubes.CappingOn()
    tubes.Update()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(tubes.GetOutput())
    colour_by(mapper, tubes.GetOutput(), field)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    return actor, mapper


def scalar_bar(mapper, title):
    import vtk
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(mapper.GetLookupTable())
    bar.SetTitle(title)
    bar.SetNumberOfLabels(5)
    bar.SetPosition(0.88, 0.1)
    bar.SetWidth(0.1)
    bar.SetHeight(0.8)
    for p in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        p.SetColor(0, 0, 0)
    return bar


def is_planar(grid):
    low_z, high_z = grid.GetBounds()[4:6]
    return high_z - low_z < 1e-12


def render(actors, bars, planar, out, caption):
    import vtk
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    for a in actors + bars:
        renderer.AddActor(a)
    text = vtk.vtkTextActor()
    text.SetInput(caption)
    text.GetTextProperty().SetColor(0, 0, 0)
    text.GetTextProperty().SetFontSize(16)
    text.SetPosition(10, 10)
    renderer.AddActor(text)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(WIDTH, HEIGHT)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    if planar:
        camera.SetPosition(0, 0, 1)
        camera.SetFocalPoint(0, 0, 0)
        camera.SetViewUp(0, 1, 0)
    else:
        camera.SetPosition(1.0, -1.6, 0.9)  # an oblique view from the front right, z up
        camera.SetFocalPoint(0, 0, 0)
        camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(1.15 if planar else 1.0)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtk.vtkPNGWriter()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    writer.SetFileName(out)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()


def render_run_output(solid, out, field="auto", beams=None, step=-1, scale=1.0, beam_field="auto"):
    """Draws `solid` (a .pvd, .pvtu or .vtu) and optionally `beams` into `out` (PNG)."""
    solid_file = series_file(solid, step)
    grid = read_grid(solid_file)
    field = choose_field(grid, field, solid_file)
    body = merged(warped(grid, scale))
    opacity = 0.35 if beams else 1.0
    actor, mapper = body_actor(body, field, opacity)
    actors, bars = [actor], [scalar_bar(mapper, field)]
    caption = f"{os.path.basename(solid_file)}: {field}, displacement x {scale:g}"
    if beams:
        beam_file = series_file(beams, step)
        beam_grid = read_grid(beam_file)
        beam_field = choose_field(beam_grid, "displacement" if beam_field == "auto" else beam_field, beam_file)
        # The beam output is in the current configuration already: warp by (scale - 1) u.
        bounds = body.GetBounds()
        diagonal = sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5
        tube, tube_mapper = tube_actor(warped(beam_grid, scale - 1.0), beam_field, 0.006 * diagonal)
        actors.append(tube)
        bar = scalar_bar(tube_mapper, "beams: " + beam_field)
        bar.SetPosition(0.02, 0.15)
        bars.append(bar)
        caption += f"; beams (tubes): {beam_field}"
    render(actors, bars, is_planar(grid), out, caption)
    return {"file": os.path.basename(out), "width": WIDTH, "height": HEIGHT, "source": solid_file,
            "field": field, "beams": bool(beams)}


def needs_display():
    return not os.environ.get("DISPLAY")


def rerun_under_xvfb(argv, script=__file__):
    """VTK's X11 render window needs a display: run `script` with `argv` under xvfb-run."""
    if not shutil.which("xvfb-run"):
        print(f"{os.path.basename(script)}: no DISPLAY and no xvfb-run (install the Debian package xvfb)",
              file=sys.stderr)
        return 2
    cmd = ["xvfb-run", "-a", "-s", f"-screen 0 {WIDTH + 100}x{HEIGHT + 100}x24",
           sys.executable, os.path.abspath(script)] + argv
    return subprocess.run(cmd).returncode


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("series", help="solution.pvd / solid.pvd, or one .pvtu/.vtu")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--field", default="auto", help="point array to colour by (default: von_mises, else displacement)")
    ap.add_argument("--beams", help="beams.pvd (or .vtu) of a beam/solid run, drawn as tubes")
    ap.add_argument("--beam-field", default="auto", help="point array of the beams (default: displacement)")
    ap.add_argument("--step", type=int, default=-1, help="index into the series (default -1: the last step)")
    ap.add_argument("--scale", type=float, default=1.0, help="displacement scale of the deformed configuration")
    args = ap.parse_args(argv)
    for path in (args.series, args.beams):
        if path and not os.path.exists(path):
            print(f"render_vtk: {path}: file not found", file=sys.stderr)
            return 2
    if needs_display():
        return rerun_under_xvfb(argv)
    try:
        render_run_output(args.series, args.out, args.field, args.beams, args.step, args.scale, args.beam_field)
    except InputError as e:
        print(f"render_vtk: {e}", file=sys.stderr)
        return 2
    print(f"render_vtk: wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
