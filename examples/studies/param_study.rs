//! Parameter study, the one that justified the defaults: how accuracy depends on the support
//! factor `α_s`, the MLS basis, the cell type and the number of Gauss points per cell-boundary
//! segment, one parameter at a time around the defaults (linear basis, `α_s = 2`, 2 points,
//! `β = 0`, structured nodes), on
//!
//! - the cantilever (`problems/cantilever.toml`, with the exact end conditions of the closed
//!   form in `tests/validation/end_shear_exact.rs`): relative L2 and energy-norm errors at
//!   three spacings and the observed rates;
//! - the beam on a rigid foundation (`problems/beam_on_foundation.toml`): total contact force
//!   `F_c`, contact onset `l_c` and tip deflection `u_y(48, 0)` at three spacings, against the
//!   built-in Q2 finite elements (`method = "fem"`) at finer spacings; whether the run-time
//!   checks of `M` pass and whether the contact zone is one interval reaching the tip.
//!
//! The FE reference is computed at h = 0.25 and 0.125 on every run; its finest row (h = 0.0625,
//! 593k DOFs, minutes and ~6 GB) is read from `docs/data/param_study_fe_reference.csv` when the
//! cache's coarser rows agree with the fresh ones to 1e-9, and computed and cached otherwise
//! (or when `--fe-fine` is given).
//!
//! Every variant runs with `allow_unstable` (and `contact.allow_indefinite`), so the
//! combinations the program refuses by default are run and shown with their flags, not
//! hidden. Writes the Markdown tables to stdout and the charts to `target/param_study/`
//! (SVG and PNG); the full run also copies the SVGs to `docs/img/`. Results and conclusions:
//! `docs/param_study.md`.
//!
//! ```text
//! cargo run --release --features studies --example param_study [-- --fe-fine]   # full run
//! cargo run --release --features studies --example param_study -- --quick       # a check that it runs
//! ```
//!
//! `--quick`: coarser spacings, FE reference at h = 0.25, writes nothing into `docs/`;
//! `--fe-fine`: recompute the cached FE row. No parameter is tuned toward any number of the
//! paper.

mod args;
// The shared module also serves the β studies; only part of it is used here.
#[allow(dead_code)]
mod study;

#[path = "../../tests/validation/end_shear_exact.rs"]
mod end_shear_exact;

use clap::{Parser, ValueEnum};
use end_shear_exact::{
    DEPTH, LENGTH, POISSON, YOUNG, energy_density, exact_displacement, exact_stress,
};
use mlpg_contact::material::PlaneState;
use mlpg_contact::mls::Basis;
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, EdgeCondition, Field, Method, Problem};
use plotters::prelude::*;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// Jittered layout of the cell-type comparison (the problem files' default amplitude and seed).
const JITTER: Layout = Layout::Jittered { amplitude: 0.25, seed: 1 };

/// One discretisation variant.
#[derive(Clone, Copy)]
struct Variant {
    /// The parameter varied ("default", "α_s", "basis", "quadrature", "cells", "β").
    group: &'static str,
    name: &'static str,
    basis: Basis,
    support_factor: f64,
    quadrature_points: usize,
    beta: f64,
    jittered: bool,
}

const fn variant(
    group: &'static str,
    name: &'static str,
    basis: Basis,
    support_factor: f64,
    quadrature_points: usize,
) -> Variant {
    Variant { group, name, basis, support_factor, quadrature_points, beta: 0.0, jittered: false }
}

const LIN: Basis = Basis::Linear;
const QUAD: Basis = Basis::Quadratic;

/// The defaults and one change at a time.
const VARIANTS: [Variant; 17] = [
    variant("default", "default (linear, α_s=2, 2 pts, β=0, rect.)", LIN, 2.0, 2),
    variant("α_s", "α_s=1.5", LIN, 1.5, 2),
    variant("α_s", "α_s=1.75", LIN, 1.75, 2),
    variant("α_s", "α_s=2.25", LIN, 2.25, 2),
    variant("α_s", "α_s=2.5", LIN, 2.5, 2),
    variant("α_s", "α_s=3", LIN, 3.0, 2),
    variant("basis", "quadratic, α_s=2.5", QUAD, 2.5, 2),
    variant("basis", "quadratic, α_s=3", QUAD, 3.0, 2),
    variant("basis", "quadratic, α_s=3.5", QUAD, 3.5, 2),
    variant("quadrature", "1 pt", LIN, 2.0, 1),
    variant("quadrature", "3 pts", LIN, 2.0, 3),
    variant("quadrature", "4 pts", LIN, 2.0, 4),
    Variant { jittered: true, ..variant("cells", "Voronoi (jittered)", LIN, 2.0, 2) },
    Variant { jittered: true, ..variant("cells", "Voronoi (jittered), 3 pts", LIN, 2.0, 3) },
    Variant { jittered: true, ..variant("cells", "Voronoi (jittered), α_s=1.5", LIN, 1.5, 2) },
    Variant { beta: 0.5, ..variant("β", "β=0.5, α_s=3", LIN, 3.0, 2) },
    Variant { beta: 0.5, ..variant("β", "β=0.5, α_s=3, quadratic", QUAD, 3.0, 2) },
];

