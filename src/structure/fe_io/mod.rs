//! Readers of FE models in the formats engineers export, all producing [`FeModel`].
//!
//! | reader | files |
//! |---|---|
//! | [`read_matrix_market_model`] | `mass.mtx`, `stiffness.mtx` (Matrix Market), node table CSV, optional element CSV |
//! | [`read_op4_model`] | NASTRAN OUTPUT4 ASCII (`MAA`, `KAA`) + GRID cards of a bulk data file |
//! | [`read_bulk_model`] | NASTRAN bulk data / punch: GRID cards and DMIG matrices in one file |
//!
//! Every reader converts the file's per-node DOF order to the canonical
//! u v w theta_x theta_y theta_z ([`DofOrder`]), checks the data (sizes, symmetry, finite
//! values, non-negative diagonals, node ids) and finally runs [`validate`]. Errors are
//! [`FeReadError`] values naming the file, the 1-based line and, where meaningful, the column.
//!
//! OUTPUT4 is read in ASCII and binary form (dense and sparse columns, real matrices).

mod assemble;
mod bulk;
mod error;
mod matrix_market;
mod numbers;
mod op4;
mod op4_binary;

use std::path::Path;

use faer::Side;
use faer::sparse::{SparseColMat, Triplet};

pub use assemble::{DofOrder, RawMatrix, ReadOptions, Storage};
pub use bulk::{BulkData, Dmig, GridCard, parse_bulk, read_bulk_model};
pub use error::{FeReadError, SourceLocation};
pub use matrix_market::{
    parse_elements_csv, parse_matrix_market, parse_nodes_csv, read_matrix_market_model,
};
pub use numbers::parse_nastran_real;
pub use op4::{Op4Matrix, parse_op4_ascii, read_op4_model};
pub use op4_binary::{looks_like_binary_op4, parse_op4_binary};

use crate::structure::fe_model::{DOF_PER_NODE, FeModel};

/// Reads a whole file as UTF-8 text, mapping failures to `fe::read::io`.
pub(crate) fn read_text(path: &Path) -> Result<String, FeReadError> {
    std::fs::read(path)
        .map_err(|e| FeReadError::Io(SourceLocation::line(path, 0), e.to_string()))
        .and_then(|bytes| {
            String::from_utf8(bytes).map_err(|e| {
                let upto = &e.as_bytes()[..e.utf8_error().valid_up_to()];
                let line = 1 + upto.iter().filter(|&&b| b == b'\n').count();
                FeReadError::Unsupported(
                    SourceLocation::line(path, line),
                    "not UTF-8 text (binary OUTPUT4 is not supported)",
                )
            })
        })
}

/// `a + alpha * b` for two sparse matrices of the same shape.
pub(crate) fn sparse_axpy(
    a: &SparseColMat<usize, f64>,
    alpha: f64,
    b: &SparseColMat<usize, f64>,
) -> Option<SparseColMat<usize, f64>> {
    let mut t: Vec<Triplet<usize, usize, f64>> =
        Vec::with_capacity(a.compute_nnz() + b.compute_nnz());
    t.extend(a.triplet_iter().map(|x| Triplet::new(x.row, x.col, *x.val)));
    t.extend(
        b.triplet_iter()
            .map(|x| Triplet::new(x.row, x.col, alpha * *x.val)),
    );
    SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &t).ok()
}

/// Relative diagonal shift of the positive semi-definiteness test of [`validate`].
pub const PSD_TEST_SHIFT: f64 = 1e-10;

/// Checks an assembled model: sizes, finite values, and that M is positive semi-definite.
///
/// The PSD test: a sparse Cholesky factorisation of `M + delta I`, with
/// `delta = PSD_TEST_SHIFT * max_i M_ii`. If M is PSD, `M + delta I` is positive definite and
/// the factorisation succeeds (Cholesky is backward stable, so rounding cannot make a matrix
/// whose smallest eigenvalue is `delta` fail unless `delta` is below `n * eps * ||M||`, which
/// the relative shift of 1e-10 keeps well clear of). If M has an eigenvalue below `-delta`,
/// `M + delta I` is indefinite and Cholesky meets a non-positive pivot. Negative eigenvalues
/// smaller in magnitude than `delta` (rounding noise in exported files) are accepted.
/// A massless rotational DOF (zero row of M) passes: M is then singular but PSD.
///
/// Errors carry an empty path and line 0 (the model is not tied to one file); the readers
/// substitute the mass file.
pub fn validate(model: &FeModel) -> Result<(), FeReadError> {
    let loc = || SourceLocation::line(Path::new(""), 0);
    let n = model.n_dof();
    for (name, m) in [("mass", &model.mass), ("stiffness", &model.stiffness)] {
        if m.nrows() != n || m.ncols() != n {
            return Err(FeReadError::SizeNotSixPerNode(
                loc(),
                format!(
                    "{name} is {} x {}, {} nodes need {n}",
                    m.nrows(),
                    m.ncols(),
                    n / DOF_PER_NODE
                ),
            ));
        }
        if let Some(t) = m.triplet_iter().find(|t| !t.val.is_finite()) {
            return Err(FeReadError::NonFinite(
                loc(),
                format!("{name} ({}, {})", t.row + 1, t.col + 1),
            ));
        }
    }
    let max_diag = model
        .mass
        .triplet_iter()
        .filter(|t| t.row == t.col)
        .fold(0.0_f64, |acc, t| acc.max(*t.val));
    if max_diag <= 0.0 {
        return Err(FeReadError::MassNotPositiveSemiDefinite(
            loc(),
            "the mass matrix has no positive diagonal entry",
        ));
    }
    let delta = PSD_TEST_SHIFT * max_diag;
    let identity: Vec<Triplet<usize, usize, f64>> =
        (0..n).map(|i| Triplet::new(i, i, 1.0)).collect();
    let eye = SparseColMat::try_new_from_triplets(n, n, &identity)
        .map_err(|e| FeReadError::BadRecord(loc(), format!("{e:?}")))?;
    let shifted = sparse_axpy(&model.mass, delta, &eye)
        .ok_or_else(|| FeReadError::BadRecord(loc(), "cannot form M + delta I"))?;
    shifted.sp_cholesky(Side::Lower).map(|_| ()).map_err(|e| {
        FeReadError::MassNotPositiveSemiDefinite(
            loc(),
            format!(
                "Cholesky of M + {delta:.3e} I failed ({e}): M has an eigenvalue below -{delta:.3e}"
            ),
        )
    })
}
