//! `report.html`: one self-contained page per run (`--report`): the problem in words, the
//! result table (forces, onset, zones, the checks of `M`, residuals, equilibrium), the
//! warnings, the plots inline (SVG, no network) and the timings.

use super::{OutputError, Summary, write_text};
use crate::material::PlaneState;

use crate::problem::{
    ComponentCondition, ContactPair, ContactTarget, EdgeCondition, Field, Method, Problem,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Escapes text for HTML.
fn esc(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A number with at most 6 significant digits, trailing zeros dropped.
fn g(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        let digits =
            if v == 0.0 { 0 } else { (5 - v.abs().log10().floor() as i32).max(0) as usize };
        let text = format!("{v:.digits$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{v:.5e}")
    }
}

fn field(f: &Field) -> String {
    match f {
        Field::Constant(v) => g(*v),
        Field::Linear { start, end } => format!("{} to {} (linear)", g(*start), g(*end)),
        Field::Function(_) => "a function of position".into(),
    }
}

/// One sentence per loaded or supported edge.
fn conditions(problem: &Problem) -> Vec<String> {
    let names = problem.domain.edge_names();
    let mut out = Vec::new();
    for (k, c) in problem.boundary.iter().enumerate() {
        let edge = &names[k];
        match c {
            EdgeCondition::Pressure(p) => out.push(format!("edge `{edge}`: pressure {}", field(p))),
            EdgeCondition::Components(parts) => {
                let mut said = Vec::new();
                for (axis, part) in super::coordinate_names(problem).iter().zip(parts) {
                    match part {
                        ComponentCondition::Displacement(f) => {
                            said.push(format!("u_{axis} = {}", field(f)));
                        }
                        ComponentCondition::Traction(f) if !f.is_zero() => {
                            said.push(format!("traction t_{axis} = {}", field(f)));
                        }
                        ComponentCondition::Traction(_) => {}
                    }
                }
                if !said.is_empty() {
                    out.push(format!("edge `{edge}`: {}", said.join(", ")));
                }
            }
        }
    }
    out
}

/// The problem in words: body, material, discretisation, conditions, contact, steps.
fn in_words(problem: &Problem) -> String {
    let (lo, hi) = problem.domain.bounding_box();
    let m = &problem.material;
    let plane = match m.plane {
        PlaneState::Stress => "plane stress",
        PlaneState::Strain => "plane strain",
        PlaneState::Axisymmetric => {
            "axisymmetric (x is the radius r, y the axis z; loads per radian)"
        }
    };
    let d = &problem.discretisation;
    let method = match d.method {
        Method::Mfvm => format!(
            "the meshless mixed MLPG finite volume method ({:?} MLS basis, support factor α_s = {}, β = {})",
            d.mls.basis, d.mls.support_factor, d.beta
        ),
        Method::Fem => "9-node quadrilateral finite elements".to_string(),
    };
    let mut html = format!(
        "<p>Body <b>{}</b>: {} edges (<code>{}</code>) within [{}, {}] × [{}, {}]; E = {}, ν = {}, {plane}; node spacing h = {}, solved by {method}.</p>",
        esc(&problem.name),
        problem.domain.edge_names().len(),
        esc(&problem.domain.edge_names().join(", ")),
        g(lo[0]),
        g(hi[0]),
        g(lo[1]),
        g(hi[1]),
        g(m.young),
        g(m.poisson),
        g(problem.node_spacing),
    );
    let list = |items: Vec<String>| -> String {
        items.iter().map(|s| format!("<li>{}</li>", esc(s))).collect::<String>()
    };
    let _ = write!(html, "<ul>{}</ul>", list(conditions(problem)));
    let pairs = problem.pairs();
    let steps = (!pairs.is_empty() && !problem.steps.is_empty()).then(|| {
        let increments: usize = problem.steps.iter().map(|s| s.increments).sum();
        format!(
            " The load is applied in {} step(s), {increments} increment(s) in all.",
            problem.steps.len()
        )
    });
    if problem.is_scene_of_pairs() {
        let others: Vec<String> = problem.bodies().skip(1).map(body_in_words).collect();
        let _ = write!(html, "<p>Other bodies:</p><ul>{}</ul>", list(others));
        let each: Vec<String> = pairs
            .iter()
            .map(|pair| {
                let body = problem.body(pair.body).map_or("", |b| b.name.as_str());
                format!("body `{body}`: {}", pair_in_words(problem, pair, false))
            })
            .collect();
        let _ = write!(html, "<p>Contact pairs, solved in one LCP:</p><ul>{}</ul>", list(each));
        if let Some(steps) = steps {
            let _ = write!(html, "<p>{}</p>", steps.trim_start());
        }
    } else if let Some(pair) = pairs.first() {
        let said = capitalised(&pair_in_words(problem, pair, true));
        let _ = write!(html, "<p>{}.{}</p>", esc(&said), steps.unwrap_or_default());
    }
    html
}

/// One contact pair in words: "edge `e` may touch <target> with(out) friction", the target
/// body's material and spacing when `detailed` (a scene lists its bodies apart).
fn pair_in_words(problem: &Problem, pair: &ContactPair, detailed: bool) -> String {
    let c = &pair.spec;
    let edge = problem.body(pair.body).map_or("", |b| b.domain.edge_names()[c.edge].as_str());
    let target = match (&c.target, pair.target_body.and_then(|t| problem.body(t))) {
        (ContactTarget::Rigid(line), _) => format!(
            "a rigid straight obstacle through ({}, {}) with normal ({}, {})",
            g(line.point[0]),
            g(line.point[1]),
            g(line.normal[0]),
            g(line.normal[1])
        ),
        (ContactTarget::Obstacles, _) => {
            let each: Vec<String> = pair.obstacles.iter().map(obstacle_text).collect();
            format!("the rigid obstacle(s) {}", each.join("; "))
        }
        (ContactTarget::Body { edge: e2 }, Some(p2)) if detailed => {
            format!("edge `{}` of {}", p2.domain.edge_names()[*e2], body_in_words(p2))
        }
        (ContactTarget::Body { edge: e2 }, Some(p2)) => {
            format!("edge `{}` of body `{}`", p2.domain.edge_names()[*e2], p2.name)
        }
        (ContactTarget::Body { .. }, None) => "a second body".into(),
    };
    let friction = if c.friction > 0.0 {
        format!("with Coulomb friction μ = {}", c.friction)
    } else {
        "without friction".into()
    };
    format!("edge `{edge}` may touch {target} {friction}")
}

/// "body `name` (E = …, ν = …, node spacing …)".
fn body_in_words(p: &Problem) -> String {
    format!(
        "body `{}` (E = {}, ν = {}, node spacing {})",
        p.name,
        g(p.material.young),
        g(p.material.poisson),
        g(p.node_spacing)
    )
}

/// `text` with its first letter in upper case.
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |c| c.to_uppercase().chain(chars).collect())
}

