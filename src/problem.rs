//! Stage 0: the problem description — a raw TOML form ([`ProblemFile`]) validated into a
//! checked [`Problem`]. Only a `Problem` reaches the solver.

use crate::contact::{Condensation, ContactSpec, ContactTarget, RigidLine};
use crate::geometry::{Curve, Domain, Point};
use crate::material::{Material, PlaneState};
use crate::mls::{Basis, MlsParams};
use crate::nodes::Layout;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A scalar field along an edge: constant, linear in the edge parameter, or any function of
/// position (library use only).
#[derive(Clone)]
pub enum Field {
    /// The same value everywhere.
    Constant(f64),
    /// `start` at the edge's first vertex to `end` at its second, linearly.
    Linear {
        /// Value at the first vertex.
        start: f64,
        /// Value at the second vertex.
        end: f64,
    },
    /// Any function of position.
    Function(Arc<dyn Fn(Point) -> f64 + Send + Sync>),
}

impl std::fmt::Debug for Field {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Field::Constant(v) => write!(f, "Constant({v})"),
            Field::Linear { start, end } => write!(f, "Linear({start} -> {end})"),
            Field::Function(_) => write!(f, "Function(..)"),
        }
    }
}

impl Field {
    /// Value at point `p` with edge parameter `t ∈ [0, 1]`.
    pub fn value(&self, p: Point, t: f64) -> f64 {
        match self {
            Field::Constant(v) => *v,
            Field::Linear { start, end } => start + t * (end - start),
            Field::Function(f) => f(p),
        }
    }
    /// Whether the field is identically zero (a constant 0).
    pub fn is_zero(&self) -> bool {
        matches!(self, Field::Constant(v) if *v == 0.0)
    }
}

/// What is prescribed for one displacement component on an edge.
#[derive(Clone, Debug)]
pub enum ComponentCondition {
    /// Traction component `t̄_i` (force per length).
    Traction(Field),
    /// Displacement component `ū_i`, imposed by collocation of `u^h` at the edge's nodes.
    Displacement(Field),
}

/// The boundary condition on one domain edge.
#[derive(Clone, Debug)]
pub enum EdgeCondition {
    /// Per component (`[x, y]`): traction or displacement.
    Components([ComponentCondition; 2]),
    /// Normal pressure `p`, `t̄ = −p n` (positive pushes into the body).
    Pressure(Field),
}

impl EdgeCondition {
    /// Traction-free.
    pub fn free() -> Self {
        let zero = || ComponentCondition::Traction(Field::Constant(0.0));
        EdgeCondition::Components([zero(), zero()])
    }
    /// Displacement prescribed for component `axis`, if any.
    pub fn displacement(&self, axis: usize) -> Option<&Field> {
        match self {
            EdgeCondition::Components(c) => match &c[axis] {
                ComponentCondition::Displacement(f) => Some(f),
                ComponentCondition::Traction(_) => None,
            },
            EdgeCondition::Pressure(_) => None,
        }
    }
}

/// Which discretisation solves the problem.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The meshless mixed MLPG finite volume method (default).
    #[default]
    Mfvm,
    /// Biquadratic (Q2, 9-node) finite elements on a structured mesh of a rectangle
    /// ([`crate::fem`]); an independent check of the MFVM (issue 5).
    Fem,
}

/// A named set of discretisation parameters (`discretisation = "paper"` or
/// `discretisation = "stabilised"` in a problem file, or `preset = …` inside the
/// `[discretisation]` table, whose other keys then override the preset's values).
///
/// Chosen from the issue-7 study (docs/dev/beta_study.md, "Presets"): on the beam on a rigid
/// foundation and the Hertz cylinder, [`Preset::Stabilised`] reaches the issues' accuracy
/// targets (contact onset within 0.05 and total force within 0.1 % on the beam; Hertz `a`
/// within 1 % and `p₀` within 0.5 %) in a fraction of the paper's time, with half its matrix
/// nonzeros; the paper's method is more accurate in the total contact force at equal spacing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The paper's mixed MFVM: linear basis, `α_s = 2`, `β = 0`, 2 Gauss points per segment
    /// (the defaults).
    Paper,
    /// The stabilised MFVM with direct MLS strains at the cell boundaries: linear basis,
    /// `α_s = 2`, `β = 1`, 2 Gauss points per segment (method.md §3.9).
    Stabilised,
}

