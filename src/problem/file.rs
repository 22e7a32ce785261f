//! The raw problem file: TOML deserialised as written ([`ProblemFile`] and its tables), before
//! any range check. [`super::Problem::try_from`] validates it.

use super::{Basis, Condensation, ContactSolver, Method, Precision, Preset, ProblemError};
use crate::material::PlaneState;
use serde::{Deserialize, Serialize};

/// The problem file as written (TOML). See `problems/*.toml` for annotated examples.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Name used in outputs.
    #[serde(default)]
    pub name: Option<String>,
    /// Body force `[b_x, b_y]` per unit volume.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub body_force: Option<[f64; 2]>,
    /// The domain (single body).
    #[serde(default)]
    pub geometry: Option<GeometryFile>,
    /// Node layout (single body).
    #[serde(default)]
    pub nodes: Option<NodesFile>,
    /// Material (single body).
    #[serde(default)]
    pub material: Option<MaterialFile>,
    /// Two elastic bodies in contact: exactly two `[[body]]` tables instead of the single-body
    /// `geometry`, `nodes`, `material`, `boundary` and `body_force`.
    #[serde(default)]
    pub body: Vec<BodyFile>,
    /// Discretisation (all optional): a `[discretisation]` table or a preset name.
    #[serde(default, deserialize_with = "table_or_preset")]
    pub discretisation: DiscretisationFile,
    /// Boundary conditions per edge; edges not listed are traction-free.
    #[serde(default)]
    pub boundary: Vec<BoundaryFile>,
    /// Output options.
    #[serde(default)]
    pub output: OutputFile,
    /// Contact with a rigid straight obstacle or a second body (frictionless unless
    /// `friction` is given): one `[contact]` table, or several contact pairs as `[[contact]]`
    /// tables (several bodies, several edges).
    #[serde(default)]
    pub contact: Option<ContactTables>,
    /// Load steps (`[[step]]`, docs/method.md §8): the loading path from the unloaded body.
    /// Not echoed when absent, so that summaries without steps are unchanged.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub step: Vec<StepFile>,
    /// Adaptive refinement (`[refinement]`, docs/method.md §2.2). Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement: Option<AdaptiveFile>,
    /// Rigid obstacles (`[[obstacle]]`, docs/method.md §4.4), touched by the contact edge when
    /// `[contact] target` names them. Not echoed when absent.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub obstacle: Vec<ObstacleFile>,
    /// Elastodynamics (`[dynamics]`, docs/method.md §10): time stepping with inertia instead
    /// of one static solve. Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsFile>,
}

/// `[dynamics]`: Moreau–Jean time stepping of one body (docs/method.md §10). `end_time` and
/// `time_step` are required; `[material] density` must be given.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsFile {
    /// The run ends at this time (> 0); it starts at 0.
    pub end_time: f64,
    /// The fixed time step `h` (> 0, at most `end_time`).
    pub time_step: f64,
    /// The θ of the θ-method, in `[0.5, 1]` (default 0.5: no numerical dissipation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    /// Newton's coefficient of restitution `e ∈ [0, 1]` at the contacts (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Ramp the applied loads (tractions, body force) from 0 at time 0 to their full value at
    /// this time, then hold them (`> 0`, at most `end_time`; default: the full loads from time
    /// 0). A slow ramp approaches the static solution (the quasi-static limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_ramp: Option<f64>,
    /// The body's uniform velocity `[vx, vy]` at time 0 (default `[0, 0]`).
    #[serde(
        default,
        deserialize_with = "exact::optional_pair",
        skip_serializing_if = "Option::is_none"
    )]
    pub initial_velocity: Option<[f64; 2]>,
    /// The mass: `"lumped"` (default; the MFVM's `ρ |Ω_I|`, the FE's HRZ) or `"consistent"`
    /// (finite elements only: `ρ ∫ N_a N_b dA`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<super::dynamics::MassKind>,
    /// Snapshot frequency and the like.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<DynamicsOutputFile>,
}

/// `[dynamics.output]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsOutputFile {
    /// Write a snapshot of the bodies (`frames/frame_<step>.vtp`; several bodies: one
    /// `frames/frame_<step>_<k>.vtp` per body and `frames/frame_<step>.vtm` naming them;
    /// indexed by `frames.pvd` for ParaView) every this many steps, and at the first and last (default: no snapshots;
    /// `history.csv` has every step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<usize>,
}

/// `[refinement]`: the solve–estimate–mark–refine loop (rectangles, one body, MFVM). Every
/// key is optional.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveFile {
    /// Refinement steps at most (default 4; 1–30).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<usize>,
    /// Largest node count of a refined node set (default 100 000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_nodes: Option<usize>,
    /// Stop when the relative estimated error is at most this (in `(0, 1)`; default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Dörfler bulk fraction `θ ∈ (0, 1]` (default 0.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fraction: Option<f64>,
    /// `"gradient"` (default) or `"recovery"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub indicator: Option<super::Indicator>,
    /// Also refine around the contact transitions (default `true`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<bool>,
    /// Accuracy goal for the contact onset, a length (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub onset_tolerance: Option<f64>,
    /// Accuracy goal for the total contact force, its relative change between solves
    /// (in `(0, 1)`; default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_tolerance: Option<f64>,
}

