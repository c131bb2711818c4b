//! Stage 7, analysis: stability analyses built on the compiled vehicle and the runtime's
//! equations of motion (thesis chapter 6 and beyond).

pub mod linear;
pub mod linearise;
pub mod map;
pub mod roots;
