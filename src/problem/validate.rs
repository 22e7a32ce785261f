//! Validation of a [`ProblemFile`] into a [`Problem`]: every value range-checked once, here,
//! and every refusal naming the key path, the value and what would be accepted.

use super::file::*;
use super::*;
use crate::geometry::{Curve, Domain, GeometryError, projects_onto};
use crate::material::Material;

/// The largest magnitude accepted for a coordinate, a load or a modulus: products of two such
/// numbers (stiffness times displacement, squared lengths) stay far from overflow.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// The largest prescribed displacement (or obstacle displacement) accepted, in multiples of
/// the body's size (the diagonal of its bounding box). A small-strain linear model means
/// displacements well below the body's size; beyond it only a rigid motion is meaningful,
/// and a rigid motion `T` costs the strains about `log10(T / (strain · size))` digits: the
/// beam on its foundation keeps its contact force to 5.5e-8 (equilibrium error 1.3e-7) with
/// its clamp moved by 10³ times its size, and loses it entirely (0 instead of 32.34) at 10¹².
/// Larger values are a units mistake far more often than an intent.
pub const MAX_DISPLACEMENT_RATIO: f64 = 1e3;

/// The largest ratio of Young's moduli between the bodies of a problem. The stiffer body's
/// forces are its modulus times displacements that carry the round-off of the softer
/// bodies' (about ε of them): in three stacked blocks the middle block's equilibrium error
/// grows as the ratio, 5.9e-7 at 10⁹, 8.7e-6 at 10¹⁰ (failing its check), 7e-4 at 10¹² —
/// beyond 10¹² no tolerance could accept the answer.
pub const MAX_YOUNG_RATIO: f64 = 1e12;

/// Refuses a prescribed displacement `f` (key `field`) larger than
/// [`MAX_DISPLACEMENT_RATIO`] times the body's size `size`.
fn check_displacement(field: &str, f: &Field, size: f64) -> Result<(), ProblemError> {
    let largest = match *f {
        Field::Constant(v) => v.abs(),
        Field::Linear { start, end } => start.abs().max(end.abs()),
        // Built by the library only, never read from a file.
        Field::Function(_) => return Ok(()),
    };
    if largest > MAX_DISPLACEMENT_RATIO * size {
        return Err(invalid(
            field,
            format!("{largest:e}"),
            format!(
                "{:.1e} times the body's size {size:.4e} (the diagonal of its bounding box): a small-strain linear model takes displacements up to {MAX_DISPLACEMENT_RATIO:.0e} times the body's size, beyond which round-off of the rigid motion drowns the strains; check the units",
                largest / size
            ),
        ));
    }
    Ok(())
}

/// The diagonal of a domain's bounding box.
fn body_size(domain: &Domain) -> f64 {
    let (lo, hi) = domain.bounding_box();
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// Refuses Young's moduli whose ratio between two bodies exceeds [`MAX_YOUNG_RATIO`],
/// naming the stiffest body's key.
fn check_young_ratio(problem: &Problem) -> Result<(), ProblemError> {
    let young: Vec<f64> = (0..problem.body_count())
        .filter_map(|k| problem.body(k))
        .map(|p| p.material.young)
        .collect();
    let (Some(stiff), Some(soft)) = (
        young.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)),
        young.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)),
    ) else {
        return Ok(());
    };
    let ratio = stiff.1 / soft.1;
    if ratio > MAX_YOUNG_RATIO {
        return Err(invalid(
            &format!("body[{}].material.young", stiff.0),
            format!("{:e}", stiff.1),
            format!(
                "{ratio:.1e} times body[{}].material.young = {:e}: beyond a ratio of {MAX_YOUNG_RATIO:.0e} the stiffer body's forces are lost in the round-off of the softer body's displacements; treat the stiff body as rigid (a rigid obstacle) or bring the moduli closer",
                soft.0, soft.1
            ),
        ));
    }
    Ok(())
}

/// `v`, if it is a finite number of magnitude at most [`MAX_MAGNITUDE`].
fn check_finite(field: &str, v: f64) -> Result<f64, ProblemError> {
    if !v.is_finite() {
        return Err(invalid(field, v, "must be a finite number"));
    }
    if v.abs() > MAX_MAGNITUDE {
        return Err(invalid(
            field,
            format!("{v:e}"),
            format!(
                "magnitudes above {MAX_MAGNITUDE:e} make the arithmetic overflow; rescale the units"
            ),
        ));
    }
    Ok(v)
}

fn value_field(field: &str, v: ValueFile) -> Result<Field, ProblemError> {
    Ok(match v {
        ValueFile::Constant(c) => Field::Constant(check_finite(field, c)?),
        ValueFile::Linear([a, b]) => {
            Field::Linear { start: check_finite(field, a)?, end: check_finite(field, b)? }
        }
    })
}

impl TryFrom<ProblemFile> for Problem {
    type Error = ProblemError;

    fn try_from(file: ProblemFile) -> Result<Self, ProblemError> {
        let discretisation = validate_discretisation(&file.discretisation)?;
        let name = file.name.clone().unwrap_or_else(|| "problem".into());
        let bodies = if file.body.is_empty() {
            let missing = |what: &str| {
                invalid(
                    what,
                    "(missing)",
                    "a problem needs [geometry], [nodes] and [material] (or [[body]] tables)",
                )
            };
            let parts = BodyParts {
                geometry: file.geometry.as_ref().ok_or_else(|| missing("geometry"))?,
                nodes: file.nodes.as_ref().ok_or_else(|| missing("nodes"))?,
                material: file.material.as_ref().ok_or_else(|| missing("material"))?,
                boundary: &file.boundary,
                body_force: file.body_force,
            };
            vec![validate_body(name, parts, discretisation)?]
        } else {
            if file.geometry.is_some()
                || file.nodes.is_some()
                || file.material.is_some()
                || !file.boundary.is_empty()
                || file.body_force.is_some()
            {
                return Err(invalid(
                    "geometry",
                    "(top level)",
                    "with [[body]] tables, geometry, nodes, material, boundary and body_force go inside each body",
                ));
            }
            let mut bodies: Vec<Problem> = Vec::new();
            for (k, b) in file.body.iter().enumerate() {
                let parts = BodyParts {
                    geometry: &b.geometry,
                    nodes: &b.nodes,
                    material: &b.material,
                    boundary: &b.boundary,
                    body_force: b.body_force,
                };
                let body_name = match &b.name {
                    Some(name) => output_name(&format!("body[{k}].name"), name)?,
                    None => format!("body{}", k + 1),
                };
                if bodies.iter().any(|p| p.name == body_name) {
                    return Err(invalid(
                        &format!("body[{k}].name"),
                        &body_name,
                        "the bodies need different names (outputs of the second and later bodies go to <out>/<name>/)",
                    ));
                }
                bodies.push(
                    validate_body(body_name, parts, discretisation)
                        .map_err(|e| prefixed(&format!("body[{k}]."), e))?,
                );
            }
            bodies
        };
        // One description of every file: the bodies and the contact pairs; `encode` then
        // chooses how the problem holds them.
        let tables = file.contact.as_ref().map_or(&[][..], |c| c.tables());
        let key = |k: usize| file.contact.as_ref().map_or_else(|| "contact".into(), |c| c.key(k));
        if file.contact.is_none() && !file.obstacle.is_empty() {
            return Err(invalid(
                "obstacle",
                format!("{} obstacles", file.obstacle.len()),
                "obstacles need a [contact] table naming the edge that touches them",
            ));
        }
        let pairs = match bodies.len() {
            _ if !tables.is_empty() => contact_pairs(tables, &key, &file.obstacle, &bodies)?,
            1 => Vec::new(),
            2 => {
                return Err(invalid(
                    "contact",
                    "(missing)",
                    "two bodies need a [contact] table with `edge` (body 1) and `target_edge` (body 2)",
                ));
            }
            _ => contact_pairs(tables, &key, &file.obstacle, &bodies)?,
        };
        let mut problem = encode(bodies, pairs, &key)?;

        let profile_edge = match &file.output.profile_edge {
            Some(name) => problem.domain.edge_index(name).ok_or_else(|| {
                invalid(
                    "output.profile_edge",
                    name,
                    format!("no such edge; the edges are {:?}", problem.domain.edge_names()),
                )
            })?,
            None => 0,
        };
        problem.profile_edge = profile_edge;
        check_young_ratio(&problem)?;
        for (k, steps) in load_steps(&file, &problem)?.into_iter().enumerate() {
            if let Some(body) = problem.body_mut(k) {
                body.steps = steps;
            }
        }
        problem.adaptive = match &file.refinement {
            None => None,
            Some(r) => Some(adaptive(r, &problem)?),
        };
        problem.write_steps = file.output.steps.unwrap_or(false);
        problem.revolve = revolve(&file.output, &problem)?;
        let named = file.output.units.as_deref().map(units).transpose()?;
        for k in 0..problem.body_count() {
            if let Some(body) = problem.body_mut(k) {
                body.units = named.clone();
            }
        }
        super::axisymmetric::refuse_unsupported(&problem)?;
        let frictional = problem.pairs().iter().any(|p| p.spec.friction > 0.0);
        problem.dynamics = super::dynamics::dynamics(&file, &problem)?;
        // The other bodies of a dynamic run step with inertia too, each at its own density and
        // initial velocity.
        if let Some(d) = problem.dynamics.clone() {
            for (k, m) in d.others.iter().enumerate() {
                if let Some(p) = problem.body_mut(k + 1) {
                    p.dynamics = Some(super::dynamics::Dynamics {
                        density: m.density,
                        initial_velocity: m.initial_velocity,
                        others: Vec::new(),
                        ..d.clone()
                    });
                }
            }
        }
        if let (None, Some(k)) =
            (&problem.dynamics, file.body.iter().position(|b| b.initial_velocity.is_some()))
        {
            return Err(invalid(
                &format!("body[{k}].initial_velocity"),
                "(given)",
                "an initial velocity needs a [dynamics] table (the static solve has none)",
            ));
        }
        if problem.write_steps && problem.steps.is_empty() && !frictional {
            return Err(invalid(
                "output.steps",
                "true",
                "per-increment contact tables need [[step]] tables or friction (contact.friction > 0)",
            ));
        }
        Ok(problem)
    }
}

