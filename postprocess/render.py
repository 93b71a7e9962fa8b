"""Render one frame of a clothsim XDMF series with ParaView: the fabric and every static mesh of the
series (the mannequin, bodies), plus optional extra meshes, seen from the front, side, back, top or at an
angle. Runs under ParaView's Python, which needs an X server for rendering:

  xvfb-run -a pvpython postprocess/render.py output/NAME/NAME.xdmf --frame -1 --view front --out front.png
  xvfb-run -a pvpython postprocess/render.py OUT.xdmf --frame 10 --view side --size 800x1200 \\
      --color-by speed --mesh input/mannequin/makehuman_body.obj --mesh-scale 0.1 --out side.png

Axes: y is up (DESIGN.md); the front is the +z side (the camera looks along -z), the side view looks
along -x (from +x), the back along +z, the top down along -y. --up changes the up axis.
The fabric is coloured by the particle speed |velocity| (--color-by speed, the default) or in one colour
(--color-by none); static meshes are light grey. Frames are numbered from 0; negative numbers count
from the end (-1: the last). Prints the frame's time and the number of points and cells drawn.
"""
import argparse
import os
import sys

VIEWS = {  # camera direction (from the focal point towards the camera), view up, for --up y
    "front": ((0, 0, 1), (0, 1, 0)),
    "back": ((0, 0, -1), (0, 1, 0)),
    "side": ((1, 0, 0), (0, 1, 0)),
    "left": ((-1, 0, 0), (0, 1, 0)),
    "top": ((0, 1, 0), (0, 0, -1)),
    "iso": ((1, 0.8, 1.4), (0, 1, 0)),
}


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("xdmf", help="NAME.xdmf written by clothsim")
    p.add_argument("--frame", type=int, default=-1, help="frame index, negative from the end (default -1)")
    p.add_argument("--view", choices=sorted(VIEWS), default="front", help="camera (default front)")
    p.add_argument("--up", choices=["x", "y", "z"], default="y", help="the up axis of the scene (default y)")
    p.add_argument("--size", default="1000x1000", help="image size WIDTHxHEIGHT in pixels (default 1000x1000)")
    p.add_argument("--out", required=True, help="the PNG to write")
    p.add_argument("--color-by", choices=["speed", "none"], default="speed", help="fabric colouring (default speed)")
    p.add_argument("--edges", action="store_true", help="draw the fabric's quad edges")
    p.add_argument("--mesh", action="append", default=[], help="extra static mesh (OBJ, STL, VTK, ...) to draw; repeatable")
    p.add_argument("--mesh-scale", type=float, default=1.0, help="scale of the --mesh files (e.g. 0.1: decimetres to metres)")
    p.add_argument("--zoom", type=float, default=1.0, help="camera zoom after fitting the scene (default 1)")
    p.add_argument("--background", default="1,1,1", help="background colour R,G,B in [0, 1] (default white)")
    p.add_argument("--no-label", action="store_true", help="omit the time label")
    args = p.parse_args(argv)
    try:
        w, h = (int(v) for v in args.size.lower().split("x"))
        assert w > 0 and h > 0
    except (ValueError, AssertionError):
        p.error(f"--size must be WIDTHxHEIGHT, e.g. 1200x1600, got {args.size}")
    args.width, args.height = w, h
    args.background = [float(v) for v in args.background.split(",")]
    if not os.path.exists(args.xdmf):
        p.error(f"{args.xdmf} not found")
    return args


def rotate_to_up(vec, up):
    """VIEWS are written for y up; map them to a scene whose up axis is x or z."""
    x, y, z = vec
    if up == "z":
        return (x, -z, y)
    if up == "x":
        return (y, -x, z)
    return (x, y, z)


def solid_colour(display, rgb):
    display.ColorArrayName = ["POINTS", ""]
    display.DiffuseColor = display.AmbientColor = list(rgb)


def split_blocks(data):
    """[(name, dataset)] of the leaves of a composite dataset (or [('fabric', data)] for a single grid)."""
    if not data.IsA("vtkCompositeDataSet"):
        return [("fabric", data)]
    out = []
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        meta = it.GetCurrentMetaData()
        name = meta.Get(data.NAME()) if meta and meta.Has(data.NAME()) else "block"
        out.append((name, it.GetCurrentDataObject()))
        it.GoToNextItem()
    return out