/// One `[[obstacle]]`: a named rigid obstacle of kind `"line"` (`point`, `normal` into the
/// body), `"circle"` (`centre`, `radius`; the body outside the disk), `"polyline"`
/// (`points`, the obstacle on their left; optional `corner_radius` rounding the interior
/// corners) or `"gmsh"` (`file`, `curve`: the polyline through a Gmsh physical curve's nodes,
/// the obstacle on its left, `reverse` walking it the other way).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleFile {
    /// Name, for `[contact] target`.
    pub name: String,
    /// `"line"`, `"circle"`, `"polyline"` or `"gmsh"`.
    pub kind: String,
    /// Line: a point of it.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::optional_pair"
    )]
    pub point: Option<[f64; 2]>,
    /// Line: its normal, pointing into the body (normalised on reading).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::optional_pair"
    )]
    pub normal: Option<[f64; 2]>,
    /// Circle: its centre (`center` is accepted too).
    #[serde(
        default,
        alias = "center",
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::optional_pair"
    )]
    pub centre: Option<[f64; 2]>,
    /// Circle: its radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Polyline: its points `[[x, y], …]`, the obstacle on the left when walked in order.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::optional_pairs"
    )]
    pub points: Option<Vec<[f64; 2]>>,
    /// Polyline: radius of the arcs that round its interior corners (default 0: sharp).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_radius: Option<f64>,
    /// Gmsh: the mesh file (MSH 4.1 or 2.2, ASCII; a relative path is relative to the problem
    /// file's folder when the command line resolves it; [`ProblemFile::resolve_paths`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Gmsh: the physical curve whose nodes, in order along its line elements, are the
    /// polyline (optional when the file has one physical curve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<String>,
    /// Gmsh: walk the curve against the direction of its line elements (default `false`), to
    /// put the obstacle on the other side.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reverse: Option<bool>,
}

/// `[contact] target`: one obstacle name or a list of names.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub enum TargetFile {
    /// One name.
    One(String),
    /// Several names.
    Many(Vec<String>),
}

impl TargetFile {
    /// The names.
    pub fn names(&self) -> Vec<&str> {
        match self {
            TargetFile::One(s) => vec![s.as_str()],
            TargetFile::Many(v) => v.iter().map(String::as_str).collect(),
        }
    }
}

/// One `[[step]]`: the end values of named boundary conditions and of the rigid obstacle's
/// displacement, reached linearly in `increments` equal increments from the values at the
/// end of the previous step (zero before the first); with `[dynamics]`, reached linearly in
/// time at `time` (a piecewise-linear history of the values). Conditions a step does not
/// name keep their values.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StepFile {
    /// Equal load increments of the step (default 1, at least 1).
    #[serde(default)]
    pub increments: Option<usize>,
    /// With `[dynamics]`: the time at which the step's values are reached (required there,
    /// increasing from step to step; refused in a static solve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// End values of conditions declared in `[[boundary]]`: the same edge and the same kind
    /// (displacement or traction per component, or pressure); with two `[[body]]` tables each
    /// entry names its body.
    #[serde(default)]
    pub boundary: Vec<StepBoundaryFile>,
    /// Total displacement `[dx, dy]` of the rigid obstacle at the end of the step (it moves
    /// as a rigid body; default: where the previous step left it, initially `[0, 0]`).
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub obstacle_displacement: Option<[f64; 2]>,
    /// Total force `[Fx, Fy]` pressing the rigid obstacle onto the body at the end of the step,
    /// instead of `obstacle_displacement`: the obstacle translates along the force by the
    /// displacement the contact's equilibrium asks for (docs/method.md §4.6; frictionless
    /// steps, the same direction in every step).
    #[serde(
        default,
        deserialize_with = "exact::optional_pair",
        skip_serializing_if = "Option::is_none"
    )]
    pub obstacle_force: Option<[f64; 2]>,
    /// The Coulomb coefficient during this step (default: `[contact] friction`); e.g. 0 in a
    /// press step so that pressing leaves no tangential traction (docs/method.md §8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

/// One entry of a step's `boundary`: a `[[boundary]]` entry's keys, and with two `[[body]]`
/// tables the `body` (its `name`) whose declared condition the entry sets.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StepBoundaryFile {
    /// The body's name (two bodies only; required there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// Edge name (of that body).
    pub edge: String,
    /// End values of prescribed displacement components.
    #[serde(default)]
    pub displacement: Option<ComponentsFile>,
    /// End values of prescribed traction components.
    #[serde(default)]
    pub traction: Option<ComponentsFile>,
    /// End value of the normal pressure.
    #[serde(default)]
    pub pressure: Option<ValueFile>,
}

