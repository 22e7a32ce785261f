//! Isotropic linear elasticity in 2-D: plane stress and plane strain constitutive matrices.

use serde::{Deserialize, Serialize};

/// Which 2-D reduction of 3-D elasticity is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneState {
    /// Thin body, `σ_zz = 0`.
    Stress,
    /// Long body, `ε_zz = 0`.
    Strain,
}

/// An isotropic, linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Material {
    /// Young's modulus `E` [force/length²].
    pub young: f64,
    /// Poisson's ratio `ν` [-], `0 ≤ ν < 0.5`.
    pub poisson: f64,
    /// Plane stress or plane strain.
    pub plane: PlaneState,
}

/// Constitutive matrix `D` in Voigt order `(ε_xx, ε_yy, γ_xy)`, `σ = D ε`.
pub type Constitutive = [[f64; 3]; 3];

impl Material {
    /// The in-plane effective modulus and Poisson ratio `(E', ν')`:
    /// plane stress `(E, ν)`, plane strain `(E/(1−ν²), ν/(1−ν))`.
    pub fn effective(&self) -> (f64, f64) {
        match self.plane {
            PlaneState::Stress => (self.young, self.poisson),
            PlaneState::Strain => {
                let nu = self.poisson;
                (self.young / (1.0 - nu * nu), nu / (1.0 - nu))
            }
        }
    }

    /// `D = E'/(1−ν'²)·[[1, ν', 0], [ν', 1, 0], [0, 0, (1−ν')/2]]` (docs/method.md §1).
    pub fn constitutive(&self) -> Constitutive {
        let (e, nu) = self.effective();
        let c = e / (1.0 - nu * nu);
        [[c, c * nu, 0.0], [c * nu, c, 0.0], [0.0, 0.0, c * (1.0 - nu) / 2.0]]
    }

    /// Shear modulus `μ = E / (2(1+ν))`.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Out-of-plane stress `σ_zz` for a given in-plane stress (zero in plane stress).
    pub fn sigma_zz(&self, sigma: [f64; 3]) -> f64 {
        match self.plane {
            PlaneState::Stress => 0.0,
            PlaneState::Strain => self.poisson * (sigma[0] + sigma[1]),
        }
    }

    /// Von Mises equivalent stress of an in-plane stress state (with `σ_zz` from [`Self::sigma_zz`]).
    pub fn von_mises(&self, sigma: [f64; 3]) -> f64 {
        let [sx, sy, txy] = sigma;
        let sz = self.sigma_zz(sigma);
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

    #[test]
    fn plane_stress_uniaxial() {
        let m = Material { young: 100.0, poisson: 0.25, plane: PlaneState::Stress };
        let d = m.constitutive();
        // ε = (1, −ν, 0) is uniaxial stress σ = (E, 0, 0).
        let s = apply(&d, [1.0, -0.25, 0.0]);
        assert!((s[0] - 100.0).abs() < 1e-12 && s[1].abs() < 1e-12);
    }
}