fn validate_discretisation(file: &DiscretisationFile) -> Result<Discretisation, ProblemError> {
    let d = file;
    let preset = d.preset;
    let (preset_basis, preset_support, preset_beta, preset_quadrature) =
        preset.unwrap_or(Preset::Paper).values();
    let method = d.method.unwrap_or_default();
    let basis = d.basis.unwrap_or(preset_basis);
    let support_factor = d.support_factor.unwrap_or(preset_support);
    if !(support_factor.is_finite() && (1.0..=6.0).contains(&support_factor)) {
        return Err(invalid(
            "discretisation.support_factor",
            support_factor,
            "must be in [1, 6]; supports smaller than one spacing cannot hold enough nodes (recommended 2 for the linear basis)",
        ));
    }
    let quadrature_points = d.quadrature_points.unwrap_or(preset_quadrature);
    if !(1..=8).contains(&quadrature_points) {
        return Err(invalid("discretisation.quadrature_points", quadrature_points, "must be 1–8"));
    }
    let load_quadrature_points = d.load_quadrature_points.unwrap_or(5);
    if !(3..=8).contains(&load_quadrature_points) {
        return Err(invalid(
            "discretisation.load_quadrature_points",
            load_quadrature_points,
            "must be 3–8",
        ));
    }
    let (beta, beta_auto) = match d.beta {
        // Neither `beta` nor `preset`: "auto" (the paper's β = 0 where its compliance is
        // trustworthy, the stabilised blend where not). A preset keeps its own β; the FE
        // method has no β.
        None if preset.is_none() && method == Method::Mfvm => (0.0, true),
        None => (preset_beta, false),
        Some(super::BetaChoice::Value(beta)) => (beta, false),
        Some(super::BetaChoice::Auto(_)) => (0.0, true),
    };
    if !(beta.is_finite() && (0.0..=1.0).contains(&beta)) {
        return Err(invalid(
            "discretisation.beta",
            beta,
            "must be in [0, 1] (0: the paper's mixed method; 1: direct MLS strains at the cell boundaries)",
        ));
    }
    let discretisation = Discretisation {
        preset,
        method,
        mls: MlsParams { basis, support_factor, ..MlsParams::default() },
        quadrature_points,
        load_quadrature_points,
        beta,
        beta_auto,
        allow_unstable: d.allow_unstable.unwrap_or(false),
        precision: d.precision.unwrap_or_default(),
    };
    if discretisation.precision == Precision::Mixed && method == Method::Fem {
        return Err(invalid(
            "discretisation.precision",
            "\"mixed\"",
            "single-precision factors are for the MFVM (method = \"mfvm\"); the finite element model is factorised in double precision: use \"double\" or \"auto\"",
        ));
    }
    if let Some(why) = discretisation.stability_warning() {
        if !discretisation.allow_unstable && method == Method::Mfvm {
            return Err(invalid("discretisation.support_factor", support_factor, why));
        }
    }
    Ok(discretisation)
}

/// The parts of a problem file that describe one body.
struct BodyParts<'a> {
    geometry: &'a GeometryFile,
    nodes: &'a NodesFile,
    material: &'a MaterialFile,
    boundary: &'a [BoundaryFile],
    body_force: Option<[f64; 2]>,
}

/// Validates one body into a [`Problem`] without contact (field names as in a single-body file).
fn validate_body(
    name: String,
    file: BodyParts<'_>,
    discretisation: Discretisation,
) -> Result<Problem, ProblemError> {
    let (domain, mesh) = domain(file.geometry)?;
    let (h, layout, mesh_nodes) = node_layout(&file, &domain, mesh, discretisation.method)?;
    let refinement = refinement(file.nodes, file.geometry, &domain, h, discretisation.method)?;
    let material = material(file.material)?;
    let mut boundary = edge_conditions(file.boundary, &domain)?;
    if material.is_axisymmetric() {
        super::axisymmetric::axis_conditions(&domain, &mut boundary)?;
    }
    let body_force = match file.body_force {
        Some(b) => {
            check_finite("body_force", b[0])?;
            check_finite("body_force", b[1])?;
            Some(BodyForce::constant(b))
        }
        None => None,
    };
    Ok(Problem {
        name,
        domain,
        node_spacing: h,
        layout,
        refinement,
        adaptive: None,
        material,
        discretisation,
        boundary,
        body_force,
        profile_edge: 0,
        write_steps: false,
        revolve: None,
        units: None,
        others: Vec::new(),
        contact_pairs: Vec::new(),
        mesh_nodes,
        steps: Vec::new(),
        dynamics: None,
    })
}

/// The physical group (a `what`, "surface" or "curve") named `given` among `names` of mesh
/// file `file`, or the only one when not named; refusals name the key `key` and list the
/// names.
fn physical_group<'a>(
    file: &str,
    names: &[&'a str],
    given: Option<&'a str>,
    key: &str,
    what: &str,
) -> Result<&'a str, ProblemError> {
    let listed = || names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
    let name = match given {
        Some(name) => name,
        None if names.len() == 1 => names[0],
        None => {
            return Err(invalid(
                key,
                "(missing)",
                format!("{file} has several physical {what}s, name one: {}", listed()),
            ));
        }
    };
    if !names.contains(&name) {
        return Err(invalid(
            key,
            name,
            format!("{file} has no such physical {what}; it has: {}", listed()),
        ));
    }
    Ok(name)
}

/// `kind = "gmsh"`: the mesh file's body `surface` (the only surface when not named).
fn gmsh_body(file: &str, surface: Option<&str>) -> Result<gmsh::MeshBody, ProblemError> {
    let mesh = gmsh::Mesh::read(std::path::Path::new(file))
        .map_err(|e| invalid("geometry.file", file, e.to_string()))?;
    let surface =
        physical_group(file, &mesh.surface_names(), surface, "geometry.surface", "surface")?;
    mesh.body(surface)
        .map_err(|e| invalid("geometry.file", file, format!("surface `{surface}`: {e}")))
}

/// `[[obstacle]] kind = "gmsh"` (table `k`): the sharp-cornered polyline through the nodes of
/// physical curve `curve` of mesh file `file` (the only physical curve when not named), in
/// the order of its line elements, or the other way with `reverse`.
fn gmsh_obstacle(
    k: usize,
    file: &str,
    curve: Option<&str>,
    reverse: Option<bool>,
) -> Result<Polyline, ProblemError> {
    let key = |f: &str| format!("obstacle[{k}].{f}");
    let mesh = gmsh::Mesh::read(std::path::Path::new(file))
        .map_err(|e| invalid(&key("file"), file, e.to_string()))?;
    let curve = physical_group(file, &mesh.curve_names(), curve, &key("curve"), "curve")?;
    let mut points = mesh.curve_points(curve).map_err(|e| {
        let line = e.line.map(|l| format!(" (line {l})")).unwrap_or_default();
        invalid(&key("curve"), curve, format!("{file}{line}: {}", e.kind))
    })?;
    if reverse == Some(true) {
        points.reverse();
    }
    Polyline::new(&points, 0.0)
        .map_err(|why| invalid(&key("curve"), curve, format!("{file}: as a polyline, {why}")))
}

/// `[geometry]` → the domain, and for a Gmsh geometry the nodes of its mesh.
fn domain(geometry: &GeometryFile) -> Result<(Domain, Option<gmsh::MeshBody>), ProblemError> {
    let (outer, holes) = match geometry {
        GeometryFile::Rectangle { x, y, holes } => {
            for (name, v) in [("geometry.x", x), ("geometry.y", y)] {
                check_finite(name, v[0])?;
                check_finite(name, v[1])?;
                if v[1] <= v[0] {
                    return Err(invalid(name, format!("{v:?}"), "needs min < max"));
                }
            }
            (Domain::rectangle(*x, *y), holes)
        }
        GeometryFile::Polygon { vertices, edges, holes } => {
            (polygon_domain("geometry.", vertices, edges)?, holes)
        }
        GeometryFile::Curves { start, curves, holes } => {
            (curves_domain("geometry.", start, curves)?, holes)
        }
        GeometryFile::Disk { center, radius, holes } => {
            (disk_domain("geometry.", center, *radius, "rim")?, holes)
        }
        GeometryFile::Gmsh { file, surface } => {
            let body = gmsh_body(file, surface.as_deref())?;
            return Ok((body.domain.clone(), Some(body)));
        }
    };
    let outer = outer.map_err(|e| invalid("geometry", "", e.to_string()))?;
    if holes.is_empty() {
        return Ok((outer, None));
    }
    let mut cut = Vec::with_capacity(holes.len());
    for (k, hole) in holes.iter().enumerate() {
        let prefix = format!("geometry.holes[{k}].");
        let d = match hole {
            HoleFile::Disk { center, radius, name } => {
                let default = if holes.len() == 1 { "hole".into() } else { format!("hole{k}") };
                let name = name.clone().unwrap_or(default);
                disk_domain(&prefix, center, *radius, &name)?
            }
            HoleFile::Polygon { vertices, edges } => polygon_domain(&prefix, vertices, edges)?,
            HoleFile::Curves { start, curves } => curves_domain(&prefix, start, curves)?,
        };
        cut.push(d.map_err(|e| invalid(&format!("geometry.holes[{k}]"), "", e.to_string()))?);
    }
    let domain = outer.with_holes(cut).map_err(|e| match e {
        GeometryError::Hole { hole, reason } => {
            invalid(&format!("geometry.holes[{hole}]"), "", format!("the hole {reason}"))
        }
        e => invalid("geometry.holes", "", e.to_string()),
    })?;
    Ok((domain, None))
}

/// A convex polygon (`vertices`, `edges` under the key `prefix`).
fn polygon_domain(
    prefix: &str,
    vertices: &[[f64; 2]],
    edges: &[String],
) -> Result<Result<Domain, GeometryError>, ProblemError> {
    for v in vertices {
        check_finite(&format!("{prefix}vertices"), v[0])?;
        check_finite(&format!("{prefix}vertices"), v[1])?;
    }
    Ok(Domain::polygon(vertices.to_vec(), edges.to_vec()))
}