impl Variant {
    /// `base` at spacing `h` with this variant's parameters; refusals become warnings.
    fn apply(&self, base: &Problem, h: f64) -> Problem {
        let mut p = base.clone();
        p.node_spacing = h;
        p.layout = if self.jittered { JITTER } else { Layout::Structured };
        let d = &mut p.discretisation;
        d.mls.basis = self.basis;
        d.mls.support_factor = self.support_factor;
        d.quadrature_points = self.quadrature_points;
        d.beta = self.beta;
        d.allow_unstable = true;
        if let Some(c) = p.contact_mut() {
            c.allow_indefinite = true;
        }
        p
    }
    /// Whether the program refuses this combination by default (`allow_unstable` needed).
    fn refused(&self, base: &Problem) -> bool {
        let mut p = self.apply(base, base.node_spacing);
        p.discretisation.allow_unstable = false;
        p.discretisation.stability_warning().is_some()
    }
}

/// Spacings of the full and the quick run.
struct Plan {
    quick: bool,
    /// Recompute the finest FE reference instead of reading the cache.
    fe_fine: bool,
    /// Spacings, coarse to fine (rates: the last pair and a fit over the finest three).
    cantilever: Vec<f64>,
    beam: Vec<f64>,
    /// FE spacings computed on every run.
    fem: Vec<f64>,
    /// The finer FE spacing read from the cache (full run only).
    fem_cached: Option<f64>,
}

/// Parameter study on the cantilever and the beam on a rigid foundation: support factor, MLS
/// basis, cell type, Gauss points and β, one at a time around the defaults.
#[derive(Parser)]
struct Cli {
    /// Coarser spacings and the FE reference at h = 0.5 and 0.25 only: a check that the study
    /// runs (20–40 s); writes nothing into docs/
    #[arg(long)]
    quick: bool,
    /// Recompute the finest FE reference row (h = 0.0625; minutes and ~6 GB) instead of
    /// reading it from docs/data/ (full run only)
    #[arg(long)]
    fe_fine: bool,
    /// The flags written as words (`quick`, `fe-fine`), as docs/param_study.md gives them.
    #[arg(value_enum, hide = true)]
    words: Vec<Word>,
}

/// `--quick` and `--fe-fine` written without the dashes.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Word {
    Quick,
    FeFine,
}