/// Rows of the result table.
fn results(s: &Summary) -> Vec<(String, String)> {
    let mut rows = vec![
        ("nodes / degrees of freedom".into(), format!("{} / {}", s.counts.nodes, s.counts.dofs)),
        ("relative residual ‖K û − f‖/‖f‖".into(), format!("{:.2e}", s.checks.relative_residual)),
        ("global equilibrium error".into(), format!("{:.2e}", s.checks.equilibrium_error)),
        ("largest displacement |u^h|".into(), g(s.results.max_displacement)),
        ("largest von Mises stress".into(), g(s.results.max_von_mises)),
    ];
    if let Some(b) = &s.second_body {
        rows.push((
            format!(
                "second body `{}`: nodes, residual, equilibrium",
                b.name.as_deref().unwrap_or("-")
            ),
            format!("{}, {:.2e}, {:.2e}", b.nodes, b.relative_residual, b.equilibrium_error),
        ));
    }
    for b in s.bodies.iter().filter(|_| s.by_pair()) {
        rows.push((
            format!("body `{}`: nodes, residual, equilibrium", b.name.as_deref().unwrap_or("-")),
            format!("{}, {:.2e}, {:.2e}", b.nodes, b.relative_residual, b.equilibrium_error),
        ));
    }
    for (k, p) in s.pairs.iter().enumerate().filter(|_| s.by_pair()) {
        rows.push((
            format!("contact[{k}] `{}`.`{}`: total force, closed / all", p.body, p.edge),
            format!("{}, {} / {}", g(p.total_force), p.closed, p.candidates),
        ));
    }
    if let Some(c) = &s.contact {
        let opt = |v: Option<f64>| v.map_or_else(|| "–".into(), g);
        rows.push(("total contact force".into(), g(c.total_force)));
        if let Some(axial) = c.axial_force {
            // Axisymmetric: the forces above are the rings' totals (summary's units_note).
            rows.push(("axial contact force, whole circumference".into(), g(axial)));
        }
        rows.push((
            "candidates closed / all (zones)".into(),
            format!("{} / {} ({})", c.closed, c.candidates, c.closed_intervals),
        ));
        rows.push((
            "contact onset (bracket: last open, first closed)".into(),
            format!("{} ({} to {})", opt(c.onset_x), opt(c.last_open_x), opt(c.first_closed_x)),
        ));
        if let Some(t) = c.total_tangential_force {
            rows.push(("total tangential force".into(), g(t)));
        }
        let zones = |z: &Option<Vec<[f64; 2]>>| {
            z.as_ref().map(|z| {
                z.iter()
                    .map(|[a, b]| format!("[{}, {}]", g(*a), g(*b)))
                    .collect::<Vec<_>>()
                    .join(", ")
            })
        };
        if let Some(z) = zones(&c.stick_zones) {
            rows.push(("stick zones (along the tangent)".into(), z));
        }
        if let Some(z) = zones(&c.slip_zones) {
            rows.push(("slip zones (along the tangent)".into(), z));
        }
        if let Some(w) = &c.warning {
            rows.push(("contact warning".into(), w.clone()));
        }
    }
    if let Some(l) = &s.lcp {
        if let Some(d) = l.compliance_min_diagonal {
            rows.push(("M: smallest diagonal entry".into(), format!("{d:.3e}")));
        }
        if let (Some(lo), Some(hi)) =
            (l.compliance_min_symmetric_eigenvalue, l.compliance_max_symmetric_eigenvalue)
        {
            rows.push((
                "M: eigenvalues of the symmetric part".into(),
                format!("{lo:.3e} to {hi:.3e}"),
            ));
        }
        rows.push((
            "contact solver: candidates, pivots, complementarity".into(),
            format!("{}: {}, {}, {:.1e}", l.solver, l.size, l.pivots, l.max_complementarity),
        ));
    }
    rows
}