/// A disk (`center`, `radius` under the key `prefix`) whose rim is the edge `name`.
fn disk_domain(
    prefix: &str,
    center: &[f64; 2],
    radius: f64,
    name: &str,
) -> Result<Result<Domain, GeometryError>, ProblemError> {
    check_finite(&format!("{prefix}center"), center[0])?;
    check_finite(&format!("{prefix}center"), center[1])?;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(invalid(&format!("{prefix}radius"), radius, "must be a positive number"));
    }
    let p = [center[0] + radius, center[1]];
    Ok(Domain::from_curves(vec![Curve::arc_between(p, p, *center, true)], vec![name.into()]))
}

/// A loop of segments and arcs (`start`, `curves` under the key `prefix`).
fn curves_domain(
    prefix: &str,
    start: &[f64; 2],
    curves: &[CurveFile],
) -> Result<Result<Domain, GeometryError>, ProblemError> {
    check_finite(&format!("{prefix}start"), start[0])?;
    check_finite(&format!("{prefix}start"), start[1])?;
    let mut from = *start;
    let mut list = Vec::with_capacity(curves.len());
    for (i, c) in curves.iter().enumerate() {
        let field = |f: &str| format!("{prefix}curves[{i}].{f}");
        check_finite(&field("to"), c.to[0])?;
        check_finite(&field("to"), c.to[1])?;
        let curve = match c.center {
            None => {
                if let Some(turn) = c.turn {
                    return Err(invalid(
                        &field("turn"),
                        format!("{turn:?}").to_lowercase(),
                        "only used with `center` (arcs)",
                    ));
                }
                Curve::Segment { a: from, b: c.to }
            }
            Some(center) => {
                check_finite(&field("center"), center[0])?;
                check_finite(&field("center"), center[1])?;
                let ccw = c.turn.unwrap_or_default() == Turn::Ccw;
                let r0 = (from[0] - center[0]).hypot(from[1] - center[1]);
                let r1 = (c.to[0] - center[0]).hypot(c.to[1] - center[1]);
                if r0 <= 0.0 || (r1 - r0).abs() > 1e-9 * r0 {
                    return Err(invalid(
                        &field("center"),
                        format!("{center:?}"),
                        format!(
                            "the start point is at distance {r0} from the centre but `to` is at {r1}: both must lie on the arc's circle"
                        ),
                    ));
                }
                Curve::arc_between(from, c.to, center, ccw)
            }
        };
        list.push(curve);
        from = c.to;
    }
    Ok(Domain::from_curves(list, curves.iter().map(|c| c.name.clone()).collect()))
}

/// `[nodes]` → the spacing and the layout (the FE path's restrictions included).
fn node_layout(
    file: &BodyParts<'_>,
    domain: &Domain,
    mesh: Option<gmsh::MeshBody>,
    method: Method,
) -> Result<(f64, Layout, Option<Arc<MeshNodes>>), ProblemError> {
    if file.nodes.from == Some(NodesFrom::Mesh) {
        let Some(mesh) = mesh else {
            return Err(invalid(
                "nodes.from",
                "mesh",
                "only with a mesh: geometry.kind = \"gmsh\"",
            ));
        };
        for (key, given) in [
            ("nodes.spacing", file.nodes.spacing.is_some()),
            ("nodes.layout", file.nodes.layout.is_some()),
            ("nodes.jitter", file.nodes.jitter.is_some()),
            ("nodes.seed", file.nodes.seed.is_some()),
            ("nodes.refine", !file.nodes.refine.is_empty()),
        ] {
            if given {
                return Err(invalid(
                    key,
                    "(given)",
                    "not used with nodes.from = \"mesh\" (the mesh gives the nodes and their spacing)",
                ));
            }
        }
        // The nominal spacing (for the checks that compare lengths with it): the mean.
        let h = mesh.spacing.iter().sum::<f64>() / mesh.spacing.len() as f64;
        let nodes =
            MeshNodes { points: mesh.points, spacing: mesh.spacing, elements: mesh.elements };
        return Ok((h, Layout::Structured, Some(Arc::new(nodes))));
    }
    let Some(h) = file.nodes.spacing else {
        return Err(invalid(
            "nodes.spacing",
            "(missing)",
            "the node spacing is required (unless nodes.from = \"mesh\" with a Gmsh geometry)",
        ));
    };
    // A mesh's curved edges keep their nodes as boundary nodes: pieces much longer than the
    // spacing leave the first layer of interior nodes with too few neighbours (the quarter
    // plate's hole in pieces of 0.245 failed at h = 0.125, ran at h = 0.15).
    if mesh.is_some() && h.is_finite() && h > 0.0 {
        for (k, c) in domain.curves().iter().enumerate() {
            if let Curve::Polyline { points } = c {
                let longest = points
                    .windows(2)
                    .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                    .fold(0.0, f64::max);
                if longest > 1.5 * h {
                    return Err(invalid(
                        "nodes.spacing",
                        h,
                        format!(
                            "the mesh's edge `{}` has boundary pieces up to {longest:.4} long, more than 1.5 times the spacing: mesh the curves at about the node spacing, or use nodes.from = \"mesh\"",
                            domain.edge_names()[k]
                        ),
                    ));
                }
            }
        }
    }
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    if !(h.is_finite() && h > 0.0) {
        return Err(invalid("nodes.spacing", h, "must be a positive number"));
    }
    if h > size / 2.0 {
        return Err(invalid(
            "nodes.spacing",
            h,
            format!("must be at most half the domain's smallest extent ({size})"),
        ));
    }
    if domain.area() / (h * h) > 2.0e7 {
        return Err(invalid("nodes.spacing", h, "would create more than 20 million nodes"));
    }
    // A ligament narrower than the spacing (between a hole and another loop) has no node
    // inside it: the layout would leave it unresolved.
    for l in 1..domain.loop_count() {
        let gap = domain.loop_clearance(l);
        if gap < h {
            let key = if mesh.is_some() {
                "nodes.spacing".to_string()
            } else {
                format!("geometry.holes[{}]", l - 1)
            };
            return Err(invalid(
                &key,
                format!("{gap:.6}"),
                format!(
                    "the hole leaves a ligament {gap:.6} wide to the nearest other boundary, narrower than nodes.spacing = {h}: make the spacing finer or the ligament wider"
                ),
            ));
        }
    }
    let layout = match file.nodes.layout.unwrap_or_default() {
        LayoutKind::Structured => {
            if file.nodes.jitter.is_some() {
                return Err(invalid(
                    "nodes.jitter",
                    file.nodes.jitter.unwrap_or_default(),
                    "only used with layout = \"jittered\"",
                ));
            }
            Layout::Structured
        }
        LayoutKind::Jittered => {
            let amplitude = file.nodes.jitter.unwrap_or(0.25);
            if !(amplitude > 0.0 && amplitude <= 0.4) {
                return Err(invalid(
                    "nodes.jitter",
                    amplitude,
                    "must be in (0, 0.4] (fraction of the spacing)",
                ));
            }
            Layout::Jittered { amplitude, seed: file.nodes.seed.unwrap_or(1) }
        }
    };

    if method == Method::Fem {
        if matches!(file.geometry, GeometryFile::Gmsh { .. }) {
            return Err(invalid(
                "nodes.from",
                "(missing)",
                "discretisation.method = \"fem\" on a Gmsh geometry takes the mesh's own elements: set nodes.from = \"mesh\"",
            ));
        }
        if !matches!(file.geometry, GeometryFile::Rectangle { holes, .. } if holes.is_empty()) {
            let kind = match file.geometry {
                GeometryFile::Rectangle { .. } => "rectangle (with holes)",
                GeometryFile::Polygon { .. } => "polygon",
                GeometryFile::Curves { .. } => "curves",
                GeometryFile::Disk { .. } => "disk",
                GeometryFile::Gmsh { .. } => "gmsh",
            };
            return Err(invalid(
                "geometry.kind",
                kind,
                "discretisation.method = \"fem\" meshes rectangles (kind = \"rectangle\", no holes) and Gmsh meshes (kind = \"gmsh\" with nodes.from = \"mesh\")",
            ));
        }
        if layout != Layout::Structured {
            return Err(invalid(
                "nodes.layout",
                "jittered",
                "discretisation.method = \"fem\" needs layout = \"structured\" (the element grid)",
            ));
        }
    }
    Ok((h, layout, None))
}

/// `[refinement]` → the adaptive loop's parameters (any number of bodies, each without holes
/// and not from Gmsh; the MFVM, or the FE's graded grid of a rectangle).
fn adaptive(file: &AdaptiveFile, problem: &Problem) -> Result<Adaptive, ProblemError> {
    // Each body: a loop without holes, not from Gmsh. The candidates' bodies may be curved;
    // an elastic pair's target edge is straight (refused naming the contact's target edge
    // before this, docs/method.md §4.3), which the paired contact marks need.
    let several = problem.body_count() > 1;
    for k in 0..problem.body_count() {
        let Some(p) = problem.body(k) else { continue };
        let gmsh =
            p.domain.curves().iter().any(|c| matches!(c, crate::geometry::Curve::Polyline { .. }));
        if p.domain.has_holes() || p.mesh_nodes.is_some() || gmsh {
            let value = if several {
                format!("(body[{k}]: a domain with holes or a Gmsh body)")
            } else {
                "(a domain with holes or a Gmsh body)".to_string()
            };
            return Err(invalid(
                "refinement",
                value,
                "adaptive refinement is implemented for geometry kind = \"rectangle\", \"polygon\", \"curves\" and \"disk\" without holes",
            ));
        }
    }
    let steps = file.steps.unwrap_or(Adaptive::STEPS);
    if !(1..=30).contains(&steps) {
        return Err(invalid("refinement.steps", steps, "must be 1–30"));
    }
    let max_nodes = file.max_nodes.unwrap_or(Adaptive::MAX_NODES);
    if !(4..=20_000_000).contains(&max_nodes) {
        return Err(invalid("refinement.max_nodes", max_nodes, "must be 4 to 20 000 000"));
    }
    if let Some(t) = file.tolerance {
        if !(t.is_finite() && t > 0.0 && t < 1.0) {
            return Err(invalid(
                "refinement.tolerance",
                t,
                "must be in (0, 1): the relative estimated error at which to stop",
            ));
        }
    }
    let fraction = file.fraction.unwrap_or(Adaptive::FRACTION);
    if !(fraction.is_finite() && fraction > 0.0 && fraction <= 1.0) {
        return Err(invalid(
            "refinement.fraction",
            fraction,
            "must be in (0, 1]: the share of the squared estimate the marked nodes carry",
        ));
    }
    if let Some(v) = file.onset_tolerance {
        accuracy_goal(
            problem,
            "refinement.onset_tolerance",
            v,
            v.is_finite() && v > 0.0,
            "must be a positive length: the distance between the onset's two one-sided estimates at which the onset goal is met",
        )?;
    }
    if let Some(v) = file.force_tolerance {
        accuracy_goal(
            problem,
            "refinement.force_tolerance",
            v,
            v.is_finite() && v > 0.0 && v < 1.0,
            "must be in (0, 1): the relative change of the total contact force between solves at which the force goal is met",
        )?;
    }
    Ok(Adaptive {
        steps,
        max_nodes,
        tolerance: file.tolerance,
        fraction,
        indicator: file.indicator.unwrap_or_default(),
        contact: file.contact.unwrap_or(true),
        onset_tolerance: file.onset_tolerance,
        force_tolerance: file.force_tolerance,
    })
}

