//! The condensed contact system of the load path (docs/method.md §4–§5, §8): each body
//! enters through its [`Term`] (one body against rigid obstacles is one term, two bodies in
//! one pair two terms, several bodies and pairs one term per body touched by a pair); the
//! blocks `M_ab = Σ_b scatter(I_b, G_a,b K_b⁻¹ E_b)` and the free motions of the step ends are
//! condensed once, and per increment the free gaps and tangential displacements are
//! interpolated between the step ends, the step LCP solved ([`lcp::solve_step`]; μ = 0 is
//! Lemke on `M_nn`, polished) or searched around ([`lcp::load_driven::search_condensed`]),
//! then one solve per body with the contact forces of its candidates.

use super::super::friction::{History, StepEnd, lerp};
use super::super::*;
use super::{At, Path, PathSystem, Timer, Walked};

/// How one body enters the condensed contact system: its model, its normal and tangential
/// operators over the candidates that touch it (no tangential operator on a frictionless
/// one-shot path, whose system is `M_nn` alone), their global indices (`None`: candidate `c`
/// is the operators' row `c`, all candidates), and its load-step ends.
pub(in crate::pipeline) struct Term<'a> {
    pub(in crate::pipeline) model: &'a Model,
    pub(in crate::pipeline) normal: &'a contact::BodyOperator,
    pub(in crate::pipeline) tangential: Option<&'a contact::BodyOperator>,
    pub(in crate::pipeline) index: Option<&'a [usize]>,
    pub(in crate::pipeline) steps: &'a [StepEnd],
}

