//! Stage 1: the problem description — a raw TOML form ([`ProblemFile`]) validated into a
//! checked [`Problem`]. Only a `Problem` reaches the solver.
//!
//! - [`mod@file`]: the raw form, as written ([`ProblemFile`]);
//! - `validate` (private): `ProblemFile` → `Problem`, every range checked once;
//! - [`discretisation`]: method, MLS parameters, node layout, presets and stability limits;
//! - [`axisymmetric`]: the axis conditions and refusals of bodies of revolution;
//! - [`contact`]: the contact specification (rigid line or second body);
//! - [`dynamics`]: the checked `[dynamics]` table (time stepping with inertia);
//! - [`gmsh`]: a reader for Gmsh mesh files (MSH 4.1 and 2.2, ASCII);
//! - [`refine`]: the graded spacing of `[[nodes.refine]]`.

pub mod axisymmetric;
pub mod contact;
pub mod discretisation;
pub mod dynamics;
pub mod file;
pub mod gmsh;
pub mod refine;
pub mod scene;
pub mod schema;
mod validate;

pub use contact::{
    Closest, Condensation, ContactSolver, ContactSpec, ContactTarget, Obstacle, Piece, Polyline,
    RigidLine, Shape, closest_obstacle,
};
pub use discretisation::{
    AUTO_BETA, AutoKeyword, Basis, BetaChoice, Discretisation, Layout, MIN_STABILISING_BETA,
    MIXED_LINEAR_MAX_SUPPORT_FACTOR, MIXED_QUADRATIC_MAX_SUPPORT_FACTOR, Method, MlsParams,
    Precision, Preset,
};
pub use file::*;
pub use refine::{Adaptive, Indicator, NestedQuery, RefineBox, Refinement, SpacingIndex};

use crate::geometry::{Domain, Point};
use crate::material::Material;
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

/// Given nodes (the nodes of a mesh): positions and local spacing, the boundary nodes exactly on
/// the domain's boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshNodes {
    /// Node positions.
    pub points: Vec<Point>,
    /// Local spacing `h_I` of each node.
    pub spacing: Vec<f64>,
    /// The mesh's elements on these nodes (`nodes` index `points`): the finite element path
    /// (`method = "fem"`) takes them as its elements.
    pub elements: Vec<gmsh::Element>,
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
    /// Static refinement (`[[nodes.refine]]`; empty: uniform spacing `node_spacing`).
    pub refinement: Refinement,
    /// Adaptive refinement (`[refinement]`; `None`: one solve on the given node set).
    pub adaptive: Option<Adaptive>,
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
    /// Write every load increment's contact table (`[output] steps`).
    pub write_steps: bool,
    /// Write the section swept about the axis (`[output] revolve`; axisymmetric bodies).
    pub revolve: Option<Revolve>,
    /// The units named in axis labels (`[output] units`; `None`: "length", "units of E").
    pub units: Option<Units>,
    /// The other bodies of the scene, in file order (body `k ≥ 1` is `others[k − 1]`); empty
    /// for one body. Each holds no bodies and no pairs of its own.
    pub others: Vec<Problem>,
    /// The contact pairs of the scene, in file order (empty without contact): one `[contact]`
    /// table is one pair of this body (against the second body's edge when there is one),
    /// and `[[contact]]` tables are one pair each. Read them through [`Problem::pairs`].
    pub contact_pairs: Vec<ContactPair>,
    /// The nodes of a Gmsh body read with `nodes.from = "mesh"` (absent: the nodes are
    /// generated from `node_spacing` and `layout`).
    pub mesh_nodes: Option<Arc<MeshNodes>>,
    /// Load steps (`[[step]]`; empty: one step to the `boundary` values, as without steps).
    /// The second body of a two-body contact holds the same steps (the same number and
    /// increments, validated) with its own conditions; its `obstacle_displacement` is zero.
    pub steps: Vec<LoadStep>,
    /// Elastodynamics (`[dynamics]`, docs/method.md §10; `None`: the static solve).
    pub dynamics: Option<dynamics::Dynamics>,
}

