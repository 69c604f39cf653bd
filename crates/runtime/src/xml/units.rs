//! Unit strings in the modelDescription's notation (`"N.s/m"`, `"kg.m2"`, `"rad/s2"`, `"1"`):
//! their SI base-unit exponents (`<BaseUnit>`), display units and quantity names.
//!
//! Grammar: `"1"`, or a product of factors separated by `.`, optionally followed by one `/`
//! and a second product (`"1/s"` is allowed). A factor is a symbol of [`SYMBOLS`] followed by
//! an optional integer exponent (`m2`, `s-1`).

use std::f64::consts::PI;

/// The exponents of the SI base units (and of the SI derived unit rad) a unit is made of,
/// as in FMI 2.0's `<BaseUnit kg=".." m=".." ...>`. Every unit here is coherent SI
/// (`factor = 1`, `offset = 0`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BaseUnit {
    pub kg: i32,
    pub m: i32,
    pub s: i32,
    pub a: i32,
    pub k: i32,
    pub mol: i32,
    pub cd: i32,
    pub rad: i32,
}

const fn base(kg: i32, m: i32, s: i32, rad: i32) -> BaseUnit {
    BaseUnit {
        kg,
        m,
        s,
        a: 0,
        k: 0,
        mol: 0,
        cd: 0,
        rad,
    }
}

/// The unit symbols understood, with their base-unit exponents.
pub const SYMBOLS: &[(&str, BaseUnit)] = &[
    ("kg", base(1, 0, 0, 0)),
    ("m", base(0, 1, 0, 0)),
    ("s", base(0, 0, 1, 0)),
    (
        "A",
        BaseUnit {
            a: 1,
            ..base(0, 0, 0, 0)
        },
    ),
    (
        "K",
        BaseUnit {
            k: 1,
            ..base(0, 0, 0, 0)
        },
    ),
    (
        "mol",
        BaseUnit {
            mol: 1,
            ..base(0, 0, 0, 0)
        },
    ),
    (
        "cd",
        BaseUnit {
            cd: 1,
            ..base(0, 0, 0, 0)
        },
    ),
    ("rad", base(0, 0, 0, 1)),
    ("N", base(1, 1, -2, 0)),
    ("J", base(1, 2, -2, 0)),
    ("W", base(1, 2, -3, 0)),
    ("Pa", base(1, -1, -2, 0)),
    ("Hz", base(0, 0, -1, 0)),
];

impl BaseUnit {
    /// All exponents zero: the unit `"1"`, written `<BaseUnit/>`.
    pub const DIMENSIONLESS: BaseUnit = base(0, 0, 0, 0);

    fn add_scaled(self, other: BaseUnit, n: i32) -> Option<BaseUnit> {
        Some(BaseUnit {
            kg: self.kg.checked_add(other.kg.checked_mul(n)?)?,
            m: self.m.checked_add(other.m.checked_mul(n)?)?,
            s: self.s.checked_add(other.s.checked_mul(n)?)?,
            a: self.a.checked_add(other.a.checked_mul(n)?)?,
            k: self.k.checked_add(other.k.checked_mul(n)?)?,
            mol: self.mol.checked_add(other.mol.checked_mul(n)?)?,
            cd: self.cd.checked_add(other.cd.checked_mul(n)?)?,
            rad: self.rad.checked_add(other.rad.checked_mul(n)?)?,
        })
    }

    /// The non-zero exponents as `(attribute, exponent)`, in the schema's order
    /// (kg, m, s, A, K, mol, cd, rad).
    pub fn exponents(&self) -> Vec<(&'static str, i32)> {
        [
            ("kg", self.kg),
            ("m", self.m),
            ("s", self.s),
            ("A", self.a),
            ("K", self.k),
            ("mol", self.mol),
            ("cd", self.cd),
            ("rad", self.rad),
        ]
        .into_iter()
        .filter(|&(_, e)| e != 0)
        .collect()
    }
}

/// One factor of a unit: a symbol and its exponent (`"m2"` → `("m", 2)`).
fn factor(unit: &str, text: &str) -> Result<(&'static str, BaseUnit, i32), String> {
    let split = text
        .find(|c: char| c.is_ascii_digit() || c == '-')
        .unwrap_or(text.len());
    let (symbol, exponent) = text.split_at(split);
    if symbol.is_empty() {
        return Err(format!(
            "unit \"{unit}\": \"{text}\" is not a unit symbol with an optional integer exponent"
        ));
    }
    let Some(&(name, dims)) = SYMBOLS.iter().find(|(s, _)| *s == symbol) else {
        let known: Vec<&str> = SYMBOLS.iter().map(|(s, _)| *s).collect();
        return Err(format!(
            "unit \"{unit}\": unknown symbol \"{symbol}\" (known: {}, and \"1\")",
            known.join(", ")
        ));
    };
    let exponent = if exponent.is_empty() {
        1
    } else {
        let digits = exponent.strip_prefix('-').unwrap_or(exponent);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(format!(
                "unit \"{unit}\": \"{text}\" has an exponent that is not an integer"
            ));
        }
        exponent
            .parse::<i32>()
            .map_err(|_| format!("unit \"{unit}\": the exponent of \"{text}\" is too large"))?
    };
    Ok((name, dims, exponent))
}

/// Splits a unit into its numerator and optional denominator, checking there is at most one
/// `/`.
fn halves(unit: &str) -> Result<(&str, Option<&str>), String> {
    let mut parts = unit.split('/');
    let numerator = parts.next().unwrap_or("");
    let denominator = parts.next();
    if parts.next().is_some() {
        return Err(format!("unit \"{unit}\": more than one \"/\""));
    }
    Ok((numerator, denominator))
}