/// One accuracy goal of `[refinement]` (`field`, its value `v`): in range (`in_range`, else
/// refused with `what`), and on a problem the goals are implemented for (one MFVM body with a
/// `[contact]` against a rigid obstacle).
fn accuracy_goal(
    problem: &Problem,
    field: &str,
    v: f64,
    in_range: bool,
    what: &str,
) -> Result<(), ProblemError> {
    if !in_range {
        return Err(invalid(field, v, what));
    }
    let single = problem.body_count() == 1
        && problem.contact().is_some()
        && problem.discretisation.method == Method::Mfvm;
    if !single {
        return Err(invalid(
            field,
            v,
            "accuracy goals are implemented for one MFVM body with a [contact] against a rigid obstacle",
        ));
    }
    Ok(())
}

/// `[[nodes.refine]]` → the refinement regions (rectangles, polygons, curves and disks without
/// holes; MFVM only).
fn refinement(
    nodes: &NodesFile,
    geometry: &GeometryFile,
    domain: &Domain,
    h: f64,
    method: Method,
) -> Result<Refinement, ProblemError> {
    if nodes.refine.is_empty() {
        return Ok(Refinement::default());
    }
    // Rectangles: bands are boxes; other loops (no holes): bands are squares along the edge.
    let rectangle =
        domain.as_rectangle().filter(|_| matches!(geometry, GeometryFile::Rectangle { .. }));
    let loop_kind = matches!(
        geometry,
        GeometryFile::Polygon { .. } | GeometryFile::Curves { .. } | GeometryFile::Disk { .. }
    );
    let (dx, dy) = match rectangle {
        Some(r) => r,
        None if loop_kind && !domain.has_holes() => {
            let (lo, hi) = domain.bounding_box();
            ([lo[0], hi[0]], [lo[1], hi[1]])
        }
        None => {
            return Err(invalid(
                "nodes.refine",
                format!("{} table(s)", nodes.refine.len()),
                "refinement is implemented for geometry kind = \"rectangle\", \"polygon\", \"curves\" and \"disk\" without holes",
            ));
        }
    };
    if method == Method::Fem {
        return Err(invalid(
            "nodes.refine",
            format!("{} table(s)", nodes.refine.len()),
            "discretisation.method = \"fem\" meshes a uniform grid; remove [[nodes.refine]]",
        ));
    }
    let mut boxes = Vec::new();
    for (k, r) in nodes.refine.iter().enumerate() {
        let key = |name: &str| format!("nodes.refine[{k}].{name}");
        let s = r.spacing;
        if !(s.is_finite() && s > 0.0 && s <= h) {
            return Err(invalid(
                &key("spacing"),
                s,
                format!("must be a positive number at most nodes.spacing ({h})"),
            ));
        }
        // Each halving of a cell is one quadtree level; 2^-12 h is far below any use.
        if s < h / 4096.0 {
            return Err(invalid(
                &key("spacing"),
                s,
                format!("must be at least nodes.spacing / 4096 ({:e})", h / 4096.0),
            ));
        }
        let region = match (&r.edge, r.width, r.x, r.y) {
            (Some(edge), Some(width), None, None) => {
                let e = domain.edge_index(edge).ok_or_else(|| {
                    invalid(
                        &key("edge"),
                        edge,
                        format!("no such edge; the edges are {:?}", domain.edge_names()),
                    )
                })?;
                let extent = match (rectangle, e) {
                    (Some(_), 0 | 2) => dy[1] - dy[0],
                    (Some(_), _) => dx[1] - dx[0],
                    (None, _) => (dy[1] - dy[0]).min(dx[1] - dx[0]),
                };
                if !(width.is_finite() && width > 0.0 && width <= extent) {
                    return Err(invalid(
                        &key("width"),
                        width,
                        format!(
                            "must be a positive number at most the extent across the edge ({extent})"
                        ),
                    ));
                }
                if rectangle.is_none() {
                    // Squares of half-side `width` centred at points at most `width` apart
                    // along the edge: every point within `width` of it (max norm).
                    let c = domain.curve(e);
                    let n = (c.length() / width).ceil().max(1.0);
                    if n > 1.0e5 {
                        return Err(invalid(
                            &key("width"),
                            width,
                            format!(
                                "is too small for edge {edge:?} (length {:.4e}): at most 100 000 widths along a curved or slanted edge",
                                c.length()
                            ),
                        ));
                    }
                    let n = n as usize;
                    boxes.extend((0..=n).map(|i| {
                        let p = c.point_at(i as f64 / n as f64);
                        RefineBox {
                            x: [p[0] - width, p[0] + width],
                            y: [p[1] - width, p[1] + width],
                            spacing: s,
                        }
                    }));
                    continue;
                }
                // Rectangle edges: bottom, right, top, left.
                match e {
                    0 => RefineBox { x: dx, y: [dy[0], dy[0] + width], spacing: s },
                    1 => RefineBox { x: [dx[1] - width, dx[1]], y: dy, spacing: s },
                    2 => RefineBox { x: dx, y: [dy[1] - width, dy[1]], spacing: s },
                    _ => RefineBox { x: [dx[0], dx[0] + width], y: dy, spacing: s },
                }
            }
            (None, None, Some(x), Some(y)) => {
                for (name, v) in [("x", x), ("y", y)] {
                    check_finite(&key(name), v[0])?;
                    check_finite(&key(name), v[1])?;
                    if v[0] >= v[1] {
                        return Err(invalid(
                            &key(name),
                            format!("[{}, {}]", v[0], v[1]),
                            "must be [low, high] with low < high",
                        ));
                    }
                }
                if x[1] <= dx[0] || x[0] >= dx[1] || y[1] <= dy[0] || y[0] >= dy[1] {
                    let what = if rectangle.is_some() { "rectangle" } else { "bounding box" };
                    return Err(invalid(
                        &key("x"),
                        format!("[{}, {}] (y = [{}, {}])", x[0], x[1], y[0], y[1]),
                        format!(
                            "the box must overlap the {what} x = [{}, {}], y = [{}, {}]",
                            dx[0], dx[1], dy[0], dy[1]
                        ),
                    ));
                }
                RefineBox { x, y, spacing: s }
            }
            _ => {
                let given: Vec<&str> = [
                    ("edge", r.edge.is_some()),
                    ("width", r.width.is_some()),
                    ("x", r.x.is_some()),
                    ("y", r.y.is_some()),
                ]
                .iter()
                .filter(|(_, on)| *on)
                .map(|(n, _)| *n)
                .collect();
                return Err(invalid(
                    &format!("nodes.refine[{k}]"),
                    format!("keys {given:?}"),
                    "give either edge and width (a band along an edge) or x and y (a box), with spacing",
                ));
            }
        };
        boxes.push(region);
    }
    // Every box is clipped to the bounding box widened by two nominal spacings, which holds
    // every cell the graded generators query (a curved domain's grid reaches one spacing past
    // its bounding box): over such a cell the distance to the clipped box equals the distance
    // to the box as given (the box overlaps the bounding box, checked above), so the node set
    // is the same, while a box far larger than the body no longer sizes the spacing index.
    let margin = 2.0 * h;
    for b in &mut boxes {
        b.x = [b.x[0].max(dx[0] - margin), b.x[1].min(dx[1] + margin)];
        b.y = [b.y[0].max(dy[0] - margin), b.y[1].min(dy[1] + margin)];
    }
    // Nodes: the uniform set plus, per region, its part of the rectangle at its spacing.
    let refinement = Refinement { boxes };
    let (lo, hi) = ([dx[0], dy[0]], [dx[1], dy[1]]);
    let estimate = domain.area() / (h * h) + refinement.added_nodes(h, lo, hi);
    let boxes = refinement.boxes;
    if estimate > 2.0e7 {
        return Err(invalid(
            "nodes.refine",
            format!("{} table(s)", boxes.len()),
            format!("would create about {estimate:.3e} nodes, more than 20 million"),
        ));
    }
    Ok(Refinement { boxes })
}

/// `[material]` → the material.
fn material(m: &MaterialFile) -> Result<Material, ProblemError> {
    if check_finite("material.young", m.young)? <= 0.0 {
        return Err(invalid("material.young", m.young, "must be a positive number"));
    }
    if m.young < 1.0 / MAX_MAGNITUDE {
        // A modulus this small underflows in the products of assembly (a subnormal `E` gave a
        // "singular matrix" refusal that blamed the displacement conditions).
        return Err(invalid(
            "material.young",
            format!("{:e}", m.young),
            format!(
                "moduli below {:e} make the arithmetic underflow; rescale the units",
                1.0 / MAX_MAGNITUDE
            ),
        ));
    }
    if !(m.poisson.is_finite() && (0.0..0.5).contains(&m.poisson)) {
        return Err(invalid("material.poisson", m.poisson, "must be in [0, 0.5)"));
    }
    if let Some(rho) = m.density {
        if !(rho.is_finite() && rho > 0.0) {
            return Err(invalid("material.density", rho, "must be a positive number"));
        }
    }
    Ok(Material { young: m.young, poisson: m.poisson, plane: m.plane })
}

