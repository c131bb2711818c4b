//! The surface finishes of the language (`aero { finish = ... }`): OpenRocket's named finishes
//! and their roughness heights, which the checker reads and the built-in estimator's skin
//! friction (`aero::estimator`, re-exported there) uses. Here, below `aero`, so that `check`
//! does not import the estimator (ARCHITECTURE.md's layering).

/// OpenRocket's named surface finishes and their roughness heights R_s, m (OpenRocket
/// 24.12, `ExternalComponent.Finish`; the heights after Hoerner, *Fluid-Dynamic Drag*, 1965,
/// p. 5-3, as the technical documentation's table of roughness heights gives them): the
/// language's `aero { finish = "..." }` names (docs/language.md) with OpenRocket's enum
/// names for the importer.
pub const FINISHES: [(&str, &str, f64); 9] = [
    ("rough", "ROUGH", 500.0e-6),
    ("rough_unfinished", "ROUGHUNFINISHED", 250.0e-6),
    ("unfinished", "UNFINISHED", 150.0e-6),
    ("regular_paint", "NORMAL", 60.0e-6),
    ("smooth_paint", "SMOOTH", 20.0e-6),
    ("optimum_paint", "OPTIMUM", 5.0e-6),
    ("sheet_metal", "POLISHED", 2.0e-6),
    ("polished", "FINISHPOLISHED", 0.5e-6),
    ("mirror", "MIRROR", 0.0),
];

/// The default surface roughness height, m: OpenRocket's default finish, regular paint
/// (`ExternalComponent.finish = Finish.NORMAL`, 60 um).
pub const DEFAULT_ROUGHNESS: f64 = 60.0e-6;

/// The roughness height of a finish by the language's name ([`FINISHES`]), m.
pub fn finish_roughness(name: &str) -> Option<f64> {
    FINISHES.iter().find(|f| f.0 == name).map(|f| f.2)
}

/// The language's name and the roughness height, m, of an OpenRocket finish by its enum name
/// in any case (`normal`, as its `.ork` files store it); OpenRocket's `POLISHED` is our
/// `sheet_metal` (2 um: OpenRocket shows it as "aircraft sheet-metal") and its
/// `FINISHPOLISHED` our `polished` (0.5 um).
pub fn openrocket_finish(name: &str) -> Option<(&'static str, f64)> {
    FINISHES
        .iter()
        .find(|f| f.1.eq_ignore_ascii_case(name))
        .map(|f| (f.0, f.2))
}
