//! The Gmsh reader on files written by Gmsh itself (`tests/data/gmsh/`, made by its
//! `make_meshes.py` from the `.geo` files beside them): versions 4.1 and 2.2, first and second
//! order, triangles and quadrilaterals, one and two bodies per file; and damaged copies of them.
use mlpg_contact::problem::gmsh::{GmshErrorKind, Mesh};
use std::f64::consts::PI;
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh").join(name)
}

fn read(name: &str) -> Mesh {
    Mesh::read(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Names of the runs of equally named edges around a loop, in order.
fn runs(names: &[Option<String>]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for n in names {
        let n = n.clone().unwrap_or_default();
        if out.last() != Some(&n) {
            out.push(n);
        }
    }
    out
}

#[test]
fn quarter_plate_with_hole_in_every_version_and_order() {
    let exact = 100.0 - PI / 4.0;
    for order in [1, 2] {
        let v4 = read(&format!("plate_with_hole_o{order}_v4.msh"));
        let v2 = read(&format!("plate_with_hole_o{order}_v2.msh"));
        // The two versions hold the same nodes and the same boundary.
        assert_eq!(v4.points, v2.points, "order {order}");
        let loops = v4.boundary("plate").unwrap();
        assert_eq!(loops, v2.boundary("plate").unwrap(), "order {order}");
        assert_eq!(loops.len(), 1, "one closed loop, counter-clockwise");
        let l = &loops[0];
        // Every boundary edge lies on a named physical curve, the names in the .geo's order.
        let names: Vec<Option<String>> = l.edges.iter().map(|e| e.name.clone()).collect();
        assert_eq!(runs(&names), ["bottom", "right", "top", "left", "hole"], "order {order}");
        // The corner polygon cuts the hole's arc by chords: a little more area than the exact
        // region, by at most the circular segments of the hole's chords.
        let hole: Vec<_> = l.edges.iter().filter(|e| e.name.as_deref() == Some("hole")).collect();
        let theta = 0.5 * PI / hole.len() as f64;
        let segments = hole.len() as f64 * 0.5 * (theta - theta.sin());
        assert!(
            l.signed_area > exact && l.signed_area <= exact + 1.5 * segments,
            "{}",
            l.signed_area
        );
        // Nodes of the hole (ends and, second order, middles) lie on the unit circle.
        for e in &hole {
            for i in [Some(e.a), Some(e.b), e.middle].into_iter().flatten() {
                let p = v4.points[i];
                assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-12, "{p:?}");
            }
            assert_eq!(e.middle.is_some(), order == 2);
        }
    }
}

#[test]
fn two_bodies_in_one_file() {
    for name in ["two_blocks_o1_v4.msh", "two_blocks_o2_v2.msh"] {
        let mesh = read(name);
        for (surface, bottom, top, y) in [
            ("lower", "lower_bottom", "lower_top", 0.0),
            ("upper", "upper_bottom", "upper_top", 1.0),
        ] {
            let loops = mesh.boundary(surface).unwrap();
            assert_eq!(loops.len(), 1, "{name} {surface}");
            assert!((loops[0].signed_area - 2.0).abs() < 1e-12, "{name} {surface}");
            let names: Vec<Option<String>> =
                loops[0].edges.iter().map(|e| e.name.clone()).collect();
            let runs = runs(&names);
            assert!(
                runs.contains(&bottom.to_string()) && runs.contains(&top.to_string()),
                "{runs:?}"
            );
            for e in loops[0].edges.iter().filter(|e| e.name.as_deref() == Some(bottom)) {
                assert_eq!((mesh.points[e.a][1], mesh.points[e.b][1]), (y, y));
                assert!(mesh.points[e.a][0] < mesh.points[e.b][0], "counter-clockwise");
            }
        }
        let e = mesh.boundary("middle").unwrap_err();
        assert!(e.to_string().contains("`lower`, `upper`"), "{e}");
    }
}

#[test]
fn damaged_files_are_refused_with_their_line() {
    let text = std::fs::read_to_string(data("plate_with_hole_o1_v4.msh")).unwrap();
    // Cut in the middle of $Elements.
    let cut = &text[..text.find("$EndElements").unwrap() - 200];
    let cut = &cut[..cut.rfind('\n').unwrap()];
    let e = Mesh::parse(cut.as_bytes()).unwrap_err();
    assert_eq!(e.kind, GmshErrorKind::Truncated { section: "Elements" });
    assert_eq!(e.line, Some(cut.lines().count()));
    // A byte that is not UTF-8 in a node line.
    let mut bytes = text.as_bytes().to_vec();
    let k = text.find("$Nodes").unwrap() + 20;
    bytes[k] = 0xfe;
    let e = Mesh::parse(&bytes).unwrap_err();
    assert_eq!(e.kind, GmshErrorKind::NotUtf8);
    assert_eq!(e.line, Some(text[..k].matches('\n').count() + 1));
    // Binary, and an unknown version.
    for (from, to, kind) in [
        ("4.1 0 8", "4.1 1 8", GmshErrorKind::Binary),
        ("4.1 0 8", "5 0 8", GmshErrorKind::Version { found: "5".into() }),
    ] {
        let e = Mesh::parse(text.replacen(from, to, 1).as_bytes()).unwrap_err();
        assert_eq!((e.line, e.kind), (Some(2), kind));
    }
    // A file that is not there names nothing but says why.
    let e = Mesh::read(&data("missing.msh")).unwrap_err();
    assert_eq!(e.line, None);
}
