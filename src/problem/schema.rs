//! A JSON Schema (draft 2020-12) of the problem file, for editors that check TOML against one
//! (`#:schema` comments in Taplo and Even Better TOML) and for generated input.
//!
//! Written by hand after the raw structs of [`super::file`]: one `$defs` entry per struct,
//! named after it, with its keys (aliases included) as `properties` and
//! `additionalProperties: false`, as `deny_unknown_fields` refuses the others.
//! `tests/guide_keys.rs` checks that each entry's keys are exactly its struct's, and that
//! the schema accepts every shipped problem file and refuses an unknown key. The schema
//! describes shapes and types (and the string() values); the ranges are checked by
//! `Problem::try_from`.

use serde_json::{Map, Value, json};

/// A string.
fn string() -> Value {
    json!({ "type": "string" })
}

/// `true` or `false`.
fn boolean() -> Value {
    json!({ "type": "boolean" })
}

/// A non-negative integer.
fn integer() -> Value {
    json!({ "type": "integer", "minimum": 0 })
}

/// A value along an edge: a number, or `[start, end]`.
fn value() -> Value {
    json!({ "anyOf": [number(), pair()] })
}

/// A number.
fn number() -> Value {
    json!({ "type": "number" })
}

/// `[a, b]`, exactly two numbers.
fn pair() -> Value {
    json!({ "type": "array", "items": number(), "minItems": 2, "maxItems": 2 })
}

/// `[[x, y], …]`.
fn pairs() -> Value {
    json!({ "type": "array", "items": pair() })
}

/// One of the string() `values`.
fn one_of(values: &[&str]) -> Value {
    json!({ "type": "string", "enum": values })
}

/// A reference to the `$defs` entry `name`.
fn def(name: &str) -> Value {
    json!({ "$ref": format!("#/$defs/{name}") })
}

/// An array of `$defs` entries `name`.
fn list_of(name: &str) -> Value {
    json!({ "type": "array", "items": def(name) })
}

/// A table of `properties`, no other key allowed.
fn table(properties: Value, required: &[&str]) -> Value {
    json!({
        "type": "object",
        "properties": properties,
        "required": required,
        "additionalProperties": false
    })
}

/// The `$defs` of `[geometry]` (with curves and holes), `[nodes]` and `[[nodes.refine]]`.
fn geometry_and_nodes(defs: &mut Map<String, Value>) {
    let mut add = |name: &str, schema: Value| {
        defs.insert(name.to_string(), schema);
    };
    add(
        "GeometryTable",
        table(
            json!({
                "kind": one_of(&["rectangle", "polygon", "curves", "disk", "gmsh"]),
                "x": pair(), "y": pair(), "vertices": pairs(),
                "edges": { "type": "array", "items": string() },
                "start": pair(), "curves": list_of("CurveFile"),
                "center": pair(), "centre": pair(), "radius": number(),
                "file": string(), "surface": string(), "holes": list_of("HoleTable"),
            }),
            &["kind"],
        ),
    );
    add(
        "HoleTable",
        table(
            json!({
                "kind": one_of(&["disk", "polygon", "curves"]),
                "center": pair(), "centre": pair(), "radius": number(), "name": string(),
                "vertices": pairs(), "edges": { "type": "array", "items": string() },
                "start": pair(), "curves": list_of("CurveFile"),
            }),
            &["kind"],
        ),
    );
    add(
        "CurveFile",
        table(
            json!({
                "name": string(), "to": pair(), "center": pair(), "centre": pair(),
                "turn": one_of(&["ccw", "cw"]),
            }),
            &["name", "to"],
        ),
    );
    add(
        "NodesFile",
        table(
            json!({
                "from": one_of(&["layout", "mesh"]), "spacing": number(),
                "layout": one_of(&["structured", "jittered"]), "jitter": number(),
                "seed": integer(), "refine": list_of("RefineFile"),
            }),
            &[],
        ),
    );
    add(
        "RefineFile",
        table(
            json!({ "spacing": number(), "edge": string(), "width": number(), "x": pair(), "y": pair() }),
            &["spacing"],
        ),
    );
}

/// The `$defs` of `[material]`, `[discretisation]`, `[[boundary]]` and its components.
fn material_and_loads(defs: &mut Map<String, Value>) {
    let mut add = |name: &str, schema: Value| {
        defs.insert(name.to_string(), schema);
    };
    add(
        "MaterialFile",
        table(
            json!({
                "young": number(), "poisson": number(),
                "plane": one_of(&["stress", "strain", "axisymmetric"]), "density": number(),
            }),
            &["young", "poisson", "plane"],
        ),
    );
    add(
        "DiscretisationFile",
        table(
            json!({
                "preset": one_of(&["paper", "stabilised"]), "method": one_of(&["mfvm", "fem"]),
                "basis": one_of(&["linear", "quadratic"]), "support_factor": number(),
                "quadrature_points": integer(), "load_quadrature_points": integer(),
                "beta": { "anyOf": [number(), one_of(&["auto"])] }, "allow_unstable": boolean(),
                "precision": one_of(&["double", "mixed", "auto"]),
            }),
            &[],
        ),
    );
    add("ComponentsFile", table(json!({ "x": value(), "y": value() }), &[]));
    let boundary = json!({
        "edge": string(), "displacement": def("ComponentsFile"),
        "traction": def("ComponentsFile"), "pressure": value(),
    });
    add("BoundaryFile", table(boundary.clone(), &["edge"]));
    let mut step_boundary = boundary;
    step_boundary["body"] = string();
    add("StepBoundaryFile", table(step_boundary, &["edge"]));
}