/// `[[boundary]]` → one condition per domain edge (traction-free where none is given).
fn edge_conditions(
    conditions: &[BoundaryFile],
    domain: &Domain,
) -> Result<Vec<EdgeCondition>, ProblemError> {
    let mut boundary: Vec<Option<EdgeCondition>> = vec![None; domain.edge_count()];
    for (i, b) in conditions.iter().enumerate() {
        let field = format!("boundary[{i}]");
        let k = domain.edge_index(&b.edge).ok_or_else(|| {
            invalid(
                &format!("{field}.edge"),
                &b.edge,
                format!("no such edge; the edges are {:?}", domain.edge_names()),
            )
        })?;
        if boundary[k].is_some() {
            return Err(invalid(&format!("{field}.edge"), &b.edge, "edge listed twice"));
        }
        let condition = if let Some(p) = b.pressure {
            if b.displacement.is_some() || b.traction.is_some() {
                return Err(invalid(
                    &format!("{field}.pressure"),
                    &b.edge,
                    "pressure cannot be combined with displacement or traction on one edge",
                ));
            }
            EdgeCondition::Pressure(value_field(&format!("{field}.pressure"), p)?)
        } else {
            let mut comps = [None, None];
            for (axis, name) in ["x", "y"].iter().enumerate() {
                let disp = b.displacement.as_ref().and_then(|c| if axis == 0 { c.x } else { c.y });
                let trac = b.traction.as_ref().and_then(|c| if axis == 0 { c.x } else { c.y });
                comps[axis] = Some(match (disp, trac) {
                    (Some(_), Some(_)) => {
                        return Err(invalid(
                            &format!("{field}.{name}"),
                            &b.edge,
                            "a component cannot have both a displacement and a traction",
                        ));
                    }
                    (Some(v), None) => {
                        let key = format!("{field}.displacement.{name}");
                        let value = value_field(&key, v)?;
                        check_displacement(&key, &value, body_size(domain))?;
                        ComponentCondition::Displacement(value)
                    }
                    (None, Some(v)) => ComponentCondition::Traction(value_field(
                        &format!("{field}.traction.{name}"),
                        v,
                    )?),
                    (None, None) => ComponentCondition::Traction(Field::Constant(0.0)),
                });
            }
            let [Some(cx), Some(cy)] = comps else { unreachable!("both components are set above") };
            EdgeCondition::Components([cx, cy])
        };
        boundary[k] = Some(condition);
    }
    Ok(boundary.into_iter().map(|c| c.unwrap_or_else(EdgeCondition::free)).collect())
}

/// The smaller side of a domain's bounding box.
fn smallest_extent(domain: &Domain) -> f64 {
    let (lo, hi) = domain.bounding_box();
    (hi[0] - lo[0]).min(hi[1] - lo[1])
}

/// Directory names of the outputs that a body's name must not take.
const RESERVED_NAMES: [&str; 3] = ["plots", "mfvm", "fem"];

/// `[output] revolve` (degrees in `(0, 360]`, axisymmetric bodies only) and
/// `revolve_segments` (1 to [`Revolve::MAX_SEGMENTS`], only with `revolve`; default
/// `⌈Θ / 5°⌉`).
fn revolve(output: &OutputFile, problem: &Problem) -> Result<Option<Revolve>, ProblemError> {
    let Some(angle) = output.revolve else {
        return match output.revolve_segments {
            Some(n) => Err(invalid(
                "output.revolve_segments",
                n,
                "needs output.revolve, the angle to sweep (degrees)",
            )),
            None => Ok(None),
        };
    };
    if !(0.0..=360.0).contains(&angle) || angle == 0.0 {
        return Err(invalid("output.revolve", angle, "must be an angle in (0, 360] degrees"));
    }
    if !problem.material.is_axisymmetric() {
        return Err(invalid(
            "output.revolve",
            angle,
            "sweeps an axisymmetric section about its axis: needs material.plane = \"axisymmetric\"",
        ));
    }
    let segments = match output.revolve_segments {
        Some(n) if (1..=Revolve::MAX_SEGMENTS).contains(&n) => n,
        Some(n) => {
            let reason = format!("must be 1 to {}", Revolve::MAX_SEGMENTS);
            return Err(invalid("output.revolve_segments", n, reason));
        }
        None => (angle / Revolve::SEGMENT_DEGREES).ceil() as usize,
    };
    Ok(Some(Revolve { angle_degrees: angle, segments }))
}

/// `[output] units`: three names separated by commas (force, length, stress), each 1–16
/// characters without control characters.
fn units(text: &str) -> Result<Units, ProblemError> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let valid =
        |p: &&str| (1..=16).contains(&p.chars().count()) && !p.chars().any(char::is_control);
    match parts.as_slice() {
        [force, length, stress] if parts.iter().all(valid) => Ok(Units {
            force: force.to_string(),
            length: length.to_string(),
            stress: stress.to_string(),
        }),
        _ => Err(invalid(
            "output.units",
            format!("{text:?}"),
            "three unit names separated by commas, force, length and stress (each 1–16 characters), e.g. \"N, mm, MPa\"",
        )),
    }
}

/// A body name that is used as an output directory (`<out>/<name>/`): 1–64 ASCII letters,
/// digits, `_` or `-`, so that it can neither be empty, nor leave the output directory, nor
/// collide with an output file; and not one of [`RESERVED_NAMES`].
fn output_name(field: &str, name: &str) -> Result<String, ProblemError> {
    let safe = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if name.is_empty() || name.len() > 64 || !name.chars().all(safe) {
        return Err(invalid(
            field,
            format!("{name:?}"),
            "a body name names its output directory: use 1–64 letters, digits, '_' or '-'",
        ));
    }
    if RESERVED_NAMES.contains(&name) {
        return Err(invalid(
            field,
            format!("{name:?}"),
            format!("reserved for an output directory; the reserved names are {RESERVED_NAMES:?}"),
        ));
    }
    Ok(name.to_string())
}

/// Prefixes the field name of an [`ProblemError::Invalid`] (for `body[k].` tables).
fn prefixed(prefix: &str, e: ProblemError) -> ProblemError {
    match e {
        ProblemError::Invalid { field, value, reason } => {
            ProblemError::Invalid { field: format!("{prefix}{field}"), value, reason }
        }
        other => other,
    }
}

/// `e` with its key `contact.…` renamed `key.…` (`contact[k].…` for `[[contact]]` tables).
fn rekeyed(e: ProblemError, key: &str) -> ProblemError {
    match e {
        ProblemError::Invalid { field, value, reason } if field.starts_with("contact.") => {
            ProblemError::Invalid {
                field: format!("{key}{}", &field["contact".len()..]),
                value,
                reason,
            }
        }
        other => other,
    }
}

/// `[[contact]]` tables of a problem with several bodies or pairs → the validated pairs:
/// the bodies named (`body`, default the first; `target_body`, default the other of two),
/// each pair checked as the two-body or obstacle contact of `[contact]` is, frictionless and
/// solved by Lemke (one load step); a body against itself and the same pair twice refused.
fn contact_pairs(
    tables: &[ContactFile],
    key: &dyn Fn(usize) -> String,
    obstacles: &[ObstacleFile],
    bodies: &[Problem],
) -> Result<Vec<ContactPair>, ProblemError> {
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    if tables.is_empty() {
        return Err(invalid(
            "contact",
            "(missing)",
            format!(
                "several bodies ({names:?}) need [[contact]] tables, each with the `body` and `edge` that carry the candidates and the `target_body` and `target_edge` they touch"
            ),
        ));
    }
    let find = |field: String, name: &str| {
        names
            .iter()
            .position(|n| *n == name)
            .ok_or_else(|| invalid(&field, name, format!("no such body; the bodies are {names:?}")))
    };
    let mut pairs: Vec<ContactPair> = Vec::new();
    for (k, c) in tables.iter().enumerate() {
        let key = key(k);
        let body = match &c.body {
            Some(name) => find(format!("{key}.body"), name)?,
            None => 0,
        };
        let target_body = match (&c.target_body, &c.target_edge) {
            (Some(name), _) => Some(find(format!("{key}.target_body"), name)?),
            (None, Some(_)) if bodies.len() == 2 => Some(1 - body),
            // One body: `contact_spec` says that a target edge needs a second body.
            (None, Some(_)) if bodies.len() == 1 => None,
            (None, Some(_)) => {
                return Err(invalid(
                    &format!("{key}.target_body"),
                    "(missing)",
                    format!(
                        "with more than two bodies, name the body of `target_edge`; the bodies are {names:?}"
                    ),
                ));
            }
            (None, None) => None,
        };
        if target_body == Some(body) {
            return Err(invalid(
                &format!("{key}.target_body"),
                names[body],
                "a body cannot be its own contact target; name another body",
            ));
        }
        if let (Some(t), None) = (target_body, &c.target_edge) {
            return Err(invalid(
                &format!("{key}.target_edge"),
                "(missing)",
                format!(
                    "the edge of `{}` that `{}`'s edge `{}` touches",
                    names[t], names[body], c.edge
                ),
            ));
        }
        let mut view = bodies[body].clone();
        view.others = target_body.map(|t| bodies[t].clone()).into_iter().collect();
        let (spec, chosen) = contact_spec(c, obstacles, &view).map_err(|e| rekeyed(e, &key))?;
        // All pairs are one LCP: one solver for all ("auto" is Lemke's method here).
        let other = |wanted: ContactSolver| pairs.iter().position(|q| q.spec.solver == wanted);
        let conflict = match spec.solver {
            ContactSolver::ActiveSet => {
                other(ContactSolver::Lemke).map(|j| (j, "active_set", "lemke"))
            }
            ContactSolver::Lemke => {
                other(ContactSolver::ActiveSet).map(|j| (j, "lemke", "active_set"))
            }
            ContactSolver::Auto => None,
        };
        if let Some((j, ours, theirs)) = conflict {
            return Err(invalid(
                &format!("{key}.solver"),
                ours,
                format!(
                    "the contact pairs are solved together in one problem, and contact[{j}].solver is \"{theirs}\"; give every pair the same solver"
                ),
            ));
        }
        let target_edge = match spec.target {
            ContactTarget::Body { edge } => Some(edge),
            _ => None,
        };
        let pair = (body, spec.edge, target_body, target_edge);
        for (j, q) in pairs.iter().enumerate() {
            let q_edge = match q.spec.target {
                ContactTarget::Body { edge } => Some(edge),
                _ => None,
            };
            let same = pair == (q.body, q.spec.edge, q.target_body, q_edge);
            let swapped = target_body.is_some()
                && (Some(body), Some(spec.edge)) == (q.target_body, q_edge)
                && (target_body, target_edge) == (Some(q.body), Some(q.spec.edge));
            let edge_twice = target_body.is_none()
                && q.target_body.is_none()
                && (body, spec.edge) == (q.body, q.spec.edge);
            if same || swapped || edge_twice {
                return Err(invalid(
                    &key,
                    format!("`{}` edge `{}`", names[body], c.edge),
                    format!(
                        "the same contact pair as {}; give each pair once",
                        tables_key_hint(&key, j)
                    ),
                ));
            }
        }
        if tables.iter().take(k).any(|q| q.allow_indefinite != c.allow_indefinite) {
            return Err(invalid(
                &format!("{key}.allow_indefinite"),
                c.allow_indefinite.unwrap_or(false),
                "the pairs share one LCP: give every [[contact]] table the same allow_indefinite",
            ));
        }
        pairs.push(ContactPair { body, spec, target_body, obstacles: chosen });
    }
    Ok(pairs)
}

