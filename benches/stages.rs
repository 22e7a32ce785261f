//! Per-stage benchmarks of the discretisation pipeline, swept over node counts.
//!
//! The problem is the cantilever of `problems/cantilever.toml` (48 × 12, plane stress, linear
//! basis, `α_s = 2`, 2-point face quadrature) on structured grids of `4 ny × ny` intervals:
//! `ny = 25, 50, 100` give 2 626, 10 251 and 40 501 nodes. Override with a comma-separated list
//! of `ny` in `MLPG_BENCH_NY` (e.g. `MLPG_BENCH_NY=25,50`; `ny = 250` gives 251 001 nodes).
//! `MLPG_BENCH_BETA` sets `discretisation.beta` (default 0, the paper's method; 1 for the
//! sparser stabilised operator).
//!
//! The sparse LU costs ~25 s at 40 k nodes, and criterion needs at least 11 runs per size,
//! so the `factorisation` group has its own, smaller sweep: `ny = 25, 50, 70` (2 626, 10 251
//! and 19 951 nodes), overridden by `MLPG_BENCH_FACTOR_NY`.
//!
//! One benchmark group per stage, each measured on inputs prepared once per size:
//!
//! | group | measured call |
//! |---|---|
//! | `neighbours` | `Supports::new` + `Supports::support_of` at every node |
//! | `cells` | `weak_form::build_cells` |
//! | `mls` | `mls::shape_functions` at the nodes, with gradients |
//! | `assembly` | `assembly::assemble` |
//! | `factorisation` | `linear_solve::Factorisation::with_node_coordinates` (nested dissection, symbolic + numeric LU) |
//! | `solve` | `Factorisation::solve` (one right-hand side) |
//!
//! Samples are few and short (`sample_size(10)`, 1 s warm-up, 3 s measurement) so the whole
//! run takes a few minutes; criterion switches to flat sampling for the slow cases. Plots are
//! off (they need system fonts).
//!
//! ```text
//! cargo bench --bench stages [-- <group filter>]
//! ```

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use mlpg_contact::assembly::{self, AssemblyInput, GlobalSystem, SystemMatrix};
use mlpg_contact::geometry::Point;
use mlpg_contact::linear_solve::Factorisation;
use mlpg_contact::mls::{self, ShapeSet};
use mlpg_contact::neighbours::Supports;
use mlpg_contact::nodes::{self, Nodes};
use mlpg_contact::problem::Problem;
use mlpg_contact::weak_form::{self, Cell, FaceQuadrature, Faces};

/// Default grid heights (intervals across the 12-unit height).
const DEFAULT_NY: [usize; 3] = [25, 50, 100];

/// Default grid heights of the `factorisation` group.
const DEFAULT_FACTOR_NY: [usize; 3] = [25, 50, 70];

/// The cantilever of `problems/cantilever.toml` with `ny` intervals across its height and
/// `beta` from `MLPG_BENCH_BETA`.
fn cantilever(ny: usize) -> Problem {
    let spacing = 12.0 / ny as f64;
    let beta: f64 =
        std::env::var("MLPG_BENCH_BETA").ok().and_then(|v| v.parse().ok()).unwrap_or(0.0);
    let text = format!(
        r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, 48.0]
        y = [-6.0, 6.0]
        [nodes]
        spacing = {spacing:?}
        [material]
        young = 3.0e7
        poisson = 0.3
        plane = "stress"
        [discretisation]
        basis = "linear"
        support_factor = 2.0
        quadrature_points = 2
        beta = {beta:?}
        [[boundary]]
        edge = "left"
        displacement = {{ x = 0.0, y = 0.0 }}
        [[boundary]]
        edge = "right"
        traction = {{ y = 83.333333333333 }}
        "#
    );
    Problem::from_toml(&text).expect("benchmark cantilever is valid")
}

/// The outputs of the stages before assembly, for one size.
struct Inputs {
    problem: Problem,
    nodes: Nodes,
    supports: Supports,
    cells: Vec<Cell>,
    faces: Faces,
    face_quadrature: FaceQuadrature,
    face_shapes: ShapeSet,
    node_shapes: ShapeSet,
}

impl Inputs {
    fn new(ny: usize) -> Self {
        let problem = cantilever(ny);
        let disc = &problem.discretisation;
        let nodes =
            nodes::generate(&problem.domain, problem.node_spacing, problem.layout).expect("nodes");
        let supports = Supports::new(&nodes, disc.mls.support_factor);
        let cells = weak_form::build_cells(&problem.domain, &nodes).expect("cells");
        let faces = weak_form::collect_faces(&cells);
        let face_quadrature = FaceQuadrature::new(&faces.interior, disc.quadrature_points);
        let node_shapes = mls::shape_functions(&nodes.points, &nodes, &supports, &disc.mls, true)
            .expect("node shapes");
        let face_shapes = mls::shape_functions(
            &face_quadrature.points,
            &nodes,
            &supports,
            &disc.mls,
            assembly::needs_face_gradients(disc.beta),
        )
        .expect("face shapes");
        Self { problem, nodes, supports, cells, faces, face_quadrature, face_shapes, node_shapes }
    }

