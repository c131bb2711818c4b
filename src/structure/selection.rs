//! Mode classification and selection (issue: "mode selection as the vehicle file asks").
//!
//! Each elastic mode is classified from how its kinetic energy distributes over the parts of
//! the vehicle (body, each fin) and from the shape of the fin motion: *flap* is out-of-plane
//! motion that does not vary along the chord, *twist* is out-of-plane motion that varies
//! linearly along the chord (rotation about the span axis), fitted station by station.
//!
//! Cruciform symmetry makes fin modes (nearly) repeated and body bending come in pairs; any
//! orthogonal mix of a degenerate set is an eigenvector too (REFERENCE-NOTES). So within each
//! cluster of modes of one class whose frequencies agree to [`CLUSTER_TOLERANCE`], the basis is
//! rotated to localise: for each target (fin j, or body plane x-y / x-z) the direction of the
//! cluster subspace with the largest share of energy on that target is found (top eigenvector
//! of the k x k energy matrix), and the directions are made orthonormal by Löwdin's symmetric
//! orthogonalisation (the orthogonal basis closest to them). The rotated modes stay
//! M-orthonormal; their stiffness is recomputed as Rayleigh quotients (and the reduced
//! stiffness S^T K S, computed later, is exact). Fin clusters are the n_fins lowest modes of a
//! fin class when they agree to [`FIN_CLUSTER_TOLERANCE`]: on thick fins the combinations that
//! roll or bend the body are shifted several per cent (SPHADS-1 with 1.0 mm fins: flap
//! 60.27, 60.32, 60.32, 63.74 Hz), and with the 5 % rule the fourth fin took a second flap
//! mode at 263 Hz. On a body soft in torsion the roll combination (every fin moving in the
//! same sense about the axis) twists the body: it can carry more body than fin energy, so
//! that it is no fin mode by the energy rule, or lie farther than the tolerance from the
//! other combinations. Either way the cluster is completed with it, kept when the rotated
//! modes then each classify on their own fin ([`complete_fin_cluster`]; RockSim's
//! BodyTubeChildrenTest and OpenRocket's Chute release, fins on paper tubes).

use std::fmt::Write as _;

use faer::{Mat, MatRef};
use nalgebra::DMatrix;
use serde::Serialize;

use super::fe_model::{Component, DOF_PER_NODE, FeModel};
use crate::check::ir::{ModeClass, ModeCount, ModeRule};

/// Relative frequency difference below which modes of one class count as one cluster.
pub const CLUSTER_TOLERANCE: f64 = 0.05;

/// Relative spread of the n_fins lowest modes of one fin class that still counts as the fin
/// cluster (see [`select`]). Rotating a cluster changes only the basis of the subspace the modes
/// span, not the subspace, so the reduced model is as exact as with the unrotated modes; the
/// rotated modes are then no longer eigenvectors, and the reduced stiffness S^T K S (computed in
/// full, off-diagonal terms included) carries their coupling.
pub const FIN_CLUSTER_TOLERANCE: f64 = 0.25;

/// Fin geometry the classifier needs (from the vehicle's `fins` block).
#[derive(Clone, Debug)]
pub struct FinLayout {
    /// delta_i about body x, rad.
    pub angles: Vec<f64>,
}

impl FinLayout {
    /// Span direction of fin i in the body frame: (0, cos delta, sin delta).
    pub fn span_dir(&self, i: usize) -> [f64; 3] {
        let d = self.angles.get(i).copied().unwrap_or(0.0);
        [0.0, d.cos(), d.sin()]
    }
    /// Normal of fin i: x-hat cross span = (0, -sin delta, cos delta).
    pub fn normal(&self, i: usize) -> [f64; 3] {
        let d = self.angles.get(i).copied().unwrap_or(0.0);
        [0.0, -d.sin(), d.cos()]
    }
}

/// What a mode is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    BodyBending,
    FinFlap,
    FinTwist,
    /// Anything else (axial, torsion, in-plane fin motion, mixed).
    Other,
}

