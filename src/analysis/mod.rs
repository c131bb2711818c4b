//! Stage 7, analysis: what a run or a family of runs says about stability.
//!
//! - [`identify`]: time-domain identification of a damped sinusoid (matrix pencil and
//!   nonlinear least squares), eq. (6.30);
//! - [`gust_response`]: that fit after each stimulus of a run (Tables 6.1-6.2);
//! - [`sweep`]: variant sweeps: case expansion, parallel runs, tables, shards and merging.

pub mod gust_response;
pub mod identify;

pub mod sweep;
