//! Rocket thrust, thesis 5.2: eqs. (5.2.1)-(5.2.6).

use crate::runtime::eom::{ForceModel, StateView};
use crate::runtime::kinematics::cross;
use crate::runtime::thrust::ThrustCurve;

/// Thrust of the motor applied at the nozzle key node, eqs. (5.2.1)-(5.2.6).
///
/// - `T(t)` from the thrust curve (5.2.1), along body `x` before misalignment;
/// - misalignment by the small rotation `α_T`: `T_α = (1 + α_T^×) T e_x` (5.2.2);
/// - the nozzle rotates with the structure: `θ_T = S_rot,T η` and `C_T = 1 - θ_T^×` (5.2.4)
///   maps body components into the deformed nozzle frame, in which `T_α` is fixed, so the
///   body-frame force is `F = C_Tᵀ T_α = T_α + θ_T × T_α`;
/// - it acts at the deformed nozzle point moved by the thrust-line offset `δ_T`:
///   `r_T + u_T + δ_T` with `u_T = S_trans,T η`. The OCR of (5.2.6) is garbled
///   (REFERENCE-NOTES), so the moment about the body origin is derived from that point of
///   application: `G = (r_T + u_T + δ_T) × F`. The elastic displacement `u_T` is kept so
///   that the rigid moment and the modal force below describe the same point (the virtual
///   work of `F` at the displaced point is `F·(δx + δθ × (r_T+u_T+δ_T) + S_trans,T δη)`);
///   it changes the moment only at second order in `η`;
/// - modal forces `Q = S_Tᵀ [F; δ_T × F]` (5.2.3): the force at the nozzle node and its
///   moment about the node (the offset `δ_T` is rigid to the nozzle at first order).
#[derive(Debug, Clone)]
pub struct ThrustBlock {
    curve: ThrustCurve,
    /// Undeformed position of the nozzle key node `r_T`, body frame, m.
    nozzle_position: [f64; 3],
    /// Thrust-line offset `δ_T`, m.
    offset: [f64; 3],
    /// Misalignment `α_T`, rad.
    misalignment: [f64; 3],
    /// Rows `u, v, w` of `S` at the nozzle (3 x n, row-major).
    s_translation: Vec<f64>,
    /// Rows `θ_x, θ_y, θ_z` of `S` at the nozzle (3 x n, row-major).
    s_rotation: Vec<f64>,
    n: usize,
}

impl ThrustBlock {
    /// The block for `curve` at the nozzle node `nozzle_position` with the shape rows of that
    /// node (each 3 x n row-major; a shorter slice is padded with zeros).
    pub fn new(
        curve: ThrustCurve,
        nozzle_position: [f64; 3],
        offset: [f64; 3],
        misalignment: [f64; 3],
        s_translation: &[f64],
        s_rotation: &[f64],
        n: usize,
    ) -> Self {
        let pad = |s: &[f64]| {
            let mut v = vec![0.0; 3 * n];
            let k = v.len().min(s.len());
            v[..k].copy_from_slice(&s[..k]);
            v
        };
        Self {
            curve,
            nozzle_position,
            offset,
            misalignment,
            s_translation: pad(s_translation),
            s_rotation: pad(s_rotation),
            n,
        }
    }

    /// Thrust magnitude at `t`, N (5.2.1).
    pub fn thrust(&self, t: f64) -> f64 {
        self.curve.thrust_at(t)
    }
}

