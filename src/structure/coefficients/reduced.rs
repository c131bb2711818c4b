//! Evaluation of the eta-dependent inertia of (3.2.1) from the constant coefficients.

// Index loops mirror the matrix formulas (3.2.8)-(3.2.12) entry by entry.
#![allow(clippy::needless_range_loop)]

use super::{CoefficientError, ReducedModel};

type M3 = [[f64; 3]; 3];

/// `a^×` as an array.
fn skew(a: [f64; 3]) -> M3 {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}

impl ReducedModel {
    /// Number of flexible coordinates `n`.
    pub fn n(&self) -> usize {
        self.n_modes as usize
    }

    /// Size of `v = (V_B, ω_B, η̇)`: `6 + n`.
    pub fn dim(&self) -> usize {
        6 + self.n()
    }

    fn check_eta(&self, eta: &[f64]) -> Result<(), CoefficientError> {
        if eta.len() != self.n() {
            return Err(CoefficientError::LengthMismatch {
                what: "eta",
                expected: self.n(),
                found: eta.len(),
            });
        }
        Ok(())
    }

    /// `c̄_tot = c + P̄ η`, eqs. (3.2.8), (3.2.10).
    pub fn c_tot(&self, eta: &[f64]) -> Result<[f64; 3], CoefficientError> {
        self.check_eta(eta)?;
        let n = self.n();
        let mut c = self.first_moment;
        for (i, ci) in c.iter_mut().enumerate() {
            *ci += (0..n).map(|m| self.p_bar[i * n + m] * eta[m]).sum::<f64>();
        }
        Ok(c)
    }

    /// `J̄_tot = J + J̄_ru + J̄_ru^T + J̄_uu`, eqs. (3.2.9), (3.2.11), (3.2.12), with
    /// `J̄_ru = Σ_m η_m J̄'_ru,m` and `J̄_uu = Σ_mp η_m η_p J̄''_uu,mp`.
    pub fn j_tot(&self, eta: &[f64]) -> Result<M3, CoefficientError> {
        self.check_eta(eta)?;
        let n = self.n();
        let mut j = self.inertia;
        for i in 0..3 {
            for k in 0..3 {
                for m in 0..n {
                    j[i][k] += eta[m] * (self.j_ru[m][i][k] + self.j_ru[m][k][i]);
                    for p in 0..n {
                        j[i][k] += eta[m] * eta[p] * self.j_uu[m * n + p][i][k];
                    }
                }
            }
        }
        Ok(j)
    }

    /// `H̄_tot = H̄ + Σ_m η_m H̄'_m` (3 x n, row-major), eqs. (3.2.4)-(3.2.6).
    pub fn h_tot(&self, eta: &[f64]) -> Result<Vec<f64>, CoefficientError> {
        let mut h = vec![0.0; 3 * self.n()];
        self.h_tot_into(eta, &mut h)?;
        Ok(h)
    }

    /// [`Self::h_tot`] into a caller's buffer of length `3 n` (no allocation).
    pub fn h_tot_into(&self, eta: &[f64], h: &mut [f64]) -> Result<(), CoefficientError> {
        self.check_eta(eta)?;
        let n = self.n();
        if h.len() != 3 * n {
            return Err(CoefficientError::LengthMismatch {
                what: "H_tot buffer",
                expected: 3 * n,
                found: h.len(),
            });
        }
        h.copy_from_slice(&self.h_bar);
        for m in 0..n {
            for i in 0..3 {
                for p in 0..n {
                    h[i * n + p] += eta[m] * self.h_prime[(m * 3 + i) * n + p];
                }
            }
        }
        Ok(())
    }

    /// The mass matrix of (3.2.1), `M_tot(η)` ((6+n) x (6+n), row-major, written into `out`):
    /// ```text
    /// [ m 1        -c̄_tot^×   P̄       ]
    /// [ c̄_tot^×    J̄_tot      H̄_tot   ]
    /// [ P̄^T        H̄_tot^T    M̄       ]
    /// ```
    /// It is the Hessian of `T = ½ v^T M_tot(η) v` in `v = (V_B, ω_B, η̇)`, exactly quadratic
    /// in `η` (module `coefficients::reduce` gives the derivation).
    pub fn mass_matrix_into(&self, eta: &[f64], out: &mut [f64]) -> Result<(), CoefficientError> {
        let d = self.dim();
        if out.len() != d * d {
            return Err(CoefficientError::LengthMismatch {
                what: "mass matrix buffer",
                expected: d * d,
                found: out.len(),
            });
        }
        let c = self.c_tot(eta)?;
        let j = self.j_tot(eta)?;
        let h = self.h_tot(eta)?;
        self.assemble_mass_matrix(c, &j, &h, out);
        Ok(())
    }

