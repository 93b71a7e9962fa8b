"""Opens a clothsim XDMF series with ParaView's readers and checks it against the .h5 read by h5py.

Run with pvpython (ParaView's Python, which must also be able to import h5py and numpy):
  pvpython check_xdmf.py SERIES.xdmf --points N --cells C --times t0,t1,... [--fabric-x0 X]
Checks, with each of ParaView's XDMF readers (XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT):
  - the time steps are exactly the expected ones (within 1e-12), and the .h5 holds one frame each;
  - at the last time step: the number of points and cells (all grids together);
  - the grid "fabric": all cells quadrilaterals, positions, velocities and the scalars strain,
    body_contact, self_contact, stress and pressure equal (within 1e-12) to the last frame's datasets read from the .h5
    with h5py, and position[0, 0] equal to --fabric-x0;
  - every frame group has the integer attributes body_contacts, self_contacts, self_contact_particles
    (with --counts-are-step: equal to step, step + 1, step + 2, as tests/programs/test_output.c writes them).
Exits non-zero with a message on the first failed check.
"""
import argparse
import os
import sys

import h5py
import numpy as np
from paraview.simple import Delete, XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_QUAD, vtkCompositeDataSet

TOLERANCE = 1e-12
SCALARS = ("strain", "body_contact", "self_contact", "stress", "pressure")  # one value per particle, XDMF Scalar attributes
COUNTS = ("body_contacts", "self_contacts", "self_contact_particles")  # int64 attributes of each frame group
READERS = {
    "XDMFReader": lambda path: XDMFReader(FileNames=[path]),
    "Xdmf3ReaderS": lambda path: Xdmf3ReaderS(FileName=[path]),
    "Xdmf3ReaderT": lambda path: Xdmf3ReaderT(FileName=[path]),
}


