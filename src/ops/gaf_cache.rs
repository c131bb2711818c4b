//! The clamped fin's generalised aerodynamic forces `Q(k, M)` through the artifact cache
//! (issue 13, deliverable 1: "tabulated over reduced frequency k and Mach, cached in the
//! artifact").
//!
//! `analyze flutter --clamped` builds one GAF table per Mach it solves at (the scenario's, each
//! `--match-point` iterate, each thickness of `--critical-thickness`); the unsteady table is
//! the expensive part of the solution (the harmonic lattice solved at every reduced frequency:
//! [`crate::analysis::flutter::fin::gaf_table`]). Each table is stored as a content-addressed
//! artifact, one file per (fin, modes, Mach, lattice, reduced frequencies), in the same cache
//! directory and container (blake3 key, rkyv payload, atomic write) as the compiled structure
//! and the flight margin's boundary. A warm call reads the table and only runs the p-k
//! iteration on it; the modes are still computed (their eigen-solve is what the table is
//! checked against, and what the report prints).
//!
//! The key ([`gaf_key`]) holds exactly what the table is computed from: the clamped fin's
//! structural inputs ([`super::flutter::hash_clamped_fin`]), the number of modes, the Mach
//! number (its bits), every field of [`FinFlutterSettings`] (destructured without `..`, so a
//! field added there does not compile until it is hashed here), the harmonic wake's
//! discretisation ([`WakeSettings::default`], both fields), the lattice spacing,
//! [`GAF_REVISION`], the payload schema and (through the builder) the compiler and format
//! versions. The density and the speeds are not in it: `Q(k)` does not depend on them.
//!
//! A read entry is checked against the request before it is used ([`GafArtifact::to_table`]):
//! its order, its reduced frequencies (bit for bit the requested grid), its Mach, and the
//! natural frequencies of the modes it was built on (bit for bit this call's: a table is never
//! paired with other modes). A corrupt, truncated, stale or ill-fitting entry is rebuilt and
//! replaced; a cache that cannot be written is a warning, not an error.

use faer::c64;

use crate::aero::panel::Lattice;
use crate::aero::panel::harmonic::WakeSettings;
use crate::aero::panel::piston::Correction;
use crate::analysis::flutter::fin::{
    FinAero, FinFlutterError, FinFlutterSettings, FinModes, gaf_ks, gaf_table,
};
use crate::analysis::flutter::pk::GafTable;
use crate::artifact::{ArtifactPayload, Cache, CacheKey, CacheKeyBuilder, CacheOutcome};
use crate::check::ir;

/// Revision of the GAF computation: bump when `gaf_table`'s numbers change for the same
/// inputs (the lattice, the wake, the spline rows, the virtual-work projection). 2: the Mach
/// box (`panel::machbox`) replaces piston theory above Mach 1.1 where piston theory's
/// criterion fails (issue 33). 3: the transonic band answered (issue 33): a Mach inside it is
/// the blend of its two end tables (`fin::bridged`), and the doublet lattice's tables reach
/// its own limit 0.95.
pub const GAF_REVISION: &str = "clamped-fin GAF 3";

/// The cached form of one GAF table: `ks.len()` matrices of `order x order`, row-major,
/// real and imaginary parts apart.
#[derive(Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct GafArtifact {
    pub order: u64,
    pub mach: f64,
    /// Reference semichord of the reduced frequencies `k = ω b / V`, m.
    pub b_ref: f64,
    pub ks: Vec<f64>,
    pub re: Vec<f64>,
    pub im: Vec<f64>,
    pub mode_names: Vec<String>,
    /// Natural frequencies of the modes the table was built on, rad/s.
    pub omega: Vec<f64>,
}

impl ArtifactPayload for GafArtifact {
    const SCHEMA: &'static str = "GafArtifact v1: order u64, mach f64, b_ref f64, ks Vec<f64>, re Vec<f64>, im Vec<f64> (ks x order x order row-major), mode_names Vec<String>, omega Vec<f64>";
}

impl GafArtifact {
    pub fn new(table: &GafTable, modes: &FinModes, mach: f64) -> Self {
        let n = table.order();
        let mut re = Vec::with_capacity(table.ks().len() * n * n);
        let mut im = Vec::with_capacity(re.capacity());
        for i in 0..table.ks().len() {
            for z in table.at(i) {
                re.push(z.re);
                im.push(z.im);
            }
        }
        GafArtifact {
            order: n as u64,
            mach,
            b_ref: modes.b_ref(),
            ks: table.ks().to_vec(),
            re,
            im,
            mode_names: modes.names.clone(),
            omega: modes.omega.clone(),
        }
    }

