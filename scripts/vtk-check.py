#!/usr/bin/env python3
"""Opens solution.vtu files with VTK's own XML reader (the reader ParaView uses) and applies the
filters a ParaView user would: Warp By Vector on the displacement, Clean (merging coincident
points: a file over shared points must lose none), Connectivity (a body must stay one piece
after warping) and Contour on the von Mises stress. A solution.vtm is opened with the
multiblock reader and each body in it checked so. Not part of `cargo test` (it needs the `vtk`
Python package: `pip install vtk`; python/tests/test_vtk.py checks the multiblock's contents);
run it by hand after changing src/post/vtk.rs:

    python3 scripts/vtk-check.py out/beam/solution.vtm out/beam/solution.vtu [more ...]
"""
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy


def grids(path):
    """(label, unstructured grid) of a .vtu file, or of each body of a .vtm file."""
    if path.endswith(".vtm"):
        reader = vtk.vtkXMLMultiBlockDataReader()
        reader.SetFileName(path)
        reader.Update()
        it = reader.GetOutput().NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            data = it.GetCurrentDataObject()
            if data.IsA("vtkUnstructuredGrid"):
                name = it.GetCurrentMetaData().Get(vtk.vtkCompositeDataSet.NAME())
                yield f"{path} [{name}]", data
            it.GoToNextItem()
    else:
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        yield path, reader.GetOutput()


def check(grid):
    n_points, n_cells = grid.GetNumberOfPoints(), grid.GetNumberOfCells()
    pd = grid.GetPointData()
    arrays = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    problems = []
    if n_points == 0 or n_cells == 0:
        problems.append("empty grid")
    vector = next((a for a in arrays if "displacement" in a.lower()), None)
    if vector is None:
        problems.append(f"no displacement point array (have {arrays})")
        return problems, {}
    warp = vtk.vtkWarpVector()
    warp.SetInputData(grid)
    grid.GetPointData().SetActiveVectors(vector)
    warp.SetScaleFactor(1.0)
    warp.Update()
    p0 = vtk_to_numpy(grid.GetPoints().GetData())
    p1 = vtk_to_numpy(warp.GetOutput().GetPoints().GetData())
    u = vtk_to_numpy(pd.GetArray(vector))
    warp_error = float(abs(p1 - p0 - u).max())
    clean = vtk.vtkStaticCleanUnstructuredGrid()
    clean.SetInputData(grid)
    clean.SetTolerance(0.0)
    clean.Update()
    merged = n_points - clean.GetOutput().GetNumberOfPoints()
    conn = vtk.vtkConnectivityFilter()
    conn.SetInputConnection(warp.GetOutputPort())
    conn.SetExtractionModeToAllRegions()
    conn.Update()
    regions = conn.GetNumberOfExtractedRegions()
    stress = next((a for a in arrays if "mises" in a.lower()), None)
    contour_cells = -1
    lo = hi = 0.0
    if stress is not None:
        lo, hi = pd.GetArray(stress).GetRange()
        geom = vtk.vtkDataSetSurfaceFilter()
        geom.SetInputConnection(warp.GetOutputPort())
        contour = vtk.vtkContourFilter()
        contour.SetInputConnection(geom.GetOutputPort())
        grid.GetPointData().SetActiveScalars(stress)
        contour.SetInputArrayToProcess(0, 0, 0, 0, stress)
        contour.SetValue(0, 0.5 * (lo + hi))
        contour.Update()
        contour_cells = contour.GetOutput().GetNumberOfCells()
    if merged:
        problems.append(f"{merged} coincident points merged by Clean")
    if regions != 1:
        problems.append(f"{regions} connected regions after Warp By Vector")
    if warp_error > 1e-12 * max(1.0, float(abs(p0).max())):
        problems.append(f"warp error {warp_error:.3e}")
    varies = stress is not None and hi - lo > 1e-6 * max(abs(lo), abs(hi))
    if varies and contour_cells <= 0:
        problems.append("contour of the von Mises stress is empty")
    facts = dict(points=n_points, cells=n_cells, arrays=arrays, merged=merged, regions=regions,
                 warp_error=warp_error, contour_cells=contour_cells)
    return problems, facts


def main():
    bad = 0
    for path in sys.argv[1:]:
        for label, grid in grids(path):
            problems, facts = check(grid)
            print(f"{label}: {facts}")
            for p in problems:
                print(f"  PROBLEM: {p}")
            bad += bool(problems)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
