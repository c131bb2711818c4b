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
];

/// All column names for the given mode names: rigid channels, `eta_<mode>` for every mode,
/// `eta_dot_<mode>` for every mode, then energies and momenta.
pub fn channel_names(mode_names: &[String]) -> Vec<String> {
    let mut v: Vec<String> = RIGID_CHANNELS.iter().map(|s| s.to_string()).collect();
    v.extend(mode_names.iter().map(|m| format!("eta_{m}")));
    v.extend(mode_names.iter().map(|m| format!("eta_dot_{m}")));
    v.extend(INVARIANT_CHANNELS.iter().map(|s| s.to_string()));
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modal_channels_sit_between_the_rigid_and_invariant_ones() {
        let names = channel_names(&["body_bending_y1".into(), "fin1_flap".into()]);
        assert_eq!(
            names.len(),
            RIGID_CHANNELS.len() + 4 + INVARIANT_CHANNELS.len()
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
}