/// One body's force balance: its name and `Σ f`, `Σ R`, `Σ ν P` and the relative error.
type Balance = (String, [f64; 2], [f64; 2], [f64; 2], f64);

/// Every body's force balance, the first body first (from `summary.json`'s `bodies`).
fn balances(s: &Summary) -> Vec<Balance> {
    let body = |b: &super::summary::BodySummary| {
        let name = b.name.clone().unwrap_or_else(|| "-".into());
        (name, b.applied_force, b.reaction_force, b.contact_force, b.equilibrium_error)
    };
    s.bodies.iter().map(body).collect()
}

/// The force balance table: per body and direction the applied load, the reactions, the
/// contact force and their sum (zero in equilibrium), with the relative error.
fn balance_table(s: &Summary, problem: &Problem) -> String {
    let axes = super::coordinate_names(problem);
    let mut html = String::from("<h2>Force balance</h2>\n");
    html.push_str(if problem.material.is_axisymmetric() {
        "<p>Per body, the sums over the whole body of the applied load Σf, the support reactions ΣR and the contact forces Σν P (per radian: r is x, z is y); in equilibrium they add up to zero.</p>\n"
    } else {
        "<p>Per body, the sums over the whole body of the applied load Σf, the support reactions ΣR and the contact forces Σν P; in equilibrium they add up to zero.</p>\n"
    });
    html.push_str(
        "<table id=\"balance\">\n<tr><th>body</th><th>direction</th><th>applied Σf</th><th>reactions ΣR</th><th>contact Σν P</th><th>sum</th><th>relative error</th></tr>\n",
    );
    for (name, f, r, p, error) in balances(s) {
        for (a, axis) in axes.iter().enumerate() {
            let error = if a == 0 { format!("{error:.2e}") } else { String::new() };
            let _ = writeln!(
                html,
                "<tr><td>{}</td><td>{axis}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{:.2e}</td><td class=\"num\">{error}</td></tr>",
                esc(&name),
                g(f[a]),
                g(r[a]),
                g(p[a]),
                f[a] + r[a] + p[a]
            );
        }
    }
    html.push_str("</table>\n");
    html
}

/// The list of the run's files, each a link relative to `dir` (where `report.html` is).
fn file_links(dir: &Path, files: &[PathBuf]) -> String {
    let mut html = String::from("<h2>Files</h2>\n<ul id=\"files\">\n");
    for path in files {
        let rel = path.strip_prefix(dir).unwrap_or(path);
        let href: Vec<String> =
            rel.components().map(|c| percent_encode(&c.as_os_str().to_string_lossy())).collect();
        let _ = writeln!(
            html,
            "<li><a href=\"{}\"><code>{}</code></a></li>",
            esc(&href.join("/")),
            esc(&rel.display().to_string())
        );
    }
    html.push_str("</ul>\n");
    html
}