    fn assemble(&self) -> GlobalSystem {
        let d = self.problem.material.constitutive();
        assembly::assemble(&AssemblyInput {
            body: assembly::Body::new(&self.problem, &self.nodes, &d),
            cells: &self.cells,
            interior_faces: &self.faces.interior,
            boundary_faces: &self.faces.boundary,
            face_quadrature: &self.face_quadrature,
            face_shapes: &self.face_shapes,
            node_shapes: &self.node_shapes,
            axisymmetric: None,
            beta: self.problem.discretisation.beta,
        })
        .expect("assembly")
    }
}

/// Every stage's output for one size, so each benchmark can run its stage alone.
struct Fixture {
    ny: usize,
    inputs: Inputs,
    system: GlobalSystem,
    factorisation: Factorisation,
}

impl Fixture {
    fn new(ny: usize) -> Self {
        let inputs = Inputs::new(ny);
        let system = inputs.assemble();
        let factorisation =
            Factorisation::with_node_coordinates(&system.matrix, &inputs.nodes.points).expect("LU");
        Self { ny, inputs, system, factorisation }
    }

    fn id(&self) -> BenchmarkId {
        BenchmarkId::from_parameter(self.inputs.nodes.len())
    }

    fn elements(&self) -> Throughput {
        Throughput::Elements(self.inputs.nodes.len() as u64)
    }
}

/// Grid heights from the environment variable `var`, else `default`.
fn sizes(var: &str, default: &[usize]) -> Vec<usize> {
    match std::env::var(var) {
        Ok(list) => list.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => default.to_vec(),
    }
}

fn stages(c: &mut Criterion) {
    let fixtures: Vec<Fixture> =
        sizes("MLPG_BENCH_NY", &DEFAULT_NY).into_iter().map(Fixture::new).collect();
    // (node positions, K) for the factorisation sweep, reusing the fixtures' matrices where
    // possible.
    let factor_inputs: Vec<(Vec<Point>, SystemMatrix)> =
        sizes("MLPG_BENCH_FACTOR_NY", &DEFAULT_FACTOR_NY)
            .into_iter()
            .map(|ny| match fixtures.iter().find(|f| f.ny == ny) {
                Some(f) => (f.inputs.nodes.points.clone(), f.system.matrix.clone()),
                None => {
                    let inputs = Inputs::new(ny);
                    let matrix = inputs.assemble().matrix;
                    (inputs.nodes.points, matrix)
                }
            })
            .collect();

    let mut group = c.benchmark_group("neighbours");
    for f in &fixtures {
        group.throughput(f.elements());
        group.bench_with_input(f.id(), f, |b, f| {
            let alpha = f.inputs.problem.discretisation.mls.support_factor;
            let mut support = Vec::new();
            b.iter(|| {
                let supports = Supports::new(black_box(&f.inputs.nodes), alpha);
                let mut total = 0usize;
                for &p in &f.inputs.nodes.points {
                    supports.support_of(&f.inputs.nodes.points, p, &mut support);
                    total += support.len();
                }
                black_box((supports, total))
            });
        });
    }
    group.finish();

    let mut group = c.benchmark_group("cells");
    for f in &fixtures {
        group.throughput(f.elements());
        group.bench_with_input(f.id(), f, |b, f| {
            b.iter(|| {
                weak_form::build_cells(
                    black_box(&f.inputs.problem.domain),
                    black_box(&f.inputs.nodes),
                )
            });
        });
    }
    group.finish();

    let mut group = c.benchmark_group("mls");
    for f in &fixtures {
        group.throughput(f.elements());
        group.bench_with_input(f.id(), f, |b, f| {
            let params = &f.inputs.problem.discretisation.mls;
            b.iter(|| {
                mls::shape_functions(
                    black_box(&f.inputs.nodes.points),
                    &f.inputs.nodes,
                    &f.inputs.supports,
                    params,
                    true,
                )
            });
        });
    }
    group.finish();

    let mut group = c.benchmark_group("assembly");
    for f in &fixtures {
        group.throughput(f.elements());
        group.bench_with_input(f.id(), f, |b, f| b.iter(|| black_box(f.inputs.assemble())));
    }
    group.finish();

    let mut group = c.benchmark_group("factorisation");
    for (points, matrix) in &factor_inputs {
        group.throughput(Throughput::Elements(points.len() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(points.len()), matrix, |b, matrix| {
            b.iter(|| Factorisation::with_node_coordinates(black_box(matrix), points));
        });
    }
    group.finish();

    let mut group = c.benchmark_group("solve");
    for f in &fixtures {
        group.throughput(f.elements());
        group.bench_with_input(f.id(), f, |b, f| {
            b.iter(|| f.factorisation.solve(black_box(&f.system.rhs)));
        });
    }
    group.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        // Plotting needs system fonts, which headless machines may lack; numbers suffice.
        .without_plots()
}

criterion_group! {
    name = benches;
    config = config();
    targets = stages
}
criterion_main!(benches);