/// The problem holding `bodies` (the first first) and their contact `pairs`: the first body
/// with the others and the pairs as its scene ([`Problem::others`],
/// [`Problem::contact_pairs`]).
///
/// # Errors
/// [`ProblemError`] for a stiffness condensation in a scene of pairs (named by `key`).
fn encode(
    mut bodies: Vec<Problem>,
    pairs: Vec<ContactPair>,
    key: &dyn Fn(usize) -> String,
) -> Result<Problem, ProblemError> {
    let others = bodies.split_off(1.min(bodies.len()));
    let mut first = bodies.pop().ok_or_else(|| invalid("body", 0, "missing"))?;
    first.others = others;
    first.contact_pairs = pairs;
    if first.is_scene_of_pairs() {
        let stiffness = first
            .contact_pairs
            .iter()
            .position(|p| p.spec.condensation != Condensation::Compliance);
        if let Some(k) = stiffness {
            return Err(invalid(
                &format!("{}.condensation", key(k)),
                "stiffness",
                "several bodies or contact pairs take the compliance condensation only",
            ));
        }
    }
    Ok(first)
}

/// `contact[j]`, for a message about table `key`'s duplicate.
fn tables_key_hint(key: &str, j: usize) -> String {
    match key.find('[') {
        Some(i) => format!("{}[{j}]", &key[..i]),
        None => key.to_string(),
    }
}

fn contact_spec(
    c: &ContactFile,
    obstacles: &[ObstacleFile],
    problem: &Problem,
) -> Result<(ContactSpec, Vec<Obstacle>), ProblemError> {
    let (domain, boundary) = (&problem.domain, &problem.boundary);
    let edge = domain.edge_index(&c.edge).ok_or_else(|| {
        invalid(
            "contact.edge",
            &c.edge,
            format!("no such edge; the edges are {:?}", domain.edge_names()),
        )
    })?;
    if boundary[edge].displacement(0).is_some() || boundary[edge].displacement(1).is_some() {
        return Err(invalid(
            "contact.edge",
            &c.edge,
            "this edge has a displacement condition; a contact edge must be free to move",
        ));
    }
    if let Some(t) = c.gap_tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(invalid("contact.gap_tolerance", t, "must be a positive number"));
        }
    }
    let allow_indefinite = c.allow_indefinite.unwrap_or(false);
    let condensation = c.condensation.unwrap_or_default();
    let friction = c.friction.unwrap_or(0.0);
    let solver = c.solver.unwrap_or_default();
    let interference = c.interference.unwrap_or(0.0);
    if !(interference.is_finite() && interference >= 0.0) {
        return Err(invalid(
            "contact.interference",
            interference,
            "the designed interference of a press or shrink fit must be a finite number ≥ 0",
        ));
    }
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(invalid(
            "contact.friction",
            friction,
            "the Coulomb friction coefficient must be a finite number ≥ 0",
        ));
    }
    if let Some(second) = problem.second_body() {
        if !obstacles.is_empty() || c.target.is_some() {
            return Err(invalid(
                if c.target.is_some() { "contact.target" } else { "obstacle" },
                "",
                "two bodies touch each other: give `target_edge`, not obstacles",
            ));
        }
        if c.obstacle_point.is_some() || c.obstacle_normal.is_some() {
            return Err(invalid(
                "contact.obstacle_point",
                "",
                "two bodies touch each other: give `target_edge`, not an obstacle",
            ));
        }
        let name = c.target_edge.as_deref().ok_or_else(|| {
            invalid(
                "contact.target_edge",
                "(missing)",
                "the edge of the second body that the first body's `edge` touches",
            )
        })?;
        let target = second.domain.edge_index(name).ok_or_else(|| {
            invalid(
                "contact.target_edge",
                name,
                format!(
                    "no such edge of `{}`; its edges are {:?}",
                    second.name,
                    second.domain.edge_names()
                ),
            )
        })?;
        if second.boundary[target].displacement(0).is_some()
            || second.boundary[target].displacement(1).is_some()
        {
            return Err(invalid(
                "contact.target_edge",
                name,
                "this edge has a displacement condition; a contact edge must be free to move",
            ));
        }
        // The edges must face each other: body 1 must lie on the side the target normal points
        // to (a curved target: outside its line or circle, docs/method.md §4.5).
        let target_curve = second.domain.curve(target);
        let (a2, b2) = second.domain.edge(target);
        let target_length = (b2[0] - a2[0]).hypot(b2[1] - a2[1]);
        // The signed distance from the target's line or circle, over it or not.
        let across = |x: Point| -> (bool, f64) {
            match second.domain.straight_normal(target) {
                Some(nu) => (
                    projects_onto(x, a2, b2, 1e-9 * target_length),
                    (x[0] - a2[0]) * nu[0] + (x[1] - a2[1]) * nu[1],
                ),
                None => (
                    (-1e-9..=1.0 + 1e-9).contains(&target_curve.parameter(x)),
                    target_curve.signed_distance(x),
                ),
            }
        };
        if across(domain.centroid()).1 <= 0.0 {
            return Err(invalid(
                "contact.target_edge",
                name,
                "the first body is not on the outer side of this edge of the second body: the bodies would overlap",
            ));
        }
        // Initial interference: the contact edge's points over the target edge may reach
        // across it by at most 10 % of the smaller body's smallest extent (as for a rigid
        // obstacle) and at most the larger node spacing (a prescribed small interference).
        let curve = domain.curve(edge);
        let worst = (0..=1024)
            .map(|i| across(curve.point_at(i as f64 / 1024.0)))
            .filter(|&(over, _)| over)
            .map(|(_, d)| d)
            .fold(f64::INFINITY, f64::min);
        let extent = smallest_extent(domain).min(smallest_extent(&second.domain));
        let allowed = (0.1 * extent).min(problem.node_spacing.max(second.node_spacing));
        if worst < -allowed {
            return Err(invalid(
                "contact.target_edge",
                name,
                format!(
                    "the bodies overlap: the contact edge reaches {:.3e} across this edge of the second body, more than the {allowed:.3e} allowed (10 % of the smaller body's smallest extent, at most the larger node spacing); if the overlap is a designed press or shrink fit, mesh the bodies touching at the nominal interface and declare the overlap as `interference`",
                    -worst
                ),
            ));
        }
        // The interference solved is the declared one plus any small geometric overlap: a
        // small-strain fit, as for the overlap itself.
        if interference - worst.min(0.0) > 0.1 * extent {
            return Err(invalid(
                "contact.interference",
                interference,
                format!(
                    "the interference (with the geometric overlap {:.3e}) exceeds 10 % of the smaller body's smallest extent ({:.3e}): not a small-strain fit",
                    (-worst).max(0.0),
                    0.1 * extent
                ),
            ));
        }
        return Ok((
            ContactSpec {
                edge,
                target: ContactTarget::Body { edge: target },
                gap_tolerance: c.gap_tolerance,
                allow_indefinite,
                condensation,
                friction,
                solver,
                interference,
            },
            Vec::new(),
        ));
    }
    if c.interference.is_some_and(|d| d != 0.0) {
        return Err(invalid(
            "contact.interference",
            interference,
            "only between two elastic bodies (`target_edge`); a rigid obstacle's interference is its position: place it δ into the body (or move it with a `[[step]]`)",
        ));
    }
    if c.target_edge.is_some() {
        return Err(invalid(
            "contact.target_edge",
            "",
            "only for two bodies ([[body]] tables); a rigid obstacle takes obstacle_point and obstacle_normal",
        ));
    }
    let legacy = c.obstacle_point.is_some() || c.obstacle_normal.is_some();
    if legacy && (c.target.is_some() || !obstacles.is_empty()) {
        return Err(invalid(
            "contact.obstacle_point",
            "",
            "give either obstacle_point and obstacle_normal (one line) or [[obstacle]] tables named by `target`, not both",
        ));
    }
    if !legacy && (c.target.is_some() || !obstacles.is_empty()) {
        let chosen = rigid_obstacles(c, obstacles, domain, edge)?;
        let spec = ContactSpec {
            edge,
            target: ContactTarget::Obstacles,
            gap_tolerance: c.gap_tolerance,
            allow_indefinite,
            condensation,
            friction,
            solver,
            interference: 0.0,
        };
        return Ok((spec, chosen));
    }
    let missing = |f: &str| {
        invalid(
            f,
            "(missing)",
            "a rigid obstacle needs obstacle_point and obstacle_normal (or [[obstacle]] tables named by `target`)",
        )
    };
    let obstacle_point = c.obstacle_point.ok_or_else(|| missing("contact.obstacle_point"))?;
    let obstacle_normal = c.obstacle_normal.ok_or_else(|| missing("contact.obstacle_normal"))?;
    for v in obstacle_point {
        check_finite("contact.obstacle_point", v)?;
    }
    for v in obstacle_normal {
        check_finite("contact.obstacle_normal", v)?;
    }
    let [nx, ny] = obstacle_normal;
    let len = nx.hypot(ny);
    if len == 0.0 {
        return Err(invalid("contact.obstacle_normal", "[0, 0]", "must be a non-zero vector"));
    }
    // A component below 1e-12 of the length is round-off: it is snapped to zero, so that a
    // normal given as [1e-300, 1] is the same obstacle as [0, 1].
    let snap = |c: f64| if c.abs() <= 1e-12 * len { 0.0 } else { c };
    let (nx, ny) = (snap(nx), snap(ny));
    let len = nx.hypot(ny);
    let obstacle = RigidLine { point: obstacle_point, normal: [nx / len, ny / len] };
    // The body must lie on the side the normal points to: its centroid, at least.
    let centroid = domain.centroid();
    if obstacle.gap(centroid) <= 0.0 {
        return Err(invalid(
            "contact.obstacle_normal",
            format!("{obstacle_normal:?}"),
            "the body's centroid is not on the side the normal points to: the obstacle would cross the body (the normal must point into the body)",
        ));
    }
    let curve = domain.curve(edge);
    let worst = (0..=1024)
        .map(|i| obstacle.gap(curve.point_at(i as f64 / 1024.0)))
        .fold(f64::INFINITY, f64::min);
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    if worst < -0.1 * size {
        return Err(invalid(
            "contact.obstacle_point",
            format!("{obstacle_point:?}"),
            format!(
                "the obstacle penetrates the contact edge by {:.3e}, more than 10 % of the body's smallest extent: not a small-strain indentation",
                -worst
            ),
        ));
    }
    Ok((
        ContactSpec {
            edge,
            target: ContactTarget::Rigid(obstacle),
            gap_tolerance: c.gap_tolerance,
            allow_indefinite,
            condensation,
            friction,
            solver,
            interference: 0.0,
        },
        Vec::new(),
    ))
}