impl Kind {
    fn matches(self, c: ModeClass) -> bool {
        matches!(
            (self, c),
            (Kind::BodyBending, ModeClass::BodyBending)
                | (Kind::FinFlap, ModeClass::FinFlap)
                | (Kind::FinTwist, ModeClass::FinTwist)
        )
    }
}

/// Classification of one mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModeInfo {
    pub kind: Kind,
    /// The fin the mode is localised on (fin modes).
    pub fin: Option<usize>,
    /// For body bending: 'y' (motion in the x-y plane) or 'z' (x-z plane).
    pub plane: Option<char>,
    pub frequency_hz: f64,
    /// Share of kinetic energy on the body and on each fin.
    pub body_fraction: f64,
    pub fin_fractions: Vec<f64>,
    /// Name used for output channels: `body_bending_z1`, `fin1_flap`, `mode7`.
    pub name: String,
}

/// The selected modes, ready for fixity and reduction.
#[derive(Clone, Debug)]
pub struct Selection {
    pub shapes: Mat<f64>,
    pub omega2: Vec<f64>,
    pub info: Vec<ModeInfo>,
    /// The classification of every candidate mode (for reports and error messages).
    pub candidates: Vec<ModeInfo>,
}

#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SelectionError {
    #[error("{0}")]
    Unmet(String),
    #[error("mode index {index} asked for, but only {available} elastic modes were computed")]
    IndexOutOfRange { index: usize, available: usize },
    #[error("no elastic modes to select from")]
    NoModes,
}

impl SelectionError {
    pub fn code(&self) -> &'static str {
        match self {
            SelectionError::Unmet(_) => "structure::modes::unmet",
            SelectionError::IndexOutOfRange { .. } => "structure::modes::index",
            SelectionError::NoModes => "structure::modes::none",
        }
    }
}

/// y = A x for a sparse matrix in full symmetric storage.
pub fn spmv(a: &faer::sparse::SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let symbolic = a.symbolic();
    let row_idx = symbolic.row_idx();
    let val = a.val();
    y.iter_mut().for_each(|v| *v = 0.0);
    for (j, xj) in x.iter().enumerate() {
        if *xj == 0.0 {
            continue;
        }
        for idx in symbolic.col_range(j) {
            y[row_idx[idx]] += val[idx] * xj;
        }
    }
}

/// The component of each node: as given, or, for models read from files (all `Unknown`),
/// inferred from geometry: nodes on the body axis are body; others belong to the fin whose
/// angular position is nearest (body shells read from files are not recognised: documented
/// limitation).
pub fn components(model: &FeModel, fins: Option<&FinLayout>) -> Vec<Component> {
    let length = model
        .nodes
        .iter()
        .map(|n| n.position[0].abs())
        .fold(0.0, f64::max)
        .max(1e-9);
    model
        .nodes
        .iter()
        .map(|n| match (n.component, fins) {
            (Component::Unknown, Some(f)) if !f.angles.is_empty() => {
                let (y, z) = (n.position[1], n.position[2]);
                if (y * y + z * z).sqrt() < 1e-6 * length {
                    Component::Body
                } else {
                    let a = z.atan2(y);
                    let best = (0..f.angles.len())
                        .min_by(|&i, &j| {
                            ang_dist(a, f.angles[i]).total_cmp(&ang_dist(a, f.angles[j]))
                        })
                        .unwrap_or(0);
                    Component::Fin(u16::try_from(best).unwrap_or(0))
                }
            }
            (Component::Unknown, _) => Component::Body,
            (c, _) => c,
        })
        .collect()
}