/// `name` with every byte but unreserved URL characters percent-encoded (RFC 3986).
fn percent_encode(name: &str) -> String {
    name.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

/// Writes `report.html` into `dir` from the run's summary and the SVG plots among `files`.
///
/// # Errors
/// [`OutputError`] if a plot cannot be read or the page cannot be written.
pub fn write_report(
    dir: &Path,
    problem: &Problem,
    summary: &Summary,
    files: &[PathBuf],
) -> Result<PathBuf, OutputError> {
    let mut html = String::new();
    let title = format!("mlpg-contact: {}", summary.problem.name);
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>\n\
         body {{ font-family: sans-serif; max-width: 1100px; margin: 2em auto; color: #222; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; }}\n\
         td, th {{ border: 1px solid #bbb; padding: 0.3em 0.8em; text-align: left; }}\n\
         td.num {{ font-family: monospace; }}\n\
         figure {{ margin: 1.5em 0; }} figure svg {{ width: 100%; height: auto; }}\n\
         .warning {{ color: #a00; }}\n</style>\n</head>\n<body>\n<h1>{}</h1>\n",
        esc(&title),
        esc(&title)
    );
    let _ = write!(
        html,
        "<p>{} {}</p>\n<h2>The problem</h2>\n{}\n",
        summary.program.name,
        summary.program.version,
        in_words(problem)
    );
    html.push_str("<h2>Results</h2>\n<table id=\"results\">\n");
    for (k, v) in results(summary) {
        let _ = writeln!(html, "<tr><th>{}</th><td class=\"num\">{}</td></tr>", esc(&k), esc(&v));
    }
    html.push_str("</table>\n");
    html.push_str(&balance_table(summary, problem));
    if !summary.warnings.is_empty() {
        html.push_str("<h2>Warnings</h2>\n<ul>\n");
        for w in &summary.warnings {
            let _ = writeln!(html, "<li class=\"warning\">{}</li>", esc(w));
        }
        html.push_str("</ul>\n");
    }
    html.push_str("<h2>Plots</h2>\n");
    for path in files.iter().filter(|p| p.extension().is_some_and(|e| e == "svg")) {
        let svg = std::fs::read_to_string(path).map_err(super::io(path))?;
        // Inline: drop the XML declaration, keep the <svg> element.
        let start = svg.find("<svg").unwrap_or(0);
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("plot");
        let rel = path.strip_prefix(dir).unwrap_or(path).display().to_string();
        let _ = writeln!(
            html,
            "<figure id=\"{}\">{}<figcaption><code>{}</code></figcaption></figure>",
            esc(name),
            &svg[start..],
            esc(&rel)
        );
    }
    html.push_str(
        "<h2>Timings</h2>\n<table id=\"timings\">\n<tr><th>stage</th><th>seconds</th></tr>\n",
    );
    for (stage, seconds) in &summary.timings {
        let _ =
            writeln!(html, "<tr><td>{}</td><td class=\"num\">{seconds:.3}</td></tr>", esc(stage));
    }
    html.push_str("</table>\n");
    html.push_str(&file_links(dir, files));
    html.push_str("</body>\n</html>\n");
    let path = dir.join("report.html");
    write_text(&path, &html)?;
    Ok(path)
}

/// One rigid obstacle in words (the report's problem statement).
fn obstacle_text(o: &crate::problem::Obstacle) -> String {
    use crate::problem::{Piece, Shape};
    let shape = match &o.shape {
        Shape::Line(l) => format!(
            "a straight line through ({}, {}) with normal ({}, {})",
            g(l.point[0]),
            g(l.point[1]),
            g(l.normal[0]),
            g(l.normal[1])
        ),
        Shape::Circle { centre, radius } => format!(
            "a disk of radius {} about ({}, {}), the body outside it",
            g(*radius),
            g(centre[0]),
            g(centre[1])
        ),
        Shape::Polyline(p) => {
            let arcs: Vec<f64> = p
                .pieces
                .iter()
                .filter_map(|q| match q {
                    Piece::Arc { radius, .. } => Some(*radius),
                    Piece::Segment { .. } => None,
                })
                .collect();
            let segments = p.pieces.len() - arcs.len();
            match arcs.first() {
                Some(r) => format!(
                    "a polyline of {segments} segments with {} corners rounded to radius {}",
                    arcs.len(),
                    g(*r)
                ),
                None => format!("a polyline of {segments} segments with sharp corners"),
            }
        }
    };
    format!("`{}`, {shape}", o.name)
}

#[cfg(test)]
mod tests {
    #[test]
    fn numbers_read_well() {
        let g = super::g;
        assert_eq!(
            [g(1.0), g(0.3), g(30000.0), g(-0.0643642), g(0.0)],
            ["1", "0.3", "30000", "-0.0643642", "0"]
        );
        assert_eq!(g(32.34714824628428), "32.3471");
        assert_eq!(g(1.5e-7), "1.50000e-7");
    }

    #[test]
    fn links_are_relative_and_encoded() {
        let dir = std::path::Path::new("/run");
        let files = [dir.join("plots/a b.svg"), dir.join("lower/contact.csv")];
        let html = super::file_links(dir, &files);
        assert!(html.contains("<a href=\"plots/a%20b.svg\"><code>plots/a b.svg</code></a>"));
        assert!(html.contains("<a href=\"lower/contact.csv\">"));
        assert!(!html.contains("/run"), "{html}");
    }
}
