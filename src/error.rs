//! The crate error: one variant per pipeline stage, each wrapping that stage's typed error.

use crate::{
    assembly::AssemblyError, contact::ContactError, dynamics::DynamicsError, fem::FemError,
    geometry::GeometryError, lcp::LcpError, linear_solve::SolveError, mls::MlsError,
    post::OutputError, problem::ProblemError, weak_form::CellError,
};

/// Any failure of the pipeline, tagged by the stage that raised it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The problem description is invalid.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The geometry, node generation or boundary tagging failed (stage 0: [`crate::geometry`]).
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// An MLS moment matrix could not be factorised (stage 4: [`crate::mls`]).
    #[error(transparent)]
    Mls(#[from] MlsError),
    /// Subdomain cells could not be built (stage 5: [`crate::weak_form`]).
    #[error(transparent)]
    Cells(#[from] CellError),
    /// Assembly of the global system failed (stage 6: [`crate::assembly`]).
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The finite element discretisation failed (stage 6: [`crate::fem`], `method = "fem"`).
    #[error(transparent)]
    Fem(#[from] FemError),
    /// Factorisation or solve failed (stage 7: [`crate::linear_solve`]).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Contact candidates or condensation failed (stage 9: [`crate::contact`]).
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The LCP, its frictional step, a load-driven search or the active set failed (stage 7:
    /// [`crate::lcp`]).
    #[error(transparent)]
    Lcp(#[from] LcpError),
    /// Lemke's method failed numerically on the condensed contact problem (a terminated run
    /// whose result fails verification, or the pivot limit): the conditioning of `M`, the
    /// work done and what to do ([`LemkeRefusal`]).
    #[error("{0}")]
    LemkeRefused(Box<LemkeRefusal>),
    /// A load increment of a `[[step]]` path failed (docs/method.md §8): which one, and why.
    #[error(
        "load step {step} (`step[{index}]`), increment {increment} of {increments}: {cause}",
        index = step - 1
    )]
    Increment {
        /// The step, 1-based.
        step: usize,
        /// The increment within the step, 1-based.
        increment: usize,
        /// The step's increments.
        increments: usize,
        /// What failed.
        cause: Box<Error>,
    },
    /// The solution holds a value that is not finite.
    #[error(
        "the solution's {what} is not finite (NaN or infinite): the arithmetic overflowed or the system is singular; check the magnitudes of the loads and the material, and the displacement conditions"
    )]
    NonFinite {
        /// Which quantity.
        what: &'static str,
    },
    /// The run would need more memory than the process may use.
    #[error(
        "this problem needs about {gb:.1} GB ({nodes:.0} nodes), more than the {avail:.1} GB {limit} leaves: increase nodes.spacing (the memory grows as 1/spacing²), lower discretisation.support_factor{precision_hint}",
        gb = estimate / 1e9,
        avail = available / 1e9
    )]
    Memory {
        /// Estimated peak bytes.
        estimate: f64,
        /// Estimated node count.
        nodes: f64,
        /// Bytes the process may use.
        available: f64,
        /// Which limit.
        limit: &'static str,
        /// `", or set discretisation.precision = \"mixed\" (MFVM)"` when the factors would be
        /// double precision, else empty (the advice is already taken).
        precision_hint: &'static str,
    },
    /// Writing outputs failed (stage 11: [`crate::post`]).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The time stepping failed (stage 10: [`crate::dynamics`]).
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
}

impl From<crate::lcp::load_driven::LoadDrivenError> for Error {
    fn from(e: crate::lcp::load_driven::LoadDrivenError) -> Self {
        Error::Lcp(e.into())
    }
}