impl ForceModel for ThrustBlock {
    fn generalized_forces(&mut self, t: f64, s: &StateView, out: &mut [f64]) {
        let n = self.n;
        let thrust = self.curve.thrust_at(t);
        if thrust == 0.0 {
            return;
        }
        let a = self.misalignment;
        // (1 + α^×) T e_x = T (1, α_z, -α_y), eq. (5.2.2).
        let t_alpha = [thrust, thrust * a[2], -thrust * a[1]];
        let mut theta = [0.0; 3];
        let mut u = [0.0; 3];
        for i in 0..3 {
            for m in 0..n.min(s.eta.len()) {
                theta[i] += self.s_rotation[i * n + m] * s.eta[m];
                u[i] += self.s_translation[i * n + m] * s.eta[m];
            }
        }
        // F = C_Tᵀ T_α = (1 + θ^×) T_α, eq. (5.2.4).
        let tx = cross(&theta, &t_alpha);
        let f = [t_alpha[0] + tx[0], t_alpha[1] + tx[1], t_alpha[2] + tx[2]];
        let r = [0, 1, 2].map(|i| self.nozzle_position[i] + u[i] + self.offset[i]);
        let g = cross(&r, &f);
        let g_nozzle = cross(&self.offset, &f);
        for i in 0..3 {
            out[i] += f[i];
            out[3 + i] += g[i];
        }
        for m in 0..n {
            let mut q = 0.0;
            for i in 0..3 {
                q +=
                    self.s_translation[i * n + m] * f[i] + self.s_rotation[i * n + m] * g_nozzle[i];
            }
            out[6 + m] += q;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runtime::eom::StateLayout;

    fn block(offset: [f64; 3], misalignment: [f64; 3]) -> ThrustBlock {
        let curve = ThrustCurve::from_points("test", &[(0.0, 100.0), (2.0, 100.0)]).unwrap();
        // One mode: at the nozzle u = (0, 0.5, 0), θ = (0, 0, 0.2).
        ThrustBlock::new(
            curve,
            [-2.0, 0.0, 0.0],
            offset,
            misalignment,
            &[0.0, 0.5, 0.0],
            &[0.0, 0.0, 0.2],
            1,
        )
    }

    fn forces(b: &mut ThrustBlock, eta: f64) -> Vec<f64> {
        let layout = StateLayout { n: 1 };
        let x = layout.state(
            [0.0; 3],
            [0.0, 0.0, 0.0, 1.0],
            [0.0; 3],
            [0.0; 3],
            &[eta],
            &[0.0],
        );
        let mut out = vec![0.0; 7];
        b.generalized_forces(1.0, &StateView::new(layout, &x), &mut out);
        out
    }

    #[test]
    fn aligned_thrust_on_the_axis_gives_pure_axial_force() {
        let mut b = block([0.0; 3], [0.0; 3]);
        let out = forces(&mut b, 0.0);
        assert_eq!(out, vec![100.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn misalignment_and_offset_by_hand() {
        // α = (0, 0.01, 0.02): T_α = 100 (1, 0.02, -0.01). δ = (0, 0.01, 0).
        let mut b = block([0.0, 0.01, 0.0], [0.0, 0.01, 0.02]);
        let out = forces(&mut b, 0.0);
        let f = [100.0, 2.0, -1.0];
        for i in 0..3 {
            assert!((out[i] - f[i]).abs() < 1e-12);
        }
        // r = (-2, 0.01, 0); r × F = (0.01·(-1) - 0·2, 0·100 - (-2)(-1), (-2)(2) - 0.01·100).
        let g = [-0.01, -2.0, -5.0];
        for i in 0..3 {
            assert!((out[3 + i] - g[i]).abs() < 1e-12, "{i}: {}", out[3 + i]);
        }
        // Q = u·F + θ·(δ × F); δ × F = (0.01·(-1), 0, -0.01·100) = (-0.01, 0, -1).
        assert!((out[6] - (0.5 * 2.0 - 0.2)).abs() < 1e-12, "{}", out[6]);
    }

    #[test]
    fn nozzle_rotation_and_displacement_by_hand() {
        let mut b = block([0.0; 3], [0.0; 3]);
        let eta = 0.1;
        let out = forces(&mut b, eta);
        // θ = (0, 0, 0.02), F = T_α + θ × T_α = (100, 0.02·100, 0) = (100, 2, 0).
        assert!((out[0] - 100.0).abs() < 1e-12 && (out[1] - 2.0).abs() < 1e-12);
        // r = (-2, 0.05, 0); r × F = (0, 0, -2·2 - 0.05·100) = (0, 0, -9).
        assert!((out[5] + 9.0).abs() < 1e-12, "{}", out[5]);
        // Q = u_shape·F = 0.5·2 = 1 (no offset: no moment about the nozzle).
        assert!((out[6] - 1.0).abs() < 1e-12);
        // After burnout nothing.
        let layout = StateLayout { n: 1 };
        let x = layout.state(
            [0.0; 3],
            [0.0, 0.0, 0.0, 1.0],
            [0.0; 3],
            [0.0; 3],
            &[eta],
            &[0.0],
        );
        let mut o = vec![0.0; 7];
        b.generalized_forces(5.0, &StateView::new(layout, &x), &mut o);
        assert!(o.iter().all(|v| *v == 0.0));
    }
}