/// The bodies and contact pairs of a scene of pairs ([`Problem::multibody`]), borrowed from
/// the problem.
#[derive(Clone, Copy, Debug)]
pub struct Multibody<'a> {
    /// Bodies 2, 3, … in file order (body 1 is the problem itself). Each has no contact.
    pub bodies: &'a [Problem],
    /// The contact pairs, in file order.
    pub pairs: &'a [ContactPair],
}

/// One contact pair of a scene: an edge of one body (carrying the
/// candidates) against an edge of another body or against rigid obstacles.
#[derive(Clone, Debug)]
pub struct ContactPair {
    /// The body carrying the candidates: 0 for the first body (the problem itself), `k` for
    /// `Problem::others[k − 1]`.
    pub body: usize,
    /// The contact edge of `body` and its target: [`ContactTarget::Body`] (an edge of
    /// `target_body`), [`ContactTarget::Obstacles`] (`obstacles`) or [`ContactTarget::Rigid`].
    pub spec: ContactSpec,
    /// The target body (numbered as `body`) for [`ContactTarget::Body`].
    pub target_body: Option<usize>,
    /// The obstacles of [`ContactTarget::Obstacles`] (empty otherwise).
    pub obstacles: Vec<Obstacle>,
}

impl Problem {
    /// Body `k` of the scene: 0 is the problem itself, `k ≥ 1` the `k`-th other body.
    pub fn body(&self, k: usize) -> Option<&Problem> {
        match k {
            0 => Some(self),
            k => self.others.get(k - 1),
        }
    }
    /// Body `k`, mutable (as [`Problem::body`]).
    pub fn body_mut(&mut self, k: usize) -> Option<&mut Problem> {
        match k {
            0 => Some(self),
            k => self.others.get_mut(k - 1),
        }
    }
    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        1 + self.others.len()
    }
}

/// One load step, validated: the state at its end and the increments that reach it linearly
/// from the end of the previous step (the unloaded body before the first; docs/method.md §8).
#[derive(Clone, Debug)]
pub struct LoadStep {
    /// Equal increments (≥ 1).
    pub increments: usize,
    /// With `[dynamics]`: the time at which the step's state holds (the states are
    /// interpolated linearly in time between steps, from the unloaded body at time 0, and
    /// held after the last; docs/method.md §10.5). `None` in a static solve.
    pub time: Option<f64>,
    /// Every edge's condition at the end of the step (same kinds as `Problem::boundary`).
    pub boundary: Vec<EdgeCondition>,
    /// Total displacement of the rigid obstacle at the end of the step (zero with
    /// `obstacle_force`).
    pub obstacle_displacement: Point,
    /// The force pressing the rigid obstacle onto the body at the end of the step
    /// (`[[step]] obstacle_force`; docs/method.md §4.6): the obstacle's displacement along it
    /// is then an unknown, found by the contact's equilibrium.
    pub obstacle_force: Option<Point>,
    /// The Coulomb coefficient `μ ≥ 0` during the step (`[[step]] friction`, default the
    /// contact's).
    pub friction: f64,
    /// Whether the step sets `friction` itself; with several contact pairs a step that does
    /// not keeps each pair's own coefficient.
    pub friction_set: bool,
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
    let mut value = value.to_string();
    // A number whose plain form is long (1e300 prints 301 digits) is shown as `1e300`.
    if value.len() > 16 {
        if let Ok(v) = value.parse::<f64>() {
            value = format!("{v:e}");
        }
    }
    ProblemError::Invalid { field: field.into(), value, reason: reason.into() }
}

