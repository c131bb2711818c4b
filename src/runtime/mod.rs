pub mod aero;