    /// Back to the table, checked against the request (module doc): an error (the entry is
    /// then rebuilt) when anything does not fit or a value is not finite.
    pub fn to_table(&self, modes: &FinModes, mach: f64, ks: &[f64]) -> Result<GafTable, String> {
        let n = modes.order();
        let bits = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        };
        if self.order != n as u64 || self.mach.to_bits() != mach.to_bits() {
            return Err("the cached GAF table is of another order or Mach".into());
        }
        if !bits(&self.ks, ks) {
            return Err(
                "the cached GAF table's reduced frequencies are not the requested ones".into(),
            );
        }
        if !bits(&self.omega, &modes.omega) || self.b_ref.to_bits() != modes.b_ref().to_bits() {
            return Err("the cached GAF table was built on other modes".into());
        }
        let nn = n * n;
        if self.re.len() != ks.len() * nn || self.im.len() != self.re.len() {
            return Err("the cached GAF table's sizes do not fit its order".into());
        }
        if self.re.iter().chain(&self.im).any(|x| !x.is_finite()) {
            return Err("the cached GAF table holds a value that is not finite".into());
        }
        let values: Vec<Vec<c64>> = (0..ks.len())
            .map(|i| {
                (i * nn..(i + 1) * nn)
                    .map(|j| c64::new(self.re[j], self.im[j]))
                    .collect()
            })
            .collect();
        GafTable::new(n, ks.to_vec(), values).map_err(|e| e.to_string())
    }
}

/// The cache key of the GAF table of `v`'s clamped fin with `n_modes` modes at Mach `mach`
/// for `settings` (module doc).
pub fn gaf_key(
    v: &ir::Vehicle,
    n_modes: usize,
    mach: f64,
    settings: &FinFlutterSettings,
) -> std::io::Result<CacheKey> {
    gaf_key_at_revision(GAF_REVISION, v, n_modes, mach, settings)
}

/// [`gaf_key`] as revision `revision` of the computation made it: the key under which an
/// older build stored its table (so that a test can show such an entry is not served).
pub fn gaf_key_at_revision(
    revision: &str,
    v: &ir::Vehicle,
    n_modes: usize,
    mach: f64,
    settings: &FinFlutterSettings,
) -> std::io::Result<CacheKey> {
    let FinFlutterSettings {
        aero,
        chordwise,
        spanwise,
        correction,
        k_count,
        k_max,
    } = *settings;
    let WakeSettings { length, ring } = WakeSettings::default();
    let mut b = CacheKeyBuilder::new("clamped-fin-gaf");
    b.text("revision", revision);
    b.text("schema", GafArtifact::SCHEMA);
    super::flutter::hash_clamped_fin(&mut b, v)?;
    b.u64("modes", n_modes as u64);
    b.f64("mach", mach);
    b.text(
        "aero",
        match aero {
            FinAero::QuasiSteady => "quasi-steady",
            FinAero::Unsteady => "unsteady",
            FinAero::DoubletLattice => "doublet-lattice",
        },
    );
    b.u64("chordwise", chordwise as u64);
    b.u64("spanwise", spanwise as u64);
    // `fin_lattice` lays the panels out with cosine spacing.
    b.text("spacing", "cosine");
    b.text(
        "piston correction",
        match correction {
            Correction::None => "none",
            Correction::Ackeret => "ackeret",
        },
    );
    b.u64("k count", k_count as u64);
    b.f64("k max", k_max);
    b.f64("wake length", length);
    b.f64("wake ring", ring);
    b.u64(
        "mach boxes",
        crate::aero::panel::machbox::DEFAULT_BOXES as u64,
    );
    b.f64(
        "piston min mach",
        crate::aero::panel::machbox::PISTON_MIN_MACH,
    );
    Ok(b.finish())
}

/// A GAF table through the cache.
pub struct CachedGaf {
    pub table: GafTable,
    /// `None` when no key could be made (the table was built and not stored).
    pub key: Option<CacheKey>,
    pub outcome: CacheOutcome,
    /// Why the table could not be stored or looked up, if so (the analysis goes on).
    pub warning: Option<String>,
}

/// The GAF table of `v`'s clamped fin (`modes`, `lattice`, `settings` as
/// [`gaf_table`] takes them) at Mach `mach`: read from `cache` when a valid entry exists, else
/// built and stored (module doc).
pub fn cached_gaf_table(
    v: &ir::Vehicle,
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
    cache: &Cache,
) -> Result<CachedGaf, FinFlutterError> {
    let key = gaf_key(v, modes.order(), mach, settings);
    let ks = gaf_ks(settings);
    let mut warning = None;
    let outcome = match &key {
        Err(e) => {
            warning = Some(format!("no cache key for the GAF table: {e}"));
            CacheOutcome::Miss
        }
        Ok(key) => match cache.lookup::<GafArtifact>(key) {
            Ok(Some(art)) => {
                let read = rkyv::deserialize::<GafArtifact, rkyv::rancor::Error>(art.get())
                    .map_err(|e| e.to_string())
                    .and_then(|a| a.to_table(modes, mach, &ks));
                match read {
                    Ok(table) => {
                        return Ok(CachedGaf {
                            table,
                            key: Some(*key),
                            outcome: CacheOutcome::Hit,
                            warning: None,
                        });
                    }
                    Err(message) => CacheOutcome::Rebuilt {
                        reason: crate::artifact::ArtifactError::InvalidPayload {
                            path: cache.path_for(key),
                            message,
                        },
                    },
                }
            }
            Ok(None) => CacheOutcome::Miss,
            Err(reason) => CacheOutcome::Rebuilt { reason },
        },
    };
    let table = gaf_table(modes, lattice, mach, settings)?;
    let key = key.ok();
    if let Some(k) = &key {
        let art = GafArtifact::new(&table, modes, mach);
        if let Err(e) = crate::artifact::write_atomic(cache.dir(), k, &art) {
            warning = Some(format!("cannot store the GAF table in the cache: {e}"));
        }
    }
    Ok(CachedGaf {
        table,
        key,
        outcome,
        warning,
    })
}