/// `[contact]`: one edge of the body against a rigid straight line (`obstacle_point`,
/// `obstacle_normal`), against `[[obstacle]]` tables (`target`), or, with two `[[body]]`
/// tables, against an edge of the second body (`target_edge`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// The body carrying the candidates (`[[body]]` name; default the first body). Not
    /// echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// The edge that may touch the obstacle.
    pub edge: String,
    /// A point of the rigid obstacle line.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub obstacle_point: Option<[f64; 2]>,
    /// Normal of the obstacle line, pointing into the body (normalised on reading).
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub obstacle_normal: Option<[f64; 2]>,
    /// Two bodies: the edge of the second body that `edge` (of the first) touches.
    #[serde(default)]
    pub target_edge: Option<String>,
    /// The body whose `target_edge` the edge touches (`[[body]]` name; default the second
    /// body when `target_edge` is given). Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_body: Option<String>,
    /// The `[[obstacle]]` (a name) or obstacles (a list of names) the edge may touch; each
    /// candidate pairs with the closest. Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<TargetFile>,
    /// Absolute gap below which a candidate counts as closed (default 1e-5 · max |g0|).
    #[serde(default)]
    pub gap_tolerance: Option<f64>,
    /// Proceed (with a warning) when the condensed compliance fails its checks.
    #[serde(default)]
    pub allow_indefinite: Option<bool>,
    /// `"compliance"` (default, exact for MLS) or `"stiffness"` (the paper's literal form on
    /// nodal parameters, for comparison).
    #[serde(default)]
    pub condensation: Option<Condensation>,
    /// Coulomb friction coefficient `μ ≥ 0` (default 0: frictionless; docs/method.md §8).
    /// Not echoed when absent, so that frictionless summaries are unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// `"lemke"`, `"active_set"` or `"auto"` (default; docs/method.md §5). Not echoed when
    /// absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<ContactSolver>,
    /// Two bodies: a designed interference `δ ≥ 0` (a press or shrink fit), the initial gaps
    /// reduced by `δ` along the pair's normals (default 0). Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interference: Option<f64>,
}

/// `contact`: one `[contact]` table, or `[[contact]]` tables (one per contact pair). Written
/// back as read (a table, or an array of tables).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum ContactTables {
    /// One `[contact]` table.
    One(Box<ContactFile>),
    /// `[[contact]]` tables, in file order.
    Many(Vec<ContactFile>),
}

impl ContactTables {
    /// The tables, in file order.
    pub fn tables(&self) -> &[ContactFile] {
        match self {
            ContactTables::One(c) => std::slice::from_ref(&**c),
            ContactTables::Many(v) => v,
        }
    }
    /// The tables, mutable.
    pub fn tables_mut(&mut self) -> &mut [ContactFile] {
        match self {
            ContactTables::One(c) => std::slice::from_mut(&mut **c),
            ContactTables::Many(v) => v,
        }
    }
    /// The key path of table `k`: `contact` for one `[contact]` table, `contact[k]` for
    /// `[[contact]]` tables.
    pub fn key(&self, k: usize) -> String {
        match self {
            ContactTables::One(_) => "contact".into(),
            ContactTables::Many(_) => format!("contact[{k}]"),
        }
    }
}

impl From<ContactFile> for ContactTables {
    fn from(c: ContactFile) -> Self {
        ContactTables::One(Box::new(c))
    }
}

impl<'de> Deserialize<'de> for ContactTables {
    /// A table (`[contact]`) or an array of tables (`[[contact]]`); unknown keys inside either
    /// are named with their path (`contact[1].edge`), which an untagged enum cannot do.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Tables;
        impl<'de> serde::de::Visitor<'de> for Tables {
            type Value = ContactTables;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a [contact] table or [[contact]] tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                ContactFile::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(|c| ContactTables::One(Box::new(c)))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Self::Value, A::Error> {
                Vec::<ContactFile>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(ContactTables::Many)
            }
        }
        deserializer.deserialize_any(Tables)
    }
}

/// One `[[body]]` table of a problem with several bodies.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// Name (outputs of the second body go to `<out>/<name>/`).
    #[serde(default)]
    pub name: Option<String>,
    /// Body force `[b_x, b_y]` per unit volume.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub body_force: Option<[f64; 2]>,
    /// The domain.
    pub geometry: GeometryFile,
    /// Node layout.
    pub nodes: NodesFile,
    /// Material.
    pub material: MaterialFile,
    /// Boundary conditions per edge; edges not listed are traction-free.
    #[serde(default)]
    pub boundary: Vec<BoundaryFile>,
    /// With `[dynamics]`: the body's uniform velocity `[vx, vy]` at time 0 (default
    /// `[0, 0]`). Not echoed when absent.
    #[serde(
        default,
        deserialize_with = "exact::optional_pair",
        skip_serializing_if = "Option::is_none"
    )]
    pub initial_velocity: Option<[f64; 2]>,
}

