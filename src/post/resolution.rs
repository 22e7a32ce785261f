//! The resolution warning: a contact zone closed by few candidates gives numbers that look
//! final but are not. Each end of a zone is known only to within one candidate spacing (the
//! bracket between its last open and first closed candidate), so a zone of `n` closed
//! candidates has its width, and with it the peak pressure (`p0 ∝ P / a` for a Hertzian
//! zone), uncertain by about one part in `n`; below [`MIN_CLOSED`] that exceeds 12 %, and the
//! pressure profile across the zone is drawn by a handful of points.

use crate::solution::ContactSolution;

/// The fewest closed candidates a contact zone (a run of consecutive closed candidates) should
/// have.
pub const MIN_CLOSED: usize = 8;

/// The lengths of the runs of consecutive closed candidates.
fn zones(closed: &[bool]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut run = 0;
    for &c in closed.iter().chain(std::iter::once(&false)) {
        if c {
            run += 1;
        } else if run > 0 {
            out.push(run);
            run = 0;
        }
    }
    out
}

/// The warning for a contact (`name`: `"contact"` or `"contact[k]"`) whose smallest zone closes
/// fewer than [`MIN_CLOSED`] candidates, with the remedy; none without a closed candidate.
pub fn warning(name: &str, c: &ContactSolution) -> Option<String> {
    let zones = zones(&c.closed);
    let fewest = zones.iter().copied().min().filter(|&n| n < MIN_CLOSED)?;
    let which = if zones.len() == 1 {
        "the contact zone closes".to_string()
    } else {
        format!("the smallest of its {} contact zones closes", zones.len())
    };
    Some(format!(
        "{name}: under-resolved: {which} {fewest} candidate{} (fewer than {MIN_CLOSED}), so its width and peak pressure are uncertain by more than an eighth; refine the node spacing near the contact edge ([[nodes.refine]] around the zone, for about 16 candidates across it) or add a [refinement] table",
        if fewest == 1 { "" } else { "s" }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zones_are_the_runs_of_closed_candidates() {
        assert_eq!(zones(&[]), Vec::<usize>::new());
        assert_eq!(zones(&[false, true, true, false, true]), vec![2, 1]);
        assert_eq!(zones(&[true; 9]), vec![9]);
    }
}