/// `[output] revolve` and `revolve_segments`: the angle an axisymmetric body's section is
/// swept about the axis for `solution_revolved.vtu`, and the segments (wedges) over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Revolve {
    /// Swept angle `Θ` in degrees, in `(0, 360]`.
    pub angle_degrees: f64,
    /// Segments `n` over `Θ` (each `Θ / n`), at least 1.
    pub segments: usize,
}

/// `[output] units = "N, mm, MPa"`: the names of the force, length and stress units of the
/// problem's numbers, used in the plots' axis labels only (nothing is converted).
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// Force unit.
    pub force: String,
    /// Length unit.
    pub length: String,
    /// Stress unit.
    pub stress: String,
}

impl Revolve {
    /// Default segment width in degrees: `revolve_segments` defaults to `⌈Θ / 5°⌉`.
    pub const SEGMENT_DEGREES: f64 = 5.0;
    /// Most segments accepted.
    pub const MAX_SEGMENTS: usize = 3600;

    /// Whether the sweep is a full turn (the last copy of the section is the first).
    pub fn full_turn(&self) -> bool {
        self.angle_degrees == 360.0
    }
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

    /// Every shipped problem file read from JSON (the TOML converted key for key) gives the
    /// same raw form as read from TOML, and a wrong key is named by its path in JSON too.
    #[test]
    fn json_reads_like_toml() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
        let mut paths: Vec<_> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        paths.sort();
        for path in paths.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
            let text = std::fs::read_to_string(path).unwrap();
            let value: toml::Value = toml::from_str(&text).unwrap();
            let json = serde_json::to_string(&value).unwrap();
            let from_toml = serde_json::to_value(ProblemFile::from_toml(&text).unwrap()).unwrap();
            let from_json = serde_json::to_value(ProblemFile::from_json(&json).unwrap()).unwrap();
            assert_eq!(from_toml, from_json, "{}", path.display());
        }
        let e = ProblemFile::from_json(
            r#"{"name": "x", "geometry": {"kind": "rectangle", "x": "abc"}}"#,
        )
        .unwrap_err();
        assert!(e.to_string().contains("at `geometry.x`"), "{e}");
    }

    #[test]
    fn a_modulus_that_underflows_is_refused_with_the_reason() {
        for young in ["5e-324", "1e-150"] {
            let text = BODY.replace("young = 1000.0", &format!("young = {young}"));
            let e = Problem::from_toml(&text).unwrap_err().to_string();
            assert!(e.contains("material.young") && e.contains("underflow"), "{young}: {e}");
        }
        let text = BODY.replace("young = 1000.0", "young = 1e-90");
        if let Err(e) = Problem::from_toml(&text) {
            let e = e.to_string();
            assert!(!e.contains("material.young"), "a small representable modulus passes: {e}");
        }
    }

    #[test]
    fn long_numbers_in_messages_are_shown_in_scientific_form() {
        let e = invalid("nodes.refine[0].spacing", 1e50, "too large").to_string();
        assert!(e.contains(": 1e50 (too large)"), "{e}");
        let e = invalid("x", 0.25, "r").to_string();
        assert!(e.contains(": 0.25 (r)"), "{e}");
        let e = invalid("name", "a-very-long-name-that-is-no-number", "r").to_string();
        assert!(e.contains("a-very-long-name-that-is-no-number"), "{e}");
    }

    fn discretisation(head: &str, table: &str) -> Discretisation {
        Problem::from_toml(&format!("{head}\n{BODY}\n{table}")).unwrap().discretisation
    }

    #[test]
    fn presets_equal_their_explicit_values() {
        let default = discretisation("", "");
        let paper = discretisation("discretisation = \"paper\"", "");
        assert_eq!(paper.preset, Some(Preset::Paper));
        // The same numbers; without a preset β is "auto" (β = 0 first), with "paper" it is 0.
        assert_eq!(Discretisation { preset: None, beta_auto: true, ..paper }, default);
        assert!(!paper.beta_auto && paper.beta == 0.0);
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

    #[test]
    fn centre_and_center_are_both_accepted() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("problems/cylinder_indenter.toml");
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.contains("\ncentre = "));
        let british = Problem::from_toml(&text).unwrap();
        let american = Problem::from_toml(&text.replace("\ncentre = ", "\ncenter = ")).unwrap();
        assert_eq!(format!("{:?}", british.obstacles()), format!("{:?}", american.obstacles()));
        let disk = |key: &str| {
            format!(
                "[geometry]\nkind = \"disk\"\n{key} = [0.0, 0.0]\nradius = 1.0\n[nodes]\nspacing = 0.25\n[material]\nyoung = 1.0\npoisson = 0.3\nplane = \"strain\"\n[[boundary]]\nedge = \"rim\"\ndisplacement = {{ x = 0.0, y = 0.0 }}\n"
            )
        };
        let (a, b) = (Problem::from_toml(&disk("center")), Problem::from_toml(&disk("centre")));
        assert_eq!(format!("{:?}", a.unwrap().domain), format!("{:?}", b.unwrap().domain));
    }

    #[test]
    fn accuracy_goals_are_validated_with_key_paths() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("problems/beam_on_foundation_adaptive.toml");
        let beam = std::fs::read_to_string(path).unwrap();
        let with = |keys: &str| {
            Problem::from_toml(&beam.replace("[refinement]\n", &format!("[refinement]\n{keys}\n")))
        };
        let a = with("onset_tolerance = 0.01\nforce_tolerance = 1e-4").unwrap().adaptive.unwrap();
        assert_eq!((a.onset_tolerance, a.force_tolerance), (Some(0.01), Some(1e-4)));
        let a = with("").unwrap().adaptive.unwrap();
        assert_eq!((a.onset_tolerance, a.force_tolerance), (None, None));
        for (keys, key) in [
            ("onset_tolerance = 0.0", "refinement.onset_tolerance"),
            ("onset_tolerance = -0.01", "refinement.onset_tolerance"),
            ("force_tolerance = 0.0", "refinement.force_tolerance"),
            ("force_tolerance = 1.0", "refinement.force_tolerance"),
        ] {
            let e = with(keys).unwrap_err().to_string();
            assert!(e.contains(key), "{keys}: {e}");
        }
        // Without a contact there is no onset or contact force to aim at.
        for key in ["onset_tolerance", "force_tolerance"] {
            let text = format!("{BODY}\n[refinement]\n{key} = 0.01");
            let e = Problem::from_toml(&text).unwrap_err().to_string();
            assert!(e.contains(&format!("refinement.{key}")) && e.contains("[contact]"), "{e}");
        }
    }

    #[test]
    fn adaptive_table_is_validated_with_key_paths() {
        let with = |table: &str| Problem::from_toml(&format!("{BODY}\n[refinement]\n{table}"));
        let a = with("").unwrap().adaptive.unwrap();
        assert_eq!(
            (a.steps, a.max_nodes, a.tolerance),
            (Adaptive::STEPS, Adaptive::MAX_NODES, None)
        );
        assert_eq!(
            (a.fraction, a.indicator, a.contact),
            (Adaptive::FRACTION, Indicator::Gradient, true)
        );
        let a = with("steps = 3\nmax_nodes = 5000\ntolerance = 0.01\nfraction = 0.4\nindicator = \"recovery\"\ncontact = false")
            .unwrap()
            .adaptive
            .unwrap();
        assert_eq!((a.steps, a.max_nodes, a.tolerance), (3, 5000, Some(0.01)));
        assert_eq!((a.fraction, a.indicator, a.contact), (0.4, Indicator::Recovery, false));
        assert!(Problem::from_toml(BODY).unwrap().adaptive.is_none());
        for (table, key) in [
            ("steps = 0", "refinement.steps"),
            ("steps = 31", "refinement.steps"),
            ("max_nodes = 2", "refinement.max_nodes"),
            ("tolerance = 0.0", "refinement.tolerance"),
            ("tolerance = 1.5", "refinement.tolerance"),
            ("fraction = 0.0", "refinement.fraction"),
            ("fraction = 1.1", "refinement.fraction"),
            ("indicator = \"residual\"", "refinement.indicator"),
            ("size = 2", "size"),
        ] {
            let e = with(table).unwrap_err().to_string();
            assert!(e.contains(key), "{table}: {e}");
        }
        // The FE's rectangle is refined too (a graded tensor-product grid).
        let fem = Problem::from_toml(&format!(
            "{BODY}\n[discretisation]\nmethod = \"fem\"\n[refinement]\nsteps = 2"
        ))
        .unwrap();
        assert_eq!(fem.adaptive.map(|a| a.steps), Some(2));
        // Polygons (and curves) are refined; domains with holes are refused.
        let polygon = BODY.replace(
            "kind = \"rectangle\"\nx = [0.0, 4.0]\ny = [0.0, 1.0]",
            "kind = \"polygon\"\nvertices = [[0.0, 0.0], [4.0, 0.0], [0.0, 1.0]]\nedges = [\"a\", \"b\", \"c\"]",
        );
        assert!(Problem::from_toml(&(polygon + "\n[refinement]\n")).unwrap().adaptive.is_some());
        let holed = Problem::from_toml(&(BODY.replace(
            "y = [0.0, 1.0]",
            "y = [0.0, 1.0]\nholes = [{ kind = \"disk\", center = [2.0, 0.5], radius = 0.2, name = \"hole\" }]",
        ) + "\n[refinement]\n"))
        .unwrap_err()
        .to_string();
        assert!(holed.contains("`refinement`") && holed.contains("without holes"), "{holed}");
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/two_blocks.toml");
        let two = std::fs::read_to_string(path).unwrap();
        let p = Problem::from_toml(&format!("{two}\n[refinement]\n")).unwrap();
        assert!(p.adaptive.is_some() && p.second_body().is_some());
        // A curved first body on a block (the Cattaneo–Mindlin pair) is accepted; a second
        // body with a hole is refused, naming it.
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cattaneo_mindlin.toml");
        let cm = std::fs::read_to_string(path).unwrap();
        let p = Problem::from_toml(&format!("{cm}\n[refinement]\n")).unwrap();
        assert!(p.adaptive.is_some() && p.second_body().is_some());
        let block = "geometry = { kind = \"rectangle\", x = [-0.6, 0.6], y = [-0.4, 0.0] }";
        assert!(cm.contains(block));
        let holed = cm.replace(
            block,
            "geometry = { kind = \"rectangle\", x = [-0.6, 0.6], y = [-0.4, 0.0], holes = [{ kind = \"disk\", center = [0.0, -0.2], radius = 0.05, name = \"hole\" }] }",
        );
        let e = Problem::from_toml(&format!("{holed}\n[refinement]\n")).unwrap_err().to_string();
        assert!(e.contains("`refinement`") && e.contains("body[1]"), "{e}");
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("problems/three_block_stack.toml");
        let three = std::fs::read_to_string(path).unwrap();
        // Three bodies in two pairs are accepted; one of them with a hole is refused, naming it.
        let p = Problem::from_toml(&format!("{three}\n[refinement]\n")).unwrap();
        assert!(p.adaptive.is_some() && p.multibody().is_some());
        let top = "geometry = { kind = \"rectangle\", x = [0.0, 2.0], y = [2.0, 3.0] }";
        assert!(three.contains(top));
        let holed = three.replace(
            top,
            "geometry = { kind = \"rectangle\", x = [0.0, 2.0], y = [2.0, 3.0], holes = [{ kind = \"disk\", center = [1.0, 2.5], radius = 0.1, name = \"hole\" }] }",
        );
        let e = Problem::from_toml(&format!("{holed}\n[refinement]\n")).unwrap_err().to_string();
        assert!(e.contains("`refinement`") && e.contains("body[2]"), "{e}");
    }

    #[test]
    fn refinement_tables_become_boxes_and_bad_ones_name_their_key() {
        let with = |tables: &str| {
            Problem::from_toml(&format!(
                "{BODY}
{tables}"
            ))
        };
        let p = with(
            "[[nodes.refine]]\nedge = \"bottom\"\nspacing = 0.125\nwidth = 0.5\n             [[nodes.refine]]\nx = [1.0, 2.0]\ny = [0.25, 0.5]\nspacing = 0.0625",
        )
        .unwrap();
        assert_eq!(
            p.refinement.boxes,
            vec![
                RefineBox { x: [0.0, 4.0], y: [0.0, 0.5], spacing: 0.125 },
                RefineBox { x: [1.0, 2.0], y: [0.25, 0.5], spacing: 0.0625 },
            ]
        );
        assert!(with("").unwrap().refinement.is_empty());
        // A box far larger than the body is clipped to the body's bounding box widened by two
        // nominal spacings (0.5): the spacing over the body is the same, the index small.
        let huge =
            with("[[nodes.refine]]\nx = [0.0, 1e9]\ny = [-1e50, 0.5]\nspacing = 0.125").unwrap();
        assert_eq!(
            huge.refinement.boxes,
            vec![RefineBox { x: [0.0, 4.5], y: [-0.5, 0.5], spacing: 0.125 }]
        );
        // A band along a curved edge: squares of half-side `width` along it.
        let quarter = Problem::from_toml(&(BODY.replace(
            "kind = \"rectangle\"\nx = [0.0, 4.0]\ny = [0.0, 1.0]",
            "kind = \"curves\"\nstart = [1.0, 0.0]\ncurves = [{ name = \"arc\", to = [0.0, 1.0], center = [0.0, 0.0] }, { name = \"left\", to = [0.0, 0.0] }, { name = \"bottom\", to = [1.0, 0.0] }]",
        ) + "\n[[nodes.refine]]\nedge = \"arc\"\nspacing = 0.05\nwidth = 0.1"))
        .unwrap();
        let boxes = &quarter.refinement.boxes;
        assert_eq!(boxes.len(), 17, "{boxes:?}");
        assert_eq!(boxes[0], RefineBox { x: [0.9, 1.1], y: [-0.1, 0.1], spacing: 0.05 });
        for (tables, key) in [
            (
                "[[nodes.refine]]\nedge = \"bottom\"\nspacing = 0.5\nwidth = 0.5",
                "nodes.refine[0].spacing",
            ),
            (
                "[[nodes.refine]]\nedge = \"base\"\nspacing = 0.1\nwidth = 0.5",
                "nodes.refine[0].edge",
            ),
            (
                "[[nodes.refine]]\nedge = \"left\"\nspacing = 0.1\nwidth = 5.0",
                "nodes.refine[0].width",
            ),
            ("[[nodes.refine]]\nedge = \"left\"\nspacing = 0.1\nx = [0.0, 1.0]", "nodes.refine[0]"),
            (
                "[[nodes.refine]]\nx = [1.0, 0.0]\ny = [0.0, 1.0]\nspacing = 0.1",
                "nodes.refine[0].x",
            ),
            (
                "[[nodes.refine]]\nx = [5.0, 6.0]\ny = [0.0, 1.0]\nspacing = 0.1",
                "nodes.refine[0].x",
            ),
            (
                "[[nodes.refine]]\nx = [0.0, 1.0]\ny = [0.0, 1.0]\nspacing = 1e-9",
                "nodes.refine[0].spacing",
            ),
            ("[[nodes.refine]]\nx = [0.0, 1.0]\ny = [0.0, 1.0]\nspacing = 0.1\nsize = 2", "size"),
        ] {
            let e = with(tables).unwrap_err().to_string();
            assert!(e.contains(key), "{tables}: {e}");
        }
    }
}