/// `[geometry]`. Read through the flat [`GeometryTable`] (so that a parse error names its key
/// path, e.g. `geometry.x`, which an internally tagged enum cannot), written with `kind` as the
/// tag.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(try_from = "GeometryTable", tag = "kind", rename_all = "snake_case")]
pub enum GeometryFile {
    /// `kind = "rectangle"`, `x = [x0, x1]`, `y = [y0, y1]`; edges `bottom, right, top, left`.
    Rectangle {
        /// `[x0, x1]`.
        x: [f64; 2],
        /// `[y0, y1]`.
        y: [f64; 2],
        /// Holes cut out of the body (`[[geometry.holes]]` or `holes = [{ … }]`).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<HoleFile>,
    },
    /// `kind = "polygon"`: convex, counter-clockwise `vertices` and one name per edge.
    Polygon {
        /// Vertices `[[x, y], …]`.
        vertices: Vec<[f64; 2]>,
        /// Edge names; edge k runs from vertex k to k+1.
        edges: Vec<String>,
        /// Holes cut out of the body (`[[geometry.holes]]` or `holes = [{ … }]`).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<HoleFile>,
    },
    /// `kind = "curves"`: a closed loop of straight segments and circular arcs around the body
    /// (counter-clockwise; the body on the left), from `start` through each curve's `to`,
    /// the last `to` being `start` again. Each curve is one named edge.
    Curves {
        /// Start point of the loop.
        start: [f64; 2],
        /// The curves in order.
        curves: Vec<CurveFile>,
        /// Holes cut out of the body (`[[geometry.holes]]` or `holes = [{ … }]`).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<HoleFile>,
    },
    /// `kind = "disk"`: the full disk; its one edge is named `rim`.
    Disk {
        /// Centre.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
        /// Holes cut out of the body (`[[geometry.holes]]` or `holes = [{ … }]`).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<HoleFile>,
    },
    /// `kind = "gmsh"`: a physical surface of a Gmsh mesh file (MSH 4.1 or 2.2, ASCII); its
    /// edges are the physical curves along its boundary ([`crate::problem::gmsh::MeshBody`]).
    Gmsh {
        /// The mesh file; a relative path is relative to the problem file's folder (the
        /// command line resolves it; [`super::ProblemFile::resolve_paths`]).
        file: String,
        /// The physical surface (required when the file has several).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surface: Option<String>,
    },
}

/// The `kind` of a `[geometry]` table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GeometryKind {
    /// `x`, `y`.
    Rectangle,
    /// `vertices`, `edges`.
    Polygon,
    /// `start`, `curves`.
    Curves,
    /// `center`, `radius`.
    Disk,
    /// `file`, `surface`.
    Gmsh,
}

/// `[geometry]` as written: `kind` and the union of every kind's keys. Converted into
/// [`GeometryFile`], refusing a key of another kind and naming a missing one.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryTable {
    /// The kind.
    pub kind: GeometryKind,
    /// Rectangle: `[x0, x1]`.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub x: Option<[f64; 2]>,
    /// Rectangle: `[y0, y1]`.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub y: Option<[f64; 2]>,
    /// Polygon: vertices.
    #[serde(default, deserialize_with = "exact::optional_pairs")]
    pub vertices: Option<Vec<[f64; 2]>>,
    /// Polygon: edge names.
    #[serde(default)]
    pub edges: Option<Vec<String>>,
    /// Curves: the start point.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub start: Option<[f64; 2]>,
    /// Curves: the curves.
    #[serde(default)]
    pub curves: Option<Vec<CurveFile>>,
    /// Disk: the centre (`centre` is accepted too).
    #[serde(default, alias = "centre", deserialize_with = "exact::optional_pair")]
    pub center: Option<[f64; 2]>,
    /// Disk: the radius.
    #[serde(default)]
    pub radius: Option<f64>,
    /// Gmsh: the mesh file.
    #[serde(default)]
    pub file: Option<String>,
    /// Gmsh: the physical surface.
    #[serde(default)]
    pub surface: Option<String>,
    /// Every kind but Gmsh: the holes.
    #[serde(default)]
    pub holes: Option<Vec<HoleFile>>,
}

impl TryFrom<GeometryTable> for GeometryFile {
    type Error = String;

    fn try_from(g: GeometryTable) -> Result<Self, String> {
        let (name, keys): (&str, &[&str]) = match g.kind {
            GeometryKind::Rectangle => ("rectangle", &["x", "y"]),
            GeometryKind::Polygon => ("polygon", &["vertices", "edges"]),
            GeometryKind::Curves => ("curves", &["start", "curves"]),
            GeometryKind::Disk => ("disk", &["center", "radius"]),
            GeometryKind::Gmsh => ("gmsh", &["file", "surface"]),
        };
        let given = [
            ("x", g.x.is_some()),
            ("y", g.y.is_some()),
            ("vertices", g.vertices.is_some()),
            ("edges", g.edges.is_some()),
            ("start", g.start.is_some()),
            ("curves", g.curves.is_some()),
            ("center", g.center.is_some()),
            ("radius", g.radius.is_some()),
            ("file", g.file.is_some()),
            ("surface", g.surface.is_some()),
        ];
        if g.holes.is_some() && g.kind == GeometryKind::Gmsh {
            return Err(
                "`holes` is not a key of kind = \"gmsh\" (the mesh's surface has its own holes: the loops inside its outer boundary)"
                    .into(),
            );
        }
        let holes = g.holes.unwrap_or_default();
        foreign_key(&given, keys, &format!("kind = \"{name}\""))?;
        let missing = |key: &str| format!("kind = \"{name}\" needs `{key}`");
        Ok(match g.kind {
            GeometryKind::Rectangle => GeometryFile::Rectangle {
                x: g.x.ok_or_else(|| missing("x"))?,
                y: g.y.ok_or_else(|| missing("y"))?,
                holes,
            },
            GeometryKind::Polygon => GeometryFile::Polygon {
                vertices: g.vertices.ok_or_else(|| missing("vertices"))?,
                edges: g.edges.ok_or_else(|| missing("edges"))?,
                holes,
            },
            GeometryKind::Curves => GeometryFile::Curves {
                start: g.start.ok_or_else(|| missing("start"))?,
                curves: g.curves.ok_or_else(|| missing("curves"))?,
                holes,
            },
            GeometryKind::Disk => GeometryFile::Disk {
                center: g.center.ok_or_else(|| missing("center"))?,
                radius: g.radius.ok_or_else(|| missing("radius"))?,
                holes,
            },
            GeometryKind::Gmsh => GeometryFile::Gmsh {
                file: g.file.ok_or_else(|| missing("file"))?,
                surface: g.surface,
            },
        })
    }
}