impl Preset {
    /// All presets with their problem-file names.
    pub const ALL: [(&'static str, Preset); 2] =
        [("paper", Preset::Paper), ("stabilised", Preset::Stabilised)];

    /// The preset's `(basis, support_factor, beta, quadrature_points)`.
    pub fn values(self) -> (Basis, f64, f64, usize) {
        match self {
            Preset::Paper => (Basis::Linear, 2.0, 0.0, 2),
            Preset::Stabilised => (Basis::Linear, 2.0, 1.0, 2),
        }
    }
}

/// Discretisation parameters of the mixed MFVM (and the choice of method).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Discretisation {
    /// The preset the values started from, if the problem file named one.
    pub preset: Option<Preset>,
    /// The method (default [`Method::Mfvm`]); the MLS and face-quadrature fields are ignored
    /// by [`Method::Fem`].
    pub method: Method,
    /// MLS approximation parameters.
    pub mls: MlsParams,
    /// Gauss–Legendre points per cell-boundary segment for the field traction (default 2).
    pub quadrature_points: usize,
    /// Gauss–Legendre points per segment for applied tractions (default 5, at least 3).
    pub load_quadrature_points: usize,
    /// Stabilisation blend `β ∈ [0, 1]` (method.md §3.9): the stress at a cell-boundary
    /// Gauss point `x_q` is `σ_q = D[(1 − β) Σ_J φ_J(x_q) ε̂_J + β Σ_K B_K(x_q) û_K]`.
    /// `β = 0` (default) is the paper's mixed method; `β = 1` a primal finite-volume scheme
    /// that never uses the collocated strains `S`.
    pub beta: f64,
    /// Accept a combination outside the stability limits of [`Discretisation::stability_warning`]
    /// (the refusal becomes a warning recorded in `summary.json`).
    pub allow_unstable: bool,
}

impl Default for Discretisation {
    fn default() -> Self {
        Self {
            preset: None,
            method: Method::Mfvm,
            mls: MlsParams::default(),
            quadrature_points: 2,
            load_quadrature_points: 5,
            beta: 0.0,
            allow_unstable: false,
        }
    }
}

/// Largest support factor accepted for the pure mixed method (`β = 0`) with a linear basis.
pub const MIXED_LINEAR_MAX_SUPPORT_FACTOR: f64 = 2.25;
/// Largest support factor accepted for the pure mixed method (`β = 0`) with a quadratic basis.
/// Issue 7 proposed 3; the parameter study (docs/param_study.md) measured `α_s = 3` failing the
/// run-time `M` checks on the paper's beam at h = 1 and 0.125 (84 contact intervals) and its
/// cantilever energy error growing from h = 0.5 to 0.25, while 2.5 was intact everywhere.
pub const MIXED_QUADRATIC_MAX_SUPPORT_FACTOR: f64 = 2.5;
/// Smallest blend `β` that lifts those limits. The gap s₄/s_max above the rigid modes of a
/// free body grows roughly in proportion to `β` (9 × 9 nodes, α_s = 3: 5e-5 at β = 0.001,
/// 3.4e-4 at 0.01, 2.4e-3 at 0.1, 1.9e-2 at 1; tests/validation/free_body.rs), so a tiny `β`
/// is as unstable as `β = 0`; method.md §3.9 measured `β ≥ 0.1` sufficient for α_s 2–4.
pub const MIN_STABILISING_BETA: f64 = 0.1;

impl Discretisation {
    /// Why this combination is outside the measured stability limits of the pure mixed method,
    /// or `None` when it is inside them.
    ///
    /// With `β = 0` the collocated strains are smoothed by supports larger than about
    /// `α_s = 2.25` (linear basis) or `α_s = 2.5` (quadratic basis) so much that checkerboard
    /// displacement modes become nearly free (method.md §2, §3.8: s₄/s_max ≈ 7e-7 at
    /// `α_s = 3` on a 9 × 9 free body) and the contact compliance loses its positive diagonal
    /// (§4.1). A blend `β ≥` [`MIN_STABILISING_BETA`] lifts these limits (§3.9); a smaller
    /// positive `β` is treated like `β = 0`.
    pub fn stability_warning(&self) -> Option<String> {
        if self.beta >= MIN_STABILISING_BETA {
            return None;
        }
        let alpha = self.mls.support_factor;
        let limit = match self.mls.basis {
            Basis::Linear => MIXED_LINEAR_MAX_SUPPORT_FACTOR,
            Basis::Quadratic => MIXED_QUADRATIC_MAX_SUPPORT_FACTOR,
        };
        (alpha > limit).then(|| {
            format!(
                "support_factor = {alpha} with the {} basis and beta = {} ({}) is unstable above {limit}: the collocated strains admit nearly free checkerboard modes and contact answers become meaningless (method.md §3.8); use support_factor <= {limit}, or beta = 0.5 (stabilised MFVM, method.md §3.9; at least {MIN_STABILISING_BETA}), or set allow_unstable = true to proceed anyway",
                self.mls.basis.name(),
                self.beta,
                if self.beta == 0.0 { "the pure mixed method" } else { "too little stabilisation" }
            )
        })
    }
}

/// A validated problem: everything the solver needs, with all ranges checked.
#[derive(Clone, Debug)]
pub struct Problem {
    /// A short name (for outputs).
    pub name: String,
    /// The domain.
    pub domain: Domain,
    /// Nominal node spacing `h`.
    pub node_spacing: f64,
    /// Node layout.
    pub layout: Layout,
    /// Material.
    pub material: Material,
    /// Discretisation parameters.
    pub discretisation: Discretisation,
    /// One condition per domain edge (in edge order).
    pub boundary: Vec<EdgeCondition>,
    /// Body force `b` per unit volume, as a function of position.
    pub body_force: Option<BodyForce>,
    /// Edge whose displacement profile is plotted (default: edge 0).
    pub profile_edge: usize,
    /// Frictionless contact, if any.
    pub contact: Option<ContactSpec>,
    /// The second elastic body of a two-body contact (its own `contact` is `None`).
    pub second_body: Option<Box<Problem>>,
}

/// Body force per unit volume `b(x)`.
#[derive(Clone)]
pub struct BodyForce(pub Arc<dyn Fn(Point) -> [f64; 2] + Send + Sync>);

impl std::fmt::Debug for BodyForce {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BodyForce(..)")
    }
}

