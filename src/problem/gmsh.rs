//! Stage 1 (problem input): a reader for Gmsh mesh files, MSH 4.1 and MSH 2.2 in ASCII.
//!
//! A body drawn in Gmsh arrives as a 2-D mesh whose *physical groups* carry the names a problem
//! file uses: a physical surface is a body, a physical curve an edge that boundary conditions
//! and contact refer to. [`Mesh::parse`] reads the nodes (the plane `z = 0`), the elements and
//! the physical names; [`Mesh::boundary`] turns a physical surface into closed boundary loops
//! (counter-clockwise outside, clockwise around holes) whose edges carry the names of the
//! physical curves lying on them.
//!
//! Format references: the Gmsh reference manual, section "MSH file format" (version 4.1) and
//! its "Legacy formats" appendix (version 2.2). Binary files are refused with the way out (save
//! as ASCII); every error names the line of the file where it was found.

use crate::geometry::{Curve, Domain, Point};
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

/// An element kind of a 2-D mesh (Gmsh element type numbers in brackets).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// One node (15).
    Point,
    /// Two-node line (1).
    Line2,
    /// Three-node line (8): two ends, then the middle node.
    Line3,
    /// Three-node triangle (2).
    Tri3,
    /// Six-node triangle (9): three corners, then the edge nodes.
    Tri6,
    /// Four-node quadrilateral (3).
    Quad4,
    /// Eight-node quadrilateral (16): four corners, then the edge nodes.
    Quad8,
    /// Nine-node quadrilateral (10): four corners, the edge nodes, the centre.
    Quad9,
}

impl ElementKind {
    fn from_gmsh(t: u32) -> Result<Self, GmshErrorKind> {
        Ok(match t {
            15 => Self::Point,
            1 => Self::Line2,
            8 => Self::Line3,
            2 => Self::Tri3,
            9 => Self::Tri6,
            3 => Self::Quad4,
            16 => Self::Quad8,
            10 => Self::Quad9,
            // Tetrahedra, hexahedra, prisms, pyramids of orders 1-2 (and their serendipity forms).
            4..=7 | 11..=14 | 17..=19 | 29..=31 | 92 | 93 => {
                return Err(GmshErrorKind::SolidElement { element_type: t });
            }
            _ => return Err(GmshErrorKind::UnknownElementType { element_type: t }),
        })
    }

    /// Number of nodes.
    pub fn node_count(self) -> usize {
        match self {
            Self::Point => 1,
            Self::Line2 => 2,
            Self::Line3 | Self::Tri3 => 3,
            Self::Quad4 => 4,
            Self::Tri6 => 6,
            Self::Quad8 => 8,
            Self::Quad9 => 9,
        }
    }

    /// Topological dimension (0, 1 or 2).
    pub fn dimension(self) -> u8 {
        match self {
            Self::Point => 0,
            Self::Line2 | Self::Line3 => 1,
            _ => 2,
        }
    }

    /// Corner count of a 2-D element (0 for points and lines).
    fn corners(self) -> usize {
        match self {
            Self::Tri3 | Self::Tri6 => 3,
            Self::Quad4 | Self::Quad8 | Self::Quad9 => 4,
            _ => 0,
        }
    }

    /// Whether edges carry a middle node (second order).
    fn has_edge_nodes(self) -> bool {
        matches!(self, Self::Line3 | Self::Tri6 | Self::Quad8 | Self::Quad9)
    }
}

/// One element: its kind, its nodes (indices into [`Mesh::points`]) and its physical tags.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Element kind.
    pub kind: ElementKind,
    /// Node indices into [`Mesh::points`], in Gmsh's order.
    pub nodes: Vec<usize>,
    /// Physical group tags of the element (of its entity, in MSH 4.1); empty if none.
    pub physical: Vec<i32>,
    /// Line of the file the element was read from.
    pub line: usize,
}

/// A named physical group.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PhysicalName {
    /// Dimension: 0 point, 1 curve, 2 surface.
    pub dimension: u8,
    /// Physical tag.
    pub tag: i32,
    /// Name, without the quotes.
    pub name: String,
}

/// The MSH version a file was written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MshVersion {
    /// MSH 2.2 (legacy).
    V2,
    /// MSH 4.1.
    V4,
}

/// A 2-D Gmsh mesh.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// The version of the file.
    pub version: MshVersion,
    /// Node positions (`z` is dropped after checking that it is 0).
    pub points: Vec<Point>,
    /// Gmsh's tag of each node.
    pub node_tags: Vec<u64>,
    /// Every element of dimension 0–2.
    pub elements: Vec<Element>,
    /// Physical names, in file order.
    pub physical_names: Vec<PhysicalName>,
}

/// One edge of a boundary loop: from node `a` to node `b` (indices into [`Mesh::points`]),
/// the middle node of a second-order edge, and the name of the physical curve it lies on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// Start node.
    pub a: usize,
    /// End node.
    pub b: usize,
    /// Middle node of a second-order edge.
    pub middle: Option<usize>,
    /// Name of the physical curve containing the edge, if any.
    pub name: Option<String>,
}

/// A closed loop of boundary edges; `edges[k].b == edges[k + 1].a`, cyclically.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryLoop {
    /// The edges in order: counter-clockwise for the outer loop, clockwise around a hole.
    pub edges: Vec<BoundaryEdge>,
    /// Signed area enclosed by the corner polygon (positive for the outer loop).
    pub signed_area: f64,
}

