"""Writes the meshes of two elastic spheres of revolution (two_spheres.geo) for the finite
element twin of the MFVM two-sphere test (tests/validation/axisymmetric_spheres.rs) and its
study (examples/studies/two_spheres.rs). Needs the `gmsh` Python package (`pip install
gmsh`); the product and the tests never run Gmsh, they read the committed .msh files.

From this folder, `python3 make_two_spheres.py` rewrites the committed levels:

    two_spheres_0.msh  hc = 0.02   (1 814 nodes)
    two_spheres_1.msh  hc = 0.01   (3 718 nodes, the test's)
    two_spheres_2.msh  hc = 0.005  (9 738 nodes)

each with H = 0.2 (the element size at distance >= 1 from the contact; hc within 0.15 of it,
linear in between). `--hc 0.014,0.007 --out DIR` writes other levels as
DIR/two_spheres_hc<hc>.msh (not committed; the study reads them with `--meshes`), and
`--scaled` sets H = 10 hc instead of 0.2 (every size halves with hc).

Written with Gmsh 4.15.2: MSH 4.1 ASCII, recombined, Mesh.ElementOrder = 2 with complete
(9-node) quadrilaterals, as make_meshes.py's quads()."""
import argparse
import os

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
COMMITTED = [0.02, 0.01, 0.005]


def write(hc, big, out):
    gmsh.clear()
    gmsh.parser.setNumber("hc", [hc])
    gmsh.parser.setNumber("H", [big])
    # `merge` keeps the parser variables set above (`open` would reset them).
    gmsh.merge(os.path.join(HERE, "two_spheres.geo"))
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.model.mesh.generate(2)
    gmsh.write(out)
    print(f"{out}: hc = {hc}, H = {big}, {len(gmsh.model.mesh.getNodes()[0])} nodes")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hc", help="comma-separated contact sizes (default: the committed)")
    parser.add_argument("--out", default=HERE, help="output folder")
    parser.add_argument("--scaled", action="store_true", help="H = 10 hc instead of 0.2")
    args = parser.parse_args()
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    if args.hc is None:
        for level, hc in enumerate(COMMITTED):
            big = 10 * hc if args.scaled else 0.2
            write(hc, big, os.path.join(args.out, f"two_spheres_{level}.msh"))
    else:
        for hc in [float(h) for h in args.hc.split(",")]:
            big = 10 * hc if args.scaled else 0.2
            write(hc, big, os.path.join(args.out, f"two_spheres_hc{hc}.msh"))
    gmsh.finalize()


if __name__ == "__main__":
    main()