impl Plan {
    fn parse() -> Self {
        let cli: Cli = args::parse(&[]);
        let quick = cli.quick || cli.words.contains(&Word::Quick);
        let fe_fine = cli.fe_fine || cli.words.contains(&Word::FeFine);
        if quick {
            Self {
                quick: true,
                fe_fine: false,
                cantilever: vec![2.0, 1.0, 0.5],
                beam: vec![1.0, 0.5, 0.25],
                fem: vec![0.5, 0.25],
                fem_cached: None,
            }
        } else {
            Self {
                quick: false,
                fe_fine,
                cantilever: vec![2.0, 1.0, 0.5, 0.25],
                beam: vec![1.0, 0.5, 0.25, 0.125],
                fem: vec![0.25, 0.125],
                fem_cached: Some(0.0625),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Cantilever

struct CantileverRow {
    nodes: usize,
    nonzeros: usize,
    /// `(Σ A_i |u^h_i − u_i|² / Σ A_i |u_i|²)^{1/2}` (cell areas as weights).
    l2: f64,
    /// `max_i |u^h_i − u_i| / max_i |u_y,i|` (as in tests/validation/cantilever_end_shear.rs).
    max: f64,
    /// `(Σ A_i δσ·D⁻¹δσ / Σ A_i σ·D⁻¹σ)^{1/2}` with nodal stresses.
    energy: f64,
    seconds: f64,
}

/// `problems/cantilever.toml` with the closed form's end conditions: its displacement on the
/// left edge, its (parabolic) traction on the right edge; top and bottom free as in the file.
fn cantilever_base() -> Problem {
    let mut p = study::load("cantilever.toml");
    let (lo, hi) = p.domain.bounding_box();
    assert!(
        lo == [0.0, -DEPTH / 2.0]
            && hi == [LENGTH, DEPTH / 2.0]
            && p.material.young == YOUNG
            && p.material.poisson == POISSON
            && p.material.plane == PlaneState::Stress,
        "problems/cantilever.toml no longer matches the closed form's data"
    );
    let component = |f: fn([f64; 2]) -> f64| Field::Function(Arc::new(f));
    let left = p.domain.edge_index("left").expect("edge left");
    let right = p.domain.edge_index("right").expect("edge right");
    p.boundary[left] = EdgeCondition::Components([
        ComponentCondition::Displacement(component(|q| exact_displacement(q)[0])),
        ComponentCondition::Displacement(component(|q| exact_displacement(q)[1])),
    ]);
    // Outward normal (1, 0): t = (σ_xx, τ_xy).
    p.boundary[right] = EdgeCondition::Components([
        ComponentCondition::Traction(component(|q| exact_stress(q)[0])),
        ComponentCondition::Traction(component(|q| exact_stress(q)[2])),
    ]);
    p
}

fn cantilever(base: &Problem, v: &Variant, h: f64) -> Result<CantileverRow, String> {
    let p = v.apply(base, h);
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&p, &mut silent).map_err(|e| e.to_string())?;
    let nonzeros = model.system.matrix.values.len();
    let (model, _, s) =
        mlpg_contact::solve_model(&p, model, None, &mut silent).map_err(|e| e.to_string())?;
    let seconds = t0.elapsed().as_secs_f64();
    let (mut du, mut uu, mut de, mut ee, mut max_err, mut max_u) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, &x) in model.nodes.points.iter().enumerate() {
        let area = model.mfvm().expect("an MFVM model").cells[i].area();
        let (ue, u) = (exact_displacement(x), s.displacement[i]);
        let e = (u[0] - ue[0]).hypot(u[1] - ue[1]);
        du += area * e * e;
        uu += area * (ue[0] * ue[0] + ue[1] * ue[1]);
        max_err = f64::max(max_err, e);
        max_u = f64::max(max_u, ue[1].abs());
        let se = exact_stress(x);
        let ds = [s.stress[i][0] - se[0], s.stress[i][1] - se[1], s.stress[i][2] - se[2]];
        de += area * energy_density(ds);
        ee += area * energy_density(se);
    }
    Ok(CantileverRow {
        nodes: model.nodes.len(),
        nonzeros,
        l2: (du / uu).sqrt(),
        max: max_err / max_u,
        energy: (de / ee).sqrt(),
        seconds,
    })
}

// ---------------------------------------------------------------------------------------------
// Beam on a rigid foundation

struct BeamRow {
    nodes: usize,
    nonzeros: usize,
    force: f64,
    /// Reported `l_c`: `gap^(2/3)` estimate clipped to [last open, first closed].
    onset: f64,
    /// The same estimate unclipped (the FE reference's `l_c`).
    onset_raw: f64,
    last_open: f64,
    first_closed: f64,
    tip: f64,
    intervals: usize,
    /// The tip candidate is closed (contact zone reaches the free end).
    tip_closed: bool,
    /// Smallest diagonal entry of `M`.
    min_diagonal: f64,
    /// Smallest eigenvalue of `(M + Mᵀ)/2` over the largest.
    min_eigenvalue_ratio: f64,
    /// The program's own run-time checks of `M` passed (no warning).
    m_ok: bool,
    /// MLS (nodes and faces) plus assembly [s]: what the basis, support and quadrature cost
    /// before the factorisation.
    assembly_seconds: f64,
    seconds: f64,
}

impl BeamRow {
    /// `M` checks passed and one closed interval reaching the tip: contact is intact.
    fn intact(&self) -> bool {
        self.m_ok && self.intervals == 1 && self.tip_closed
    }
}

fn beam(p: &Problem) -> Result<BeamRow, String> {
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(p, &mut silent).map_err(|e| e.to_string())?;
    let nonzeros = model.system.matrix.values.len();
    let (model, _, s) =
        mlpg_contact::solve_model(p, model, None, &mut silent).map_err(|e| e.to_string())?;
    let seconds = t0.elapsed().as_secs_f64();
    let c = s.contact().ok_or("no contact solution")?;
    let (lo, hi) = p.domain.bounding_box();
    let tip_point = [hi[0], 0.5 * (lo[1] + hi[1])];
    let tip = model
        .nodes
        .points
        .iter()
        .position(|q| (q[0] - tip_point[0]).abs() < 1e-9 && (q[1] - tip_point[1]).abs() < 1e-9)
        .map_or(f64::NAN, |i| s.displacement[i][1]);
    let m = c.condensed.as_ref().unwrap();
    Ok(BeamRow {
        nodes: model.nodes.len(),
        nonzeros,
        force: c.total_force,
        onset: c.onset.from_gap.unwrap_or(f64::NAN),
        onset_raw: c.onset.from_gap_raw.unwrap_or(f64::NAN),
        last_open: c.onset.last_open.unwrap_or(f64::NAN),
        first_closed: c.onset.first_closed.unwrap_or(f64::NAN),
        tip,
        intervals: c.onset.closed_intervals,
        tip_closed: c.closed.last().copied().unwrap_or(false),
        min_diagonal: m.min_diagonal,
        min_eigenvalue_ratio: m.min_symmetric_eigenvalue / m.max_symmetric_eigenvalue,
        m_ok: c.warning.is_none(),
        assembly_seconds: {
            let t = study::stage_times(&s, seconds);
            t[0] + t[1]
        },
        seconds,
    })
}

/// The FE reference: the finest FE values and their change from the next coarser spacing.
struct Reference {
    force: f64,
    onset: f64,
    tip: f64,
    force_uncertainty: f64,
    onset_uncertainty: f64,
    tip_uncertainty: f64,
}

/// The FE rows kept in the cache: `h, nodes, F_c, l_c (raw), l_c (clipped), u_y(48, 0), M ok,
/// intervals, seconds`.
const FE_CACHE: &str = "docs/data/param_study_fe_reference.csv";

fn fe_run(base: &Problem, h: f64) -> BeamRow {
    let mut p = base.clone();
    p.node_spacing = h;
    p.discretisation.method = Method::Fem;
    beam(&p).unwrap_or_else(|e| panic!("FE reference at h = {h}: {e}"))
}

fn fe_line(h: f64, r: &BeamRow) -> String {
    format!(
        "{h},{},{:.12},{:.10},{:.10},{:.12e},{},{},{:.1}",
        r.nodes, r.force, r.onset_raw, r.onset, r.tip, r.m_ok, r.intervals, r.seconds
    )
}

fn parse_fe_line(line: &str) -> Option<(f64, BeamRow)> {
    let f: Vec<&str> = line.split(',').collect();
    let num = |k: usize| f.get(k)?.trim().parse::<f64>().ok();
    Some((
        num(0)?,
        BeamRow {
            nodes: num(1)? as usize,
            nonzeros: 0,
            force: num(2)?,
            onset_raw: num(3)?,
            onset: num(4)?,
            last_open: f64::NAN,
            first_closed: f64::NAN,
            tip: num(5)?,
            intervals: num(7)? as usize,
            tip_closed: true,
            min_diagonal: f64::NAN,
            min_eigenvalue_ratio: f64::NAN,
            m_ok: f.get(6)?.trim() == "true",
            assembly_seconds: f64::NAN,
            seconds: num(8)?,
        },
    ))
}

/// The cached FE rows, if the cache exists and its rows at the spacings computed in this run
/// agree with them to 1e-9 (relative): the check that the cache still belongs to this code.
fn read_fe_cache(path: &Path, fresh: &[(f64, BeamRow)]) -> Result<Vec<(f64, BeamRow)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rows: Vec<(f64, BeamRow)> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('h'))
        .filter_map(parse_fe_line)
        .collect();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
    for (h, r) in fresh {
        let (_, c) = rows
            .iter()
            .find(|(hc, _)| hc == h)
            .ok_or_else(|| format!("the cache has no row at h = {h}"))?;
        if !(close(r.force, c.force) && close(r.onset_raw, c.onset_raw) && close(r.tip, c.tip)) {
            return Err(format!(
                "stale: at h = {h} the cache has F_c = {:.12}, this code {:.12}",
                c.force, r.force
            ));
        }
    }
    Ok(rows)
}