impl Error {
    /// The problem-file keys that decide this error, for a message that names the input
    /// (`None` for a validation error, which names its key itself).
    pub fn input_keys(&self) -> Option<&'static str> {
        use crate::assembly::AssemblyError as A;
        use crate::contact::ContactError as C;
        use crate::fem::FemError as F;
        use crate::lcp::LcpError as L;
        use crate::lcp::load_driven::LoadDrivenError as D;
        Some(match self {
            Error::Problem(_) => return None,
            Error::Geometry(_) => "geometry, nodes.spacing",
            Error::Mls(_) => "discretisation.support_factor, discretisation.basis, nodes.spacing",
            Error::Cells(_) => "geometry, nodes.spacing, nodes.layout",
            Error::Assembly(A::MissingFaceGradients { .. }) => "discretisation.beta",
            Error::Assembly(_) => "boundary[*].displacement",
            Error::Fem(F::NotRectangle { .. }) => "geometry.kind, discretisation.method",
            Error::Fem(F::NotStructured { .. }) => "nodes.layout, discretisation.method",
            Error::Fem(F::ElementKind { .. } | F::DegenerateElement { .. }) => "geometry.file",
            Error::Fem(_) => "boundary[*].displacement",
            Error::Solve(_) => "boundary[*].displacement, material, discretisation",
            Error::Contact(C::IndefiniteCompliance { .. }) => {
                "discretisation.support_factor, discretisation.beta, contact.allow_indefinite"
            }
            Error::Contact(C::TargetConstrained { .. }) => {
                "contact.target_edge, boundary of the second body"
            }
            Error::Contact(C::NoPartner { .. }) => "contact.edge, contact.target_edge, geometry",
            // The caller's inconsistency: no input key decides it.
            Error::Contact(C::MissingTangential { .. }) => return None,
            Error::Contact(_) => "contact.edge, boundary[*].displacement",
            Error::Lcp(L::FrictionNotConverged { .. }) => "contact.friction, step",
            Error::Lcp(L::ActiveSet(_)) => "contact.solver",
            Error::Lcp(L::LoadDriven(
                D::NotRestrained { .. }
                | D::NotPressed { .. }
                | D::Unsupported { .. }
                | D::SeveralHeld { .. }
                | D::FreeBody { .. },
            )) => "boundary[*].displacement, contact",
            Error::Lcp(L::LoadDriven(D::MovesWithObstacle { .. })) => {
                "boundary[*].displacement, step[*].obstacle_force"
            }
            Error::Lcp(L::LoadDriven(D::Undetermined { .. } | D::HeldNotConverged { .. })) => {
                "boundary[*] of the body named, body_force, contact"
            }
            Error::Lcp(L::LoadDriven(D::SlantedFriction { .. })) => {
                "step[*].obstacle_force, step[*].friction, contact.friction"
            }
            Error::Lcp(L::LoadDriven(_)) => "step[*].obstacle_force",
            Error::Lcp(_) => "contact, discretisation.support_factor, discretisation.beta",
            Error::LemkeRefused(_) => "contact.solver, nodes.spacing",
            Error::Increment { cause, .. } => return cause.input_keys(),
            Error::NonFinite { .. } => "material.young, boundary[*] values, body_force",
            Error::Memory { .. } => {
                "nodes.spacing, discretisation.support_factor, discretisation.precision"
            }
            Error::Output(_) => "--out",
            Error::Dynamics(crate::dynamics::DynamicsError::ActiveSet { .. }) => {
                "contact.solver, dynamics.time_step"
            }
            Error::Dynamics(_) => "dynamics.time_step, contact, material",
        })
    }
}

/// Why Lemke's method could not answer a frictionless contact problem whose compliance `M`
/// passed its checks (docs/method.md §4.1, §5): Lemke's own error, the extreme eigenvalues of
/// the symmetric part of `M` (those of the checks, not computed again), the pivots done, the
/// residual reached, and what to do.
#[derive(Debug)]
pub struct LemkeRefusal {
    /// Lemke's error: [`LcpError::InaccurateSolution`], [`LcpError::PivotLimit`] or
    /// [`LcpError::RayTermination`] (impossible in exact arithmetic for a positive definite
    /// symmetric part).
    pub cause: LcpError,
    /// Contact candidates (the size of `M`).
    pub candidates: usize,
    /// Pivots done.
    pub pivots: usize,
    /// The largest scaled violation of the terminated run (`−min z`, `−min w`,
    /// complementarity; [`crate::lcp::LcpResiduals`]); `None` when the run did not terminate.
    pub residual: Option<f64>,
    /// Smallest eigenvalue of `(M + Mᵀ)/2`.
    pub min_symmetric_eigenvalue: f64,
    /// Largest eigenvalue of `(M + Mᵀ)/2`.
    pub max_symmetric_eigenvalue: f64,
    /// Whether `contact.solver = "active_set"` takes this problem (every problem the pipeline
    /// refuses this way: the sparse system has every path the condensed one has).
    pub active_set_applies: bool,
    /// The active-set solver's error when `"auto"` tried it after Lemke and it failed too.
    pub active_set_failure: Option<String>,
}