/// What went wrong reading a mesh file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GmshErrorKind {
    /// A line that is not UTF-8.
    #[error("the line is not UTF-8 text (is this an MSH file?)")]
    NotUtf8,
    /// No `$MeshFormat` at the start.
    #[error("no `$MeshFormat` section at the start: not an MSH file")]
    NotMsh,
    /// A binary file.
    #[error(
        "binary MSH files are not read: save the mesh as ASCII (Gmsh: `-format msh41` with `Mesh.Binary = 0`, or File > Export without 'Save in binary format')"
    )]
    Binary,
    /// A version other than 4.1 or 2.x.
    #[error("MSH version {found} is not read: save the mesh as version 4.1 or 2.2 (ASCII)")]
    Version {
        /// The version as written.
        found: String,
    },
    /// A required section is missing.
    #[error("the file has no `${section}` section")]
    MissingSection {
        /// Section name.
        section: &'static str,
    },
    /// The file ends inside a section.
    #[error("the file ends inside `${section}` (truncated?)")]
    Truncated {
        /// Section name.
        section: &'static str,
    },
    /// A line that does not hold what the format says.
    #[error("expected {expected}, found `{found}`")]
    Syntax {
        /// What the format requires here.
        expected: &'static str,
        /// The line as found (shortened).
        found: String,
    },
    /// A 3-D element.
    #[error(
        "element type {element_type} is a 3-D element: mlpg-contact solves plane problems (mesh a surface, not a volume)"
    )]
    SolidElement {
        /// Gmsh element type number.
        element_type: u32,
    },
    /// An element type this reader does not know.
    #[error(
        "element type {element_type} is not read (points, 2- and 3-node lines, 3- and 6-node triangles, 4-, 8- and 9-node quadrilaterals are)"
    )]
    UnknownElementType {
        /// Gmsh element type number.
        element_type: u32,
    },
    /// An element refers to a node that is not in `$Nodes`.
    #[error("node {tag} is not in `$Nodes`")]
    UnknownNode {
        /// The node tag.
        tag: u64,
    },
    /// A node tag given twice.
    #[error("node {tag} is given twice")]
    DuplicateNode {
        /// The node tag.
        tag: u64,
    },
    /// A node off the plane `z = 0`.
    #[error("node {tag} has z = {z}: the mesh must lie in the plane z = 0")]
    NotPlanar {
        /// The node tag.
        tag: u64,
        /// Its z coordinate.
        z: f64,
    },
    /// A non-finite coordinate.
    #[error("node {tag} has a coordinate that is not a finite number")]
    NonFinite {
        /// The node tag.
        tag: u64,
    },
    /// The file names no physical groups.
    #[error(
        "the mesh has no physical groups: name the body's surface and its edges in Gmsh (Physical Surface, Physical Curve)"
    )]
    NoPhysicalGroups,
    /// No physical surface of the requested name.
    #[error("no physical surface named `{name}` (the file has: {available})")]
    NoSurface {
        /// The requested name.
        name: String,
        /// The physical surfaces the file has.
        available: String,
    },
    /// The surface's elements do not form closed boundary loops.
    #[error("the boundary of surface `{name}` is not a set of closed loops ({reason})")]
    OpenBoundary {
        /// The surface name.
        name: String,
        /// What was found.
        reason: String,
    },
    /// An element with zero area.
    #[error("element at line {element_line} has zero area")]
    Degenerate {
        /// Line of the element.
        element_line: usize,
    },
    /// Boundary edges on no physical curve.
    #[error(
        "the boundary of surface `{name}` from node {from} to node {to} lies on no physical curve: every boundary curve needs a Physical Curve (its edge name)"
    )]
    UnnamedBoundary {
        /// The surface name.
        name: String,
        /// Tag of the first node of the unnamed run.
        from: u64,
        /// Tag of its last node.
        to: u64,
    },
    /// A physical curve in several separate pieces along the boundary.
    #[error(
        "physical curve `{curve}` appears in {runs} separate pieces along the boundary of surface `{name}`: an edge must be one connected piece (give each piece its own Physical Curve)"
    )]
    SplitCurve {
        /// The surface name.
        name: String,
        /// The curve name.
        curve: String,
        /// Number of pieces.
        runs: usize,
    },
    /// No physical curve of the requested name (or one without line elements).
    #[error("no physical curve named `{name}` with line elements (the file has: {available})")]
    NoCurve {
        /// The requested name.
        name: String,
        /// The physical curves the file has.
        available: String,
    },
    /// A physical curve whose line elements are not one open chain or one closed loop.
    #[error(
        "physical curve `{name}` is not one open chain or closed loop of line elements: {reason}"
    )]
    NotAChain {
        /// The curve name.
        name: String,
        /// What was found.
        reason: String,
    },
    /// The boundary loop is not a valid domain.
    #[error("the boundary of surface `{name}` is not a valid domain: {reason}")]
    Domain {
        /// The surface name.
        name: String,
        /// Why.
        reason: String,
    },
}

/// A body read from a mesh: the domain bounded by the surface's boundary loop, and the nodes of
/// the surface's elements with their local spacing (for `nodes.from = "mesh"`).
#[derive(Clone, Debug)]
pub struct MeshBody {
    /// The domain: one edge per physical curve along the loop. A run of boundary edges whose
    /// nodes are collinear to 1e-12 of its length (well within the 1e-9 spacings to which
    /// mesh nodes are tagged to their edges) is a [`Curve::Segment`]; any other is a
    /// [`Curve::Polyline`] through its nodes, middle nodes of second-order edges included (the
    /// body's boundary is the polygon through the boundary nodes; for a curved edge its area
    /// error is the circular segments of the chords, `≈ L h² / (12 R)` for chords of length
    /// `h` on an arc of length `L` and radius `R`, four times less with middle nodes).
    pub domain: Domain,
    /// The nodes of the surface's elements (corner, edge and centre nodes), in file order.
    pub points: Vec<Point>,
    /// The local spacing of each node: the mean over the elements that hold it of the element
    /// size (the side of the equilateral triangle or the square of the element's area), halved
    /// for second-order elements (their nodes are half a side apart).
    pub spacing: Vec<f64>,
    /// The surface's elements, their nodes numbered as `points` (for the finite element path,
    /// which takes the mesh's own elements).
    pub elements: Vec<Element>,
}

/// A reading error: what went wrong and the line (1-based) where it was found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{kind}", line.map(|l| format!("line {l}: ")).unwrap_or_default())]
pub struct GmshError {
    /// Line of the file, when the error belongs to one.
    pub line: Option<usize>,
    /// What went wrong.
    pub kind: GmshErrorKind,
}

fn at(line: usize, kind: GmshErrorKind) -> GmshError {
    GmshError { line: Some(line), kind }
}

/// The raw lines of a file (split at `\n`), numbered from 0.
type RawLines<'a> = std::iter::Enumerate<std::slice::Split<'a, u8, fn(&u8) -> bool>>;

/// Lines of the file with their numbers, blank lines skipped.
struct Lines<'a> {
    lines: RawLines<'a>,
    /// Number of the line last returned (1-based), or of the last line of the file.
    last: usize,
}

