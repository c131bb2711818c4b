//! A fin-thickness dispersion's flutter boundaries from a few compiled thicknesses (issue 35).
//!
//! When a dispersion draws `fins.thickness` and nothing else of the clamped fin (no other
//! `fins.*` entry, no `structure.generate.fin_mesh.*`, no material constant), the flutter
//! boundary of a sample is interpolated in `ln t` between the boundaries at the two node
//! thicknesses around its own (`analysis::flutter::thickness`, where the interpolation, its
//! error and the node rule are derived). The nodes cover the smallest and largest thickness
//! drawn over the whole sample set (indices `0..samples`, whatever the shard: every shard
//! computes the same nodes, so a sample's boundary, and so its row, does not depend on the
//! shard or on `--jobs`). A node's boundary is the boundary of the sample's own vehicle with
//! the node's thickness: the same cache key as a run at that thickness, so it is built once,
//! stored, and read back by a re-run, another shard or a later `flexflight run`. Within a
//! run, a node is built by the first sample that needs it while the others wait for it.
//!
//! An orthotropic fin (`fins { E2; G12 }`) is the same family: its lamina element is
//! `t K1 + t^3 K3` as the isotropic one (`analysis::flutter::thickness`), so the
//! interpolation's derivation holds for it unchanged.
//!
//! The structure of each sample (its artifact, the flight's modes) is still compiled exactly
//! at its own thickness, through the artifact cache: about 0.7 s a sample against about 15 s
//! for a cold boundary (docs/performance.md). `--exact-boundaries` turns the family off.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::analysis::flutter::fin::FinFlutterError;
use crate::analysis::flutter::margin::{Boundary, BoundaryFin, BoundarySpec};
use crate::analysis::flutter::thickness;
use crate::artifact::{Cache, CacheKey, CacheOutcome};
use crate::check::ir::{Dispersion, Vehicle};
use crate::ops::flutter::{CachedBoundary, boundary_key, cached_boundary};

/// The dispersion entry whose draws are the fin thickness.
pub const THICKNESS_PATH: &str = "fins.thickness";

/// The entry of `d` that draws the fin thickness, if the family applies to `d`: it draws
/// `fins.thickness` and no other input of the clamped fin (module doc).
pub fn thickness_entry(d: &Dispersion) -> Option<usize> {
    let touches_fin = |p: &str| {
        p.starts_with("fins.") || p.starts_with("structure.generate.fin") || p.contains("material")
    };
    let j = d.entries.iter().position(|e| e.path == THICKNESS_PATH)?;
    let others = d
        .entries
        .iter()
        .enumerate()
        .any(|(k, e)| k != j && touches_fin(&e.path));
    (!others).then_some(j)
}

type NodeBoundary = Result<(Boundary, BoundaryFin), FinFlutterError>;

/// The node thicknesses of a run and the node boundaries built so far.
pub struct ThicknessFamily {
    /// Node thicknesses, m, increasing ([`thickness::nodes`]).
    pub nodes: Vec<f64>,
    built: Mutex<BTreeMap<CacheKey, Arc<OnceLock<NodeBoundary>>>>,
}

impl ThicknessFamily {
    /// The family over `[t_min, t_max]` (m); `None` when the range gives fewer than two nodes.
    pub fn new(t_min: f64, t_max: f64) -> Option<Self> {
        let nodes = thickness::nodes(t_min, t_max);
        (nodes.len() >= 2).then(|| ThicknessFamily {
            nodes,
            built: Mutex::new(BTreeMap::new()),
        })
    }

    /// What `samples/<id>.json` records of the boundary: the nodes, so that a re-run with
    /// other nodes or `--exact-boundaries` does not reuse the sample.
    pub fn describe(&self) -> String {
        format!(
            "interpolated in ln t between the thicknesses {:?} m",
            self.nodes
        )
    }

    fn node(&self, v: &Vehicle, t: f64, spec: &BoundarySpec, cache: &Cache) -> NodeBoundary {
        let mut vn = v.clone();
        if let Some(f) = vn.fins.as_mut() {
            f.thickness.value = t;
        }
        let cell = match boundary_key(&vn, spec) {
            Ok(key) => {
                let mut built = self
                    .built
                    .lock()
                    .map_err(|_| FinFlutterError::Vehicle("the node table was poisoned".into()))?;
                Arc::clone(built.entry(key).or_default())
            }
            // No key: solved here, not shared (cached_boundary says why).
            Err(_) => Arc::new(OnceLock::new()),
        };
        cell.get_or_init(|| cached_boundary(&vn, spec, cache).map(|c| (c.boundary, c.fin)))
            .clone()
    }

    /// The boundary of `v` (a sample's vehicle) for `spec`: interpolated between the two
    /// nodes around its fin thickness. A thickness outside the nodes (which the node rule
    /// excludes for the run's own samples) is an error, never extrapolated nor quietly
    /// solved exactly: the margin then says it was not computed.
    pub fn boundary(
        &self,
        v: &Vehicle,
        spec: &BoundarySpec,
        cache: &Cache,
    ) -> Result<CachedBoundary, FinFlutterError> {
        let Some(t) = v.fins.as_ref().map(|f| f.thickness.value) else {
            return Err(FinFlutterError::NoFins);
        };
        let Some(k) = thickness::bracket(&self.nodes, t) else {
            let e = thickness::ThicknessInterpError::Outside {
                t,
                lo: self.nodes[0],
                hi: self.nodes[self.nodes.len() - 1],
            };
            return Err(FinFlutterError::Vehicle(e.to_string()));
        };
        let (t0, t1) = (self.nodes[k], self.nodes[k + 1]);
        let (b0, f0) = self.node(v, t0, spec, cache)?;
        let (b1, f1) = self.node(v, t1, spec, cache)?;
        let (boundary, fin) = thickness::interpolate((&b0, &f0, t0), (&b1, &f1, t1), t)
            .map_err(|e| FinFlutterError::Vehicle(e.to_string()))?;
        Ok(CachedBoundary {
            boundary,
            fin,
            key: None,
            outcome: CacheOutcome::Hit,
            warning: None,
        })
    }
}
