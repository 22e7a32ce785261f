"""A run's ParaView files read with VTK's own XML readers (the ones ParaView uses): the
multiblock `solution.vtm` opens every body, the contact edge and the obstacle; the bodies carry
stress and strain tensors and the reactions, the contact edge its gaps, forces and states; the
time series `solution.pvd` of a problem with load steps points to the multiblock. Skipped when
VTK's Python package is missing (`pip install vtk`)."""
import math
import os
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import mlpg_contact as mc

vtkIOXML = pytest.importorskip("vtkmodules.vtkIOXML", reason="needs VTK's Python package: pip install vtk")
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet  # noqa: E402
from vtkmodules.vtkFiltersGeneral import vtkWarpVector  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def read_blocks(path: Path) -> dict:
    """The data sets of a `.vtm` file by block name: {block: {data set name: data set}}."""
    reader = vtkIOXML.vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    top = reader.GetOutput()
    blocks = {}
    for b in range(top.GetNumberOfBlocks()):
        block = top.GetBlock(b)
        name = top.GetMetaData(b).Get(vtkCompositeDataSet.NAME())
        blocks[name] = {
            block.GetMetaData(k).Get(vtkCompositeDataSet.NAME()): block.GetBlock(k)
            for k in range(block.GetNumberOfBlocks())
        }
    return blocks


def array(data, name):
    a = data.GetArray(name)
    assert a is not None, f"no array {name}"
    return vtk_to_numpy(a)


def strings(field, name):
    a = field.GetAbstractArray(name)
    assert a is not None, f"no field array {name}"
    return [a.GetValue(k) for k in range(a.GetNumberOfValues())]


def csv_columns(path: Path) -> dict:
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    return {h: [r[k] for r in rows] for k, h in enumerate(header)}


def reaction_totals(path: Path) -> np.ndarray:
    cols = csv_columns(path)
    total = np.zeros(2)
    for axis, r in zip(cols["axis"], cols["reaction"]):
        total[int(axis == "y")] += float(r)
    return total


def test_two_bodies_with_friction_and_load_steps(tmp_path):
    out = tmp_path / "cm"
    mc.solve(ROOT / "problems" / "cattaneo_mindlin.toml").write(out)

    # The time series: the final state (the end of the second step) is the multiblock.
    pvd = ET.parse(out / "solution.pvd").getroot()
    sets = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    assert sets == [(2.0, "solution.vtm")]

    blocks = read_blocks(out / "solution.vtm")
    assert set(blocks) == {"bodies", "contact"}
    assert set(blocks["bodies"]) == {"cylinder", "block"}
    for name, body in blocks["bodies"].items():
        assert body.GetClassName() == "vtkUnstructuredGrid"
        pd = body.GetPointData()
        assert pd.GetTensors() is not None and pd.GetTensors().GetName() == "stress"
        stress = array(pd, "stress")
        strain = array(pd, "strain")
        assert stress.shape == (body.GetNumberOfPoints(), 6) and strain.shape == stress.shape
        # Plane strain: σzz = ν (σxx + σyy), εzz = 0; no out-of-plane shear.
        assert np.allclose(stress[:, 2], 0.3 * (stress[:, 0] + stress[:, 1]), rtol=0, atol=1e-10 * abs(stress).max())
        assert not strain[:, 2].any() and not stress[:, 4:].any()
        # One cell per node: its reaction, adding up to reactions.csv's.
        reaction = array(body.GetCellData(), "node_reaction")
        folder = out if name == "cylinder" else out / name
        expected = reaction_totals(folder / "reactions.csv")
        assert abs(expected).max() > 0
        assert np.allclose(reaction[:, :2].sum(axis=0), expected, rtol=1e-9, atol=0)

    contact = blocks["contact"]["contact of `cylinder`"]
    assert contact.GetClassName() == "vtkPolyData"
    pd = contact.GetPointData()
    table = csv_columns(out / "contact.csv")
    n = len(table["candidate"])
    assert contact.GetNumberOfPoints() == n and contact.GetNumberOfVerts() == n and contact.GetNumberOfLines() == 1
    for name, column in [("initial_gap", "initial_gap"), ("gap", "gap"), ("normal_force", "force"),
                         ("pressure", "pressure"), ("tangential_force", "tangential_force"), ("slip", "slip")]:
        assert np.allclose(array(pd, name), np.array(table[column], dtype=float), rtol=1e-11, atol=0), name
    legend = strings(contact.GetFieldData(), "state_legend")
    assert legend == ["open", "stick", "slip+", "slip-"]
    states = [legend[s] for s in array(pd, "state")]
    assert states == table["state"]
    assert "stick" in states and any(s.startswith("slip") for s in states)
    assert array(pd, "normal_force").sum() > 0