impl<'a> Lines<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        let newline: fn(&u8) -> bool = |b| *b == b'\n';
        Self { lines: bytes.split(newline).enumerate(), last: 0 }
    }

    /// The next non-blank line, or `None` at the end of the file.
    fn next(&mut self) -> Result<Option<(usize, &'a str)>, GmshError> {
        for (k, raw) in self.lines.by_ref() {
            self.last = k + 1;
            let text = std::str::from_utf8(raw).map_err(|_| at(k + 1, GmshErrorKind::NotUtf8))?;
            let text = text.trim();
            if !text.is_empty() {
                return Ok(Some((k + 1, text)));
            }
        }
        Ok(None)
    }

    /// The next line inside `section`: the end of the file or another section's header is
    /// [`GmshErrorKind::Truncated`].
    fn inside(&mut self, section: &'static str) -> Result<(usize, &'a str), GmshError> {
        match self.next()? {
            Some((n, text)) if text.starts_with('$') && text != format!("$End{section}") => {
                Err(at(n, GmshErrorKind::Truncated { section }))
            }
            Some(line) => Ok(line),
            None => Err(at(self.last, GmshErrorKind::Truncated { section })),
        }
    }

    /// Numbers of the next line inside `section`: at least `min` of them.
    fn numbers<T: std::str::FromStr>(
        &mut self,
        section: &'static str,
        min: usize,
        expected: &'static str,
    ) -> Result<(usize, Vec<T>), GmshError> {
        let (n, text) = self.inside(section)?;
        let values: Option<Vec<T>> = text.split_whitespace().map(|w| w.parse().ok()).collect();
        match values {
            Some(v) if v.len() >= min => Ok((n, v)),
            _ => Err(at(n, GmshErrorKind::Syntax { expected, found: shorten(text) })),
        }
    }

    /// Consumes the `$End<section>` line.
    fn end(&mut self, section: &'static str) -> Result<(), GmshError> {
        let (n, text) = self.inside(section)?;
        if text == format!("$End{section}") {
            Ok(())
        } else {
            Err(at(
                n,
                GmshErrorKind::Syntax { expected: "the end of the section", found: shorten(text) },
            ))
        }
    }

    /// Skips an unknown section up to its `$End` line.
    fn skip(&mut self, name: &str) -> Result<(), GmshError> {
        let end = format!("$End{name}");
        while let Some((_, text)) = self.next()? {
            if text == end {
                return Ok(());
            }
        }
        Err(at(self.last, GmshErrorKind::Truncated { section: "(a section)" }))
    }
}

fn shorten(text: &str) -> String {
    const MAX: usize = 60;
    if text.chars().count() > MAX {
        text.chars().take(MAX).collect::<String>() + "…"
    } else {
        text.to_string()
    }
}

/// Nodes and elements as read, before the node tags are resolved.
#[derive(Default)]
struct Raw {
    points: Vec<Point>,
    node_tags: Vec<u64>,
    index: HashMap<u64, usize>,
    /// (kind, node tags, physical tags, line).
    elements: Vec<(ElementKind, Vec<u64>, Vec<i32>, usize)>,
    names: Vec<PhysicalName>,
    /// MSH 4.1: physical tags of each (dimension, entity tag).
    entity_physicals: HashMap<(u8, i32), Vec<i32>>,
    /// (line, tag, z) of the node farthest off the plane `z = 0`.
    off_plane: Option<(usize, u64, f64)>,
}

impl Raw {
    fn add_node(&mut self, line: usize, tag: u64, xyz: &[f64]) -> Result<(), GmshError> {
        if xyz.iter().any(|v| !v.is_finite()) {
            return Err(at(line, GmshErrorKind::NonFinite { tag }));
        }
        if self.index.insert(tag, self.points.len()).is_some() {
            return Err(at(line, GmshErrorKind::DuplicateNode { tag }));
        }
        if self.off_plane.is_none_or(|(_, _, z)| xyz[2].abs() > z.abs()) && xyz[2] != 0.0 {
            self.off_plane = Some((line, tag, xyz[2]));
        }
        self.node_tags.push(tag);
        self.points.push([xyz[0], xyz[1]]);
        Ok(())
    }

    /// The node farthest off the plane `z = 0`, if farther than round-off of the extent.
    fn check_planar(&self) -> Result<(), GmshError> {
        let Some((line, tag, z)) = self.off_plane else { return Ok(()) };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &self.points {
            for d in 0..2 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        let extent = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        if z.abs() > 1e-9 * extent {
            Err(at(line, GmshErrorKind::NotPlanar { tag, z }))
        } else {
            Ok(())
        }
    }
}

impl Mesh {
    /// Reads a mesh file.
    ///
    /// # Errors
    /// [`GmshError`] with `line: None` if the file cannot be read (the message says why).
    pub fn read(path: &std::path::Path) -> Result<Self, GmshError> {
        let bytes = std::fs::read(path).map_err(|e| GmshError {
            line: None,
            kind: GmshErrorKind::Syntax { expected: "a readable file", found: e.to_string() },
        })?;
        Self::parse(&bytes)
    }

    /// Parses the bytes of an MSH 4.1 or 2.2 ASCII file.
    ///
    /// # Errors
    /// [`GmshError`] naming the line: not an MSH file, binary, another version, a truncated or
    /// malformed section, 3-D or unknown elements, unknown or duplicate nodes, nodes off the
    /// plane, no physical groups.
    pub fn parse(bytes: &[u8]) -> Result<Self, GmshError> {
        let mut lines = Lines::new(bytes);
        let Some((n, first)) = lines.next()? else {
            return Err(at(1, GmshErrorKind::NotMsh));
        };
        if first != "$MeshFormat" {
            return Err(at(n, GmshErrorKind::NotMsh));
        }
        let (n, format) = lines.inside("MeshFormat")?;
        let words: Vec<&str> = format.split_whitespace().collect();
        if words.len() < 3 {
            return Err(at(
                n,
                GmshErrorKind::Syntax {
                    expected: "version file-type data-size",
                    found: shorten(format),
                },
            ));
        }
        if words[1] != "0" {
            return Err(at(n, GmshErrorKind::Binary));
        }
        let version = match words[0] {
            "4.1" => MshVersion::V4,
            v if v.starts_with("2.") => MshVersion::V2,
            v => return Err(at(n, GmshErrorKind::Version { found: v.to_string() })),
        };
        lines.end("MeshFormat")?;
        let mut raw = Raw::default();
        let (mut seen_nodes, mut seen_elements) = (false, false);
        while let Some((n, header)) = lines.next()? {
            match header {
                "$PhysicalNames" => read_names(&mut lines, &mut raw)?,
                "$Entities" if version == MshVersion::V4 => read_entities(&mut lines, &mut raw)?,
                "$Nodes" => {
                    match version {
                        MshVersion::V4 => read_nodes_v4(&mut lines, &mut raw)?,
                        MshVersion::V2 => read_nodes_v2(&mut lines, &mut raw)?,
                    }
                    seen_nodes = true;
                }
                "$Elements" => {
                    match version {
                        MshVersion::V4 => read_elements_v4(&mut lines, &mut raw)?,
                        MshVersion::V2 => read_elements_v2(&mut lines, &mut raw)?,
                    }
                    seen_elements = true;
                }
                h if h.starts_with('$') && !h.starts_with("$End") => lines.skip(&h[1..])?,
                h => {
                    return Err(at(
                        n,
                        GmshErrorKind::Syntax {
                            expected: "a section header `$Name`",
                            found: shorten(h),
                        },
                    ));
                }
            }
        }
        for (seen, section) in [(seen_nodes, "Nodes"), (seen_elements, "Elements")] {
            if !seen {
                return Err(GmshError {
                    line: None,
                    kind: GmshErrorKind::MissingSection { section },
                });
            }
        }
        raw.check_planar()?;
        let mut elements = Vec::with_capacity(raw.elements.len());
        for (kind, tags, physical, line) in raw.elements {
            let nodes = tags
                .iter()
                .map(|t| {
                    raw.index
                        .get(t)
                        .copied()
                        .ok_or(at(line, GmshErrorKind::UnknownNode { tag: *t }))
                })
                .collect::<Result<Vec<usize>, _>>()?;
            elements.push(Element { kind, nodes, physical, line });
        }
        if elements.iter().all(|e| e.physical.is_empty()) {
            return Err(GmshError { line: None, kind: GmshErrorKind::NoPhysicalGroups });
        }
        Ok(Mesh {
            version,
            points: raw.points,
            node_tags: raw.node_tags,
            elements,
            physical_names: raw.names,
        })
    }

