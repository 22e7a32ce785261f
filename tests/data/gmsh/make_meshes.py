"""Regenerates the .msh files of this folder from their .geo files (needs the `gmsh` Python
package: `pip install gmsh`; the product never runs Gmsh). Run from this folder:

    python3 make_meshes.py

Written with Gmsh 4.15.2. Versions 4.1 and 2.2, first and second order."""
import gmsh

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for geo in ["plate_with_hole", "two_blocks"]:
    for order in [1, 2]:
        for version in [4.1, 2.2]:
            gmsh.clear()
            gmsh.open(f"{geo}.geo")
            gmsh.option.setNumber("Mesh.ElementOrder", order)
            gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.option.setNumber("Mesh.Binary", 0)
            gmsh.model.mesh.generate(2)
            gmsh.write(f"{geo}_o{order}_v{'4' if version > 3 else '2'}.msh")
gmsh.finalize()