impl LemkeRefusal {
    /// The refusal of a Lemke run that ended with `cause` on an `M` of `candidates` rows whose
    /// symmetric part has the extreme eigenvalues `min`, `max`.
    ///
    /// # Errors
    /// `cause` itself when it is not a numerical failure (an invalid parameter, a dimension
    /// mismatch, …).
    pub fn new(
        cause: LcpError,
        candidates: usize,
        [min, max]: [f64; 2],
        active_set_applies: bool,
    ) -> Result<Self, LcpError> {
        let (pivots, residual) = match &cause {
            LcpError::InaccurateSolution { pivots, min_z, min_w, max_complementarity, .. } => {
                (*pivots, Some(max_complementarity.max(-min_z).max(-min_w)))
            }
            LcpError::PivotLimit { limit } => (*limit, None),
            LcpError::RayTermination { pivots } => (*pivots, None),
            _ => return Err(cause),
        };
        Ok(Self {
            cause,
            candidates,
            pivots,
            residual,
            min_symmetric_eigenvalue: min,
            max_symmetric_eigenvalue: max,
            active_set_applies,
            active_set_failure: None,
        })
    }

    /// `λ_min / λ_max` of the symmetric part of `M`.
    pub fn eigenvalue_ratio(&self) -> f64 {
        self.min_symmetric_eigenvalue / self.max_symmetric_eigenvalue
    }
}

impl std::fmt::Display for LemkeRefusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.diagnosis(f)?;
        match (&self.active_set_failure, self.active_set_applies) {
            (Some(e), _) => write!(
                f,
                ". The active-set solver was tried next and failed too ({e}); use a coarser \
                 contact edge (a larger nodes.spacing)"
            ),
            (None, true) => write!(
                f,
                ". Set `[contact] solver = \"active_set\"` (it never forms M), or use a coarser \
                 contact edge (a larger nodes.spacing)"
            ),
            (None, false) => write!(f, ". Use a coarser contact edge (a larger nodes.spacing)"),
        }
    }
}

impl LemkeRefusal {
    /// What failed and the conditioning of `M`, without the advice (the record of an `"auto"`
    /// run that the active-set solver answered after Lemke failed).
    pub fn diagnosis_text(&self) -> String {
        struct D<'a>(&'a LemkeRefusal);
        impl std::fmt::Display for D<'_> {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                self.0.diagnosis(f)
            }
        }
        D(self).to_string()
    }

    fn diagnosis(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Lemke's method could not solve the contact problem ({} candidates): it stopped after \
             {} pivots",
            self.candidates, self.pivots
        )?;
        match self.residual {
            Some(r) => write!(f, " with a scaled residual of {r:.1e} (accepted up to 1e-6)")?,
            None => write!(f, " without a verified answer")?,
        }
        write!(
            f,
            " [{}]. The conditioning of M: the eigenvalues of its symmetric part run from {:.3e} \
             to {:.3e} (ratio {:.1e}; the smaller the ratio, the more digits Lemke's dense \
             pivoting loses)",
            self.cause,
            self.min_symmetric_eigenvalue,
            self.max_symmetric_eigenvalue,
            self.eigenvalue_ratio()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The refusal's residual is the worst scaled violation of the terminated run; errors that
    /// are not numerical failures are handed back; the message carries the numbers and the
    /// advice, or the active-set solver's failure.
    #[test]
    fn lemke_refusal_from_lemke_errors() {
        let inaccurate = LcpError::InaccurateSolution {
            pivots: 7,
            min_z: -3e-4,
            min_w: -1e-5,
            max_complementarity: 2e-7,
            threshold: 1e-6,
        };
        let mut r = LemkeRefusal::new(inaccurate, 5, [1e-6, 1e4], true).unwrap();
        assert_eq!((r.pivots, r.candidates, r.residual), (7, 5, Some(3e-4)));
        assert_eq!(r.eigenvalue_ratio(), 1e-6 / 1e4);
        let text = r.to_string();
        for part in [
            "(5 candidates)",
            "after 7 pivots with a scaled residual of 3.0e-4",
            "from 1.000e-6 to 1.000e4 (ratio 1.0e-10",
            "solver = \"active_set\"",
        ] {
            assert!(text.contains(part), "`{part}` missing: {text}");
        }
        assert!(text.starts_with(&r.diagnosis_text()) && !r.diagnosis_text().contains("Set"));
        r.active_set_failure = Some("it failed".into());
        assert!(r.to_string().contains("failed too (it failed)"));
        assert!(!r.to_string().contains("solver = \"active_set\""));
        let limit = LemkeRefusal::new(LcpError::PivotLimit { limit: 3 }, 2, [1.0, 2.0], false);
        let limit = limit.unwrap();
        assert_eq!((limit.pivots, limit.residual), (3, None));
        assert!(!limit.to_string().contains("active_set"));
        let other = LcpError::DimensionMismatch { what: "q", expected: 2, found: 1 };
        assert!(matches!(
            LemkeRefusal::new(other, 2, [1.0, 2.0], true),
            Err(LcpError::DimensionMismatch { .. })
        ));
    }
}