fn ang_dist(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// Per-DOF energy density phi_i (M phi)_i of a mode.
fn energy_density(phi: &[f64], m_phi: &[f64]) -> Vec<f64> {
    phi.iter().zip(m_phi).map(|(a, b)| a * b).collect()
}

/// The class of a fin motion's measures ([`Classifier::fin_motion`]): out of plane (flap or
/// twist, whichever is larger) when that exceeds the in-plane motion, else `Other`.
fn fin_class(flap: f64, twist: f64, in_plane: f64) -> Kind {
    if in_plane >= flap + twist {
        Kind::Other
    } else if flap >= twist {
        Kind::FinFlap
    } else {
        Kind::FinTwist
    }
}

/// Masks of each fin's DOFs, the targets a fin cluster is localised on.
fn fin_targets(comps: &[Component], n_fins: usize) -> Vec<Vec<f64>> {
    (0..n_fins)
        .map(|j| target_mask(comps, |c, _| c == Component::Fin(j as u16)))
        .collect()
}

/// A fin's motion in a mode ([`Classifier::fin_motion_signed`]).
#[derive(Clone, Copy, Debug, Default)]
struct FinMotion {
    flap: f64,
    twist: f64,
    in_plane: f64,
    flap_signed: f64,
    twist_signed: f64,
}

struct Classifier<'a> {
    model: &'a FeModel,
    comps: Vec<Component>,
    fins: Option<&'a FinLayout>,
    n_fins: usize,
}