    /// The tag of the physical group of `dimension` named `name`.
    pub fn physical_tag(&self, dimension: u8, name: &str) -> Option<i32> {
        self.physical_names
            .iter()
            .find(|p| p.dimension == dimension && p.name == name)
            .map(|p| p.tag)
    }

    /// The name of physical group `tag` of `dimension`.
    pub fn physical_name(&self, dimension: u8, tag: i32) -> Option<&str> {
        self.physical_names
            .iter()
            .find(|p| p.dimension == dimension && p.tag == tag)
            .map(|p| p.name.as_str())
    }

    /// The 2-D elements of physical surface `name`.
    ///
    /// # Errors
    /// [`GmshErrorKind::NoSurface`] listing the surfaces the file has.
    pub fn surface(&self, name: &str) -> Result<Vec<&Element>, GmshError> {
        let no_surface = || GmshError {
            line: None,
            kind: GmshErrorKind::NoSurface {
                name: name.to_string(),
                available: {
                    let names: Vec<String> = self
                        .physical_names
                        .iter()
                        .filter(|p| p.dimension == 2)
                        .map(|p| format!("`{}`", p.name))
                        .collect();
                    if names.is_empty() { "none".into() } else { names.join(", ") }
                },
            },
        };
        let tag = self.physical_tag(2, name).ok_or_else(no_surface)?;
        let found: Vec<&Element> = self
            .elements
            .iter()
            .filter(|e| e.kind.dimension() == 2 && e.physical.contains(&tag))
            .collect();
        if found.is_empty() { Err(no_surface()) } else { Ok(found) }
    }