impl BodyForce {
    /// A constant body force.
    pub fn constant(b: [f64; 2]) -> Self {
        Self(Arc::new(move |_| b))
    }
    /// `b(p)`.
    pub fn at(&self, p: Point) -> [f64; 2] {
        (self.0)(p)
    }
}

/// A problem file that failed to parse or validate. Messages name the field and the value.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// TOML syntax error, unknown key, missing field or wrong type.
    #[error("cannot parse problem file: {0}")]
    Parse(String),
    /// A value out of its allowed range.
    #[error("invalid value for `{field}`: {value} ({reason})")]
    Invalid {
        /// Dotted path of the field.
        field: String,
        /// The offending value, as written.
        value: String,
        /// What is allowed.
        reason: String,
    },
}

fn invalid(field: &str, value: impl std::fmt::Display, reason: impl Into<String>) -> ProblemError {
    ProblemError::Invalid { field: field.into(), value: value.to_string(), reason: reason.into() }
}

// ---------------------------------------------------------------------------------------------
// Raw file form.

/// The problem file as written (TOML). See `problems/*.toml` for annotated examples.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Name used in outputs.
    #[serde(default)]
    pub name: Option<String>,
    /// Body force `[b_x, b_y]` per unit volume.
    #[serde(default)]
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
    /// Frictionless contact with a rigid straight obstacle.
    #[serde(default)]
    pub contact: Option<ContactFile>,
}

