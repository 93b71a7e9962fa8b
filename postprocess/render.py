"""Render one frame of a clothsim XDMF series with ParaView: the fabric and every static mesh of the
series (the mannequin, bodies), plus optional extra meshes, seen from the front, side, back, top or at an
angle. Runs under ParaView's Python, which needs an X server for rendering:

  xvfb-run -a pvpython postprocess/render.py output/NAME/NAME.xdmf --frame -1 --view front --out front.png
  xvfb-run -a pvpython postprocess/render.py OUT.xdmf --frame 10 --view side --size 800x1200 \\
      --color-by speed --mesh input/mannequin/makehuman_body.obj --mesh-scale 0.1 --out side.png

Axes: y is up (docs/scene_format.md, gravity); the front is the +z side (the camera looks along -z), the side view looks
along -x (from +x), the back along +z, the top down along -y. --up changes the up axis.
The fabric is coloured by (--color-by):
  fabric    shaded as cloth: one colour per fabric of the scene (the run's scene, kept in the series' .h5, says which
            fabric each pattern piece is cut from), lit, with smooth normals (ParaView's surface normals), each
            piece's outline (its seams, hem and neckline) drawn as a darker line
  piece     the same, but one colour per pattern piece (the connected sets of quads of the series' topology, in
            the order of the scene's pieces)
  strain, stress, pressure
            a fit map: the per-particle fields of the series (relative stretch, membrane stress N/m, contact
            pressure on the body N/m^2), with a colour bar; the range is --range MIN MAX, else 0 up to the
            99th percentile of the frame (a few contact peaks would wash the rest out), values above drawn
            in the top colour
  speed     the particle speed |velocity| (the default)
  none      one colour
Static meshes are light grey. The camera frames the fabric (--fit fabric, the default) or everything drawn
(--fit all). Frames are numbered from 0; negative numbers count from the end (-1: the
last). Prints the frame's time and the number of points and cells drawn.

With --sequence N the tool draws N frames spread evenly over the series, or its frames up to --t-max (all of
them when there are no more)
with one camera, into --out as a printf pattern (frames_%04d.png): the pictures of a movie
(postprocess/movie.py assembles them with ffmpeg).
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


FIT_MAPS = {  # field: colour bar title
    "strain": "strain (l - l0) / l0",
    "stress": "stress, N/m",
    "pressure": "pressure on the body, N/m^2",
}
# Fabric colours of --color-by fabric (one per fabric of the scene) and piece (one per pattern piece), in turn: muted
# dyed cottons. Twelve, so that the 10 pieces of the T-shirt under the dress (input/tshirt_dress.yaml) are all told apart.
FABRIC_COLOURS = [(0.62, 0.16, 0.20), (0.18, 0.32, 0.55), (0.80, 0.62, 0.30), (0.25, 0.48, 0.36),
                  (0.50, 0.30, 0.55), (0.85, 0.45, 0.35), (0.35, 0.55, 0.70), (0.55, 0.50, 0.40),
                  (0.45, 0.50, 0.20), (0.15, 0.48, 0.50), (0.70, 0.55, 0.65), (0.30, 0.30, 0.36)]


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("xdmf", help="NAME.xdmf written by clothsim")
    p.add_argument("--frame", type=int, default=-1, help="frame index, negative from the end (default -1)")
    p.add_argument("--view", choices=sorted(VIEWS), default="front", help="camera (default front)")
    p.add_argument("--up", choices=["x", "y", "z"], default="y", help="the up axis of the scene (default y)")
    p.add_argument("--size", default="1000x1000", help="image size WIDTHxHEIGHT in pixels (default 1000x1000)")
    p.add_argument("--out", required=True, help="the PNG to write")
    p.add_argument("--color-by", choices=["speed", "none", "fabric", "piece"] + list(FIT_MAPS), default="speed", help="fabric colouring (default speed)")
    p.add_argument("--fit", choices=["fabric", "all"], default="fabric", help="what the camera frames (default fabric)")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"), help="colour range of a fit map (default 0 .. 99th percentile)")
    p.add_argument("--sequence", type=int, default=0, help="draw this many frames spread over the series into --out, a printf pattern")
    p.add_argument("--t-max", type=float, help="with --sequence: only the frames up to this time, s")
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
    if args.sequence < 0 or (args.sequence and "%" not in args.out):
        p.error("--sequence N needs N >= 1 and --out with a frame-number pattern, e.g. frames/frame_%04d.png")
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


def piece_labels(block):
    """Per point, the index of its pattern piece: the connected sets of the fabric's cells (seams are links, not
    cells), numbered by their lowest point, which follows the scene's order of pieces."""
    import numpy as np
    from vtk.util.numpy_support import vtk_to_numpy
    n = block.GetNumberOfPoints()
    parent = np.arange(n)

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    cells = vtk_to_numpy(block.GetCells().GetData()) if hasattr(block, "GetCells") else None
    offset = 0
    while cells is not None and offset < len(cells):
        count = cells[offset]
        ids = cells[offset + 1:offset + 1 + count]
        first = root(ids[0])
        for other in ids[1:]:
            r = root(other)
            if r != first:
                parent[max(r, first)] = min(r, first)
                first = min(r, first)
        offset += count + 1
    roots = np.array([root(a) for a in range(n)])
    _, labels = np.unique(roots, return_inverse=True)
    return labels


