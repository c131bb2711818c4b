//! A uniform cantilever wing in bending and torsion with Theodorsen strip theory, and the
//! Goland wing (Goland, "The flutter of a uniform cantilever wing", J. Appl. Mech. 12(4),
//! 1945, A197-A208; Goland & Luke, "The flutter of a uniform wing with tip weights",
//! J. Appl. Mech. 15, 1948).
//!
//! # Structure: beam elements
//!
//! The wing's elastic axis is a straight beam along the span `y` (root `y = 0` clamped), with
//! the deflection `w` (up) and the twist `θ` (nose up) of the section about the elastic axis.
//! Element of length `ℓ` with nodal DOF `(w, w', θ)`: Hermite cubics `N_w` for the bending
//! (Euler-Bernoulli), linear `N_θ` for the torsion (Przemieniecki, *Theory of Matrix
//! Structural Analysis*, 1968, §5.3 and §11.4: the standard stiffness `EI/ℓ³ [12, 6ℓ, ...]`,
//! `GJ/ℓ [1, -1; -1, 1]`). The consistent mass follows from the kinetic energy per unit span
//! of a section whose mass centre lies `d = x_θ b` aft of the elastic axis (derived: the mass
//! centre moves up by `w - d θ`):
//!
//! `T' = (1/2) (m ẇ² - 2 S ẇ θ̇ + I_α θ̇²)`, `S = m d`, `I_α` about the elastic axis,
//!
//! so `M = ∫ (m N_wᵀN_w - S (N_wᵀN_θ + N_θᵀN_w) + I_α N_θᵀN_θ) dy`, integrated per element by
//! four-point Gauss-Legendre quadrature (exact for these polynomial products, degree <= 6).
//!
//! # Aerodynamics: strip theory
//!
//! Each strip carries the two-dimensional Theodorsen airloads of its own motion
//! ([`flexflight::analysis::flutter::theodorsen::section_gaf`], coordinates `(h/b, θ)`, `h = -w` down, elastic axis at
//! `a` semichords aft of mid-chord). In `(w, θ)` the section's generalised forces per unit span
//! are `q A(k) (w, θ)` with (derived from the section's `q b² Q η` and `h = -w`)
//!
//! `A = [[Q_11, -b Q_12], [-b Q_21, b² Q_22]]`,
//!
//! and the wing's, on modal coordinates `Φ` (mass-normalised modes of the clamped beam),
//! `Q(k) = Q_11 P_ww - b Q_12 P_wθ - b Q_21 P_θw + b² Q_22 P_θθ`, `P_ab = Φᵀ ∫ N_aᵀ N_b dy Φ`.
//! No tip loss, no finite-span induction: this is the model of Goland's own analysis.
//!
//! # The Goland wing
//!
//! Semi-span 20 ft, chord 6 ft, elastic axis at 33 % chord, mass centre at 43 % chord,
//! mass 0.746 slug/ft, `I_α` = 1.943 slug ft²/ft about the elastic axis, `EI` = 23.65e6 lb ft²,
//! `GJ` = 2.39e6 lb ft², sea-level air 0.002378 slug/ft³ (Goland 1945; the same data are
//! used in Bisplinghoff, Ashley & Halfman, *Aeroelasticity*, 1955, ch. 9). Converted to SI exactly
//! (1 ft = 0.3048 m, 1 slug = 14.593 902 937 kg, 1 lbf = 4.448 221 615 260 5 N).

use faer::c64;
use nalgebra::{DMatrix, SymmetricEigen};

use flexflight::analysis::flutter::pk::{FlutterError, FlutterModel, GafFn};
use flexflight::analysis::flutter::theodorsen::section_gaf;

pub const FT: f64 = 0.3048;
pub const LBF: f64 = 4.448_221_615_260_5;
/// 1 slug = 1 lbf s²/ft (exact in the definitions of the pound-force and the foot; the
/// language's `slug` unit is the same quotient).
pub const SLUG: f64 = LBF / FT;

/// A flutter problem of [`UniformWing::flutter_problem`]: the modal model, its strip-theory
/// GAF and the modes.
pub type StripProblem<F> = (FlutterModel, GafFn<F>, Modes);

/// A uniform cantilever wing (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformWing {
    pub span: f64,
    pub chord: f64,
    /// Elastic axis, fraction of the chord from the leading edge.
    pub elastic_axis: f64,
    /// Mass centre, fraction of the chord from the leading edge.
    pub mass_centre: f64,
    /// Mass per unit span, kg/m.
    pub mass: f64,
    /// Pitch inertia per unit span about the elastic axis, kg m.
    pub inertia: f64,
    pub ei: f64,
    pub gj: f64,
    pub density: f64,
}

