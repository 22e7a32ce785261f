//! Isotropic linear elasticity in 2-D: plane stress, plane strain and axisymmetric constitutive
//! matrices.

use serde::{Deserialize, Serialize};

/// Which 2-D reduction of 3-D elasticity is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneState {
    /// Thin body, `σ_zz = 0`.
    Stress,
    /// Long body, `ε_zz = 0`.
    Strain,
    /// A body of revolution under axisymmetric loads: `x` is the radius `r ≥ 0`, `y` the axis
    /// `z`, and the hoop strain `ε_θθ = u_r / r` is the fourth strain (docs/method.md §9).
    Axisymmetric,
}

/// An isotropic, linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Material {
    /// Young's modulus `E` [force/length²].
    pub young: f64,
    /// Poisson's ratio `ν` [-], `0 ≤ ν < 0.5`.
    pub poisson: f64,
    /// Plane stress, plane strain or axisymmetric.
    pub plane: PlaneState,
}

/// Constitutive matrix `D` in Voigt order `(ε_xx, ε_yy, γ_xy)`, `σ = D ε`.
pub type Constitutive = [[f64; 3]; 3];

/// The hoop column and row of the axisymmetric constitutive law (docs/method.md §9.1): with
/// the in-plane block `D` of [`Material::constitutive`] (the plane-strain matrix),
/// `(σ_rr, σ_zz, σ_rz) = D (ε_rr, ε_zz, γ_rz) + λ ε_θθ (1, 1, 0)` and
/// `σ_θθ = λ (ε_rr + ε_zz) + (λ + 2μ) ε_θθ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hoop {
    /// `λ`: the coupling of the hoop strain to `σ_rr`, `σ_zz` and of `ε_rr`, `ε_zz` to `σ_θθ`.
    pub coupling: f64,
    /// `λ + 2μ`: `∂σ_θθ/∂ε_θθ`.
    pub diagonal: f64,
}

impl Hoop {
    /// The fourth row of `D₄`: `σ_θθ = row · (ε_rr, ε_zz, γ_rz, ε_θθ)`.
    pub fn row(&self) -> [f64; 4] {
        [self.coupling, self.coupling, 0.0, self.diagonal]
    }

    /// `σ_θθ` of the in-plane strain `e` and the hoop strain `hoop`.
    pub fn stress(&self, e: [f64; 3], hoop: f64) -> f64 {
        self.coupling * (e[0] + e[1]) + self.diagonal * hoop
    }

    /// The in-plane stress `(σ_rr, σ_zz, σ_rz)` of `e` and `hoop` with the in-plane block `d`.
    pub fn in_plane(&self, d: &Constitutive, e: [f64; 3], hoop: f64) -> [f64; 3] {
        let s = apply(d, e);
        [s[0] + self.coupling * hoop, s[1] + self.coupling * hoop, s[2]]
    }

    /// The full `D₄` in the order `(ε_rr, ε_zz, γ_rz, ε_θθ)` (rows `σ_rr, σ_zz, σ_rz, σ_θθ`).
    pub fn full(&self, d: &Constitutive) -> [[f64; 4]; 4] {
        let c = self.coupling;
        [
            [d[0][0], d[0][1], d[0][2], c],
            [d[1][0], d[1][1], d[1][2], c],
            [d[2][0], d[2][1], d[2][2], 0.0],
            self.row(),
        ]
    }
}

impl Material {
    /// The in-plane effective modulus and Poisson ratio `(E', ν')`:
    /// plane stress `(E, ν)`, plane strain `(E/(1−ν²), ν/(1−ν))`; axisymmetric as plane strain
    /// (the in-plane block of `D₄` is the plane-strain matrix).
    pub fn effective(&self) -> (f64, f64) {
        match self.plane {
            PlaneState::Stress => (self.young, self.poisson),
            PlaneState::Strain | PlaneState::Axisymmetric => {
                let nu = self.poisson;
                (self.young / (1.0 - nu * nu), nu / (1.0 - nu))
            }
        }
    }

    /// `D = E'/(1−ν'²)·[[1, ν', 0], [ν', 1, 0], [0, 0, (1−ν')/2]]` (docs/method.md §1); in
    /// axisymmetry the in-plane block of `D₄`, completed by [`Self::hoop`].
    pub fn constitutive(&self) -> Constitutive {
        let (e, nu) = self.effective();
        let c = e / (1.0 - nu * nu);
        [[c, c * nu, 0.0], [c * nu, c, 0.0], [0.0, 0.0, c * (1.0 - nu) / 2.0]]
    }