def main(argv):
    args = parse_args(argv)
    from paraview import simple as pv
    import vtk

    reader = pv.XDMFReader(FileNames=[os.path.abspath(args.xdmf)])
    times = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
    times = [t for t in times if t is not None] or [0.0]
    try:
        time = times[args.frame]
    except IndexError:
        sys.exit(f"render.py: frame {args.frame} out of range: {args.xdmf} has {len(times)} frames")
    algorithm = reader.GetClientSideObject()   # pvpython runs builtin: the VTK reader itself
    algorithm.UpdateTimeStep(time)
    data = algorithm.GetOutputDataObject(0)

    view = pv.CreateView("RenderView")
    view.ViewSize = [args.width, args.height]
    view.OrientationAxesVisibility = 0
    view.Background = args.background
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    npoints = ncells = 0
    fabric_seen = False
    for name, block in split_blocks(data):
        if block is None or block.GetNumberOfPoints() == 0:
            continue
        copy = block.NewInstance()
        copy.DeepCopy(block)
        source = pv.TrivialProducer()
        source.GetClientSideObject().SetOutput(copy)
        display = pv.Show(source, view)
        npoints += copy.GetNumberOfPoints()
        ncells += copy.GetNumberOfCells()
        if name.startswith("fabric"):
            fabric_seen = True
            if args.edges:
                display.SetRepresentationType("Surface With Edges")
                display.EdgeColor = [0.2, 0.2, 0.2]
            if args.color_by == "speed" and copy.GetPointData().GetArray("velocity") is not None:
                pv.ColorBy(display, ("POINTS", "velocity", "Magnitude"))
                lut = pv.GetColorTransferFunction("velocity")
                lut.ApplyPreset("Viridis (matplotlib)", True)
                display.RescaleTransferFunctionToDataRange(True, False)
                bar = pv.GetScalarBar(lut, view)
                bar.Title = "speed, m/s"
                bar.ComponentTitle = ""
                bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
                display.SetScalarBarVisibility(view, True)
            else:
                solid_colour(display, (0.75, 0.25, 0.2))
        else:
            solid_colour(display, (0.8, 0.8, 0.8))
    if not fabric_seen:
        print(f"render.py: warning: no fabric block in {args.xdmf} at t = {time}", file=sys.stderr)
    for path in args.mesh:
        mesh = pv.OpenDataFile(path)
        if mesh is None:
            sys.exit(f"render.py: ParaView cannot read {path}")
        if args.mesh_scale != 1.0:
            mesh = pv.Transform(Input=mesh)
            mesh.Transform.Scale = [args.mesh_scale] * 3
        display = pv.Show(mesh, view)
        solid_colour(display, (0.8, 0.8, 0.8))
        mesh.UpdatePipeline()
        npoints += mesh.GetDataInformation().GetNumberOfPoints()
        ncells += mesh.GetDataInformation().GetNumberOfCells()
    if not args.no_label:
        label = pv.Text(Text=f"t = {time:.3f} s  ({os.path.basename(args.xdmf)}, frame {times.index(time)} of {len(times)})")
        text = pv.Show(label, view)
        text.FontSize = 14
        text.Color = [0.1, 0.1, 0.1]
        text.WindowLocation = "Upper Left Corner"

    direction, up = VIEWS[args.view]
    direction, up = rotate_to_up(direction, args.up), rotate_to_up(up, args.up)
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraPosition = list(direction)
    view.CameraViewUp = list(up)
    view.CameraParallelProjection = 0
    view.ResetCamera(False)
    if args.zoom != 1.0:
        pv.GetActiveCamera().Zoom(args.zoom)
    pv.SaveScreenshot(args.out, view, ImageResolution=[args.width, args.height])
    print(f"render.py: {args.out}: {args.width}x{args.height}, view {args.view}, t = {time:g} s "
          f"(frame {times.index(time)} of {len(times)}), {npoints} points, {ncells} cells")


if __name__ == "__main__":
    main(sys.argv[1:])
