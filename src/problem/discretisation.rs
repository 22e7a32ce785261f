//! Discretisation parameters: the method, the MLS approximation, the node layout, the
//! stabilisation blend and the presets, with the stability limits of the pure mixed method.

use serde::{Deserialize, Serialize};

/// Which discretisation solves the problem.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The meshless mixed MLPG finite volume method (default).
    #[default]
    Mfvm,
    /// Biquadratic (Q2, 9-node) finite elements on a structured mesh of a rectangle
    /// ([`crate::fem`]); an independent check of the MFVM.
    Fem,
}

/// `discretisation.precision`: the precision of the stored factors of `K` (MFVM; the finite
/// element model is always factorised in double precision).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// Double-precision factors (the default).
    #[default]
    Double,
    /// Single-precision factors of the static-pivoting LU, refined to the double-precision
    /// backward error (iterative refinement, then GMRES-IR): about 0.6 times the memory;
    /// a solve that does not reach that accuracy is refused, never returned.
    Mixed,
    /// [`Precision::Mixed`] when the memory estimate in double precision exceeds what the
    /// process may use, [`Precision::Double`] otherwise.
    Auto,
}

impl Precision {
    /// `true` for the default (not echoed in `summary.json`, so that summaries without the
    /// key are unchanged).
    pub fn is_double(&self) -> bool {
        *self == Precision::Double
    }
}

/// A named set of discretisation parameters (`discretisation = "paper"` or
/// `discretisation = "stabilised"` in a problem file, or `preset = …` inside the
/// `[discretisation]` table, whose other keys then override the preset's values).
///
/// Chosen from the stabilisation study (docs/dev/beta_study.md, "Time to accuracy and the presets"): on the beam on a rigid
/// foundation and the Hertz cylinder, [`Preset::Stabilised`] reaches the accuracy
/// targets (contact onset within 0.05 and total force within 0.1 % on the beam; Hertz `a`
/// within 1 % and `p₀` within 0.5 %) in a fraction of the paper's time, with half its matrix
/// nonzeros; the paper's method is more accurate in the total contact force at equal spacing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The paper's mixed MFVM: linear basis, `α_s = 2`, `β = 0`, 2 Gauss points per segment
    /// (the defaults).
    Paper,
    /// The stabilised MFVM with direct MLS strains at the cell boundaries: linear basis,
    /// `α_s = 2`, `β = 1`, 2 Gauss points per segment (docs/method.md §3.9).
    Stabilised,
}

impl Preset {
    /// All presets with their problem-file names.
    pub const ALL: [(&'static str, Preset); 2] =
        [("paper", Preset::Paper), ("stabilised", Preset::Stabilised)];

    /// The preset's `(basis, support_factor, beta, quadrature_points)`.
    pub fn values(self) -> (Basis, f64, f64, usize) {
        match self {
            Preset::Paper => (Basis::Linear, 2.0, 0.0, 2),
            Preset::Stabilised => (Basis::Linear, 2.0, 1.0, 2),
        }
    }
}

/// Discretisation parameters of the mixed MFVM (and the choice of method).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Discretisation {
    /// The preset the values started from, if the problem file named one.
    pub preset: Option<Preset>,
    /// The method (default [`Method::Mfvm`]); the MLS and face-quadrature fields are ignored
    /// by [`Method::Fem`].
    pub method: Method,
    /// MLS approximation parameters.
    pub mls: MlsParams,
    /// Gauss–Legendre points per cell-boundary segment for the field traction (default 2).
    pub quadrature_points: usize,
    /// Gauss–Legendre points per segment for applied tractions (default 5, at least 3).
    pub load_quadrature_points: usize,
    /// Stabilisation blend `β ∈ [0, 1]` (docs/method.md §3.9): the stress at a cell-boundary
    /// Gauss point `x_q` is `σ_q = D[(1 − β) Σ_J φ_J(x_q) ε̂_J + β Σ_K B_K(x_q) û_K]`.
    /// `β = 0` (default) is the paper's mixed method; `β = 1` a primal finite-volume scheme
    /// that never uses the collocated strains `S`.
    pub beta: f64,
    /// `beta = "auto"`: `β = 0` (the paper's method), and when the condensed contact
    /// compliance at `β = 0` fails its run-time checks the run is repeated once at
    /// [`AUTO_BETA`] (docs/dev/beta_study.md) by the run ([`crate::pipeline::Outcome::solve`]:
    /// the command line, `run`, Python); [`crate::pipeline::solve`] solves once at `β` as
    /// given. The problem file's default for the MFVM when
    /// neither `beta` nor `preset` is given ([`Discretisation::default`], for problems built in
    /// code, keeps `β = 0` without a second attempt). Not echoed when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub beta_auto: bool,
    /// Accept a combination outside the stability limits of [`Discretisation::stability_warning`]
    /// (the refusal becomes a warning recorded in `summary.json`).
    pub allow_unstable: bool,
    /// Precision of the factors of `K` (default [`Precision::Double`]).
    #[serde(skip_serializing_if = "Precision::is_double")]
    pub precision: Precision,
}

impl Default for Discretisation {
    fn default() -> Self {
        Self {
            preset: None,
            method: Method::Mfvm,
            mls: MlsParams::default(),
            quadrature_points: 2,
            load_quadrature_points: 5,
            beta: 0.0,
            beta_auto: false,
            allow_unstable: false,
            precision: Precision::Double,
        }
    }
}

/// Largest support factor accepted for the pure mixed method (`β = 0`) with a linear basis.
pub const MIXED_LINEAR_MAX_SUPPORT_FACTOR: f64 = 2.25;
/// Largest support factor accepted for the pure mixed method (`β = 0`) with a quadratic basis.
/// A limit of 3 was proposed first; the parameter study (docs/param_study.md) measured `α_s = 3` failing the
/// run-time `M` checks on the paper's beam at h = 1 and 0.125 (84 contact intervals) and its
/// cantilever energy error growing from h = 0.5 to 0.25, while 2.5 was intact everywhere.
pub const MIXED_QUADRATIC_MAX_SUPPORT_FACTOR: f64 = 2.5;
/// Smallest blend `β` that lifts those limits. The gap s₄/s_max above the rigid modes of a
/// free body grows roughly in proportion to `β` (9 × 9 nodes, α_s = 3: 5e-5 at β = 0.001,
/// 3.4e-4 at 0.01, 2.4e-3 at 0.1, 1.9e-2 at 1; tests/validation/free_body.rs), so a tiny `β`
/// is as unstable as `β = 0`; docs/method.md §3.9 measured `β ≥ 0.1` sufficient for α_s 2–4.
pub const MIN_STABILISING_BETA: f64 = 0.1;
/// The blend a `beta = "auto"` run repeats with when `M` at `β = 0` is not trustworthy: the
/// stabilised blend the refusal has always advised (docs/method.md §3.9).
pub const AUTO_BETA: f64 = 0.5;

/// `discretisation.beta` as written: a number in `[0, 1]` or `"auto"`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BetaChoice {
    /// A fixed blend.
    Value(f64),
    /// `"auto"` ([`Discretisation::beta_auto`]).
    Auto(AutoKeyword),
}