fn write_fe_cache(path: &Path, rows: &[(f64, BeamRow)]) {
    let commit = std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or("unknown".into(), |s| s.trim().to_string());
    let mut text = format!(
        "# Q2 FE reference of examples/studies/param_study.rs: problems/beam_on_foundation.toml with\n\
         # method = \"fem\" (element size h); u_y at (48, 0); seconds: wall time of that run.\n\
         # Written by `cargo run --release --features studies --example param_study` (full run, cache missing or\n\
         # stale, or `-- --fe-fine`) at commit {commit} plus uncommitted changes, if any. Every\n\
         # full run recomputes the coarser rows and ignores this file unless they agree to 1e-9.\n\
         h,nodes,force,onset_raw,onset,tip,m_ok,intervals,seconds\n"
    );
    for (h, r) in rows {
        text.push_str(&fe_line(*h, r));
        text.push('\n');
    }
    std::fs::create_dir_all(path.parent().expect("directory")).expect("cache directory");
    std::fs::write(path, text).expect("write the FE cache");
}

fn fe_reference(base: &Problem, plan: &Plan) -> Reference {
    let mut rows: Vec<(f64, BeamRow)> = plan.fem.iter().map(|&h| (h, fe_run(base, h))).collect();
    let mut note = String::from("all rows computed in this run");
    if let Some(fine) = plan.fem_cached {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(FE_CACHE);
        let cached =
            if plan.fe_fine { Err("--fe-fine given".into()) } else { read_fe_cache(&path, &rows) };
        match cached.ok().and_then(|c| c.into_iter().find(|(h, _)| *h == fine)) {
            Some(row) => {
                note = format!(
                    "h = {fine} read from `{FE_CACHE}` (its coarser rows agree with this run to 1e-9); the rest computed in this run"
                );
                rows.push(row);
            }
            None => {
                eprintln!("computing the FE reference at h = {fine} (minutes; cached afterwards)");
                rows.push((fine, fe_run(base, fine)));
                write_fe_cache(&path, &rows);
                note = format!("all rows computed in this run; written to `{FE_CACHE}`");
            }
        }
    }
    println!("## Reference: Q2 finite elements (`method = \"fem\"`, element size h)\n");
    println!("({note}.)\n");
    println!(
        "| h | nodes | F_c | l_c (gap, unclipped) | l_c (clipped) | u_y(48, 0) | M checks | intervals | time [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (h, r) in &rows {
        println!(
            "| {h} | {} | {:.6} | {:.4} | {:.4} | {:.9e} | {} | {} | {:.1} |",
            r.nodes,
            r.force,
            r.onset_raw,
            r.onset,
            r.tip,
            if r.m_ok { "pass" } else { "FAIL" },
            r.intervals,
            r.seconds
        );
    }
    let (a, b) = (&rows[rows.len() - 2].1, &rows[rows.len() - 1].1);
    let reference = Reference {
        force: b.force,
        onset: b.onset_raw,
        tip: b.tip,
        force_uncertainty: (b.force - a.force).abs(),
        onset_uncertainty: (b.onset_raw - a.onset_raw).abs(),
        tip_uncertainty: (b.tip - a.tip).abs(),
    };
    println!(
        "\nReference (finest FE; uncertainty = change from the next coarser FE): F_c = {:.6} ± {:.1e}, l_c = {:.4} ± {:.1e}, u_y(48, 0) = {:.9e} ± {:.1e}\n",
        reference.force,
        reference.force_uncertainty,
        reference.onset,
        reference.onset_uncertainty,
        reference.tip,
        reference.tip_uncertainty
    );
    reference
}

// ---------------------------------------------------------------------------------------------
// Tables

/// Slope of `log e` against `log h` between the last two spacings.
fn last_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len();
    (e[n - 2] / e[n - 1]).ln() / (h[n - 2] / h[n - 1]).ln()
}

