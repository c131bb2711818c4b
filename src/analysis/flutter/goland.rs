//! The Goland wing (placeholder until the next step).