/// A hole in a `[geometry]` (`holes = [{ kind = "disk", … }, …]`): the region cut out of
/// the body, described as a body would be (its outline counter-clockwise; the body then lies
/// outside it). Read through the flat [`HoleTable`].
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(try_from = "HoleTable", tag = "kind", rename_all = "snake_case")]
pub enum HoleFile {
    /// `kind = "disk"`: a circular hole; its one edge is named `name` (default `hole`, or
    /// `hole<k>` for `holes[k]` when there are several).
    Disk {
        /// Centre.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
        /// The edge name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
    },
    /// `kind = "polygon"`: a convex polygonal hole, counter-clockwise `vertices` and one name
    /// per edge.
    Polygon {
        /// Vertices `[[x, y], …]`.
        vertices: Vec<[f64; 2]>,
        /// Edge names; edge k runs from vertex k to k+1.
        edges: Vec<String>,
    },
    /// `kind = "curves"`: a hole bounded by a loop of segments and arcs, from `start` through
    /// each curve's `to` (counter-clockwise around the hole; arcs `turn = "ccw"` bulge out of
    /// it), each curve one named edge.
    Curves {
        /// Start point of the loop.
        start: [f64; 2],
        /// The curves in order.
        curves: Vec<CurveFile>,
    },
}

/// The `kind` of a hole.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HoleKind {
    /// `center`, `radius`, `name`.
    Disk,
    /// `vertices`, `edges`.
    Polygon,
    /// `start`, `curves`.
    Curves,
}

/// A hole as written: `kind` and the union of every kind's keys ([`HoleFile`]).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HoleTable {
    /// The kind.
    pub kind: HoleKind,
    /// Disk: the centre (`centre` is accepted too).
    #[serde(default, alias = "centre", deserialize_with = "exact::optional_pair")]
    pub center: Option<[f64; 2]>,
    /// Disk: the radius.
    #[serde(default)]
    pub radius: Option<f64>,
    /// Disk: the edge name.
    #[serde(default)]
    pub name: Option<String>,
    /// Polygon: vertices.
    #[serde(default, deserialize_with = "exact::optional_pairs")]
    pub vertices: Option<Vec<[f64; 2]>>,
    /// Polygon: edge names.
    #[serde(default)]
    pub edges: Option<Vec<String>>,
    /// Curves: the start point.
    #[serde(default, deserialize_with = "exact::optional_pair")]
    pub start: Option<[f64; 2]>,
    /// Curves: the curves.
    #[serde(default)]
    pub curves: Option<Vec<CurveFile>>,
}

impl TryFrom<HoleTable> for HoleFile {
    type Error = String;

    fn try_from(g: HoleTable) -> Result<Self, String> {
        let (kind, keys): (&str, &[&str]) = match g.kind {
            HoleKind::Disk => ("disk", &["center", "radius", "name"]),
            HoleKind::Polygon => ("polygon", &["vertices", "edges"]),
            HoleKind::Curves => ("curves", &["start", "curves"]),
        };
        let given = [
            ("center", g.center.is_some()),
            ("radius", g.radius.is_some()),
            ("name", g.name.is_some()),
            ("vertices", g.vertices.is_some()),
            ("edges", g.edges.is_some()),
            ("start", g.start.is_some()),
            ("curves", g.curves.is_some()),
        ];
        foreign_key(&given, keys, &format!("a hole of kind = \"{kind}\""))?;
        let missing = |key: &str| format!("a hole of kind = \"{kind}\" needs `{key}`");
        Ok(match g.kind {
            HoleKind::Disk => HoleFile::Disk {
                center: g.center.ok_or_else(|| missing("center"))?,
                radius: g.radius.ok_or_else(|| missing("radius"))?,
                name: g.name,
            },
            HoleKind::Polygon => HoleFile::Polygon {
                vertices: g.vertices.ok_or_else(|| missing("vertices"))?,
                edges: g.edges.ok_or_else(|| missing("edges"))?,
            },
            HoleKind::Curves => HoleFile::Curves {
                start: g.start.ok_or_else(|| missing("start"))?,
                curves: g.curves.ok_or_else(|| missing("curves"))?,
            },
        })
    }
}