/// Least-squares slope of `log e` against `log h` over the finest three spacings.
fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let from = h.len().saturating_sub(3);
    let pts: Vec<(f64, f64)> = h[from..]
        .iter()
        .zip(&e[from..])
        .filter(|(_, e)| e.is_finite() && **e > 0.0)
        .map(|(h, e)| (h.ln(), e.ln()))
        .collect();
    if pts.len() < 3 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

fn fixed(v: f64) -> String {
    if v.is_finite() { format!("{v:.2}") } else { "—".into() }
}

fn sci(v: f64) -> String {
    if v.is_finite() { format!("{v:.2e}") } else { "—".into() }
}

fn flags(refused: bool) -> &'static str {
    if refused { "refused by default" } else { "" }
}

type CantileverResults = Vec<Vec<Result<CantileverRow, String>>>;
type BeamResults = Vec<Vec<Result<BeamRow, String>>>;

fn cantilever_errors(
    rows: &[Result<CantileverRow, String>],
    f: fn(&CantileverRow) -> f64,
) -> Vec<f64> {
    rows.iter().map(|r| r.as_ref().map_or(f64::NAN, f)).collect()
}

fn per_row(r: &BeamRow) -> f64 {
    r.nonzeros as f64 / (2 * r.nodes) as f64
}

fn print_summary(
    plan: &Plan,
    refused: &[bool],
    reference: &Reference,
    cantilever: &CantileverResults,
    beam: &BeamResults,
) {
    let (hc, hb) = (&plan.cantilever, &plan.beam);
    let (hc_min, hb_min) = (hc[hc.len() - 1], hb[hb.len() - 1]);
    println!("## Summary\n");
    println!(
        "Cantilever errors at h = {hc_min} and the fitted rate over the finest three spacings; beam errors against the FE reference (F_c ± {:.1e}, l_c ± {:.1e}) at h = {}; `intact`: the `M` checks pass and the contact zone is one interval reaching the tip at every spacing.\n",
        reference.force_uncertainty,
        reference.onset_uncertainty,
        hb.iter().map(f64::to_string).collect::<Vec<_>>().join(", ")
    );
    println!(
        "| parameter | variant | flags | cantilever L2 | rate | cantilever energy | rate | beam intact | \\|F_c − ref\\| | \\|l_c − ref\\| (h = {hb_min}) | nnz/row (beam h = {hb_min}) | beam h = {hb_min}: MLS + assembly / total [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (k, v) in VARIANTS.iter().enumerate() {
        let l2 = cantilever_errors(&cantilever[k], |r| r.l2);
        let en = cantilever_errors(&cantilever[k], |r| r.energy);
        let b = &beam[k];
        let intact = b.iter().all(|r| r.as_ref().is_ok_and(BeamRow::intact));
        let forces: Vec<String> = b
            .iter()
            .map(|r| r.as_ref().map_or("failed".into(), |r| sci((r.force - reference.force).abs())))
            .collect();
        let last = b[b.len() - 1].as_ref().ok();
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            v.group,
            v.name,
            flags(refused[k]),
            sci(l2[l2.len() - 1]),
            fixed(fitted_rate(hc, &l2)),
            sci(en[en.len() - 1]),
            fixed(fitted_rate(hc, &en)),
            if intact { "yes" } else { "**no**" },
            forces.join(" / "),
            last.map_or("—".into(), |r| format!("{:.3}", (r.onset - reference.onset).abs())),
            last.map_or("—".into(), |r| format!("{:.1}", per_row(r))),
            last.map_or("—".into(), |r| format!("{:.2} / {:.2}", r.assembly_seconds, r.seconds)),
        );
    }
    println!();
}

fn print_cantilever(plan: &Plan, refused: &[bool], results: &CantileverResults) {
    let h = &plan.cantilever;
    let cols = |what: &str| h.iter().map(|h| format!(" {what} h={h} |")).collect::<String>();
    println!("## Cantilever: errors against the closed form\n");
    println!(
        "L2: `(Σ A_i |u^h_i − u_i|² / Σ A_i |u_i|²)^½` over the nodes, `A_i` the cell areas; energy: the same weighting of `δσ·D⁻¹δσ` with the nodal stresses; max-norm: `max |u^h_i − u_i| / max |u_y|` (the validation test's measure). Rates: last halving, and fitted over the finest three spacings.\n"
    );
    println!(
        "| variant | flags |{} L2 rate (last, fit) |{} energy rate (last, fit) | max-norm h={} | nodes | nnz/row | time [s] |",
        cols("L2"),
        cols("energy"),
        h[h.len() - 1]
    );
    println!(
        "|---|---|{}---|{}---|---|---|---|---|",
        "---|".repeat(h.len()),
        "---|".repeat(h.len())
    );
    for ((v, rows), &refused) in VARIANTS.iter().zip(results).zip(refused) {
        let l2 = cantilever_errors(rows, |r| r.l2);
        let en = cantilever_errors(rows, |r| r.energy);
        let max = cantilever_errors(rows, |r| r.max);
        let list = |e: &[f64]| e.iter().map(|e| format!(" {} |", sci(*e))).collect::<String>();
        let last = rows[rows.len() - 1].as_ref().ok();
        println!(
            "| {} | {} |{} {}, {} |{} {}, {} | {} | {} | {} | {} |",
            v.name,
            flags(refused),
            list(&l2),
            fixed(last_rate(h, &l2)),
            fixed(fitted_rate(h, &l2)),
            list(&en),
            fixed(last_rate(h, &en)),
            fixed(fitted_rate(h, &en)),
            sci(max[max.len() - 1]),
            last.map_or("—".into(), |r| r.nodes.to_string()),
            last.map_or("—".into(), |r| format!(
                "{:.1}",
                r.nonzeros as f64 / (2 * r.nodes) as f64
            )),
            last.map_or("—".into(), |r| format!("{:.2}", r.seconds)),
        );
        for (r, h) in rows.iter().zip(h) {
            if let Err(e) = r {
                println!("| {} | failed at h = {h}: {e} |", v.name);
            }
        }
    }
    println!();
}