/// `[contact]`: one edge of the body against a rigid straight line (`obstacle_point`,
/// `obstacle_normal`), or, with two `[[body]]` tables, against an edge of the second body
/// (`target_edge`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// The edge that may touch the obstacle.
    pub edge: String,
    /// A point of the rigid obstacle line.
    #[serde(default)]
    pub obstacle_point: Option<[f64; 2]>,
    /// Normal of the obstacle line, pointing into the body (normalised on reading).
    #[serde(default)]
    pub obstacle_normal: Option<[f64; 2]>,
    /// Two bodies: the edge of the second body that `edge` (of the first) touches.
    #[serde(default)]
    pub target_edge: Option<String>,
    /// Absolute gap below which a candidate counts as closed (default 1e-5 · max |g0|).
    #[serde(default)]
    pub gap_tolerance: Option<f64>,
    /// Proceed (with a warning) when the condensed compliance fails its checks.
    #[serde(default)]
    pub allow_indefinite: Option<bool>,
    /// `"compliance"` (default, exact for MLS) or `"stiffness"` (the paper's literal form on
    /// nodal parameters, for comparison).
    #[serde(default)]
    pub condensation: Option<String>,
}

/// One `[[body]]` table of a two-body problem.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// Name (outputs of the second body go to `<out>/<name>/`).
    #[serde(default)]
    pub name: Option<String>,
    /// Body force `[b_x, b_y]` per unit volume.
    #[serde(default)]
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
}

/// `[geometry]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum GeometryFile {
    /// `kind = "rectangle"`, `x = [x0, x1]`, `y = [y0, y1]`; edges `bottom, right, top, left`.
    Rectangle {
        /// `[x0, x1]`.
        x: [f64; 2],
        /// `[y0, y1]`.
        y: [f64; 2],
    },
    /// `kind = "polygon"`: convex, counter-clockwise `vertices` and one name per edge.
    Polygon {
        /// Vertices `[[x, y], …]`.
        vertices: Vec<[f64; 2]>,
        /// Edge names; edge k runs from vertex k to k+1.
        edges: Vec<String>,
    },
    /// `kind = "curves"`: a closed loop of straight segments and circular arcs around the body
    /// (counter-clockwise; the body on the left), from `start` through each curve's `to`,
    /// the last `to` being `start` again. Each curve is one named edge.
    Curves {
        /// Start point of the loop.
        start: [f64; 2],
        /// The curves in order.
        curves: Vec<CurveFile>,
    },
    /// `kind = "disk"`: the full disk; its one edge is named `rim`.
    Disk {
        /// Centre.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
    },
}

/// One curve of a `kind = "curves"` geometry: from the end of the previous curve (or the
/// loop's `start`) to `to`, straight, or along the circle about `center` when it is given.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CurveFile {
    /// Edge name (used by `[[boundary]]`, `[contact]`, `[output]`).
    pub name: String,
    /// End point.
    pub to: [f64; 2],
    /// Centre of a circular arc (absent: a straight segment). `to` must lie on the circle
    /// through the start point; `to` equal to the start point gives the full circle.
    #[serde(default)]
    pub center: Option<[f64; 2]>,
    /// Direction of an arc: `"ccw"` (default; the body inside the circle) or `"cw"` (the
    /// body outside it, as around a hole).
    #[serde(default)]
    pub turn: Option<String>,
}

/// `[nodes]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NodesFile {
    /// Nominal spacing `h` (> 0).
    pub spacing: f64,
    /// `"structured"` (default) or `"jittered"`.
    #[serde(default)]
    pub layout: Option<String>,
    /// Jitter amplitude as a fraction of `h` (jittered only; default 0.25, range (0, 0.4]).
    #[serde(default)]
    pub jitter: Option<f64>,
    /// Seed of the jitter (default 1).
    #[serde(default)]
    pub seed: Option<u64>,
}

