//! The load path on the condensed contact system (docs/method.md §8; plan in
//! docs/dev/contact_core.md): steps × increments over any number of bodies, each entering the
//! contact problem through its [`Term`]. One body against rigid obstacles is one term, two
//! bodies in one pair two terms, several bodies and pairs one term per body touched by a pair.
//!
//! Per increment: the free gaps and tangential displacements interpolated between the step
//! ends, the step LCP ([`lcp::solve_step`]; μ = 0 is Lemke on `M_nn`), or one of the two
//! searches of docs/method.md §4.6–4.7 around it (a force-driven obstacle, a translation held
//! by the contact), then one solve per body with the contact forces of its candidates.

use super::friction::{History, StepEnd, StepStart, at_increment, force_along, lerp};
use super::*;
use std::ops::Range;

/// How one body enters the condensed contact system: its model, its normal and tangential
/// operators over the candidates that touch it (no tangential operator on a frictionless
/// one-shot path, whose system is `M_nn` alone), their global indices (`None`: candidate `c`
/// is the operators' row `c`, all candidates), and its load-step ends.
pub(super) struct Term<'a> {
    pub(super) model: &'a Model,
    pub(super) normal: &'a contact::BodyOperator,
    pub(super) tangential: Option<&'a contact::BodyOperator>,
    pub(super) index: Option<&'a [usize]>,
    pub(super) steps: &'a [StepEnd],
}

impl Term<'_> {
    /// Global index of the term's row `r`.
    fn global(&self, r: usize) -> usize {
        self.index.map_or(r, |index| index[r])
    }

    /// The term's share of the global vector `v`.
    fn gather(&self, v: &[f64]) -> Vec<f64> {
        match self.index {
            None => v.to_vec(),
            Some(index) => index.iter().map(|&g| v[g]).collect(),
        }
    }

    /// Adds the term's rows `part` into the global vector `v`.
    fn scatter_add(&self, part: &[f64], v: &mut [f64]) {
        for (r, x) in part.iter().enumerate() {
            v[self.global(r)] += x;
        }
    }

    /// The term's rows `part` as a global vector of `m` (zero where the term has no row).
    fn scatter_vec(&self, part: Vec<f64>, m: usize) -> Vec<f64> {
        if self.index.is_none() {
            return part;
        }
        let mut v = vec![0.0; m];
        self.scatter_add(&part, &mut v);
        v
    }

    /// The term's `mb × mb` block `part` as a global `m × m` block.
    fn scatter_block(&self, part: Vec<f64>, m: usize) -> Vec<f64> {
        let Some(index) = self.index else { return part };
        let mb = index.len();
        let mut out = vec![0.0; m * m];
        for (i, &gi) in index.iter().enumerate() {
            for (j, &gj) in index.iter().enumerate() {
                out[gi * m + gj] += part[i * mb + j];
            }
        }
        out
    }
}

/// A body's rigid translation held by the contact alone (docs/method.md §4.7): path term
/// `term`'s pin and `a_c = −s_c ν_c·r` over all candidates (`s_c = +1` on the candidate's
/// body, `−1` on its target), found by the nested search
/// ([`lcp::load_driven::search_condensed`]) from the body's load along `r`.
pub(super) struct Held {
    pub(super) term: usize,
    pub(super) pin: assembly::PinnedMode,
    pub(super) along: Vec<f64>,
}

/// The factor from a body's loads to the contact forces' units: `2π` for an axisymmetric body
/// (its loads are per radian, the rings' forces totals over the circumference, so a held
/// body's search balances `2π` times its load along the translation; `contact::rings`), 1
/// otherwise.
pub(super) fn ring_units(model: &crate::model::Model) -> f64 {
    match model.system.axisymmetric {
        true => crate::contact::rings::REVOLUTION,
        false => 1.0,
    }
}

