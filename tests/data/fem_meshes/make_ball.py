"""Writes the meshes of the steel ball's section (ball.geo) for the finite element twin of the
MFVM ball impact: problems/ball_impact_axisymmetric_fem.toml and its validation test
(tests/validation/dynamics.rs, fem_ball_impact_matches_hertz_and_the_mfvm). Needs the `gmsh`
Python package (`pip install gmsh`); the product and the tests never run Gmsh, they read the
committed .msh files.

From this folder, `python3 make_ball.py` rewrites the committed levels:

    ball_0.msh                                        hc = 0.2 mm (1 165 nodes, the test's
                                                      coarse level)
    ../../../problems/ball_impact_axisymmetric_fem.msh  hc = 0.1 mm (1 703 nodes, shipped; the
                                                      test's fine level)
    ball_lower.msh                                    the shipped mesh mirrored about z = -1 um
                                                      (z -> -z - 2 um, orientation reversed):
                                                      the lower sphere of the two spheres'
                                                      FE test (tests/validation/
                                                      dynamics_spheres.rs)

each with H = 1 mm (the element size at distance >= 5 mm from the south pole; hc within 1 mm
of it, linear in between). `--hc 0.00005 --out DIR` writes other levels as
DIR/ball_hc<hc>.msh (not committed; docs/dev/dynamics.md's table), `--H` another far size.

Written with Gmsh 4.15.2: MSH 4.1 ASCII, recombined (all quadrilaterals),
Mesh.ElementOrder = 2 with complete (9-node) quadrilaterals whose middle nodes on the arc lie
on the circle."""
import argparse
import os

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
COMMITTED = [
    (2e-4, os.path.join(HERE, "ball_0.msh"), False),
    (1e-4, os.path.join(HERE, "..", "..", "..", "problems", "ball_impact_axisymmetric_fem.msh"), False),
    (1e-4, os.path.join(HERE, "ball_lower.msh"), True),
]
# The gap between the two spheres' poles (the lower one's north pole at z = -GAP).
GAP = 2e-6


def write(hc, big, out, lower=False):
    gmsh.clear()
    gmsh.parser.setNumber("hc", [hc])
    gmsh.parser.setNumber("H", [big])
    # `merge` keeps the parser variables set above (`open` would reset them).
    gmsh.merge(os.path.join(HERE, "ball.geo"))
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.model.mesh.generate(2)
    if lower:
        # The mirror image z -> -z - GAP of every node; a reflection turns the elements
        # clockwise, so their orientation is reversed.
        gmsh.model.mesh.affineTransform([1, 0, 0, 0, 0, -1, 0, -GAP, 0, 0, 1, 0])
        gmsh.model.mesh.reverse()
    gmsh.write(out)
    print(f"{out}: hc = {hc}, H = {big}, {len(gmsh.model.mesh.getNodes()[0])} nodes")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hc", help="comma-separated contact sizes in m (default: the committed)")
    parser.add_argument("--H", type=float, default=1e-3, help="far element size in m")
    parser.add_argument("--out", default=HERE, help="output folder (with --hc)")
    args = parser.parse_args()
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    if args.hc is None:
        for hc, out, lower in COMMITTED:
            write(hc, args.H, os.path.normpath(out), lower)
    else:
        for hc in [float(h) for h in args.hc.split(",")]:
            write(hc, args.H, os.path.join(args.out, f"ball_hc{hc}.msh"))
    gmsh.finalize()


if __name__ == "__main__":
    main()