/// The assembled, clamped beam model.
pub struct BeamModel {
    pub mass: DMatrix<f64>,
    pub stiffness: DMatrix<f64>,
    /// `∫ N_aᵀ N_b dy` for (a, b) = (w, w), (w, θ), (θ, w), (θ, θ).
    pub w_ww: DMatrix<f64>,
    pub w_wt: DMatrix<f64>,
    pub w_tw: DMatrix<f64>,
    pub w_tt: DMatrix<f64>,
}

/// Natural modes of the clamped beam.
pub struct Modes {
    /// rad/s, ascending.
    pub omega: Vec<f64>,
    /// Mass-normalised shapes, one column per mode.
    pub shapes: DMatrix<f64>,
    /// "bending" or "torsion" by the larger kinetic-energy share.
    pub kinds: Vec<&'static str>,
}

impl UniformWing {
    /// The Goland wing (module doc).
    pub fn goland() -> UniformWing {
        UniformWing {
            span: 20.0 * FT,
            chord: 6.0 * FT,
            elastic_axis: 0.33,
            mass_centre: 0.43,
            mass: 0.746 * SLUG / FT,
            inertia: 1.943 * SLUG * FT * FT / FT,
            ei: 23.65e6 * LBF * FT * FT,
            gj: 2.39e6 * LBF * FT * FT,
            density: 0.002378 * SLUG / (FT * FT * FT),
        }
    }

    pub fn semichord(&self) -> f64 {
        0.5 * self.chord
    }

    /// `a`: elastic axis in semichords aft of mid-chord.
    pub fn a(&self) -> f64 {
        2.0 * self.elastic_axis - 1.0
    }

    /// Static unbalance `S = m d` per unit span (kg), `d` the mass centre aft of the axis.
    pub fn unbalance(&self) -> f64 {
        self.mass * (self.mass_centre - self.elastic_axis) * self.chord
    }