CLOTH = ("fabric", "piece")  # the colourings shaded as cloth


def scene_fabric_of_pieces(xdmf):
    """Per pattern piece in the scene's order, the index of its fabric in the scene's fabrics: (the scene is kept in
    the series' .h5 as the dataset /provenance/scene_text, in series of clothsim before 2026-11-29 as the attribute
    scene_text); None when the series does not say."""
    import h5py
    import yaml
    try:
        with h5py.File(os.path.splitext(xdmf)[0] + ".h5", "r") as f:
            text = f["provenance/scene_text"][()] if "provenance/scene_text" in f else f.attrs["scene_text"]
        scene = yaml.safe_load(text.decode() if isinstance(text, bytes) else text)
        fabrics = list(scene["fabrics"])
        return [fabrics.index(piece["fabric"]) for piece in scene["pieces"]]
    except (OSError, KeyError, ValueError, TypeError, yaml.YAMLError):
        return None


def cloth_labels(block, args):
    """Per point, its colour's index: its pattern piece's (--color-by piece) or its piece's fabric's (fabric)."""
    import numpy as np
    labels = piece_labels(block)
    if args.color_by == "fabric":
        fabric_of = scene_fabric_of_pieces(args.xdmf)
        if fabric_of is None or len(fabric_of) != labels.max() + 1:
            print(f"render.py: warning: the fabrics of {args.xdmf}'s pieces are not known: a colour per piece", file=sys.stderr)
        else:
            labels = np.asarray(fabric_of)[labels]
    return labels


def draw_outlines(pv, view, surface, shown):
    """The pattern pieces' outlines (the boundary edges of the fabric's surface: seams, hems, necklines) as dark
    lines, as a pattern's seam lines."""
    edges = pv.FeatureEdges(Input=surface)
    edges.BoundaryEdges, edges.FeatureEdges, edges.NonManifoldEdges, edges.ManifoldEdges = 1, 0, 0, 0
    shown.append(edges)
    display = pv.Show(edges, view)
    solid_colour(display, (0.12, 0.10, 0.10))
    display.LineWidth = 1.5
    display.Opacity = 0.6


def colour_fabric(pv, view, display, block, args, source):
    """Colours one fabric block as --color-by asks; returns the pipeline object to show (smooth normals for
    piece)."""
    import numpy as np
    from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    if args.color_by in CLOTH:
        labels = cloth_labels(block, args)
        array = numpy_to_vtk(labels.astype(np.float64), deep=True)
        array.SetName(args.color_by)
        block.GetPointData().AddArray(array)
        ncolours = int(labels.max()) + 1
        pv.ColorBy(display, ("POINTS", args.color_by))
        lut = pv.GetColorTransferFunction(args.color_by)
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = sum(([str(k), str(k)] for k in range(ncolours)), [])
        lut.IndexedColors = sum((list(FABRIC_COLOURS[k % len(FABRIC_COLOURS)]) for k in range(ncolours)), [])
        display.SetScalarBarVisibility(view, False)
        display.Specular = 0.05   # cotton: matt
        display.Ambient = 0.15
        display.Diffuse = 0.85
        display.Interpolation = "Gouraud"
        return
    if args.color_by in FIT_MAPS and block.GetPointData().GetArray(args.color_by) is not None:
        field = args.color_by
        values = vtk_to_numpy(block.GetPointData().GetArray(field)).ravel()
        lo, hi = args.range if args.range else (0.0, float(np.percentile(values, 99)) if len(values) else 1.0)
        if hi <= lo:
            hi = lo + (1e-12 if lo == 0 else abs(lo) * 1e-6)
        pv.ColorBy(display, ("POINTS", field))
        lut = pv.GetColorTransferFunction(field)
        lut.ApplyPreset("Turbo" if field != "strain" else "Viridis (matplotlib)", True)
        lut.RescaleTransferFunction(lo, hi)
        lut.AutomaticRescaleRangeMode = "Never"
        bar = pv.GetScalarBar(lut, view)
        bar.Title = FIT_MAPS[field]
        bar.ComponentTitle = ""
        bar.AutomaticLabelFormat = 0   # 140, 0.0173: not 1.4e+02
        bar.LabelFormat = bar.RangeLabelFormat = "%.3g"
        bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
        display.SetScalarBarVisibility(view, True)
        return
    if args.color_by == "speed" and block.GetPointData().GetArray("velocity") is not None:
        pv.ColorBy(display, ("POINTS", "velocity", "Magnitude"))
        lut = pv.GetColorTransferFunction("velocity")
        lut.ApplyPreset("Viridis (matplotlib)", True)
        display.RescaleTransferFunctionToDataRange(True, False)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = "speed, m/s"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
        display.SetScalarBarVisibility(view, True)
        return
    solid_colour(display, (0.75, 0.25, 0.2))


