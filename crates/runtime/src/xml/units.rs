//! Units as the model description writes them: display units and quantity names, beside the
//! base-unit exponents of [`model::units`](crate::model::units) (the grammar, which the
//! declaration is checked against at compile time).

use std::f64::consts::PI;

pub use crate::model::units::{parse, BaseUnit, SYMBOLS};

/// A display unit of a unit: `DisplayUnit_value = factor * Unit_value`.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplayUnit {
    pub name: String,
    pub factor: f64,
}

/// The display unit of a unit measuring angles: every `rad` replaced by `deg`
/// (`"rad/s"` → `"deg/s"`, factor 180/π). Only for units where rad has a positive exponent
/// (angles and their rates); a damping constant per radian (`"N.m.s/rad"`) is customarily
/// given per radian and keeps no display unit.
pub fn display_unit(unit: &str) -> Result<Option<DisplayUnit>, String> {
    let dims = parse(unit)?;
    if dims.rad <= 0 {
        return Ok(None);
    }
    // `unit` parsed: every factor is a symbol and an optional integer exponent
    let rename = |product: &str| -> String {
        let factors: Vec<String> = product
            .split('.')
            .map(|factor| match factor.strip_prefix("rad") {
                // no other symbol starts with "rad"
                Some(exponent) => format!("deg{exponent}"),
                None => factor.to_string(),
            })
            .collect();
        factors.join(".")
    };
    let (numerator, denominator) = match unit.split_once('/') {
        Some((n, d)) => (n, Some(d)),
        None => (unit, None),
    };
    let mut name = rename(numerator);
    if let Some(denominator) = denominator {
        name.push('/');
        name.push_str(&rename(denominator));
    }
    Ok(Some(DisplayUnit {
        name,
        // a product, not `powi`, which a Windows build leaves to msvcrt's `pow`
        factor: (0..dims.rad.unsigned_abs()).fold(1.0, |f, _| match dims.rad > 0 {
            true => f * (180.0 / PI),
            false => f * (PI / 180.0),
        }),
    }))
}

/// The physical quantity of a unit, for `<SimpleType><Real quantity=..>` (quantity names
/// are not standardized; these follow the Modelica Standard Library). `None` when the unit
/// is dimensionless or not in the table.
pub fn quantity(unit: &str) -> Option<&'static str> {
    Some(match unit {
        "m" => "Length",
        "m/s" => "Velocity",
        "m/s2" => "Acceleration",
        "kg" => "Mass",
        "s" => "Time",
        "N" => "Force",
        "N.m" => "Torque",
        "N.s" => "Impulse",
        "rad" => "Angle",
        "rad/s" => "AngularVelocity",
        "rad/s2" => "AngularAcceleration",
        "J" => "Energy",
        "W" => "Power",
        "kg.m2" => "MomentOfInertia",
        "kg.m/s" => "Momentum",
        "kg.m2/s" => "AngularMomentum",
        "N/m" => "TranslationalSpringConstant",
        "N.s/m" => "TranslationalDampingConstant",
        "N.m/rad" => "RotationalSpringConstant",
        "N.m.s/rad" => "RotationalDampingConstant",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_units_of_angles() {
        let deg = 57.29577951308232;
        for (unit, name) in [("rad", "deg"), ("rad/s", "deg/s"), ("rad/s2", "deg/s2")] {
            assert_eq!(
                display_unit(unit),
                Ok(Some(DisplayUnit {
                    name: name.into(),
                    factor: deg
                }))
            );
        }
        assert_eq!(display_unit("rad2").unwrap().unwrap().factor, deg * deg);
        assert_eq!(display_unit("rad2").unwrap().unwrap().name, "deg2");
        assert_eq!(display_unit("N.m.s/rad"), Ok(None));
        assert_eq!(display_unit("m/s"), Ok(None));
        assert_eq!(display_unit("1"), Ok(None));
        assert!(display_unit("rad/x").is_err());
    }

    #[test]
    fn quantities() {
        assert_eq!(quantity("N.m"), Some("Torque"));
        assert_eq!(quantity("J"), Some("Energy"));
        assert_eq!(quantity("1"), None);
        assert_eq!(quantity("kg.m2/s"), Some("AngularMomentum"));
        // Every quantity in the table is for a unit that parses.
        for unit in [
            "m",
            "m/s",
            "m/s2",
            "kg",
            "s",
            "N",
            "N.m",
            "N.s",
            "rad",
            "rad/s",
            "rad/s2",
            "J",
            "W",
            "kg.m2",
            "kg.m/s",
            "kg.m2/s",
            "N/m",
            "N.s/m",
            "N.m/rad",
            "N.m.s/rad",
        ] {
            assert!(quantity(unit).is_some() && parse(unit).is_ok(), "{unit}");
        }
    }
}