def fail(message):
    print("check_xdmf: FAILED: " + message, file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def check_counts(h5path, name, g, counts_are_step):
    for k, count in enumerate(COUNTS):
        value = g.attrs.get(count)
        check(value is not None and np.issubdtype(np.asarray(value).dtype, np.integer) and np.ndim(value) == 0,
              f"{h5path}:/frames/{name} has no integer attribute {count}")
        if counts_are_step:
            check(int(value) == int(g.attrs["step"]) + k, f"{h5path}:/frames/{name} {count} = {value}, expected step + {k}")


def last_frame_from_h5(h5path, times, counts_are_step):
    """Checks the frame groups' times against `times` and their counts; returns (position, velocity,
    {scalar: values}) of the last."""
    with h5py.File(h5path, "r") as f:
        frames = sorted(((g.attrs["time"], name) for name, g in f["frames"].items()), key=lambda x: x[0])
        found = [t for t, _ in frames]
        check(len(found) == len(times) and np.allclose(found, times, rtol=0, atol=TOLERANCE),
              f"{h5path} holds frames at times {found}, expected {times}")
        for _, name in frames:
            check_counts(h5path, name, f["frames"][name], counts_are_step)
        last = f["frames"][frames[-1][1]]
        for name in ("position", "velocity"):
            check(last[name].dtype == np.float64 and last[name].ndim == 2 and last[name].shape[1] == 3,
                  f"{h5path}:{last.name}/{name} is {last[name].dtype} {last[name].shape}, expected float64 (N, 3)")
        for name in SCALARS:
            check(name in last and last[name].dtype == np.float64 and last[name].shape == (last["position"].shape[0], 1),
                  f"{h5path}:{last.name}/{name} is missing or not float64 (N, 1)")
        return last["position"][...], last["velocity"][...], {name: last[name][...] for name in SCALARS}


def leaves(data, name=None):
    """(name, dataset) of every leaf of a (possibly composite) dataset; name None where unnamed."""
    if not data.IsA("vtkCompositeDataSet"):
        return [(name, data)]
    found = []
    for i in range(data.GetNumberOfPieces() if data.IsA("vtkMultiPieceDataSet") else data.GetNumberOfBlocks()):
        meta = data.GetMetaData(i) if data.HasMetaData(i) else None
        child = data.GetPiece(i) if data.IsA("vtkMultiPieceDataSet") else data.GetBlock(i)
        if child is not None:
            found += leaves(child, meta.Get(vtkCompositeDataSet.NAME()) if meta is not None else None)
    return found


def fabric_block(data):
    """The grid 'fabric': named so (XDMFReader appends '[k]'), or where a reader drops the names
    (Xdmf3ReaderS merges the grids of a frame into unnamed pieces) the one grid of quadrilaterals."""
    grids = leaves(data)
    named = [d for name, d in grids if name is not None and (name == "fabric" or name.startswith("fabric["))]
    if not named:
        named = [d for _, d in grids if d.GetNumberOfCells() and all(d.GetCellType(c) == VTK_QUAD for c in range(d.GetNumberOfCells()))]
    check(len(named) == 1, f"{len(named)} fabric grids among {[(name, d.GetClassName()) for name, d in grids]}")
    return named[0]


def check_reader(name, path, args, times, position, velocity, scalars):
    reader = READERS[name](path)
    found = reader.TimestepValues
    found = list(found) if hasattr(found, "__len__") else [found]
    check(len(found) == len(times) and np.allclose(found, times, rtol=0, atol=TOLERANCE),
          f"{name}: {path} has time steps {found}, expected {times}")
    reader.UpdatePipeline(found[-1])
    info = reader.GetDataInformation()
    check(info.GetNumberOfPoints() == args.points, f"{name}: {info.GetNumberOfPoints()} points, expected {args.points}")
    check(info.GetNumberOfCells() == args.cells, f"{name}: {info.GetNumberOfCells()} cells, expected {args.cells}")
    fabric = fabric_block(reader.GetClientSideObject().GetOutputDataObject(0))
    cell_types = {fabric.GetCellType(c) for c in range(fabric.GetNumberOfCells())}
    check(cell_types == {VTK_QUAD}, f"{name}: fabric cell types {cell_types}, expected quads ({VTK_QUAD})")
    points = vtk_to_numpy(fabric.GetPoints().GetData())
    check(points.shape == position.shape and np.abs(points - position).max() <= TOLERANCE,
          f"{name}: fabric positions at t = {found[-1]} differ from the .h5")
    shown_velocity = fabric.GetPointData().GetArray("velocity")
    check(shown_velocity is not None, f"{name}: fabric has no point array 'velocity'")
    shown_velocity = vtk_to_numpy(shown_velocity)
    check(shown_velocity.shape == velocity.shape and np.abs(shown_velocity - velocity).max() <= TOLERANCE,
          f"{name}: fabric velocities at t = {found[-1]} differ from the .h5")
    for field, values in scalars.items():
        shown = fabric.GetPointData().GetArray(field)
        check(shown is not None and shown.GetNumberOfComponents() == 1, f"{name}: fabric has no scalar point array '{field}'")
        shown = vtk_to_numpy(shown).reshape(-1, 1)
        check(shown.shape == values.shape and np.abs(shown - values).max() <= TOLERANCE,
              f"{name}: fabric {field} at t = {found[-1]} differs from the .h5")
    if args.fabric_x0 is not None:
        check(abs(points[0, 0] - args.fabric_x0) <= TOLERANCE,
              f"{name}: fabric position[0, 0] = {points[0, 0]!r} at the last step, expected {args.fabric_x0!r}")
    Delete(reader)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("xdmf")
    parser.add_argument("--points", type=int, required=True, help="points at the last time step, all grids")
    parser.add_argument("--cells", type=int, required=True, help="cells at the last time step, all grids")
    parser.add_argument("--times", required=True, help="expected time steps, comma-separated")
    parser.add_argument("--fabric-x0", type=float, help="expected x of fabric particle 0 at the last time step")
    parser.add_argument("--counts-are-step", action="store_true",
                        help="the frame counts are step, step + 1, step + 2 (tests/programs/test_output.c)")
    parser.add_argument("--readers", default=",".join(READERS), help="ParaView readers to try, comma-separated")
    args = parser.parse_args()
    times = [float(t) for t in args.times.split(",")]
    check(os.path.isfile(args.xdmf), f"{args.xdmf} does not exist")
    position, velocity, scalars = last_frame_from_h5(os.path.splitext(args.xdmf)[0] + ".h5", times, args.counts_are_step)
    for name in args.readers.split(","):
        check_reader(name, args.xdmf, args, times, position, velocity, scalars)
    print(f"check_xdmf: {args.xdmf}: {args.points} points, {args.cells} cells, {len(times)} time steps, "
          f"fields velocity, {', '.join(SCALARS)}, counts {', '.join(COUNTS)}, read by {args.readers}")


if __name__ == "__main__":
    main()
