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

/// Seeded mutations of Gmsh-written files (bytes changed, lines deleted or repeated, numbers
/// replaced by extreme values, files cut short): every one is read or refused, none panics,
/// and a mesh that is read gives boundary loops or a typed refusal.
#[test]
fn mutated_files_never_panic() {
    const NUMBERS: [&str; 9] = [
        "-1",
        "0",
        "1e308",
        "nan",
        "18446744073709551615",
        "-9223372036854775808",
        "4294967297",
        "3",
        "2.5",
    ];
    let mut state = 0x5eed_u64;
    let mut next = move || {
        // SplitMix64.
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let (mut read_ok, mut refused, mut loops_ok) = (0, 0, 0);
    for file in ["plate_with_hole_o1_v4.msh", "plate_with_hole_o2_v2.msh", "two_blocks_o2_v4.msh"] {
        let text = std::fs::read_to_string(data(file)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for _ in 0..700 {
            let mut bytes = text.as_bytes().to_vec();
            match next() % 5 {
                0 => {
                    let k = (next() % bytes.len() as u64) as usize;
                    bytes[k] = (next() % 256) as u8;
                }
                1 | 2 => {
                    let k = (next() % lines.len() as u64) as usize;
                    let mut l = lines.clone();
                    if next() % 2 == 0 {
                        l.remove(k);
                    } else {
                        l.insert(k, lines[k]);
                    }
                    bytes = l.join("\n").into_bytes();
                }
                3 => {
                    let k = (next() % lines.len() as u64) as usize;
                    let mut words: Vec<&str> = lines[k].split(' ').collect();
                    let w = (next() % words.len() as u64) as usize;
                    words[w] = NUMBERS[(next() % NUMBERS.len() as u64) as usize];
                    let mut l = lines.clone();
                    let replaced = words.join(" ");
                    l[k] = &replaced;
                    bytes = l.join("\n").into_bytes();
                }
                _ => bytes.truncate((next() % bytes.len() as u64) as usize),
            }
            let outcome = std::panic::catch_unwind(|| match Mesh::parse(&bytes) {
                Ok(mesh) => {
                    let surfaces: Vec<String> = mesh
                        .physical_names
                        .iter()
                        .filter(|p| p.dimension == 2)
                        .map(|p| p.name.clone())
                        .collect();
                    let ok = surfaces.iter().filter(|s| mesh.boundary(s).is_ok()).count();
                    (true, ok)
                }
                Err(e) => {
                    assert!(!e.to_string().is_empty());
                    (false, 0)
                }
            });
            match outcome {
                Ok((true, ok)) => {
                    read_ok += 1;
                    loops_ok += ok;
                }
                Ok((false, _)) => refused += 1,
                Err(_) => panic!(
                    "{file}: a mutated file panicked the reader:\n{}",
                    String::from_utf8_lossy(&bytes)
                ),
            }
        }
    }
    eprintln!("mutated files: {read_ok} read ({loops_ok} surfaces with loops), {refused} refused");
    assert_eq!(read_ok + refused, 2100);
    assert!(read_ok > 0 && refused > 0, "the mutations exercise both outcomes");
}

/// The quarter plate as a body: one edge per physical curve, the straight ones segments, the
/// hole the polygon through its nodes (second order: through the middle nodes too). The area
/// exceeds the exact one by the circular segments of the polygon's chords, `(θ − sin θ)/2` each
/// for a chord of angle `θ` on the unit circle: about four times less with the middle nodes.
#[test]
fn quarter_plate_bodies_have_polygonal_holes() {
    use mlpg_contact::geometry::Curve;
    let exact = 100.0 - PI / 4.0;
    let mut excess = Vec::new();
    for order in [1, 2] {
        let body = read(&format!("plate_with_hole_o{order}_v4.msh")).body("plate").unwrap();
        let d = &body.domain;
        assert_eq!(d.edge_names(), ["bottom", "right", "top", "left", "hole"]);
        assert_eq!(d.curves().iter().filter(|c| c.is_straight()).count(), 4);
        let Curve::Polyline { points } = d.curve(4) else { panic!("{:?}", d.curve(4)) };
        assert!(points.iter().all(|p| (p[0].hypot(p[1]) - 1.0).abs() < 1e-12));
        let segments: f64 = points
            .windows(2)
            .map(|w| {
                let theta = 2.0 * (0.5 * (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).asin();
                0.5 * (theta - theta.sin())
            })
            .sum();
        let e = d.area() - exact;
        assert!(
            (e - segments).abs() < 1e-12,
            "order {order}: area excess {e}, segments {segments}"
        );
        assert_eq!(
            body.points.len(),
            read(&format!("plate_with_hole_o{order}_v4.msh")).points.len()
        );
        excess.push(e);
    }
    assert!(excess[1] < excess[0] / 3.0, "{excess:?}");
}

/// Obstacle curves (`punch.geo`, meshed in one dimension): the open punch profile walked from
/// its first point to its last through every node, middle nodes included; the closed ring
/// ending where it starts, counter-clockwise (positive area), its nodes on the circle.
#[test]
fn physical_curves_chain_into_polylines() {
    let corners = [[-0.1, 1.0], [-0.1, 0.0], [0.1, 0.0], [0.1, 1.0]];
    for (name, pieces) in [("punch_o1_v4.msh", 1), ("punch_o2_v2.msh", 2)] {
        let mesh = read(name);
        assert_eq!(mesh.curve_names(), ["punch", "ring"], "{name}");
        let punch = mesh.curve_points("punch").unwrap();
        // Sides of length 1 and a face of 0.2 at size 0.05: 20 + 4 + 20 pieces (each halved
        // by the middle nodes at second order).
        assert_eq!(punch.len(), 44 * pieces + 1, "{name}");
        assert_eq!(punch[0], corners[0], "{name}");
        assert_eq!(punch[20 * pieces], corners[1], "{name}");
        assert_eq!(punch[24 * pieces], corners[2], "{name}");
        assert_eq!(punch[44 * pieces], corners[3], "{name}");
        // Monotone along each side and the face: the walk never turns back.
        for w in punch.windows(2) {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1]];
            let l = d[0].hypot(d[1]);
            assert!(l > 0.02 / pieces as f64 && l < 0.06 / pieces as f64, "{name}: {w:?}");
        }
        let ring = mesh.curve_points("ring").unwrap();
        assert_eq!(ring.first(), ring.last(), "{name}: closed");
        let area: f64 =
            ring.windows(2).map(|w| 0.5 * (w[0][0] * w[1][1] - w[1][0] * w[0][1])).sum();
        // The nodes are equally spaced on each quarter arc: the regular inscribed polygon.
        let n = (ring.len() - 1) as f64;
        let polygon = 0.5 * n * 0.05 * 0.05 * (2.0 * PI / n).sin();
        assert!((area / polygon - 1.0).abs() < 1e-12, "{name}: area {area} vs {polygon}");
        for p in &ring {
            assert!(((p[0] - 0.5).hypot(p[1] - 0.5) - 0.05).abs() < 1e-12, "{name}: {p:?}");
        }
        let e = mesh.curve_points("rim").unwrap_err();
        assert!(matches!(e.kind, GmshErrorKind::NoCurve { .. }), "{e}");
    }
}