/// `[[obstacle]]` → the validated obstacles named by `[contact] target` (all of them when it
/// is absent), checked against the body: its centroid outside every obstacle, the contact
/// edge `edge` penetrating none by more than 10 % of the body's smallest extent.
fn rigid_obstacles(
    c: &ContactFile,
    files: &[ObstacleFile],
    domain: &Domain,
    edge: usize,
) -> Result<Vec<Obstacle>, ProblemError> {
    let mut all: Vec<Obstacle> = Vec::with_capacity(files.len());
    for (k, o) in files.iter().enumerate() {
        let key = |f: &str| format!("obstacle[{k}].{f}");
        if o.name.is_empty() {
            return Err(invalid(&key("name"), "\"\"", "an obstacle needs a non-empty name"));
        }
        if all.iter().any(|a| a.name == o.name) {
            return Err(invalid(&key("name"), &o.name, "two obstacles have this name"));
        }
        let given = |f: &str, present: bool| -> Result<(), ProblemError> {
            if present {
                Err(invalid(&key(f), "", format!("not a key of kind \"{}\"", o.kind)))
            } else {
                Ok(())
            }
        };
        let need = |f: &str| invalid(&key(f), "(missing)", format!("kind \"{}\" needs it", o.kind));
        let pair = |f: &str, v: Option<[f64; 2]>| -> Result<[f64; 2], ProblemError> {
            let v = v.ok_or_else(|| need(f))?;
            check_finite(&key(f), v[0])?;
            check_finite(&key(f), v[1])?;
            Ok(v)
        };
        if o.kind != "gmsh" {
            given("file", o.file.is_some())?;
            given("curve", o.curve.is_some())?;
            given("reverse", o.reverse.is_some())?;
        }
        let shape = match o.kind.as_str() {
            "line" => {
                given("centre", o.centre.is_some())?;
                given("radius", o.radius.is_some())?;
                given("points", o.points.is_some())?;
                given("corner_radius", o.corner_radius.is_some())?;
                let point = pair("point", o.point)?;
                let [nx, ny] = pair("normal", o.normal)?;
                let len = nx.hypot(ny);
                if len == 0.0 {
                    return Err(invalid(&key("normal"), "[0, 0]", "must be a non-zero vector"));
                }
                let snap = |c: f64| if c.abs() <= 1e-12 * len { 0.0 } else { c };
                let (nx, ny) = (snap(nx), snap(ny));
                let len = nx.hypot(ny);
                Shape::Line(RigidLine { point, normal: [nx / len, ny / len] })
            }
            "circle" => {
                given("point", o.point.is_some())?;
                given("normal", o.normal.is_some())?;
                given("points", o.points.is_some())?;
                given("corner_radius", o.corner_radius.is_some())?;
                let centre = pair("centre", o.centre)?;
                let radius = o.radius.ok_or_else(|| need("radius"))?;
                if !(radius.is_finite() && radius > 0.0) {
                    return Err(invalid(&key("radius"), radius, "must be a positive number"));
                }
                Shape::Circle { centre, radius }
            }
            "polyline" => {
                given("point", o.point.is_some())?;
                given("normal", o.normal.is_some())?;
                given("centre", o.centre.is_some())?;
                given("radius", o.radius.is_some())?;
                let points = o.points.as_ref().ok_or_else(|| need("points"))?;
                for p in points {
                    check_finite(&key("points"), p[0])?;
                    check_finite(&key("points"), p[1])?;
                }
                let r = o.corner_radius.unwrap_or(0.0);
                if !(r.is_finite() && r >= 0.0) {
                    return Err(invalid(&key("corner_radius"), r, "must be a number ≥ 0"));
                }
                let line = Polyline::new(points, r).map_err(|why| {
                    invalid(&key("points"), format!("{} points", points.len()), why)
                })?;
                Shape::Polyline(line)
            }
            "gmsh" => {
                given("point", o.point.is_some())?;
                given("normal", o.normal.is_some())?;
                given("centre", o.centre.is_some())?;
                given("radius", o.radius.is_some())?;
                given("points", o.points.is_some())?;
                given("corner_radius", o.corner_radius.is_some())?;
                let file = o.file.as_deref().ok_or_else(|| need("file"))?;
                Shape::Polyline(gmsh_obstacle(k, file, o.curve.as_deref(), o.reverse)?)
            }
            other => {
                return Err(invalid(
                    &key("kind"),
                    other,
                    "one of \"line\", \"circle\", \"polyline\", \"gmsh\"",
                ));
            }
        };
        all.push(Obstacle { name: o.name.clone(), shape });
    }
    let names: Vec<String> = all.iter().map(|o| o.name.clone()).collect();
    let chosen: Vec<Obstacle> = match &c.target {
        None => all,
        Some(t) => {
            let mut out: Vec<Obstacle> = Vec::new();
            let wanted = t.names();
            if wanted.is_empty() {
                return Err(invalid("contact.target", "[]", "name at least one [[obstacle]]"));
            }
            for name in wanted {
                let o = all.iter().find(|o| o.name == name).ok_or_else(|| {
                    invalid(
                        "contact.target",
                        name,
                        format!("no [[obstacle]] of that name; the obstacles are {names:?}"),
                    )
                })?;
                if out.iter().any(|p| p.name == name) {
                    return Err(invalid("contact.target", name, "named twice"));
                }
                out.push(o.clone());
            }
            out
        }
    };
    let centroid = domain.centroid();
    for o in &chosen {
        if o.shape.closest(centroid).gap <= 0.0 {
            return Err(invalid(
                "contact.target",
                &o.name,
                format!(
                    "the body's centroid is inside this {} obstacle (or on its side of it): the obstacle would cross the body",
                    o.shape.kind()
                ),
            ));
        }
    }
    let curve = domain.curve(edge);
    let worst = (0..=1024)
        .filter_map(|i| closest_obstacle(&chosen, curve.point_at(i as f64 / 1024.0)))
        .map(|(_, c)| c.gap)
        .fold(f64::INFINITY, f64::min);
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    if worst < -0.1 * size {
        return Err(invalid(
            "contact.target",
            format!("{:?}", chosen.iter().map(|o| o.name.as_str()).collect::<Vec<_>>()),
            format!(
                "the obstacles penetrate the contact edge by {:.3e}, more than 10 % of the body's smallest extent: not a small-strain indentation",
                -worst
            ),
        ));
    }
    Ok(chosen)
}

/// Whether a field is identically zero (a constant 0 or a linear field from 0 to 0).
fn field_is_zero(f: &Field) -> bool {
    match f {
        Field::Constant(v) => *v == 0.0,
        Field::Linear { start, end } => *start == 0.0 && *end == 0.0,
        Field::Function(_) => false,
    }
}