    /// Assembles `elements` beam elements and clamps the root (module doc).
    pub fn beam(&self, elements: usize) -> BeamModel {
        let n = 3 * elements; // free DOF (root removed)
        let l = self.span / elements as f64;
        let mut mass = DMatrix::zeros(n, n);
        let mut stiffness = DMatrix::zeros(n, n);
        let mut w_ww = DMatrix::zeros(n, n);
        let mut w_wt = DMatrix::zeros(n, n);
        let mut w_tw = DMatrix::zeros(n, n);
        let mut w_tt = DMatrix::zeros(n, n);
        // Gauss-Legendre 4 points on [0, 1].
        let gp = [
            (
                0.5 - 0.5 * 0.861_136_311_594_052_6,
                0.5 * 0.347_854_845_137_453_9,
            ),
            (
                0.5 - 0.5 * 0.339_981_043_584_856_3,
                0.5 * 0.652_145_154_862_546_1,
            ),
            (
                0.5 + 0.5 * 0.339_981_043_584_856_3,
                0.5 * 0.652_145_154_862_546_1,
            ),
            (
                0.5 + 0.5 * 0.861_136_311_594_052_6,
                0.5 * 0.347_854_845_137_453_9,
            ),
        ];
        let s = self.unbalance();
        for e in 0..elements {
            // Element DOF (w1, w1', θ1, w2, w2', θ2) -> global index (None: clamped root).
            let dof = |local: usize| -> Option<usize> {
                let node = e + local / 3;
                (node > 0).then(|| 3 * (node - 1) + local % 3)
            };
            let mut ke = [[0.0; 6]; 6];
            let bend = [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
                [-12.0, -6.0 * l, 12.0, -6.0 * l],
                [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
            ];
            let bi = [0, 1, 3, 4];
            for i in 0..4 {
                for j in 0..4 {
                    ke[bi[i]][bi[j]] += self.ei / (l * l * l) * bend[i][j];
                }
            }
            let g = self.gj / l;
            ke[2][2] += g;
            ke[5][5] += g;
            ke[2][5] -= g;
            ke[5][2] -= g;
            let (mut nww, mut nwt, mut ntt) = ([[0.0; 6]; 6], [[0.0; 6]; 6], [[0.0; 6]; 6]);
            for &(xi, wt) in &gp {
                let nw = [
                    1.0 - 3.0 * xi * xi + 2.0 * xi * xi * xi,
                    l * (xi - 2.0 * xi * xi + xi * xi * xi),
                    0.0,
                    3.0 * xi * xi - 2.0 * xi * xi * xi,
                    l * (-xi * xi + xi * xi * xi),
                    0.0,
                ];
                let nt = [0.0, 0.0, 1.0 - xi, 0.0, 0.0, xi];
                for i in 0..6 {
                    for j in 0..6 {
                        nww[i][j] += wt * l * nw[i] * nw[j];
                        nwt[i][j] += wt * l * nw[i] * nt[j];
                        ntt[i][j] += wt * l * nt[i] * nt[j];
                    }
                }
            }
            for i in 0..6 {
                let Some(gi) = dof(i) else { continue };
                for j in 0..6 {
                    let Some(gj) = dof(j) else { continue };
                    stiffness[(gi, gj)] += ke[i][j];
                    mass[(gi, gj)] += self.mass * nww[i][j] - s * (nwt[i][j] + nwt[j][i])
                        + self.inertia * ntt[i][j];
                    w_ww[(gi, gj)] += nww[i][j];
                    w_wt[(gi, gj)] += nwt[i][j];
                    w_tw[(gi, gj)] += nwt[j][i];
                    w_tt[(gi, gj)] += ntt[i][j];
                }
            }
        }
        BeamModel {
            mass,
            stiffness,
            w_ww,
            w_wt,
            w_tw,
            w_tt,
        }
    }

    /// The lowest `count` natural modes of the clamped beam of `elements` elements (dense
    /// Cholesky reduction `L⁻¹ K L⁻ᵀ` and a symmetric eigensolve, nalgebra).
    pub fn modes(&self, elements: usize, count: usize) -> Result<(BeamModel, Modes), FlutterError> {
        let beam = self.beam(elements);
        let n = beam.mass.nrows();
        if count == 0 || count > n {
            return Err(FlutterError::BadModel(format!(
                "{count} modes requested of a beam with {n} DOF"
            )));
        }
        let chol = beam
            .mass
            .clone()
            .cholesky()
            .ok_or(FlutterError::SingularMass)?;
        let linv = chol.l().try_inverse().ok_or(FlutterError::SingularMass)?;
        let c = &linv * &beam.stiffness * linv.transpose();
        let c = (&c + c.transpose()) * 0.5;
        let eig = SymmetricEigen::new(c);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
        let mut shapes = DMatrix::zeros(n, count);
        let mut omega = Vec::with_capacity(count);
        let mut kinds = Vec::with_capacity(count);
        for (col, &j) in order.iter().take(count).enumerate() {
            let y = eig.eigenvectors.column(j);
            let phi = linv.transpose() * y;
            // Sign: largest component positive (deterministic).
            let big = phi
                .iter()
                .fold(0.0_f64, |a, &v| if v.abs() > a.abs() { v } else { a });
            let phi = if big < 0.0 { -phi } else { phi };
            let (mut ew, mut et) = (0.0, 0.0);
            for node in 0..elements {
                ew += phi[3 * node].powi(2) * self.mass;
                et += phi[3 * node + 2].powi(2) * self.inertia;
            }
            kinds.push(if ew >= et { "bending" } else { "torsion" });
            omega.push(eig.eigenvalues[j].max(0.0).sqrt());
            shapes.set_column(col, &phi);
        }
        Ok((
            beam,
            Modes {
                omega,
                shapes,
                kinds,
            },
        ))
    }

    /// The flutter problem on `count` modes of an `elements`-element beam: modal mass (unit),
    /// stiffness `diag(ω²)`, and Theodorsen strip theory exact in `k` (module doc).
    pub fn flutter_problem(
        &self,
        elements: usize,
        count: usize,
    ) -> Result<StripProblem<impl Fn(f64, &mut [c64]) + use<>>, FlutterError> {
        let (beam, modes) = self.modes(elements, count)?;
        let phi = &modes.shapes;
        let p = |w: &DMatrix<f64>| -> Vec<f64> {
            let m = phi.transpose() * w * phi;
            (0..count)
                .flat_map(|i| (0..count).map(move |j| (i, j)))
                .map(|(i, j)| m[(i, j)])
                .collect()
        };
        let (pww, pwt, ptw, ptt) = (p(&beam.w_ww), p(&beam.w_wt), p(&beam.w_tw), p(&beam.w_tt));
        let b = self.semichord();
        let a = self.a();
        let nn = count * count;
        let gaf = GafFn {
            order: count,
            k_max: 1e3,
            f: move |k: f64, out: &mut [c64]| {
                let q = section_gaf(a, k);
                for e in 0..nn {
                    out[e] = q[0] * pww[e] - q[1] * (b * pwt[e]) - q[2] * (b * ptw[e])
                        + q[3] * (b * b * ptt[e]);
                }
            },
        };
        let mut stiffness = vec![0.0; nn];
        let mut mass = vec![0.0; nn];
        for i in 0..count {
            mass[i * count + i] = 1.0;
            stiffness[i * count + i] = modes.omega[i] * modes.omega[i];
        }
        let names = (0..count)
            .map(|i| format!("mode {} ({})", i + 1, modes.kinds[i]))
            .collect();
        let model = FlutterModel {
            names,
            mass,
            stiffness,
            damping: vec![0.0; nn],
            structural_g: 0.0,
            b_ref: b,
            density: self.density,
        };
        Ok((model, gaf, modes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexflight::analysis::flutter::pk::{PkSettings, k_method, pk_solve};

    /// Without static unbalance bending and torsion uncouple, and the FE frequencies converge
    /// to the exact cantilever values `1.87510² sqrt(EI/(m L⁴))` and `(π/2L) sqrt(GJ/I_α)`.
    #[test]
    fn uncoupled_frequencies_are_exact_cantilever_values() {
        let mut w = UniformWing::goland();
        w.mass_centre = w.elastic_axis;
        let (_, modes) = w.modes(20, 4).unwrap();
        let beta1 = 1.875_104_068_711_961;
        let bend = beta1 * beta1 * (w.ei / (w.mass * w.span.powi(4))).sqrt();
        let tors = std::f64::consts::FRAC_PI_2 / w.span * (w.gj / w.inertia).sqrt();
        assert_eq!(modes.kinds[0], "bending");
        assert_eq!(modes.kinds[1], "torsion");
        assert!(
            (modes.omega[0] / bend - 1.0).abs() < 1e-7,
            "{}",
            modes.omega[0] / bend - 1.0
        );
        assert!(
            (modes.omega[1] / tors - 1.0).abs() < 3e-4,
            "{}",
            modes.omega[1] / tors - 1.0
        );
    }

    fn goland(
        elements: usize,
        modes: usize,
    ) -> (flexflight::analysis::flutter::pk::PkSolution, FlutterModel) {
        let w = UniformWing::goland();
        let (model, gaf, _) = w.flutter_problem(elements, modes).unwrap();
        let speeds: Vec<f64> = (1..=60).map(|i| 5.0 * i as f64).collect();
        (
            pk_solve(&model, &gaf, &speeds, PkSettings::default()).unwrap(),
            model,
        )
    }

    /// The Goland wing flutters in its torsion branch coalescing with first bending, at
    /// 137.005 m/s (449.49 ft/s), 70.04 rad/s (20 elements, 4 modes). Published (Goland 1945,
    /// Goland & Luke 1948, the solution of the same strip-theory equations): 450 ft/s
    /// (137.16 m/s, often rounded to 137 m/s) and 70.7 rad/s; achieved -0.11 % and -0.93 %
    /// (converged strip theory gives about 70.0 rad/s: the 70.7 is probably the original's
    /// approximation, docs/validation.md). The k method gives the same point.
    #[test]
    fn goland_flutter_matches_published() {
        let (sol, model) = goland(20, 4);
        let f = sol.critical().unwrap();
        assert_eq!(f.name, "mode 2 (torsion)");
        assert_eq!(
            f.partner.as_ref().map(|p| p.1.as_str()),
            Some("mode 1 (bending)")
        );
        // 450 ft/s = 137.16 m/s: -0.11 %.
        let rel = f.speed / (450.0 * 0.3048) - 1.0;
        assert!((rel + 0.0011).abs() < 0.0001, "{rel}");
        assert!((f.omega - 70.7).abs() < 0.01 * 70.7, "{}", f.omega);
        assert!((f.speed - 137.004_807_6).abs() < 1e-6, "{}", f.speed);
        assert!((f.omega - 70.043_107_85).abs() < 1e-6, "{}", f.omega);
        let w = UniformWing::goland();
        let (_, gaf, _) = w.flutter_problem(20, 4).unwrap();
        let ks: Vec<f64> = (1..=300).map(|i| 0.005 * i as f64).collect();
        let km = k_method(&model, &gaf, &ks).unwrap();
        let kf = km.flutter.first().unwrap();
        assert!(
            (kf.speed - f.speed).abs() < 1e-9 * f.speed,
            "{} vs {}",
            kf.speed,
            f.speed
        );
        assert!((kf.omega - f.omega).abs() < 1e-9 * f.omega);
        // Static divergence of the strip-theory wing (zero-frequency root).
        let d = sol.divergence.unwrap();
        assert!((d.speed - 252.437_980).abs() < 1e-5, "{}", d.speed);
    }

    /// Mesh and mode convergence: 40 elements and 6 modes move the flutter speed by less
    /// than 0.02 % (achieved 0.013 %; the 20-element, 4-mode model is converged for the comparison above).
    #[test]
    fn goland_flutter_is_converged() {
        let a = goland(20, 4).0.critical().unwrap().speed;
        let b = goland(40, 6).0.critical().unwrap().speed;
        assert!((a - b).abs() < 2e-4 * b, "{a} vs {b}");
    }
}