impl Term<'_> {
    /// Global index of the term's row `r`.
    pub(in crate::pipeline) fn global(&self, r: usize) -> usize {
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

/// The condensed blocks over all candidates (`g0` in `free_gap`) and the frictionless `M`
/// with its checks, from one condensation per term.
pub(in crate::pipeline) struct Condensed {
    pub(in crate::pipeline) blocks: contact::CondensedBlocks,
    pub(in crate::pipeline) compliance: contact::CondensedContact,
}

/// `M_ab = Σ_b scatter(I_b, G_a,b K_b⁻¹ E_b,b)` and the free gaps over the terms
/// (docs/method.md §8), and `M_nn`'s checks. For one and two bodies this is the sum the
/// frictional path always computed (the first term's blocks, then each other's added).
///
/// # Errors
/// A failed solve ([`contact::ContactError`]), a compliance check's dense eigenvalue failure;
/// [`contact::ContactError::MissingTangential`] for a term without its tangential operator
/// or no term at all.
pub(in crate::pipeline) fn condense(
    terms: &[Term<'_>],
    initial_gap: &[f64],
) -> Result<Condensed, Error> {
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
pub(in crate::pipeline) fn condense_normal(
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
pub(in crate::pipeline) fn normal_blocks(
    condensed: &mut contact::CondensedContact,
) -> contact::CondensedBlocks {
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
pub(in crate::pipeline) struct PathAnswer {
    pub(in crate::pipeline) step: lcp::FrictionSolution,
    /// The last increment's normal LCP as Lemke (and the polish) answered it (the search's
    /// last trial), when that increment was frictionless.
    pub(in crate::pipeline) normal: Option<Normal>,
    pub(in crate::pipeline) u: Vec<Vec<f64>>,
    pub(in crate::pipeline) problem: lcp::FrictionProblem,
    pub(in crate::pipeline) histories: Vec<History>,
    pub(in crate::pipeline) load_driven: Option<solution::LoadDriven>,
    /// The held bodies' records, in the order of [`Path::held`].
    pub(in crate::pipeline) rigid_modes: Vec<solution::RigidMode>,
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
/// by Lemke on `M_nn` (with `lemke`'s parameters, polished on its closed set) with the
/// normal LCP's own answer, or the frictional step LCP.
fn solve_plain(
    lemke: &lcp::LemkeParams,
    step_problem: &lcp::FrictionProblem,
    timer: &mut Timer<'_, '_>,
) -> Result<Increment, lcp::LcpError> {
    if !step_problem.is_frictionless() {
        return Ok((lcp::solve_step(step_problem)?, None));
    }
    let mut solved = timer
        .run("lemke", |progress| lcp::solve_frictionless_step(step_problem, lemke, progress))?;
    let polish = timer.run("lemke_polish", |_| solved.polish(step_problem))?;
    Ok((solved.step, Some((solved.lcp, polish))))
}

/// An increment's step answer and, when frictionless, its normal LCP's
/// ([`PathAnswer::normal`]).
type Increment = (lcp::FrictionSolution, Option<Normal>);

/// A frictionless increment's normal LCP answer, as Lemke (and the polish) gave it, and the
/// polish's record.
pub(in crate::pipeline) type Normal = (lcp::LcpSolution, lcp::Polish);

/// The condensed system along the path: the terms, Lemke's parameters, the free motions of
/// the step ends, the step problem (the blocks, the increment's free motion, `μ`, the
/// accumulated tangential displacements), `M_nn` for the searches, and their records.
struct System<'w, 'a> {
    terms: &'w [Term<'a>],
    lemke: &'w lcp::LemkeParams,
    ends: Vec<FreeMotion>,
    step_problem: lcp::FrictionProblem,
    /// `M_nn`, the searches' compliance (only with held bodies or a force-driven obstacle).
    compliance: Option<Vec<f64>>,
    searches: Searches,
}

impl PathSystem for System<'_, '_> {
    type Answer = Increment;

    fn begin_step(&mut self, path: &Path<'_>, k: usize) -> Result<(), Error> {
        self.step_problem.friction.clone_from(&path.friction[k]);
        Ok(())
    }

    /// The free motion at `λ` between the step's start (the previous step's end, or the
    /// unloaded start) and its end, then the step LCP, or the search for a force-driven
    /// obstacle or held translations around it.
    fn solve(
        &mut self,
        path: &Path<'_>,
        at: &At<'_>,
        timer: &mut Timer<'_, '_>,
    ) -> Result<Increment, lcp::LcpError> {
        let System { terms, lemke, ends, step_problem, compliance, searches } = self;
        let (qn1, qt1) = &ends[at.k];
        (step_problem.free_gap, step_problem.free_tangential) = match at.k.checked_sub(1) {
            Some(previous) => {
                let (qn0, qt0) = &ends[previous];
                (lerp(qn0, qn1, at.lambda), lerp(qt0, qt1, at.lambda))
            }
            None => {
                let qt0 = vec![0.0; qt1.len()];
                (lerp(path.initial_gap, qn1, at.lambda), lerp(&qt0, qt1, at.lambda))
            }
        };
        let Some(compliance) = compliance.as_deref() else {
            return solve_plain(lemke, step_problem, timer);
        };
        let base = step_problem.free_gap.clone();
        let solve = |q: &[f64]| {
            step_problem.free_gap = q.to_vec();
            solve_plain(lemke, step_problem, timer)
        };
        fn forces(answer: &Increment) -> &[f64] {
            answer.0.normal.as_slice()
        }
        let unknowns = at.unknowns;
        let found = lcp::load_driven::search_condensed(compliance, &base, unknowns, solve, forces)?;
        let loads: Vec<f64> = unknowns.held.iter().map(|h| h.1).collect();
        searches.record_held(path, terms, (&loads, (found.translations, found.evaluations)));
        if let Some((_, e, target)) = unknowns.force {
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

    /// One solve per body with the contact forces of its candidates, each held body's pin
    /// set to the translation found.
    fn displacements(
        &mut self,
        path: &Path<'_>,
        (step, _): &mut Increment,
        (at, record): (&At<'_>, bool),
        timer: &mut Timer<'_, '_>,
    ) -> Result<(Vec<Vec<f64>>, f64), Error> {
        let mut u = Vec::with_capacity(self.terms.len());
        let mut equilibrium: f64 = 0.0;
        for (b, term) in self.terms.iter().enumerate() {
            let normal = term.gather(&step.normal);
            let tangential = term.tangential.map(|op| (op, term.gather(&step.tangential)));
            let mut rhs = at.rhss[b].clone();
            term.normal.add_forces(&normal, &mut rhs);
            if let Some((op, forces)) = &tangential {
                op.add_forces(forces, &mut rhs);
            }
            // The body's free translation found: the pin's value (the solve adds the rigid
            // translation, which K_int does not see, to the pinned answer).
            for (held, r) in path.held.iter().zip(&self.searches.rigid_modes) {
                if held.term == b {
                    let pin = held.pin;
                    super::set_pin_value(
                        &mut rhs,
                        term.model,
                        pin,
                        r.translation[pin.axis as usize],
                    );
                }
            }
            let u_b = timer.run("solve", |_| term.model.factorisation.solve(&rhs))?;
            if record {
                let mut ops = vec![(term.normal, normal.as_slice())];
                ops.extend(tangential.as_ref().map(|(op, t)| (*op, t.as_slice())));
                let e = solution::equilibrium_error(&term.model.system, &at.loads[b], &u_b, &ops);
                equilibrium = if b == 0 { e } else { equilibrium.max(e) };
            }
            u.push(u_b);
        }
        Ok((u, equilibrium))
    }

    fn step((step, _): &Increment) -> &lcp::FrictionSolution {
        step
    }

    fn changes(_: &Increment) -> &[usize] {
        &[]
    }

    fn end_increment(&mut self, (step, _): &Increment) {
        self.step_problem.previous_tangential.clone_from(&step.tangential_displacement);
    }
}

/// Runs the load path (docs/method.md §8) on the condensed blocks `blocks` of `terms`,
/// Lemke's frictionless steps with `lemke`'s parameters.
///
/// # Errors
/// The step solver's and the searches' errors (naming the step and the increment when the
/// problem has `[[step]]` tables), a failed solve.
pub(in crate::pipeline) fn run_condensed(
    path: &Path<'_>,
    terms: &[Term<'_>],
    blocks: contact::CondensedBlocks,
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<PathAnswer, Error> {
    let m = path.initial_gap.len();
    let one_shot = path.is_one_shot();
    let ends = match one_shot {
        // One step: its end is the condensation's, no solve.
        true => step_end_gaps(path, terms, &blocks)?,
        false => clock.run("load_steps", || step_end_gaps(path, terms, &blocks))?,
    };
    let searched = path.steps.iter().any(|s| s.force.is_some()) || !path.held.is_empty();
    let mut system = System {
        terms,
        lemke,
        ends,
        compliance: searched.then(|| blocks.nn.clone()),
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
        searches: Searches::default(),
    };
    let bodies: Vec<_> = terms.iter().map(|t| (t.model, t.steps)).collect();
    // A one-shot path times its stages one by one (`lemke`, `lemke_polish`, `solve`).
    let stage = (!one_shot).then_some("friction");
    let Walked { last: (step, normal), u, histories } =
        super::drive(path, &bodies, &mut system, (stage, clock))?;
    let System { step_problem, searches, .. } = system;
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

/// The normal LCP of the answer given its tangential forces (`q = q_n + M_nt T`), for the
/// `lcp` record of the summary.
pub(in crate::pipeline) fn normal_lcp(
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
    use crate::pipeline::friction::StepEnd;

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