impl Classifier<'_> {
    fn classify(&self, phi: &[f64], m_phi: &[f64], omega2: f64, index: usize) -> ModeInfo {
        let e = energy_density(phi, m_phi);
        let total: f64 = e.iter().sum::<f64>().max(f64::MIN_POSITIVE);
        let mut body = 0.0;
        let mut fin = vec![0.0; self.n_fins];
        // Body energy by motion type: axial (u), transverse (v, w), torsion (theta_x).
        let (mut axial, mut transverse_y, mut transverse_z, mut torsion) = (0.0, 0.0, 0.0, 0.0);
        for (k, c) in self.comps.iter().enumerate() {
            let s = &e[k * DOF_PER_NODE..(k + 1) * DOF_PER_NODE];
            let sum: f64 = s.iter().sum();
            match c {
                Component::Fin(i) if (*i as usize) < self.n_fins => fin[*i as usize] += sum,
                _ => {
                    body += sum;
                    axial += s[0];
                    // v with theta_z, w with theta_y: bending in the x-y and x-z planes.
                    transverse_y += s[1] + s[5];
                    transverse_z += s[2] + s[4];
                    torsion += s[3];
                }
            }
        }
        let body_fraction = body / total;
        let fin_fractions: Vec<f64> = fin.iter().map(|f| f / total).collect();
        let frequency_hz = omega2.max(0.0).sqrt() / std::f64::consts::TAU;
        let (mut kind, mut fin_idx, mut plane) = (Kind::Other, None, None);
        if body_fraction >= 0.5 {
            let bending = transverse_y + transverse_z;
            if bending > axial && bending > torsion {
                kind = Kind::BodyBending;
                plane = Some(if transverse_y >= transverse_z {
                    'y'
                } else {
                    'z'
                });
            }
        } else if let Some(fins) = self.fins {
            let (j, _) = fin_fractions
                .iter()
                .enumerate()
                .fold(
                    (0, f64::MIN),
                    |acc, (i, f)| if *f > acc.1 { (i, *f) } else { acc },
                );
            fin_idx = Some(j);
            let (flap, twist, in_plane) = self.fin_motion(phi, fins, j);
            kind = fin_class(flap, twist, in_plane);
        }
        let name = match (kind, fin_idx, plane) {
            (Kind::BodyBending, _, Some(p)) => format!("body_bending_{p}"),
            (Kind::FinFlap, Some(j), _) => format!("fin{}_flap", j + 1),
            (Kind::FinTwist, Some(j), _) => format!("fin{}_twist", j + 1),
            _ => format!("mode{}", index + 1),
        };
        ModeInfo {
            kind,
            fin: fin_idx,
            plane,
            frequency_hz,
            body_fraction,
            fin_fractions,
            name,
        }
    }

    /// Flap, twist and in-plane measures of fin j's motion: out-of-plane displacements w
    /// are fitted per span station as w = a + b xi (xi: chordwise position over the local
    /// chord); flap = sum of a^2, twist = sum of (b xi)^2, in-plane = sum of in-plane u^2.
    fn fin_motion(&self, phi: &[f64], fins: &FinLayout, j: usize) -> (f64, f64, f64) {
        let m = self.fin_motion_signed(phi, fins, j);
        (m.flap, m.twist, m.in_plane)
    }

    /// [`Classifier::fin_motion`] with the signed sums of the fits: `flap_signed` = sum of
    /// n a, `twist_signed` = sum of b sxx over the stations (n nodes at a station, sxx the
    /// sum of their xi^2). The normal of fin j is x-hat cross its span direction, so the same
    /// sign on every fin is a rotation in one sense about the body axis: a roll combination.
    fn fin_motion_signed(&self, phi: &[f64], fins: &FinLayout, j: usize) -> FinMotion {
        let n = fins.normal(j);
        let sdir = fins.span_dir(j);
        let mut pts: Vec<(f64, f64, f64)> = Vec::new(); // (span coord, chord coord, w)
        let mut in_plane = 0.0;
        for (k, c) in self.comps.iter().enumerate() {
            if *c != Component::Fin(u16::try_from(j).unwrap_or(u16::MAX)) {
                continue;
            }
            let p = self.model.nodes[k].position;
            let u = &phi[k * DOF_PER_NODE..k * DOF_PER_NODE + 3];
            let w = n[0] * u[0] + n[1] * u[1] + n[2] * u[2];
            let us = sdir[0] * u[0] + sdir[1] * u[1] + sdir[2] * u[2];
            in_plane += u[0] * u[0] + us * us;
            let rho = p[1] * sdir[1] + p[2] * sdir[2];
            pts.push((rho, p[0], w));
        }
        if pts.is_empty() {
            return FinMotion::default();
        }
        // Bin by span coordinate into stations.
        let (lo, hi) = pts
            .iter()
            .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
        let bins = 8usize;
        let width = ((hi - lo) / bins as f64).max(1e-12);
        let mut groups: Vec<Vec<(f64, f64)>> = vec![Vec::new(); bins + 1];
        for (rho, x, w) in &pts {
            let b = (((rho - lo) / width) as usize).min(bins);
            groups[b].push((*x, *w));
        }
        let (mut flap, mut twist) = (0.0, 0.0);
        let (mut flap_signed, mut twist_signed) = (0.0, 0.0);
        for g in groups.iter().filter(|g| !g.is_empty()) {
            let nn = g.len() as f64;
            let xm = g.iter().map(|p| p.0).sum::<f64>() / nn;
            let chord = g.iter().map(|p| p.0).fold(f64::MIN, f64::max)
                - g.iter().map(|p| p.0).fold(f64::MAX, f64::min);
            let wm = g.iter().map(|p| p.1).sum::<f64>() / nn;
            if g.len() < 2 || chord <= 0.0 {
                flap += nn * wm * wm;
                flap_signed += nn * wm;
                continue;
            }
            let sxx: f64 = g.iter().map(|p| ((p.0 - xm) / chord).powi(2)).sum();
            let sxw: f64 = g.iter().map(|p| (p.0 - xm) / chord * (p.1 - wm)).sum();
            let b = if sxx > 0.0 { sxw / sxx } else { 0.0 };
            flap += nn * wm * wm;
            twist += b * b * sxx;
            flap_signed += nn * wm;
            twist_signed += b * sxx;
        }
        FinMotion {
            flap,
            twist,
            in_plane,
            flap_signed,
            twist_signed,
        }
    }

    /// The share of a mode's fin motion of `kind` that is a roll combination:
    /// |sum_j s_j| / sum_j |s_j| over the fins' signed amplitudes s_j
    /// ([`Classifier::fin_motion_signed`]): 1 when every fin moves alike in the same sense
    /// about the axis, 0 for a combination orthogonal to it (on a symmetric fin set every
    /// other combination of a cluster sums to zero).
    fn roll_share(&self, phi: &[f64], kind: Kind) -> f64 {
        let Some(fins) = self.fins else { return 0.0 };
        let (mut sum, mut abs) = (0.0, 0.0);
        for j in 0..self.n_fins {
            let m = self.fin_motion_signed(phi, fins, j);
            let a = if kind == Kind::FinTwist {
                m.twist_signed
            } else {
                m.flap_signed
            };
            sum += a;
            abs += a.abs();
        }
        if abs > 0.0 { sum.abs() / abs } else { 0.0 }
    }
}

