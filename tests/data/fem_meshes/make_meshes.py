"""Regenerates the .msh files of this folder (second-order meshes for the finite element tests
on curved boundaries, tests/validation/fem_curved.rs) from their .geo files. Needs the `gmsh`
Python package (`pip install gmsh`); the product and the tests never run Gmsh. From this folder:

    python3 make_meshes.py

Written with Gmsh 4.15.2: MSH 4.1 ASCII, Mesh.ElementOrder = 2 with complete (9-node)
quadrilaterals. `tri`: 6-node triangles; `quad`: recombined, 9-node quadrilaterals (with a
few triangles where the recombination leaves them). Size factors 2, 1, 1/2 of the .geo's for the
plate; the cylinder cap of the Cattaneo-Mindlin case (tests/validation/fem_friction.rs) and the
Hertz quarter cylinder (tests/validation/hertz.rs), both recombined, at factors 2, 1 (and 1/2
for the quarter cylinder). The two-sphere meshes (two_spheres_*.msh) have their own script,
make_two_spheres.py."""
import gmsh

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for kind in ["tri", "quad"]:
    for level, factor in enumerate([2.0, 1.0, 0.5]):
        gmsh.clear()
        gmsh.open("plate_with_hole.geo")
        gmsh.option.setNumber("Mesh.MeshSizeFactor", factor)
        gmsh.option.setNumber("Mesh.RecombineAll", 1 if kind == "quad" else 0)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.model.mesh.generate(2)
        gmsh.write(f"plate_with_hole_{kind}_{level}.msh")
def quads(geo, name, factors):
    for level, factor in enumerate(factors):
        gmsh.clear()
        gmsh.open(geo)
        gmsh.option.setNumber("Mesh.MeshSizeFactor", factor)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.model.mesh.generate(2)
        gmsh.write(f"{name}_{level}.msh")
quads("cattaneo_cap.geo", "cattaneo_cap", [2.0, 1.0])
quads("hertz_cylinder.geo", "hertz_cylinder", [2.0, 1.0, 0.5])
gmsh.finalize()