/// One curve of a `kind = "curves"` geometry: from the end of the previous curve (or the
/// loop's `start`) to `to`, straight, or along the circle about `center` when it is given.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CurveFile {
    /// Edge name (used by `[[boundary]]`, `[contact]`, `[output]`).
    pub name: String,
    /// End point.
    #[serde(deserialize_with = "exact::pair")]
    pub to: [f64; 2],
    /// Centre of a circular arc (absent: a straight segment). `to` must lie on the circle
    /// through the start point; `to` equal to the start point gives the full circle.
    #[serde(default, alias = "centre", deserialize_with = "exact::optional_pair")]
    pub center: Option<[f64; 2]>,
    /// Direction of an arc: `"ccw"` (default; the body inside the circle) or `"cw"` (the
    /// body outside it, as around a hole).
    #[serde(default)]
    pub turn: Option<Turn>,
}

/// `[nodes]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NodesFile {
    /// Where the nodes come from: `"layout"` (default; our own layouts inside the boundary)
    /// or `"mesh"` (the nodes of a `kind = "gmsh"` geometry's mesh, each with its local element
    /// size as spacing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<NodesFrom>,
    /// Nominal spacing `h` (> 0); required unless `from = "mesh"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// `"structured"` (default) or `"jittered"`.
    #[serde(default)]
    pub layout: Option<LayoutKind>,
    /// Jitter amplitude as a fraction of `h` (jittered only; default 0.25, range (0, 0.4]).
    #[serde(default)]
    pub jitter: Option<f64>,
    /// Seed of the jitter (default 1).
    #[serde(default)]
    pub seed: Option<u64>,
    /// `[[nodes.refine]]`: regions of finer spacing (rectangles only; absent: uniform).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub refine: Vec<RefineFile>,
}

/// `[[nodes.refine]]`: a region of finer node spacing, either a band along a named edge
/// (`edge`, `width`) or a box (`x`, `y`); the spacing grows back to `nodes.spacing` outside it
/// (docs/method.md §2.1).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RefineFile {
    /// Spacing asked for inside the region (`> 0`, at most `nodes.spacing`).
    pub spacing: f64,
    /// Edge along which to refine (with `width`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<String>,
    /// Width of the band along `edge` (`> 0`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// `[x0, x1]` of a box (with `y`).
    #[serde(
        default,
        deserialize_with = "exact::optional_pair",
        skip_serializing_if = "Option::is_none"
    )]
    pub x: Option<[f64; 2]>,
    /// `[y0, y1]` of a box (with `x`).
    #[serde(
        default,
        deserialize_with = "exact::optional_pair",
        skip_serializing_if = "Option::is_none"
    )]
    pub y: Option<[f64; 2]>,
}

/// `[material]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Young's modulus `E` (> 0).
    pub young: f64,
    /// Poisson's ratio `ν`, `0 ≤ ν < 0.5`.
    pub poisson: f64,
    /// `"stress"`, `"strain"` or `"axisymmetric"` (x the radius, y the axis; docs/method.md §9).
    pub plane: PlaneState,
    /// Mass density `ρ` (> 0): needed only with `[dynamics]`. Not echoed when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
}

/// `[discretisation]`, or a preset name alone (`discretisation = "stabilised"`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiscretisationFile {
    /// `"paper"` or `"stabilised"` ([`super::Preset`]); the other keys override its values.
    #[serde(default)]
    pub preset: Option<Preset>,
    /// `"mfvm"` (default) or `"fem"` (Q2 finite elements; rectangles with structured nodes).
    #[serde(default)]
    pub method: Option<Method>,
    /// `"linear"` (default) or `"quadratic"`.
    #[serde(default)]
    pub basis: Option<Basis>,
    /// `α_s` (default 2; range [1, 6]).
    #[serde(default)]
    pub support_factor: Option<f64>,
    /// Gauss points per segment for the field traction (default 2; 1–8).
    #[serde(default)]
    pub quadrature_points: Option<usize>,
    /// Gauss points per segment for applied tractions (default 5; 3–8).
    #[serde(default)]
    pub load_quadrature_points: Option<usize>,
    /// Stabilisation blend `β ∈ [0, 1]` (0: the paper's mixed method; docs/method.md §3.9), or
    /// `"auto"` ([`super::Discretisation::beta_auto`]; the default for the MFVM without a
    /// `preset`, which otherwise sets β).
    #[serde(default)]
    pub beta: Option<super::BetaChoice>,
    /// Turn the refusal of an unstable `support_factor`/`basis`/`beta` combination into a
    /// warning (default false).
    #[serde(default)]
    pub allow_unstable: Option<bool>,
    /// `"double"` (default), `"mixed"` or `"auto"` ([`super::Precision`]). Not echoed when
    /// absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub precision: Option<Precision>,
}