fn print_beam(plan: &Plan, refused: &[bool], reference: &Reference, results: &BeamResults) {
    println!("## Beam on a rigid foundation: all runs\n");
    println!(
        "`M`: the program's run-time checks of the condensed compliance (positive diagonal, positive definite symmetric part); `λ_min/λ_max`: of `(M + Mᵀ)/2`; `zone`: number of closed intervals along the edge, `tip` when the last candidate is closed. `l_c`: the `gap^(2/3)` estimate clipped to [last open, first closed]. Every error is against the FE reference.\n"
    );
    println!(
        "| variant | h | nodes | nnz/row | M | min diag M | λ_min/λ_max | zone | F_c | F_c − ref | l_c | l_c − ref | [last open, first closed] | u_y(48,0) − ref | MLS + assembly [s] | time [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for ((v, rows), &refused) in VARIANTS.iter().zip(results).zip(refused) {
        let name = if refused { format!("{} (refused by default)", v.name) } else { v.name.into() };
        for (r, h) in rows.iter().zip(&plan.beam) {
            match r {
                Err(e) => println!("| {name} | {h} | failed: {e} |"),
                Ok(r) => println!(
                    "| {name} | {h} | {} | {:.1} | {} | {:.2e} | {:.1e} | {}{} | {:.6} | {:+.2e} | {:.4} | {:+.3} | [{}, {}] | {:+.1e} | {:.2} | {:.2} |",
                    r.nodes,
                    per_row(r),
                    if r.m_ok { "pass" } else { "**FAIL**" },
                    r.min_diagonal,
                    r.min_eigenvalue_ratio,
                    r.intervals,
                    if r.tip_closed { ", tip" } else { ", **tip open**" },
                    r.force,
                    r.force - reference.force,
                    r.onset,
                    r.onset - reference.onset,
                    r.last_open,
                    r.first_closed,
                    r.tip - reference.tip,
                    r.assembly_seconds,
                    r.seconds
                ),
            }
        }
    }
    println!();
}

// ---------------------------------------------------------------------------------------------
// Figures (SVG, drawn here so that each panel shows one parameter against the default)

const PALETTE: [RGBColor; 6] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
];

/// One curve of a panel: label, colour (`None`: the default, black dashed), points, the
/// points to mark as broken (beam contact not intact) and the abscissae of failed runs (no
/// answer at all; marked at the top of the panel).
struct Curve {
    label: String,
    colour: Option<RGBColor>,
    points: Vec<(f64, f64)>,
    broken: Vec<(f64, f64)>,
    failed: Vec<f64>,
}

struct Panel {
    title: String,
    x_label: String,
    y_label: String,
    x_log: bool,
    curves: Vec<Curve>,
    /// Vertical dashed line (e.g. a stability limit).
    marker: Option<f64>,
    /// Horizontal dashed line (the reference's own uncertainty).
    floor: Option<f64>,
    legend: Option<SeriesLabelPosition>,
}

fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if lo.is_finite() { (lo / 1.5, hi * 1.5) } else { (1e-6, 1.0) }
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    // A log-scale x is drawn as log2 on a linear axis, labelled at the halvings.
    let tx = |x: f64| if panel.x_log { x.log2() } else { x };
    let map = |ps: &[(f64, f64)]| ps.iter().map(|&(x, y)| (tx(x), y)).collect::<Vec<_>>();
    let all = || panel.curves.iter().flat_map(|c| c.points.iter().chain(&c.broken));
    let (y0, y1) = log_range(all().map(|p| p.1).chain(panel.floor));
    let (a, b) = all()
        .map(|p| p.0)
        .chain(panel.curves.iter().flat_map(|c| c.failed.iter().copied()))
        .filter(|x| x.is_finite())
        .map(tx)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let pad = if panel.x_log { 0.3 } else { 0.1 };
    let (x0, x1) = (a - pad, b + pad);
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 15))
        .margin(6)
        .x_label_area_size(34)
        .y_label_area_size(58)
        .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
        .map_err(e)?;
    let x_log = panel.x_log;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .x_labels(12)
        .x_label_formatter(&|&v| {
            if !x_log {
                format!("{v:.2}").trim_end_matches('0').trim_end_matches('.').to_string()
            } else if (v - v.round()).abs() < 1e-9 {
                format!("{}", 2f64.powf(v.round()))
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(e)?;
    let grey = RGBColor(150, 150, 150).stroke_width(1);
    if let Some(y) = panel.floor {
        chart.draw_series(DashedLineSeries::new([(x0, y), (x1, y)], 4, 4, grey)).map_err(e)?;
    }
    if let Some(x) = panel.marker {
        chart.draw_series(DashedLineSeries::new([(x, y0), (x, y1)], 4, 4, grey)).map_err(e)?;
    }
    for c in &panel.curves {
        let colour = c.colour.unwrap_or(BLACK);
        let style = colour.stroke_width(2);
        let points = map(&c.points);
        let series = if c.colour.is_some() {
            chart.draw_series(LineSeries::new(points.iter().copied(), style))
        } else {
            chart.draw_series(DashedLineSeries::new(points.iter().copied(), 7, 4, style))
        };
        series.map_err(e)?.label(c.label.as_str()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
        });
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(e)?;
        let broken = map(&c.broken).into_iter().chain(c.failed.iter().map(|&x| (tx(x), y1 / 1.2)));
        chart.draw_series(broken.map(|p| Cross::new(p, 7, colour.stroke_width(3)))).map_err(e)?;
    }
    if let Some(position) = panel.legend.clone() {
        chart
            .configure_series_labels()
            .position(position)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

fn draw_grid<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    columns: usize,
    panels: &[Panel],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root.titled(title, ("sans-serif", 20)).map_err(|e| e.to_string())?;
    let rows = panels.len().div_ceil(columns);
    for (area, panel) in root.split_evenly((rows, columns)).iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_figure(path: &Path, title: &str, columns: usize, panels: &[Panel], size: (u32, u32)) {
    static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
    static REGISTER: std::sync::Once = std::sync::Once::new();
    REGISTER.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            panic!("embedded DejaVuSans.ttf failed to parse");
        }
    });
    draw_grid(SVGBackend::new(path, size).into_drawing_area(), title, columns, panels)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // A PNG beside it in target/ (for viewing; docs/ takes the SVG).
    let png = path.with_extension("png");
    draw_grid(BitMapBackend::new(&png, size).into_drawing_area(), title, columns, panels)
        .unwrap_or_else(|e| panic!("{}: {e}", png.display()));
}

/// A curve of the support-factor figure: label, error of variant `k`, whether it is a beam error.
type BySupport<'a> = (&'a str, Box<dyn Fn(usize) -> f64 + 'a>, bool);

/// The groups of the convergence figure: the parameter varied and its variants.
const GROUPS: [(&str, &[&str]); 4] = [
    ("support factor α_s (linear, β = 0)", &["α_s"]),
    ("basis", &["basis"]),
    ("quadrature points and cell type", &["quadrature", "cells"]),
    ("stabilised β = 0.5 (larger supports)", &["β"]),
];

