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

/// Parses the ASCII VTU or VTP text written by the program: the `Piece` element's attributes
/// and every data array (a string array's values are its bytes, each string ended by a 0).
fn parse_piece(text: &str) -> (HashMap<String, usize>, Vec<DataArray>) {
    let mut piece = HashMap::new();
    let mut section = String::new();
    let mut arrays: Vec<DataArray> = Vec::new();
    let mut open: Option<DataArray> = None;
    for line in text.lines().map(str::trim) {
        if line.starts_with("<Piece") {
            for key in [
                "NumberOfPoints",
                "NumberOfCells",
                "NumberOfVerts",
                "NumberOfLines",
                "NumberOfPolys",
            ] {
                if let Some(v) = attribute(line, key) {
                    piece.insert(key.to_string(), v.parse().unwrap());
                }
            }
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
        } else if let Some(tag) =
            ["Points", "Cells", "PointData", "CellData", "FieldData", "Verts", "Lines"]
                .iter()
                .find(|t| line.starts_with(&format!("<{t}")))
        {
            section = tag.to_string();
        }
    }
    assert!(open.is_none(), "unterminated DataArray");
    (piece, arrays)
}

/// Parses the ASCII VTU text written by the program.
fn parse(text: &str) -> (usize, usize, Vec<DataArray>) {
    let (piece, arrays) = parse_piece(text);
    (piece["NumberOfPoints"], piece["NumberOfCells"], arrays)
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
    for (name, components) in [("displacement", 3), ("stress", 6), ("strain", 6), ("von_mises", 1)]
    {
        let key = format!("PointData/{name}");
        assert!(arrays.contains_key(&key), "{key} missing");
        assert_eq!(arrays[&key].components, components, "{key}");
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
        revolve: None,
        units: None,
        others: Vec::new(),
        contact_pairs: Vec::new(),
        mesh_nodes: None,
        steps: Vec::new(),
        dynamics: None,
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
    // The tensors in VTK's order xx, yy, zz, xy, yz, xz: plane stress, so σzz = 0 and
    // εzz = −ν (εxx + εyy) / (1 − ν); the tensor shear εxy is half the engineering γxy.
    let sigma6 = [sigma[0], sigma[1], 0.0, sigma[2], 0.0, 0.0];
    let nu = problem.material.poisson;
    let eps6 = [2e-3, 0.7e-3, -nu / (1.0 - nu) * 2.7e-3, 0.5 * (-3e-3 + 1.5e-3), 0.0, 0.0];
    let s = &vtu.arrays["PointData/stress"].values;
    let stress_err = s
        .chunks(6)
        .map(|t| (0..6).map(|c| (t[c] - sigma6[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let e = &vtu.arrays["PointData/strain"].values;
    let strain_err = e
        .chunks(6)
        .map(|t| (0..6).map(|c| (t[c] - eps6[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    assert!(strain_err < 1e-8 * 3e-3, "{name}: point strain error {strain_err:e}");
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
        for p2 in problem.bodies().skip(1) {
            bodies.push((out.join(&p2.name).join("solution.vtu"), p2.node_spacing));
        }
        for (path, h) in bodies {
            let vtu = read_and_check(&path, h);
            assert!(vtu.points.len() < vtu.polygons.iter().map(Vec::len).sum::<usize>());
        }
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// A block pressed onto a rigid line, then sheared (friction, two load steps).
const PRESSED_BLOCK: &str = r#"
name = "pressed_block"
[geometry]
kind = "rectangle"
x = [0.0, 2.0]
y = [0.0, 1.0]
[nodes]
spacing = 0.125
[material]
young = 1000.0
poisson = 0.3
plane = "strain"
[[boundary]]
edge = "top"
displacement = { x = 0.0, y = 0.0 }
[contact]
edge = "bottom"
obstacle_point = [0.0, -0.01]
obstacle_normal = [0.0, 1.0]
friction = 0.3
[[step]]
boundary = [{ edge = "top", displacement = { x = 0.0, y = -0.03 } }]
[[step]]
increments = 2
boundary = [{ edge = "top", displacement = { x = 0.004, y = -0.03 } }]
[output]
steps = true
"#;

/// The `file` attributes of the `<DataSet …/>` lines of a `.vtm` or `.pvd` text, with the
/// line's `name` (`.vtm`) or `timestep` (`.pvd`).
fn data_sets(text: &str, key: &str) -> Vec<(String, String)> {
    text.lines()
        .filter(|l| l.trim_start().starts_with("<DataSet"))
        .map(|l| (attribute(l, key).unwrap(), attribute(l, "file").unwrap()))
        .collect()
}

/// A parsed VTP or VTU file: the piece's counts and the arrays by `section/name`.
fn read_piece(path: &Path) -> (HashMap<String, usize>, HashMap<String, DataArray>) {
    let (piece, list) = parse_piece(&std::fs::read_to_string(path).unwrap());
    let arrays = list.into_iter().map(|a| (format!("{}/{}", a.section, a.name), a)).collect();
    (piece, arrays)
}

/// Runs the shipped dynamic problem `file` (under `problems/`) with a snapshot every `every`
/// steps into the scratch folder `name`; returns the run's report and the folder.
fn run_with_frames(
    file: &str,
    every: usize,
    name: &str,
) -> (mlpg_contact::pipeline::dynamics::DynamicReport, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("problems").join(file)).unwrap()
        + &format!("\n[dynamics.output]\nevery = {every}\n");
    let problem = Problem::from_toml(&text).unwrap();
    let out = scratch(name);
    let report = mlpg_contact::pipeline::dynamics::run(
        &problem,
        &out,
        serde_json::Value::Null,
        &mut mlpg_contact::Silent,
    )
    .unwrap();
    (report, out)
}

/// One frame of a dynamic run of several bodies (`file`, a `frames/frame_<step>.vtm` under
/// `out`): checks that it names the bodies `names` in order, each its own
/// `frame_<step>_<k>.vtp` with `nodes[k]` points and one 3-component displacement and
/// velocity per node; returns each body's (points, displacements, velocities), 3 components
/// each.
fn frame_bodies(out: &Path, file: &str, names: &[&str], nodes: &[usize]) -> Vec<[Vec<f64>; 3]> {
    let vtm = std::fs::read_to_string(out.join(file)).unwrap();
    let stem = file.trim_start_matches("frames/").trim_end_matches(".vtm");
    let sets = data_sets(&vtm, "name");
    let listed: Vec<(String, String)> =
        names.iter().enumerate().map(|(k, n)| (n.to_string(), format!("{stem}_{k}.vtp"))).collect();
    assert_eq!(sets, listed, "{vtm}");
    sets.iter()
        .zip(nodes)
        .map(|((_, f), &n)| {
            let (piece, mut arrays) = read_piece(&out.join("frames").join(f));
            assert_eq!(piece["NumberOfPoints"], n, "{f}");
            let mut take = |key: &str| arrays.remove(key).unwrap_or_else(|| panic!("{f}: {key}"));
            let [points, u, v] =
                ["Points/", "PointData/displacement", "PointData/velocity"].map(&mut take);
            assert_eq!([points.components, u.components, v.components], [3, 3, 3], "{f}");
            assert_eq!([u.values.len(), v.values.len()], [3 * n, 3 * n], "{f}");
            [points.values, u.values, v.values]
        })
        .collect()
}

/// The strings of a string array (bytes, each string ended by a 0).
fn strings(a: &DataArray) -> Vec<String> {
    let bytes: Vec<u8> = a.values.iter().map(|&v| v as u8).collect();
    bytes
        .split(|&b| b == 0)
        .filter(|s| !s.is_empty())
        .map(|s| s.to_vec())
        .map(|s| String::from_utf8(s).unwrap())
        .collect()
}

/// The column `name` of a CSV file as text.
fn column(path: &Path, name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    lines.map(|l| l.split(',').nth(k).unwrap().to_string()).collect()
}

fn sum_column(path: &Path, name: &str) -> f64 {
    column(path, name).iter().map(|v| v.parse::<f64>().unwrap()).sum()
}

/// `reactions.csv`'s total `(Σ R_x, Σ R_y)`.
fn reaction_totals(dir: &Path) -> [f64; 2] {
    let path = dir.join("reactions.csv");
    let axis = column(&path, "axis");
    let r = column(&path, "reaction");
    let mut total = [0.0; 2];
    for (a, v) in axis.iter().zip(&r) {
        total[usize::from(a == "y")] += v.parse::<f64>().unwrap();
    }
    total
}

/// The sums of the two first components of a vector array.
fn vector_totals(a: &DataArray) -> [f64; 2] {
    assert_eq!(a.components, 3, "{}", a.name);
    a.values.chunks(3).fold([0.0; 2], |t, v| [t[0] + v[0], t[1] + v[1]])
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale
}

/// `solution.vtm` opens the body, the contact edge and the obstacle; `solution.pvd` (load
/// steps) the final state; the body's reactions (MFVM cell data, FE point data) add up to
/// `reactions.csv`'s; the contact edge's arrays are `contact.csv`'s columns, its state codes
/// follow its legend, and after "Warp By Vector" at scale 1 each candidate's distance to the
/// warped obstacle line is its final gap.
#[test]
fn multiblock_holds_body_contact_and_obstacle() {
    for method in ["mfvm", "fem"] {
        let text = format!("{PRESSED_BLOCK}\n[discretisation]\nmethod = \"{method}\"\n");
        let problem = Problem::from_toml(&text).unwrap();
        let out = scratch(&format!("pressed-{method}"));
        run(&problem, &out);
        let vtm = std::fs::read_to_string(out.join("solution.vtm")).unwrap();
        let sets = data_sets(&vtm, "name");
        let files: Vec<&str> = sets.iter().map(|(_, f)| f.as_str()).collect();
        assert_eq!(files, ["solution.vtu", "contact.vtp", "obstacles.vtp"], "{method}: {vtm}");
        let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
        assert_eq!(data_sets(&pvd, "timestep"), [("2".to_string(), "solution.vtm".to_string())]);

        // Reactions.
        let (_, body) = read_piece(&out.join("solution.vtu"));
        let key = if method == "fem" { "PointData/reaction" } else { "CellData/node_reaction" };
        let from_vtu = vector_totals(&body[key]);
        let from_csv = reaction_totals(&out);
        let scale = from_csv[0].abs() + from_csv[1].abs();
        assert!(scale > 0.0);
        for c in 0..2 {
            assert!(
                close(from_vtu[c], from_csv[c], scale),
                "{method}: {from_vtu:?} vs {from_csv:?}"
            );
        }
        assert_eq!(body["PointData/stress"].components, 6);
        // Plane strain: σzz = ν (σxx + σyy).
        for t in body["PointData/stress"].values.chunks(6) {
            assert!(close(t[2], 0.3 * (t[0] + t[1]), t[0].abs() + t[1].abs()), "{t:?}");
        }

        // The contact edge.
        let (piece, contact) = read_piece(&out.join("contact.vtp"));
        let csv = out.join("contact.csv");
        let n = column(&csv, "candidate").len();
        assert_eq!(piece["NumberOfPoints"], n);
        assert_eq!(piece["NumberOfVerts"], n);
        assert_eq!(piece["NumberOfLines"], 1);
        for (array, col) in [
            ("normal_force", "force"),
            ("pressure", "pressure"),
            ("gap", "gap"),
            ("initial_gap", "initial_gap"),
            ("tangential_force", "tangential_force"),
            ("slip", "slip"),
        ] {
            let a = &contact[&format!("PointData/{array}")];
            assert_eq!(a.values.len(), n, "{array}");
            let (x, y) = (a.values.iter().sum::<f64>(), sum_column(&csv, col));
            let scale = a.values.iter().map(|v| v.abs()).sum::<f64>().max(1e-300);
            assert!(close(x, y, scale), "{method}: {array} {x} vs {col} {y}");
        }
        assert!(contact["PointData/normal_force"].values.iter().any(|&p| p > 0.0));
        let legend = strings(&contact["FieldData/state_legend"]);
        assert_eq!(legend, ["open", "stick", "slip+", "slip-"]);
        let states: Vec<String> =
            contact["PointData/state"].values.iter().map(|&s| legend[s as usize].clone()).collect();
        assert_eq!(states, column(&csv, "state"), "{method}");

        // Warped by their displacements, the candidates lie their final gap from the warped
        // obstacle (the line's normal is +y).
        let (_, obstacle) = read_piece(&out.join("obstacles.vtp"));
        assert_eq!(strings(&obstacle["FieldData/obstacle_names"]), ["obstacle"]);
        let p = &obstacle["Points/"].values;
        let d = &obstacle["PointData/displacement"].values;
        let line_y = p[1] + d[1];
        assert!((p[4] + d[4] - line_y).abs() < 1e-15, "the obstacle line is horizontal");
        let x = &contact["Points/"].values;
        let u = &contact["PointData/displacement"].values;
        let gap = &contact["PointData/gap"].values;
        for k in 0..n {
            let warped = x[3 * k + 1] + u[3 * k + 1] - line_y;
            assert!(
                (warped - gap[k]).abs() < 1e-9,
                "{method}: candidate {k}: {warped} vs {}",
                gap[k]
            );
        }

        // `[output] steps`: the contact edge per increment, at times 1, 1.5 and 2; the last one
        // is the final state.
        let series = std::fs::read_to_string(out.join("steps/contact.pvd")).unwrap();
        let entries = data_sets(&series, "timestep");
        let times: Vec<&str> = entries.iter().map(|(t, _)| t.as_str()).collect();
        assert_eq!(times, ["1", "1.5", "2"], "{method}: {series}");
        let (_, last) = read_piece(&out.join("steps").join(&entries[2].1));
        for name in ["normal_force", "tangential_force", "slip", "state"] {
            let key = format!("PointData/{name}");
            assert_eq!(last[&key].values, contact[&key].values, "{method}: {name}");
        }
        let (_, first) = read_piece(&out.join("steps").join(&entries[0].1));
        // The shear of step 2 changes the tangential forces of step 1.
        let t1 = &first["PointData/tangential_force"].values;
        let t2 = &last["PointData/tangential_force"].values;
        let change = t1.iter().zip(t2).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(change > 0.1, "{method}: step 1 {t1:?}, step 2 {t2:?}");
        assert!(first["PointData/normal_force"].values.iter().sum::<f64>() > 0.0);
        assert_eq!(strings(&first["FieldData/state_legend"]), legend);
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// Three bodies in two contact pairs: `solution.vtm` names each body's `solution.vtu` and
/// each pair's `contact_<k>.vtp` (frictionless: states open and closed), every file exists,
/// and there is no obstacle and no time series.
#[test]
fn multiblock_of_several_bodies() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("problems/three_block_stack.toml")).unwrap();
    let problem = Problem::from_toml(&text).unwrap();
    let out = scratch("stack");
    run(&problem, &out);
    let vtm = std::fs::read_to_string(out.join("solution.vtm")).unwrap();
    let sets = data_sets(&vtm, "name");
    let files: Vec<&str> = sets.iter().map(|(_, f)| f.as_str()).collect();
    assert_eq!(
        files,
        [
            "solution.vtu",
            "middle/solution.vtu",
            "top/solution.vtu",
            "contact_0.vtp",
            "contact_1.vtp"
        ]
    );
    assert!(!out.join("solution.pvd").exists() && !out.join("obstacles.vtp").exists());
    for f in &files[..3] {
        let (piece, arrays) = read_piece(&out.join(f));
        assert!(piece["NumberOfCells"] > 0);
        assert_eq!(arrays["PointData/stress"].components, 6, "{f}");
        assert!(arrays.contains_key("CellData/node_reaction"), "{f}");
    }
    for k in 0..2 {
        let (_, contact) = read_piece(&out.join(format!("contact_{k}.vtp")));
        let csv = out.join(format!("contact_{k}.csv"));
        let force = contact["PointData/normal_force"].values.iter().sum::<f64>();
        assert!(force > 0.0 && close(force, sum_column(&csv, "force"), force), "pair {k}");
        assert_eq!(strings(&contact["FieldData/state_legend"]), ["open", "closed"]);
        let closed: Vec<String> =
            contact["PointData/state"].values.iter().map(|s| s.to_string()).collect();
        assert_eq!(closed, column(&csv, "in_contact"), "pair {k}");
        assert!(!contact.contains_key("PointData/tangential_force"));
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The section's `∫ r dA` from `solution.vtu`'s polygons (x = r): `Σ (1/6) Σ_edges
/// (x_i + x_{i+1}) (x_i y_{i+1} − x_{i+1} y_i)` per polygon.
fn section_moment(vtu: &Vtu) -> f64 {
    let mut total = 0.0;
    for polygon in &vtu.polygons {
        for (k, &a) in polygon.iter().enumerate() {
            let (p, q) = (vtu.points[a], vtu.points[polygon[(k + 1) % polygon.len()]]);
            total += (p[0] + q[0]) * (p[0] * q[1] - q[0] * p[1]) / 6.0;
        }
    }
    total
}

/// The volume of a wedge from its six corners in VTK's order (the right-hand normal of the base
/// `0, 1, 2` pointing towards `3, 4, 5`; VTK's own volume of such a wedge is positive), split
/// into three tetrahedra: positive when the wedge is ordered so.
fn wedge_volume(c: &[[f64; 3]; 6]) -> f64 {
    let tet = |a: [f64; 3], b: [f64; 3], d: [f64; 3], e: [f64; 3]| {
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
        let w = [e[0] - a[0], e[1] - a[1], e[2] - a[2]];
        (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))
            / 6.0
    };
    tet(c[0], c[1], c[2], c[3]) + tet(c[1], c[2], c[3], c[4]) + tet(c[2], c[3], c[4], c[5])
}

/// A revolved VTU: its 3-D points, its cells and its arrays by `section/name`.
type Revolved = (Vec<[f64; 3]>, Vec<Vec<usize>>, HashMap<String, DataArray>);

/// Reads `solution_revolved.vtu`: its 3-D points, its cells (all wedges, type 13) and arrays.
fn read_revolved(path: &Path) -> Revolved {
    let (piece, arrays) = read_piece(path);
    let points: Vec<[f64; 3]> =
        arrays["Points/"].values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    assert_eq!(points.len(), piece["NumberOfPoints"]);
    let connectivity = &arrays["Cells/connectivity"].values;
    let offsets = &arrays["Cells/offsets"].values;
    let mut cells = Vec::new();
    let mut start = 0;
    for &end in offsets {
        cells.push(connectivity[start..end as usize].iter().map(|&v| v as usize).collect());
        start = end as usize;
    }
    assert_eq!(cells.len(), piece["NumberOfCells"]);
    assert!(arrays["Cells/types"].values.iter().all(|&t| t == 13.0), "every cell a wedge");
    (points, cells, arrays)
}

/// problems/thick_cylinder_axisymmetric.toml (coarsened to h = 0.1) with `[output] revolve =
/// 360`: the section swept a full turn into wedges. The wedges' volume tends to the revolved
/// volume `2π ∫ r dA` (∫ r dA from `solution.vtu`'s polygons, 0.75 for this rectangle) as the
/// chord error `1 − sin Δ / Δ ≈ Δ²/6` of the segment angle Δ: within 1.2 Δ²/6 at 24 and 96
/// segments, shrinking by 16 (±10 %) between them. The displacement of every copy is
/// `(u_r cos θ, u_r sin θ, u_z)` of its section point; the stress keeps its trace and the von
/// Mises stress is the section's.
#[test]
fn revolved_section_fills_the_revolved_volume() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/thick_cylinder_axisymmetric.toml");
    let text = std::fs::read_to_string(file).unwrap().replace("spacing = 0.05", "spacing = 0.1");
    assert!(text.contains("spacing = 0.1") && text.contains("[output]\n"));
    let mut errors = Vec::new();
    for segments in [24usize, 96] {
        let out = scratch(&format!("revolved-{segments}"));
        let with = text.replace(
            "[output]\n",
            &format!("[output]\nrevolve = 360.0\nrevolve_segments = {segments}\n"),
        );
        let problem = Problem::from_toml(&with).unwrap();
        run(&problem, &out);
        let section = read_and_check(&out.join("solution.vtu"), 0.1);
        let moment = section_moment(&section);
        assert!((moment - 0.75).abs() < 1e-12, "∫ r dA = {moment}");
        let (points, cells, arrays) = read_revolved(&out.join("solution_revolved.vtu"));
        let m = section.points.len();
        assert_eq!(points.len(), segments * m, "a full turn reuses the first copy");
        let volumes: Vec<f64> =
            cells.iter().map(|c| wedge_volume(&std::array::from_fn(|k| points[c[k]]))).collect();
        assert!(volumes.iter().all(|v| *v > 0.0), "every wedge ordered as VTK orders one");
        let volume: f64 = volumes.iter().sum();
        let exact = std::f64::consts::TAU * moment;
        let delta = std::f64::consts::TAU / segments as f64;
        let error = 1.0 - volume / exact;
        println!("{segments} segments: volume {volume:.9} against {exact:.9}, error {error:.3e}");
        assert!(error > 0.0 && error < 1.2 * delta * delta / 6.0, "{segments}: {error:e}");
        errors.push(error);
        // Fields: copy j of section point k is point j m + k.
        let u2 = &section.arrays["PointData/displacement"].values;
        let u3 = &arrays["PointData/displacement"].values;
        let (s2, s3) =
            (&section.arrays["PointData/stress"].values, &arrays["PointData/stress"].values);
        let (v2, v3) =
            (&section.arrays["PointData/von_mises"].values, &arrays["PointData/von_mises"].values);
        let scale = u2.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let stress_scale = s2.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (i, p) in points.iter().enumerate() {
            let (k, theta) = (i % m, (i / m) as f64 * delta);
            let (ur, uz) = (u2[3 * k], u2[3 * k + 1]);
            let expected = [ur * theta.cos(), ur * theta.sin(), uz];
            for a in 0..3 {
                assert!((u3[3 * i + a] - expected[a]).abs() <= 1e-10 * scale, "point {i}");
            }
            let r = section.points[k][0];
            // Both files print 12 significant digits.
            assert!((p[0].hypot(p[1]) - r).abs() <= 1e-10 * r && p[2] == section.points[k][1]);
            let trace = |s: &[f64], j: usize| s[6 * j] + s[6 * j + 1] + s[6 * j + 2];
            assert!((trace(s3, i) - trace(s2, k)).abs() <= 1e-10 * stress_scale, "point {i}");
            assert!((v3[i] - v2[k]).abs() <= 1e-10 * stress_scale);
        }
    }
    let ratio = errors[0] / errors[1];
    assert!((ratio / 16.0 - 1.0).abs() < 0.1, "error ratio {ratio} (chord error ∝ Δ²)");
}

/// The snapshots of a dynamic run of several bodies (`problems/newtons_cradle.toml` with
/// `[dynamics.output] every = 100`, 280 steps): `frames.pvd` lists one multiblock per frame
/// (steps 0, 100, 200 and the last, 280) at its time; each `frames/frame_<step>.vtm` names the
/// three bars, in body order, each its own point set with one displacement and one velocity
/// per node. At time 0 the striker moves at `v0` and the others rest, undeformed; at the end
/// the bars, warped by their displacements, do not overlap and the last one moves at about
/// `v0` (its node-averaged velocity within 5 % of `v0` of the run's mass-weighted final
/// velocity; measured 0.09787 against 0.09792), the striker nearly at rest (within 5 % of
/// `v0`; measured 2e-5), and the last bar's left end has moved more than `v0 / 2`.
#[test]
fn dynamic_snapshots_of_several_bodies() {
    let (report, out) = run_with_frames("newtons_cradle.toml", 100, "cradle-frames");
    let v0 = 0.1;
    let bodies = report.summary.bodies.as_ref().expect("three bodies");
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["striker", "middle", "last"]);
    let pvd = std::fs::read_to_string(out.join("frames.pvd")).unwrap();
    let expected: Vec<(String, String)> = [("0", 0), ("1.25", 100), ("2.5", 200), ("3.5", 280)]
        .iter()
        .map(|(t, step)| (t.to_string(), format!("frames/frame_{step:06}.vtm")))
        .collect();
    assert_eq!(data_sets(&pvd, "timestep"), expected, "{pvd}");
    // Each frame: the bodies' (undeformed x range, warped x range, mean nodal velocity).
    let nodes: Vec<usize> = bodies.iter().map(|b| b.nodes).collect();
    let frame = |file: &str| {
        frame_bodies(&out, file, &names, &nodes)
            .into_iter()
            .map(|[points, u, v]| {
                let n = points.len() / 3;
                let x: Vec<f64> = points.chunks(3).map(|p| p[0]).collect();
                let warped: Vec<f64> =
                    points.chunks(3).zip(u.chunks(3)).map(|(p, d)| p[0] + d[0]).collect();
                let range = |x: &[f64]| {
                    (
                        x.iter().copied().fold(f64::INFINITY, f64::min),
                        x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                    )
                };
                let mean = [0, 1].map(|c| v.chunks(3).map(|t| t[c]).sum::<f64>() / n as f64);
                (range(&x), range(&warped), mean, u.iter().fold(0.0_f64, |a, b| a.max(b.abs())))
            })
            .collect::<Vec<_>>()
    };
    let start = frame(&expected[0].1);
    for (k, (x, warped, mean, largest)) in start.iter().enumerate() {
        assert_eq!(x, warped, "body {k} undeformed at time 0");
        assert_eq!(*largest, 0.0);
        let v = if k == 0 { v0 } else { 0.0 };
        assert!((mean[0] - v).abs() <= 1e-12 && mean[1].abs() <= 1e-12, "body {k}: {mean:?}");
    }
    let end = frame(&expected[3].1);
    for k in 0..2 {
        let (gap, next) = (end[k].1.1, end[k + 1].1.0);
        assert!(gap < next, "bodies {k} and {} overlap: {gap} ≥ {next}", k + 1);
    }
    let last = bodies[2].final_velocity[0];
    println!(
        "cradle frames: final mean nodal velocities {:?}; the run's {:?}; the last bar moved {}",
        end.iter().map(|e| e.2[0]).collect::<Vec<_>>(),
        bodies.iter().map(|b| b.final_velocity[0]).collect::<Vec<_>>(),
        end[2].1.0 - start[2].1.0
    );
    assert!((end[2].2[0] - last).abs() <= 0.05 * v0, "last bar {:?} against {last}", end[2].2);
    assert!(end[0].2[0].abs() <= 0.05 * v0, "striker {:?}", end[0].2);
    let moved = end[2].1.0 - start[2].1.0;
    assert!(moved > 0.5 * v0, "the last bar moved {moved}");
    let _ = std::fs::remove_dir_all(&out);
}

/// Snapshots of several axisymmetric bodies: `problems/spheres_impact_axisymmetric.toml` with
/// `every = 140` — the index lists steps 0, 140, 280; each `.vtm` names `upper` and `lower`;
/// each `.vtp` holds the body's section points (r, z, 0) with one 3-component displacement and
/// velocity per node; at time 0 every node of the upper sphere moves at −1 m/s along the axis
/// and every node of the lower one at +1 m/s, undeformed; at the end the warped spheres do not
/// overlap (the lower one's highest warped point below the upper one's lowest) and their
/// node-averaged axial velocities are within 0.05 m/s of the run's mass-weighted final ones
/// (measured ±1.0294 against ±0.99993: the unweighted mean of nodes graded to the pole, whose
/// waves ring on; 35 µm apart at the end).
#[test]
fn dynamic_snapshots_of_several_axisymmetric_bodies() {
    let (report, out) = run_with_frames("spheres_impact_axisymmetric.toml", 140, "spheres-frames");
    let bodies = report.summary.bodies.as_ref().expect("two bodies");
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["upper", "lower"]);
    let pvd = std::fs::read_to_string(out.join("frames.pvd")).unwrap();
    let steps: Vec<String> =
        data_sets(&pvd, "timestep").into_iter().map(|(_, f)| f).collect::<Vec<_>>();
    let expected: Vec<String> =
        [0, 140, 280].iter().map(|s| format!("frames/frame_{s:06}.vtm")).collect();
    assert_eq!(steps, expected, "{pvd}");
    // Each body of a frame: (lowest and highest warped z, mean nodal axial velocity, the
    // largest |displacement|, the nodal axial velocities' spread).
    let nodes: Vec<usize> = bodies.iter().map(|b| b.nodes).collect();
    let frame = |file: &str| {
        frame_bodies(&out, file, &names, &nodes)
            .into_iter()
            .map(|[points, u, v]| {
                let n = points.len() / 3;
                assert!(points.chunks(3).all(|p| p[0] >= 0.0 && p[2] == 0.0), "{file}: r ≥ 0");
                let z: Vec<f64> =
                    points.chunks(3).zip(u.chunks(3)).map(|(p, d)| p[1] + d[1]).collect();
                let vz: Vec<f64> = v.chunks(3).map(|t| t[1]).collect();
                let lo = z.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = z.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let mean = vz.iter().sum::<f64>() / n as f64;
                let spread = vz.iter().map(|w| (w - mean).abs()).fold(0.0, f64::max);
                (lo, hi, mean, u.iter().fold(0.0_f64, |a, b| a.max(b.abs())), spread)
            })
            .collect::<Vec<_>>()
    };
    let start = frame(&expected[0]);
    for (k, (_, _, mean, largest, spread)) in start.iter().enumerate() {
        let v = if k == 0 { -1.0 } else { 1.0 };
        assert_eq!(*largest, 0.0, "body {k} undeformed at time 0");
        assert!((mean - v).abs() <= 1e-12 && *spread <= 1e-12, "body {k}: {mean} ± {spread}");
    }
    let end = frame(&expected[2]);
    println!(
        "sphere frames: the lower's top {:.6e} below the upper's bottom {:.6e}; mean nodal axial velocities {:.5} {:.5}, the run's {:.5} {:.5}",
        end[1].1,
        end[0].0,
        end[0].2,
        end[1].2,
        bodies[0].final_velocity[1],
        bodies[1].final_velocity[1]
    );
    assert!(end[1].1 < end[0].0, "the spheres overlap: {} ≥ {}", end[1].1, end[0].0);
    for (k, e) in end.iter().enumerate() {
        let run = bodies[k].final_velocity[1];
        assert!((e.2 - run).abs() <= 0.05, "body {k}: nodal mean {} against the run's {run}", e.2);
    }
    let _ = std::fs::remove_dir_all(&out);
}
