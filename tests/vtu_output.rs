//! `solution.vtu` read back as text: shared points (no two within `1e-9 h`), valid
//! connectivity, polygons of at least three distinct points, one point-data tuple per point,
//! the MLS field at the points exact on a patch test, and the same bytes on one thread and on
//! many.

use mlpg_contact::geometry::{Domain, Point};
use mlpg_contact::material::{Material, PlaneState};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, Discretisation, EdgeCondition, Field, Problem};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A data array of the file: its section (`Points`, `Cells`, `PointData`, `CellData`), name,
/// number of components and values.
#[derive(Debug)]
struct DataArray {
    section: String,
    name: String,
    components: usize,
    values: Vec<f64>,
}

fn attribute(line: &str, key: &str) -> Option<String> {
    let start = line.find(&format!("{key}=\""))? + key.len() + 2;
    let end = start + line[start..].find('"')?;
    Some(line[start..end].to_string())
}

/// Parses the ASCII VTU text written by the program.
fn parse(text: &str) -> (usize, usize, Vec<DataArray>) {
    let (mut n_points, mut n_cells) = (0, 0);
    let mut section = String::new();
    let mut arrays: Vec<DataArray> = Vec::new();
    let mut open: Option<DataArray> = None;
    for line in text.lines().map(str::trim) {
        if line.starts_with("<Piece") {
            n_points = attribute(line, "NumberOfPoints").unwrap().parse().unwrap();
            n_cells = attribute(line, "NumberOfCells").unwrap().parse().unwrap();
        } else if let Some(a) = open.as_mut() {
            if line == "</DataArray>" {
                arrays.push(open.take().unwrap());
            } else {
                a.values.extend(line.split_whitespace().map(|t| t.parse::<f64>().unwrap()));
            }
        } else if line.starts_with("<DataArray") {
            open = Some(DataArray {
                section: section.clone(),
                name: attribute(line, "Name").unwrap_or_default(),
                components: attribute(line, "NumberOfComponents").map_or(1, |c| c.parse().unwrap()),
                values: Vec::new(),
            });
        } else if let Some(tag) = ["Points", "Cells", "PointData", "CellData"]
            .iter()
            .find(|t| line.starts_with(&format!("<{t}")))
        {
            section = tag.to_string();
        }
    }
    assert!(open.is_none(), "unterminated DataArray");
    (n_points, n_cells, arrays)
}

/// The parsed file: points, polygons and the arrays by `section/name`.
struct Vtu {
    points: Vec<Point>,
    polygons: Vec<Vec<usize>>,
    arrays: HashMap<String, DataArray>,
}

