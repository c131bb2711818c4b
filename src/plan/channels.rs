//! Names of the output channels of a run (the columns of `history.csv`, documented in the
//! README under "Run outputs"): snake_case, frame and axis as suffixes.

/// Rigid channels before the modal ones, in column order.
pub const RIGID_CHANNELS: &[&str] = &[
    "t",
    "p_inertial_x",
    "p_inertial_y",
    "p_inertial_z",
    "v_body_x",
    "v_body_y",
    "v_body_z",
    "omega_body_x",
    "omega_body_y",
    "omega_body_z",
    "roll",
    "pitch",
    "yaw",
    "q0",
    "q1",
    "q2",
    "q3",
    "alpha",
    "beta",
    "mach",
    "dynamic_pressure",
    "altitude",
    "air_density",
    "speed_of_sound",
];

/// Channels after the modal ones, in column order.
pub const INVARIANT_CHANNELS: &[&str] = &[
    "max_deformation",
    "energy_kinetic",
    "energy_strain",
    "energy_gravitational",
    "energy_total",
    "momentum_body_x",
    "momentum_body_y",
    "momentum_body_z",
    "momentum_inertial_x",
    "momentum_inertial_y",
    "momentum_inertial_z",
    "h_cm_body_x",
    "h_cm_body_y",
    "h_cm_body_z",
    "h_cm_inertial_x",
    "h_cm_inertial_y",
    "h_cm_inertial_z",
    "mass",
    "cm_body_x",
    "cm_body_y",
    "cm_body_z",
    "work_loads",
    "work_propulsive",
    "energy_dissipated",
    "energy_balance_residual",
];

/// Which aerodynamic channels a run writes (after the invariants).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AeroChannels {
    /// The body aerodynamics block is on.
    pub body: bool,
    /// Number of fins when the fin aerodynamics block is on (0 otherwise).
    pub fins: usize,
}

/// Body-aero force and moment channels (body axes; moment about the undeformed mass centre).
pub const BODY_AERO_CHANNELS: &[&str] = &[
    "body_aero_force_body_x",
    "body_aero_force_body_y",
    "body_aero_force_body_z",
    "body_aero_moment_cm_body_x",
    "body_aero_moment_cm_body_y",
    "body_aero_moment_cm_body_z",
];

/// Fin-aero force and moment channels (all fins together; body axes; moment about the
/// undeformed mass centre).
pub const FIN_AERO_CHANNELS: &[&str] = &[
    "fin_aero_force_body_x",
    "fin_aero_force_body_y",
    "fin_aero_force_body_z",
    "fin_aero_moment_cm_body_x",
    "fin_aero_moment_cm_body_y",
    "fin_aero_moment_cm_body_z",
];

/// Flight channels, last: inertial speed and acceleration magnitude of the body origin
/// (m/s, m/s^2) and its height above the ground (m); then `static_margin` (calibres) when
/// both aerodynamic blocks are on.
pub const FLIGHT_CHANNELS: &[&str] = &["speed", "acceleration", "height"];

/// All column names for the given mode names: rigid channels, `eta_<mode>` for every mode,
/// `eta_dot_<mode>` for every mode, energies and momenta, then the aerodynamic channels
/// (body aero force and moment; fin aero force and moment; per fin `fin<i>_alpha` in degrees
/// and `fin<i>_root_stress` in Pa).
pub fn channel_names(mode_names: &[String], aero: AeroChannels) -> Vec<String> {
    let mut v: Vec<String> = RIGID_CHANNELS.iter().map(|s| s.to_string()).collect();
    v.extend(mode_names.iter().map(|m| format!("eta_{m}")));
    v.extend(mode_names.iter().map(|m| format!("eta_dot_{m}")));
    v.extend(INVARIANT_CHANNELS.iter().map(|s| s.to_string()));
    if aero.body {
        v.extend(BODY_AERO_CHANNELS.iter().map(|s| s.to_string()));
    }
    if aero.fins > 0 {
        v.extend(FIN_AERO_CHANNELS.iter().map(|s| s.to_string()));
        for i in 1..=aero.fins {
            v.push(format!("fin{i}_alpha"));
            v.push(format!("fin{i}_root_stress"));
        }
    }
    v.extend(FLIGHT_CHANNELS.iter().map(|s| s.to_string()));
    if aero.body && aero.fins > 0 {
        v.push("static_margin".to_string());
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modal_channels_sit_between_the_rigid_and_invariant_ones() {
        let names = channel_names(
            &["body_bending_y1".into(), "fin1_flap".into()],
            AeroChannels::default(),
        );
        assert_eq!(
            names.len(),
            RIGID_CHANNELS.len() + 4 + INVARIANT_CHANNELS.len() + FLIGHT_CHANNELS.len()
        );
        let k = RIGID_CHANNELS.len();
        assert_eq!(names[k - 1], "speed_of_sound");
        assert_eq!(
            names[k..k + 4],
            [
                "eta_body_bending_y1",
                "eta_fin1_flap",
                "eta_dot_body_bending_y1",
                "eta_dot_fin1_flap"
            ]
        );
        assert_eq!(names[k + 4], "max_deformation");
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "column names are unique");
    }

    #[test]
    fn aero_channels_follow_the_invariants_fin_by_fin() {
        let names = channel_names(
            &["fin1_flap".into()],
            AeroChannels {
                body: true,
                fins: 2,
            },
        );
        let k = RIGID_CHANNELS.len() + 2 + INVARIANT_CHANNELS.len();
        assert_eq!(names[k], "body_aero_force_body_x");
        assert_eq!(names[k + 6], "fin_aero_force_body_x");
        assert_eq!(
            names[k + 12..],
            [
                "fin1_alpha",
                "fin1_root_stress",
                "fin2_alpha",
                "fin2_root_stress",
                "speed",
                "acceleration",
                "height",
                "static_margin"
            ]
        );
    }
}
