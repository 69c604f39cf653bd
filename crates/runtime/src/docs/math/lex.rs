//! The tokens of an equation as the notes write it in plain Unicode: names with the dots of
//! their time derivatives and their subscripts (`θ̇`, `ẍ1`, `i_A`, `M₁₂`), numbers,
//! operators, brackets and superscripts (`²`, `⁻¹`, `ᵀ`, primes). A character it does not
//! know makes the whole equation unreadable, so the caller can fall back to plain text.

/// One token of an equation.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Token {
    /// A name of one letter (`x`, `θ`) or several (`sin`, `tau`, `so`), with the dots of
    /// its time derivatives (one letter only) and its subscript (`ẍ1`, `i_A`, `J_boom`).
    Name {
        text: String,
        dots: u8,
        subscript: Option<String>,
    },
    /// `2`, `0.5`, `½`.
    Number(String),
    /// An operator or a separator: `=`, `-`, `≤`, `·`, `,`, `/`, `|`, ...
    Operator(char),
    Open(char),
    Close(char),
    /// What a superscript says, in ordinary characters: `2`, `−1`, `T`, `′`.
    Superscript(String),
}

/// Operators and separators the notes use, each shown as itself (`-` as a minus sign).
const OPERATORS: &str = "=+-−<>≤≥≈≠→←·×⊗/,;:∫∂∇|";

/// Functions written after their argument-free name (`sin θ`) or with digits (`atan2`).
pub(super) const FUNCTIONS: &[&str] = &[
    "sin", "cos", "tan", "atan", "atan2", "sinh", "cosh", "tanh", "exp", "log", "ln", "det",
    "diag", "sqrt",
];

/// The tokens of `text`, or `None` at the first character that has no place in one.
pub(super) fn tokens(text: &str) -> Option<Vec<Token>> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if let Some(script) = superscript(c) {
            let mut text = String::from(script);
            i += 1;
            while let Some(script) = chars.get(i).copied().and_then(superscript) {
                text.push(script);
                i += 1;
            }
            out.push(Token::Superscript(text));
        } else if c == '\'' {
            let n = chars[i..].iter().take_while(|&&c| c == '\'').count();
            out.push(Token::Superscript(primes(n)?.to_string()));
            i += n;
        } else if is_letter(c) || dotted_letter(c).is_some() {
            let (token, next) = name(&chars, i)?;
            out.push(token);
            i = next;
        } else if c.is_ascii_digit() || matches!(c, '½' | '¼' | '¾') {
            let (token, next) = number(&chars, i);
            out.push(token);
            i = next;
        } else if OPERATORS.contains(c) {
            out.push(Token::Operator(c));
            i += 1;
        } else if matches!(c, '(' | '[' | '{') {
            out.push(Token::Open(c));
            i += 1;
        } else if matches!(c, ')' | ']' | '}') {
            out.push(Token::Close(c));
            i += 1;
        } else {
            return None;
        }
    }
    Some(out)
}

/// A name from `chars[start]`: its letters, the dots after a single letter, then a
/// subscript (digits, `₁₂`, or `_` and letters or digits). Returns the index after it.
fn name(chars: &[char], start: usize) -> Option<(Token, usize)> {
    let mut i = start;
    let mut text = String::new();
    let mut dots = 0;
    if let Some((letter, n)) = dotted_letter(chars[i]) {
        text.push(letter);
        dots = n;
        i += 1;
    } else {
        while i < chars.len()
            && (is_letter(chars[i])
                || (chars[i] == '\'' && chars.get(i + 1).is_some_and(|&c| is_letter(c))))
        {
            text.push(chars[i]);
            i += 1;
        }
    }
    // `atan2`: a function whose name ends in digits, not a subscript.
    let digits = chars[i..].iter().take_while(|c| c.is_ascii_digit()).count();
    let with_digits: String = text
        .chars()
        .chain(chars[i..i + digits].iter().copied())
        .collect();
    if digits > 0 && FUNCTIONS.contains(&with_digits.as_str()) {
        return Some((
            Token::Name {
                text: with_digits,
                dots: 0,
                subscript: None,
            },
            i + digits,
        ));
    }
    while let Some(n) = chars.get(i).copied().and_then(combining_dots) {
        dots += n;
        i += 1;
    }
    // Dots sit on one letter, and the notes go no further than second derivatives.
    if dots > 2 || (dots > 0 && text.chars().count() > 1) {
        return None;
    }
    let mut subscript = String::new();
    if chars.get(i) == Some(&'_') {
        i += 1;
        while i < chars.len() && (chars[i].is_alphanumeric() && superscript(chars[i]).is_none()) {
            subscript.push(chars[i]);
            i += 1;
        }
        if subscript.is_empty() {
            return None;
        }
    } else {
        let digit = |c: char| Some(c).filter(char::is_ascii_digit).or(subscript_digit(c));
        while let Some(d) = chars.get(i).copied().and_then(digit) {
            subscript.push(d);
            i += 1;
        }
    }
    let subscript = (!subscript.is_empty()).then_some(subscript);
    Some((
        Token::Name {
            text,
            dots,
            subscript,
        },
        i,
    ))
}

/// A number from `chars[start]`: digits with an optional decimal part, or a vulgar fraction.
fn number(chars: &[char], start: usize) -> (Token, usize) {
    if !chars[start].is_ascii_digit() {
        return (Token::Number(chars[start].to_string()), start + 1);
    }
    let mut i = start;
    while i < chars.len() && chars[i].is_ascii_digit() {
        i += 1;
    }
    if chars.get(i) == Some(&'.') && chars.get(i + 1).is_some_and(char::is_ascii_digit) {
        i += 1;
        while i < chars.len() && chars[i].is_ascii_digit() {
            i += 1;
        }
    }
    (Token::Number(chars[start..i].iter().collect()), i)
}