/// Reads `path` and checks the structure; `h` is the smallest node spacing.
fn read_and_check(path: &Path, h: f64) -> Vtu {
    let text = std::fs::read_to_string(path).unwrap();
    let (n_points, n_cells, list) = parse(&text);
    let arrays: HashMap<String, DataArray> =
        list.into_iter().map(|a| (format!("{}/{}", a.section, a.name), a)).collect();
    let pts = &arrays["Points/"];
    assert_eq!(pts.components, 3);
    assert_eq!(pts.values.len(), 3 * n_points);
    let points: Vec<Point> = pts.values.chunks(3).map(|c| [c[0], c[1]]).collect();
    // Unique points: no two within 1e-9 h (sorted by x, then a sweep).
    let tol = 1e-9 * h;
    let mut order: Vec<usize> = (0..n_points).collect();
    order.sort_by(|&a, &b| points[a][0].total_cmp(&points[b][0]));
    let mut closest = f64::INFINITY;
    for (i, &a) in order.iter().enumerate() {
        for &b in &order[i + 1..] {
            if points[b][0] - points[a][0] > tol {
                break;
            }
            let d = (points[a][0] - points[b][0]).hypot(points[a][1] - points[b][1]);
            closest = closest.min(d);
            assert!(d >= tol, "points {a} and {b} are {d:e} apart (h = {h})");
        }
    }
    let connectivity: Vec<usize> =
        arrays["Cells/connectivity"].values.iter().map(|&v| v as usize).collect();
    let offsets: Vec<usize> = arrays["Cells/offsets"].values.iter().map(|&v| v as usize).collect();
    assert_eq!(offsets.len(), n_cells);
    assert_eq!(*offsets.last().unwrap(), connectivity.len());
    assert!(connectivity.iter().all(|&k| k < n_points), "connectivity index out of range");
    let mut polygons = Vec::new();
    let mut start = 0;
    for &end in &offsets {
        let polygon = connectivity[start..end].to_vec();
        let mut distinct = polygon.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert!(
            distinct.len() >= 3,
            "polygon {} has {} distinct points",
            polygons.len(),
            distinct.len()
        );
        polygons.push(polygon);
        start = end;
    }
    for a in arrays.values().filter(|a| a.section == "PointData") {
        assert_eq!(a.values.len(), a.components * n_points, "PointData/{}", a.name);
    }
    for a in arrays.values().filter(|a| a.section == "CellData") {
        assert_eq!(a.values.len(), a.components * n_cells, "CellData/{}", a.name);
    }
    for name in ["displacement", "stress_xx_yy_xy", "von_mises"] {
        assert!(arrays.contains_key(&format!("PointData/{name}")), "PointData/{name} missing");
    }
    println!(
        "{}: {n_points} points, {n_cells} cells, closest points {closest:.3e} = {:.3e} h",
        path.display(),
        closest / h
    );
    Vtu { points, polygons, arrays }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mlpg-vtu-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn run(problem: &Problem, out: &Path) {
    mlpg_contact::run(problem, out, serde_json::Value::Null, &mut mlpg_contact::Silent).unwrap();
}

fn exact(p: Point) -> [f64; 2] {
    [1e-3 * (1.0 + 2.0 * p[0] - 3.0 * p[1]), 1e-3 * (-0.5 + 1.5 * p[0] + 0.7 * p[1])]
}

fn patch_problem(layout: Layout) -> Problem {
    let domain = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap();
    let condition = EdgeCondition::Components([
        ComponentCondition::Displacement(Field::Function(Arc::new(|p| exact(p)[0]))),
        ComponentCondition::Displacement(Field::Function(Arc::new(|p| exact(p)[1]))),
    ]);
    Problem {
        name: "patch".into(),
        domain,
        node_spacing: 0.2,
        layout,
        refinement: Default::default(),
        adaptive: None,
        material: Material { young: 1000.0, poisson: 0.3, plane: PlaneState::Stress },
        discretisation: Discretisation::default(),
        boundary: vec![condition; 4],
        body_force: None,
        profile_edge: 0,
        write_steps: false,
        contact: None,
        obstacles: Vec::new(),
        second_body: None,
        multibody: None,
        mesh_nodes: None,
        steps: Vec::new(),
    }
}

fn patch_test(name: &str, layout: Layout) {
    let problem = patch_problem(layout);
    let out = scratch(name);
    run(&problem, &out);
    let vtu = read_and_check(&out.join("solution.vtu"), 0.2);
    let u = &vtu.arrays["PointData/displacement"].values;
    let scale = 6e-3;
    let err = vtu
        .points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let e = exact(*p);
            (u[3 * k] - e[0]).abs().max((u[3 * k + 1] - e[1]).abs())
        })
        .fold(0.0, f64::max);
    // Constant strain: the interpolated stress is D ε everywhere.
    let d = problem.material.constitutive();
    let sigma = mlpg_contact::material::apply(&d, [2e-3, 0.7e-3, -3e-3 + 1.5e-3]);
    let s = &vtu.arrays["PointData/stress_xx_yy_xy"].values;
    let stress_err = s
        .chunks(3)
        .map(|t| (0..3).map(|c| (t[c] - sigma[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let stress_scale = sigma.iter().map(|v| v.abs()).fold(0.0, f64::max);
    println!(
        "{name}: max |u^h − u| at {} points = {err:.3e} ({:.3e} relative); max |σ − Dε| = {stress_err:.3e} ({:.3e} relative); {} polygons",
        vtu.points.len(),
        err / scale,
        stress_err / stress_scale,
        vtu.polygons.len()
    );
    assert!(err < 1e-10 * scale, "{name}: point displacement error {err:e}");
    assert!(stress_err < 1e-8 * stress_scale, "{name}: point stress error {stress_err:e}");
    // The node's own values stay as cell data, one per node.
    assert!(vtu.arrays.contains_key("CellData/node"));
    assert!(vtu.arrays.contains_key("CellData/node_displacement"));

    // Same bytes on one thread.
    let one = scratch(&format!("{name}-1"));
    rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| run(&problem, &one));
    assert_eq!(
        std::fs::read(out.join("solution.vtu")).unwrap(),
        std::fs::read(one.join("solution.vtu")).unwrap(),
        "{name}: solution.vtu depends on the thread count"
    );
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&one);
}

#[test]
fn patch_test_point_field_is_exact_structured() {
    patch_test("structured", Layout::Structured);
}

#[test]
fn patch_test_point_field_is_exact_jittered() {
    patch_test("jittered", Layout::Jittered { amplitude: 0.3, seed: 5 });
}

/// Shipped problems with curved and non-convex boundaries and two bodies.
#[test]
fn shipped_problems_have_shared_points() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in ["plate_with_hole", "hertz_cylinder", "two_blocks"] {
        let text = std::fs::read_to_string(root.join("problems").join(format!("{file}.toml")));
        let problem = Problem::from_toml(&text.unwrap()).unwrap();
        let out = scratch(file);
        run(&problem, &out);
        let mut bodies = vec![(out.join("solution.vtu"), problem.node_spacing)];
        if let Some(p2) = &problem.second_body {
            bodies.push((out.join(&p2.name).join("solution.vtu"), p2.node_spacing));
        }
        for (path, h) in bodies {
            let vtu = read_and_check(&path, h);
            assert!(vtu.points.len() < vtu.polygons.iter().map(Vec::len).sum::<usize>());
        }
        let _ = std::fs::remove_dir_all(&out);
    }
}