/// The `$defs` of `[contact]`, `[[obstacle]]`, `[[step]]` and its boundary entries.
fn contact(defs: &mut Map<String, Value>) {
    let mut add = |name: &str, schema: Value| {
        defs.insert(name.to_string(), schema);
    };
    add(
        "ContactFile",
        table(
            json!({
                "body": string(), "edge": string(), "obstacle_point": pair(),
                "obstacle_normal": pair(), "target_edge": string(), "target_body": string(),
                "target": { "anyOf": [string(), { "type": "array", "items": string() }] },
                "gap_tolerance": number(), "allow_indefinite": boolean(),
                "condensation": one_of(&["compliance", "stiffness"]), "friction": number(),
                "solver": one_of(&["lemke", "active_set", "auto"]), "interference": number(),
            }),
            &["edge"],
        ),
    );
    add(
        "ObstacleFile",
        table(
            json!({
                "name": string(), "kind": one_of(&["line", "circle", "polyline", "gmsh"]),
                "point": pair(), "normal": pair(), "centre": pair(), "center": pair(),
                "radius": number(), "points": pairs(), "corner_radius": number(),
                "file": string(), "curve": string(), "reverse": boolean(),
            }),
            &["name", "kind"],
        ),
    );
    add(
        "StepFile",
        table(
            json!({
                "increments": integer(), "time": number(), "boundary": list_of("StepBoundaryFile"),
                "obstacle_displacement": pair(), "obstacle_force": pair(), "friction": number(),
            }),
            &[],
        ),
    );
}

/// The `$defs` of `[[body]]`, `[refinement]`, `[dynamics]` and `[output]`.
fn bodies_and_control(defs: &mut Map<String, Value>) {
    let mut add = |name: &str, schema: Value| {
        defs.insert(name.to_string(), schema);
    };
    add(
        "BodyFile",
        table(
            json!({
                "name": string(), "body_force": pair(), "geometry": def("GeometryTable"),
                "nodes": def("NodesFile"), "material": def("MaterialFile"),
                "boundary": list_of("BoundaryFile"), "initial_velocity": pair(),
            }),
            &["geometry", "nodes", "material"],
        ),
    );
    add(
        "AdaptiveFile",
        table(
            json!({
                "steps": integer(), "max_nodes": integer(), "tolerance": number(),
                "fraction": number(), "indicator": one_of(&["gradient", "recovery"]),
                "contact": boolean(), "onset_tolerance": number(), "force_tolerance": number(),
            }),
            &[],
        ),
    );
    add("DynamicsOutputFile", table(json!({ "every": integer() }), &[]));
    add(
        "DynamicsFile",
        table(
            json!({
                "end_time": number(), "time_step": number(), "theta": number(),
                "restitution": number(), "load_ramp": number(), "initial_velocity": pair(),
                "mass": one_of(&["lumped", "consistent"]),
                "output": def("DynamicsOutputFile"),
            }),
            &["end_time", "time_step"],
        ),
    );
    add(
        "OutputFile",
        table(
            json!({
                "profile_edge": string(), "steps": boolean(), "revolve": number(),
                "revolve_segments": integer(), "units": string(),
            }),
            &[],
        ),
    );
}

/// The schema of the problem file.
pub fn problem_file() -> Value {
    let mut defs = Map::new();
    geometry_and_nodes(&mut defs);
    material_and_loads(&mut defs);
    contact(&mut defs);
    bodies_and_control(&mut defs);
    let mut root = table(
        json!({
            "name": string(), "body_force": pair(), "geometry": def("GeometryTable"),
            "nodes": def("NodesFile"), "material": def("MaterialFile"),
            "body": list_of("BodyFile"),
            "discretisation": { "anyOf": [one_of(&["paper", "stabilised"]), def("DiscretisationFile")] },
            "boundary": list_of("BoundaryFile"), "output": def("OutputFile"),
            "contact": { "anyOf": [def("ContactFile"), list_of("ContactFile")] },
            "step": list_of("StepFile"), "refinement": def("AdaptiveFile"),
            "obstacle": list_of("ObstacleFile"), "dynamics": def("DynamicsFile"),
        }),
        &[],
    );
    root["$schema"] = json!("https://json-schema.org/draft/2020-12/schema");
    root["title"] = json!("mlpg-contact problem file");
    root["$defs"] = Value::Object(defs);
    root
}
