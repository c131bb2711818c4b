//! Physical units and dimensions of the vehicle description language.
//!
//! Every quantity written in a vehicle file is converted to SI at check time; the IR never
//! holds anything else. Angles are a base dimension here (not dimensionless as in strict SI)
//! so that `cant = 5 m` or `velocity = (1, 0, 0) rad/s` is caught; the stored value is in
//! radians. Temperature (K) is its own dimension for user atmosphere tables.

use std::fmt;

/// Exponents of the base dimensions: mass, length, time, angle, temperature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Dim {
    pub mass: i8,
    pub length: i8,
    pub time: i8,
    pub angle: i8,
    pub temperature: i8,
}

const fn dim(mass: i8, length: i8, time: i8, angle: i8) -> Dim {
    Dim {
        mass,
        length,
        time,
        angle,
        temperature: 0,
    }
}

impl Dim {
    pub const NONE: Dim = dim(0, 0, 0, 0);
    pub const LENGTH: Dim = dim(0, 1, 0, 0);
    pub const AREA: Dim = dim(0, 2, 0, 0);
    pub const MASS: Dim = dim(1, 0, 0, 0);
    pub const TIME: Dim = dim(0, 0, 1, 0);
    pub const ANGLE: Dim = dim(0, 0, 0, 1);
    pub const FREQUENCY: Dim = dim(0, 0, -1, 0);
    pub const VELOCITY: Dim = dim(0, 1, -1, 0);
    pub const ACCELERATION: Dim = dim(0, 1, -2, 0);
    pub const ANGULAR_VELOCITY: Dim = dim(0, 0, -1, 1);
    pub const FORCE: Dim = dim(1, 1, -2, 0);
    pub const PRESSURE: Dim = dim(1, -1, -2, 0);
    pub const DENSITY: Dim = dim(1, -3, 0, 0);
    pub const IMPULSE: Dim = dim(1, 1, -1, 0);
    pub const INERTIA: Dim = dim(1, 2, 0, 0);
    pub const LINEAR_DENSITY: Dim = dim(1, -1, 0, 0);
    pub const TEMPERATURE: Dim = Dim {
        mass: 0,
        length: 0,
        time: 0,
        angle: 0,
        temperature: 1,
    };

    pub fn times(self, o: Dim) -> Dim {
        Dim {
            mass: self.mass.saturating_add(o.mass),
            length: self.length.saturating_add(o.length),
            time: self.time.saturating_add(o.time),
            angle: self.angle.saturating_add(o.angle),
            temperature: self.temperature.saturating_add(o.temperature),
        }
    }

    pub fn powi(self, p: i8) -> Dim {
        Dim {
            mass: self.mass.saturating_mul(p),
            length: self.length.saturating_mul(p),
            time: self.time.saturating_mul(p),
            angle: self.angle.saturating_mul(p),
            temperature: self.temperature.saturating_mul(p),
        }
    }

    /// A name an engineer recognises, when there is one.
    pub fn name(self) -> Option<&'static str> {
        Some(match self {
            Dim::NONE => "dimensionless",
            Dim::LENGTH => "length",
            Dim::AREA => "area",
            Dim::MASS => "mass",
            Dim::TIME => "time",
            Dim::ANGLE => "angle",
            Dim::FREQUENCY => "frequency",
            Dim::VELOCITY => "velocity",
            Dim::ACCELERATION => "acceleration",
            Dim::ANGULAR_VELOCITY => "angular velocity",
            Dim::FORCE => "force",
            Dim::PRESSURE => "pressure or stress",
            Dim::DENSITY => "density",
            Dim::IMPULSE => "impulse",
            Dim::INERTIA => "moment of inertia",
            Dim::LINEAR_DENSITY => "mass per length",
            Dim::TEMPERATURE => "temperature",
            _ => return None,
        })
    }

    /// The SI unit of this dimension, for messages ("kg*m/s^2").
    pub fn si_unit(self) -> String {
        let mut num = Vec::new();
        let mut den = Vec::new();
        for (sym, e) in [
            ("kg", self.mass),
            ("m", self.length),
            ("s", self.time),
            ("rad", self.angle),
            ("K", self.temperature),
        ] {
            let target = if e > 0 { &mut num } else { &mut den };
            match e.unsigned_abs() {
                0 => {}
                1 => target.push(sym.to_string()),
                n => target.push(format!("{sym}^{n}")),
            }
        }
        match (num.is_empty(), den.is_empty()) {
            (true, true) => "1".to_string(),
            (false, true) => num.join("*"),
            (true, false) => format!("1/{}", den.join("/")),
            (false, false) => format!("{}/{}", num.join("*"), den.join("/")),
        }
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.name() {
            Some(n) if *self != Dim::NONE => write!(f, "{n} [{}]", self.si_unit()),
            Some(n) => f.write_str(n),
            None => write!(f, "[{}]", self.si_unit()),
        }
    }
}