/// Select modes as the vehicle file asks. `omega2`/`shapes` are the elastic modes
/// (M-orthonormal, sorted by frequency).
pub fn select(
    model: &FeModel,
    omega2: &[f64],
    shapes: MatRef<'_, f64>,
    fins: Option<&FinLayout>,
    rules: &[ModeRule],
) -> Result<Selection, SelectionError> {
    let ne = omega2.len().min(shapes.ncols());
    if ne == 0 {
        return Err(SelectionError::NoModes);
    }
    let n_dof = shapes.nrows();
    let comps = components(model, fins);
    let n_fins = fins.map_or(0, |f| f.angles.len());
    let cl = Classifier {
        model,
        comps,
        fins,
        n_fins,
    };
    let mut phis: Vec<Vec<f64>> = (0..ne)
        .map(|j| (0..n_dof).map(|i| shapes[(i, j)]).collect())
        .collect();
    let mut w2: Vec<f64> = omega2[..ne].to_vec();
    let mut m_phis: Vec<Vec<f64>> = phis
        .iter()
        .map(|p| {
            let mut y = vec![0.0; n_dof];
            spmv(&model.mass, p, &mut y);
            y
        })
        .collect();
    let mut info: Vec<ModeInfo> = (0..ne)
        .map(|j| cl.classify(&phis[j], &m_phis[j], w2[j], j))
        .collect();

    // Localise clusters of repeated modes.
    let mut start = 0;
    while start < ne {
        let kind = info[start].kind;
        let mut end = start + 1;
        // A fin cluster is the next n_fins modes of one fin class when they lie within
        // FIN_CLUSTER_TOLERANCE: the combinations that move the body (roll, bending) are
        // shifted by the coupling, beyond CLUSTER_TOLERANCE on thick fins.
        let fin_kind = matches!(kind, Kind::FinFlap | Kind::FinTwist);
        if fin_kind
            && n_fins > 1
            && start + n_fins <= ne
            && info[start..start + n_fins].iter().all(|m| {
                m.kind == kind
                    && m.frequency_hz - info[start].frequency_hz
                        <= FIN_CLUSTER_TOLERANCE * info[start].frequency_hz
            })
        {
            end = start + n_fins;
        }
        while end < ne
            && info[end].kind == kind
            && kind != Kind::Other
            && (info[end].frequency_hz - info[start].frequency_hz).abs()
                <= CLUSTER_TOLERANCE * info[start].frequency_hz.max(1e-12)
        {
            end += 1;
        }
        if fin_kind && n_fins > 1 && end - start < n_fins {
            // One combination of the fin class missing from its cluster: on a body soft in
            // torsion the roll combination (every fin moving in the same sense about the
            // axis) carries the body's torsion and can have more body than fin energy
            // (module doc). Complete the cluster with it where that localises.
            if let Some(done) = complete_fin_cluster(
                &cl,
                model,
                &mut phis,
                &mut m_phis,
                &mut w2,
                &mut info,
                start,
                kind,
            ) {
                start = done + 1;
                continue;
            }
        }
        let k = end - start;
        let targets: Vec<Vec<f64>> = match kind {
            Kind::FinFlap | Kind::FinTwist if k == n_fins && k > 1 => {
                fin_targets(&cl.comps, n_fins)
            }
            Kind::BodyBending if k == 2 => vec![
                target_mask(&cl.comps, |c, d| c != is_fin(c) && (d == 1 || d == 5)),
                target_mask(&cl.comps, |c, d| c != is_fin(c) && (d == 2 || d == 4)),
            ],
            _ => Vec::new(),
        };
        if !targets.is_empty() {
            localise(
                model,
                &mut phis[start..end],
                &mut m_phis[start..end],
                &mut w2[start..end],
                &targets,
            );
            for j in start..end {
                info[j] = cl.classify(&phis[j], &m_phis[j], w2[j], j);
            }
        }
        start = end;
    }
    // Body bending planes: number pairs in order (z1, y1, z2, y2 ...) for stable names.
    let mut counts = std::collections::HashMap::new();
    for m in info.iter_mut() {
        if let (Kind::BodyBending, Some(p)) = (m.kind, m.plane) {
            let c = counts.entry(p).or_insert(0);
            *c += 1;
            m.name = format!("body_bending_{p}{c}");
        }
    }

    // Apply the rules in order, without duplicates.
    let mut chosen: Vec<usize> = Vec::new();
    let push = |chosen: &mut Vec<usize>, j: usize| {
        if !chosen.contains(&j) {
            chosen.push(j);
        }
    };
    for rule in rules {
        match rule {
            ModeRule::Indices(idx) => {
                for &i in &idx.value {
                    if i == 0 || i > ne {
                        return Err(SelectionError::IndexOutOfRange {
                            index: i,
                            available: ne,
                        });
                    }
                    push(&mut chosen, i - 1);
                }
            }
            ModeRule::BandHz { lo, hi } => {
                let found: Vec<usize> = (0..ne)
                    .filter(|&j| {
                        info[j].frequency_hz >= lo.value && info[j].frequency_hz <= hi.value
                    })
                    .collect();
                if found.is_empty() {
                    return Err(SelectionError::Unmet(format!(
                        "no elastic mode between {} Hz and {} Hz; computed modes span {:.3} to {:.3} Hz",
                        lo.value,
                        hi.value,
                        info[0].frequency_hz,
                        info[ne - 1].frequency_hz
                    )));
                }
                found.into_iter().for_each(|j| push(&mut chosen, j));
            }
            ModeRule::Class { class, count } => {
                let of_class: Vec<usize> = (0..ne)
                    .filter(|&j| info[j].kind.matches(class.value))
                    .collect();
                match count.value {
                    ModeCount::Count(n) => {
                        if of_class.len() < n {
                            return Err(unmet(class.value, &format!("{n}"), &info));
                        }
                        of_class[..n].iter().for_each(|&j| push(&mut chosen, j));
                    }
                    ModeCount::PerFin => {
                        for fin in 0..n_fins {
                            match of_class.iter().find(|&&j| info[j].fin == Some(fin)) {
                                Some(&j) => push(&mut chosen, j),
                                None => {
                                    return Err(unmet(
                                        class.value,
                                        &format!("one per fin ({n_fins} fins)"),
                                        &info,
                                    ));
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    let mut out = Mat::zeros(n_dof, chosen.len());
    for (c, &j) in chosen.iter().enumerate() {
        for i in 0..n_dof {
            out[(i, c)] = phis[j][i];
        }
    }
    Ok(Selection {
        shapes: out,
        omega2: chosen.iter().map(|&j| w2[j]).collect(),
        info: chosen.iter().map(|&j| info[j].clone()).collect(),
        candidates: info,
    })
}

/// Completes a fin cluster whose roll combination (every fin moving alike in the same sense
/// about the axis: [`Classifier::roll_share`]) the frequency rule missed, and localises its
/// `n_fins` modes on the fins. On a body soft in torsion the roll combination twists the
/// body, which shifts it from the other combinations and can give it more body than fin
/// energy. Two cases, from mode `start`, the first of class `kind` not yet in a cluster:
///
/// 1. The roll combination is no fin mode by the energy rule: `n_fins - 1` modes of `kind`
///    lie within [`FIN_CLUSTER_TOLERANCE`] of `start`, and the unclassified mode in that
///    window whose fins move in that class (out of plane, flap or twist by
///    [`Classifier::fin_motion`] summed over the fins) and carry the largest share of its
///    energy completes them. RockSim's BodyTubeChildrenTest (a 30 mm paper tube): flap
///    cluster 879.3, 887.7, 887.7 Hz, roll combination 784.3 Hz with 56 % of its energy in
///    the body.
/// 2. The roll combination is a mode of `kind` farther than the tolerance from the others:
///    of the `n_fins` lowest modes of `kind` from `start` on, exactly one is a roll
///    combination (roll share above 1/2) and the others lie within the tolerance of one
///    another. OpenRocket's Chute release (three plywood fins on a paper tube): twist roll
///    combination 516.9 Hz, the pair 695.7 Hz (26 % apart).
///
/// Rotating the modes changes the basis, not the subspace they span (as for any cluster), so
/// the reduced model keeps the body torsion the roll combination carries. A completion is
/// kept only when each rotated mode then classifies as `kind` on its own fin; otherwise
/// nothing changes and `None` is returned. Returns the highest index of the cluster.
#[allow(clippy::too_many_arguments)]
fn complete_fin_cluster(
    cl: &Classifier<'_>,
    model: &FeModel,
    phis: &mut [Vec<f64>],
    m_phis: &mut [Vec<f64>],
    w2: &mut [f64],
    info: &mut [ModeInfo],
    start: usize,
    kind: Kind,
) -> Option<usize> {
    let fins = cl.fins?;
    let n_fins = cl.n_fins;
    let f0 = info[start].frequency_hz;
    let near = |j: usize| (info[j].frequency_hz - f0).abs() <= FIN_CLUSTER_TOLERANCE * f0;
    let members: Vec<usize> = (0..info.len())
        .filter(|&j| near(j) && info[j].kind == kind)
        .collect();
    let mut idx: Vec<usize> = if members.len() == n_fins - 1 && members[0] == start {
        // Case 1.
        let moves_as = |j: usize| {
            let (mut flap, mut twist, mut in_plane) = (0.0, 0.0, 0.0);
            for f in 0..n_fins {
                let (a, b, c) = cl.fin_motion(&phis[j], fins, f);
                flap += a;
                twist += b;
                in_plane += c;
            }
            fin_class(flap, twist, in_plane) == kind
        };
        let fin_share = |m: &ModeInfo| m.fin_fractions.iter().sum::<f64>();
        let extra = (0..info.len())
            .filter(|&j| near(j) && info[j].kind == Kind::Other && moves_as(j))
            .max_by(|&a, &b| fin_share(&info[a]).total_cmp(&fin_share(&info[b])))?;
        let mut idx = members;
        idx.push(extra);
        idx
    } else {
        // Case 2.
        let class: Vec<usize> = (start..info.len())
            .filter(|&j| info[j].kind == kind)
            .take(n_fins)
            .collect();
        if class.len() < n_fins {
            return None;
        }
        let roll: Vec<usize> = class
            .iter()
            .copied()
            .filter(|&j| cl.roll_share(&phis[j], kind) > 0.5)
            .collect();
        let rest: Vec<f64> = class
            .iter()
            .filter(|j| !roll.contains(j))
            .map(|&j| info[j].frequency_hz)
            .collect();
        let lo = rest.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = rest.iter().copied().fold(0.0, f64::max);
        if roll.len() != 1 || hi - lo > FIN_CLUSTER_TOLERANCE * lo {
            return None;
        }
        class
    };
    idx.sort_unstable();
    let targets = fin_targets(&cl.comps, n_fins);
    let mut p: Vec<Vec<f64>> = idx.iter().map(|&j| phis[j].clone()).collect();
    let mut mp: Vec<Vec<f64>> = idx.iter().map(|&j| m_phis[j].clone()).collect();
    let mut w: Vec<f64> = idx.iter().map(|&j| w2[j]).collect();
    localise(model, &mut p, &mut mp, &mut w, &targets);
    let new: Vec<ModeInfo> = idx
        .iter()
        .enumerate()
        .map(|(t, &j)| cl.classify(&p[t], &mp[t], w[t], j))
        .collect();
    let mut on: Vec<usize> = new.iter().filter_map(|m| m.fin).collect();
    on.sort_unstable();
    on.dedup();
    if new.iter().any(|m| m.kind != kind) || on.len() != n_fins {
        return None;
    }
    for (t, &j) in idx.iter().enumerate() {
        phis[j] = std::mem::take(&mut p[t]);
        m_phis[j] = std::mem::take(&mut mp[t]);
        w2[j] = w[t];
        info[j] = new[t].clone();
    }
    idx.last().copied()
}

fn is_fin(c: Component) -> Component {
    // Helper for the body masks: returns the component itself when it is a fin, so
    // `c != is_fin(c)` is true exactly for non-fin nodes.
    match c {
        Component::Fin(_) => c,
        _ => Component::Fin(u16::MAX),
    }
}

/// 0/1 weights per DOF selecting a target region.
fn target_mask(comps: &[Component], sel: impl Fn(Component, usize) -> bool) -> Vec<f64> {
    let mut w = vec![0.0; comps.len() * DOF_PER_NODE];
    for (k, c) in comps.iter().enumerate() {
        for d in 0..DOF_PER_NODE {
            if sel(*c, d) {
                w[k * DOF_PER_NODE + d] = 1.0;
            }
        }
    }
    w
}

/// Rotate a cluster of modes so that mode t is concentrated on target t (see module doc).
fn localise(
    model: &FeModel,
    phis: &mut [Vec<f64>],
    m_phis: &mut [Vec<f64>],
    w2: &mut [f64],
    targets: &[Vec<f64>],
) {
    let k = phis.len();
    let n = phis[0].len();
    // E_t[a][b] = sum_i mask_t,i * (phi_a,i (M phi_b)_i + phi_b,i (M phi_a)_i) / 2
    let mut q = DMatrix::<f64>::zeros(k, k);
    for (t, mask) in targets.iter().enumerate() {
        let mut e = DMatrix::<f64>::zeros(k, k);
        for a in 0..k {
            for b in a..k {
                let v: f64 = (0..n)
                    .map(|i| {
                        mask[i] * 0.5 * (phis[a][i] * m_phis[b][i] + phis[b][i] * m_phis[a][i])
                    })
                    .sum();
                e[(a, b)] = v;
                e[(b, a)] = v;
            }
        }
        let eig = e.symmetric_eigen();
        let top = eig.eigenvalues.imax();
        q.set_column(t, &eig.eigenvectors.column(top));
    }
    // Löwdin: Q (Q^T Q)^(-1/2).
    let g = q.transpose() * &q;
    let eg = g.symmetric_eigen();
    if eg.eigenvalues.iter().any(|l| *l <= 1e-10) {
        return; // the targets do not span the cluster: leave it as it is
    }
    let inv_sqrt = &eg.eigenvectors
        * DMatrix::from_diagonal(&eg.eigenvalues.map(|l| 1.0 / l.sqrt()))
        * eg.eigenvectors.transpose();
    let r = q * inv_sqrt;
    let old: Vec<Vec<f64>> = phis.to_vec();
    let old_m: Vec<Vec<f64>> = m_phis.to_vec();
    let mut kphi = vec![0.0; n];
    for t in 0..k {
        let mut sign = 0.0;
        for i in 0..n {
            phis[t][i] = (0..k).map(|a| old[a][i] * r[(a, t)]).sum();
            m_phis[t][i] = (0..k).map(|a| old_m[a][i] * r[(a, t)]).sum();
            sign += targets[t][i] * phis[t][i];
        }
        // Sign convention: net motion of the target region positive.
        if sign < 0.0 {
            phis[t].iter_mut().for_each(|v| *v = -*v);
            m_phis[t].iter_mut().for_each(|v| *v = -*v);
        }
        spmv(&model.stiffness, &phis[t], &mut kphi);
        let kk: f64 = phis[t].iter().zip(&kphi).map(|(a, b)| a * b).sum();
        let mm: f64 = phis[t].iter().zip(&m_phis[t]).map(|(a, b)| a * b).sum();
        w2[t] = kk / mm.max(f64::MIN_POSITIVE);
    }
}

fn unmet(class: ModeClass, wanted: &str, info: &[ModeInfo]) -> SelectionError {
    let mut found = String::new();
    for m in info.iter().take(24) {
        let _ = write!(found, "{} {:.2} Hz", m.name, m.frequency_hz);
        // An unclassified mode says where its energy is (what kept it out of a class).
        if m.kind == Kind::Other {
            let fins: f64 = m.fin_fractions.iter().sum();
            let _ = write!(
                found,
                " (body {:.0} %, fins {:.0} %)",
                100.0 * m.body_fraction,
                100.0 * fins
            );
        }
        found.push_str("; ");
    }
    SelectionError::Unmet(format!(
        "asked for {:?} modes ({wanted}) but the {} lowest elastic modes do not contain them: {}",
        class,
        info.len(),
        found.trim_end_matches("; ")
    ))
}