def draw_frame(pv, view, algorithm, time, args):
    """Shows the blocks of the series at time; returns (the sources shown, points, cells, the fabric's bounds or
    None)."""
    algorithm.UpdateTimeStep(time)
    data = algorithm.GetOutputDataObject(0)
    shown, npoints, ncells, fabric_bounds = [], 0, 0, None
    for name, block in split_blocks(data):
        if block is None or block.GetNumberOfPoints() == 0:
            continue
        copy = block.NewInstance()
        copy.DeepCopy(block)
        source = pv.TrivialProducer()
        source.GetClientSideObject().SetOutput(copy)
        shown.append(source)
        npoints += copy.GetNumberOfPoints()
        ncells += copy.GetNumberOfCells()
        if name.startswith("fabric"):
            b = copy.GetBounds()
            fabric_bounds = b if fabric_bounds is None else [f(x, y) for f, x, y in zip((min, max) * 3, fabric_bounds, b)]
            if args.color_by in CLOTH:   # smooth shading: point normals averaged over the cells around
                surface = pv.ExtractSurface(Input=source)
                smooth = pv.GenerateSurfaceNormals(Input=surface)
                smooth.Splitting = 0
                shown += [surface, smooth]
                display = pv.Show(smooth, view)
                draw_outlines(pv, view, surface, shown)
            else:
                display = pv.Show(source, view)
            if args.edges:
                display.SetRepresentationType("Surface With Edges")
                display.EdgeColor = [0.2, 0.2, 0.2]
            colour_fabric(pv, view, display, copy, args, source)
        else:
            display = pv.Show(source, view)
            solid_colour(display, (0.8, 0.8, 0.8))
    return shown, npoints, ncells, fabric_bounds


def add_meshes(pv, view, args):
    """The extra --mesh files; returns (points, cells)."""
    npoints = ncells = 0
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
    return npoints, ncells


def place_camera(pv, view, args, fabric_bounds):
    """The camera of --view, fitted to the fabric's bounds (--fit fabric) or to everything drawn."""
    direction, up = VIEWS[args.view]
    direction, up = rotate_to_up(direction, args.up), rotate_to_up(up, args.up)
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraPosition = list(direction)
    view.CameraViewUp = list(up)
    view.CameraParallelProjection = 0
    if args.fit == "fabric" and fabric_bounds is not None:
        view.ResetCamera(*fabric_bounds)
        pv.GetActiveCamera().Zoom(0.92)   # a margin: the neck and the hem off the picture's edges
    else:
        view.ResetCamera(False)
    if args.zoom != 1.0:
        pv.GetActiveCamera().Zoom(args.zoom)


def sequence_frames(nframes, count):
    """count frame indices spread evenly over nframes (all of them when count >= nframes), first and last kept."""
    if count >= nframes or nframes == 1:
        return list(range(nframes))
    if count == 1:
        return [nframes - 1]
    return sorted({round(k * (nframes - 1) / (count - 1)) for k in range(count)})


def main(argv):
    args = parse_args(argv)
    from paraview import simple as pv

    reader = pv.XDMFReader(FileNames=[os.path.abspath(args.xdmf)])
    times = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
    times = [t for t in times if t is not None] or [0.0]
    if args.sequence:
        kept = [t for t in times if args.t_max is None or t <= args.t_max] or times[:1]
        frames = sequence_frames(len(kept), args.sequence)
    else:
        if not -len(times) <= args.frame < len(times):
            sys.exit(f"render.py: frame {args.frame} out of range: {args.xdmf} has {len(times)} frames")
        frames = [args.frame % len(times)]
    algorithm = reader.GetClientSideObject()   # pvpython runs builtin: the VTK reader itself

    view = pv.CreateView("RenderView")
    view.ViewSize = [args.width, args.height]
    view.OrientationAxesVisibility = 0
    view.Background = args.background
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    extra_points, extra_cells = add_meshes(pv, view, args)
    label = text = None
    if not args.no_label:
        label = pv.Text()
        text = pv.Show(label, view)
        text.FontSize = 14
        text.Color = [0.1, 0.1, 0.1]
        text.WindowLocation = "Upper Left Corner"
    shown = []
    for count, frame in enumerate(frames):
        time = times[frame]
        for source in reversed(shown):
            pv.Delete(source)
        shown, npoints, ncells, fabric_bounds = draw_frame(pv, view, algorithm, time, args)
        if fabric_bounds is None:
            print(f"render.py: warning: no fabric block in {args.xdmf} at t = {time}", file=sys.stderr)
        if label is not None:
            label.Text = f"t = {time:.3f} s  ({os.path.basename(args.xdmf)}, frame {frame} of {len(times)})"
        if count == 0:  # one camera for a whole sequence, fitted to its first frame
            place_camera(pv, view, args, fabric_bounds)
        out = args.out % count if args.sequence else args.out
        pv.SaveScreenshot(out, view, ImageResolution=[args.width, args.height])
        print(f"render.py: {out}: {args.width}x{args.height}, view {args.view}, t = {time:g} s "
              f"(frame {frame} of {len(times)}), {npoints + extra_points} points, {ncells + extra_cells} cells")


if __name__ == "__main__":
    main(sys.argv[1:])