def test_obstacle_and_contact_edge_meet_after_warping(tmp_path):
    out = tmp_path / "ci"
    mc.solve(ROOT / "problems" / "cylinder_indenter.toml").write(out)
    reader = vtkIOXML.vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(out / "solution.vtm"))
    warp = vtkWarpVector()  # ParaView's "Warp By Vector", on the whole multiblock
    warp.SetInputConnection(reader.GetOutputPort())
    warp.SetInputArrayToProcess(0, 0, 0, 0, "displacement")
    warp.SetScaleFactor(1.0)
    warp.Update()
    warped = warp.GetOutputDataObject(0)
    names = [warped.GetMetaData(b).Get(vtkCompositeDataSet.NAME()) for b in range(warped.GetNumberOfBlocks())]
    assert names == ["bodies", "contact", "obstacles"]
    contact = warped.GetBlock(1).GetBlock(0)
    obstacle = warped.GetBlock(2).GetBlock(0)
    assert strings(obstacle.GetFieldData(), "obstacle_names") == ["indenter"]
    # The indenter (a unit circle drawn with 360 chords) moved down by the step's 0.015.
    ring = vtk_to_numpy(obstacle.GetPoints().GetData())[:, :2]
    centre = ring.mean(axis=0)
    assert np.allclose(centre, [0.0, 1.0 - 0.015], atol=1e-12)
    assert np.allclose(np.hypot(*(ring - centre).T), 1.0, atol=1e-12)
    # Each warped candidate's distance from the moved circle is its final (linearised) gap,
    # to second order in the displacement.
    x = vtk_to_numpy(contact.GetPoints().GetData())[:, :2]
    gap = array(contact.GetPointData(), "gap")
    closed = array(contact.GetPointData(), "in_contact") == 1
    assert closed.sum() >= 3 and (~closed).sum() >= 3
    distance = np.hypot(*(x - centre).T) - 1.0
    assert abs(distance - gap).max() < 1e-4, abs(distance - gap).max()
    assert abs(distance[closed]).max() < 1e-4
    assert distance[~closed].min() > 0


def test_revolved_axisymmetric_body_has_the_revolved_volume(tmp_path):
    """`[output] revolve = 360`: VTK reads `solution_revolved.vtu` as wedges of positive volume
    summing to the swept volume 2π ∫ r dA (0.75 for the thick cylinder's section) within the
    chord error Δ²/6 of the 96 segments; every point's displacement is radial-axial."""
    binary = Path(os.environ.get("MLPG_CONTACT_BIN", ROOT / "target" / "release" / "mlpg-contact"))
    text = (ROOT / "problems" / "thick_cylinder_axisymmetric.toml").read_text()
    text = text.replace("spacing = 0.05", "spacing = 0.1")
    text = text.replace("[output]\n", "[output]\nrevolve = 360.0\nrevolve_segments = 96\n")
    problem = tmp_path / "revolved.toml"
    problem.write_text(text)
    subprocess.run([binary, problem, "--out", tmp_path / "o", "--quiet"], check=True)
    reader = vtkIOXML.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "o" / "solution_revolved.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfCells() > 0
    assert {grid.GetCellType(k) for k in range(grid.GetNumberOfCells())} == {13}  # VTK_WEDGE
    sizes = vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.Update()
    volume = array(sizes.GetOutput().GetCellData(), "Volume")
    assert (volume > 0).all(), volume.min()
    exact = 2 * math.pi * 0.75
    delta = 2 * math.pi / 96
    error = 1 - volume.sum() / exact
    assert 0 < error < 1.2 * delta**2 / 6, error
    # u = (u_r cos θ, u_r sin θ, u_z): no component along the hoop direction.
    points = vtk_to_numpy(grid.GetPoints().GetData())
    u = array(grid.GetPointData(), "displacement")
    hoop = u[:, 0] * points[:, 1] - u[:, 1] * points[:, 0]
    assert abs(hoop).max() <= 1e-10 * abs(u).max()
    assert grid.GetPointData().GetTensors().GetName() == "stress"
