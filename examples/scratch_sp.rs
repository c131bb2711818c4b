use faer::c64;
use flexflight::analysis::flutter::fin::{FinAero, FinFlutterSettings};
use flexflight::analysis::flutter::pk::{GafTable, PkSolution};
use flexflight::analysis::flutter::vehicle::{FlightBlocks, N_RIGID, flight_gaf, solve_gaf, vehicle_coordinates};
use flexflight::analysis::linear::analyse;
use flexflight::analysis::linearise::LineariseOptions;
use flexflight::cli::linear::load_variant;
fn sp(sol: &PkSolution, v: f64) -> (f64, f64) {
    let i = sol.speeds.iter().position(|s| (s - v).abs() < 1e-9).unwrap();
    let mut best = (0.0, f64::NAN);
    for j in 0..N_RIGID { let p = sol.roots[j][i].p; if p.im > best.0 { best = (p.im, p.re); } }
    best
}
fn main() {
    for t in ["4 mm", "1.5 mm", "1.0 mm", "0.875 mm", "0.6 mm"] {
        let sets = vec![format!("fins.thickness={t}"), std::env::args().nth(1).unwrap_or("fins.cant=0 deg".into())];
        let v = load_variant(std::path::Path::new("examples/thesis/section_6_5.vdl"), "subsonic_t06", &sets, Some(std::path::Path::new("/tmp/p/cache"))).unwrap();
        let lin = analyse(&v, LineariseOptions::default()).unwrap();
        let names = &lin.model.state_names;
        let idx: Vec<usize> = ["theta_y", "v_body_z", "omega_body_y"].iter().map(|n| names.iter().position(|s| s == n).unwrap()).collect();
        let w_lin = lin.eigen.roots.iter().filter(|r| r.imag > 1e-3 && !r.neutral && r.imag < 50.0).max_by(|a, b| { let s = |r: &flexflight::analysis::roots::Root| -> f64 { idx.iter().map(|&i| r.participation[i]).sum() }; s(a).total_cmp(&s(b)) }).map(|r| (r.imag, r.real)).unwrap();
        let coords = vehicle_coordinates(&v).unwrap();
        let nn = coords.order(); let b = coords.b_ref();
        let fins = flight_gaf(&v, FlightBlocks::Fins, 200.0, 5000.0, b).unwrap().unwrap();
        let body = flight_gaf(&v, FlightBlocks::Body, 200.0, 5000.0, b).unwrap().unwrap();
        let k_max = 20.0;
        for (label, rigid_only) in [("full", false), ("rigid-only", true)] {
            let at = |k: f64| -> Vec<c64> { (0..nn*nn).map(|e| { let (r, c) = (e / nn, e % nn); let keep = !rigid_only || (r < N_RIGID && c < N_RIGID) || (r >= N_RIGID && c >= N_RIGID); if keep { c64::new(fins.d[e] + body.d[e], k * (fins.c1[e] + body.c1[e])) } else { c64::new(0.0, 0.0) } }).collect() };
            let gaf = GafTable::new(nn, vec![0.0, k_max], vec![at(0.0), at(k_max)]).unwrap();
            let s = FinFlutterSettings { aero: FinAero::QuasiSteady, k_max, ..FinFlutterSettings::default() };
            let coords = vehicle_coordinates(&v).unwrap();
            let speeds: Vec<f64> = (0..=20).map(|i| 100.0 + 5.0 * i as f64).collect();
            let flight = solve_gaf(coords, gaf, 0.736_429, &speeds, true, &s).unwrap();
            let w = sp(&flight.solution, 200.0);
            println!("{t}: linear {:.4} {:+.4}i ; p-k flight loads {label}: {:.4} {:+.4}", w_lin.0, w_lin.1, w.0, w.1);
        }
    }
}