    /// The hoop row and column of the axisymmetric law (`None` in plane stress and strain).
    pub fn hoop(&self) -> Option<Hoop> {
        match self.plane {
            PlaneState::Axisymmetric => {
                let (e, nu) = (self.young, self.poisson);
                let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
                Some(Hoop { coupling: lambda, diagonal: lambda + 2.0 * self.shear_modulus() })
            }
            PlaneState::Stress | PlaneState::Strain => None,
        }
    }

    /// Whether `x` is the radius and `y` the axis of a body of revolution.
    pub fn is_axisymmetric(&self) -> bool {
        self.plane == PlaneState::Axisymmetric
    }

    /// Shear modulus `μ = E / (2(1+ν))`.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Out-of-plane stress for a given in-plane stress: `σ_zz`, zero in plane stress and
    /// `ν(σ_xx + σ_yy)` in plane strain; in axisymmetry the hoop stress `σ_θθ`, which is not a
    /// function of the in-plane stress and is given as `hoop` (ignored otherwise).
    pub fn out_of_plane(&self, sigma: [f64; 3], hoop: Option<f64>) -> f64 {
        match self.plane {
            PlaneState::Stress => 0.0,
            PlaneState::Strain => self.poisson * (sigma[0] + sigma[1]),
            PlaneState::Axisymmetric => hoop.unwrap_or(f64::NAN),
        }
    }

    /// Out-of-plane stress `σ_zz` for a given in-plane stress (zero in plane stress; NaN in
    /// axisymmetry, where [`Self::out_of_plane`] needs the hoop stress).
    pub fn sigma_zz(&self, sigma: [f64; 3]) -> f64 {
        self.out_of_plane(sigma, None)
    }

    /// Von Mises equivalent stress of an in-plane stress state (with `σ_zz` from
    /// [`Self::sigma_zz`]; in axisymmetry use [`Self::von_mises_with`]).
    pub fn von_mises(&self, sigma: [f64; 3]) -> f64 {
        self.von_mises_with(sigma, None)
    }

    /// Von Mises equivalent stress with the out-of-plane stress of [`Self::out_of_plane`].
    pub fn von_mises_with(&self, sigma: [f64; 3], hoop: Option<f64>) -> f64 {
        let [sx, sy, txy] = sigma;
        let sz = self.out_of_plane(sigma, hoop);
        (0.5 * ((sx - sy).powi(2) + (sy - sz).powi(2) + (sz - sx).powi(2)) + 3.0 * txy * txy).sqrt()
    }
}

/// `σ = D ε` for a Voigt strain.
pub fn apply(d: &Constitutive, eps: [f64; 3]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (i, row) in d.iter().enumerate() {
        s[i] = row[0] * eps[0] + row[1] * eps[1] + row[2] * eps[2];
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_matches_lame_form() {
        let m = Material { young: 210.0, poisson: 0.3, plane: PlaneState::Strain };
        let (e, nu) = (m.young, m.poisson);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = m.shear_modulus();
        let d = m.constitutive();
        assert!((d[0][0] - (lambda + 2.0 * mu)).abs() < 1e-12 * d[0][0]);
        assert!((d[0][1] - lambda).abs() < 1e-12 * d[0][0]);
        assert!((d[2][2] - mu).abs() < 1e-12 * d[0][0]);
    }

    /// `D₄` is the isotropic law in cylindrical components: uniaxial stress along the axis,
    /// `ε = (−ν, 1, 0, −ν)/E`, gives `σ = (0, 1, 0, 0)`.
    #[test]
    fn axisymmetric_uniaxial_along_the_axis() {
        let m = Material { young: 200.0, poisson: 0.3, plane: PlaneState::Axisymmetric };
        let hoop = m.hoop().expect("axisymmetric");
        let d4 = hoop.full(&m.constitutive());
        let e = [-0.3 / 200.0, 1.0 / 200.0, 0.0, -0.3 / 200.0];
        let s: Vec<f64> = d4.iter().map(|r| (0..4).map(|k| r[k] * e[k]).sum()).collect();
        for (got, want) in s.iter().zip([0.0, 1.0, 0.0, 0.0]) {
            assert!((got - want).abs() < 1e-14, "{s:?}");
        }
        assert!(Material { plane: PlaneState::Strain, ..m }.hoop().is_none());
    }

    #[test]
    fn plane_stress_uniaxial() {
        let m = Material { young: 100.0, poisson: 0.25, plane: PlaneState::Stress };
        let d = m.constitutive();
        // ε = (1, −ν, 0) is uniaxial stress σ = (E, 0, 0).
        let s = apply(&d, [1.0, -0.25, 0.0]);
        assert!((s[0] - 100.0).abs() < 1e-12 && s[1].abs() < 1e-12);
    }
}
