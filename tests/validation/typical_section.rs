//! The typical section in plunge and pitch with Theodorsen aerodynamics, in the
//! non-dimensional form of Hodges & Pierce, *Introduction to Structural Dynamics and
//! Aeroelasticity*, 2nd ed., 2011, ch. 5.
//!
//! Parameters (H&P §5.2-5.3): `a` the elastic axis and `e` the mass centre, both in
//! semichords aft of mid-chord; `μ = m / (π ρ b²)`; `r² = I_P / (m b²)` (radius of gyration
//! about the elastic axis); `σ = ω_h / ω_θ`. Coordinates `η = (h/b, θ)`; kinetic energy
//! `T = (m b²/2) (ĥ̇² + 2 x_θ ĥ̇ θ̇ + r² θ̇²)` with `x_θ = e - a` (the mass centre's downward
//! displacement is `h + x_θ b θ`), potential energy `(m b²/2) ω_θ² (σ² ĥ² + r² θ²)`, so
//!
//! `M = m b² [[1, x_θ], [x_θ, r²]]`, `K = m b² ω_θ² diag(σ², r²)`,
//!
//! and the generalised aerodynamic forces `q b² Q(k) η` of [`flexflight::analysis::flutter::theodorsen::section_gaf`].
//! The model is built with `b = 1`, `ω_θ = 1`, `ρ = 1`, so speeds are `U / (b ω_θ)` and
//! frequencies `ω / ω_θ`.
//!
//! Divergence (derived, H&P §5.3 give the same steady result): `K_θ = q_D 4π b² (a + 1/2)`
//! gives `U_D / (b ω_θ) = r sqrt(μ / (1 + 2a))`.

use faer::c64;

use flexflight::analysis::flutter::pk::{FlutterModel, GafFn};
use flexflight::analysis::flutter::theodorsen::section_gaf;

/// A typical section in H&P's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TypicalSection {
    pub a: f64,
    pub e: f64,
    pub mu: f64,
    pub r2: f64,
    pub sigma: f64,
}

impl TypicalSection {
    /// Hodges & Pierce's example (§5.3, §5.5): `a = -1/5`, `e = -1/10`, `μ = 20`,
    /// `r² = 6/25`, `σ = 2/5`.
    pub fn hodges_pierce() -> TypicalSection {
        TypicalSection {
            a: -0.2,
            e: -0.1,
            mu: 20.0,
            r2: 6.0 / 25.0,
            sigma: 0.4,
        }
    }

    /// The structural model with `b = ω_θ = ρ = 1` (module doc).
    pub fn model(&self) -> FlutterModel {
        let m = self.mu * std::f64::consts::PI; // μ π ρ b²
        let x = self.e - self.a;
        FlutterModel {
            names: vec!["plunge".into(), "pitch".into()],
            mass: vec![m, m * x, m * x, m * self.r2],
            stiffness: vec![m * self.sigma * self.sigma, 0.0, 0.0, m * self.r2],
            damping: vec![0.0; 4],
            structural_g: 0.0,
            b_ref: 1.0,
            density: 1.0,
        }
    }

    /// Theodorsen's GAF of the section (times `b² = 1`), exact in `k` up to `k_max`.
    pub fn gaf(&self, k_max: f64) -> GafFn<impl Fn(f64, &mut [c64])> {
        let a = self.a;
        GafFn {
            order: 2,
            k_max,
            f: move |k: f64, out: &mut [c64]| out.copy_from_slice(&section_gaf(a, k)),
        }
    }

