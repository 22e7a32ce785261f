//! The result block the command line prints after its stage list, read from the run's
//! summary (the numbers of `summary.json`, formatted for a terminal).

use super::summary::{
    AdaptiveSummary, ContactSummary, LcpSummary, LoadDrivenSummary, RigidModeSummary, Summary,
};
use std::fmt::{Formatter, Result};

/// `summary` as the command line's result block, one line per fact (the caller adds the line
/// naming the files written).
pub struct Console<'a>(pub &'a Summary);

impl std::fmt::Display for Console<'_> {
    fn fmt(&self, f: &mut Formatter<'_>) -> Result {
        let s = self.0;
        bodies(f, s)?;
        pairs(f, s)?;
        if let (true, Some(l)) = (s.by_pair(), &s.lcp) {
            pairs_lcp(f, l)?;
        }
        if let (Some(c), Some(l)) = (&s.contact, &s.lcp) {
            contact(f, c, l)?;
        }
        if let Some(r) = &s.refinement {
            refinement(f, r)?;
        }
        Ok(())
    }
}

/// A number to six decimals, or a dash.
fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "–".to_string(), |v| format!("{v:.6}"))
}

/// The first body's counts and checks, then the second's or every further body's.
fn bodies(f: &mut Formatter<'_>, s: &Summary) -> Result {
    writeln!(f, "{}: {} nodes, {} DOFs", s.problem.name, s.counts.nodes, s.counts.dofs)?;
    writeln!(
        f,
        "  residual {:.2e}, equilibrium error {:.2e}",
        s.checks.relative_residual, s.checks.equilibrium_error
    )?;
    if let Some(second) = &s.second_body {
        writeln!(
            f,
            "  second body {}: {} nodes, residual {:.2e}, equilibrium error {:.2e}",
            second.name.as_deref().unwrap_or("-"),
            second.nodes,
            second.relative_residual,
            second.equilibrium_error
        )?;
    }
    for b in s.bodies.iter().filter(|_| s.by_pair()) {
        writeln!(
            f,
            "  body {}: {} nodes, residual {:.2e}, equilibrium error {:.2e}",
            b.name.as_deref().unwrap_or("-"),
            b.nodes,
            b.relative_residual,
            b.equilibrium_error
        )?;
        if let Some(r) = &b.rigid_mode {
            write_rigid_mode(f, "    ", "held by contact alone", r)?;
        }
    }
    Ok(())
}

/// One line per contact pair of a scene (its friction and a force-driven obstacle's record
/// below it).
fn pairs(f: &mut Formatter<'_>, s: &Summary) -> Result {
    if !s.by_pair() {
        return Ok(());
    }
    let first_rigid = s.pairs.iter().position(|p| p.target_body.is_none()).unwrap_or(usize::MAX);
    for (k, p) in s.pairs.iter().enumerate() {
        let target = match (&p.target_body, &p.target_edge) {
            (Some(b), Some(e)) => format!("{b}.{e}"),
            _ => "obstacle".into(),
        };
        writeln!(
            f,
            "  contact[{k}] {}.{} against {target}: total force {:.6}, {} of {} candidates closed in {} zone(s)",
            p.body, p.edge, p.total_force, p.closed, p.candidates, p.closed_intervals
        )?;
        if let Some(fr) = &p.friction {
            let [stick, slip] = fr.stick_slip_counts;
            writeln!(
                f,
                "    friction μ = {}: tangential force {:.6}, {stick} candidates stick and {slip} slip ({} increment(s), residual {:.1e})",
                fr.coefficient, fr.total_tangential_force, fr.increments, fr.residual
            )?;
        }
        // The obstacles move together: their record once, with the first rigid pair.
        if let Some(l) = p.load_driven.as_ref().filter(|_| k == first_rigid) {
            write_load_driven(f, "    ", l)?;
        }
    }
    Ok(())
}

/// The one LCP of a scene's pairs: Lemke's or the active set's work.
fn pairs_lcp(f: &mut Formatter<'_>, l: &LcpSummary) -> Result {
    match &l.active_set {
        None => writeln!(
            f,
            "  one LCP over {} candidates: M eigenvalues of the symmetric part {:.3e} to {:.3e}; Lemke: {} pivots, complementarity {:.1e}",
            l.size,
            l.compliance_min_symmetric_eigenvalue.unwrap_or(f64::NAN),
            l.compliance_max_symmetric_eigenvalue.unwrap_or(f64::NAN),
            l.pivots,
            l.max_complementarity
        )?,
        Some(a) => writeln!(
            f,
            "  one LCP over {} candidates, active set: {} linear solves, {} factorisations, {} update columns, {} Lemke rescues; complementarity {:.1e}",
            l.size,
            a.iterations,
            a.work.factorisations,
            a.work.update_columns,
            a.rescues.len(),
            l.max_complementarity
        )?,
    }
    Ok(())
}

