"""Regenerates the .msh files of this folder from their .geo files (needs the `gmsh` Python
package: `pip install gmsh`; the product never runs Gmsh). Run from this folder:

    python3 make_meshes.py

Written with Gmsh 4.15.2. `plate_with_hole` and `two_blocks`: versions 4.1 and 2.2, first and
second order. `kirsch` and `hertz_cylinder` (first order) at the node spacings of their TOML
twins in tests/validation (the .geo's `h`): kirsch in both versions, hertz_cylinder in 4.1.
`kirsch_full` (the hole a second loop): first order, 4.1, at h = 0.2, 0.1, 0.05 (its TOML
twin's spacings), and second order, 4.1, at h = 0.2, 0.1 with corners at H = 5h, for the FE
path on the mesh's elements. Also problems/plate_with_hole_gmsh.msh (plate_with_hole at
h = 0.4, version 4.1). `punch` (obstacle curves only, meshed in one dimension): first order in
4.1, second order in 2.2. `two_bodies` (two bodies in one file, every side named): first
order, 4.1. `hertz_half_disk` (graded by a distance field): first order, 4.1, at hc = 0.006."""
import gmsh


def mesh(geo, out, order=1, version=4.1, h=None, dimension=2, H=None, hc=None):
    gmsh.clear()
    if hc is not None:
        gmsh.parser.setNumber("hc", [hc])
    if h is not None:
        gmsh.parser.setNumber("h", [h])
    if H is not None:
        gmsh.parser.setNumber("H", [H])
    # `merge` keeps the parser variable set above (`open` would reset it).
    gmsh.merge(f"{geo}.geo")
    gmsh.option.setNumber("Mesh.ElementOrder", order)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.model.mesh.generate(dimension)
    gmsh.write(out)


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for geo in ["plate_with_hole", "two_blocks"]:
    for order in [1, 2]:
        for version in [4.1, 2.2]:
            mesh(geo, f"{geo}_o{order}_v{'4' if version > 3 else '2'}.msh", order, version)
for h in [0.2, 0.1, 0.05]:
    for version in [4.1, 2.2]:
        mesh("kirsch", f"kirsch_h{h}_v{'4' if version > 3 else '2'}.msh", 1, version, h)
for h in [0.02, 0.01, 0.005]:
    mesh("hertz_cylinder", f"hertz_cylinder_h{h}_v4.msh", 1, 4.1, h)
for h in [0.2, 0.1, 0.05]:
    mesh("kirsch_full", f"kirsch_full_h{h}_v4.msh", 1, 4.1, h)
for h in [0.2, 0.1]:
    mesh("kirsch_full", f"kirsch_full_o2_h{h}_v4.msh", 2, 4.1, h, H=5 * h)
mesh("plate_with_hole", "../../../problems/plate_with_hole_gmsh.msh", 1, 4.1, 0.4)
mesh("punch", "punch_o1_v4.msh", 1, 4.1, dimension=1)
mesh("punch", "punch_o2_v2.msh", 2, 2.2, dimension=1)
mesh("two_bodies", "two_bodies_o1_v4.msh")
mesh("hertz_half_disk", "hertz_half_disk_hc0.006_v4.msh", H=0.08, hc=0.006)
gmsh.finalize()
