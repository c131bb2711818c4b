use flexflight::analysis::flutter::fin::{FinAero, FinFlutterSettings};
use flexflight::analysis::flutter::vehicle::{FlightBlocks, flight_gaf, vehicle_coordinates, vehicle_gaf, vehicle_lattice};
use flexflight::cli::linear::load_variant;
fn main() {
    let sets = vec!["fins.thickness=1.0 mm".to_string()];
    let v = load_variant(std::path::Path::new("examples/thesis/section_6_5.vdl"), "subsonic_t06", &sets, Some(std::path::Path::new("/tmp/p/cache"))).unwrap();
    let coords = vehicle_coordinates(&v).unwrap();
    let nn = coords.order(); let b = coords.b_ref();
    let fins = flight_gaf(&v, FlightBlocks::Fins, 200.0, 5000.0, b).unwrap().unwrap();
    let s = FinFlutterSettings { aero: FinAero::QuasiSteady, ..FinFlutterSettings::default() };
    let lat = vehicle_lattice(&coords, &s).unwrap();
    let q = vehicle_gaf(&coords, &lat, 200.0 / 320.545, &s, None).unwrap();
    let q0 = q.at(0);
    println!("nn {nn}; modes {:?}", v.compiled.modes.iter().map(|m| m.name.clone()).collect::<Vec<_>>());
    for (r, c) in [(2,2),(4,4),(1,1),(5,5),(3,3),(2,4),(4,2)] { println!("Q[{r},{c}] panel {:.5} flight {:.5}", q0[r*nn+c].re, fins.d[r*nn+c]); }
    for j in 6..nn { println!("mode {j}: Q[pitch,j] panel {:+.5} flight {:+.5} | Q[j,pitch] panel {:+.5} flight {:+.5} | Q[plunge z,j] p {:+.5} f {:+.5} | Q[j,z] p {:+.5} f {:+.5} | Q[j,j] p {:+.5} f {:+.5}", q0[4*nn+j].re, fins.d[4*nn+j], q0[j*nn+4].re, fins.d[j*nn+4], q0[2*nn+j].re, fins.d[2*nn+j], q0[j*nn+2].re, fins.d[j*nn+2], q0[j*nn+j].re, fins.d[j*nn+j]); }
}