/// `[output]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputFile {
    /// Edge whose displacement profile is plotted (default: the first edge).
    #[serde(default)]
    pub profile_edge: Option<String>,
    /// Write every load increment's contact table under `steps/` (default `false`; needs
    /// `[[step]]` tables or friction).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<bool>,
    /// Axisymmetric bodies: also write `solution_revolved.vtu`, the section swept about the
    /// axis by this angle in degrees, in (0, 360] (default: not written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revolve: Option<f64>,
    /// The segments (wedges) over the swept angle (default one per 5°; needs `revolve`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revolve_segments: Option<usize>,
    /// The force, length and stress units of the numbers, for axis labels, e.g.
    /// `"N, mm, MPa"` (default: the labels say "length" and "units of E").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
}

/// One `[[boundary]]` entry.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryFile {
    /// Edge name.
    pub edge: String,
    /// Prescribed displacement components, e.g. `{ x = 0.0, y = 0.0 }`.
    #[serde(default)]
    pub displacement: Option<ComponentsFile>,
    /// Prescribed traction components, e.g. `{ y = -1.0 }` or `{ y = [-1.0, -2.0] }`.
    #[serde(default)]
    pub traction: Option<ComponentsFile>,
    /// Normal pressure (positive pushes into the body), constant or `[start, end]`.
    #[serde(default)]
    pub pressure: Option<ValueFile>,
}

/// `{ x = …, y = … }`, each optional.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentsFile {
    /// x component.
    #[serde(default)]
    pub x: Option<ValueFile>,
    /// y component.
    #[serde(default)]
    pub y: Option<ValueFile>,
}

/// A constant or a `[start, end]` pair varying linearly along the edge.
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub enum ValueFile {
    /// Constant.
    Constant(f64),
    /// Linear from the edge's first vertex to its second.
    Linear(#[serde(deserialize_with = "exact::pair")] [f64; 2]),
}

impl ProblemFile {
    /// Parses TOML text.
    ///
    /// # Errors
    /// [`ProblemError::Parse`] with the TOML error (line, column, unknown or missing key).
    pub fn from_toml(text: &str) -> Result<Self, ProblemError> {
        let deserializer =
            toml::de::Deserializer::parse(text).map_err(|e| ProblemError::Parse(e.to_string()))?;
        with_key_path(deserializer)
    }

    /// Parses JSON text with the same keys and tables as the TOML problem file (what the
    /// Python package sends for a problem given as a dict).
    ///
    /// # Errors
    /// [`ProblemError::Parse`] with the JSON error and the key path (`at `geometry.x``).
    pub fn from_json(text: &str) -> Result<Self, ProblemError> {
        with_key_path(&mut serde_json::Deserializer::from_str(text))
    }

    /// Makes the relative paths of the file (`kind = "gmsh"` geometries' and obstacles'
    /// `file`) relative to `folder`, the problem file's folder; absolute paths are kept.
    pub fn resolve_paths(&mut self, folder: &std::path::Path) {
        let geometries =
            self.geometry.iter_mut().chain(self.body.iter_mut().map(|b| &mut b.geometry));
        let geometry_files = geometries.filter_map(|g| match g {
            GeometryFile::Gmsh { file, .. } => Some(file),
            _ => None,
        });
        let obstacle_files = self.obstacle.iter_mut().filter_map(|o| o.file.as_mut());
        for file in geometry_files.chain(obstacle_files) {
            if std::path::Path::new(file.as_str()).is_relative() {
                *file = folder.join(file.as_str()).to_string_lossy().into_owned();
            }
        }
    }
}

/// Deserialises a [`ProblemFile`] from any format, naming the key path of an error
/// (`at `geometry.x`: …`) unless it is the document's root.
fn with_key_path<'de, D>(deserializer: D) -> Result<ProblemFile, ProblemError>
where
    D: serde::Deserializer<'de>,
    D::Error: std::fmt::Display,
{
    serde_path_to_error::deserialize(deserializer).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        if path == "." {
            ProblemError::Parse(inner.to_string())
        } else {
            ProblemError::Parse(format!("at `{path}`: {inner}"))
        }
    })
}

/// Reads `discretisation` as a table ([`DiscretisationFile`], unknown keys refused with their
/// name) or as a preset name alone (`discretisation = "stabilised"`).
fn table_or_preset<'de, D>(deserializer: D) -> Result<DiscretisationFile, D::Error>
where
    D: serde::Deserializer<'de>,
{
    struct TableOrPreset;
    impl<'de> serde::de::Visitor<'de> for TableOrPreset {
        type Value = DiscretisationFile;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a [discretisation] table or a preset name (\"paper\", \"stabilised\")")
        }
        fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<Self::Value, E> {
            let preset = Preset::deserialize(serde::de::value::StrDeserializer::<E>::new(name))?;
            Ok(DiscretisationFile { preset: Some(preset), ..Default::default() })
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
            DiscretisationFile::deserialize(serde::de::value::MapAccessDeserializer::new(map))
        }
    }
    deserializer.deserialize_any(TableOrPreset)
}

// Constructors for building a problem in code (`examples/build_problem.rs`): each returns the
// table with its other keys at their defaults, as if left out of the file.