    /// The boundary of physical surface `name` as closed loops: the outer loop first
    /// (counter-clockwise), then the holes (clockwise), each starting where the edge names
    /// change (at its lowest such node), so that the result does not depend on element order.
    ///
    /// An edge is on the boundary when exactly one element of the surface has it; it is named
    /// after the physical curve whose line element joins the same two nodes.
    ///
    /// # Errors
    /// [`GmshErrorKind::NoSurface`], [`GmshErrorKind::Degenerate`] for an element of zero area,
    /// [`GmshErrorKind::OpenBoundary`] if the boundary edges do not form closed loops (a node
    /// where the boundary branches, or a surface glued to itself).
    pub fn boundary(&self, name: &str) -> Result<Vec<BoundaryLoop>, GmshError> {
        let elements = self.surface(name)?;
        // Boundary edges keyed by their sorted corner pair; the value is the oriented edge and
        // how many elements share it.
        let mut edges: BTreeMap<(usize, usize), (BoundaryEdge, usize)> = BTreeMap::new();
        for e in &elements {
            let c = e.kind.corners();
            let corners = &e.nodes[..c];
            let area = polygon_area(corners.iter().map(|&i| self.points[i]));
            let scale = corners
                .iter()
                .map(|&i| {
                    let p = self.points[i];
                    let q = self.points[corners[0]];
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .fold(0.0, f64::max);
            if area.abs() <= 1e-12 * scale * scale || !area.is_finite() {
                return Err(GmshError {
                    line: None,
                    kind: GmshErrorKind::Degenerate { element_line: e.line },
                });
            }
            for k in 0..c {
                let (mut a, mut b) = (corners[k], corners[(k + 1) % c]);
                if area < 0.0 {
                    std::mem::swap(&mut a, &mut b);
                }
                let middle = e.kind.has_edge_nodes().then(|| e.nodes[c + k]);
                let key = (a.min(b), a.max(b));
                edges
                    .entry(key)
                    .and_modify(|(_, count)| *count += 1)
                    .or_insert((BoundaryEdge { a, b, middle, name: None }, 1));
            }
        }
        let mut names: HashMap<(usize, usize), &str> = HashMap::new();
        for e in self.elements.iter().filter(|e| e.kind.dimension() == 1) {
            let (a, b) = (e.nodes[0], e.nodes[1]);
            if let Some(n) = e.physical.iter().find_map(|&t| self.physical_name(1, t)) {
                names.insert((a.min(b), a.max(b)), n);
            }
        }
        let mut next: BTreeMap<usize, BoundaryEdge> = BTreeMap::new();
        for (key, (mut edge, count)) in edges {
            if count != 1 {
                continue;
            }
            edge.name = names.get(&key).map(|s| s.to_string());
            let a = edge.a;
            if next.insert(a, edge).is_some() {
                return Err(GmshError {
                    line: None,
                    kind: GmshErrorKind::OpenBoundary {
                        name: name.to_string(),
                        reason: format!("two boundary edges start at node {}", self.node_tags[a]),
                    },
                });
            }
        }
        let mut loops = Vec::new();
        while let Some((&start, _)) = next.iter().next() {
            let mut chain = Vec::new();
            let mut at_node = start;
            while let Some(edge) = next.remove(&at_node) {
                at_node = edge.b;
                chain.push(edge);
                if at_node == start {
                    break;
                }
            }
            if at_node != start {
                return Err(GmshError {
                    line: None,
                    kind: GmshErrorKind::OpenBoundary {
                        name: name.to_string(),
                        reason: format!("the boundary stops at node {}", self.node_tags[at_node]),
                    },
                });
            }
            // Start where the name changes, at the lowest such node (else at the lowest node).
            let m = chain.len();
            let first = (0..m)
                .filter(|&k| chain[k].name != chain[(k + m - 1) % m].name)
                .min_by_key(|&k| chain[k].a)
                .unwrap_or_else(|| (0..m).min_by_key(|&k| chain[k].a).unwrap_or(0));
            chain.rotate_left(first);
            let signed_area = polygon_area(chain.iter().map(|e| self.points[e.a]));
            loops.push(BoundaryLoop { edges: chain, signed_area });
        }
        loops.sort_by(|a, b| b.signed_area.total_cmp(&a.signed_area));
        Ok(loops)
    }
}

impl Mesh {
    /// The physical surfaces' names, in file order.
    pub fn surface_names(&self) -> Vec<&str> {
        self.physical_names.iter().filter(|p| p.dimension == 2).map(|p| p.name.as_str()).collect()
    }

    /// The physical curves' names, in file order.
    pub fn curve_names(&self) -> Vec<&str> {
        self.physical_names.iter().filter(|p| p.dimension == 1).map(|p| p.name.as_str()).collect()
    }

    /// The nodes of physical curve `name` in order along it: its line elements chained end to
    /// end, a 3-node line's middle node between its ends. The chain is walked in the direction
    /// of the curve's first line element in the file (Gmsh writes a curve's elements from its
    /// first point to its last). A closed loop ends with its first node again.
    ///
    /// # Errors
    /// [`GmshErrorKind::NoCurve`] listing the physical curves the file has (also for a curve
    /// without line elements); [`GmshErrorKind::NotAChain`] when the elements branch, join a
    /// node to itself or form several pieces (with the line of an offending element).
    pub fn curve_points(&self, name: &str) -> Result<Vec<Point>, GmshError> {
        let no_curve = || GmshError {
            line: None,
            kind: GmshErrorKind::NoCurve {
                name: name.to_string(),
                available: {
                    let names: Vec<String> =
                        self.curve_names().iter().map(|n| format!("`{n}`")).collect();
                    if names.is_empty() { "none".into() } else { names.join(", ") }
                },
            },
        };
        let tag = self.physical_tag(1, name).ok_or_else(no_curve)?;
        let elements: Vec<&Element> = self
            .elements
            .iter()
            .filter(|e| e.kind.dimension() == 1 && e.physical.contains(&tag))
            .collect();
        if elements.is_empty() {
            return Err(no_curve());
        }
        let not_a_chain = |line: usize, reason: String| GmshError {
            line: Some(line),
            kind: GmshErrorKind::NotAChain { name: name.to_string(), reason },
        };
        // The elements at each node (at most two).
        let mut at: HashMap<usize, Vec<usize>> = HashMap::new();
        for (k, e) in elements.iter().enumerate() {
            let (a, b) = (e.nodes[0], e.nodes[1]);
            if a == b {
                return Err(not_a_chain(
                    e.line,
                    format!("a line element joins node {} to itself", self.node_tags[a]),
                ));
            }
            for n in [a, b] {
                let list = at.entry(n).or_default();
                list.push(k);
                if list.len() > 2 {
                    return Err(not_a_chain(
                        e.line,
                        format!(
                            "it branches at node {}: three line elements meet there",
                            self.node_tags[n]
                        ),
                    ));
                }
            }
        }
        // Walk from the first element in its direction, then back from its start; each step
        // takes the other element at the node reached and orients it away from that node.
        let other = |k: usize, node: usize| at[&node].iter().copied().find(|&j| j != k);
        let oriented = |k: usize, from: usize| {
            let e = elements[k];
            let mid = (e.kind == ElementKind::Line3).then(|| e.nodes[2]);
            if e.nodes[0] == from { (e.nodes[1], mid) } else { (e.nodes[0], mid) }
        };
        let mut used = vec![false; elements.len()];
        used[0] = true;
        let start = elements[0].nodes[0];
        let mut forward: Vec<usize> = vec![start];
        let (mut node, mid) = oriented(0, start);
        forward.extend(mid);
        forward.push(node);
        let mut k = 0;
        while let Some(j) = other(k, node).filter(|&j| !used[j]) {
            used[j] = true;
            let (next, mid) = oriented(j, node);
            forward.extend(mid);
            forward.push(next);
            (k, node) = (j, next);
        }
        let closed = node == start && elements.len() > 1;
        let mut backward: Vec<usize> = Vec::new();
        if !closed {
            let (mut k, mut node) = (0, start);
            while let Some(j) = other(k, node).filter(|&j| !used[j]) {
                used[j] = true;
                let (next, mid) = oriented(j, node);
                backward.extend(mid);
                backward.push(next);
                (k, node) = (j, next);
            }
        }
        if let Some(j) = used.iter().position(|u| !u) {
            let pieces = {
                // Count the connected pieces for the message.
                let mut seen = used.clone();
                let mut count = 1;
                while let Some(s) = seen.iter().position(|u| !u) {
                    count += 1;
                    let mut stack = vec![s];
                    seen[s] = true;
                    while let Some(i) = stack.pop() {
                        for n in &elements[i].nodes[..2] {
                            for &m in &at[n] {
                                if !seen[m] {
                                    seen[m] = true;
                                    stack.push(m);
                                }
                            }
                        }
                    }
                }
                count
            };
            return Err(not_a_chain(
                elements[j].line,
                format!(
                    "its line elements form {pieces} separate pieces, not one open chain or closed loop"
                ),
            ));
        }
        backward.reverse();
        backward.extend(forward);
        Ok(backward.into_iter().map(|n| self.points[n]).collect())
    }

    /// The body of physical surface `name` ([`MeshBody`]): its boundary loops (the outer one,
    /// then each hole's) as a [`Domain`] whose edges are the physical curves along them, and
    /// its nodes.
    ///
    /// # Errors
    /// As [`Self::boundary`]; [`GmshErrorKind::UnnamedBoundary`], [`GmshErrorKind::SplitCurve`], and
    /// [`GmshErrorKind::Domain`] when the loop is not a valid domain.
    pub fn body(&self, name: &str) -> Result<MeshBody, GmshError> {
        let fail = |kind| GmshError { line: None, kind };
        let loops = self.boundary(name)?;
        let mut curves_of_loops = Vec::with_capacity(loops.len());
        let mut names = Vec::new();
        for boundary_loop in &loops {
            let edges = &boundary_loop.edges;
            // Runs of equally named edges (the loop starts where the names change).
            let mut runs: Vec<(Option<String>, Vec<usize>)> = Vec::new();
            for e in edges {
                let nodes = [e.middle, Some(e.b)].into_iter().flatten();
                match runs.last_mut() {
                    Some((n, list)) if *n == e.name => list.extend(nodes),
                    _ => runs.push((e.name.clone(), std::iter::once(e.a).chain(nodes).collect())),
                }
            }
            let mut curves = Vec::with_capacity(runs.len());
            for (curve, list) in &runs {
                let Some(curve) = curve else {
                    return Err(fail(GmshErrorKind::UnnamedBoundary {
                        name: name.into(),
                        from: self.node_tags[list[0]],
                        to: self.node_tags[list[list.len() - 1]],
                    }));
                };
                let count = runs.iter().filter(|(n, _)| n.as_ref() == Some(curve)).count()
                    + usize::from(names.contains(curve));
                if count > 1 {
                    return Err(fail(GmshErrorKind::SplitCurve {
                        name: name.into(),
                        curve: curve.clone(),
                        runs: count,
                    }));
                }
                let points: Vec<Point> = list.iter().map(|&i| self.points[i]).collect();
                let (a, b) = (points[0], points[points.len() - 1]);
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let len = dx.hypot(dy);
                let straight = len > 0.0
                    && points.iter().all(|p| {
                        ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() <= 1e-12 * len * len
                            && (p[0] - a[0]) * dx + (p[1] - a[1]) * dy >= -1e-12 * len * len
                            && (p[0] - b[0]) * dx + (p[1] - b[1]) * dy <= 1e-12 * len * len
                    });
                curves.push(if straight {
                    Curve::Segment { a, b }
                } else {
                    Curve::Polyline { points: Arc::from(points) }
                });
            }
            names.extend(runs.into_iter().filter_map(|(n, _)| n));
            curves_of_loops.push(curves);
        }
        let domain = Domain::from_loops(curves_of_loops, names).map_err(|e| {
            fail(GmshErrorKind::Domain { name: name.into(), reason: e.to_string() })
        })?;
        // The surface's nodes and their spacing.
        let elements = self.surface(name)?;
        let mut index = vec![usize::MAX; self.points.len()];
        let mut sums: Vec<(f64, usize)> = Vec::new();
        let mut points = Vec::new();
        let mut used: Vec<usize> = elements.iter().flat_map(|e| e.nodes.iter().copied()).collect();
        used.sort_unstable();
        used.dedup();
        for &i in &used {
            index[i] = points.len();
            points.push(self.points[i]);
            sums.push((0.0, 0));
        }
        for e in &elements {
            let c = e.kind.corners();
            let area = polygon_area(e.nodes[..c].iter().map(|&i| self.points[i])).abs();
            let side = if c == 3 { (4.0 * area / 3f64.sqrt()).sqrt() } else { area.sqrt() };
            let size = if e.kind.has_edge_nodes() { 0.5 * side } else { side };
            for &i in &e.nodes {
                let s = &mut sums[index[i]];
                s.0 += size;
                s.1 += 1;
            }
        }
        let spacing = sums.iter().map(|&(sum, n)| sum / n as f64).collect();
        let elements = elements
            .iter()
            .map(|e| Element { nodes: e.nodes.iter().map(|&i| index[i]).collect(), ..(*e).clone() })
            .collect();
        Ok(MeshBody { domain, points, spacing, elements })
    }
}

/// Signed area of the polygon through `points` (positive counter-clockwise).
fn polygon_area(points: impl Iterator<Item = Point>) -> f64 {
    let p: Vec<Point> = points.collect();
    let n = p.len();
    0.5 * (0..n).map(|k| p[k][0] * p[(k + 1) % n][1] - p[(k + 1) % n][0] * p[k][1]).sum::<f64>()
}

fn read_names(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "PhysicalNames";
    let (_, count) = lines.numbers::<usize>(S, 1, "the number of physical names")?;
    for _ in 0..count[0] {
        let (n, text) = lines.inside(S)?;
        let syntax = || {
            at(
                n,
                GmshErrorKind::Syntax { expected: "dimension tag \"name\"", found: shorten(text) },
            )
        };
        let mut words = text.splitn(3, char::is_whitespace);
        let dimension: u8 = words.next().and_then(|w| w.parse().ok()).ok_or_else(syntax)?;
        let tag: i32 = words.next().and_then(|w| w.trim().parse().ok()).ok_or_else(syntax)?;
        let name = words.next().map(str::trim).ok_or_else(syntax)?;
        let name = name.strip_prefix('"').and_then(|s| s.strip_suffix('"')).ok_or_else(syntax)?;
        raw.names.push(PhysicalName { dimension, tag, name: name.to_string() });
    }
    lines.end(S)
}

fn read_entities(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "Entities";
    let (_, counts) =
        lines.numbers::<usize>(S, 4, "the numbers of points, curves, surfaces, volumes")?;
    for (dimension, &count) in counts[..4].iter().enumerate() {
        for _ in 0..count {
            let (n, v) = lines.numbers::<f64>(S, 1, "an entity")?;
            // Points: tag x y z nPhys phys...; others: tag 6 box values nPhys phys... nBound ...
            let at_count = if dimension == 0 { 4 } else { 7 };
            let syntax = || {
                at(
                    n,
                    GmshErrorKind::Syntax {
                        expected: "an entity with its physical tags",
                        found: String::new(),
                    },
                )
            };
            let count = *v.get(at_count).ok_or_else(syntax)?;
            let tags = (count >= 0.0 && count <= v.len() as f64)
                .then(|| v.get(at_count + 1..at_count + 1 + count as usize))
                .flatten()
                .ok_or_else(syntax)?;
            if dimension <= 2 {
                raw.entity_physicals.insert(
                    (dimension as u8, v[0] as i32),
                    tags.iter().map(|&t| t as i32).collect(),
                );
            }
        }
    }
    lines.end(S)
}

fn read_nodes_v4(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "Nodes";
    let (_, header) =
        lines.numbers::<u64>(S, 4, "numEntityBlocks numNodes minNodeTag maxNodeTag")?;
    for _ in 0..header[0] {
        let (_, block) =
            lines.numbers::<u64>(S, 4, "entityDim entityTag parametric numNodesInBlock")?;
        let count = block[3];
        // The count comes from the file: reserve no more than a modest amount up front.
        let mut tags = Vec::with_capacity(count.min(1 << 16) as usize);
        for _ in 0..count {
            tags.push(lines.numbers::<u64>(S, 1, "a node tag")?.1[0]);
        }
        for tag in tags {
            let (n, xyz) = lines.numbers::<f64>(S, 3, "x y z")?;
            raw.add_node(n, tag, &xyz)?;
        }
    }
    lines.end(S)
}

fn read_nodes_v2(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "Nodes";
    let (_, count) = lines.numbers::<usize>(S, 1, "the number of nodes")?;
    for _ in 0..count[0] {
        let (n, text) = lines.inside(S)?;
        let v: Vec<&str> = text.split_whitespace().collect();
        let parsed = (v.len() >= 4)
            .then(|| {
                Some((
                    v[0].parse::<u64>().ok()?,
                    [v[1].parse().ok()?, v[2].parse().ok()?, v[3].parse().ok()?],
                ))
            })
            .flatten();
        let (tag, xyz): (u64, [f64; 3]) = parsed.ok_or_else(|| {
            at(n, GmshErrorKind::Syntax { expected: "tag x y z", found: shorten(text) })
        })?;
        raw.add_node(n, tag, &xyz)?;
    }
    lines.end(S)
}

fn read_elements_v4(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "Elements";
    let (_, header) = lines.numbers::<u64>(S, 4, "numEntityBlocks numElements minTag maxTag")?;
    for _ in 0..header[0] {
        let (n, block) =
            lines.numbers::<i64>(S, 4, "entityDim entityTag elementType numElementsInBlock")?;
        let kind = ElementKind::from_gmsh(u32::try_from(block[2]).unwrap_or(u32::MAX))
            .map_err(|k| at(n, k))?;
        let physical = raw
            .entity_physicals
            .get(&(block[0] as u8, block[1] as i32))
            .cloned()
            .unwrap_or_default();
        for _ in 0..block[3] {
            let (n, v) =
                lines.numbers::<u64>(S, 1 + kind.node_count(), "an element tag and its nodes")?;
            if v.len() != 1 + kind.node_count() {
                return Err(at(
                    n,
                    GmshErrorKind::Syntax {
                        expected: "an element tag and its nodes",
                        found: format!("{} numbers", v.len()),
                    },
                ));
            }
            raw.elements.push((kind, v[1..].to_vec(), physical.clone(), n));
        }
    }
    lines.end(S)
}

fn read_elements_v2(lines: &mut Lines<'_>, raw: &mut Raw) -> Result<(), GmshError> {
    const S: &str = "Elements";
    let (_, count) = lines.numbers::<usize>(S, 1, "the number of elements")?;
    for _ in 0..count[0] {
        let (n, v) = lines.numbers::<i64>(S, 3, "tag type numTags tags... nodes...")?;
        let kind = ElementKind::from_gmsh(u32::try_from(v[1]).unwrap_or(u32::MAX))
            .map_err(|k| at(n, k))?;
        let tags = usize::try_from(v[2]).unwrap_or(usize::MAX);
        if tags.checked_add(3 + kind.node_count()) != Some(v.len()) {
            return Err(at(
                n,
                GmshErrorKind::Syntax {
                    expected: "tag type numTags tags... nodes...",
                    found: format!(
                        "{} numbers for {} tags and {} nodes",
                        v.len(),
                        tags,
                        kind.node_count()
                    ),
                },
            ));
        }
        // The first tag is the physical group (0: none), the second the elementary entity.
        let physical = v
            .get(3)
            .filter(|_| tags >= 1)
            .filter(|&&t| t != 0)
            .map(|&t| vec![t as i32])
            .unwrap_or_default();
        let nodes = v[3 + tags..].iter().map(|&t| t as u64).collect();
        raw.elements.push((kind, nodes, physical, n));
    }
    lines.end(S)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square as two triangles, physical surface "plate", edges "bottom" and "left".
    const SQUARE_V2: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"bottom\"\n1 2 \"left\"\n2 3 \"plate\"\n$EndPhysicalNames\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n4\n1 1 2 1 1 1 2\n2 1 2 2 4 4 1\n3 2 2 3 1 1 2 3\n4 2 2 3 1 3 4 1\n$EndElements\n";

    /// The same square in MSH 4.1, the second triangle clockwise.
    const SQUARE_V4: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"bottom\"\n1 2 \"left\"\n2 3 \"plate\"\n$EndPhysicalNames\n$Entities\n0 2 1 0\n1 0 0 0 1 0 0 1 1 2 1 -2\n4 0 0 0 0 1 0 1 2 2 4 -1\n1 0 0 0 1 1 0 1 3 0\n$EndEntities\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n$Elements\n3 4 1 4\n1 1 1 1\n1 1 2\n1 4 1 1\n2 4 1\n2 1 2 2\n3 1 2 3\n4 1 4 3\n$EndElements\n";

    /// [`SQUARE_V2`] with its right and top sides on physical curves too (`right_tag` 4 names
    /// "right"; 2 makes it a second piece of "left").
    fn named_square(right_tag: u32) -> Mesh {
        let text = SQUARE_V2
            .replace("3\n1 1 \"bottom\"", "5\n1 4 \"right\"\n1 5 \"top\"\n1 1 \"bottom\"")
            .replace(
                "4\n1 1 2 1 1 1 2\n",
                &format!("6\n1 1 2 1 1 1 2\n5 1 2 {right_tag} 2 2 3\n6 1 2 5 3 3 4\n"),
            );
        Mesh::parse(text.as_bytes()).unwrap()
    }

    #[test]
    fn bodies_take_one_edge_per_physical_curve() {
        let body = named_square(4).body("plate").unwrap();
        let d = &body.domain;
        assert_eq!(d.edge_names(), ["bottom", "right", "top", "left"]);
        assert!(d.is_polygon(), "straight runs are segments");
        assert_eq!(d.as_rectangle(), Some(([0.0, 1.0], [0.0, 1.0])));
        assert_eq!(body.points.len(), 4);
        // Two right triangles of area 1/2: the equilateral triangle of that area.
        let side = (2.0 / 3f64.sqrt()).sqrt();
        assert!(body.spacing.iter().all(|&h| (h - side).abs() < 1e-15), "{:?}", body.spacing);
        // Unnamed boundary pieces, a curve in two pieces, a missing surface.
        let kind = |m: &Mesh| m.body("plate").unwrap_err().kind;
        let square = Mesh::parse(SQUARE_V2.as_bytes()).unwrap();
        assert!(
            matches!(kind(&square), GmshErrorKind::UnnamedBoundary { from: 2, to: 4, .. }),
            "{:?}",
            kind(&square)
        );
        assert!(matches!(kind(&named_square(2)), GmshErrorKind::SplitCurve { runs: 2, .. }));
        assert!(matches!(square.body("disk").unwrap_err().kind, GmshErrorKind::NoSurface { .. }));
        assert_eq!(square.surface_names(), ["plate"]);
    }

    fn err(text: &str) -> GmshError {
        Mesh::parse(text.as_bytes()).unwrap_err()
    }

    #[test]
    fn both_versions_read_the_same_square() {
        for (text, version) in [(SQUARE_V2, MshVersion::V2), (SQUARE_V4, MshVersion::V4)] {
            let mesh = Mesh::parse(text.as_bytes()).unwrap();
            assert_eq!(mesh.version, version);
            assert_eq!(mesh.points, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
            assert_eq!(mesh.surface("plate").unwrap().len(), 2);
            let loops = mesh.boundary("plate").unwrap();
            assert_eq!(loops.len(), 1);
            let l = &loops[0];
            assert!((l.signed_area - 1.0).abs() < 1e-15);
            let walk: Vec<(usize, usize, Option<&str>)> =
                l.edges.iter().map(|e| (e.a, e.b, e.name.as_deref())).collect();
            // Counter-clockwise from node 0 (where "bottom" starts after "left").
            assert_eq!(
                walk,
                vec![(0, 1, Some("bottom")), (1, 2, None), (2, 3, None), (3, 0, Some("left"))],
                "{version:?}"
            );
        }
    }

    #[test]
    fn bad_files_name_the_line() {
        let e = err("hello\n");
        assert_eq!((e.line, e.kind), (Some(1), GmshErrorKind::NotMsh));
        let e = err(&SQUARE_V2.replace("2.2 0 8", "2.2 1 8"));
        assert_eq!((e.line, e.kind), (Some(2), GmshErrorKind::Binary));
        let e = err(&SQUARE_V2.replace("2.2 0 8", "3.0 0 8"));
        assert_eq!(e.kind, GmshErrorKind::Version { found: "3.0".into() });
        // Truncated inside $Elements.
        let cut = &SQUARE_V2[..SQUARE_V2.find("4 2 2 3 1").unwrap()];
        let e = err(cut);
        assert_eq!(e.kind, GmshErrorKind::Truncated { section: "Elements" });
        // A tetrahedron.
        let e = err(&SQUARE_V2.replace("4 2 2 3 1 3 4 1", "4 4 2 3 1 1 2 3 4"));
        assert_eq!((e.line, e.kind), (Some(22), GmshErrorKind::SolidElement { element_type: 4 }));
        // An unknown node.
        let e = err(&SQUARE_V2.replace("4 2 2 3 1 3 4 1", "4 2 2 3 1 3 9 1"));
        assert_eq!((e.line, e.kind), (Some(22), GmshErrorKind::UnknownNode { tag: 9 }));
        // No physical groups (v2: physical tag 0 everywhere).
        let none = SQUARE_V2
            .replace("1 1 2 1 1 1 2", "1 1 2 0 1 1 2")
            .replace("2 1 2 2 4 4 1", "2 1 2 0 4 4 1")
            .replace("3 2 2 3 1 1 2 3", "3 2 2 0 1 1 2 3")
            .replace("4 2 2 3 1 3 4 1", "4 2 2 0 1 3 4 1");
        assert_eq!(err(&none).kind, GmshErrorKind::NoPhysicalGroups);
        // Off the plane.
        let e = err(&SQUARE_V2.replace("3 1 1 0", "3 1 1 0.5"));
        assert_eq!(e.line, Some(14));
        assert!(matches!(e.kind, GmshErrorKind::NotPlanar { tag: 3, .. }), "{e}");
        // Not UTF-8.
        let mut bytes = SQUARE_V2.as_bytes().to_vec();
        let k = SQUARE_V2.find("$Nodes").unwrap();
        bytes[k + 1] = 0xff;
        let e = Mesh::parse(&bytes).unwrap_err();
        assert_eq!((e.line, e.kind), (Some(10), GmshErrorKind::NotUtf8));
        // A wrong number of nodes for the element type.
        let e = err(&SQUARE_V2.replace("4 2 2 3 1 3 4 1", "4 2 2 3 1 3 4"));
        assert_eq!(e.line, Some(22));
        // Display names the line.
        assert!(e.to_string().starts_with("line 22: expected"), "{e}");
    }

    #[test]
    fn missing_surface_lists_the_available_ones() {
        let mesh = Mesh::parse(SQUARE_V2.as_bytes()).unwrap();
        let e = mesh.boundary("body").unwrap_err();
        assert_eq!(
            e.kind,
            GmshErrorKind::NoSurface { name: "body".into(), available: "`plate`".into() }
        );
    }

    /// A v2 mesh of five nodes on a line and the line elements `elements` (`a b` pairs, or
    /// `a b m` for 3-node lines) on the physical curve "c" (tag 1), in that order; element `k`
    /// (from 0) is on line `18 + k` of the file.
    fn curve_mesh(elements: &[&[u64]]) -> Mesh {
        let mut text = String::from(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"c\"\n$EndPhysicalNames\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 3 0 0\n5 4 0 0\n$EndNodes\n",
        );
        text += &format!("$Elements\n{}\n", elements.len());
        for (k, e) in elements.iter().enumerate() {
            let kind = if e.len() == 3 { 8 } else { 1 };
            let nodes: Vec<String> = e.iter().map(|n| n.to_string()).collect();
            text += &format!("{} {kind} 2 1 1 {}\n", k + 1, nodes.join(" "));
        }
        text += "$EndElements\n";
        Mesh::parse(text.as_bytes()).unwrap()
    }

    #[test]
    fn curves_chain_in_the_direction_of_their_first_element() {
        let xs = |m: &Mesh| m.curve_points("c").unwrap().iter().map(|p| p[0]).collect::<Vec<_>>();
        // In order, shuffled, and with elements pointing both ways: the first element decides.
        assert_eq!(xs(&curve_mesh(&[&[1, 2], &[2, 3], &[3, 4]])), [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(xs(&curve_mesh(&[&[3, 4], &[1, 2], &[2, 3]])), [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(xs(&curve_mesh(&[&[3, 2], &[3, 4], &[1, 2]])), [3.0, 2.0, 1.0, 0.0]);
        // A 3-node line's middle node between its ends.
        assert_eq!(xs(&curve_mesh(&[&[3, 5, 4], &[1, 3, 2]])), [0.0, 1.0, 2.0, 3.0, 4.0]);
        // A closed loop ends where it starts (a triangle 1-2-3, walked from element 1).
        let m = curve_mesh(&[&[2, 3], &[3, 1], &[1, 2]]);
        assert_eq!(xs(&m), [1.0, 2.0, 0.0, 1.0]);
    }

    #[test]
    fn curves_that_are_not_one_chain_are_refused_with_the_line() {
        let fail = |elements: &[&[u64]]| curve_mesh(elements).curve_points("c").unwrap_err();
        let e = fail(&[&[1, 2], &[2, 3], &[2, 4]]);
        assert_eq!(e.line, Some(20));
        assert!(e.to_string().contains("branches at node 2"), "{e}");
        let e = fail(&[&[1, 2], &[3, 4], &[4, 5]]);
        assert_eq!(e.line, Some(19));
        assert!(e.to_string().contains("2 separate pieces"), "{e}");
        let e = fail(&[&[1, 2], &[3, 3]]);
        assert_eq!(e.line, Some(19));
        assert!(e.to_string().contains("joins node 3 to itself"), "{e}");
        let e = curve_mesh(&[&[1, 2]]).curve_points("d").unwrap_err();
        assert!(e.to_string().contains("no physical curve named `d`"), "{e}");
        assert!(e.to_string().contains("`c`"), "{e}");
    }
}
