//! Validation suite: one self-contained file per case under `tests/validation/`.
mod validation {
    mod common;
    // The long strip (and strip on a block) of the contact studies, shared with them.
    #[path = "../../examples/studies/strip.rs"]
    mod strip;
    // Linear field reproduced to round-off, structured and jittered nodes.
    mod patch_test;
    // Timoshenko & Goodier cantilever: the closed form (also used by examples/studies/param_study.rs).
    mod end_shear_exact;
    // Timoshenko & Goodier cantilever: errors and rates, structured and jittered.
    mod cantilever_end_shear;
    // Free body: exactly three rigid modes at α_s = 2; checkerboard modes at α_s = 3.
    mod free_body;
    // Applied load + reactions = 0 with body force, linear traction and pressure.
    mod equilibrium;
    // The paper's beam on a rigid foundation: KKT, equilibrium, contact zone, convergence.
    mod beam_on_foundation;
    // Condensed compliance M = G K⁻¹ E equals a dense computation.
    mod condensation;
    // Two elastic bodies: uniform pressure, non-matching layouts, mirror symmetry.
    mod two_bodies;
    // Three blocks stacked, two contact pairs in one LCP: exact uniaxial stress.
    mod stack;
    // The contact core's load path: friction, steps and held bodies for several pairs.
    mod contact_core;
    // Every combination of friction, steps, refinement and solver, for 1–3 bodies.
    mod capabilities;
    mod obstacle_pairs;
    // Plate with a circular hole (Kirsch): curved, non-convex boundary; errors and rates.
    mod kirsch;
    // Bodies with holes: patch test, the full Kirsch plate from curves and from Gmsh, FE.
    mod holes;
    // Hertz: elastic cylinder (quarter disk) on a rigid flat; half-width, peak, profile.
    mod hertz;
    // Kirsch and Hertz from Gmsh .msh files against their TOML-built twins; mesh nodes.
    mod gmsh;
    // Hertz: rigid cylinder (a circle obstacle) pressed into an elastic block.
    mod cylinder_indenter;
    // Load-driven contact: the rigid cylinder pressed by a force; Hertz, the displacement run.
    mod load_driven;
    // Adaptive refinement (docs/method.md §2.2) on the rigid cylinder indenter against uniform.
    mod adaptive_hertz;
    // Adaptive refinement of two bodies: a beam on an elastic block against FE and uniform.
    mod adaptive_two_bodies;
    // A target 100 x softer than the candidates: M indefinite below its cells, accepted on the answer.
    mod soft_target;
    // A graded Gmsh half-disk on a rigid flat, default discretisation, against Hertz.
    mod graded_half_disk;
    // Adaptive refinement against uniform on the fully clamped cantilever (FE reference).
    mod clamped_cantilever;
    mod clamped_cantilever_measure;
    // Adaptive refinement against uniform on the Kirsch quarter plate (exact solution).
    mod adaptive_kirsch;
    // Adaptive refinement on a curved body: the Hertz quarter cylinder against uniform.
    mod adaptive_hertz_cylinder;
    // Adaptive refinement of two bodies, the first curved: Hertz cylinder on a block; Cattaneo–Mindlin.
    mod adaptive_hertz_two_bodies;
    // Adaptive refinement of FE meshes (graded tensor-product grids): the indenter against Hertz.
    mod adaptive_fem;
    // Elastodynamics: lumped mass, free flight, the bar impact against the 1-D wave solution.
    mod dynamics;
    // Elastodynamics of two bodies: equal bars exchange their velocities (St Venant).
    mod dynamics_pair;
    // The active-set solver per time step equals Lemke's: the bar impact, Newton's cradle, the block on a slab.
    mod dynamics_active_set;
    // A block sliding with friction onto a rigid wall: rigid-body arrival, gaps, Coulomb's cone.
    mod dynamics_wall;
    // Friction in the time stepping on FE bodies (sliding, stick, slip, pairs) and on axisymmetric rings.
    mod dynamics_friction;
    // Two equal elastic spheres colliding head-on: Hertz's two-body impact, the one ball on a flat.
    mod dynamics_spheres;
    // The quasi-static limit: a slowly loaded dynamic contact approaches the static solve.
    mod quasi_static;
    // Loads and prescribed displacements in time ([[step]] with time): d'Alembert, impulses, statics.
    mod dynamics_history;
    // A rigid obstacle moving in time: a wall hitting a bar at rest is the bar impact in the wall's frame.
    mod dynamics_obstacle;
    // The FE consistent mass against the lumped one: bar impact, cantilever period, active set.
    mod dynamics_mass;
    // Flat rigid punch (a polyline obstacle with rounded corners) on an elastic block.
    mod flat_punch;
    // Axisymmetric bodies: patch test, Lamé's thick cylinder, solid cylinders on the axis.
    mod axisymmetric;
    // Axisymmetric contact: rings; a cylinder on a flat (exact), Hertz's sphere, MFVM and FE.
    mod axisymmetric_contact;
    // Axisymmetric contact along load paths: steps, a force-driven flat, a rigid sphere, friction.
    mod axisymmetric_contact_paths;
    // Axisymmetric elastic pairs: two cylinders end to end (exact), Hertz's sphere on a block.
    mod axisymmetric_pairs;
    // Two elastic spheres (a curved target edge) against Hertz.
    mod axisymmetric_spheres;
    // Two elastic cylinders in plane strain (a curved target edge) against Hertz.
    mod hertz_two_cylinders;
    // Lamé's thick sphere under internal pressure: a curved section (quarter annulus, two arcs).
    mod axisymmetric_sphere;
    // A rigid flat circular punch on a large cylinder: the stiffness against Sneddon.
    mod flat_punch_axisymmetric;
    // Adaptive refinement of an axisymmetric body: the Hertz sphere against uniform node sets.
    mod axisymmetric_adaptive;
    // Interference fits: confined blocks (exact), Lamé's shrink fit of long cylinders.
    mod interference;
    // FE oracle: Q2 patch tests (Dirichlet, tractions) and equilibrium.
    mod fem_patch_test;
    // FE on Gmsh meshes with curved sides (T6, Q9): patch test, Kirsch errors and rates.
    mod fem_curved;
    // FE oracle: Timoshenko & Goodier cantilever, errors and rates.
    mod fem_cantilever;
    // FE oracle on the paper's beam; MFVM vs FE within their discretisation errors.
    mod fem_beam_on_foundation;
    // FE oracle, two blocks: exact on matching meshes; node-to-segment error recorded otherwise.
    mod fem_two_bodies;
    // The static-pivoting LU (default from 100k unknowns) against faer's LU on small MFVM matrices.
    mod static_pivoting;
    // Coulomb friction, one step: tiny μ = frictionless, huge μ = bonded, gross sliding.
    mod friction;
    // Coulomb friction on the FE path: bonded, sliding, steps, two bodies.
    mod fem_friction;
    // The active-set contact solver equals Lemke on the shipped rigid-obstacle problems.
    mod active_set;
    // The active-set solver on every shipped contact problem (directory listing) or refused.
    mod active_set_shipped;
    // Lemke's numerical failure: a refusal naming M's conditioning; "auto" falls back to the active set.
    mod lemke_fallback;
    // Friction on the active-set path equals the Lemke-based step, increment by increment.
    mod active_set_friction;
    // Active-set iterations against the number of candidates (at most 30, not growing).
    mod active_set_iterations;
}
