//! `flexflight montecarlo`: the dispersion's samples flown (check, compile through the cache
//! shared by the samples of one structural key, plan, fly, flutter margin; one
//! `samples/<id>.json` per sample, resume, shards and merge: [`runner`]) and their statistics
//! ([`summary`]). The draws and the statistics themselves are `analysis::montecarlo`.

pub mod family;
pub mod runner;
pub mod summary;