    /// Assemble `M_tot` from its η-dependent parts `c̄_tot`, `J̄_tot`, `H̄_tot` (3 x n,
    /// row-major) into `out` ((6+n)², row-major; no allocation; `out.len()` must be right).
    /// The layout is the one documented at [`Self::mass_matrix_into`].
    pub fn assemble_mass_matrix(
        &self,
        c_tot: [f64; 3],
        j: &[[f64; 3]; 3],
        h: &[f64],
        out: &mut [f64],
    ) {
        let n = self.n();
        let d = self.dim();
        let c = skew(c_tot);
        out.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..3 {
            out[i * d + i] = self.mass;
            for k in 0..3 {
                out[i * d + 3 + k] = -c[i][k];
                out[(3 + i) * d + k] = c[i][k];
                out[(3 + i) * d + 3 + k] = j[i][k];
            }
            for p in 0..n {
                out[i * d + 6 + p] = self.p_bar[i * n + p];
                out[(6 + p) * d + i] = self.p_bar[i * n + p];
                out[(3 + i) * d + 6 + p] = h[i * n + p];
                out[(6 + p) * d + 3 + i] = h[i * n + p];
            }
        }
        for m in 0..n {
            for p in 0..n {
                out[(6 + m) * d + 6 + p] = self.modal_mass[m * n + p];
            }
        }
    }

    /// Allocating convenience for [`Self::mass_matrix_into`].
    pub fn mass_matrix(&self, eta: &[f64]) -> Result<Vec<f64>, CoefficientError> {
        let mut out = vec![0.0; self.dim() * self.dim()];
        self.mass_matrix_into(eta, &mut out)?;
        Ok(out)
    }

    /// `∂M_tot/∂η_m` at `η` ((6+n) x (6+n), row-major, into `out`): the V-ω block
    /// `∓(P̄ e_m)^×`, the ω-ω block `J̄'_m + J̄'_m^T + Σ_p η_p (J̄''_mp + J̄''_pm)` and the
    /// ω-η̇ block `H̄'_m`. The velocity-dependent terms of (3.2.1) follow from these
    /// (Boltzmann-Hamel form of (2.4.1)-(2.4.2) with `∂T/∂η = ½ v^T ∂M_tot/∂η v`).
    pub fn mass_matrix_derivative_into(
        &self,
        eta: &[f64],
        m: usize,
        out: &mut [f64],
    ) -> Result<(), CoefficientError> {
        self.check_eta(eta)?;
        let n = self.n();
        let d = self.dim();
        if m >= n {
            return Err(CoefficientError::ModeOutOfRange {
                index: m,
                n_modes: n,
            });
        }
        if out.len() != d * d {
            return Err(CoefficientError::LengthMismatch {
                what: "mass matrix derivative buffer",
                expected: d * d,
                found: out.len(),
            });
        }
        out.iter_mut().for_each(|x| *x = 0.0);
        let pm = skew([self.p_bar[m], self.p_bar[n + m], self.p_bar[2 * n + m]]);
        for i in 0..3 {
            for k in 0..3 {
                out[i * d + 3 + k] = -pm[i][k];
                out[(3 + i) * d + k] = pm[i][k];
                let mut jd = self.j_ru[m][i][k] + self.j_ru[m][k][i];
                for p in 0..n {
                    jd += eta[p] * (self.j_uu[m * n + p][i][k] + self.j_uu[p * n + m][i][k]);
                }
                out[(3 + i) * d + 3 + k] = jd;
            }
            for p in 0..n {
                let hv = self.h_prime[(m * 3 + i) * n + p];
                out[(3 + i) * d + 6 + p] = hv;
                out[(6 + p) * d + 3 + i] = hv;
            }
        }
        Ok(())
    }

    /// Kinetic energy `T = ½ v^T M_tot(η) v`, `v = (V_B, ω_B, η̇)`.
    pub fn kinetic_energy(&self, eta: &[f64], v: &[f64]) -> Result<f64, CoefficientError> {
        let d = self.dim();
        if v.len() != d {
            return Err(CoefficientError::LengthMismatch {
                what: "v",
                expected: d,
                found: v.len(),
            });
        }
        let mm = self.mass_matrix(eta)?;
        let mut t = 0.0;
        for i in 0..d {
            for k in 0..d {
                t += v[i] * mm[i * d + k] * v[k];
            }
        }
        Ok(0.5 * t)
    }
}