/// The keyword `"auto"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AutoKeyword {
    /// `"auto"`.
    Auto,
}

impl Discretisation {
    /// Why this combination is outside the measured stability limits of the pure mixed method,
    /// or `None` when it is inside them.
    ///
    /// With `β = 0` the collocated strains are smoothed by supports larger than about
    /// `α_s = 2.25` (linear basis) or `α_s = 2.5` (quadratic basis) so much that checkerboard
    /// displacement modes become nearly free (docs/method.md §2, §3.8: s₄/s_max ≈ 7e-7 at
    /// `α_s = 3` on a 9 × 9 free body) and the contact compliance loses its positive diagonal
    /// (§4.1). A blend `β ≥` [`MIN_STABILISING_BETA`] lifts these limits (§3.9); a smaller
    /// positive `β` is treated like `β = 0`.
    pub fn stability_warning(&self) -> Option<String> {
        if self.beta >= MIN_STABILISING_BETA {
            return None;
        }
        let alpha = self.mls.support_factor;
        let limit = match self.mls.basis {
            Basis::Linear => MIXED_LINEAR_MAX_SUPPORT_FACTOR,
            Basis::Quadratic => MIXED_QUADRATIC_MAX_SUPPORT_FACTOR,
        };
        (alpha > limit).then(|| {
            format!(
                "support_factor = {alpha} with the {} basis and beta = {} ({}) is unstable above {limit}: the collocated strains admit nearly free checkerboard modes and contact answers become meaningless (docs/method.md §3.8); use support_factor <= {limit}, or beta = 0.5 (stabilised MFVM, docs/method.md §3.9; at least {MIN_STABILISING_BETA}), or set allow_unstable = true to proceed anyway",
                self.mls.basis.name(),
                self.beta,
                if self.beta == 0.0 { "the pure mixed method" } else { "too little stabilisation" }
            )
        })
    }
}

/// Parameters of the MLS approximation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MlsParams {
    /// Polynomial basis (linear by default).
    pub basis: Basis,
    /// Support factor `α_s`: node `I` has support radius `r_I = α_s h_I` (default 2).
    pub support_factor: f64,
    /// Smallest accepted reciprocal 1-norm condition number of a moment matrix (default 1e-10).
    pub min_rcond: f64,
}

impl Default for MlsParams {
    fn default() -> Self {
        Self { basis: Basis::Linear, support_factor: 2.0, min_rcond: 1e-10 }
    }
}

/// Polynomial basis `p` of the MLS approximation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// `p = (1, ξ, η)` (default; \[AHR04\] shows a low order suffices for the mixed method).
    Linear,
    /// `p = (1, ξ, η, ξ², ξη, η²)`.
    Quadratic,
}

impl Basis {
    /// Number of terms `m`.
    pub fn terms(self) -> usize {
        match self {
            Basis::Linear => 3,
            Basis::Quadratic => 6,
        }
    }

    /// Name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Basis::Linear => "linear",
            Basis::Quadratic => "quadratic",
        }
    }
}

/// How nodes are laid out in the domain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Layout {
    /// A regular grid (rectangles: exact fit of the spacing to the sides).
    Structured,
    /// The regular grid with interior nodes moved by a seeded uniform random offset of at most
    /// `amplitude · h` in each coordinate (`0 < amplitude ≤ 0.4`).
    Jittered {
        /// Maximum offset as a fraction of the spacing.
        amplitude: f64,
        /// Seed of the deterministic generator.
        seed: u64,
    },
}