/// A held body's load `load` along its pinned translation, in the contact forces' units
/// ([`ring_units`]): the target of its search (docs/method.md §4.7).
pub(super) fn load_along(
    model: &crate::model::Model,
    pin: assembly::PinnedMode,
    load: &[f64],
) -> f64 {
    load.iter().skip(pin.axis as usize).step_by(2).sum::<f64>() * ring_units(model)
}

/// Sets the pin's collocation row of `rhs` (body `model`) to the translation `t` found
/// (docs/method.md §4.7): the solve then adds the rigid translation, which `K_int` does not
/// see, to the pinned answer.
pub(super) fn set_pin_value(
    rhs: &mut [f64],
    model: &crate::model::Model,
    pin: assembly::PinnedMode,
    t: f64,
) {
    rhs[crate::nodes::dof(pin.node as usize, pin.axis)] = model.system.collocation_scale * t;
}

/// Refuses the answer of a held body's search when nothing determines the body's position
/// (docs/method.md §4.7): no load along the translation, no force carried along it, and the
/// touching gaps do not block it both ways (every translation of an interval answers).
pub(super) fn check_determined(
    (body, mode): (&str, &'static str),
    load: f64,
    along: &[f64],
    result: &lcp::LcpSolution,
    free_gap: &[f64],
) -> Result<(), lcp::load_driven::LoadDrivenError> {
    let (z, w) = (&result.z, &result.w);
    let carries = z.iter().zip(along).any(|(z, a)| *z * a != 0.0);
    let touching = 1e-12 * free_gap.iter().fold(0.0f64, |g, q| g.max(q.abs()));
    let blocked = |sign: f64| along.iter().zip(w).any(|(a, w)| sign * a > 0.0 && *w <= touching);
    if load == 0.0 && !carries && !(blocked(1.0) && blocked(-1.0)) {
        return Err(lcp::load_driven::LoadDrivenError::Undetermined { body: body.into(), mode });
    }
    Ok(())
}

/// What the path is run on besides the terms: the candidates' initial gaps and normals, the
/// step ends that carry the obstacle's motion, force and increments (the first term's), `μ`
/// per step and candidate, the candidates the obstacle moves, the held translation, and the
/// candidate ranges whose histories are recorded apart (the pairs).
pub(super) struct Path<'a> {
    pub(super) initial_gap: &'a [f64],
    pub(super) normals: &'a [geometry::Point],
    pub(super) steps: &'a [StepEnd],
    pub(super) friction: Vec<Vec<f64>>,
    /// The candidates the obstacle's motion or force moves (`None`: all): with several pairs,
    /// those of the pairs against rigid obstacles, which move together (docs/method.md §4.6).
    pub(super) moved: Option<&'a [bool]>,
    /// The bodies held by contact alone.
    pub(super) held: Vec<Held>,
    pub(super) groups: Vec<Range<usize>>,
    pub(super) write_steps: bool,
    /// Whether the problem has `[[step]]` tables (a failure then names the step).
    pub(super) named_steps: bool,
    /// Lemke's parameters on the frictionless steps (the default but in tests that provoke
    /// its failure).
    pub(super) lemke: &'a lcp::LemkeParams,
}

impl Path<'_> {
    /// Whether the obstacle's motion moves candidate `c`'s target.
    fn moves(&self, c: usize) -> bool {
        self.moved.is_none_or(|moved| moved[c])
    }

    /// Frictionless contact in one step of one increment without a search: the one-shot
    /// problem (docs/method.md §4–§5), whose stages are timed one by one (`lemke`,
    /// `lemke_polish`, `solve`) instead of as one `friction` stage.
    fn is_one_shot(&self) -> bool {
        let plain = self.held.is_empty() && self.steps.iter().all(|s| s.force.is_none());
        let frictionless = self.friction.iter().flatten().all(|&mu| mu == 0.0);
        plain && frictionless && self.steps.len() == 1 && self.steps[0].increments == 1
    }
}

/// Times the path's stages: inside the path's one `friction` stage (no clock), or each as its
/// own stage on a one-shot path ([`Path::is_one_shot`]).
struct Timer<'c, 'p>(Option<&'c mut Clock<'p>>);