fn write_figures(
    plan: &Plan,
    reference: &Reference,
    cantilever: &CantileverResults,
    beam: &BeamResults,
) -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/param_study");
    std::fs::create_dir_all(&dir).expect("output directory");
    let intact = |k: usize, i: usize| beam[k][i].as_ref().is_ok_and(BeamRow::intact);
    let force_error = |k: usize, i: usize| {
        beam[k][i].as_ref().map_or(f64::NAN, |r| (r.force - reference.force).abs())
    };
    let onset_error = |k: usize, i: usize| {
        beam[k][i].as_ref().map_or(f64::NAN, |r| (r.onset - reference.onset).abs())
    };
    let cant = |k: usize, i: usize, f: fn(&CantileverRow) -> f64| {
        cantilever[k][i].as_ref().map_or(f64::NAN, f)
    };
    type Quantity<'a> = (&'a str, &'a [f64], bool, Box<dyn Fn(usize, usize) -> f64 + 'a>);
    let quantities: [Quantity; 3] = [
        (
            "cantilever: energy error",
            &plan.cantilever,
            false,
            Box::new(|k, i| cant(k, i, |r| r.energy)),
        ),
        ("cantilever: L2 error", &plan.cantilever, false, Box::new(|k, i| cant(k, i, |r| r.l2))),
        ("beam: |F_c − F_ref|", &plan.beam, true, Box::new(force_error)),
    ];
    let curve = |k: usize, h: &[f64], is_beam: bool, y: &dyn Fn(usize, usize) -> f64, colour| {
        let pts: Vec<(usize, (f64, f64))> = (0..h.len())
            .map(|i| (i, (h[i], y(k, i))))
            .filter(|(_, p)| p.1.is_finite() && p.1 > 0.0)
            .collect();
        Curve {
            label: VARIANTS[k].name.into(),
            colour,
            points: pts.iter().map(|p| p.1).collect(),
            broken: pts.iter().filter(|(i, _)| is_beam && !intact(k, *i)).map(|p| p.1).collect(),
            failed: (0..h.len()).filter(|&i| !y(k, i).is_finite()).map(|i| h[i]).collect(),
        }
    };
    let mut panels = Vec::new();
    for (group_title, groups) in GROUPS {
        for (column, (q_title, h, is_beam, y)) in quantities.iter().enumerate() {
            let mut curves = vec![curve(0, h, *is_beam, y.as_ref(), None)];
            let members = VARIANTS.iter().enumerate().filter(|(_, v)| groups.contains(&v.group));
            for (c, (k, _)) in members.enumerate() {
                curves.push(curve(k, h, *is_beam, y.as_ref(), Some(PALETTE[c % PALETTE.len()])));
            }
            panels.push(Panel {
                title: format!("{q_title} — {group_title}"),
                x_label: "h".into(),
                y_label: "error".into(),
                x_log: true,
                curves,
                marker: None,
                floor: is_beam.then_some(reference.force_uncertainty),
                legend: (column == 0).then_some(SeriesLabelPosition::UpperLeft),
            });
        }
    }
    let convergence = dir.join("param_study_convergence.svg");
    draw_figure(
        &convergence,
        "Errors against node spacing, one parameter at a time (black dashed: the defaults; ×: beam contact not intact, at the top: no answer; grey: FE reference uncertainty in F_c)",
        3,
        &panels,
        (1800, 2000),
    );
    // Errors at the finest spacings against α_s, one panel per basis (β = 0, structured, 2 pts).
    let (ic, ib) = (plan.cantilever.len() - 1, plan.beam.len() - 1);
    let mut support_panels = Vec::new();
    for (basis, tag, limit) in [
        (LIN, "linear", mlpg_contact::problem::MIXED_LINEAR_MAX_SUPPORT_FACTOR),
        (QUAD, "quadratic", mlpg_contact::problem::MIXED_QUADRATIC_MAX_SUPPORT_FACTOR),
    ] {
        let members: Vec<usize> = (0..VARIANTS.len())
            .filter(|&k| {
                let v = &VARIANTS[k];
                v.basis == basis && v.beta == 0.0 && !v.jittered && v.quadrature_points == 2
            })
            .collect();
        let mut sorted = members.clone();
        sorted.sort_by(|&a, &b| VARIANTS[a].support_factor.total_cmp(&VARIANTS[b].support_factor));
        let series: [BySupport; 4] = [
            ("cantilever energy", Box::new(|k| cant(k, ic, |r| r.energy)), false),
            ("cantilever L2", Box::new(|k| cant(k, ic, |r| r.l2)), false),
            ("beam |F_c − F_ref|", Box::new(|k| force_error(k, ib)), true),
            ("beam |l_c − l_ref|", Box::new(|k| onset_error(k, ib)), true),
        ];
        let curves = series
            .iter()
            .enumerate()
            .map(|(c, (label, y, is_beam))| {
                let pts: Vec<(usize, (f64, f64))> = sorted
                    .iter()
                    .map(|&k| (k, (VARIANTS[k].support_factor, y(k))))
                    .filter(|(_, p)| p.1.is_finite() && p.1 > 0.0)
                    .collect();
                Curve {
                    label: (*label).into(),
                    colour: Some(PALETTE[c]),
                    points: pts.iter().map(|p| p.1).collect(),
                    broken: pts
                        .iter()
                        .filter(|(k, _)| *is_beam && !intact(*k, ib))
                        .map(|p| p.1)
                        .collect(),
                    failed: sorted
                        .iter()
                        .filter(|&&k| !y(k).is_finite())
                        .map(|&k| VARIANTS[k].support_factor)
                        .collect(),
                }
            })
            .collect();
        support_panels.push(Panel {
            title: format!(
                "{tag} basis (cantilever h = {}, beam h = {})",
                plan.cantilever[ic], plan.beam[ib]
            ),
            x_label: "support factor α_s".into(),
            y_label: "error".into(),
            x_log: false,
            curves,
            marker: Some(limit),
            floor: Some(reference.force_uncertainty),
            legend: Some(SeriesLabelPosition::UpperLeft),
        });
    }
    let support = dir.join("param_study_support.svg");
    draw_figure(
        &support,
        "Errors at the finest spacings against the support factor (β = 0; ×: beam contact not intact, at the top: no answer; grey: refusal limit, FE uncertainty in F_c)",
        2,
        &support_panels,
        (1500, 560),
    );
    vec![convergence, support]
}

fn main() {
    let start = Instant::now();
    let plan = Plan::parse();
    let beam_base = study::load("beam_on_foundation.toml");
    let cantilever_base = cantilever_base();
    println!(
        "# Parameter study ({} run)\n\nInputs: problems/cantilever.toml (with the closed form's end conditions), problems/beam_on_foundation.toml.\n",
        if plan.quick { "quick" } else { "full" }
    );
    println!("Load average at the start: {}.\n", load_average());
    let reference = fe_reference(&beam_base, &plan);
    let refused: Vec<bool> = VARIANTS.iter().map(|v| v.refused(&beam_base)).collect();
    let mut cantilever_results = Vec::new();
    let mut beam_results = Vec::new();
    for v in &VARIANTS {
        eprintln!("{} ({:.0} s)", v.name, start.elapsed().as_secs_f64());
        cantilever_results
            .push(plan.cantilever.iter().map(|&h| cantilever(&cantilever_base, v, h)).collect());
        beam_results.push(plan.beam.iter().map(|&h| beam(&v.apply(&beam_base, h))).collect());
    }
    print_summary(&plan, &refused, &reference, &cantilever_results, &beam_results);
    print_cantilever(&plan, &refused, &cantilever_results);
    print_beam(&plan, &refused, &reference, &beam_results);
    let figures = write_figures(&plan, &reference, &cantilever_results, &beam_results);
    println!("figures: {}", figures[0].parent().expect("directory").display());
    if !plan.quick {
        let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/img");
        for f in &figures {
            std::fs::copy(f, docs.join(f.file_name().expect("file name"))).expect("copy");
        }
        println!("copied to {}", docs.display());
    }
    println!(
        "total time: {:.0} s (load average at the end: {})",
        start.elapsed().as_secs_f64(),
        load_average()
    );
}

/// The 1-minute load average (Linux), for judging the times.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}
