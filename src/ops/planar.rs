//! The planar eigen-stability models of thesis ch. 6 at a scenario's initial condition
//! (`flexflight analyze planar`, sweeps with `analysis = planar_pinned | planar_unpinned`):
//! the analysis, its diagnostics and its report with NACA TN 4197 alongside.

use std::fmt::Write as _;

use crate::analysis::planar::{
    self, PlanarAnalysis, PlanarError, PlanarKind, PlanarVehicle, Speed,
};
use crate::analysis::tn4197::{Tn4197Fin, Tn4197Form};
use crate::check::ir::{InitialPosition, InitialVelocity, Scenario};
use crate::diagnostics::Diagnostic;

/// A planar error as a diagnostic pointing at the scenario.
pub fn planar_diagnostic(e: &PlanarError, sc: &Scenario) -> Diagnostic {
    match e {
        PlanarError::NoFins { .. } => Diagnostic::error("analysis::planar::no_fins", e.to_string())
            .label(sc.vehicle.span, "this vehicle has no `fins` block"),
        PlanarError::NoEquilibrium { .. } => {
            Diagnostic::error("analysis::planar::no_equilibrium", e.to_string())
                .label(sc.initial.span, "at this initial speed")
                .with_help(
                    "the unpinned model (6.2) flies at terminal velocity: drag must equal weight somewhere between -0.5 km and 86 km at this speed (drag too small: a higher speed; too large: a lower one); the pinned model has no such condition",
                )
        }
        _ => Diagnostic::error("analysis::planar::failed", e.to_string())
            .label(sc.name.span, "while analysing this scenario"),
    }
}

/// Initial altitude (m) and airspeed (m/s) of a scenario.
pub fn initial_condition(sc: &Scenario, v: &PlanarVehicle) -> Result<(f64, f64), PlanarError> {
    let h = match &sc.initial.position {
        InitialPosition::Altitude(h) => h.value,
        InitialPosition::Inertial(p) => -p.value[2],
    };
    let speed = match &sc.initial.velocity {
        InitialVelocity::Body(vb) => vb.value.iter().map(|x| x * x).sum::<f64>().sqrt(),
        InitialVelocity::Mach(m) => m.value * v.condition_at_speed(h, 1.0)?.speed_of_sound,
    };
    Ok((h, speed))
}

/// The planar analysis of `kind` at the scenario's initial speed and altitude (the unpinned
/// model at its equilibrium altitude for that speed), with the declared fin thickness; used
/// by `analyze planar` and by sweeps with `analysis = planar_pinned | planar_unpinned`.
pub fn analyse_at_initial_condition(
    scenario: &Scenario,
    v: &PlanarVehicle,
    kind: PlanarKind,
) -> Result<PlanarAnalysis, PlanarError> {
    let t = v.fins.declared_thickness;
    let (h, speed) = initial_condition(scenario, v)?;
    let h = match kind {
        PlanarKind::Pinned => h,
        PlanarKind::Unpinned => {
            let mp = v.mass_properties(t)?;
            planar::equilibrium_altitude(v, mp.mass, Speed::Airspeed(speed))?
        }
    };
    let c = v.condition_at_speed(h, speed)?;
    planar::analyse(planar::parameters(v, kind, t, c)?)
}

/// The TN 4197 fin of the analysed vehicle at the analysis' fin thickness.
pub fn tn4197_fin(v: &PlanarVehicle, r: &PlanarAnalysis) -> Tn4197Fin {
    let f = &v.fins;
    Tn4197Fin {
        shear_modulus: f.shear_modulus(),
        span: f.span,
        root_chord: f.root_chord,
        tip_chord: f.tip_chord,
        thickness: r.parameters.thickness,
        tip_le_offset: f.tip_le_offset,
    }
}