impl NodesFile {
    /// `[nodes] spacing = h` on the structured layout.
    pub fn structured(spacing: f64) -> Self {
        Self {
            from: None,
            spacing: Some(spacing),
            layout: None,
            jitter: None,
            seed: None,
            refine: Vec::new(),
        }
    }
}

impl MaterialFile {
    /// `[material]`: Young's modulus, Poisson's ratio and the plane state.
    pub fn new(young: f64, poisson: f64, plane: PlaneState) -> Self {
        Self { young, poisson, plane, density: None }
    }
}

impl ComponentsFile {
    /// Both components, constant.
    pub fn xy(x: f64, y: f64) -> Self {
        Self { x: Some(x.into()), y: Some(y.into()) }
    }
    /// The `x` component alone (`y` free).
    pub fn x(x: f64) -> Self {
        Self { x: Some(x.into()), y: None }
    }
    /// The `y` component alone (`x` free).
    pub fn y(y: f64) -> Self {
        Self { x: None, y: Some(y.into()) }
    }
}

impl From<f64> for ValueFile {
    fn from(v: f64) -> Self {
        ValueFile::Constant(v)
    }
}

impl From<[f64; 2]> for ValueFile {
    /// `[start, end]`, linear along the edge.
    fn from(v: [f64; 2]) -> Self {
        ValueFile::Linear(v)
    }
}

impl BoundaryFile {
    /// `[[boundary]]`: prescribed displacement components on `edge`.
    pub fn displacement(edge: impl Into<String>, components: ComponentsFile) -> Self {
        Self { edge: edge.into(), displacement: Some(components), ..Self::default() }
    }
    /// `[[boundary]]`: a traction (force per unit length, global components) on `edge`.
    pub fn traction(edge: impl Into<String>, components: ComponentsFile) -> Self {
        Self { edge: edge.into(), traction: Some(components), ..Self::default() }
    }
    /// `[[boundary]]`: a pressure (pushing into the body) on `edge`.
    pub fn pressure(edge: impl Into<String>, pressure: impl Into<ValueFile>) -> Self {
        Self { edge: edge.into(), pressure: Some(pressure.into()), ..Self::default() }
    }
}

impl ContactFile {
    /// `[contact]`: `edge` against the rigid straight line through `point` with unit normal
    /// `normal` pointing into the body.
    pub fn rigid_line(edge: impl Into<String>, point: [f64; 2], normal: [f64; 2]) -> Self {
        Self {
            edge: edge.into(),
            obstacle_point: Some(point),
            obstacle_normal: Some(normal),
            ..Self::default()
        }
    }
    /// `[contact]` of two bodies: `edge` of the first against `target_edge` of the second.
    pub fn bodies(edge: impl Into<String>, target_edge: impl Into<String>) -> Self {
        Self { edge: edge.into(), target_edge: Some(target_edge.into()), ..Self::default() }
    }
}

/// The direction of a circular arc in `[geometry] curves` (`turn = "ccw" | "cw"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Turn {
    /// Counter-clockwise (default): the body inside the circle.
    #[default]
    Ccw,
    /// Clockwise: the body outside the circle (around a hole).
    Cw,
}

/// `[nodes] from`: where the nodes come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NodesFrom {
    /// Our own layouts inside the boundary (`spacing`, `layout`; default).
    #[default]
    Layout,
    /// The nodes of the geometry's mesh (`kind = "gmsh"` only).
    Mesh,
}

/// `[nodes] layout`: the node layout's name (its parameters are the table's other keys).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LayoutKind {
    /// A regular grid (default).
    #[default]
    Structured,
    /// The grid with seeded random offsets of the interior nodes (`jitter`, `seed`).
    Jittered,
}

/// Fixed-length arrays read exactly: serde's `[f64; 2]` would drop extra elements silently.
mod exact {
    use serde::de::{Deserialize, Deserializer, Error};

    fn two<E: Error>(v: &[f64]) -> Result<[f64; 2], E> {
        <[f64; 2]>::try_from(v).map_err(|_| E::invalid_length(v.len(), &"exactly 2 numbers"))
    }

    /// `[a, b]`, exactly two numbers.
    pub fn pair<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
        two(&Vec::<f64>::deserialize(d)?)
    }

    /// An optional `[a, b]`.
    pub fn optional_pair<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        Option::<Vec<f64>>::deserialize(d)?.map(|v| two(&v)).transpose()
    }

    /// An optional `[[a, b], …]`, each exactly two numbers.
    pub fn optional_pairs<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
        match Option::<Vec<Vec<f64>>>::deserialize(d)? {
            Some(list) => list.iter().map(|v| two(v)).collect::<Result<_, _>>().map(Some),
            None => Ok(None),
        }
    }
}

/// Refuses the first key `given` (present) that is not among `keys`, the keys of `what`.
fn foreign_key(given: &[(&str, bool)], keys: &[&str], what: &str) -> Result<(), String> {
    match given.iter().find(|(key, present)| *present && !keys.contains(key)) {
        Some((key, _)) => {
            Err(format!("`{key}` is not a key of {what} (its keys are {})", keys.join(", ")))
        }
        None => Ok(()),
    }
}