/// A letter of a name: Latin or Greek, not a superscript letter like `ᵀ`, not a mark.
fn is_letter(c: char) -> bool {
    c.is_alphabetic() && superscript(c).is_none() && combining_dots(c).is_none()
}

/// The dots a combining mark puts over the letter before it.
fn combining_dots(c: char) -> Option<u8> {
    match c {
        '\u{307}' => Some(1),
        '\u{308}' => Some(2),
        _ => None,
    }
}

/// A letter written with its dots in one character (`ẋ`, `ẍ`): the letter and the dots.
pub(super) fn dotted_letter(c: char) -> Option<(char, u8)> {
    const ONE_DOT: [(char, char); 38] = [
        ('ȧ', 'a'),
        ('ḃ', 'b'),
        ('ċ', 'c'),
        ('ḋ', 'd'),
        ('ė', 'e'),
        ('ḟ', 'f'),
        ('ġ', 'g'),
        ('ḣ', 'h'),
        ('ṁ', 'm'),
        ('ṅ', 'n'),
        ('ȯ', 'o'),
        ('ṗ', 'p'),
        ('ṙ', 'r'),
        ('ṡ', 's'),
        ('ṫ', 't'),
        ('ẇ', 'w'),
        ('ẋ', 'x'),
        ('ẏ', 'y'),
        ('ż', 'z'),
        ('Ȧ', 'A'),
        ('Ḃ', 'B'),
        ('Ċ', 'C'),
        ('Ḋ', 'D'),
        ('Ė', 'E'),
        ('Ḟ', 'F'),
        ('Ġ', 'G'),
        ('Ḣ', 'H'),
        ('Ṁ', 'M'),
        ('Ṅ', 'N'),
        ('Ȯ', 'O'),
        ('Ṗ', 'P'),
        ('Ṙ', 'R'),
        ('Ṡ', 'S'),
        ('Ṫ', 'T'),
        ('Ẇ', 'W'),
        ('Ẋ', 'X'),
        ('Ẏ', 'Y'),
        ('Ż', 'Z'),
    ];
    const TWO_DOTS: [(char, char); 19] = [
        ('ä', 'a'),
        ('ë', 'e'),
        ('ḧ', 'h'),
        ('ï', 'i'),
        ('ö', 'o'),
        ('ẗ', 't'),
        ('ü', 'u'),
        ('ẅ', 'w'),
        ('ẍ', 'x'),
        ('ÿ', 'y'),
        ('Ä', 'A'),
        ('Ë', 'E'),
        ('Ḧ', 'H'),
        ('Ï', 'I'),
        ('Ö', 'O'),
        ('Ü', 'U'),
        ('Ẅ', 'W'),
        ('Ẍ', 'X'),
        ('Ÿ', 'Y'),
    ];
    let find = |table: &[(char, char)]| table.iter().find(|(d, _)| *d == c).map(|(_, l)| *l);
    find(&ONE_DOT)
        .map(|l| (l, 1))
        .or_else(|| find(&TWO_DOTS).map(|l| (l, 2)))
}

/// What a superscript character says in ordinary characters.
fn superscript(c: char) -> Option<char> {
    Some(match c {
        '⁰' => '0',
        '¹' => '1',
        '²' => '2',
        '³' => '3',
        '⁴'..='⁹' => char::from_digit(c as u32 - '⁴' as u32 + 4, 10)?,
        '⁻' => '−',
        'ᵀ' => 'T',
        _ => return None,
    })
}

/// What a subscript digit says.
fn subscript_digit(c: char) -> Option<char> {
    ('₀'..='₉')
        .contains(&c)
        .then(|| char::from_digit(c as u32 - '₀' as u32, 10))
        .flatten()
}

/// `n` primes as one character: ′, ″ or ‴.
fn primes(n: usize) -> Option<char> {
    ['′', '″', '‴'].get(n.wrapping_sub(1)).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(text: &str, dots: u8, subscript: Option<&str>) -> Token {
        Token::Name {
            text: text.into(),
            dots,
            subscript: subscript.map(Into::into),
        }
    }

    #[test]
    fn dots_come_combining_or_precomposed_and_subscripts_in_three_spellings() {
        assert_eq!(
            tokens("θ̇ ẍ1 φ̈ ẋ i_A M₁₂ J_boom").unwrap(),
            [
                name("θ", 1, None),
                name("x", 2, Some("1")),
                name("φ", 2, None),
                name("x", 1, None),
                name("i", 0, Some("A")),
                name("M", 0, Some("12")),
                name("J", 0, Some("boom")),
            ]
        );
    }

    #[test]
    fn superscripts_primes_numbers_and_functions_with_digits() {
        assert_eq!(
            tokens("I_B⁻¹ Rᵀ x'' 0.5 ½ atan2(").unwrap(),
            [
                name("I", 0, Some("B")),
                Token::Superscript("−1".into()),
                name("R", 0, None),
                Token::Superscript("T".into()),
                name("x", 0, None),
                Token::Superscript("″".into()),
                Token::Number("0.5".into()),
                Token::Number("½".into()),
                name("atan2", 0, None),
                Token::Open('('),
            ]
        );
        assert_eq!(tokens("Euler's").unwrap(), [name("Euler's", 0, None)]);
    }

    #[test]
    fn what_has_no_place_in_an_equation_is_refused() {
        for text in [
            "x & y",
            "ab\u{307}",
            "sin\u{307}",
            "x_",
            "\u{307}",
            "x ''''",
            "x # 1",
        ] {
            assert_eq!(tokens(text), None, "{text:?}");
        }
    }
}