/// The TN 4197 flutter Mach and speed at the analysis' condition in the three published
/// forms (see [`crate::analysis::tn4197`]).
pub fn tn4197_json(v: &PlanarVehicle, r: &PlanarAnalysis) -> serde_json::Value {
    let fin = tn4197_fin(v, r);
    let c = &r.parameters.condition;
    let one = |form: Tn4197Form| {
        serde_json::json!({
            "form": form,
            "flutter_mach": fin.flutter_mach_in(form, c.pressure),
            "flutter_speed_m_s": fin.flutter_speed_in(form, c.pressure, c.speed_of_sound),
        })
    };
    let mut j = serde_json::json!({
        "shear_modulus_pa": fin.shear_modulus,
        "aspect_ratio": fin.aspect_ratio(),
        "thickness_ratio": fin.thickness / fin.root_chord,
        "thickness_ratio_chord": "root",
        "epsilon": fin.epsilon(),
        "pressure_pa": c.pressure,
    });
    for form in Tn4197Form::ALL {
        j[form.key()] = one(form);
    }
    j
}

/// The human report of one analysis.
pub fn analysis_text(v: &PlanarVehicle, r: &PlanarAnalysis) -> String {
    let p = &r.parameters;
    let c = &p.condition;
    let mp = &p.mass_properties;
    let f = &v.fins;
    let mut s = String::new();
    let opt = |x: Option<f64>| {
        x.map_or("none (body load is a couple)".to_string(), |x| {
            format!("{x:.6} m")
        })
    };
    let _ = writeln!(
        s,
        "planar {} model (thesis {}), vehicle {}",
        p.kind.name(),
        if p.kind == PlanarKind::Pinned {
            "6.1"
        } else {
            "6.2"
        },
        v.name
    );
    let _ = writeln!(s, "flight condition");
    let _ = writeln!(s, "  altitude            {:.3} m", c.altitude);
    let _ = writeln!(
        s,
        "  airspeed V          {:.4} m/s   Mach {:.5}",
        c.speed, c.mach
    );
    let _ = writeln!(
        s,
        "  density             {:.6e} kg/m^3   pressure {:.6e} Pa   a {:.4} m/s",
        c.density, c.pressure, c.speed_of_sound
    );
    let _ = writeln!(
        s,
        "  dynamic pressure q  {:.6e} Pa   g {:.5} m/s^2",
        c.dynamic_pressure, c.gravity
    );
    let _ = writeln!(s, "vehicle (fin thickness t = {:.4e} m)", p.thickness);
    let _ = writeln!(
        s,
        "  mass m              {:.6} kg   weight W {:.6e} N",
        mp.mass, p.weight
    );
    let _ = writeln!(
        s,
        "  centre of mass x    {:.6} m   pitch inertia J {:.6e} kg m^2",
        mp.x_cg, mp.inertia
    );
    let _ = writeln!(
        s,
        "  fins                {} (pitch-plane n_eff {:.4}), span L {:.5} m, mean chord c {:.5} m, area S_f {:.6e} m^2",
        f.count, p.pitch_plane_fins, f.span, f.mean_chord, p.fin_area
    );
    let _ = writeln!(
        s,
        "  fin material        E {:.4e} Pa, rho {:.1} kg/m^3, nu {:.4}",
        f.youngs_modulus, f.density, f.poisson
    );
    let _ = writeln!(
        s,
        "  I = c t^3/12        {:.6e} m^4 (6.11)",
        p.fin_bending_inertia
    );
    let _ = writeln!(
        s,
        "  k = n_eff 24EI/L^3  {:.6e} N/m (6.10)",
        p.fin_stiffness
    );
    let _ = writeln!(s, "  m_f                 {:.6e} kg", p.fin_mass);
    let _ = writeln!(s, "geometry");
    let _ = writeln!(
        s,
        "  S {:.6e} m^2, b {:.5} m",
        p.reference_area, p.reference_length
    );
    let _ = writeln!(s, "  body c.p. x         {}", opt(p.x_cp_body));
    let _ = writeln!(s, "  a (forward of c.g.) {}", opt(p.a));
    let _ = writeln!(
        s,
        "  fin c.p. x          {:.6} m   d (aft of c.g.) {:.6} m",
        p.x_cp_fin, p.d
    );
    let ae = &p.aero;
    let _ = writeln!(s, "coefficients (runtime tables, alpha = 0, per rad)");
    let _ = writeln!(
        s,
        "  body C_Nalpha {:.6}  C_Malpha(ref) {:.6}  C_A {:.6}  dC_A/dMach {:.6}  C_Aalpha {:.6}",
        ae.cn_alpha_body, ae.cm_alpha_body, ae.ca_body, ae.ca_mach_body, ae.ca_alpha_body
    );
    let _ = writeln!(
        s,
        "  fin  C_Nalpha {:.6}  C_A {:.6}  dC_A/dMach {:.6}  C_Aalpha {:.6}  x_cp {:.6} m aft of root LE (one fin, on S)",
        ae.cn_alpha_fin, ae.ca_fin, ae.ca_mach_fin, ae.ca_alpha_fin, ae.x_cp_fin
    );
    let _ = writeln!(
        s,
        "  rate derivatives    C_Nalpha-dot {:.4}  C_Malpha-dot {:.4}",
        p.cn_alpha_dot, p.cm_alpha_dot
    );
    let _ = writeln!(s, "loads per unit state");
    let _ = writeln!(
        s,
        "  P_b = qS C_Nalpha,B {:.6e} N/rad   P_f {:.6e} N/rad   M_b {:.6e} N m/rad",
        p.body_lift, p.fin_lift, p.body_moment
    );
    let _ = writeln!(
        s,
        "  A_f0 {:.6e} N   A_0 {:.6e} N   axial damping {:.6e} N s/m",
        p.fin_axial_force, p.axial_force, p.axial_damping
    );
    let matrix = |s: &mut String, name: &str, rows: &[Vec<f64>]| {
        let _ = writeln!(s, "{name}");
        for row in rows {
            let cells: Vec<String> = row.iter().map(|x| format!("{x:>14.6e}")).collect();
            let _ = writeln!(s, "  [{}]", cells.join(" "));
        }
    };
    let _ = writeln!(
        s,
        "coordinates x = ({})   state X = ({})",
        r.coordinates.join(", "),
        r.state.join(", ")
    );
    matrix(&mut s, "M (6.7/6.27)", &r.mass);
    matrix(&mut s, "C (6.8/6.29)", &r.damping);
    matrix(&mut s, "K (6.9/6.28)", &r.stiffness);
    matrix(&mut s, "A (6.13)", &r.state_matrix);
    let _ = writeln!(s, "eigenvalues");
    let mut ev = r.eigenvalues.clone();
    ev.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
    for e in &ev {
        let _ = writeln!(
            s,
            "  {:>14.6e} {:+14.6e} i   ({:.4} Hz)",
            e.re,
            e.im,
            e.im.abs() / (2.0 * std::f64::consts::PI)
        );
    }
    let vd = &r.verdict;
    let _ = writeln!(
        s,
        "sigma_d {:.6e} 1/s   omega_d {:.6e} rad/s ({:.4} Hz)   {}",
        vd.sigma_d,
        vd.omega_d,
        vd.omega_d / (2.0 * std::f64::consts::PI),
        vd.class.name()
    );
    let fin = tn4197_fin(v, r);
    let _ = writeln!(
        s,
        "NACA TN 4197 flutter boundary (G {:.4e} Pa, A = b^2/S {:.5}, t/c_r {:.5e} (root chord), eps {:.5}, p {:.6e} Pa)",
        fin.shear_modulus,
        fin.aspect_ratio(),
        fin.thickness / fin.root_chord,
        fin.epsilon(),
        c.pressure
    );
    for form in Tn4197Form::ALL {
        let _ = writeln!(
            s,
            "  {:<50} flutter Mach {:.5}   V_f {:.3} m/s",
            form.name(),
            fin.flutter_mach_in(form, c.pressure),
            fin.flutter_speed_in(form, c.pressure, c.speed_of_sound)
        );
    }
    s
}