    /// `U_D / (b ω_θ) = r sqrt(μ / (1 + 2a))` (module doc).
    pub fn divergence_speed(&self) -> f64 {
        (self.r2 * self.mu / (1.0 + 2.0 * self.a)).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexflight::analysis::flutter::pk::{Gaf, GafTable, PkSettings, k_method, pk_solve};

    fn speeds(lo: f64, hi: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
            .collect()
    }

    fn solve(sp: &[f64]) -> flexflight::analysis::flutter::pk::PkSolution {
        let s = TypicalSection::hodges_pierce();
        pk_solve(&s.model(), &s.gaf(50.0), sp, PkSettings::default()).unwrap()
    }

    /// The H&P section flutters in its pitch branch coalescing with plunge. Our p-k values
    /// (U_F/(b ω_θ) = 2.18391, ω_F/ω_θ = 0.64898, k_F = 0.29717) pinned near the achieved
    /// convergence (the k iteration converges to 1e-11).
    #[test]
    fn hodges_pierce_section_flutter() {
        let sol = solve(&speeds(0.05, 3.0, 60));
        let f = sol.critical().expect("a flutter point");
        assert_eq!(f.name, "pitch");
        assert_eq!(f.partner.as_ref().map(|p| p.1.as_str()), Some("plunge"));
        assert!((f.speed - 2.183_914_959).abs() < 1e-8, "{}", f.speed);
        assert!((f.omega - 0.648_983_537).abs() < 1e-8, "{}", f.omega);
        assert!((f.k - f.omega / f.speed).abs() < 1e-10);
        assert!((f.q - 0.5 * f.speed * f.speed).abs() < 1e-12);
        assert!(sol.unstable_at_start.is_empty());
    }

    /// A coordinate the air does not act on (an in-plane mode of a plate: no normal
    /// displacement) has round-off damping `g = 2 Re(p)/Im(p) ~ 1e-17` of either sign; its
    /// sign changes are not flutter. Failed before: spurious crossings on that branch.
    #[test]
    fn an_uncoupled_coordinate_does_not_flutter() {
        let s = TypicalSection::hodges_pierce();
        let m2 = s.model();
        let n = 3;
        let grow = |a: &[f64], diag: f64| {
            let mut b = vec![0.0; n * n];
            for i in 0..2 {
                for j in 0..2 {
                    b[i * n + j] = a[i * 2 + j];
                }
            }
            b[n * n - 1] = diag;
            b
        };
        let model = FlutterModel {
            names: vec![m2.names[0].clone(), m2.names[1].clone(), "in-plane".into()],
            mass: grow(&m2.mass, 1.0),
            // A frequency between the section's two.
            stiffness: grow(&m2.stiffness, 0.5),
            damping: grow(&m2.damping, 0.0),
            ..m2
        };
        let g2 = s.gaf(50.0);
        let gaf = flexflight::analysis::flutter::pk::GafFn {
            order: 3,
            k_max: 50.0,
            f: move |k: f64, out: &mut [c64]| {
                let mut q = [c64::new(0.0, 0.0); 4];
                g2.eval(k, &mut q);
                out.fill(c64::new(0.0, 0.0));
                for i in 0..2 {
                    for j in 0..2 {
                        out[i * 3 + j] = q[i * 2 + j];
                    }
                }
            },
        };
        let sol = pk_solve(&model, &gaf, &speeds(0.05, 3.0, 60), PkSettings::default()).unwrap();
        assert!(
            sol.flutter.iter().all(|f| f.name != "in-plane"),
            "{:?}",
            sol.flutter
        );
        let f = sol.critical().unwrap();
        assert_eq!(f.name, "pitch");
        assert!((f.speed - 2.183_914_959).abs() < 1e-8, "{}", f.speed);
    }

    /// Root finding, not a grid pick: two unrelated speed grids give the same flutter speed.
    #[test]
    fn flutter_speed_does_not_depend_on_the_grid() {
        let a = solve(&speeds(0.05, 3.0, 60)).critical().unwrap().speed;
        let b = solve(&speeds(0.3, 2.9, 7)).critical().unwrap().speed;
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }

    /// At g = 0 the k method solves the same harmonic equation as p-k: same flutter point.
    #[test]
    fn k_method_agrees_with_pk() {
        let s = TypicalSection::hodges_pierce();
        let pk = solve(&speeds(0.05, 3.0, 60));
        let f = pk.critical().unwrap();
        let ks: Vec<f64> = (1..=200).map(|i| 0.01 * i as f64).collect();
        let km = k_method(&s.model(), &s.gaf(50.0), &ks).unwrap();
        let kf = km.flutter.first().expect("k-method flutter");
        assert!(
            (kf.speed - f.speed).abs() < 1e-8 * f.speed,
            "{} vs {}",
            kf.speed,
            f.speed
        );
        assert!(
            (kf.omega - f.omega).abs() < 1e-8,
            "{} vs {}",
            kf.omega,
            f.omega
        );
        assert!((kf.k - f.k).abs() < 1e-8);
    }

    /// The zero-frequency root is the static divergence `r sqrt(μ / (1 + 2a)) = sqrt(8)`.
    #[test]
    fn divergence_is_the_static_root() {
        let s = TypicalSection::hodges_pierce();
        let d = solve(&speeds(0.05, 3.0, 20)).divergence.unwrap();
        assert!(
            (d.speed - s.divergence_speed()).abs() < 1e-12 * d.speed,
            "{}",
            d.speed
        );
        assert!((d.speed - 8f64.sqrt()).abs() < 1e-12);
        // The divergence shape is K⁻¹ Q^R(0)'s eigenvector (h/b, θ) = (-r²/(σ² (a + 1/2)), 1) =
        // (-5, 1): most of its strain energy (σ² 25 = 4 against r² = 0.24) is in the plunge spring.
        assert_eq!(d.name, "plunge");
    }

    /// Tabulated Q(k) (81 points, 0..4, cubic spline) reproduces the exact-aerodynamics flutter
    /// point closely; a table too short for the flutter k is an error, not an extrapolation.
    #[test]
    fn tabulated_gaf_reproduces_exact() {
        let s = TypicalSection::hodges_pierce();
        let exact = s.gaf(50.0);
        let ks: Vec<f64> = (0..=80).map(|i| 0.05 * i as f64).collect();
        let mats: Vec<Vec<c64>> = ks
            .iter()
            .map(|&k| {
                let mut m = vec![c64::new(0.0, 0.0); 4];
                flexflight::analysis::flutter::pk::Gaf::eval(&exact, k, &mut m);
                m
            })
            .collect();
        let table = GafTable::new(2, ks, mats).unwrap();
        // From V = 0.3 (k of the pitch branch 3.4 < 4) upwards.
        let sp = speeds(0.3, 3.0, 28);
        let t = pk_solve(&s.model(), &table, &sp, PkSettings::default()).unwrap();
        let e = solve(&sp);
        let (ft, fe) = (t.critical().unwrap(), e.critical().unwrap());
        // Achieved: 9.3e-7 relative in speed, 2.2e-6 in frequency.
        assert!(
            (ft.speed - fe.speed).abs() < 2e-6 * fe.speed,
            "{} vs {}",
            ft.speed,
            fe.speed
        );
        assert!((ft.omega - fe.omega).abs() < 3e-6 * fe.omega);
        let short = GafTable::new(
            2,
            vec![0.0, 0.1],
            vec![
                section_gaf(s.a, 0.0).to_vec(),
                section_gaf(s.a, 0.1).to_vec(),
            ],
        )
        .unwrap();
        let err = pk_solve(&s.model(), &short, &sp, PkSettings::default()).unwrap_err();
        assert!(
            matches!(
                err,
                flexflight::analysis::flutter::pk::FlutterError::KOutOfRange { .. }
            ),
            "{err}"
        );
    }

    /// A speed range below the flutter speed finds no flutter point (and says nothing false).
    #[test]
    fn no_crossing_below_the_flutter_speed() {
        let sol = solve(&speeds(0.05, 2.0, 30));
        assert!(sol.flutter.is_empty());
        assert!(
            sol.roots
                .iter()
                .all(|b| b.iter().all(|r| r.g().is_none_or(|g| g < 0.0)))
        );
    }
}