impl Timer<'_, '_> {
    fn run<T>(
        &mut self,
        stage: &'static str,
        f: impl FnOnce(&mut dyn FnMut(usize, usize)) -> T,
    ) -> T {
        match &mut self.0 {
            Some(clock) => clock.run_counted(stage, f),
            None => f(&mut |_, _| {}),
        }
    }
}

/// The condensed blocks over all candidates (`g0` in `free_gap`) and the frictionless `M`
/// with its checks, from one condensation per term.
pub(super) struct Condensed {
    pub(super) blocks: contact::CondensedBlocks,
    pub(super) compliance: contact::CondensedContact,
}

/// `M_ab = Σ_b scatter(I_b, G_a,b K_b⁻¹ E_b,b)` and the free gaps over the terms
/// (docs/method.md §8), and `M_nn`'s checks. For one and two bodies this is the sum the
/// frictional path always computed (the first term's blocks, then each other's added).
///
/// # Errors
/// A failed solve ([`contact::ContactError`]), a compliance check's dense eigenvalue failure;
/// [`contact::ContactError::MissingTangential`] for a term without its tangential operator
/// or no term at all.
pub(super) fn condense(terms: &[Term<'_>], initial_gap: &[f64]) -> Result<Condensed, Error> {
    let m = initial_gap.len();
    let mut total: Option<contact::CondensedBlocks> = None;
    let mut parts = Vec::with_capacity(terms.len());
    for (k, term) in terms.iter().enumerate() {
        let tangential = term.tangential.ok_or_else(|| missing_tangential(k))?;
        let b = contact::condense_blocks(
            &term.model.factorisation,
            &term.model.system.rhs,
            term.normal,
            tangential,
        )?;
        let global = contact::CondensedBlocks {
            size: m,
            nn: term.scatter_block(b.nn, m),
            nt: term.scatter_block(b.nt, m),
            tn: term.scatter_block(b.tn, m),
            tt: term.scatter_block(b.tt, m),
            free_gap: term.scatter_vec(b.free_gap, m),
            free_tangential: term.scatter_vec(b.free_tangential, m),
        };
        parts.push(contact::CondensedPart {
            compliance: global.nn.clone(),
            free_gap: global.free_gap.clone(),
        });
        total = Some(match total {
            None => global,
            Some(mut t) => {
                let add =
                    |a: &mut Vec<f64>, b: &[f64]| a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                add(&mut t.nn, &global.nn);
                add(&mut t.nt, &global.nt);
                add(&mut t.tn, &global.tn);
                add(&mut t.tt, &global.tt);
                add(&mut t.free_gap, &global.free_gap);
                add(&mut t.free_tangential, &global.free_tangential);
                t
            }
        });
    }
    let total = total.ok_or_else(|| contact::ContactError::MissingTangential {
        what: "no contact body was given".into(),
    })?;
    let compliance = contact::CondensedContact::combine(initial_gap, &parts)?;
    Ok(Condensed { blocks: total.with_initial_gap(initial_gap), compliance })
}

/// [`condense`]'s error for term `k` without its tangential operator.
fn missing_tangential(k: usize) -> contact::ContactError {
    let what = format!("body term {k} has none (frictionless terms condense by `condense_normal`)");
    contact::ContactError::MissingTangential { what }
}

/// The frictionless `M = Σ_b scatter(I_b, G_b K_b⁻¹ E_b)` and `q` over the terms with `M`'s
/// checks (docs/method.md §4.2–4.5), one condensation per term
/// ([`contact::condense_model_observed`]: by reach-restricted solves where they pay), for a
/// one-shot path. Terms over all candidates (one pair) are combined part by part, terms over
/// some candidates each (several pairs) summed into one part first: the sums the one-shot
/// routes always computed, in their order.
///
/// # Errors
/// A failed solve or second factorisation, a dense eigenvalue failure.
pub(super) fn condense_normal(
    terms: &[Term<'_>],
    initial_gap: &[f64],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<contact::CondensedContact, contact::ContactError> {
    let mut parts = Vec::with_capacity(terms.len());
    for term in terms {
        parts.push(contact::condense_model_observed(term.model, term.normal, progress)?);
    }
    if terms.iter().all(|t| t.index.is_none()) {
        return contact::CondensedContact::combine(initial_gap, &parts);
    }
    let m = initial_gap.len();
    let mut total = contact::CondensedPart { compliance: vec![0.0; m * m], free_gap: vec![0.0; m] };
    for (term, part) in terms.iter().zip(parts) {
        let mb = term.normal.len();
        for i in 0..mb {
            let gi = term.global(i);
            total.free_gap[gi] += part.free_gap[i];
            for j in 0..mb {
                total.compliance[gi * m + term.global(j)] += part.compliance[i * mb + j];
            }
        }
    }
    contact::CondensedContact::combine(initial_gap, &[total])
}

/// The condensed blocks of a one-shot path ([`Path::is_one_shot`]): `M_nn` and `q_n` of
/// `condensed` (taken: [`PathAnswer::problem`] gives `M_nn` back), no tangential blocks.
pub(super) fn normal_blocks(condensed: &mut contact::CondensedContact) -> contact::CondensedBlocks {
    let m = condensed.free_gap.len();
    contact::CondensedBlocks {
        size: m,
        nn: std::mem::take(&mut condensed.compliance),
        nt: Vec::new(),
        tn: Vec::new(),
        tt: Vec::new(),
        free_gap: condensed.free_gap.clone(),
        free_tangential: vec![0.0; m],
    }
}

/// What the path ends with: the last increment's answer, each term's nodal parameters, the
/// last step problem (its blocks and free gaps), one history per group, and the searches'
/// records.
pub(super) struct PathAnswer {
    pub(super) step: lcp::FrictionSolution,
    /// The last increment's normal LCP as Lemke (and the polish) answered it (the search's
    /// last trial), when that increment was frictionless.
    pub(super) normal: Option<Normal>,
    pub(super) u: Vec<Vec<f64>>,
    pub(super) problem: lcp::FrictionProblem,
    pub(super) histories: Vec<History>,
    pub(super) load_driven: Option<solution::LoadDriven>,
    /// The held bodies' records, in the order of [`Path::held`].
    pub(super) rigid_modes: Vec<solution::RigidMode>,
}

/// The gaps `q_n` and tangential displacements `q_t` without contact forces.
type FreeMotion = (Vec<f64>, Vec<f64>);

/// `(q_n, q_t)` at the end of each step: the last step's from the condensation (the models'
/// right-hand sides are the last step's), the others by one solve per body; a rigid
/// obstacle's displacement `d` shifts the gap by `−d·ν_c` and the tangential displacement
/// relative to it by `−d·t_c`.
fn step_end_gaps(
    path: &Path<'_>,
    terms: &[Term<'_>],
    blocks: &contact::CondensedBlocks,
) -> Result<Vec<FreeMotion>, Error> {
    let m = path.initial_gap.len();
    let steps = path.steps;
    steps
        .iter()
        .enumerate()
        .map(|(k, end)| {
            let (mut qn, mut qt) = if k + 1 == steps.len() {
                (blocks.free_gap.clone(), blocks.free_tangential.clone())
            } else {
                let mut qn = path.initial_gap.to_vec();
                let mut qt = vec![0.0; m];
                for term in terms {
                    let u = term.model.factorisation.solve(&term.steps[k].rhs)?;
                    term.scatter_add(&term.normal.gap_contribution(&u), &mut qn);
                    if let Some(tangential) = term.tangential {
                        term.scatter_add(&tangential.gap_contribution(&u), &mut qt);
                    }
                }
                (qn, qt)
            };
            if end.obstacle != [0.0, 0.0] {
                let d = end.obstacle;
                for c in (0..m).filter(|&c| path.moves(c)) {
                    let (nu, t) = (path.normals[c], contact::tangent(path.normals[c]));
                    qn[c] -= d[0] * nu[0] + d[1] * nu[1];
                    qt[c] -= d[0] * t[0] + d[1] * t[1];
                }
            }
            Ok((qn, qt))
        })
        .collect()
}

/// The running state of the searches over the increments.
#[derive(Default)]
struct Searches {
    load_driven: Option<solution::LoadDriven>,
    rigid_modes: Vec<solution::RigidMode>,
    total_evaluations: usize,
}

/// One increment's answer without a search, or one trial of a search: the frictionless step
/// by Lemke on `M_nn` (with the path's parameters, polished on its closed set) with the
/// normal LCP's own answer, or the frictional step LCP.
fn solve_plain(
    path: &Path<'_>,
    step_problem: &lcp::FrictionProblem,
    timer: &mut Timer<'_, '_>,
) -> Result<Increment, lcp::LcpError> {
    if !step_problem.is_frictionless() {
        return Ok((lcp::solve_step(step_problem)?, None));
    }
    let mut solved = timer.run("lemke", |progress| {
        lcp::solve_frictionless_step(step_problem, path.lemke, progress)
    })?;
    let polish = timer.run("lemke_polish", |_| solved.polish(step_problem))?;
    Ok((solved.step, Some((solved.lcp, polish))))
}

/// An increment's step answer and, when frictionless, its normal LCP's
/// ([`PathAnswer::normal`]).
type Increment = (lcp::FrictionSolution, Option<Normal>);

/// A frictionless increment's normal LCP answer, as Lemke (and the polish) gave it, and the
/// polish's record.
pub(super) type Normal = (lcp::LcpSolution, lcp::Polish);

/// One increment's step answer at load factor `lambda` of step `k`: the step LCP, or the
/// search for a force-driven obstacle or a held translation around it.
#[allow(clippy::too_many_arguments)]
fn solve_increment(
    path: &Path<'_>,
    terms: &[Term<'_>],
    step_problem: &mut lcp::FrictionProblem,
    compliance: Option<&[f64]>,
    start: &StepStart,
    (k, lambda): (usize, f64),
    searches: &mut Searches,
    timer: &mut Timer<'_, '_>,
) -> Result<Increment, lcp::LcpError> {
    let end = &path.steps[k];
    let Some(compliance) = compliance else { return solve_plain(path, step_problem, timer) };
    let base = step_problem.free_gap.clone();
    let solve = |q: &[f64]| {
        step_problem.free_gap = q.to_vec();
        solve_plain(path, step_problem, timer)
    };
    fn forces(answer: &Increment) -> &[f64] {
        answer.0.normal.as_slice()
    }
    // The held bodies (their loads along r in the contact's units) and a force-driven
    // obstacle, searched at once (docs/method.md §4.6–4.7).
    let mut held = Vec::with_capacity(path.held.len());
    for Held { term, pin, along } in &path.held {
        let load = lerp(&start.loads[*term], &terms[*term].steps[k].load, lambda);
        let load = load_along(terms[*term].model, *pin, &load);
        refuse_not_pressed(*pin, along, load)?;
        held.push((along.as_slice(), load));
    }
    let force = end.force.map(|f| {
        let (e, size, mut along) = force_along(f, path.normals);
        for (c, a) in along.iter_mut().enumerate() {
            if !path.moves(c) {
                *a = 0.0;
            }
        }
        (along, e, start.force_at(size, lambda))
    });
    let unknowns = lcp::load_driven::nested::Unknowns {
        held: &held,
        force: force.as_ref().map(|(along, e, target)| (along.as_slice(), *e, *target)),
    };
    let found = lcp::load_driven::search_condensed(compliance, &base, unknowns, solve, forces)?;
    let loads: Vec<f64> = held.iter().map(|h| h.1).collect();
    searches.record_held(path, terms, (&loads, (found.translations, found.evaluations)));
    if let Some((_, e, target)) = force {
        let search = &found.outer;
        searches.load_driven = Some(solution::LoadDriven::found(
            (e, target),
            search.displacement,
            search.force,
            (found.evaluations, searches.total_evaluations),
        ));
    }
    Ok(found.outer.answer)
}

/// Refuses a held body whose load along its translation `r` (`load`, non-zero) no contact
/// force can balance: every `a_c` has the opposite sign (the load pulls the body off what
/// holds it, docs/method.md §4.7).
fn refuse_not_pressed(
    pin: assembly::PinnedMode,
    along: &[f64],
    load: f64,
) -> Result<(), lcp::LcpError> {
    if load != 0.0 && along.iter().all(|a| load.signum() * a <= 0.0) {
        return Err(lcp::load_driven::LoadDrivenError::NotPressed { mode: pin.name(), load }.into());
    }
    Ok(())
}

impl Searches {
    /// Counts a search's LCP solves and records each held body's translation: `loads` along
    /// their translations, `translations` in the order of [`Path::held`].
    fn record_held(
        &mut self,
        path: &Path<'_>,
        terms: &[Term<'_>],
        (loads, (translations, evaluations)): (&[f64], (Vec<f64>, usize)),
    ) {
        self.total_evaluations += evaluations;
        self.rigid_modes = path
            .held
            .iter()
            .zip(translations)
            .zip(loads)
            .map(|((held, translation), &load)| {
                let pin = held.pin;
                let mut t = [0.0; 2];
                t[pin.axis as usize] = translation;
                solution::RigidMode {
                    mode: pin.name(),
                    pin_point: terms[held.term].model.nodes.points[pin.node as usize],
                    translation: t,
                    load,
                    evaluations,
                    total_evaluations: self.total_evaluations,
                }
            })
            .collect();
    }
}

/// The step answer's rows `range` (the residuals, method and counts are the whole step's).
pub(super) fn select(step: &lcp::FrictionSolution, range: Range<usize>) -> lcp::FrictionSolution {
    lcp::FrictionSolution {
        normal: step.normal[range.clone()].to_vec(),
        tangential: step.tangential[range.clone()].to_vec(),
        gap: step.gap[range.clone()].to_vec(),
        tangential_displacement: step.tangential_displacement[range.clone()].to_vec(),
        slip_increment: step.slip_increment[range.clone()].to_vec(),
        state: step.state[range].to_vec(),
        residuals: step.residuals,
        method: step.method,
        pivots: step.pivots,
        iterations: step.iterations,
        lemke_failure: step.lemke_failure.clone(),
    }
}

/// Runs the load path (docs/method.md §8) on the condensed blocks `blocks` of `terms`.
///
/// # Errors
/// The step solver's and the searches' errors (naming the step and the increment when the
/// problem has `[[step]]` tables), a failed solve.
pub(super) fn run_condensed(
    path: &Path<'_>,
    terms: &[Term<'_>],
    blocks: contact::CondensedBlocks,
    clock: &mut Clock<'_>,
) -> Result<PathAnswer, Error> {
    let m = path.initial_gap.len();
    let one_shot = path.is_one_shot();
    let ends = match one_shot {
        // One step: its end is the condensation's, no solve.
        true => step_end_gaps(path, terms, &blocks)?,
        false => clock.run("load_steps", || step_end_gaps(path, terms, &blocks))?,
    };
    let mut walk = Walk {
        path,
        terms,
        step_problem: lcp::FrictionProblem {
            nn: blocks.nn,
            nt: blocks.nt,
            tn: blocks.tn,
            tt: blocks.tt,
            free_gap: path.initial_gap.to_vec(),
            free_tangential: vec![0.0; m],
            previous_tangential: vec![0.0; m],
            friction: path.friction[0].clone(),
        },
        histories: path.groups.iter().map(|g| History::new(g.len(), path.write_steps)).collect(),
        searches: Searches::default(),
        last: None,
    };
    match one_shot {
        true => walk.steps(&ends, &mut Timer(Some(clock)))?,
        false => clock.run("friction", || walk.steps(&ends, &mut Timer(None)))?,
    }
    let Walk { step_problem, histories, searches, last, .. } = walk;
    let Some((step, normal, u)) = last else {
        unreachable!("validated: at least one step with at least one increment")
    };
    Ok(PathAnswer {
        step,
        normal,
        u,
        problem: step_problem,
        histories,
        load_driven: searches.load_driven,
        rigid_modes: searches.rigid_modes,
    })
}

/// The load path's running state: the step problem, the histories, the searches' records and
/// the last increment's answer (its step answer, normal LCP and each term's displacements).
struct Walk<'w, 'a> {
    path: &'w Path<'a>,
    terms: &'w [Term<'a>],
    step_problem: lcp::FrictionProblem,
    histories: Vec<History>,
    searches: Searches,
    last: Option<(lcp::FrictionSolution, Option<Normal>, Vec<Vec<f64>>)>,
}

impl Walk<'_, '_> {
    /// Every step's increments from the unloaded start (no load, the obstacle where it was
    /// given) through the step ends `ends`.
    fn steps(&mut self, ends: &[FreeMotion], timer: &mut Timer<'_, '_>) -> Result<(), Error> {
        let (path, terms) = (self.path, self.terms);
        let m = path.initial_gap.len();
        let mut start = StepStart::new(terms.iter().map(|t| t.model.system.rhs.len()));
        let (mut qn0, mut qt0) = (path.initial_gap.to_vec(), vec![0.0; m]);
        let compliance = (path.steps.iter().any(|s| s.force.is_some()) || !path.held.is_empty())
            .then(|| self.step_problem.nn.clone());
        for (k, (end, (qn1, qt1))) in path.steps.iter().zip(ends).enumerate() {
            self.step_problem.friction.clone_from(&path.friction[k]);
            for i in 1..=end.increments {
                let started = std::time::Instant::now();
                let lambda = i as f64 / end.increments as f64;
                self.step_problem.free_gap = lerp(&qn0, qn1, lambda);
                self.step_problem.free_tangential = lerp(&qt0, qt1, lambda);
                let solved = solve_increment(
                    path,
                    terms,
                    &mut self.step_problem,
                    compliance.as_deref(),
                    &start,
                    (k, lambda),
                    &mut self.searches,
                    timer,
                );
                // With [[step]] tables, a failure names the step and the increment.
                let (step, normal) = solved
                    .map_err(|e| at_increment(path.named_steps, (k, i, end.increments), e))?;
                let (u, equilibrium) = self.bodies(&step, &start, (k, lambda), timer)?;
                let seconds = started.elapsed().as_secs_f64();
                let groups = path.groups.iter().cloned();
                let record = (equilibrium, &[][..], seconds);
                History::record_pairs(&mut self.histories, groups, &step, (k, i, lambda), record);
                self.step_problem.previous_tangential.clone_from(&step.tangential_displacement);
                self.last = Some((step, normal, u));
            }
            start.advance(terms.iter().map(|t| &t.steps[k]), end);
            (qn0, qt0) = (qn1.clone(), qt1.clone());
        }
        Ok(())
    }

    /// One solve per body with the contact forces of its candidates at load factor `lambda`
    /// of step `k` (from the step's `start`), and the worst body's equilibrium
    /// error (computed only when a history records it).
    fn bodies(
        &self,
        step: &lcp::FrictionSolution,
        start: &StepStart,
        (k, lambda): (usize, f64),
        timer: &mut Timer<'_, '_>,
    ) -> Result<(Vec<Vec<f64>>, f64), Error> {
        let mut u = Vec::with_capacity(self.terms.len());
        let mut equilibrium: f64 = 0.0;
        for (b, term) in self.terms.iter().enumerate() {
            let normal = term.gather(&step.normal);
            let tangential = term.tangential.map(|op| (op, term.gather(&step.tangential)));
            let mut rhs = lerp(&start.rhss[b], &term.steps[k].rhs, lambda);
            term.normal.add_forces(&normal, &mut rhs);
            if let Some((op, forces)) = &tangential {
                op.add_forces(forces, &mut rhs);
            }
            // The body's free translation found: the pin's value (the solve adds the rigid
            // translation, which K_int does not see, to the pinned answer).
            for (held, r) in self.path.held.iter().zip(&self.searches.rigid_modes) {
                if held.term == b {
                    let pin = held.pin;
                    set_pin_value(&mut rhs, term.model, pin, r.translation[pin.axis as usize]);
                }
            }
            let u_b = timer.run("solve", |_| term.model.factorisation.solve(&rhs))?;
            if !self.histories.is_empty() {
                let load = lerp(&start.loads[b], &term.steps[k].load, lambda);
                let mut ops = vec![(term.normal, normal.as_slice())];
                ops.extend(tangential.as_ref().map(|(op, t)| (*op, t.as_slice())));
                let e = solution::equilibrium_error(&term.model.system, &load, &u_b, &ops);
                equilibrium = if b == 0 { e } else { equilibrium.max(e) };
            }
            u.push(u_b);
        }
        Ok((u, equilibrium))
    }
}

/// The normal LCP of the answer given its tangential forces (`q = q_n + M_nt T`), for the
/// `lcp` record of the summary.
pub(super) fn normal_lcp(
    problem: &lcp::FrictionProblem,
    step: &lcp::FrictionSolution,
) -> Result<lcp::LcpSolution, Error> {
    let m = step.normal.len();
    let q: Vec<f64> = (0..m)
        .map(|i| {
            let row = &problem.nt[i * m..(i + 1) * m];
            problem.free_gap[i] + row.iter().zip(&step.tangential).map(|(a, b)| a * b).sum::<f64>()
        })
        .collect();
    let normal = lcp::Lcp::new(m, problem.nn.clone(), q)?;
    Ok(lcp::LcpSolution {
        w: normal.w(&step.normal),
        residuals: normal.residuals(&step.normal),
        z: step.normal.clone(),
        pivots: step.pivots,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frictionless term (no tangential operator) or no term at all is refused as what it
    /// is, not as a missing contact target.
    #[test]
    fn condense_names_a_missing_tangential_operator() {
        let problem = crate::problem::Problem::from_toml(
            r#"
            [geometry]
            kind = "rectangle"
            x = [0.0, 1.0]
            y = [0.0, 1.0]
            [nodes]
            spacing = 0.25
            [material]
            young = 1000.0
            poisson = 0.3
            plane = "stress"
            [[boundary]]
            edge = "bottom"
            displacement = { x = 0.0, y = 0.0 }
            [contact]
            edge = "top"
            obstacle_point = [0.0, 1.01]
            obstacle_normal = [0.0, -1.0]
            "#,
        )
        .unwrap();
        let model = super::super::discretise(&problem, &mut crate::progress::Silent).unwrap();
        let spec = problem.contact().unwrap();
        let target = |x| contact::rigid_target(&problem, spec, x).unwrap();
        let candidates =
            contact::candidates_on(&problem, &model, spec.edge, &target, spec.condensation)
                .unwrap();
        let steps = vec![StepEnd::whole(&model, 0.0)];
        let term = Term {
            model: &model,
            normal: &candidates.operator,
            tangential: None,
            index: None,
            steps: &steps,
        };
        let message = |e: Error| match e {
            Error::Contact(e @ contact::ContactError::MissingTangential { .. }) => e.to_string(),
            other => panic!("not a missing tangential operator: {other}"),
        };
        let frictionless = message(condense(&[term], &candidates.initial_gap).err().unwrap());
        assert!(frictionless.contains("body term 0 has none"), "{frictionless}");
        let none = message(condense(&[], &[]).err().unwrap());
        assert!(none.contains("no contact body"), "{none}");
    }
}