/// `[[step]]` → the load steps of the first body and, with two bodies, of the second (the
/// same steps and increments, each body's own conditions): each step's end state from the
/// previous one (the `[[boundary]]` values, which must be zero, before the first;
/// docs/method.md §8).
fn load_steps(file: &ProblemFile, problem: &Problem) -> Result<Vec<Vec<LoadStep>>, ProblemError> {
    if file.step.is_empty() {
        return Ok(Vec::new());
    }
    // The bodies in order (0 is `problem` itself) and whether there are several.
    let all: Vec<&Problem> = problem.bodies().collect();
    let second = (all.len() > 1).then_some(());
    // One body given as a `[[body]]` table: its steps may name it.
    let one_table = file.body.len() == 1;
    let body_force = all.iter().any(|p| p.body_force.is_some());
    // With [dynamics] the steps are a history in time (docs/method.md §10.5): no contact is
    // needed, and the body force acts in full from time 0.
    let dynamic = file.dynamics.is_some();
    let mut times = Vec::with_capacity(file.step.len());
    for (k, step) in file.step.iter().enumerate() {
        let previous = times.iter().rev().find_map(|t: &Option<f64>| *t).unwrap_or(0.0);
        times.push(super::dynamics::step_time(k, step, previous, dynamic)?);
    }
    let why = if dynamic {
        None
    } else if problem.pairs().is_empty() {
        Some(
            "load steps need contact: without it the problem is linear and one solve gives the answer",
        )
    } else if body_force {
        Some("load steps do not scale the body force yet: remove body_force or the steps")
    } else {
        None
    };
    if let Some(reason) = why {
        return Err(invalid("step", format!("{} steps", file.step.len()), reason));
    }
    // Each body: its name, the key prefix of its [[boundary]], the declared entries, the
    // validated body.
    let bodies: Vec<(&str, String, &[BoundaryFile], &Problem)> = if file.body.is_empty() {
        vec![(problem.name.as_str(), String::new(), &file.boundary, problem)]
    } else {
        all.iter()
            .zip(&file.body)
            .enumerate()
            .map(|(k, (p, b))| (p.name.as_str(), format!("body[{k}]."), &b.boundary[..], *p))
            .collect()
    };
    // The path starts from the unloaded bodies: every value of [[boundary]] is the value
    // before step 1 and must be zero (a step sets the loads).
    for (_, prefix, declared, body) in &bodies {
        starts_unloaded(prefix, declared, body)?;
    }
    // A step's obstacle motion or force moves every rigid obstacle of every pair together
    // (docs/method.md §4.6): it needs a pair against rigid obstacles.
    let movable = problem.pairs().iter().any(|p| p.target_body.is_none());
    let mut states: Vec<(Vec<EdgeCondition>, Vec<LoadStep>)> =
        bodies.iter().map(|b| (b.3.boundary.clone(), Vec::new())).collect();
    let mut obstacle = [0.0, 0.0];
    // A force-driven obstacle (docs/method.md §4.6): set from the first step on.
    let by_force = file.step.iter().any(|s| s.obstacle_force.is_some());
    if by_force && file.step[0].obstacle_force.is_none() {
        return Err(invalid(
            "step[0].obstacle_force",
            "(missing)",
            "with `obstacle_force` in a later step the first step must set it too: an unloaded obstacle's position is not determined by a force",
        ));
    }
    let mut force: Option<[f64; 2]> = None;
    for (k, (step, &time)) in file.step.iter().zip(&times).enumerate() {
        let field = |f: &str| format!("step[{k}].{f}");
        let increments = step.increments.unwrap_or(1);
        if !(1..=100_000).contains(&increments) {
            return Err(invalid(&field("increments"), increments, "must be 1–100000"));
        }
        if let Some(d) = step.obstacle_displacement {
            if !movable {
                return Err(invalid(
                    &field("obstacle_displacement"),
                    format!("{d:?}"),
                    NO_OBSTACLE,
                ));
            }
            let key = field("obstacle_displacement");
            check_finite(&key, d[0])?;
            check_finite(&key, d[1])?;
            check_displacement(
                &key,
                &Field::Constant(d[0].hypot(d[1])),
                body_size(&problem.domain),
            )?;
            obstacle = d;
        }
        let friction = match step.friction {
            None => problem.contact().map_or(0.0, |c| c.friction),
            Some(mu) if mu.is_finite() && mu >= 0.0 => mu,
            Some(mu) => {
                return Err(invalid(
                    &field("friction"),
                    mu,
                    "the Coulomb friction coefficient must be a finite number ≥ 0",
                ));
            }
        };
        if let Some(f) = step.obstacle_force {
            let key = field("obstacle_force");
            if !movable {
                return Err(invalid(&key, format!("{f:?}"), NO_OBSTACLE));
            }
            check_finite(&key, f[0])?;
            check_finite(&key, f[1])?;
            let size = f[0].hypot(f[1]);
            if !(size > 0.0 && size.is_finite()) {
                return Err(invalid(
                    &key,
                    format!("{f:?}"),
                    "the force must be non-zero (its direction is the direction the obstacle moves along)",
                ));
            }
            if let Some(p) = force {
                let (cross, dot) = (p[0] * f[1] - p[1] * f[0], p[0] * f[0] + p[1] * f[1]);
                if dot <= 0.0 || cross.abs() > 1e-12 * size * p[0].hypot(p[1]) {
                    return Err(invalid(
                        &key,
                        format!("{f:?}"),
                        format!(
                            "every step presses the obstacle along the same direction (the first step's force is along {p:?}); only the magnitude may change"
                        ),
                    ));
                }
            }
            force = Some(f);
        }
        if by_force {
            if let Some(d) = step.obstacle_displacement {
                return Err(invalid(
                    &field("obstacle_displacement"),
                    format!("{d:?}"),
                    "the steps press the obstacle by `obstacle_force`: give forces in every step, not displacements",
                ));
            }
        }
        let mut named = Vec::new();
        for (j, b) in step.boundary.iter().enumerate() {
            let f = |g: &str| field(&format!("boundary[{j}].{g}"));
            let names: Vec<&str> = bodies.iter().map(|b| b.0).collect();
            let index = match (&b.body, second) {
                (None, None) => 0,
                // One body given as a `[[body]]` table: its steps may name it.
                (Some(name), None) if one_table && names == [name.as_str()] => 0,
                (Some(name), None) => {
                    return Err(invalid(
                        &f("body"),
                        name,
                        "only with [[body]] tables (a single body's steps name its edges only)",
                    ));
                }
                (None, Some(_)) => {
                    return Err(invalid(
                        &f("body"),
                        "(missing)",
                        format!(
                            "with [[body]] tables each step entry names its body: one of {names:?}"
                        ),
                    ));
                }
                (Some(name), Some(_)) => names.iter().position(|n| n == name).ok_or_else(|| {
                    invalid(&f("body"), name, format!("no such body; the bodies are {names:?}"))
                })?,
            };
            let (name, prefix, declared, body) = &bodies[index];
            let e = body.domain.edge_index(&b.edge).ok_or_else(|| {
                invalid(
                    &f("edge"),
                    &b.edge,
                    format!(
                        "no such edge of `{name}`; its edges are {:?}",
                        body.domain.edge_names()
                    ),
                )
            })?;
            if named.contains(&(index, e)) {
                return Err(invalid(&f("edge"), &b.edge, "edge listed twice in one step"));
            }
            named.push((index, e));
            if !declared.iter().any(|d| body.domain.edge_index(&d.edge) == Some(e)) {
                return Err(invalid(
                    &f("edge"),
                    &b.edge,
                    format!(
                        "this edge has no condition in {}: a step sets the values of declared conditions (declare it there with the value 0)",
                        if prefix.is_empty() {
                            "[[boundary]]".to_string()
                        } else {
                            format!("{prefix}boundary")
                        }
                    ),
                ));
            }
            set_step_values(&f, b, &mut states[index].0[e], body_size(&body.domain))?;
        }
        if dynamic && step.friction.is_some() && problem.pairs().is_empty() {
            return Err(invalid(
                &field("friction"),
                step.friction.unwrap_or(0.0),
                "no contact pair: a step's friction coefficient needs a contact; remove it or add a [contact] table",
            ));
        }
        // With [dynamics] a step may only change the friction (from its previous step's time
        // to its own).
        let only_friction = dynamic && step.friction.is_some();
        if step.obstacle_displacement.is_none()
            && step.obstacle_force.is_none()
            && step.boundary.is_empty()
            && !only_friction
        {
            return Err(invalid(
                &field("boundary"),
                "(missing)",
                if !movable {
                    "a step needs `boundary` values"
                } else {
                    "a step needs `boundary` values, `obstacle_displacement` or `obstacle_force`"
                },
            ));
        }
        for (boundary, steps) in &mut states {
            steps.push(LoadStep {
                increments,
                time,
                boundary: boundary.clone(),
                obstacle_displacement: obstacle,
                obstacle_force: force,
                friction,
                friction_set: step.friction.is_some(),
            });
        }
    }
    Ok(states.into_iter().map(|s| s.1).collect())
}

/// Why a step may not move an obstacle in a scene without one.
const NO_OBSTACLE: &str = "no contact pair is against rigid obstacles: between bodies a step moves a body through its `boundary` values";

/// Refuses a non-zero value among a body's declared conditions `declared` (key paths under
/// `prefix`): with steps the path starts from the unloaded body.
fn starts_unloaded(
    prefix: &str,
    declared: &[BoundaryFile],
    body: &Problem,
) -> Result<(), ProblemError> {
    for (i, b) in declared.iter().enumerate() {
        let Some(k) = body.domain.edge_index(&b.edge) else { continue };
        let nonzero = match &body.boundary[k] {
            EdgeCondition::Pressure(p) => (!field_is_zero(p)).then(|| "pressure".to_string()),
            EdgeCondition::Components(c) => (0..2).find_map(|a| {
                let (kind, f) = match &c[a] {
                    ComponentCondition::Displacement(f) => ("displacement", f),
                    ComponentCondition::Traction(f) => ("traction", f),
                };
                (!field_is_zero(f)).then(|| format!("{kind}.{}", ["x", "y"][a]))
            }),
        };
        if let Some(key) = nonzero {
            return Err(invalid(
                &format!("{prefix}boundary[{i}].{key}"),
                &b.edge,
                "with [[step]] tables the loading starts from the unloaded body: [[boundary]] declares each condition with the value 0 and the steps set its values",
            ));
        }
    }
    Ok(())
}

/// Sets the end values of one step entry `b` on its edge's declared condition (key paths by
/// `f`): the same kind per component, or the pressure.
fn set_step_values(
    f: &dyn Fn(&str) -> String,
    b: &StepBoundaryFile,
    condition: &mut EdgeCondition,
    size: f64,
) -> Result<(), ProblemError> {
    if b.pressure.is_none() && b.displacement.is_none() && b.traction.is_none() {
        return Err(invalid(&f("edge"), &b.edge, "the step gives no value for this edge"));
    }
    match condition {
        EdgeCondition::Pressure(p) => {
            if b.displacement.is_some() || b.traction.is_some() {
                return Err(invalid(
                    &f(if b.displacement.is_some() { "displacement" } else { "traction" }),
                    &b.edge,
                    "this edge has a pressure condition in [[boundary]]; a step can only set its pressure",
                ));
            }
            if let Some(v) = b.pressure {
                *p = value_field(&f("pressure"), v)?;
            }
        }
        EdgeCondition::Components(c) => {
            if b.pressure.is_some() {
                return Err(invalid(
                    &f("pressure"),
                    &b.edge,
                    "this edge has no pressure condition in [[boundary]]",
                ));
            }
            for (axis, name) in ["x", "y"].iter().enumerate() {
                let pick = |c: &Option<ComponentsFile>| {
                    c.as_ref().and_then(|c| if axis == 0 { c.x } else { c.y })
                };
                for (kind, v) in
                    [("displacement", pick(&b.displacement)), ("traction", pick(&b.traction))]
                {
                    let Some(v) = v else { continue };
                    let key = f(&format!("{kind}.{name}"));
                    let value = value_field(&key, v)?;
                    if kind == "displacement" {
                        check_displacement(&key, &value, size)?;
                    }
                    match (&mut c[axis], kind) {
                        (ComponentCondition::Displacement(old), "displacement")
                        | (ComponentCondition::Traction(old), "traction") => *old = value,
                        _ => {
                            return Err(invalid(
                                &key,
                                &b.edge,
                                format!(
                                    "[[boundary]] gives this edge's {name} component no {kind} condition; a step sets the values of declared conditions only"
                                ),
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