/// Parses a unit string into its base-unit exponents. An unknown symbol or a malformed
/// string is an error that names the unit.
///
/// ```
/// use mechfmu::xml::units::{parse, BaseUnit};
/// let torque = parse("N.m").unwrap();
/// assert_eq!((torque.kg, torque.m, torque.s), (1, 2, -2));
/// assert_eq!(parse("1").unwrap(), BaseUnit::DIMENSIONLESS);
/// assert!(parse("furlong/s").is_err());
/// ```
pub fn parse(unit: &str) -> Result<BaseUnit, String> {
    if unit.is_empty() {
        return Err("unit \"\": an empty unit (use \"1\" for a dimensionless quantity)".into());
    }
    let (numerator, denominator) = halves(unit)?;
    let mut result = BaseUnit::DIMENSIONLESS;
    for (text, sign) in [(Some(numerator), 1), (denominator, -1)] {
        let Some(text) = text else { continue };
        if text == "1" && sign == 1 {
            continue;
        }
        for part in text.split('.') {
            if part.is_empty() {
                return Err(format!(
                    "unit \"{unit}\": an empty factor (around \".\" or \"/\")"
                ));
            }
            let (_, dims, exponent) = factor(unit, part)?;
            result = exponent
                .checked_mul(sign)
                .and_then(|n| result.add_scaled(dims, n))
                .ok_or_else(|| format!("unit \"{unit}\": exponent overflow"))?;
        }
    }
    Ok(result)
}

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
    let (numerator, denominator) = halves(unit)?;
    let rename = |text: &str| -> Result<String, String> {
        let parts: Result<Vec<String>, String> = text
            .split('.')
            .map(|part| {
                if part == "1" {
                    return Ok(part.to_string());
                }
                let (symbol, _, _) = factor(unit, part)?;
                Ok(if symbol == "rad" {
                    format!("deg{}", &part[symbol.len()..])
                } else {
                    part.to_string()
                })
            })
            .collect();
        Ok(parts?.join("."))
    };
    let mut name = rename(numerator)?;
    if let Some(denominator) = denominator {
        name.push('/');
        name.push_str(&rename(denominator)?);
    }
    Ok(Some(DisplayUnit {
        name,
        factor: (180.0 / PI).powi(dims.rad),
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

    fn dims(kg: i32, m: i32, s: i32, rad: i32) -> BaseUnit {
        base(kg, m, s, rad)
    }

    #[test]
    fn every_unit_of_the_contract() {
        // Every unit in shared/MECHANISMS.md.
        let cases = [
            ("kg", dims(1, 0, 0, 0)),
            ("m", dims(0, 1, 0, 0)),
            ("s", dims(0, 0, 1, 0)),
            ("N", dims(1, 1, -2, 0)),
            ("J", dims(1, 2, -2, 0)),
            ("W", dims(1, 2, -3, 0)),
            ("rad", dims(0, 0, 0, 1)),
            ("1", dims(0, 0, 0, 0)),
            ("m/s", dims(0, 1, -1, 0)),
            ("m/s2", dims(0, 1, -2, 0)),
            ("N/m", dims(1, 0, -2, 0)),
            ("N.s/m", dims(1, 0, -1, 0)),
            ("N.m", dims(1, 2, -2, 0)),
            ("N.m.s/rad", dims(1, 2, -1, -1)),
            ("kg.m2", dims(1, 2, 0, 0)),
            ("kg.m2/s", dims(1, 2, -1, 0)),
            ("rad/s", dims(0, 0, -1, 1)),
            ("rad/s2", dims(0, 0, -2, 1)),
        ];
        for (unit, expected) in cases {
            assert_eq!(parse(unit), Ok(expected), "{unit}");
        }
    }

    #[test]
    fn exponents_and_reciprocals() {
        assert_eq!(parse("1/s"), Ok(dims(0, 0, -1, 0)));
        assert_eq!(parse("m.s-2"), Ok(dims(0, 1, -2, 0)));
        assert_eq!(parse("kg.m2/s2"), parse("J"));
        assert_eq!(parse("kg.m/s2"), parse("N"));
        assert_eq!(parse("m0"), Ok(BaseUnit::DIMENSIONLESS));
        assert_eq!(
            parse("mol.K.A.cd").map(|b| (b.mol, b.k, b.a, b.cd)),
            Ok((1, 1, 1, 1))
        );
        assert_eq!(
            parse("N.m").unwrap().exponents(),
            vec![("kg", 1), ("m", 2), ("s", -2)]
        );
        assert!(BaseUnit::DIMENSIONLESS.exponents().is_empty());
    }

    #[test]
    fn errors_name_the_unit() {
        for bad in [
            "",
            "furlong",
            "N.x/m",
            "m/s/s",
            "m..s",
            "/s",
            "m/",
            "m.",
            "2",
            "m 2",
            "m2.5",
            "m-",
            "kg.m2/",
            "1.m",
            "m99999999999",
        ] {
            let err = parse(bad).expect_err(bad);
            assert!(err.contains(&format!("\"{bad}\"")), "{bad}: {err}");
        }
        assert!(parse("N.x/m").unwrap_err().contains("unknown symbol \"x\""));
        assert!(parse("deg").unwrap_err().contains("unknown symbol \"deg\""));
    }

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
