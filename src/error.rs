//! The crate error: one variant per pipeline stage, each wrapping that stage's typed error.

use crate::{
    assembly::AssemblyError, contact::ContactError, fem::FemError, geometry::GeometryError,
    lcp::LcpError, linear_solve::SolveError, mls::MlsError, post::OutputError,
    problem::ProblemError, weak_form::CellError,
};

/// Any failure of the pipeline, tagged by the stage that raised it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The problem description is invalid.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// Node generation or boundary tagging failed (stage 1).
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// An MLS moment matrix could not be factorised (stage 3).
    #[error(transparent)]
    Mls(#[from] MlsError),
    /// Subdomain cells could not be built (stage 4).
    #[error(transparent)]
    Cells(#[from] CellError),
    /// Assembly of the global system failed (stage 5).
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The finite element discretisation failed (stages 1–5 with `method = "fem"`).
    #[error(transparent)]
    Fem(#[from] FemError),
    /// Factorisation or solve failed (stage 6).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Contact candidates or condensation failed (stage 7).
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The LCP has no solution or Lemke failed (stage 8).
    #[error(transparent)]
    Lcp(#[from] LcpError),
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
        "this problem needs about {gb:.1} GB ({nodes:.0} nodes), more than the {avail:.1} GB {limit} leaves: increase nodes.spacing (the memory grows as 1/spacing²), or lower discretisation.support_factor",
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
    },
    /// Writing outputs failed (stage 9).
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl Error {
    /// The problem-file keys that decide this error, for a message that names the input
    /// (`None` for a validation error, which names its key itself).
    pub fn input_keys(&self) -> Option<&'static str> {
        use crate::assembly::AssemblyError as A;
        use crate::contact::ContactError as C;
        use crate::fem::FemError as F;
        use crate::lcp::LcpError as L;
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
            Error::Fem(F::Gmsh(_)) => "geometry.surface",
            Error::Fem(_) => "boundary[*].displacement",
            Error::Solve(_) => "boundary[*].displacement, material, discretisation",
            Error::Contact(C::IndefiniteCompliance { .. }) => {
                "discretisation.support_factor, discretisation.beta, contact.allow_indefinite"
            }
            Error::Contact(C::TargetConstrained { .. } | C::CurvedTarget { .. }) => {
                "contact.target_edge, boundary of the second body"
            }
            Error::Contact(C::NoPartner { .. }) => "contact.edge, contact.target_edge, geometry",
            Error::Contact(_) => "contact.edge, boundary[*].displacement",
            Error::Lcp(L::FrictionNotConverged { .. }) => "contact.friction, step",
            Error::Lcp(L::ActiveSet(_)) => "contact.solver",
            Error::Lcp(_) => "contact, discretisation.support_factor, discretisation.beta",
            Error::Increment { cause, .. } => return cause.input_keys(),
            Error::NonFinite { .. } => "material.young, boundary[*] values, body_force",
            Error::Memory { .. } => "nodes.spacing, discretisation.support_factor",
            Error::Output(_) => "--out",
        })
    }
}