/// The contact of one body or of two bodies: forces, onset, friction and the LCP's work.
fn contact(f: &mut Formatter<'_>, c: &ContactSummary, l: &LcpSummary) -> Result {
    writeln!(
        f,
        "  contact: total force {:.6}, {} of {} candidates closed in {} zone(s)",
        c.total_force, c.closed, c.candidates, c.closed_intervals
    )?;
    writeln!(
        f,
        "  onset {} (bracket {} to {}, from the pressures {})",
        opt(c.onset_x),
        opt(c.last_open_x),
        opt(c.first_closed_x),
        opt(c.onset_x_from_pressure)
    )?;
    if let Some(l) = &c.load_driven {
        write_load_driven(f, "  ", l)?;
    }
    if let Some(r) = &c.rigid_mode {
        write_rigid_mode(f, "  ", "held by the contact", r)?;
    }
    if let (Some(mu), Some(tangential), Some([stick, slip])) =
        (c.friction_coefficient, c.total_tangential_force, c.stick_slip_counts)
    {
        writeln!(
            f,
            "  friction μ = {mu}: tangential force {tangential:.6}, {stick} candidates stick and {slip} slip ({} solver, residual {:.1e})",
            c.friction_solver
                .and_then(|m| serde_json::to_value(m).ok())
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_else(|| "-".into()),
            c.friction_residual.unwrap_or(f64::NAN)
        )?;
    }
    if let (Some(diagonal), Some(low), Some(high)) = (
        l.compliance_min_diagonal,
        l.compliance_min_symmetric_eigenvalue,
        l.compliance_max_symmetric_eigenvalue,
    ) {
        writeln!(
            f,
            "  M: min diagonal {diagonal:.3e}, eigenvalues of the symmetric part {low:.3e} to {high:.3e}; Lemke: {} pivots, complementarity {:.1e}",
            l.pivots, l.max_complementarity
        )?;
    }
    if let Some(a) = &l.active_set {
        writeln!(
            f,
            "  active set: {} iterations, changes {:?}, {} factorisations, {} update columns, {} Lemke rescues; complementarity {:.1e}",
            a.iterations,
            a.changes_per_iteration,
            a.work.factorisations,
            a.work.update_columns,
            a.rescues.len(),
            l.max_complementarity
        )?;
    }
    Ok(())
}

/// The adaptive loop's table, one row per step (and per body of a scene).
fn refinement(f: &mut Formatter<'_>, r: &AdaptiveSummary) -> Result {
    writeln!(
        f,
        "  adaptive refinement ({} indicator, stopped by {}):",
        r.parameters.indicator.name(),
        r.stopped_by
    )?;
    writeln!(
        f,
        "    step    nodes   min h_I  est. error  marked  contact force      onset  bracket"
    )?;
    for row in &r.steps {
        writeln!(
            f,
            "    {:>4} {:>8} {:>9.3e} {:>11.3e} {:>7} {:>14} {:>10} [{}, {}]",
            row.step,
            row.nodes,
            row.min_spacing,
            row.estimated_error,
            row.marked,
            opt(row.total_contact_force),
            opt(row.onset_x),
            opt(row.last_open_x),
            opt(row.first_closed_x)
        )?;
        for b in row.bodies.iter().flatten() {
            writeln!(
                f,
                "         {:>8} {:>9.3e} {:>11.3e} {:>7}  body {}",
                b.nodes, b.min_spacing, b.estimated_error, b.marked, b.name
            )?;
        }
    }
    Ok(())
}

/// The console line of an obstacle pressed by a force (docs/method.md §4.6).
fn write_load_driven(f: &mut Formatter<'_>, indent: &str, l: &LoadDrivenSummary) -> Result {
    writeln!(
        f,
        "{indent}obstacle pressed by ({:.6e}, {:.6e}): displaced by ({:.6e}, {:.6e}), s = {:.9e} along the force, carrying {:.9e} ({} LCP solves)",
        l.obstacle_force[0],
        l.obstacle_force[1],
        l.obstacle_displacement[0],
        l.obstacle_displacement[1],
        l.displacement_along_force,
        l.carried_force,
        l.lcp_solves
    )
}

/// The console line of a translation held by the contact (docs/method.md §4.7).
fn write_rigid_mode(
    f: &mut Formatter<'_>,
    indent: &str,
    held: &str,
    r: &RigidModeSummary,
) -> Result {
    writeln!(
        f,
        "{indent}{} {held}: the body translates by ({:.9e}, {:.9e}) (the point ({:.6}, {:.6})), load along it {:.6e} ({} LCP solves)",
        r.mode,
        r.translation[0],
        r.translation[1],
        r.pin_point[0],
        r.pin_point[1],
        r.load_along_mode,
        r.lcp_solves
    )
}