/// A unit: multiply a written number by `scale` to get SI (radians for angles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    pub scale: f64,
    pub dim: Dim,
}

impl Unit {
    pub const ONE: Unit = Unit {
        scale: 1.0,
        dim: Dim::NONE,
    };

    pub fn times(self, o: Unit) -> Unit {
        Unit {
            scale: self.scale * o.scale,
            dim: self.dim.times(o.dim),
        }
    }

    pub fn powi(self, p: i8) -> Unit {
        Unit {
            scale: self.scale.powi(i32::from(p)),
            dim: self.dim.powi(p),
        }
    }
}

/// The unit names the language knows, with their SI scale and dimension.
pub const UNITS: &[(&str, f64, Dim)] = &[
    // length
    ("m", 1.0, Dim::LENGTH),
    ("mm", 1e-3, Dim::LENGTH),
    ("um", 1e-6, Dim::LENGTH),
    ("cm", 1e-2, Dim::LENGTH),
    ("km", 1e3, Dim::LENGTH),
    ("in", 0.0254, Dim::LENGTH),
    ("ft", 0.3048, Dim::LENGTH),
    // mass
    ("kg", 1.0, Dim::MASS),
    ("g", 1e-3, Dim::MASS),
    ("lb", 0.453_592_37, Dim::MASS),
    // 1 slug = 1 lbf s^2 / ft (the lbf and ft above).
    ("slug", 4.448_221_615_260_5 / 0.3048, Dim::MASS),
    // time
    ("s", 1.0, Dim::TIME),
    ("ms", 1e-3, Dim::TIME),
    ("min", 60.0, Dim::TIME),
    // frequency
    ("Hz", 1.0, Dim::FREQUENCY),
    ("kHz", 1e3, Dim::FREQUENCY),
    // angle
    ("rad", 1.0, Dim::ANGLE),
    ("deg", std::f64::consts::PI / 180.0, Dim::ANGLE),
    // force
    ("N", 1.0, Dim::FORCE),
    ("kN", 1e3, Dim::FORCE),
    ("lbf", 4.448_221_615_260_5, Dim::FORCE),
    // pressure and stress
    ("Pa", 1.0, Dim::PRESSURE),
    ("kPa", 1e3, Dim::PRESSURE),
    ("MPa", 1e6, Dim::PRESSURE),
    ("GPa", 1e9, Dim::PRESSURE),
    ("bar", 1e5, Dim::PRESSURE),
    ("psi", 6_894.757_293_168, Dim::PRESSURE),
    // temperature (absolute only)
    ("K", 1.0, Dim::TEMPERATURE),
];

/// Look up one unit name (case-sensitive: `mm` is not `Mm`).
pub fn lookup(name: &str) -> Option<Unit> {
    UNITS
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|&(_, scale, dim)| Unit { scale, dim })
}

/// All unit names, for "did you mean" suggestions.
pub fn names() -> impl Iterator<Item = &'static str> {
    UNITS.iter().map(|(n, _, _)| *n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compound_units_have_the_right_dimension_and_scale() {
        let kg = lookup("kg").unwrap();
        let m = lookup("m").unwrap();
        let s = lookup("s").unwrap();
        let density = kg.times(m.powi(-3));
        assert_eq!(density.dim, Dim::DENSITY);
        let n_s = lookup("N").unwrap().times(s);
        assert_eq!(n_s.dim, Dim::IMPULSE);
        let deg_s = lookup("deg").unwrap().times(s.powi(-1));
        assert_eq!(deg_s.dim, Dim::ANGULAR_VELOCITY);
        assert!((deg_s.scale - std::f64::consts::PI / 180.0).abs() < 1e-15);
        assert_eq!(lookup("mm").unwrap().powi(2).scale, 1e-6);
    }

    #[test]
    fn si_unit_strings() {
        assert_eq!(Dim::FORCE.si_unit(), "kg*m/s^2");
        assert_eq!(Dim::DENSITY.si_unit(), "kg/m^3");
        assert_eq!(Dim::FREQUENCY.si_unit(), "1/s");
        assert_eq!(Dim::NONE.si_unit(), "1");
    }
}
