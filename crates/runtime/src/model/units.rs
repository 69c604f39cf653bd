//! Unit strings of a declaration (`"N.s/m"`, `"kg.m2"`, `"rad/s2"`, `"1"`): their grammar
//! and their SI base-unit exponents (`<BaseUnit>` in a model description). The parser is a
//! `const fn`, so `mechanism!` rejects a malformed unit at compile time with the message
//! the model description's generator would give.
//!
//! Grammar: `"1"`, or a product of factors separated by `.`, optionally followed by one `/`
//! and a second product (`"1/s"` is allowed). A factor is a symbol of [`SYMBOLS`] followed by
//! an optional integer exponent (`m2`, `s-1`).

use super::const_text::{str_eq, ConstMessage};

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

/// No exponent, for the symbols of the base units `base` does not take.
const ONE: BaseUnit = base(0, 0, 0, 0);

/// The unit symbols understood, with their base-unit exponents.
pub const SYMBOLS: &[(&str, BaseUnit)] = &[
    ("kg", base(1, 0, 0, 0)),
    ("m", base(0, 1, 0, 0)),
    ("s", base(0, 0, 1, 0)),
    ("A", BaseUnit { a: 1, ..ONE }),
    ("K", BaseUnit { k: 1, ..ONE }),
    ("mol", BaseUnit { mol: 1, ..ONE }),
    ("cd", BaseUnit { cd: 1, ..ONE }),
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

    const fn add_scaled(self, other: BaseUnit, n: i32) -> Option<BaseUnit> {
        const fn term(a: i32, b: i32, n: i32) -> Option<i32> {
            match b.checked_mul(n) {
                Some(bn) => a.checked_add(bn),
                None => None,
            }
        }
        let (Some(kg), Some(m), Some(s), Some(a), Some(k), Some(mol), Some(cd), Some(rad)) = (
            term(self.kg, other.kg, n),
            term(self.m, other.m, n),
            term(self.s, other.s, n),
            term(self.a, other.a, n),
            term(self.k, other.k, n),
            term(self.mol, other.mol, n),
            term(self.cd, other.cd, n),
            term(self.rad, other.rad, n),
        ) else {
            return None;
        };
        Some(BaseUnit {
            kg,
            m,
            s,
            a,
            k,
            mol,
            cd,
            rad,
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

/// What is wrong with a unit string; the text is the offending part of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitError<'a> {
    Empty,
    TwoSlashes,
    /// Nothing between two separators, or before or after one.
    EmptyFactor,
    /// A factor that does not start with a symbol (`"2"`).
    NoSymbol(&'a str),
    UnknownSymbol(&'a str),
    /// A factor whose exponent is not an integer (`"m-"`, `"m2x"`).
    BadExponent(&'a str),
    /// An exponent, or a sum of them, beyond `i32`.
    Overflow,
}

impl UnitError<'_> {
    /// Writes the message for this error in `unit` (which names the unit).
    pub const fn describe(self, unit: &str, message: &mut ConstMessage) {
        message.push("unit \"").push(unit).push("\": ");
        match self {
            UnitError::Empty => {
                message.push("an empty unit (use \"1\" for a dimensionless quantity)");
            }
            UnitError::TwoSlashes => {
                message.push("more than one \"/\"");
            }
            UnitError::EmptyFactor => {
                message.push("an empty factor (around \".\" or \"/\")");
            }
            UnitError::NoSymbol(text) => {
                message
                    .push("\"")
                    .push(text)
                    .push("\" is not a unit symbol with an optional integer exponent");
            }
            UnitError::UnknownSymbol(symbol) => {
                message
                    .push("unknown symbol \"")
                    .push(symbol)
                    .push("\" (known: ");
                let mut i = 0;
                while i < SYMBOLS.len() {
                    message.push(SYMBOLS[i].0).push(", ");
                    i += 1;
                }
                message.push("and \"1\")");
            }
            UnitError::BadExponent(text) => {
                message
                    .push("\"")
                    .push(text)
                    .push("\" has an exponent that is not an integer");
            }
            UnitError::Overflow => {
                message.push("an exponent is too large");
            }
        }
    }
}

/// Parses a unit string into its base-unit exponents. An unknown symbol or a malformed
/// string is an error that names the unit.
///
/// ```
/// use mechfmu::model::units::{parse, BaseUnit};
/// let torque = parse("N.m").unwrap();
/// assert_eq!((torque.kg, torque.m, torque.s), (1, 2, -2));
/// assert_eq!(parse("1").unwrap(), BaseUnit::DIMENSIONLESS);
/// assert!(parse("furlong/s").is_err());
/// ```
pub fn parse(unit: &str) -> Result<BaseUnit, String> {
    base_units(unit).map_err(|error| {
        let mut message = ConstMessage::new();
        error.describe(unit, &mut message);
        message.as_str().to_string()
    })
}

/// [`parse`], at compile time: the base-unit exponents of `unit`, or what is wrong with it.
pub const fn base_units(unit: &str) -> Result<BaseUnit, UnitError<'_>> {
    if unit.is_empty() {
        return Err(UnitError::Empty);
    }
    let (numerator, denominator) = match find(unit, b'/') {
        None => (unit, None),
        Some(slash) => {
            let (numerator, rest) = unit.split_at(slash);
            let denominator = rest.split_at(1).1;
            if find(denominator, b'/').is_some() {
                return Err(UnitError::TwoSlashes);
            }
            (numerator, Some(denominator))
        }
    };
    let mut result = BaseUnit::DIMENSIONLESS;
    if !(numerator.len() == 1 && numerator.as_bytes()[0] == b'1') {
        result = match add_product(result, numerator, 1) {
            Ok(sum) => sum,
            Err(e) => return Err(e),
        };
    }
    if let Some(denominator) = denominator {
        result = match add_product(result, denominator, -1) {
            Ok(sum) => sum,
            Err(e) => return Err(e),
        };
    }
    Ok(result)
}

/// `sum` plus `sign` times the factors of `product` (`"kg.m2"`).
const fn add_product(
    mut sum: BaseUnit,
    mut product: &str,
    sign: i32,
) -> Result<BaseUnit, UnitError<'_>> {
    loop {
        let (factor, rest) = match find(product, b'.') {
            Some(dot) => {
                let (factor, rest) = product.split_at(dot);
                (factor, Some(rest.split_at(1).1))
            }
            None => (product, None),
        };
        let (dims, exponent) = match parse_factor(factor) {
            Ok(parsed) => parsed,
            Err(e) => return Err(e),
        };
        sum = match exponent.checked_mul(sign) {
            Some(n) => match sum.add_scaled(dims, n) {
                Some(s) => s,
                None => return Err(UnitError::Overflow),
            },
            None => return Err(UnitError::Overflow),
        };
        match rest {
            Some(rest) => product = rest,
            None => return Ok(sum),
        }
    }
}

/// One factor: a symbol and its exponent (`"m2"` → metres, 2).
const fn parse_factor(text: &str) -> Result<(BaseUnit, i32), UnitError<'_>> {
    if text.is_empty() {
        return Err(UnitError::EmptyFactor);
    }
    let bytes = text.as_bytes();
    let mut split = 0;
    while split < bytes.len() && !bytes[split].is_ascii_digit() && bytes[split] != b'-' {
        split += 1;
    }
    let (symbol, exponent) = text.split_at(split);
    if symbol.is_empty() {
        return Err(UnitError::NoSymbol(text));
    }
    let Some(dims) = symbol_units(symbol) else {
        return Err(UnitError::UnknownSymbol(symbol));
    };
    if exponent.is_empty() {
        return Ok((dims, 1));
    }
    let digits = exponent.as_bytes();
    let negative = digits[0] == b'-';
    let mut i = if negative { 1 } else { 0 };
    if i == digits.len() {
        return Err(UnitError::BadExponent(text));
    }
    let mut value: i32 = 0;
    while i < digits.len() {
        if !digits[i].is_ascii_digit() {
            return Err(UnitError::BadExponent(text));
        }
        value = match value.checked_mul(10) {
            Some(v) => match v.checked_add((digits[i] - b'0') as i32) {
                Some(v) => v,
                None => return Err(UnitError::Overflow),
            },
            None => return Err(UnitError::Overflow),
        };
        i += 1;
    }
    Ok((dims, if negative { -value } else { value }))
}

const fn symbol_units(symbol: &str) -> Option<BaseUnit> {
    let mut i = 0;
    while i < SYMBOLS.len() {
        if str_eq(SYMBOLS[i].0, symbol) {
            return Some(SYMBOLS[i].1);
        }
        i += 1;
    }
    None
}

/// The position of the first `byte` in `text`.
const fn find(text: &str, byte: u8) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == byte {
            return Some(i);
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dims(kg: i32, m: i32, s: i32, rad: i32) -> BaseUnit {
        base(kg, m, s, rad)
    }

    #[test]
    fn every_unit_of_the_contract() {
        // Every unit in docs/mechanisms/README.md.
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
            "m2147483647.m",
        ] {
            let err = parse(bad).expect_err(bad);
            assert!(err.contains(&format!("\"{bad}\"")), "{bad}: {err}");
        }
        assert!(parse("N.x/m").unwrap_err().contains("unknown symbol \"x\""));
        assert!(parse("deg").unwrap_err().contains("unknown symbol \"deg\""));
        assert!(parse("m-").unwrap_err().contains("\"m-\" has an exponent"));
        assert!(parse("2")
            .unwrap_err()
            .contains("\"2\" is not a unit symbol"));
    }

    const NEWTON: Result<BaseUnit, UnitError<'static>> = base_units("kg.m/s2");

    #[test]
    fn parses_at_compile_time() {
        assert_eq!(NEWTON, Ok(dims(1, 1, -2, 0)));
        assert_eq!(base_units("m/ss"), Err(UnitError::UnknownSymbol("ss")));
    }
}