/// `[material]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Young's modulus `E` (> 0).
    pub young: f64,
    /// Poisson's ratio `ν`, `0 ≤ ν < 0.5`.
    pub poisson: f64,
    /// `"stress"` or `"strain"`.
    pub plane: String,
}

/// `[discretisation]`, or a preset name alone (`discretisation = "stabilised"`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiscretisationFile {
    /// `"paper"` or `"stabilised"` ([`Preset`]); the other keys override its values.
    #[serde(default)]
    pub preset: Option<String>,
    /// `"mfvm"` (default) or `"fem"` (Q2 finite elements; rectangles with structured nodes).
    #[serde(default)]
    pub method: Option<String>,
    /// `"linear"` (default) or `"quadratic"`.
    #[serde(default)]
    pub basis: Option<String>,
    /// `α_s` (default 2; range [1, 6]).
    #[serde(default)]
    pub support_factor: Option<f64>,
    /// Gauss points per segment for the field traction (default 2; 1–8).
    #[serde(default)]
    pub quadrature_points: Option<usize>,
    /// Gauss points per segment for applied tractions (default 5; 3–8).
    #[serde(default)]
    pub load_quadrature_points: Option<usize>,
    /// Stabilisation blend `β ∈ [0, 1]` (default 0, the paper's mixed method; method.md §3.9).
    #[serde(default)]
    pub beta: Option<f64>,
    /// Turn the refusal of an unstable `support_factor`/`basis`/`beta` combination into a
    /// warning (default false).
    #[serde(default)]
    pub allow_unstable: Option<bool>,
}

/// `[output]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputFile {
    /// Edge whose displacement profile is plotted (default: the first edge).
    #[serde(default)]
    pub profile_edge: Option<String>,
}

/// One `[[boundary]]` entry.
#[derive(Clone, Debug, Deserialize, Serialize)]
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
#[derive(Clone, Debug, Deserialize, Serialize)]
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
    Linear([f64; 2]),
}

// ---------------------------------------------------------------------------------------------
// Validation.

impl ProblemFile {
    /// Parses TOML text.
    ///
    /// # Errors
    /// [`ProblemError::Parse`] with the TOML error (line, column, unknown or missing key).
    pub fn from_toml(text: &str) -> Result<Self, ProblemError> {
        toml::from_str(text).map_err(|e| ProblemError::Parse(e.to_string()))
    }
}

fn check_finite(field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() { Ok(v) } else { Err(invalid(field, v, "must be a finite number")) }
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
        let mut problem = if file.body.is_empty() {
            let missing = |what: &str| {
                invalid(
                    what,
                    "(missing)",
                    "a problem needs [geometry], [nodes] and [material] (or two [[body]] tables)",
                )
            };
            let parts = BodyParts {
                geometry: file.geometry.as_ref().ok_or_else(|| missing("geometry"))?,
                nodes: file.nodes.as_ref().ok_or_else(|| missing("nodes"))?,
                material: file.material.as_ref().ok_or_else(|| missing("material"))?,
                boundary: &file.boundary,
                body_force: file.body_force,
            };
            validate_body(name, parts, discretisation)?
        } else {
            if file.body.len() != 2 {
                return Err(invalid(
                    "body",
                    file.body.len(),
                    "give exactly two [[body]] tables (or one body at the top level)",
                ));
            }
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
            let mut bodies = Vec::new();
            for (k, b) in file.body.iter().enumerate() {
                let parts = BodyParts {
                    geometry: &b.geometry,
                    nodes: &b.nodes,
                    material: &b.material,
                    boundary: &b.boundary,
                    body_force: b.body_force,
                };
                let body_name = b.name.clone().unwrap_or_else(|| format!("body{}", k + 1));
                bodies.push(
                    validate_body(body_name, parts, discretisation)
                        .map_err(|e| prefixed(&format!("body[{k}]."), e))?,
                );
            }
            if bodies[0].name == bodies[1].name {
                return Err(invalid(
                    "body[1].name",
                    &bodies[1].name,
                    "the two bodies need different names (outputs of the second go to <out>/<name>/)",
                ));
            }
            let second = bodies.pop().map(Box::new);
            let mut first = bodies.pop().ok_or_else(|| invalid("body", 0, "missing"))?;
            first.second_body = second;
            first
        };

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
        problem.contact = match &file.contact {
            None => None,
            Some(c) => Some(contact_spec(c, &problem)?),
        };
        if problem.second_body.is_some() && problem.contact.is_none() {
            return Err(invalid(
                "contact",
                "(missing)",
                "two bodies need a [contact] table with `edge` (body 1) and `target_edge` (body 2)",
            ));
        }
        Ok(problem)
    }
}

