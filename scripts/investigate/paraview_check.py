"""Opens a run's snapshots with ParaView's own XDMF reader and checks every time step against the HDF5
files it points to (docs/CASES.md, "Output"): the same particle count, positions and fields.

    pvbatch scripts/investigate/paraview_check.py OUT/snapshots/snapshots.xmf

Needs ParaView (Debian: apt-get install paraview) and h5py (python3-h5py). Prints one line per time
step and exits 1 when a step differs.
"""
import os
import sys

import h5py
import numpy as np
from paraview import servermanager
from paraview.simple import XDMFReader
from vtk.util.numpy_support import vtk_to_numpy


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    xmf = os.path.abspath(sys.argv[1])
    reader = XDMFReader(FileNames=[xmf])
    times = list(reader.TimestepValues) or [0.0]
    snapshots = sorted(f for f in os.listdir(os.path.dirname(xmf)) if f.endswith(".h5"))
    failures = 0
    for t, name in zip(times, snapshots):
        reader.UpdatePipeline(t)
        data = servermanager.Fetch(reader)
        block = data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data
        points = vtk_to_numpy(block.GetPoints().GetData())
        with h5py.File(os.path.join(os.path.dirname(xmf), name), "r") as h5:
            position = np.asarray(h5["position"])
            fields = {k: np.asarray(h5[k]) for k in h5.keys() if k != "position"}
        ok = points.shape[0] == position.shape[0] and np.array_equal(points[:, : position.shape[1]], position)
        checked = []
        for key, values in fields.items():
            array = block.GetPointData().GetArray(key)
            if array is None:
                ok = False
                checked.append(f"{key} missing")
                continue
            ok = ok and np.array_equal(vtk_to_numpy(array).reshape(values.shape), values)
            checked.append(key)
        failures += not ok
        print(f"t = {t:.6g} s, {name}: {points.shape[0]} particles, fields {', '.join(checked)}: "
              f"{'identical to the HDF5 file' if ok else 'DIFFERENT'}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
