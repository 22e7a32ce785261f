//! # mlpg-contact
//!
//! Two-dimensional linear elastostatics by the meshless *mixed* MLPG finite volume method
//! (MFVM) with moving least squares (MLS) approximation, after Erdönmez ("Solution of contact
//! problem using 'mixed' MLPG finite volume method with MLS approximations") and \[AHR04\].
//!
//! Find `u` with `div σ + b = 0` in `Ω`, `σ = D ε(u)`, `u = ū` on `Γ_u`, `σ·n = t̄` on `Γ_t`
//! (paper eqs. 6–7), discretised by the MFVM or by finite elements. Contact (`g ≥ 0, p ≥ 0,
//! g p = 0` on `Γ_c`) of a body with rigid obstacles (lines, circles, rounded polylines) or
//! between several elastic bodies is posed as the linear complementarity problem
//! `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0` and solved by Lemke's method on the condensed `M`, or
//! by a primal–dual active-set method on the sparse system without forming `M` (stage 7:
//! [`lcp`], on the systems of [`contact::sparse`]);
//! Coulomb friction and load steps follow the load path increment by increment
//! (docs/method.md §8).
//!
//! ## Example
//!
//! A block pressed onto a rigid line: its top edge moves down by 0.03 and its bottom edge,
//! 0.01 above the line, touches it.
//!
//! ```
//! let problem = mlpg_contact::problem::Problem::from_toml(r#"
//!     [geometry]
//!     kind = "rectangle"
//!     x = [0.0, 2.0]
//!     y = [0.0, 1.0]
//!     [nodes]
//!     spacing = 0.25
//!     [material]
//!     young = 1000.0
//!     poisson = 0.0
//!     plane = "stress"
//!     [[boundary]]
//!     edge = "top"
//!     displacement = { x = 0.0, y = -0.03 }
//!     [contact]
//!     edge = "bottom"
//!     obstacle_point = [0.0, -0.01]
//!     obstacle_normal = [0.0, 1.0]
//! "#).unwrap();
//! let solution = mlpg_contact::solve(&problem).unwrap();
//! let contact = solution.contact().unwrap();
//! // Uniform compression once the gap is closed: strain (0.03 − 0.01) / 1, stress E · 0.02 = 20
//! // over the width 2, so the line carries 40 and every candidate is closed.
//! assert!((contact.total_force - 40.0).abs() < 1e-6, "F = {}", contact.total_force);
//! assert!(contact.closed.iter().all(|&c| c));
//! assert!(solution.equilibrium_error < 1e-9);
//! ```
//!
//! The user guide (`docs/guide/` in the repository, an mdBook) describes every key of the
//! problem file; its page "Using the crate from Rust" goes on from this example.
//!
//! ## Pipeline
//!
//! The modules are the stages, in order; a module imports only modules of its own or an
//! earlier stage, and the module graph has no cycle (`tests/architecture.rs` reads this table
//! and checks every `crate::` path of `src/` against it).
//!
//! | stage | modules | produces |
//! |---|---|---|
//! | 0 | [`progress`], [`random`], [`geometry`], [`material`], [`system`] | stage timing and progress; a seeded generator; points, curves, the domain; elastic constants `D`; the machine's memory limits, resident set and cores |
//! | 1 | [`problem`] | the validated [`problem::Problem`], from TOML or from a [`problem::ProblemFile`] built in code |
//! | 2 | [`nodes`] | [`nodes::Nodes`] with boundary tags |
//! | 3 | [`neighbours`] | [`neighbours::Supports`] (MLS supports, cell grid) |
//! | 4 | [`mls`] | [`mls::ShapeSet`]: `φ`, `∇φ` at nodes and quadrature points |
//! | 5 | [`weak_form`] | subdomain cells `Ω_s`, faces, face quadrature |
//! | 6 | [`assembly`], [`fem`] | [`assembly::GlobalSystem`]: `K = −Q D [(1 − β) Φ S + β B_q]`, `f`, collocation rows; or the finite element system on a Q2 mesh |
//! | 7 | [`linear_solve`], [`lcp`] | [`linear_solve::Factorisation`] (sparse LU); the contact problem's algorithms, pure algebra: Lemke's method, the frictional step LCP, the load-driven searches, the primal–dual active-set iteration |
//! | 8 | [`model`] | [`model::Model`]: the discretised body, MFVM or FE ([`model::Scheme`]) |
//! | 9 | [`contact`] | candidates, gap `G`, force `E`, [`contact::CondensedContact`] `M = G K⁻¹ E`; the sparse systems of the active-set method ([`contact::sparse`]) |
//! | 10 | [`solution`], [`dynamics`], [`refine`] | recovery: displacement `u^h`, stress, reactions, the contact table, checks; Moreau–Jean time stepping with contact (mass, `M̂`, one LCP per step, history); the a posteriori estimate, marks and refined problem of adaptive refinement |
//! | 11 | [`post`] | outputs: CSV, VTU, plots, `summary.json` |
//! | 12 | [`error`] | [`Error`], one variant per stage |
//! | 13 | [`pipeline`] | orchestration: [`discretise`], [`solve_model`], [`solve`], [`run`], [`compare`] |
//!
//! The equations the modules cite (`docs/method.md §N`) are in the repository's
//! `docs/method.md`.
//!
//! ## Glossary
//!
//! | symbol | meaning |
//! |---|---|
//! | `û` | fictitious nodal parameters (MLS is not interpolating) |
//! | `u^h(x) = Σ φ_J(x) û_J` | the displacement field; every reported displacement is this |
//! | `ε̂_J` | strain collocated at node `J` (`ε̂ = S û`) |
//! | `Ω_s`, `Ω_I` | subdomain (cell) of node `I` |
//! | `α_s` | support factor: support radius `r_I = α_s h_I` |
//! | `β` | stabilisation blend (docs/method.md §3.9): face stress `D[(1 − β) Σ φ_J ε̂_J + β Σ B_K û_K]` |
//! | `Γ_u, Γ_t, Γ_c` | Dirichlet, traction and contact boundaries |
//! | `g`, `p` | gap and contact pressure |
//!
//! Spelling is British throughout ("neighbour", "discretisation", "factorisation").
//!
//! # References
//!
//! - \[AHR04\] Atluri, Han & Rajendran, "A new implementation of the meshless finite volume
//!   method, through the MLPG 'mixed' approach", CMES 6(6):491–513, 2004.
//! - \[LS81\] Lancaster & Salkauskas, "Surfaces generated by moving least squares methods",
//!   Math. Comp. 37:141–158, 1981.
//! - \[CPS92\] Cottle, Pang & Stone, *The Linear Complementarity Problem*, 1992 (Lemke, ch. 4).
//! - \[KO88\] Kikuchi & Oden, *Contact Problems in Elasticity*, SIAM 1988.
//! - \[X05\] Xiao, Gama, Gillespie & Kansa, EABE 29:95–106, 2005.
//! - \[TG70\] Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed., 1970 (cantilever, §21).
#![warn(rustdoc::broken_intra_doc_links)]

pub mod assembly;
pub mod contact;
pub mod dynamics;
pub mod error;
pub mod fem;
pub mod geometry;
pub mod lcp;
pub mod linear_solve;
pub mod material;
pub mod mls;
pub mod model;
pub mod neighbours;
pub mod nodes;
pub mod pipeline;
pub mod post;
pub mod problem;
pub mod progress;
pub mod random;
pub mod refine;
pub mod solution;
pub mod system;
pub mod weak_form;

pub use error::Error;
pub use model::Model;
pub use pipeline::{
    RunReport, compare, discretise, run, solve, solve_model, solve_model_with, solve_with_lemke,
};
pub use progress::{Progress, Silent, StageTiming};
pub use solution::{ContactSolution, Solution};

/// The user guide's Rust examples (`docs/guide/`), compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../docs/guide/doctests.md")]
pub struct GuideExamples;