fn validate_discretisation(file: &DiscretisationFile) -> Result<Discretisation, ProblemError> {
    let d = file;
    let preset = match d.preset.as_deref() {
        None => None,
        Some(name) => match Preset::ALL.iter().find(|(n, _)| *n == name) {
            Some(&(_, p)) => Some(p),
            None => {
                return Err(invalid(
                    "discretisation.preset",
                    name,
                    "expected \"paper\" or \"stabilised\"",
                ));
            }
        },
    };
    let (preset_basis, preset_support, preset_beta, preset_quadrature) =
        preset.unwrap_or(Preset::Paper).values();
    let method = match d.method.as_deref().unwrap_or("mfvm") {
        "mfvm" => Method::Mfvm,
        "fem" => Method::Fem,
        other => {
            return Err(invalid("discretisation.method", other, "expected \"mfvm\" or \"fem\""));
        }
    };
    let basis = match d.basis.as_deref() {
        None => preset_basis,
        Some("linear") => Basis::Linear,
        Some("quadratic") => Basis::Quadratic,
        Some(other) => {
            return Err(invalid(
                "discretisation.basis",
                other,
                "expected \"linear\" or \"quadratic\"",
            ));
        }
    };
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
    let beta = d.beta.unwrap_or(preset_beta);
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
        allow_unstable: d.allow_unstable.unwrap_or(false),
    };
    if let Some(why) = discretisation.stability_warning() {
        if !discretisation.allow_unstable && method == Method::Mfvm {
            return Err(invalid("discretisation.support_factor", support_factor, why));
        }
    }
    Ok(discretisation)
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
            Ok(DiscretisationFile { preset: Some(name.to_owned()), ..Default::default() })
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
            DiscretisationFile::deserialize(serde::de::value::MapAccessDeserializer::new(map))
        }
    }
    deserializer.deserialize_any(TableOrPreset)
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
    let domain = match &file.geometry {
        GeometryFile::Rectangle { x, y } => {
            for (name, v) in [("geometry.x", x), ("geometry.y", y)] {
                check_finite(name, v[0])?;
                check_finite(name, v[1])?;
                if v[1] <= v[0] {
                    return Err(invalid(name, format!("{v:?}"), "needs min < max"));
                }
            }
            Domain::rectangle(*x, *y)
        }
        GeometryFile::Polygon { vertices, edges } => {
            for v in vertices {
                check_finite("geometry.vertices", v[0])?;
                check_finite("geometry.vertices", v[1])?;
            }
            Domain::polygon(vertices.clone(), edges.clone())
        }
        GeometryFile::Curves { start, curves } => {
            check_finite("geometry.start", start[0])?;
            check_finite("geometry.start", start[1])?;
            let mut from = *start;
            let mut list = Vec::with_capacity(curves.len());
            for (i, c) in curves.iter().enumerate() {
                let field = |f: &str| format!("geometry.curves[{i}].{f}");
                check_finite(&field("to"), c.to[0])?;
                check_finite(&field("to"), c.to[1])?;
                let curve = match c.center {
                    None => {
                        if c.turn.is_some() {
                            return Err(invalid(
                                &field("turn"),
                                c.turn.as_deref().unwrap_or_default(),
                                "only used with `center` (arcs)",
                            ));
                        }
                        Curve::Segment { a: from, b: c.to }
                    }
                    Some(center) => {
                        check_finite(&field("center"), center[0])?;
                        check_finite(&field("center"), center[1])?;
                        let ccw = match c.turn.as_deref().unwrap_or("ccw") {
                            "ccw" => true,
                            "cw" => false,
                            other => {
                                return Err(invalid(
                                    &field("turn"),
                                    other,
                                    "expected \"ccw\" or \"cw\"",
                                ));
                            }
                        };
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
            Domain::from_curves(list, curves.iter().map(|c| c.name.clone()).collect())
        }
        GeometryFile::Disk { center, radius } => {
            check_finite("geometry.center", center[0])?;
            check_finite("geometry.center", center[1])?;
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(invalid("geometry.radius", radius, "must be a positive number"));
            }
            let p = [center[0] + radius, center[1]];
            Domain::from_curves(vec![Curve::arc_between(p, p, *center, true)], vec!["rim".into()])
        }
    }
    .map_err(|e| invalid("geometry", "", e.to_string()))?;

    let h = file.nodes.spacing;
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
    let layout = match file.nodes.layout.as_deref().unwrap_or("structured") {
        "structured" => {
            if file.nodes.jitter.is_some() {
                return Err(invalid(
                    "nodes.jitter",
                    file.nodes.jitter.unwrap_or_default(),
                    "only used with layout = \"jittered\"",
                ));
            }
            Layout::Structured
        }
        "jittered" => {
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
        other => {
            return Err(invalid("nodes.layout", other, "expected \"structured\" or \"jittered\""));
        }
    };

    if discretisation.method == Method::Fem {
        if !matches!(file.geometry, GeometryFile::Rectangle { .. }) {
            return Err(invalid(
                "geometry.kind",
                "polygon",
                "discretisation.method = \"fem\" meshes rectangles only (kind = \"rectangle\")",
            ));
        }
        if layout != Layout::Structured {
            return Err(invalid(
                "nodes.layout",
                file.nodes.layout.as_deref().unwrap_or_default(),
                "discretisation.method = \"fem\" needs layout = \"structured\" (the element grid)",
            ));
        }
    }

    let m = &file.material;
    if !(m.young.is_finite() && m.young > 0.0) {
        return Err(invalid("material.young", m.young, "must be a positive number"));
    }
    if !(m.poisson.is_finite() && (0.0..0.5).contains(&m.poisson)) {
        return Err(invalid("material.poisson", m.poisson, "must be in [0, 0.5)"));
    }
    let plane = match m.plane.as_str() {
        "stress" => PlaneState::Stress,
        "strain" => PlaneState::Strain,
        other => {
            return Err(invalid("material.plane", other, "expected \"stress\" or \"strain\""));
        }
    };
    let material = Material { young: m.young, poisson: m.poisson, plane };

    let mut boundary: Vec<Option<EdgeCondition>> = vec![None; domain.edge_count()];
    for (i, b) in file.boundary.iter().enumerate() {
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
                    (Some(v), None) => ComponentCondition::Displacement(value_field(
                        &format!("{field}.displacement.{name}"),
                        v,
                    )?),
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
    let boundary: Vec<EdgeCondition> =
        boundary.into_iter().map(|c| c.unwrap_or_else(EdgeCondition::free)).collect();
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
        material,
        discretisation,
        boundary,
        body_force,
        profile_edge: 0,
        contact: None,
        second_body: None,
    })
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

fn contact_spec(c: &ContactFile, problem: &Problem) -> Result<ContactSpec, ProblemError> {
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
    let condensation = match c.condensation.as_deref().unwrap_or("compliance") {
        "compliance" => Condensation::Compliance,
        "stiffness" => Condensation::Stiffness,
        other => {
            return Err(invalid(
                "contact.condensation",
                other,
                "expected \"compliance\" or \"stiffness\"",
            ));
        }
    };
    if let Some(second) = problem.second_body.as_deref() {
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
        // The edges must face each other: body 1 must lie on the side the target normal points to.
        let nu = second.domain.straight_normal(target).ok_or_else(|| {
            invalid(
                "contact.target_edge",
                name,
                "this edge of the second body is curved; the target must be a straight edge (swap the bodies so the curved edge belongs to the first)",
            )
        })?;
        let (a2, _) = second.domain.edge(target);
        let centroid = domain.centroid();
        if (centroid[0] - a2[0]) * nu[0] + (centroid[1] - a2[1]) * nu[1] <= 0.0 {
            return Err(invalid(
                "contact.target_edge",
                name,
                "the first body is not on the outer side of this edge of the second body: the bodies would overlap",
            ));
        }
        return Ok(ContactSpec {
            edge,
            target: ContactTarget::Body { edge: target },
            gap_tolerance: c.gap_tolerance,
            allow_indefinite,
            condensation,
        });
    }
    if c.target_edge.is_some() {
        return Err(invalid(
            "contact.target_edge",
            "",
            "only for two bodies ([[body]] tables); a rigid obstacle takes obstacle_point and obstacle_normal",
        ));
    }
    let missing = |f: &str| {
        invalid(f, "(missing)", "a rigid obstacle needs obstacle_point and obstacle_normal")
    };
    let obstacle_point = c.obstacle_point.ok_or_else(|| missing("contact.obstacle_point"))?;
    let obstacle_normal = c.obstacle_normal.ok_or_else(|| missing("contact.obstacle_normal"))?;
    for v in obstacle_point.iter().chain(&obstacle_normal) {
        check_finite("contact", *v)?;
    }
    let [nx, ny] = obstacle_normal;
    let len = nx.hypot(ny);
    if len == 0.0 {
        return Err(invalid("contact.obstacle_normal", "[0, 0]", "must be a non-zero vector"));
    }
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
    Ok(ContactSpec {
        edge,
        target: ContactTarget::Rigid(obstacle),
        gap_tolerance: c.gap_tolerance,
        allow_indefinite,
        condensation,
    })
}

impl Problem {
    /// Parses and validates TOML text.
    ///
    /// # Errors
    /// [`ProblemError`] naming the offending field and value.
    pub fn from_toml(text: &str) -> Result<Self, ProblemError> {
        Problem::try_from(ProblemFile::from_toml(text)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BODY: &str = r#"
name = "preset"
[geometry]
kind = "rectangle"
x = [0.0, 4.0]
y = [0.0, 1.0]
[nodes]
spacing = 0.25
[material]
young = 1000.0
poisson = 0.3
plane = "stress"
"#;

    fn discretisation(head: &str, table: &str) -> Discretisation {
        Problem::from_toml(&format!("{head}\n{BODY}\n{table}")).unwrap().discretisation
    }

    #[test]
    fn presets_equal_their_explicit_values() {
        let default = discretisation("", "");
        let paper = discretisation("discretisation = \"paper\"", "");
        assert_eq!(paper.preset, Some(Preset::Paper));
        assert_eq!(Discretisation { preset: None, ..paper }, default);
        let stabilised = discretisation("discretisation = \"stabilised\"", "");
        let explicit = discretisation(
            "",
            "[discretisation]\nbasis = \"linear\"\nsupport_factor = 2.0\nbeta = 1.0\nquadrature_points = 2",
        );
        assert_eq!(stabilised.preset, Some(Preset::Stabilised));
        assert_eq!(Discretisation { preset: None, ..stabilised }, explicit);
        assert_eq!(stabilised.beta, 1.0);
    }

    #[test]
    fn table_keys_override_the_preset() {
        let d = discretisation(
            "",
            "[discretisation]\npreset = \"stabilised\"\nsupport_factor = 3.0\nquadrature_points = 3",
        );
        assert_eq!(d.preset, Some(Preset::Stabilised));
        assert_eq!((d.beta, d.mls.support_factor, d.quadrature_points), (1.0, 3.0, 3));
    }
}
